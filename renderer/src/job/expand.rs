//! Expanding a job into its stimuli: per scene, the independent reference first (if the job
//! has one), then every point set x time filter x level. Ids are stable
//! (`plane-hammersley-truncated_box-0064`, `plane-reference`) and each stimulus's seed depends
//! only on the master seed and its id, so adding a level or a point set to a job never changes
//! the other stimuli. Each test stimulus names the stimulus it is measured against: the
//! scene's reference, or with [`Reference::HighestLevel`] the highest level of its own point
//! set and time filter — which is then its own reference.

use super::{Job, Reference};
use crate::hash;
pub use crate::ids::{reference_id, stimulus_id};
use crate::sampling::SamplingConfig;

/// One stimulus to render.
#[derive(Clone, Debug, PartialEq)]
pub struct StimulusSpec {
    pub id: String,
    /// Index into [`Job::scenes`].
    pub scene_index: usize,
    pub scene: String,
    pub sampling: SamplingConfig,
    /// An independent reference render (`<scene>-reference`).
    pub reference: bool,
    /// The id of the stimulus this one is measured against (its own id for the highest level
    /// under [`Reference::HighestLevel`]); `None` for an independent reference.
    pub reference_id: Option<String>,
    /// The stimulus's own seed: `hash(job seed, [name_id(id)])`.
    pub seed: u64,
}

impl StimulusSpec {
    /// Whether this stimulus is its own reference (zero error by construction).
    pub fn own_reference(&self) -> bool {
        self.reference_id.as_deref() == Some(self.id.as_str())
    }
}

/// Every stimulus of the job, references first within each scene.
pub fn expand(job: &Job) -> Vec<StimulusSpec> {
    let mut out = Vec::new();
    for (scene_index, scene) in job.scenes.iter().enumerate() {
        let mut push = |id: String, sampling: SamplingConfig, reference_id: Option<String>| {
            let seed = hash::hash(job.seed, &[hash::name_id(&id)]);
            out.push(StimulusSpec {
                id,
                scene_index,
                scene: scene.name.clone(),
                sampling,
                reference: reference_id.is_none(),
                reference_id,
                seed,
            });
        };
        if let Reference::Independent(r) = &job.reference {
            push(reference_id(&scene.name), r.clone(), None);
        }
        for &ps in &job.point_sets {
            for &tf in &job.time_filters {
                let against = match job.reference {
                    Reference::Independent(_) => reference_id(&scene.name),
                    Reference::HighestLevel => {
                        stimulus_id(&scene.name, ps, tf, job.highest_level())
                    }
                };
                for &spp in &job.levels {
                    let sampling = super::stimulus_sampling(ps, spp, tf, &job.overrides.sampling);
                    push(
                        stimulus_id(&scene.name, ps, tf, spp),
                        sampling,
                        Some(against.clone()),
                    );
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condition::{PointSetKind, TimeFilter};
    use crate::job::{JobScene, Overrides};

    fn job(levels: Vec<u32>, point_sets: &[&str]) -> Job {
        Job {
            assets: Default::default(),
            path: "j.json".into(),
            name: "j".into(),
            scenes: ["plane", "spheres"]
                .iter()
                .map(|n| JobScene {
                    name: n.to_string(),
                    path: format!("{n}.json").into(),
                })
                .collect(),
            levels,
            point_sets: point_sets.iter().map(|s| s.parse().unwrap()).collect(),
            time_filters: vec![TimeFilter::TruncatedBox, TimeFilter::Box],
            reference: Reference::Independent(SamplingConfig {
                point_set: PointSetKind::Hammersley,
                spp: 1000,
                time_filter: TimeFilter::TruncatedBox,
                ..Default::default()
            }),
            seed: 42,
            overrides: Overrides::default(),
            frames_per_unit: 8,
        }
    }

    #[test]
    fn one_stimulus_per_combination_plus_a_reference_per_scene() {
        let s = expand(&job(
            vec![1, 8, 27, 64],
            &["hammersley", "stratified", "poisson"],
        ));
        assert_eq!(s.len(), 2 * (1 + 3 * 2 * 4));
        assert_eq!(s.iter().filter(|s| s.reference).count(), 2);
        assert_eq!(s[0].id, "plane-reference");
        assert_eq!(s[0].reference_id, None);
        assert_eq!(s[1].id, "plane-hammersley-truncated_box-0001");
        assert_eq!(s[1].reference_id.as_deref(), Some("plane-reference"));
        assert!(s.iter().all(|s| !s.own_reference()));
        assert!(s.iter().any(|s| s.id == "spheres-poisson-box-0064"));
        let mut ids: Vec<_> = s.iter().map(|s| &s.id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), s.len(), "ids are unique");
        let mut seeds: Vec<_> = s.iter().map(|s| s.seed).collect();
        seeds.sort();
        seeds.dedup();
        assert_eq!(seeds.len(), s.len(), "seeds are distinct");
    }

    #[test]
    fn ids_and_seeds_are_stable_when_the_job_grows() {
        let small = expand(&job(vec![8, 27], &["hammersley"]));
        let big = expand(&job(vec![1, 8, 27, 64], &["poisson", "hammersley"]));
        for s in &small {
            let same = big.iter().find(|b| b.id == s.id).expect("still present");
            assert_eq!(same, s);
        }
        // Pinned value: a change of the seed derivation would silently re-render every study.
        assert_eq!(
            small[0].seed,
            hash::hash(42, &[hash::name_id("plane-reference")])
        );
    }

    #[test]
    fn highest_level_references_are_per_condition_and_render_nothing_extra() {
        let mut j = job(vec![8, 64, 27], &["hammersley", "poisson"]);
        j.reference = Reference::HighestLevel;
        let s = expand(&j);
        assert_eq!(s.len(), 2 * 2 * 2 * 3, "no reference renders");
        assert!(s.iter().all(|s| !s.reference));
        for spec in &s {
            let (scene, ps, tf) = (
                &spec.scene,
                &spec.sampling.point_set,
                &spec.sampling.time_filter,
            );
            let want = stimulus_id(scene, *ps, *tf, 64);
            assert_eq!(
                spec.reference_id.as_deref(),
                Some(want.as_str()),
                "{}",
                spec.id
            );
            assert_eq!(spec.own_reference(), spec.sampling.spp == 64, "{}", spec.id);
        }
        // Same ids and seeds as with an independent reference: switching the reference choice
        // re-renders nothing that exists.
        let independent = expand(&job(vec![8, 64, 27], &["hammersley", "poisson"]));
        for spec in &s {
            let same = independent.iter().find(|o| o.id == spec.id).unwrap();
            assert_eq!((same.seed, &same.sampling), (spec.seed, &spec.sampling));
        }
    }
}
