//! A video's prediction from predictions of single frames spread over it.
//!
//! Rendering every frame of the thesis's 210-frame video at 768 x 768 and eight levels is
//! beyond the shared machine, so the sets of `scenes/replication/sweep.txt` render one frame and
//! `blurlab predict` predicts each such set alone. This file combines those predictions, as
//! [`video_q`] pools a video's frames: per condition and level,
//! d'_video = (mean_f d'_f^beta)^(1/beta) over the frames f, with the model's time exponent beta
//! ([`FITTED`]'s space exponent). The frames are a sample of the video, so this
//! mean estimates the pooled mean over all of its frames; the most visible frame (the limit
//! beta -> infinity: an observer who waits for the worst moment) is reported beside it, and each
//! frame's own JND. d' = k Q, so with one k in every file pooling d' is pooling Q.
//!
//! [`FITTED`]: crate::observer::model::pooling::FITTED

use super::stimuli::threshold;
use crate::jnd::Threshold;
use crate::observer::model::pooling::video_q;
use anyhow::{Result, bail};
use experiment::predicted::PredictedTable;
use experiment::trials::Condition;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One frame's prediction, named for the report.
pub struct Frame {
    pub label: String,
    /// The file read, for messages.
    pub file: PathBuf,
    pub table: PredictedTable,
}

impl Frame {
    /// A `predicted.csv` (or the folder holding one), labelled by its job's folder name.
    pub fn load(path: &Path) -> Result<Self> {
        let file = if path.is_dir() {
            path.join("predicted.csv")
        } else {
            path.to_path_buf()
        };
        let table = PredictedTable::load(&file)?;
        Ok(Self {
            label: label(&file),
            file,
            table,
        })
    }
}

/// `results/thesis_full_f093/predict/predicted.csv` -> `thesis_full_f093/predict`.
fn label(file: &Path) -> String {
    let parts: Vec<String> = file
        .parent()
        .map(|p| p.components().rev().take(2).collect::<Vec<_>>())
        .unwrap_or_default()
        .into_iter()
        .rev()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.is_empty() {
        file.display().to_string()
    } else {
        parts.join("/")
    }
}

/// One condition over the frames.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoJnd {
    pub condition: Condition,
    /// Each frame's JND, in the order of the frames given (None: the frame lacks the condition).
    pub per_frame: Vec<Option<Threshold>>,
    /// The JND of the pooled d' over the frames that have the condition.
    pub pooled: Threshold,
    /// The JND of the most visible frame at each level.
    pub most_visible: Threshold,
    /// Frames that have the condition.
    pub frames: usize,
}

/// Combine single-frame predictions with time exponent `beta` (>= 1; infinity is the
/// maximum over the frames, the Minkowski mean's limit).
pub fn combine(frames: &[Frame], beta: f64) -> Result<Vec<VideoJnd>> {
    if frames.is_empty() {
        bail!("no frame predictions to combine");
    }
    if beta.is_nan() || beta < 1.0 {
        bail!("--exponent is {beta}; expected a number >= 1 (inf: the most visible frame)");
    }
    check_one_k(frames)?;
    let mut conditions: Vec<Condition> = frames
        .iter()
        .flat_map(|f| f.table.conditions().map(|(c, _)| c.clone()))
        .collect();
    conditions.sort();
    conditions.dedup();
    conditions
        .into_iter()
        .map(|c| video_jnd(frames, c, beta))
        .collect()
}

/// The Minkowski mean of the frames' d' with exponent `beta`; its limit, the maximum, for an
/// infinite `beta` (where `video_q`'s powers would overflow to inf / inf).
fn pool(ds: &[f64], beta: f64) -> f64 {
    if beta.is_infinite() {
        ds.iter().cloned().fold(0.0, f64::max)
    } else {
        video_q(ds, beta)
    }
}

/// Pooling d' across files computed with different k would pool different units.
fn check_one_k(frames: &[Frame]) -> Result<()> {
    let k0 = frames[0].table.rows[0].k;
    for f in frames {
        if let Some(r) = f.table.rows.iter().find(|r| r.k != k0) {
            bail!(
                "{}: stimulus {} has k = {}, {} has k = {k0}; predict every frame with one \
                 --sensitivity",
                f.label,
                r.test_stimulus,
                r.k,
                frames[0].label
            );
        }
    }
    Ok(())
}

fn video_jnd(frames: &[Frame], c: Condition, beta: f64) -> Result<VideoJnd> {
    let curves: Vec<Option<Vec<(u32, f64)>>> = frames
        .iter()
        .map(|f| {
            f.table
                .curve(&c)
                .map(|cv| cv.points.iter().map(|&(s, d)| (s as u32, d)).collect())
        })
        .collect();
    check_same_levels(frames, &curves, &c)?;
    let present: Vec<&Vec<(u32, f64)>> = curves.iter().flatten().collect();
    // Every frame that has the condition has every level (checked above): its d' per level.
    let mut by_level: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
    for curve in &present {
        for &(s, d) in curve.iter() {
            by_level.entry(s).or_default().push(d);
        }
    }
    let pooled: Vec<(u32, f64)> = by_level
        .iter()
        .map(|(&s, ds)| (s, pool(ds, beta)))
        .collect();
    let most: Vec<(u32, f64)> = by_level
        .iter()
        .map(|(&s, ds)| (s, ds.iter().cloned().fold(0.0, f64::max)))
        .collect();
    Ok(VideoJnd {
        per_frame: curves
            .iter()
            .map(|cv| cv.as_deref().map(threshold))
            .collect(),
        pooled: threshold(&pooled),
        most_visible: threshold(&most),
        frames: present.len(),
        condition: c,
    })
}

/// A level one frame predicts and another (with the same condition) lacks would be pooled over
/// fewer frames than the rest, or, dropped, would cut the curve where its JND may lie: refuse
/// it, naming the frame and the row it lacks.
fn check_same_levels(
    frames: &[Frame],
    curves: &[Option<Vec<(u32, f64)>>],
    c: &Condition,
) -> Result<()> {
    let levels = |cv: &Vec<(u32, f64)>| cv.iter().map(|&(s, _)| s).collect::<Vec<u32>>();
    let with: Vec<(&Frame, Vec<u32>)> = frames
        .iter()
        .zip(curves)
        .filter_map(|(f, cv)| cv.as_ref().map(|cv| (f, levels(cv))))
        .collect();
    for (f, own) in &with {
        for (g, other) in &with {
            if let Some(missing) = other.iter().find(|s| !own.contains(s)) {
                bail!(
                    "{}: condition {c} has no row at {missing} spp, which {} has; every frame \
                     must predict the same levels (predict that frame's stimulus set again)",
                    f.file.display(),
                    g.file.display()
                );
            }
        }
    }
    Ok(())
}

/// The table: one row per condition, a column per frame, then the pooled and the most
/// visible frame's JND (spp).
pub fn markdown(frames: &[Frame], jnds: &[VideoJnd], beta: f64) -> String {
    let mut s = format!(
        "JND (spp) per frame and over the {} frames (d' pooled with exponent {beta}; k = {})\n\n",
        frames.len(),
        frames[0].table.rows[0].k
    );
    let head: Vec<&str> = frames.iter().map(|f| f.label.as_str()).collect();
    s += &format!(
        "| condition | {} | pooled | most visible frame |\n",
        head.join(" | ")
    );
    s += &format!("|---|{}---|---|\n", "---|".repeat(frames.len()));
    for j in jnds {
        let cells: Vec<String> = j
            .per_frame
            .iter()
            .map(|t| t.as_ref().map_or("-".into(), Threshold::display))
            .collect();
        s += &format!(
            "| {} | {} | {} | {} |\n",
            j.condition,
            cells.join(" | "),
            j.pooled.display(),
            j.most_visible.display()
        );
    }
    s
}

/// The paths as given, for the command line.
pub fn load_all(paths: &[PathBuf]) -> Result<Vec<Frame>> {
    paths.iter().map(|p| Frame::load(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use experiment::predicted::PredictedRow;
    use renderer::condition::{PointSetKind, TimeFilter};

    /// A frame whose condition has d' = a / sqrt(spp) at levels 1-64 (k = 2).
    fn frame(label: &str, a: f64, point_set: PointSetKind) -> Frame {
        let rows = [1u32, 8, 27, 64]
            .iter()
            .map(|&spp| {
                let d = a / (spp as f64).sqrt();
                PredictedRow {
                    scene: "plane".into(),
                    point_set,
                    time_filter: TimeFilter::Box,
                    spp,
                    test_stimulus: format!("t{spp}"),
                    reference_stimulus: "r".into(),
                    q: d / 2.0,
                    k: 2.0,
                    d_prime: d,
                    p_correct: experiment::predicted::two_pair_p_correct(d),
                    p_frame_min: 0.5,
                    p_frame_median: 0.5,
                    p_frame_max: 0.5,
                    frames: 1,
                }
            })
            .collect();
        Frame {
            label: label.into(),
            file: PathBuf::from(format!("{label}.csv")),
            table: PredictedTable::from_rows(rows),
        }
    }

    fn spp(t: &Threshold) -> f64 {
        t.spp().unwrap_or(f64::NAN)
    }

    #[test]
    fn identical_frames_pool_to_the_frame() {
        let f = [
            frame("a", 8.0, PointSetKind::Random),
            frame("b", 8.0, PointSetKind::Random),
        ];
        let j = &combine(&f, 2.8).unwrap()[0];
        // d' = 8 / sqrt(spp) crosses d' = 2.1036 at spp = 14.46 (stimuli.rs's test).
        assert!((spp(&j.pooled) - 14.463).abs() < 0.01, "{j:?}");
        assert_eq!(j.pooled, j.most_visible);
        assert_eq!(j.frames, 2);
    }

    #[test]
    fn a_clean_frame_lowers_the_pooled_d_by_the_minkowski_mean() {
        // Frames with d' = 8 / sqrt(spp) and 0: pooled d' = 8 / sqrt(spp) 2^(-1/beta), so
        // the JND is (8 2^(-1/beta) / 2.1036)^2; the most visible frame keeps 14.46.
        let f = [
            frame("a", 8.0, PointSetKind::Random),
            frame("b", 0.0, PointSetKind::Random),
        ];
        for beta in [1.0, 2.8, 6.0] {
            let j = &combine(&f, beta).unwrap()[0];
            let d = (8.0 * 2f64.powf(-1.0 / beta) / 2.103_6_f64).powi(2);
            assert!((spp(&j.pooled) - d).abs() < 0.02 * d, "beta {beta}: {j:?}");
            assert!((spp(&j.most_visible) - 14.463).abs() < 0.01);
            assert_eq!(j.per_frame[1], Some(Threshold::BelowRange { bound: 1 }));
        }
    }

    #[test]
    fn a_condition_missing_from_a_frame_pools_over_the_others() {
        let f = [
            frame("a", 8.0, PointSetKind::Random),
            frame("b", 8.0, PointSetKind::Stratified),
        ];
        let j = combine(&f, 2.8).unwrap();
        assert_eq!(j.len(), 2);
        assert_eq!(j[0].frames, 1);
        assert!(j[0].per_frame[1].is_none() || j[1].per_frame[0].is_none());
        let md = markdown(&f, &j, 2.8);
        assert!(md.contains("| - |"), "{md}");
    }

    #[test]
    fn different_k_or_a_bad_exponent_is_refused() {
        let mut b = frame("b", 8.0, PointSetKind::Random);
        b.table.rows[0].k = 1.0;
        let err = combine(&[frame("a", 8.0, PointSetKind::Random), b], 2.8).unwrap_err();
        assert!(err.to_string().contains("--sensitivity"), "{err}");
        assert!(combine(&[frame("a", 8.0, PointSetKind::Random)], 0.5).is_err());
        assert!(combine(&[], 2.8).is_err());
    }

    #[test]
    fn a_level_missing_from_one_frame_is_refused_and_named() {
        let mut b = frame("b", 8.0, PointSetKind::Random);
        b.table = PredictedTable::from_rows(
            b.table
                .rows
                .iter()
                .filter(|r| r.spp != 27)
                .cloned()
                .collect(),
        );
        let err = combine(&[frame("a", 8.0, PointSetKind::Random), b], 2.8).unwrap_err();
        let msg = err.to_string();
        assert!(msg.starts_with("b.csv: "), "{msg}");
        assert!(msg.contains("no row at 27 spp, which a.csv has"), "{msg}");
    }

    #[test]
    fn an_infinite_exponent_pools_to_the_most_visible_frame() {
        let f = [
            frame("a", 8.0, PointSetKind::Random),
            frame("b", 2.0, PointSetKind::Random),
        ];
        let j = &combine(&f, f64::INFINITY).unwrap()[0];
        assert_eq!(j.pooled, j.most_visible);
        assert!((spp(&j.pooled) - 14.463).abs() < 0.01, "{j:?}");
        // And a large finite exponent approaches it from below.
        let big = &combine(&f, 64.0).unwrap()[0];
        assert!(spp(&big.pooled) < spp(&j.pooled) && spp(&big.pooled) > 0.9 * spp(&j.pooled));
    }

    #[test]
    fn labels_are_the_last_two_folders() {
        assert_eq!(
            label(Path::new("results/thesis_full_f093/predict/predicted.csv")),
            "thesis_full_f093/predict"
        );
    }
}
