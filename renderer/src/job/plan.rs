//! A job, expanded and sized ([`Plan`]): its stimuli, each one's frame setup, the units of
//! work, which stimuli serve as references; and where a stimulus's frames go and whether they
//! keep EXR copies. The runner renders by it, `finalize` finishes by it, `dry_run` counts it.

use super::expand::StimulusSpec;
use super::shard::{self, Unit};
use super::source::{FrameSetup, FrameSource};
use super::{Job, expand};
use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// The job, expanded and sized.
pub(crate) struct Plan {
    pub specs: Vec<StimulusSpec>,
    /// Per stimulus: its scene's setup (with the job's overrides applied by the source).
    pub setups: Vec<FrameSetup>,
    pub units: Vec<Unit>,
    /// Per stimulus: some stimulus is measured against it (its frames keep EXR copies and are
    /// rendered first within a shard).
    pub serves_as_reference: Vec<bool>,
}

impl Plan {
    pub fn new(job: &Job, sources: &[Box<dyn FrameSource>]) -> Result<Self> {
        if sources.len() != job.scenes.len() {
            bail!(
                "{} scenes but {} frame sources",
                job.scenes.len(),
                sources.len()
            );
        }
        let specs = expand(job);
        let setups: Vec<FrameSetup> = specs
            .iter()
            .map(|s| sources[s.scene_index].setup())
            .collect();
        let serves_as_reference: Vec<bool> = specs
            .iter()
            .map(|s| s.reference || specs.iter().any(|o| o.reference_id.as_ref() == Some(&s.id)))
            .collect();
        let sizes: Vec<(u32, u64, bool)> = specs
            .iter()
            .zip(&setups)
            .zip(&serves_as_reference)
            .map(|((s, u), &r)| {
                let per_frame = u.width as u64 * u.height as u64 * s.sampling.spp as u64;
                (u.frames, per_frame, r)
            })
            .collect();
        let units = shard::units(&sizes, job.frames_per_unit);
        Ok(Self {
            specs,
            setups,
            units,
            serves_as_reference,
        })
    }

    /// The stimulus that stimulus `i` is measured against, unless it has none to be measured
    /// against (an independent reference, or its own reference).
    pub(super) fn reference_of(&self, i: usize) -> Option<usize> {
        let spec = &self.specs[i];
        if spec.own_reference() {
            return None;
        }
        let id = spec.reference_id.as_ref()?;
        self.specs.iter().position(|s| &s.id == id)
    }

    /// Whether stimulus `i`'s frames get an error against a reference.
    pub(super) fn measured(&self, i: usize) -> bool {
        self.reference_of(i).is_some()
    }
}

pub(super) fn stimulus_dir(job_dir: &Path, spec: &StimulusSpec) -> PathBuf {
    job_dir.join(&spec.id)
}

/// Whether stimulus `s` keeps EXR frames: references (to measure others against) and, on
/// request, every stimulus.
pub(super) fn need_exr(job: &Job, plan: &Plan, s: usize) -> bool {
    plan.serves_as_reference[s] || job.keep_exr()
}
