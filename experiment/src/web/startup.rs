//! What `blurlab serve` checks of its study folder before it listens (issue 51 item 1; the tokens
//! are checked as they are read, `tokens::check_tokens`): every subject's existing log belonging to
//! that subject, to a browser session and to this design. A fault found here names the file and the
//! field; found later, in front of a subject, no retry could fix it.

use crate::Design;
use crate::log::SessionLog;
use anyhow::{Result, bail};
use std::path::Path;

/// Every enrolled subject's log in `sessions`, where one exists, is that subject's browser
/// session of `design`.
pub fn check_logs<'a>(
    sessions: &Path,
    subjects: impl Iterator<Item = &'a str>,
    design: &Design,
) -> Result<()> {
    for subject in subjects {
        let path = sessions.join(format!("{subject}.jsonl"));
        if !path.exists() {
            continue;
        }
        let log = SessionLog::read(&path)?;
        let h = &log.header;
        let at = path.display();
        if h.subject != subject {
            bail!(
                "{at}: header field `subject` is {:?}, but this file is subject {subject:?}'s \
                 log; move it out of the sessions folder",
                h.subject
            );
        }
        if h.mode != "web" {
            bail!(
                "{at}: header field `mode` is {:?}; a browser session's log is \"web\" (a lab or \
                 simulated session of {subject} is in the way: move it out of the sessions \
                 folder)",
                h.mode
            );
        }
        if h.design_hash != design.hash {
            bail!(
                "{at}: header field `design_hash` is {:?} (design {:?}), but {} has {:?}; serve \
                 the design this session began with, or move the log out of the sessions folder",
                h.design_hash,
                h.design,
                design.path.display(),
                design.hash
            );
        }
    }
    Ok(())
}
