//! The thesis's study as a known truth: its design (2 scenes x 3 point sets x 8 levels x 4
//! repeats, 12 subjects) and simulated observers with thresholds 40 spp (plane) and 100 spp
//! (spheres), equal across point sets, logistic slope 1.5 / ln spp, subjects' thresholds
//! scaled by exp(0.6 (u - 1/2)), u uniform per subject (the `experiment` observer model).
//!
//! What the analysis should recover from such a study, computed from the model alone: the
//! 0.75 crossing of a pooled curve (a mixture of subjects' curves) and the distribution of a
//! subject's difference in correct answers between two groups of cells.

use analysis::data::Grouping;
use experiment::trials::Condition;
use experiment::{Design, Observer};
use std::path::Path;

pub const SUBJECTS: usize = 12;
pub const LEVELS: [u32; 8] = [1, 8, 27, 64, 125, 216, 343, 512];
pub const REPEATS: u32 = 4;
/// Scene and its threshold (spp where p = 0.75).
pub const SCENES: [(&str, f64); 2] = [("plane", 40.0), ("spheres", 100.0)];
pub const POINT_SETS: [&str; 3] = ["hammersley", "stratified", "poisson"];
pub const TIME_FILTER: &str = "truncated_box";
pub const SLOPE: f64 = 1.5;
/// Width of the uniform spread of subjects' ln thresholds.
pub const SPREAD: f64 = 0.6;

/// The observer file's content with answer seed `seed` (which also draws the subjects).
pub fn observer(seed: u64) -> Observer {
    let thresholds: Vec<_> = SCENES
        .iter()
        .map(|(scene, spp)| serde_json::json!({"scene": scene, "spp": spp}))
        .collect();
    let text = serde_json::json!({
        "format": "blurlab-observer/1", "name": "recovery", "slope": SLOPE, "lapse": 0.0,
        "subject_spread": SPREAD, "seed": seed, "thresholds": thresholds,
    });
    Observer::parse(Path::new("recovery-observer.json"), &text.to_string())
        .expect("the recovery observer is valid")
}

/// Write the thesis design (trial-order seed `seed`) into `dir` and load it. Its manifest is
/// never rendered: simulated subjects answer from the design alone.
pub fn write_design(dir: &Path, seed: u64) -> Design {
    let text = serde_json::json!({
        "format": "blurlab-design/1",
        "name": "recovery",
        "manifest": "stimuli/not-rendered/manifest.json",
        "factors": {"scenes": SCENES.map(|s| s.0), "point_sets": POINT_SETS,
                    "time_filters": [TIME_FILTER]},
        "levels": LEVELS,
        "repeats": REPEATS,
        "practice": {"trials": 4, "levels": [1, 8], "feedback": true},
        "seed": {"master": seed, "scheme": "per_subject"},
    });
    let path = dir.join("design.json");
    std::fs::write(&path, text.to_string()).expect("writing the design");
    Design::load(&path).expect("the recovery design is valid")
}

pub fn condition(scene: &str, point_set: &str) -> Condition {
    Condition::new(
        scene,
        point_set.parse().unwrap(),
        TIME_FILTER.parse().unwrap(),
    )
}

/// The design cells an analysis group pools (`scene/point_set/time_filter` for conditions).
pub fn cells_of(grouping: Grouping, label: &str) -> Vec<Condition> {
    let mut cells = Vec::new();
    for (scene, _) in SCENES {
        for ps in POINT_SETS {
            let member = match grouping {
                Grouping::Condition => label == format!("{scene}/{ps}/{TIME_FILTER}"),
                Grouping::Scene => label == scene,
                Grouping::PointSet => label == ps,
                Grouping::TimeFilter => label == TIME_FILTER,
            };
            if member {
                cells.push(condition(scene, ps));
            }
        }
    }
    cells
}

/// A subject's threshold factor exp(SPREAD (u - 1/2)).
pub fn subject_factor(u: f64) -> f64 {
    (SPREAD * (u - 0.5)).exp()
}

/// `n` midpoint nodes of u in (0, 1): the population of subjects, for integrals over u.
pub fn population(n: usize) -> impl Iterator<Item = f64> {
    (0..n).map(move |i| (i as f64 + 0.5) / n as f64)
}

/// The ln spp where the mean of the curves with these thresholds crosses 0.75. A pooled
/// curve with equal trials per subject and cell is this mean (a mixture of logistics): its
/// crossing is not the mean threshold, nor the crossing of any one curve. The mean is
/// strictly decreasing in x, so bisection finds the one crossing to rounding.
pub fn mixture_crossing(obs: &Observer, thresholds: &[f64]) -> f64 {
    let mean_p = |x: f64| {
        thresholds
            .iter()
            .map(|&t| obs.p_correct(t, x.exp()))
            .sum::<f64>()
            / thresholds.len() as f64
    };
    let (mut lo, mut hi) = (-20.0f64, 30.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mean_p(mid) > 0.75 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Binomial probabilities of 0..=n successes.
pub fn binomial_pmf(n: u32, p: f64) -> Vec<f64> {
    (0..=n)
        .map(|k| {
            let ln_choose: f64 = (0..k)
                .map(|i| ((n - i) as f64).ln() - ((i + 1) as f64).ln())
                .sum();
            (ln_choose + k as f64 * p.ln() + (n - k) as f64 * (1.0 - p).ln()).exp()
        })
        .collect()
}

/// The distribution of a sum of independent counts.
pub fn convolve(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// A subject's correct answers in cells with these thresholds (`REPEATS` trials each) at
/// `spp`, for threshold factor `m`: a sum of binomials.
fn correct_pmf(obs: &Observer, cells: &[f64], m: f64, spp: f64) -> Vec<f64> {
    cells.iter().fold(vec![1.0], |acc, &t| {
        convolve(&acc, &binomial_pmf(REPEATS, obs.p_correct(t * m, spp)))
    })
}

/// The distribution of one subject's correct answers in cells `a` minus those in cells `b`
/// (equal numbers of cells) at `spp`, over the population of subjects: entry `i` is the
/// probability of the difference `i - (len - 1) / 2`. Given the subject, the two counts are
/// independent (different trials); subjects are independent draws of u.
pub fn difference_pmf(obs: &Observer, a: &[f64], b: &[f64], spp: f64) -> Vec<f64> {
    assert_eq!(a.len(), b.len());
    let nodes = 400;
    let mut out = vec![0.0; 2 * a.len() * REPEATS as usize + 1];
    for u in population(nodes) {
        let m = subject_factor(u);
        let ka = correct_pmf(obs, a, m, spp);
        let kb_reversed: Vec<f64> = correct_pmf(obs, b, m, spp).into_iter().rev().collect();
        for (i, p) in convolve(&ka, &kb_reversed).into_iter().enumerate() {
            out[i] += p / nodes as f64;
        }
    }
    out
}
