//! Simulated observers (`scenes/<study>/observer.json`, format `blurlab-observer/1`): a known
//! two-alternative psychometric function per condition ([`crate::psychometric::p_correct`]),
//! for piloting a design and for testing the analysis against a known truth.
//!
//! Each subject's T is the condition's threshold times exp(spread (u - 1/2)), u uniform from
//! the subject's name: subjects differ in sensitivity, not in which condition is harder.
//!
//! A *predicted* observer answers from `blurlab predict`'s `predicted.csv` instead of typed-in
//! thresholds: `simulate --observer predicted.csv`, or an observer file whose `predicted` field
//! names that file (to set `subject_spread`, `lapse`, `seed`). Its p(spp) is the predicted
//! curve of the condition (`crate::predicted::Curve`), scaled by the same per-subject factor:
//! p_subject(spp) = (1 - 2 lapse) p_pred(spp / f) + lapse, f = exp(spread (u - 1/2)).

use crate::design::Design;
use crate::predicted::PredictedTable;
use crate::psychometric::{TARGET, p_correct};
use crate::trials::{Condition, Trial, conditions};
use anyhow::{Context, Result, bail};
use renderer::condition::{PointSetKind, TimeFilter};
use renderer::hash::{hash, name_id, unit_f64};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The format tag of an observer file.
pub const OBSERVER_FORMAT: &str = "blurlab-observer/1";

/// Bounds of an observer file's numbers (JSON holds no NaN or infinity, but 1e300 parses):
/// a slope of 100 per ln spp already goes from chance to certainty within 2% of the
/// threshold; a spread of 10 scatters thresholds over a factor e^10 = 22026; thresholds may lie
/// far beyond any rendered level (an observer who never sees the noise), but not past 1e9.
pub const MAX_SLOPE: f64 = 100.0;
pub const MAX_SUBJECT_SPREAD: f64 = 10.0;
pub const MAX_THRESHOLD_SPP: f64 = 1e9;

/// The observer file as written on disk.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObserverFile {
    pub format: String,
    pub name: String,
    /// Logistic slope in 1 / ln spp (> 0; threshold observers only).
    #[serde(default, skip_serializing_if = "is_zero")]
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
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub thresholds: Vec<ThresholdRule>,
    /// A `predicted.csv` (relative to this file) to answer from instead of `thresholds`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub predicted: Option<String>,
}

fn default_seed() -> u64 {
    1
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// Subject spread of a predicted observer given as a bare `predicted.csv`: the thesis
/// observer's (`scenes/thesis/observer.json`).
pub const PREDICTED_SUBJECT_SPREAD: f64 = 0.6;

/// The threshold (spp at p = 0.75) of the conditions a rule matches; absent factors match all.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThresholdRule {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_set: Option<PointSetKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_filter: Option<TimeFilter>,
    pub spp: f64,
}

impl ThresholdRule {
    fn matches(&self, c: &Condition) -> bool {
        self.scene.as_ref().is_none_or(|r| *r == c.scene)
            && self.point_set.is_none_or(|r| r == c.point_set)
            && self.time_filter.is_none_or(|r| r == c.time_filter)
    }
}

/// A loaded, validated observer.
#[derive(Clone, Debug, PartialEq)]
pub struct Observer {
    pub path: PathBuf,
    pub file: ObserverFile,
    /// The prediction a predicted observer answers from.
    pub predicted: Option<PredictedTable>,
}

impl Observer {
    /// An observer file (JSON), or a `predicted.csv` (by its `.csv` extension).
    pub fn load(path: &Path) -> Result<Self> {
        if path.extension().is_some_and(|e| e == "csv") {
            return Ok(Self::from_prediction(path, PredictedTable::load(path)?));
        }
        let text = renderer::utf8::read(path, "observer file")?;
        let mut o = Self::parse(path, &text)?;
        if let Some(p) = &o.file.predicted {
            let csv = path.parent().unwrap_or(Path::new("")).join(p);
            o.predicted = Some(
                PredictedTable::load(&csv)
                    .with_context(|| format!("{}: field `predicted`", path.display()))?,
            );
        }
        Ok(o)
    }

    /// Parse an observer file; a `predicted` file it names is not read (see [`Self::load`]).
    pub fn parse(path: &Path, text: &str) -> Result<Self> {
        let file: ObserverFile = renderer::json::from_str(text, path, "observer file")?;
        validate(&file).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            file,
            predicted: None,
        })
    }

    /// A predicted observer with the defaults of a bare `predicted.csv`: the thesis
    /// observer's subject spread, no lapse, seed 1.
    pub fn from_prediction(path: &Path, table: PredictedTable) -> Self {
        Self {
            path: path.to_path_buf(),
            file: ObserverFile {
                format: OBSERVER_FORMAT.into(),
                name: path
                    .file_stem()
                    .map_or("predicted".into(), |s| s.to_string_lossy().into_owned()),
                slope: 0.0,
                lapse: 0.0,
                subject_spread: PREDICTED_SUBJECT_SPREAD,
                seed: default_seed(),
                thresholds: Vec::new(),
                predicted: Some(path.display().to_string()),
            },
            predicted: Some(table),
        }
    }

    /// The condition's threshold (spp at p = 0.75): from the first matching rule, or where the
    /// predicted curve crosses 0.75.
    pub fn threshold(&self, c: &Condition) -> Option<f64> {
        if let Some(t) = &self.predicted {
            return t.curve(c).and_then(|curve| curve.spp_at(TARGET));
        }
        self.file
            .thresholds
            .iter()
            .find(|r| r.matches(c))
            .map(|r| r.spp)
    }

    /// Whether the observer has an answer for a condition.
    fn covers(&self, c: &Condition) -> bool {
        match &self.predicted {
            Some(t) => t.curve(c).is_some(),
            None => self.threshold(c).is_some(),
        }
    }

    /// A subject's threshold factor f = exp(spread (u - 1/2)).
    pub fn subject_factor(&self, subject: &str) -> f64 {
        let u = unit_f64(hash(self.file.seed, &[name_id(subject), 0x5b]));
        (self.file.subject_spread * (u - 0.5)).exp()
    }

    /// Probability that `subject` answers a trial of condition `c` at `spp` correctly.
    pub fn p_subject(&self, c: &Condition, subject: &str, spp: f64) -> Option<f64> {
        self.p_factor(c, self.subject_factor(subject), spp)
    }

    /// Probability correct at `spp` in condition `c` for a subject of threshold factor `f`.
    pub fn p_factor(&self, c: &Condition, f: f64, spp: f64) -> Option<f64> {
        match &self.predicted {
            Some(t) => {
                let p = t.curve(c)?.p_correct_at(spp / f);
                let lapse = self.file.lapse;
                Some((1.0 - 2.0 * lapse) * p + lapse)
            }
            None => self.threshold(c).map(|t| self.p_correct(t * f, spp)),
        }
    }

    /// The population's mean probability correct in condition `c` at `spp`: the subject factor
    /// integrated over u (200 midpoint nodes).
    pub fn p_population(&self, c: &Condition, spp: f64) -> Option<f64> {
        let n = 200;
        let mut sum = 0.0;
        for i in 0..n {
            let u = (i as f64 + 0.5) / n as f64;
            sum += self.p_factor(c, (self.file.subject_spread * (u - 0.5)).exp(), spp)?;
        }
        Some(sum / n as f64)
    }

    /// Refuse a design with a condition no rule covers.
    pub fn check_covers(&self, design: &Design) -> Result<()> {
        let field = if self.predicted.is_some() {
            "predicted"
        } else {
            "thresholds"
        };
        for c in conditions(design) {
            if !self.covers(&c) {
                bail!(
                    "{}: field `{field}` has no rule or row for condition scene {:?}, point set {:?}, \
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
        self.threshold(c).map(|t| t * self.subject_factor(subject))
    }

    /// Probability of a correct answer at `spp` for a subject whose threshold is `t`.
    pub fn p_correct(&self, t: f64, spp: f64) -> f64 {
        p_correct(self.file.slope, self.file.lapse, t.ln(), spp.ln())
    }

    /// Probability that the subject answers `trial` correctly: the condition's function at
    /// the trial's level, or exactly 1/2 when test and reference are the same video (the
    /// highest level under a `highest_level` reference: there is nothing to see).
    pub fn p_trial(&self, trial: &Trial, subject: &str) -> Result<f64> {
        let Some(p) = self.p_subject(&trial.condition, subject, trial.level as f64) else {
            bail!(
                "{}: no threshold rule or prediction covers scene {:?}, point set {:?}, time filter {:?}",
                self.path.display(),
                trial.condition.scene,
                trial.condition.point_set,
                trial.condition.time_filter
            );
        };
        if trial.test_stimulus == trial.reference_stimulus {
            return Ok(0.5);
        }
        Ok(p)
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

fn validate(f: &ObserverFile) -> Result<()> {
    if f.format != OBSERVER_FORMAT {
        bail!(
            "field `format` is {:?}; this version reads {OBSERVER_FORMAT:?}",
            f.format
        );
    }
    if f.predicted.is_some() {
        if !f.thresholds.is_empty() {
            bail!("fields `thresholds` and `predicted` are both given; an observer uses one");
        }
    } else if !(f.slope > 0.0 && f.slope <= MAX_SLOPE) {
        bail!(
            "field `slope` is {:?} (or missing); expected a number above 0 and at most {MAX_SLOPE} \
             (per ln spp; {MAX_SLOPE} is already a step)",
            f.slope
        );
    }
    if !(0.0..0.25).contains(&f.lapse) {
        bail!(
            "field `lapse` is {}; expected 0 <= lapse < 0.25 (at 0.25 or more the observer never \
             reaches p = 0.75)",
            renderer::limits::shortest(f.lapse)
        );
    }
    if !(0.0..=MAX_SUBJECT_SPREAD).contains(&f.subject_spread) {
        bail!(
            "field `subject_spread` is {:?}; expected a number from 0 to {MAX_SUBJECT_SPREAD} (ln \
             spp: thresholds spread over a factor e^{MAX_SUBJECT_SPREAD})",
            f.subject_spread
        );
    }
    if f.thresholds.is_empty() && f.predicted.is_none() {
        bail!("field `thresholds` is empty; expected at least one rule (or a `predicted` file)");
    }
    for (i, r) in f.thresholds.iter().enumerate() {
        if !(r.spp > 0.0 && r.spp <= MAX_THRESHOLD_SPP) {
            bail!(
                "field `thresholds[{i}].spp` is {:?}; expected samples per pixel above 0 and at \
                 most {MAX_THRESHOLD_SPP:e}",
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
        Condition::new(scene, ps.parse().unwrap(), TimeFilter::Box)
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
    fn predicted_observers_answer_from_the_curve_shifted_by_the_subject_factor() {
        use crate::predicted::tests::row;
        let dir = tempfile::tempdir().unwrap();
        // d' = 12 spp^-1/2 for every condition of the small design.
        let mut rows = Vec::new();
        for scene in ["plane", "spheres"] {
            for ps in ["hammersley", "poisson"] {
                for spp in [1, 8, 27] {
                    rows.push(row(scene, ps, spp, 12.0 / (spp as f64).sqrt()));
                }
            }
        }
        let csv = dir.path().join("predicted.csv");
        std::fs::write(&csv, PredictedTable::from_rows(rows).to_csv().unwrap()).unwrap();
        let o = Observer::load(&csv).unwrap();
        assert_eq!(o.file.subject_spread, PREDICTED_SUBJECT_SPREAD);
        o.check_covers(&small()).unwrap();
        let c = cond("plane", "poisson");
        let f = o.subject_factor("x");
        let p = o.p_subject(&c, "x", 27.0).unwrap();
        let expected = crate::predicted::two_pair_p_correct(12.0 / (27.0 / f).sqrt());
        assert!((p - expected).abs() < 1e-12);
        // The threshold is where the unshifted curve crosses 0.75, and the subject's is f times it.
        let t = o.threshold(&c).unwrap();
        let ts = o.subject_threshold(&c, "x").unwrap();
        assert!(
            (o.p_subject(&c, "x", ts).unwrap() - 0.75).abs() < 1e-9,
            "{t} {ts}"
        );
        // A JSON observer naming the file: its lapse and spread apply.
        let json = dir.path().join("o.json");
        std::fs::write(
            &json,
            r#"{"format": "blurlab-observer/1", "name": "p", "predicted": "predicted.csv",
                "lapse": 0.04, "subject_spread": 0.0}"#,
        )
        .unwrap();
        let o = Observer::load(&json).unwrap();
        let p = o.p_subject(&c, "x", 1.0).unwrap();
        let raw = crate::predicted::two_pair_p_correct(12.0);
        assert!((p - (0.92 * raw + 0.04)).abs() < 1e-12);
        let both = r#"{"format": "blurlab-observer/1", "name": "p", "predicted": "a.csv",
                       "thresholds": [{"spp": 4}]}"#;
        let e = Observer::parse(Path::new("o.json"), both).unwrap_err();
        assert!(e.to_string().contains("`predicted`"));
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
