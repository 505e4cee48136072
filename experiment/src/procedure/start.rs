//! The procedure a design's `procedure` field names: started for a subject, or asked, when
//! the design is loaded, whether it can run the design at all.

use super::seam::Procedure;
use super::{catch, constant, quest_plus, staircase};
use crate::design::Design;
use crate::design::procedure::ProcedureSpec;
use crate::trials;
use anyhow::Result;

/// A fresh procedure for `subject` under `design`.
pub fn start(design: &Design, subject: &str) -> Box<dyn Procedure> {
    let seed = design.subject_seed(subject);
    let inner = plain(design, seed);
    match &design.file.catch_trials {
        Some(c) => Box::new(catch::WithCatch::new(inner, design, seed, c.block())),
        None => inner,
    }
}

/// The procedure the design's `procedure` field names, without catch trials.
fn plain(design: &Design, seed: u64) -> Box<dyn Procedure> {
    match &design.file.procedure {
        ProcedureSpec::ConstantStimuli => Box::new(constant::ConstantStimuli::new(
            trials::main_trials(design, seed),
        )),
        ProcedureSpec::QuestPlus(q) => Box::new(quest_plus::procedure(design, seed, q)),
        ProcedureSpec::Staircase(s) => Box::new(staircase::procedure(design, seed, s)),
    }
}

/// The checks of a design's `procedure` field that need the procedure itself (run by
/// `Design::load` after the field's own checks; the message names the field).
pub fn check(spec: &ProcedureSpec, levels: &[u32]) -> Result<()> {
    match spec {
        ProcedureSpec::QuestPlus(q) => quest_plus::check_stop_width(q, levels),
        ProcedureSpec::ConstantStimuli | ProcedureSpec::Staircase(_) => Ok(()),
    }
}
