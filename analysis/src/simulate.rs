//! Test support: binomial responses from known psychometric functions, as counts and as real
//! session-log files, so the analysis can be checked against a known truth. (The experiment
//! crate's simulated observers drive the real trial logger; this is a small generator that
//! writes the log format directly. Its subjects answer with the experiment's observer function,
//! `experiment::psychometric::p_correct`, with lapse 0.)
//!
//! Every response is a pure function of (seed, subject, scene, point set, level, repeat) through
//! the counter-based hash.

use crate::data::{Curve, LevelCount, Observation};
use crate::psychometric::{GUESS, Model};
use crate::sigmoid::Sigmoid;
use anyhow::Result;
use experiment::log::LOG_FORMAT;
use experiment::psychometric::p_correct;
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::hash::{hash, name_id, unit_f64};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// The thesis's levels (spp).
pub const THESIS_LEVELS: [u32; 8] = [1, 8, 27, 64, 125, 216, 343, 512];

/// The thesis's observer of the plane: logistic, threshold 40 spp at p = 0.75, slope 1.5 in
/// 1 / ln spp, no lapse, guess 1/2 (with g = 1/2 the logistic's alpha is its 0.75 point).
pub fn thesis_plane_model() -> Model {
    Model {
        sigmoid: Sigmoid::Logistic,
        alpha: 40f64.ln(),
        beta: 1.5,
        lapse: 0.0,
        guess: GUESS,
    }
}

/// `trials` x p(level) correct at each level, rounded: data without sampling noise, whose fit
/// must return `model` up to the rounding.
pub fn expected_curve(model: &Model, levels: &[u32], trials: u32) -> Curve {
    Curve::from_counts(levels.iter().map(|&l| {
        let k = (model.p((l as f64).ln()) * trials as f64).round() as u32;
        (l, k, trials)
    }))
}

/// Draw `trials` responses at each level from `model`; `coords` key the random stream.
pub fn simulate_curve(
    model: &Model,
    levels: &[u32],
    trials: u32,
    seed: u64,
    coords: &[u64],
) -> Curve {
    let key = hash(seed, coords);
    Curve {
        points: levels
            .iter()
            .map(|&level| {
                let p = model.p((level as f64).ln());
                let correct = (0..trials)
                    .filter(|&j| unit_f64(hash(key, &[level as u64, j as u64])) < p)
                    .count() as u32;
                LevelCount {
                    level,
                    correct,
                    trials,
                }
            })
            .collect(),
    }
}

/// A simulated study: every subject sees every scene x point set x level `repeats` times.
#[derive(Clone, Debug)]
pub struct StudySpec {
    pub subjects: usize,
    /// Scene name and its true pooled threshold (spp at p = 0.75).
    pub scenes: Vec<(String, f64)>,
    /// Point-set name and a factor on the threshold.
    pub point_sets: Vec<(PointSetKind, f64)>,
    pub time_filter: TimeFilter,
    pub levels: Vec<u32>,
    pub repeats: u32,
    /// Logistic slope in 1 / ln spp.
    pub slope: f64,
    /// Subjects' thresholds vary by a factor exp(+- spread / 2) (uniform in ln spp).
    pub spread: f64,
    /// Practice trials per subject (logged, never analyzed).
    pub practice: u32,
    pub seed: u64,
}

impl StudySpec {
    /// The thesis's design: 12 subjects, 2 scenes (JND ~40 and ~100 spp), 3 point sets,
    /// 8 levels, 4 repeats.
    pub fn thesis() -> Self {
        StudySpec {
            subjects: 12,
            scenes: vec![("plane".into(), 40.0), ("spheres".into(), 100.0)],
            point_sets: vec![
                (PointSetKind::Hammersley, 1.0),
                (PointSetKind::Poisson, 1.0),
                (PointSetKind::Stratified, 1.0),
            ],
            time_filter: TimeFilter::TruncatedBox,
            levels: THESIS_LEVELS.to_vec(),
            repeats: 4,
            slope: 1.5,
            spread: 0.6,
            practice: 3,
            seed: 2024,
        }
    }

    pub fn subject_name(&self, s: usize) -> String {
        format!("s{:02}", s + 1)
    }

    /// The true model of one subject in one condition (the fits' truth; the responses come
    /// from the same logistic through `experiment::psychometric::p_correct`).
    pub fn model(&self, subject: usize, scene: usize, point_set: usize) -> Model {
        let offset = self.spread * (unit_f64(hash(self.seed, &[0x5b, subject as u64])) - 0.5);
        Model {
            sigmoid: Sigmoid::Logistic,
            alpha: (self.scenes[scene].1 * self.point_sets[point_set].1).ln() + offset,
            beta: self.slope,
            lapse: 0.0,
            guess: 0.5,
        }
    }

    fn correct(&self, subject: usize, scene: usize, ps: usize, level: u32, rep: u32) -> bool {
        let m = self.model(subject, scene, ps);
        let p = p_correct(m.beta, m.lapse, m.alpha, (level as f64).ln());
        let h = hash(
            self.seed,
            &[
                subject as u64,
                name_id(&self.scenes[scene].0),
                name_id(self.point_sets[ps].0.name()),
                level as u64,
                rep as u64,
            ],
        );
        unit_f64(h) < p
    }

    /// All main trials as observations.
    pub fn observations(&self) -> Vec<Observation> {
        let mut out = Vec::new();
        for s in 0..self.subjects {
            self.for_each_trial(|sc, ps, level, rep| {
                out.push(Observation {
                    subject: self.subject_name(s),
                    scene: self.scenes[sc].0.clone(),
                    point_set: self.point_sets[ps].0.to_string(),
                    time_filter: self.time_filter.to_string(),
                    level,
                    correct: self.correct(s, sc, ps, level, rep),
                });
            });
        }
        out
    }

    fn for_each_trial(&self, mut f: impl FnMut(usize, usize, u32, u32)) {
        for sc in 0..self.scenes.len() {
            for ps in 0..self.point_sets.len() {
                for &level in &self.levels {
                    for rep in 0..self.repeats {
                        f(sc, ps, level, rep);
                    }
                }
            }
        }
    }

    /// Write one `blurlab-session/1` log per subject into `dir` (`<subject>.jsonl`).
    ///
    /// The lines are written as JSON objects with the format's documented fields, not through
    /// the experiment crate's structs, so that fields the experiment adds later (optional, as a
    /// format version requires) do not break this generator.
    pub fn write_logs(&self, dir: &Path, design_hash: &str) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let mut paths = Vec::new();
        for s in 0..self.subjects {
            let mut lines = vec![self.header(s, design_hash)];
            // Practice trials: at the easiest level, always answered wrongly, so that counting
            // them by mistake would show.
            for i in 0..self.practice {
                lines.push(self.record(s, i, true, (0, 0), self.levels[0], false));
            }
            let mut index = 0;
            self.for_each_trial(|sc, ps, level, rep| {
                let c = self.correct(s, sc, ps, level, rep);
                lines.push(self.record(s, index, false, (sc, ps), level, c));
                index += 1;
            });
            let mut text = String::new();
            for l in &lines {
                text.push_str(&serde_json::to_string(l)?);
                text.push('\n');
            }
            let path = dir.join(format!("{}.jsonl", self.subject_name(s)));
            renderer::atomic::write_atomic(&path, text.as_bytes())?;
            paths.push(path);
        }
        Ok(paths)
    }

    fn header(&self, s: usize, design_hash: &str) -> Value {
        json!({
            "kind": "header",
            "format": LOG_FORMAT,
            "subject": self.subject_name(s),
            "session": 1,
            "design": "simulated",
            "design_hash": design_hash,
            "seed": self.seed,
            "app_version": format!("analysis-simulate {}", env!("CARGO_PKG_VERSION")),
            "mode": "simulated",
            "started_unix": 0.0,
            "trials_planned":
                (self.scenes.len() * self.point_sets.len() * self.levels.len()) as u32 * self.repeats,
        })
    }

    /// One trial line; `(sc, ps)` index the scene and point set.
    fn record(
        &self,
        s: usize,
        index: u32,
        practice: bool,
        (sc, ps): (usize, usize),
        level: u32,
        correct: bool,
    ) -> Value {
        let h = hash(self.seed, &[0x7a, s as u64, index as u64, practice as u64]);
        let diff_pair = 1 + (h & 1) as u8;
        let (scene, point_set) = (&self.scenes[sc].0, &self.point_sets[ps].0);
        json!({
            "kind": "trial",
            "index": index,
            "practice": practice,
            "scene": scene,
            "point_set": point_set,
            "time_filter": self.time_filter,
            "level": level,
            "test_stimulus": format!("{scene}-{point_set}-{level}"),
            "reference_stimulus": format!("{scene}-reference"),
            "diff_pair": diff_pair,
            "test_side": if h & 2 == 0 { "left" } else { "right" },
            "response": if correct { diff_pair } else { 3 - diff_pair },
            "correct": correct,
            "rt_ms": 800.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;

    #[test]
    fn logs_round_trip_through_the_reader_without_practice() {
        let spec = StudySpec {
            subjects: 2,
            ..StudySpec::thesis()
        };
        let dir = tempfile::tempdir().unwrap();
        spec.write_logs(dir.path(), "h1").unwrap();
        let ds = Dataset::read(&[dir.path().to_path_buf()]).unwrap();
        let direct = Dataset::from_observations(&spec.observations());
        assert_eq!(ds.groups, direct.groups);
        assert_eq!(ds.trials, 2 * 2 * 3 * 8 * 4);
        assert_eq!(ds.design_hash, "h1");
    }

    #[test]
    fn the_observer_function_is_the_models_logistic_bit_for_bit() {
        // Every subject, condition and level of the thesis study, and levels far beyond.
        let spec = StudySpec::thesis();
        for (s, sc, ps) in (0..spec.subjects)
            .flat_map(|s| (0..2).flat_map(move |sc| (0..3).map(move |ps| (s, sc, ps))))
        {
            let m = spec.model(s, sc, ps);
            for &level in spec.levels.iter().chain(&[2, 3, 1000, 100_000, u32::MAX]) {
                let x = (level as f64).ln();
                assert_eq!(
                    p_correct(m.beta, m.lapse, m.alpha, x).to_bits(),
                    m.p(x).to_bits(),
                    "subject {s}, scene {sc}, point set {ps}, level {level}"
                );
            }
        }
    }

    #[test]
    fn simulated_proportions_follow_the_model() {
        // 20000 trials at p = 0.75: standard error 0.0031; allow 4 sigma.
        let m = Model {
            sigmoid: Sigmoid::Logistic,
            alpha: 40f64.ln(),
            beta: 2.0,
            lapse: 0.0,
            guess: 0.5,
        };
        let c = simulate_curve(&m, &[40], 20_000, 1, &[2]);
        assert!((c.points[0].proportion() - 0.75).abs() < 4.0 * 0.0031);
    }
}
