//! Session logs -> binomial counts: correct / trials per subject x group x level, and pooled.
//!
//! A *condition* is one cell of the design (scene x point set x time filter). The thesis also
//! plotted marginal groupings: "per scene" pools each scene over point sets (and time filters),
//! "per point set" pools each point set over scenes. Every grouping is kept as a [`Group`]: one
//! [`Curve`] per subject and one pooled over subjects.

mod counts_table;
pub mod dropped;
mod logs;
pub mod screening;

use anyhow::{Result, bail};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Correct answers out of trials at one tested level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct LevelCount {
    /// Samples per pixel of the test video.
    pub level: u32,
    pub correct: u32,
    pub trials: u32,
}

impl LevelCount {
    /// Observed proportion correct (trials is never 0 in a [`Curve`]).
    pub fn proportion(&self) -> f64 {
        self.correct as f64 / self.trials as f64
    }

    /// The stimulus axis: natural log of spp (the thesis plots spp on a log axis).
    pub fn x(&self) -> f64 {
        (self.level as f64).ln()
    }
}

/// One psychometric data set: counts at each tested level, sorted by level, no empty level.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Curve {
    pub points: Vec<LevelCount>,
}

impl Curve {
    /// Build from (level, correct, trials) triples; levels with 0 trials are dropped and
    /// repeated levels are summed.
    pub fn from_counts(counts: impl IntoIterator<Item = (u32, u32, u32)>) -> Self {
        let mut map: BTreeMap<u32, (u32, u32)> = BTreeMap::new();
        for (level, correct, trials) in counts {
            let e = map.entry(level).or_default();
            e.0 += correct;
            e.1 += trials;
        }
        Curve {
            points: map
                .into_iter()
                .filter(|(_, (_, n))| *n > 0)
                .map(|(level, (correct, trials))| LevelCount {
                    level,
                    correct,
                    trials,
                })
                .collect(),
        }
    }

    fn add(&mut self, level: u32, correct: bool) {
        match self.points.binary_search_by_key(&level, |p| p.level) {
            Ok(i) => {
                self.points[i].trials += 1;
                self.points[i].correct += correct as u32;
            }
            Err(i) => self.points.insert(
                i,
                LevelCount {
                    level,
                    correct: correct as u32,
                    trials: 1,
                },
            ),
        }
    }

    fn merge(&mut self, other: &Curve) {
        for p in &other.points {
            match self.points.binary_search_by_key(&p.level, |q| q.level) {
                Ok(i) => {
                    self.points[i].trials += p.trials;
                    self.points[i].correct += p.correct;
                }
                Err(i) => self.points.insert(i, *p),
            }
        }
    }

    /// Counts at a level, if it was tested.
    pub fn at(&self, level: u32) -> Option<&LevelCount> {
        self.points
            .binary_search_by_key(&level, |p| p.level)
            .ok()
            .map(|i| &self.points[i])
    }

    pub fn total_trials(&self) -> u32 {
        self.points.iter().map(|p| p.trials).sum()
    }

    pub fn levels(&self) -> Vec<u32> {
        self.points.iter().map(|p| p.level).collect()
    }
}

/// Which way trials were grouped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Grouping {
    /// One design cell: scene x point set x time filter.
    Condition,
    /// A scene pooled over point sets and time filters (thesis Figures 19, 20, 24).
    Scene,
    /// A point set pooled over scenes and time filters (thesis Figures 21-23, 25).
    PointSet,
    /// A time filter pooled over scenes and point sets (only when the design has several).
    TimeFilter,
}

renderer::named!(Grouping, "grouping", [
    Condition => "condition",
    Scene => "scene",
    PointSet => "point_set",
    TimeFilter => "time_filter",
]);

/// A group's identity: its grouping and label (`scene/point_set/time_filter` for conditions).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct GroupKey {
    pub grouping: Grouping,
    pub label: String,
}

impl GroupKey {
    /// A stable id for seeding (bootstrap resamples are keyed by it).
    pub fn id(&self) -> u64 {
        renderer::hash::name_id(&format!("{}:{}", self.grouping.name(), self.label))
    }
}

/// All counts of one group: per subject (indexed like [`Dataset::subjects`]) and pooled.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Group {
    pub key: GroupKey,
    /// A condition's factors `[scene, point set, time filter]` (`None` for the marginal
    /// groupings): the cells the `cell` unit of the t-tests pairs.
    pub condition: Option<[String; 3]>,
    /// `per_subject[i]` belongs to `Dataset::subjects[i]` (empty if that subject has none).
    pub per_subject: Vec<Curve>,
    pub pooled: Curve,
}

impl Group {
    /// Per-subject proportion correct at `level`, for subjects that were tested there.
    pub fn subject_proportions(&self, level: u32) -> Vec<(usize, f64)> {
        self.per_subject
            .iter()
            .enumerate()
            .filter_map(|(s, c)| c.at(level).map(|p| (s, p.proportion())))
            .collect()
    }
}

/// Where the counts came from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// `blurlab-session/1` logs: the blurlab experiment's two-pair task.
    #[default]
    SessionLogs,
    /// Counts tables (CSV): data collected elsewhere, whose task the table does not say.
    CountsTables,
}

/// A subject left out of the analysis, with the reason given.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Exclusion {
    pub subject: String,
    pub reason: String,
    /// Main trials of that subject left out.
    pub trials: u32,
}

/// Everything the analysis needs from a study's logs.
#[derive(Clone, Debug, Serialize)]
pub struct Dataset {
    pub design: String,
    pub design_hash: String,
    /// Sorted subject ids.
    pub subjects: Vec<String>,
    /// All tested levels, sorted.
    pub levels: Vec<u32>,
    /// Conditions first, then scenes, point sets and time filters; each sorted by label.
    pub groups: Vec<Group>,
    /// Files read, sorted.
    pub files: Vec<PathBuf>,
    /// Main (non-practice) trials counted.
    pub trials: usize,
    /// Tolerated problems reported by the log reader (torn last lines).
    pub warnings: Vec<String>,
    pub source: Source,
    /// Subjects left out ([`Dataset::exclude`]), in the order given.
    pub excluded: Vec<Exclusion>,
    /// Levels at which every main trial showed the reference against itself (test and
    /// reference the same video: under the thesis's `highest_level` reference, the top level),
    /// so that any observer answers at chance there whatever its threshold. Known only from
    /// session logs (empty for counts tables). The multilevel model leaves these trials out.
    pub same_video_levels: Vec<u32>,
    /// Session logs read per header `mode` (`gui`: the lab app, `web`: `blurlab serve`,
    /// `simulated`); empty for counts tables.
    pub sessions_by_mode: BTreeMap<String, usize>,
}

/// One analyzed trial, reduced to what aggregation needs. The factors are names, not a
/// [`renderer::condition::Condition`]: a counts table holds data collected elsewhere, whose
/// point sets and time filters may be any names (a log's are checked when it is read).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Observation {
    pub subject: String,
    pub scene: String,
    pub point_set: String,
    pub time_filter: String,
    pub level: u32,
    pub correct: bool,
}

impl Dataset {
    /// Leave subjects out, each with the reason given (`None`: no reason given). Every id must
    /// be one of the data's subjects (a typo must not pass silently), and one subject must
    /// remain.
    pub fn exclude(&mut self, list: &[(String, Option<String>)]) -> Result<()> {
        for (id, _) in list {
            if !self.subjects.contains(id) {
                bail!(
                    "--exclude names subject {id:?}, which is not in the data; the subjects are {}",
                    self.subjects.join(", ")
                );
            }
        }
        let keep: Vec<bool> = self
            .subjects
            .iter()
            .map(|s| !list.iter().any(|(id, _)| id == s))
            .collect();
        if !keep.contains(&true) {
            bail!("--exclude leaves no subject to analyze");
        }
        for (id, reason) in list {
            if self.excluded.iter().any(|e| &e.subject == id) {
                continue;
            }
            let s = self.subjects.iter().position(|x| x == id).unwrap_or(0);
            let trials = self
                .groups_of(Grouping::Condition)
                .map(|g| g.per_subject[s].total_trials())
                .sum();
            self.excluded.push(Exclusion {
                subject: id.clone(),
                reason: reason.clone().unwrap_or_else(|| "no reason given".into()),
                trials,
            });
        }
        self.subjects = kept(&self.subjects, &keep);
        for g in &mut self.groups {
            g.per_subject = kept(&g.per_subject, &keep);
            g.pooled = Curve::default();
            for c in &g.per_subject {
                g.pooled.merge(c);
            }
        }
        self.groups.retain(|g| !g.pooled.points.is_empty());
        let mut levels: Vec<u32> = self.groups.iter().flat_map(|g| g.pooled.levels()).collect();
        levels.sort_unstable();
        levels.dedup();
        self.levels = levels;
        self.trials = self
            .groups_of(Grouping::Condition)
            .map(|g| g.pooled.total_trials() as usize)
            .sum();
        Ok(())
    }

    /// Aggregate observations (no file checks; used by tests and simulations too).
    pub fn from_observations(obs: &[Observation]) -> Self {
        let mut subjects: Vec<String> = obs.iter().map(|o| o.subject.clone()).collect();
        subjects.sort();
        subjects.dedup();
        let mut levels: Vec<u32> = obs.iter().map(|o| o.level).collect();
        levels.sort_unstable();
        levels.dedup();
        let n_time_filters = distinct(obs.iter().map(|o| &o.time_filter));

        // Condition cells first, keyed by their factors (names may hold any character, so the
        // label is never parsed back); the marginal groupings are merged from them.
        let mut cells: BTreeMap<[&str; 3], Vec<Curve>> = BTreeMap::new();
        for o in obs {
            let s = subjects.binary_search(&o.subject).unwrap_or(0);
            let curves = cells
                .entry([&o.scene, &o.point_set, &o.time_filter])
                .or_insert_with(|| vec![Curve::default(); subjects.len()]);
            curves[s].add(o.level, o.correct);
        }
        let mut marginals: BTreeMap<GroupKey, Vec<Curve>> = BTreeMap::new();
        for (factors, curves) in &cells {
            let mut targets = vec![
                (Grouping::Scene, factors[0]),
                (Grouping::PointSet, factors[1]),
            ];
            if n_time_filters > 1 {
                targets.push((Grouping::TimeFilter, factors[2]));
            }
            for (grouping, label) in targets {
                let entry = marginals
                    .entry(GroupKey {
                        grouping,
                        label: label.to_string(),
                    })
                    .or_insert_with(|| vec![Curve::default(); subjects.len()]);
                for (acc, c) in entry.iter_mut().zip(curves) {
                    acc.merge(c);
                }
            }
        }
        let cells = cells.into_iter().map(|(f, curves)| {
            let key = GroupKey {
                grouping: Grouping::Condition,
                label: f.join("/"),
            };
            (key, Some(f.map(String::from)), curves)
        });
        let marginals = marginals.into_iter().map(|(k, curves)| (k, None, curves));
        let groups = cells
            .chain(marginals)
            .map(|(key, condition, per_subject)| {
                let mut pooled = Curve::default();
                for c in &per_subject {
                    pooled.merge(c);
                }
                Group {
                    key,
                    condition,
                    per_subject,
                    pooled,
                }
            })
            .collect();
        Dataset {
            design: String::new(),
            design_hash: String::new(),
            subjects,
            levels,
            groups,
            files: Vec::new(),
            trials: obs.len(),
            warnings: Vec::new(),
            source: Source::SessionLogs,
            excluded: Vec::new(),
            same_video_levels: Vec::new(),
            sessions_by_mode: BTreeMap::new(),
        }
    }

    /// Groups of one grouping, sorted by label.
    pub fn groups_of(&self, grouping: Grouping) -> impl Iterator<Item = &Group> {
        self.groups
            .iter()
            .filter(move |g| g.key.grouping == grouping)
    }
}

/// The items whose `keep` flag is set.
fn kept<T: Clone>(items: &[T], keep: &[bool]) -> Vec<T> {
    items
        .iter()
        .zip(keep)
        .filter(|(_, k)| **k)
        .map(|(x, _)| x.clone())
        .collect()
}

fn distinct<'a>(it: impl Iterator<Item = &'a String>) -> usize {
    let mut v: Vec<&String> = it.collect();
    v.sort();
    v.dedup();
    v.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn o(subject: &str, scene: &str, ps: &str, level: u32, correct: bool) -> Observation {
        Observation {
            subject: subject.into(),
            scene: scene.into(),
            point_set: ps.into(),
            time_filter: "box".into(),
            level,
            correct,
        }
    }

    #[test]
    fn counts_aggregate_per_subject_condition_and_marginals() {
        let obs = vec![
            o("b", "plane", "ham", 8, true),
            o("a", "plane", "ham", 8, false),
            o("a", "plane", "ham", 8, true),
            o("a", "plane", "poisson", 8, true),
            o("a", "spheres", "ham", 27, true),
        ];
        let ds = Dataset::from_observations(&obs);
        assert_eq!(ds.subjects, vec!["a", "b"]);
        assert_eq!(ds.levels, vec![8, 27]);
        let cond: Vec<_> = ds.groups_of(Grouping::Condition).collect();
        assert_eq!(cond.len(), 3);
        assert_eq!(cond[0].key.label, "plane/ham/box");
        assert_eq!(cond[0].per_subject[0].at(8).unwrap().correct, 1);
        assert_eq!(cond[0].per_subject[0].at(8).unwrap().trials, 2);
        assert_eq!(cond[0].pooled.at(8).unwrap().trials, 3);
        // Scene "plane" pools both point sets: a has 2 of 3 at 8 spp.
        let plane = ds
            .groups_of(Grouping::Scene)
            .find(|g| g.key.label == "plane")
            .unwrap();
        assert_eq!(plane.per_subject[0].at(8).unwrap().correct, 2);
        assert_eq!(plane.per_subject[0].at(8).unwrap().trials, 3);
        assert_eq!(plane.pooled.at(8).unwrap().trials, 4);
        // Point set "ham" pools both scenes.
        let ham = ds
            .groups_of(Grouping::PointSet)
            .find(|g| g.key.label == "ham")
            .unwrap();
        assert_eq!(ham.pooled.levels(), vec![8, 27]);
        // One time filter: no time-filter grouping.
        assert_eq!(ds.groups_of(Grouping::TimeFilter).count(), 0);
        assert_eq!(ham.subject_proportions(27), vec![(0, 1.0)]);
    }

    #[test]
    fn factor_names_may_hold_the_label_separator() {
        let obs = vec![
            o("a", "plane/v2", "ham", 8, true),
            o("a", "plane", "v2/ham", 8, false),
        ];
        let ds = Dataset::from_observations(&obs);
        let scenes: Vec<&str> = ds
            .groups_of(Grouping::Scene)
            .map(|g| g.key.label.as_str())
            .collect();
        assert_eq!(scenes, ["plane", "plane/v2"]);
        let ps: Vec<&str> = ds
            .groups_of(Grouping::PointSet)
            .map(|g| g.key.label.as_str())
            .collect();
        assert_eq!(ps, ["ham", "v2/ham"]);
    }

    #[test]
    fn curve_from_counts_sorts_sums_and_drops_empty_levels() {
        let c = Curve::from_counts([(27, 3, 4), (8, 4, 4), (27, 1, 4), (64, 0, 0)]);
        assert_eq!(c.levels(), vec![8, 27]);
        assert_eq!(c.at(27).unwrap().correct, 4);
        assert_eq!(c.at(27).unwrap().trials, 8);
        assert_eq!(c.total_trials(), 12);
    }
}
