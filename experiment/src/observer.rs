//! Simulated observers (`scenes/observers/<name>.json`, format `blurlab-observer/1`): a known
//! two-alternative psychometric function per condition, for piloting a design and for testing
//! the analysis against a known truth.
//!
//! p(spp) = 0.5 + (0.5 - lapse) S(slope (ln T - ln spp) + c),   S(z) = 1 / (1 + e^-z),
//!
//! with c = logit(0.25 / (0.5 - lapse)) so that p(T) = 0.75 exactly: T *is* the JND the analysis
//! should recover (with lapse = 0, c = 0 and this is the plain logistic of the analysis crate).
//! Each subject's T is the condition's threshold times exp(spread (u - 1/2)), u uniform from
//! the subject's name: subjects differ in sensitivity, not in which condition is harder.

use crate::design::Design;
use crate::trials::{Condition, Trial, conditions};
use anyhow::{Context, Result, bail};
use renderer::hash::{hash, name_id, unit_f64};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag of an observer file.
pub const OBSERVER_FORMAT: &str = "blurlab-observer/1";

/// Proportion correct at the threshold.
pub const TARGET: f64 = 0.75;

/// The observer file as written on disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObserverFile {
    pub format: String,
    pub name: String,
    /// Logistic slope in 1 / ln spp (> 0).
    pub slope: f64,
    /// Lapse rate in [0, 0.25): the best an observer does is 1 - lapse.
    #[serde(default)]
    pub lapse: f64,
    /// Spread of subjects' thresholds in ln spp (uniform over a range this wide).
    #[serde(default)]
    pub subject_spread: f64,
    /// Seed of the simulated answers.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Threshold rules; a condition takes the first rule whose given factors all match.
    pub thresholds: Vec<ThresholdRule>,
}

fn default_seed() -> u64 {
    1
}

/// The threshold (spp at p = 0.75) of the conditions a rule matches; absent factors match all.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThresholdRule {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_set: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_filter: Option<String>,
    pub spp: f64,
}

impl ThresholdRule {
    fn matches(&self, c: &Condition) -> bool {
        let ok = |rule: &Option<String>, v: &str| rule.as_deref().is_none_or(|r| r == v);
        ok(&self.scene, &c.scene)
            && ok(&self.point_set, &c.point_set)
            && ok(&self.time_filter, &c.time_filter)
    }
}

/// A loaded, validated observer.
#[derive(Clone, Debug, PartialEq)]
pub struct Observer {
    pub path: PathBuf,
    pub file: ObserverFile,
}

impl Observer {
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read observer file {}", path.display()))?;
        Self::parse(path, &text)
    }

    pub fn parse(path: &Path, text: &str) -> Result<Self> {
        let file: ObserverFile = serde_json::from_str(text)
            .with_context(|| format!("{}: not a valid observer file", path.display()))?;
        validate(&file).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            file,
        })
    }

    /// The condition's threshold (spp), from the first matching rule.
    pub fn threshold(&self, c: &Condition) -> Option<f64> {
        self.file
            .thresholds
            .iter()
            .find(|r| r.matches(c))
            .map(|r| r.spp)
    }

    /// Refuse a design with a condition no rule covers.
    pub fn check_covers(&self, design: &Design) -> Result<()> {
        for c in conditions(design) {
            if self.threshold(&c).is_none() {
                bail!(
                    "{}: field `thresholds` has no rule for condition scene {:?}, point set {:?}, \
                     time filter {:?} of design {}",
                    self.path.display(),
                    c.scene,
                    c.point_set,
                    c.time_filter,
                    design.path.display()
                );
            }
        }
        Ok(())
    }

    /// One subject's threshold in a condition.
    pub fn subject_threshold(&self, c: &Condition, subject: &str) -> Option<f64> {
        let u = unit_f64(hash(self.file.seed, &[name_id(subject), 0x5b]));
        self.threshold(c)
            .map(|t| t * (self.file.subject_spread * (u - 0.5)).exp())
    }

    /// Probability of a correct answer at `spp` for a subject whose threshold is `t`.
    pub fn p_correct(&self, t: f64, spp: f64) -> f64 {
        let lapse = self.file.lapse;
        let q = (TARGET - 0.5) / (0.5 - lapse);
        let c = (q / (1.0 - q)).ln();
        let z = self.file.slope * (t.ln() - spp.ln()) + c;
        0.5 + (0.5 - lapse) * logistic(z)
    }

    /// Probability that the subject answers `trial` correctly: the condition's function at
    /// the trial's level, or exactly 1/2 when test and reference are the same video (the
    /// highest level under a `highest_level` reference: there is nothing to see).
    pub fn p_trial(&self, trial: &Trial, subject: &str) -> Result<f64> {
        let Some(t) = self.subject_threshold(&trial.condition, subject) else {
            bail!(
                "{}: no threshold rule covers scene {:?}, point set {:?}, time filter {:?}",
                self.path.display(),
                trial.condition.scene,
                trial.condition.point_set,
                trial.condition.time_filter
            );
        };
        if trial.test_stimulus == trial.reference_stimulus {
            return Ok(0.5);
        }
        Ok(self.p_correct(t, trial.level as f64))
    }

    /// The simulated subject's answer (pair 1 or 2), a pure function of the subject and the
    /// trial's place in the list.
    pub fn respond(&self, trial: &Trial, subject: &str) -> Result<u8> {
        let p = self.p_trial(trial, subject)?;
        let u = unit_f64(hash(
            self.file.seed,
            &[name_id(subject), trial.practice as u64, trial.index as u64],
        ));
        Ok(if u < p {
            trial.diff_pair
        } else {
            3 - trial.diff_pair
        })
    }
}

fn logistic(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

fn validate(f: &ObserverFile) -> Result<()> {
    if f.format != OBSERVER_FORMAT {
        bail!(
            "field `format` is {:?}; this version reads {OBSERVER_FORMAT:?}",
            f.format
        );
    }
    if !(f.slope.is_finite() && f.slope > 0.0) {
        bail!("field `slope` is {}; expected a positive number", f.slope);
    }
    if !(0.0..0.25).contains(&f.lapse) {
        bail!(
            "field `lapse` is {}; expected 0 <= lapse < 0.25 (at 0.25 or more the observer never \
             reaches p = 0.75)",
            f.lapse
        );
    }
    if !(f.subject_spread.is_finite() && f.subject_spread >= 0.0) {
        bail!(
            "field `subject_spread` is {}; expected a number >= 0",
            f.subject_spread
        );
    }
    if f.thresholds.is_empty() {
        bail!("field `thresholds` is empty; expected at least one rule");
    }
    for (i, r) in f.thresholds.iter().enumerate() {
        if !(r.spp.is_finite() && r.spp > 0.0) {
            bail!(
                "field `thresholds[{i}].spp` is {}; expected samples per pixel > 0",
                r.spp
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::tests::small;

    const OBS: &str = r#"{
        "format": "blurlab-observer/1", "name": "t", "slope": 2.0, "lapse": 0.04,
        "thresholds": [{"scene": "spheres", "point_set": "poisson", "spp": 200},
                       {"scene": "spheres", "spp": 100}, {"spp": 40}]
    }"#;

    fn cond(scene: &str, ps: &str) -> Condition {
        Condition {
            scene: scene.into(),
            point_set: ps.into(),
            time_filter: "box".into(),
        }
    }

    #[test]
    fn rules_match_first_specific_then_general() {
        let o = Observer::parse(Path::new("o.json"), OBS).unwrap();
        assert_eq!(o.threshold(&cond("spheres", "poisson")), Some(200.0));
        assert_eq!(o.threshold(&cond("spheres", "hammersley")), Some(100.0));
        assert_eq!(o.threshold(&cond("plane", "poisson")), Some(40.0));
        o.check_covers(&small()).unwrap();
    }

    #[test]
    fn threshold_is_where_p_is_075_whatever_the_lapse() {
        for lapse in [0.0, 0.04, 0.2] {
            let mut o = Observer::parse(Path::new("o.json"), OBS).unwrap();
            o.file.lapse = lapse;
            assert!((o.p_correct(40.0, 40.0) - 0.75).abs() < 1e-12);
            // Far below threshold the noise is plain: p -> 1 - lapse; far above, p -> 0.5.
            assert!((o.p_correct(40.0, 1e-9) - (1.0 - lapse)).abs() < 1e-6);
            assert!((o.p_correct(40.0, 1e12) - 0.5).abs() < 1e-6);
        }
    }

    #[test]
    fn zero_lapse_is_the_plain_logistic_of_the_brief() {
        let mut o = Observer::parse(Path::new("o.json"), OBS).unwrap();
        o.file.lapse = 0.0;
        let (t, spp, b) = (40.0f64, 8.0f64, 2.0);
        let expected = 0.5 + 0.5 / (1.0 + (-(b * (t.ln() - spp.ln()))).exp());
        assert!((o.p_correct(t, spp) - expected).abs() < 1e-12);
    }

    #[test]
    fn answers_follow_p() {
        // 20000 independent answers at p(8 spp): binomial standard error <= 0.0036; allow 4.5 sigma.
        let o = Observer::parse(Path::new("o.json"), OBS).unwrap();
        let d = small();
        let plan = crate::trials::plan(&d, "x");
        let mut trial = plan.main[0].clone();
        trial.condition = cond("plane", "hammersley");
        trial.level = 27;
        let n = 20_000;
        let correct = (0..n)
            .filter(|&i| {
                trial.index = i;
                o.respond(&trial, "x").unwrap() == trial.diff_pair
            })
            .count();
        let p = o.p_correct(40.0, 27.0);
        assert!((correct as f64 / n as f64 - p).abs() < 4.5 * 0.0036);
    }

    #[test]
    fn invalid_files_name_the_field() {
        for (text, field) in [
            (OBS.replace("\"slope\": 2.0", "\"slope\": 0"), "`slope`"),
            (OBS.replace("0.04", "0.3"), "`lapse`"),
            (
                OBS.replace("\"spp\": 40", "\"spp\": -1"),
                "`thresholds[2].spp`",
            ),
            (OBS.replace("observer/1", "observer/2"), "`format`"),
        ] {
            let e = format!(
                "{:#}",
                Observer::parse(Path::new("o.json"), &text).unwrap_err()
            );
            assert!(e.contains(field) && e.contains("o.json"), "{e}");
        }
        let uncovered = OBS.replace(", {\"spp\": 40}", "");
        let o = Observer::parse(Path::new("o.json"), &uncovered).unwrap();
        let e = o.check_covers(&small()).unwrap_err().to_string();
        assert!(e.contains("plane"), "{e}");
    }
}
