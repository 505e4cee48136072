//! What an analysis is asked to do: [`AnalyzeOptions`], every field with its default written
//! out (the flags of `blurlab analyze` map onto it), the validated
//! [`Settings`] it gives for a data set and design, and [`run_report`]: read, check, analyze,
//! write.

use crate::bootstrap::BootstrapSettings;
use crate::comparisons::{ComparisonSettings, PairOrder, Unit};
use crate::data::dropped::DroppedFrames;
use crate::data::{Dataset, Grouping, Source};
use crate::multilevel::MultilevelSettings;
use crate::psychometric::{FitSettings, GUESS, LapseMode};
use crate::report::{Preset, Report, Settings, analyze};
use crate::sigmoid::Sigmoid;
use crate::ttest::TestKind;
use anyhow::{Result, bail};
use experiment::Design;
use renderer::limits::MAX_RESAMPLES;
use serde::Serialize;
use std::path::PathBuf;

/// An analysis of session logs or counts tables (`blurlab analyze`; the flags' help says what
/// each field means).
#[derive(Clone, Debug, PartialEq)]
pub struct AnalyzeOptions {
    /// A sessions folder (every *.jsonl in it), session log files or counts tables.
    pub inputs: Vec<PathBuf>,
    /// Leave out main trials that fail the log checks, with a warning each.
    pub lenient: bool,
    /// Report folder.
    pub out: PathBuf,
    /// Proportion correct defining the JND.
    pub target: f64,
    /// Guess rate; `None`: the design's task, else 0.5 for session logs.
    pub guess: Option<f64>,
    /// The study's design file.
    pub design: Option<PathBuf>,
    pub sigmoid: Sigmoid,
    pub lapse: LapseMode,
    /// Parametric bootstrap resamples per pooled fit.
    pub bootstrap: usize,
    /// Master seed of the bootstrap.
    pub seed: u64,
    /// Levels (spp) of the t-tests.
    pub levels: Vec<u32>,
    /// Extra levels for the between-scene tests.
    pub scene_levels: Vec<u32>,
    pub test: TestKind,
    /// Significance level.
    pub alpha: f64,
    /// Unit of observation of the t-tests.
    pub unit: Unit,
    /// Subjects left out: `s03` or `s03=reason`.
    pub exclude: Vec<String>,
    pub preset: Option<Preset>,
    /// The model across subjects: the pooled fits only, or also the multilevel model.
    pub model: ModelKind,
    /// Equivalence margin in ln JND for the TOST of point sets and time filters (implies the
    /// multilevel model).
    pub equivalence: Option<f64>,
    /// Subject-bootstrap resamples of the multilevel model (0: none).
    pub subject_bootstrap: usize,
    /// Name main trials with more dropped frames than this (`None`: no check).
    pub max_dropped_frames: Option<u32>,
    /// Leave those trials out.
    pub exclude_dropped: bool,
    /// Name a subject with a larger share of such trials.
    pub max_dropped_share: f64,
    /// Exclusion criteria given as flags; each set field replaces the design's `exclusion`.
    pub criteria: experiment::design::online::Exclusion,
    /// Name the subjects the criteria exclude, but fit them all the same.
    pub keep_excluded: bool,
}

/// Which model across subjects `analyze` fits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// The pooled fits with their parametric bootstrap (and per-subject fits).
    #[default]
    Pooled,
    /// Also the multilevel model ([`crate::multilevel`]).
    Multilevel,
}

renderer::named!(ModelKind, "model", [Pooled => "pooled", Multilevel => "multilevel"]);

impl AnalyzeOptions {
    /// The defaults (those of `analyze <inputs> --out <out>`): target 0.75, logistic, lapse
    /// fixed at 0, 2000 bootstrap resamples with seed 1, paired t-tests per subject at 27, 64
    /// and 125 spp (scenes also at 216), alpha 0.05.
    pub fn new(inputs: Vec<PathBuf>, out: PathBuf) -> Self {
        Self {
            inputs,
            lenient: false,
            out,
            target: 0.75,
            guess: None,
            design: None,
            sigmoid: Sigmoid::Logistic,
            lapse: LapseMode::Fixed,
            bootstrap: 2000,
            seed: 1,
            levels: vec![27, 64, 125],
            scene_levels: vec![216],
            test: TestKind::Paired,
            alpha: 0.05,
            unit: Unit::Subject,
            exclude: Vec::new(),
            preset: None,
            model: ModelKind::Pooled,
            equivalence: None,
            subject_bootstrap: 200,
            max_dropped_frames: None,
            exclude_dropped: false,
            max_dropped_share: 0.2,
            criteria: Default::default(),
            keep_excluded: false,
        }
    }
}

impl AnalyzeOptions {
    /// Validated analysis settings, the guess rate from --guess or 0.5 (see
    /// [`AnalyzeOptions::settings_for`] for the default from the data and the design).
    pub fn settings(&self) -> Result<Settings> {
        self.settings_with_guess(self.guess.unwrap_or(GUESS))
    }

    /// Validated settings for this data: the guess rate from --guess, else the task of
    /// `design`, else 0.5 for session logs; the pair order from the design's factors, else
    /// the preset's.
    pub fn settings_for(&self, ds: &Dataset, design: Option<&Design>) -> Result<Settings> {
        let guess = match (self.guess, design) {
            (Some(g), _) => g,
            (None, Some(d)) => d.file.task.guess_rate(),
            (None, None) if ds.source == Source::CountsTables => bail!(
                "counts tables do not say the task: give --guess (1/m for m alternatives) or \
                 --design (its `task`)"
            ),
            (None, None) => GUESS,
        };
        let mut s = self.settings_with_guess(guess)?;
        if let Some(d) = design {
            let f = &d.file.factors;
            s.comparisons.order = PairOrder {
                scenes: f.scenes.clone(),
                point_sets: f.point_sets.iter().map(|p| p.to_string()).collect(),
                time_filters: f.time_filters.iter().map(|t| t.to_string()).collect(),
            };
        }
        Ok(s)
    }

    /// `--exclude` as (subject, reason) pairs, one per subject: a subject listed twice keeps
    /// every reason given (`s01,s01=tired` is s01 for "tired", not for no reason).
    pub fn exclusions(&self) -> Vec<(String, Option<String>)> {
        let mut out: Vec<(String, Option<String>)> = Vec::new();
        for e in &self.exclude {
            let (id, reason) = match e.split_once('=') {
                Some((id, r)) => (id.trim(), Some(r.trim()).filter(|r| !r.is_empty())),
                None => (e.trim(), None),
            };
            if id.is_empty() {
                continue;
            }
            match out.iter_mut().find(|(i, _)| i == id) {
                None => out.push((id.to_string(), reason.map(str::to_string))),
                Some((_, known)) => {
                    if let Some(r) = reason
                        && known.as_deref() != Some(r)
                    {
                        *known = Some(match known.take() {
                            Some(k) => format!("{k}; {r}"),
                            None => r.to_string(),
                        });
                    }
                }
            }
        }
        out
    }

    /// What the options leave unchecked, for the report's warnings: logs analysed without a design
    /// (a trial of an unknown scene or level becomes a group of its own), and a `--guess` that
    /// differs from the design's task (a two-pair guess rate on a four-alternative design).
    pub fn unchecked(&self, ds: &Dataset, design: Option<&Design>) -> Vec<String> {
        let mut out = Vec::new();
        match (design, self.guess) {
            (None, _) if ds.source == Source::SessionLogs => out.push(
                "no --design: the trials' scenes, point sets, time filters and levels were not \
                 checked against any design (a trial of an unknown scene becomes a group of its \
                 own); give --design to check them"
                    .to_string(),
            ),
            (Some(d), Some(g)) if (g - d.file.task.guess_rate()).abs() > 1e-9 => out.push(format!(
                "--guess {g} differs from the guess rate {} of --design {}'s task; the fits use \
                 --guess {g}",
                d.file.task.guess_rate(),
                d.path.display()
            )),
            _ => {}
        }
        out.extend(missing_scenes(ds));
        out
    }

    fn settings_with_guess(&self, guess: f64) -> Result<Settings> {
        let thesis = self.preset == Some(Preset::Thesis);
        // The preset's values; clap refuses the options it fixes, so these replace defaults.
        let (target, alpha, kind, unit) = if thesis {
            (0.75, 0.05, TestKind::Paired, Unit::Cell)
        } else {
            (self.target, self.alpha, self.test, self.unit)
        };
        let (levels, scene_levels) = if thesis {
            (vec![27, 64, 125], vec![216])
        } else {
            (self.levels.clone(), self.scene_levels.clone())
        };
        if !(guess > 0.0 && guess < 1.0) {
            bail!(
                "--guess is {}; expected a proportion in (0, 1), 1/m for m alternatives",
                renderer::limits::shortest(guess)
            );
        }
        if !(target > guess && target <= 0.9) {
            bail!(
                "--target is {}; expected a proportion correct in ({guess}, 0.9] (the guess \
                 rate {guess} is chance, and above 0.9 a free lapse of up to 0.06 could keep the \
                 function from reaching it)",
                renderer::limits::shortest(target)
            );
        }
        if !(alpha > 0.0 && alpha < 1.0) {
            bail!(
                "--alpha is {}; expected a level in (0, 1)",
                renderer::limits::shortest(alpha)
            );
        }
        if !(1000..=MAX_RESAMPLES).contains(&self.bootstrap) {
            bail!(
                "--bootstrap is {}; expected at least 1000 resamples for a 95% interval (and at \
                 most {MAX_RESAMPLES})",
                self.bootstrap
            );
        }
        if levels.contains(&0) || scene_levels.contains(&0) {
            bail!("--levels / --scene-levels: spp must be >= 1");
        }
        let multilevel = self.multilevel_settings()?;
        Ok(Settings {
            fit: FitSettings {
                sigmoid: self.sigmoid,
                lapse: self.lapse,
                guess,
            },
            target,
            bootstrap: BootstrapSettings {
                resamples: self.bootstrap,
                seed: self.seed,
                target,
                confidence: 0.95,
            },
            comparisons: ComparisonSettings {
                kind,
                levels,
                scene_extra_levels: scene_levels,
                alpha,
                unit,
                order: if thesis {
                    PairOrder::thesis()
                } else {
                    PairOrder::default()
                },
            },
            poor_fit_p: 0.05,
            preset: self.preset,
            multilevel,
        })
    }

    /// The dropped-frames policy, if `--max-dropped-frames` asks for one.
    fn dropped_frames(&self) -> Result<Option<DroppedFrames>> {
        if !(0.0..=1.0).contains(&self.max_dropped_share) {
            bail!(
                "--max-dropped-share is {}; expected a share of trials from 0 to 1",
                renderer::limits::shortest(self.max_dropped_share)
            );
        }
        match self.max_dropped_frames {
            None if self.exclude_dropped => bail!(
                "--exclude-dropped needs --max-dropped-frames N: the most dropped frames a \
                 trial may have"
            ),
            None => Ok(None),
            Some(max) => Ok(Some(DroppedFrames {
                max,
                exclude: self.exclude_dropped,
                max_share: self.max_dropped_share,
            })),
        }
    }

    /// The multilevel model's settings, if `--model multilevel` or `--equivalence` asks for it.
    fn multilevel_settings(&self) -> Result<Option<MultilevelSettings>> {
        if let Some(m) = self.equivalence
            && !(m > 0.0 && m < 5.0)
        {
            bail!(
                "--equivalence is {}; expected a margin in ln JND in (0, 5), e.g. 0.2 for a \
                 ratio within 0.82-1.22",
                renderer::limits::shortest(m)
            );
        }
        if self.subject_bootstrap != 0 && !(200..=MAX_RESAMPLES).contains(&self.subject_bootstrap) {
            bail!(
                "--subject-bootstrap is {}; expected 0 (none) or 200 to {MAX_RESAMPLES} resamples",
                self.subject_bootstrap
            );
        }
        let on = self.model == ModelKind::Multilevel || self.equivalence.is_some();
        Ok(on.then(|| MultilevelSettings {
            resamples: self.subject_bootstrap,
            seed: self.seed,
            equivalence: self.equivalence,
            ..MultilevelSettings::default()
        }))
    }
}

/// Here rather than beside [`Settings`], so that the report does not import the options (which
/// import the report's writer): no `options -> output -> figures -> report -> options` cycle.
impl Default for Settings {
    /// The `analyze` command's defaults (logistic, lapse 0, target 0.75, 2000 resamples,
    /// paired tests at 27, 64, 125 and 216 spp for scenes, alpha 0.05):
    /// [`AnalyzeOptions`]'s, written out there.
    fn default() -> Self {
        AnalyzeOptions::new(Vec::new(), std::path::PathBuf::new())
            .settings()
            .expect("the defaults are valid")
    }
}

/// Read the logs, analyze, write the report files and figures; returns the report (e.g. for
/// [`Report::summary`]). Tolerated problems (torn last lines) are in `Report::warnings` (and
/// `report.md`); printing them is the caller's (`cli::run` does).
pub fn run_report(args: &AnalyzeOptions) -> Result<Report> {
    if args.guess.is_some() || args.design.is_none() {
        // Refuse bad options before reading any data (with a design the guess rate, and so
        // the valid targets, come from its task).
        args.settings()?;
    }
    let dropped = args.dropped_frames()?;
    let design = args.design.as_deref().map(Design::load).transpose()?;
    let mut ds = Dataset::read_with(
        &args.inputs,
        design.as_ref(),
        args.lenient,
        dropped.as_ref(),
    )?;
    if let Some(d) = &design {
        check_design(d, &ds)?;
    }
    ds.exclude(&args.exclusions())?;
    let criteria = crate::exclusions::merged(
        design.as_ref().and_then(|d| d.file.exclusion.as_ref()),
        &args.criteria,
    );
    let screened = crate::exclusions::screen(&criteria, args.keep_excluded, &mut ds)?;
    if (args.model == ModelKind::Multilevel || args.equivalence.is_some()) && ds.subjects.len() < 2
    {
        bail!(
            "--model multilevel{}: the data hold {} subject{} ({}); the model's intervals and \
             TOST use Student t with subjects - 1 df, so they need at least 2 subjects (as \
             `plan --equivalence` refuses 1)",
            args.equivalence
                .map_or(String::new(), |m| format!(" / --equivalence {m}")),
            ds.subjects.len(),
            if ds.subjects.len() == 1 { "" } else { "s" },
            ds.subjects.join(", ")
        );
    }
    ds.warnings.extend(args.unchecked(&ds, design.as_ref()));
    let settings = args.settings_for(&ds, design.as_ref())?;
    let report = analyze(&ds, &settings);
    crate::output::write(&report, &args.out)?;
    if let Some(csv) = screened {
        renderer::atomic::write_atomic(&args.out.join("exclusions.csv"), csv.as_bytes())?;
    }
    if let Some(d) = &design {
        crate::adaptive::write(d, &ds.files, &report, &args.out)?;
    }
    Ok(report)
}

/// A subject with no trial of a whole scene: the tests that pair scenes leave them out, so
/// their degrees of freedom (the thesis's Table 1's df) fall without the data saying why.
fn missing_scenes(ds: &Dataset) -> Vec<String> {
    let mut out = Vec::new();
    for g in ds.groups_of(Grouping::Scene) {
        for (subject, curve) in ds.subjects.iter().zip(&g.per_subject) {
            if curve.total_trials() == 0 {
                out.push(format!(
                    "subject {subject:?} has no trial of scene {:?}: the scene tests leave \
                     {subject:?} out, which lowers their degrees of freedom (Table 1's df)",
                    g.key.label
                ));
            }
        }
    }
    out
}

/// Session logs must come from `design` (same hash); counts tables carry no hash.
fn check_design(design: &Design, ds: &Dataset) -> Result<()> {
    if ds.source == Source::SessionLogs && ds.design_hash != design.hash {
        bail!(
            "--design {} has design hash {:?}, but the session logs ({}) carry {:?} (design \
             {:?}); give the design the logs were recorded with",
            design.path.display(),
            design.hash,
            ds.files
                .first()
                .map_or(String::new(), |f| f.display().to_string()),
            ds.design_hash,
            ds.design
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_subject_excluded_twice_keeps_its_reasons() {
        let with = |list: &[&str]| AnalyzeOptions {
            exclude: list.iter().map(|s| s.to_string()).collect(),
            ..AnalyzeOptions::new(Vec::new(), PathBuf::new())
        };
        let tired = Some("tired".to_string());
        let e = with(&["s01", "s01=tired"]).exclusions();
        assert_eq!(e, vec![("s01".to_string(), tired.clone())]);
        let e = with(&["s01=tired", "s02", "s01", "s01=tired"]).exclusions();
        assert_eq!(e[0], ("s01".to_string(), tired));
        assert_eq!(e[1], ("s02".to_string(), None));
        let e = with(&["s01=tired", "s01=left early"]).exclusions();
        assert_eq!(e[0].1.as_deref(), Some("tired; left early"));
    }

    #[test]
    fn a_subject_without_a_whole_scene_is_warned_about() {
        use crate::data::Observation;
        let obs = |subject: &str, scene: &str| Observation {
            subject: subject.into(),
            scene: scene.into(),
            point_set: "sobol".into(),
            time_filter: "box".into(),
            level: 8,
            correct: true,
        };
        let all = [
            obs("s01", "plane"),
            obs("s01", "spheres"),
            obs("s02", "plane"),
        ];
        let w = missing_scenes(&Dataset::from_observations(&all));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("\"s02\" has no trial of scene \"spheres\""),
            "{w:?}"
        );
        assert!(missing_scenes(&Dataset::from_observations(&all[..2])).is_empty());
    }
}
