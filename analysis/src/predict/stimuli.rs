//! A whole stimulus set: every test stimulus against its reference, in parallel over stimuli
//! (each stimulus's frames in order on one thread, so results do not depend on the thread
//! count), then each condition's predicted psychometric function and JND.
//!
//! Which pairs: with a design, exactly the (test, reference) pairs its trials show (one
//! subject's trial list holds every condition x level), so the prediction follows the design's
//! choice of references; without one, every non-reference stimulus of the manifest against its
//! scene's reference.

use super::stage_choice::StageChoice;
use crate::jnd::Threshold;
use crate::observer::model::decision_stage::DecisionStage;
use crate::observer::model::display::Display;
use crate::observer::model::pooling::{FITTED, Grid, Placement, video_q};
use crate::observer::model::proportion_correct::two_pair_p_correct;
use crate::observer::model::shape;
use crate::observer::model::video::{ADAPTATION_FLOOR, Filters, Viewing, frame_differences};
use anyhow::{Context, Result, bail};
use experiment::Design;
use experiment::display::DisplaySpec;
use experiment::playback::frames::{VideoSource, load_frame};
use experiment::predicted::{Curve, PredictedRow};
use experiment::psychometric::TARGET;
use experiment::trials::Condition;
use rayon::prelude::*;
use renderer::manifest::Manifest;
use renderer::progress::Progress;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to predict with.
#[derive(Clone, Debug)]
pub struct PredictSettings {
    pub display: DisplaySpec,
    /// Sensitivity constant: d' = k Q.
    pub k: f64,
    /// How test and reference are compared, and why ([`StageChoice::for_layout`] by default).
    pub decision: StageChoice,
}

/// One test stimulus's prediction.
#[derive(Clone, Debug)]
pub struct StimulusPrediction {
    pub row: PredictedRow,
    /// Q of each frame (frame t of the test against frame t of the reference).
    pub q_frames: Vec<f64>,
    /// Thread CPU-free measure: wall seconds this stimulus took on its thread.
    pub seconds: f64,
}

/// The spread of single-frame JNDs of one condition.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSpread {
    /// Min, median and max of the frames whose JND falls inside the levels.
    pub inside: Option<[f64; 3]>,
    pub below: usize,
    pub above: usize,
    pub frames: usize,
}

/// A condition's predicted psychometric function at the rendered levels and its JND.
#[derive(Clone, Debug)]
pub struct ConditionPrediction {
    pub condition: Condition,
    /// (spp, d', p) at each level, sorted.
    pub points: Vec<(u32, f64, f64)>,
    /// Per level, the min and max over frames of the single-frame p.
    pub frame_p: Vec<(f64, f64)>,
    pub jnd: Threshold,
    pub frame_jnd: FrameSpread,
}

/// A predicted stimulus set.
#[derive(Clone, Debug)]
pub struct Prediction {
    pub job: String,
    pub manifest_path: PathBuf,
    pub display: DisplaySpec,
    pub pixels_per_degree: f64,
    pub k: f64,
    /// The decision stage that ran and why.
    pub decision: StageChoice,
    pub stimuli: Vec<StimulusPrediction>,
    pub conditions: Vec<ConditionPrediction>,
    pub wall_seconds: f64,
}

/// A pair to compare.
#[derive(Clone, Debug)]
struct Pair {
    condition: Condition,
    spp: u32,
    test: String,
    reference: String,
}

fn pairs(manifest: &Manifest, manifest_path: &Path, design: Option<&Design>) -> Result<Vec<Pair>> {
    let mut out = BTreeMap::new();
    match design {
        Some(d) => {
            for t in experiment::trials::plan(d, "predict").main {
                out.entry(t.test_stimulus.clone()).or_insert(Pair {
                    condition: t.condition.clone(),
                    spp: t.level,
                    test: t.test_stimulus,
                    reference: t.reference_stimulus,
                });
            }
        }
        None => {
            for s in manifest.stimuli.iter().filter(|s| !s.reference) {
                let Some(r) = manifest.reference(&s.scene) else {
                    bail!(
                        "{}: scene {:?} has no reference stimulus",
                        manifest_path.display(),
                        s.scene
                    );
                };
                out.insert(
                    s.id.clone(),
                    Pair {
                        condition: s.condition(),
                        spp: s.spp,
                        test: s.id.clone(),
                        reference: r.id.clone(),
                    },
                );
            }
        }
    }
    if out.is_empty() {
        bail!("{}: no test stimuli to predict", manifest_path.display());
    }
    Ok(out.into_values().collect())
}

/// The reference's mean luminance over all pixels and frames.
pub fn mean_luminance(video: &VideoSource, display: &Display) -> Result<f64> {
    let mut sum = 0.0;
    let mut n = 0usize;
    for i in 0..video.frame_paths.len() {
        let l = display.luminance(&load_frame(video, i)?.rgb);
        sum += l.iter().map(|&v| v as f64).sum::<f64>();
        n += l.len();
    }
    Ok(sum / n.max(1) as f64)
}

/// Predict every pair of a stimulus set (`manifest_path`: the manifest file or its folder);
/// `progress` counts pairs.
pub fn predict(
    manifest_path: &Path,
    design: Option<&Design>,
    s: &PredictSettings,
    progress: &dyn Progress,
) -> Result<Prediction> {
    let t0 = Instant::now();
    s.display.validate()?;
    let manifest = Manifest::load(manifest_path)?;
    let pairs = pairs(&manifest, manifest_path, design)?;
    let mut ids: Vec<&str> = pairs
        .iter()
        .flat_map(|p| [&*p.test, &*p.reference])
        .collect();
    ids.sort_unstable();
    ids.dedup();
    super::preflight::check(&manifest, manifest_path, &ids)?;
    let display = Display::new(&s.display);
    // Each video at the rate the design plays it (`playback.fps`), else the manifest's.
    let video = |id: &str| {
        let v = VideoSource::from_manifest(&manifest, manifest_path, id)?;
        Ok::<_, anyhow::Error>(match design {
            Some(d) => v.played_by(d),
            None => v,
        })
    };
    let mut references: Vec<&str> = pairs.iter().map(|p| p.reference.as_str()).collect();
    references.sort_unstable();
    references.dedup();
    let means: BTreeMap<&str, f64> = references
        .par_iter()
        .map(|&r| Ok((r, mean_luminance(&video(r)?, &display)?)))
        .collect::<Result<_>>()?;
    progress.start(pairs.len() as u64);
    progress.message("predicting");
    // Each worker keeps the filters of its last viewing: pairs against one reference share
    // them, and building them (CSF, band and orientation windows at every frequency) costs
    // about a fifth of a 768 x 768 frame pair.
    let stimuli = pairs
        .par_iter()
        .map_init(FilterCache::default, |cache, p| {
            let r = predict_pair(
                cache,
                p,
                &video(&p.test)?,
                &video(&p.reference)?,
                &display,
                means[p.reference.as_str()],
                s,
            )
            .with_context(|| format!("stimulus {} against {}", p.test, p.reference));
            progress.advance(1);
            r
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let conditions = conditions(&stimuli, s.k);
    Ok(Prediction {
        job: manifest.job.clone(),
        manifest_path: manifest_path.to_path_buf(),
        display: s.display.clone(),
        pixels_per_degree: display.pixels_per_degree,
        k: s.k,
        decision: s.decision.clone(),
        stimuli,
        conditions,
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The filters of the last viewing a worker predicted (one stage per run, so the viewing is
/// the key).
#[derive(Default)]
struct FilterCache(Option<(Viewing, Filters)>);

impl FilterCache {
    /// The filters for `viewing` deciding with `stage`, built unless they are the last.
    fn get(&mut self, viewing: Viewing, stage: DecisionStage) -> Result<&mut Filters> {
        if self.0.as_ref().is_none_or(|(v, _)| *v != viewing) {
            let filters = Filters::new(viewing, FITTED.channels, shape::FITTED)?
                .with_stage(stage, FITTED.space);
            self.0 = Some((viewing, filters));
        }
        Ok(&mut self.0.as_mut().expect("just set").1)
    }
}

fn predict_pair(
    cache: &mut FilterCache,
    p: &Pair,
    test: &VideoSource,
    reference: &VideoSource,
    display: &Display,
    mean: f64,
    s: &PredictSettings,
) -> Result<StimulusPrediction> {
    let k = s.k;
    let t0 = Instant::now();
    if (test.width, test.height, test.frames())
        != (reference.width, reference.height, reference.frames())
    {
        bail!(
            "the test is {}x{} with {} frames, the reference {}x{} with {}",
            test.width,
            test.height,
            test.frames(),
            reference.width,
            reference.height,
            reference.frames()
        );
    }
    let viewing = Viewing {
        width: test.width as usize,
        height: test.height as usize,
        frames: test.frames() as usize,
        fps: test.fps,
        pixels_per_degree: display.pixels_per_degree,
        // A black reference has no adaptation level; the floor of the local adaptation applies.
        mean_luminance: mean.max(ADAPTATION_FLOOR as f64),
    };
    let filters = cache.get(viewing, s.decision.stage)?;
    let q_frames: Vec<f64> =
        frame_differences(filters, &Grid::one(FITTED), Placement::MostVisible, |i| {
            Ok((
                display.luminance(&load_frame(test, i)?.rgb),
                display.luminance(&load_frame(reference, i)?.rgb),
            ))
        })?
        .into_iter()
        .map(|q| q[0])
        .collect();
    Ok(StimulusPrediction {
        row: row(p, &q_frames, k),
        q_frames,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// A CSV row from a pair's per-frame Q.
fn row(p: &Pair, q_frames: &[f64], k: f64) -> PredictedRow {
    let q = video_q(q_frames, FITTED.space);
    let mut pf: Vec<f64> = q_frames
        .iter()
        .map(|&qt| two_pair_p_correct(k * qt))
        .collect();
    pf.sort_by(f64::total_cmp);
    PredictedRow {
        scene: p.condition.scene.clone(),
        point_set: p.condition.point_set,
        time_filter: p.condition.time_filter,
        spp: p.spp,
        test_stimulus: p.test.clone(),
        reference_stimulus: p.reference.clone(),
        q,
        k,
        d_prime: k * q,
        p_correct: two_pair_p_correct(k * q),
        p_frame_min: pf[0],
        p_frame_median: median(&pf),
        p_frame_max: pf[pf.len() - 1],
        frames: q_frames.len() as u32,
    }
}

/// The same prediction with another sensitivity constant (rows and conditions recomputed).
pub fn with_k(p: &Prediction, k: f64) -> Prediction {
    let stimuli: Vec<StimulusPrediction> = p
        .stimuli
        .iter()
        .map(|s| {
            let pair = Pair {
                condition: s.row.condition(),
                spp: s.row.spp,
                test: s.row.test_stimulus.clone(),
                reference: s.row.reference_stimulus.clone(),
            };
            StimulusPrediction {
                row: row(&pair, &s.q_frames, k),
                ..s.clone()
            }
        })
        .collect();
    Prediction {
        conditions: conditions(&stimuli, k),
        stimuli,
        k,
        ..p.clone()
    }
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// The JND of a curve given at levels, never extrapolated: below / above range, or the
/// crossing of p = 0.75 between two levels (d' interpolated in log-log as the observer does).
pub fn threshold(points: &[(u32, f64)]) -> Threshold {
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Threshold::Undefined {
            reason: "no levels".into(),
        };
    };
    let p = |d: f64| two_pair_p_correct(d);
    if p(first.1) < TARGET {
        return Threshold::BelowRange { bound: first.0 };
    }
    if p(last.1) > TARGET {
        return Threshold::AboveRange { bound: last.0 };
    }
    // The first rendered segment that crosses p = 0.75. Near the model's noise floor a curve
    // can rise again after it (a 2197-spp reference: p 0.519 at 343 spp, 0.524 at 512), and a
    // search over all spp, extrapolating past the last level, would find no crossing.
    let Some(i) = (1..points.len()).find(|&i| p(points[i].1) <= TARGET) else {
        return Threshold::Value {
            spp: first.0 as f64,
        };
    };
    let curve = Curve {
        points: points.iter().map(|&(s, d)| (s as f64, d)).collect(),
    };
    // Along one segment d' is a power of spp: one crossing.
    match curve.spp_between(TARGET, points[i - 1].0 as f64, points[i].0 as f64) {
        Some(spp) => Threshold::Value { spp },
        None => Threshold::Undefined {
            reason: "the predicted curve does not cross 0.75".into(),
        },
    }
}

fn conditions(stimuli: &[StimulusPrediction], k: f64) -> Vec<ConditionPrediction> {
    let mut by: BTreeMap<Condition, Vec<&StimulusPrediction>> = BTreeMap::new();
    for s in stimuli {
        by.entry(s.row.condition()).or_default().push(s);
    }
    by.into_iter()
        .map(|(condition, mut list)| {
            list.sort_by_key(|s| s.row.spp);
            let points: Vec<(u32, f64, f64)> = list
                .iter()
                .map(|s| (s.row.spp, s.row.d_prime, s.row.p_correct))
                .collect();
            let jnd = threshold(&points.iter().map(|&(s, d, _)| (s, d)).collect::<Vec<_>>());
            let frames = list.iter().map(|s| s.q_frames.len()).min().unwrap_or(0);
            let frame_thresholds: Vec<Threshold> = (0..frames)
                .map(|t| {
                    threshold(
                        &list
                            .iter()
                            .map(|s| (s.row.spp, k * s.q_frames[t]))
                            .collect::<Vec<_>>(),
                    )
                })
                .collect();
            ConditionPrediction {
                frame_p: list
                    .iter()
                    .map(|s| (s.row.p_frame_min, s.row.p_frame_max))
                    .collect(),
                condition,
                points,
                jnd,
                frame_jnd: spread(&frame_thresholds),
            }
        })
        .collect()
}

fn spread(ts: &[Threshold]) -> FrameSpread {
    let mut inside: Vec<f64> = ts
        .iter()
        .filter_map(|t| match t {
            Threshold::Value { spp } => Some(*spp),
            _ => None,
        })
        .collect();
    inside.sort_by(f64::total_cmp);
    FrameSpread {
        inside: (!inside.is_empty())
            .then(|| [inside[0], median(&inside), inside[inside.len() - 1]]),
        below: ts
            .iter()
            .filter(|t| matches!(t, Threshold::BelowRange { .. }))
            .count(),
        above: ts
            .iter()
            .filter(|t| matches!(t, Threshold::AboveRange { .. }))
            .count(),
        frames: ts.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_visible_difference_is_exactly_chance() {
        let pair = Pair {
            condition: Condition::new(
                "s",
                renderer::condition::PointSetKind::Random,
                renderer::condition::TimeFilter::Box,
            ),
            spp: 8,
            test: "s-reference".into(),
            reference: "s-reference".into(),
        };
        let r = row(&pair, &[0.0; 4], 1.0);
        assert_eq!(r.p_correct, 0.5);
        assert_eq!([r.p_frame_min, r.p_frame_median, r.p_frame_max], [0.5; 3]);
    }

    #[test]
    fn thresholds_are_never_extrapolated() {
        // d' = 8 / sqrt(spp): p = 0.75 at spp = (8 / 2.1036)^2 = 14.46.
        let pts: Vec<(u32, f64)> = [1u32, 8, 27, 64]
            .iter()
            .map(|&s| (s, 8.0 / (s as f64).sqrt()))
            .collect();
        match threshold(&pts) {
            Threshold::Value { spp } => assert!((spp - 14.463).abs() < 0.01, "{spp}"),
            t => panic!("{t:?}"),
        }
        assert_eq!(threshold(&pts[2..]), Threshold::BelowRange { bound: 27 });
        assert_eq!(threshold(&pts[..2]), Threshold::AboveRange { bound: 8 });
    }

    #[test]
    fn a_curve_rising_again_past_its_crossing_keeps_the_crossing() {
        // d' = 8 / sqrt(spp) up to 64, then rising again below the target (noise at the
        // floor): still p = 0.75 at 14.46 spp, not "undefined".
        let mut pts: Vec<(u32, f64)> = [1u32, 8, 27, 64]
            .iter()
            .map(|&s| (s, 8.0 / (s as f64).sqrt()))
            .collect();
        pts.push((125, 1.2));
        assert!(two_pair_p_correct(1.2) < TARGET);
        match threshold(&pts) {
            Threshold::Value { spp } => assert!((spp - 14.463).abs() < 0.01, "{spp}"),
            t => panic!("{t:?}"),
        }
    }
}
