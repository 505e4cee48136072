//! What `blurlab serve` checks of its study folder before it listens (issue 51 items 1 and 2):
//! `tokens.json` as an input like any other, and every subject's existing log belonging to that
//! subject, to a browser session and to this design. A fault found here names the file and the
//! field; found later, in front of a subject, no retry could fix it.

use super::tokens::{Tokens, looks_like_token};
use crate::Design;
use crate::log::SessionLog;
use anyhow::{Result, bail};
use std::collections::HashSet;
use std::path::Path;

/// `tokens` (read from `path`) hold tokens where tokens go, and no token or subject twice.
pub fn check_tokens(tokens: &Tokens, path: &Path) -> Result<()> {
    let at = path.display();
    let token_rule = "expected 32 lowercase hex digits, as `blurlab serve` writes them (delete \
                      the file to make new ones; subjects' links change)";
    if !looks_like_token(&tokens.admin) {
        bail!("{at}: field `admin` is not a token; {token_rule}");
    }
    if let Some(open) = &tokens.open
        && !looks_like_token(&open.token)
    {
        bail!("{at}: field `open.token` is not a token; {token_rule}");
    }
    let mut by_token: std::collections::HashMap<&str, &str> = Default::default();
    let mut by_subject: HashSet<&str> = HashSet::new();
    for (i, s) in tokens.subjects.iter().enumerate() {
        crate::session::check_subject(&s.subject)
            .map_err(|e| anyhow::anyhow!("{at}: field `subjects[{i}].subject`: {e}"))?;
        if !looks_like_token(&s.token) {
            bail!(
                "{at}: field `subjects[{i}].token` (subject {}) is not a token; {token_rule}",
                s.subject
            );
        }
        if let Some(other) = by_token.insert(&s.token, &s.subject) {
            bail!(
                "{at}: subjects {other} and {} have the same token; each subject needs their \
                 own (two sessions would write one log)",
                s.subject
            );
        }
        if !by_subject.insert(&s.subject) {
            bail!(
                "{at}: subject {} has two tokens (two entries of `subjects`); keep one",
                s.subject
            );
        }
        let open = tokens.open.as_ref().map(|o| o.token.as_str());
        for (field, secret) in [("admin", Some(tokens.admin.as_str())), ("open.token", open)] {
            if secret == Some(s.token.as_str()) {
                bail!(
                    "{at}: subject {}'s token is also `{field}`; each token must differ",
                    s.subject
                );
            }
        }
    }
    Ok(())
}

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
