//! The method of constant stimuli: the subject's planned list (`trials::plan`) in order; the
//! answers change nothing.

use super::seam::Procedure;
use crate::trials::Trial;

#[derive(Debug)]
pub struct ConstantStimuli {
    main: Vec<Trial>,
    done: usize,
}

impl ConstantStimuli {
    pub fn new(main: Vec<Trial>) -> Self {
        Self { main, done: 0 }
    }
}

impl Procedure for ConstantStimuli {
    fn current(&self) -> Option<&Trial> {
        self.main.get(self.done)
    }

    fn answer(&mut self, _correct: bool) {
        self.done = (self.done + 1).min(self.main.len());
    }

    fn after_current(&self) -> Option<Trial> {
        self.main.get(self.done + 1).cloned()
    }

    fn ahead(&self, n: usize) -> Vec<Trial> {
        self.main
            .iter()
            .skip(self.done + 1)
            .take(n)
            .cloned()
            .collect()
    }

    fn planned(&self) -> u32 {
        self.main.len() as u32
    }

    fn done(&self) -> u32 {
        self.done as u32
    }
}
