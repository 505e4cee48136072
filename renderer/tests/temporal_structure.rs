//! Point sets differ only in the point set: in the thesis's jobs (`scenes/thesis/job.json` and
//! a `.job` as Figure 12 prints it) every point set gets new points and new pixel shifts every
//! frame, so the noise of consecutive frames is equally (in)dependent whatever the set.
//!
//! The measure: a static image (per pixel, a straight edge at a hashed angle and offset) is
//! estimated in frames 0 and 1 with each set under the job's sampling; the residuals
//! r_f(p) = estimate_f(p) - exact(p) are unbiased (each shifted point is uniform in the pixel),
//! and exact(p), the edge under the Gaussian pixel filter, is Φ(-d_p / σ). Given the two
//! frames' point sets, the pixels' terms r_0(p) r_1(p) are independent (independent shifts),
//! with mean zero if the frames are independent; so the self-normalised sum
//!
//!   T = Σ r_0 r_1 / sqrt(Σ r_0² r_1²)
//!
//! is standard normal under independence (the correlation coefficient's sampling distribution
//! with each pixel's own variance; Fisher's 1/sqrt(n - 3) would assume equal variances).
//! Frozen noise (the same samples in both frames) gives a correlation of 1.

use renderer::condition::TimeFilter;
use renderer::job::{JobFile, line_format, stimulus_sampling};
use renderer::sampling::{FrameSampler, SamplingConfig, SamplingOptions, Scope, pointset};
use statrs::distribution::{ContinuousCDF, Normal};
use std::path::Path;

const SIZE: u32 = 64;
const SPP: u32 = 8;

/// Residuals of frames 0 and 1 of a stimulus with `cfg`.
fn residuals(cfg: &SamplingConfig, seed: u64) -> [Vec<f64>; 2] {
    assert_eq!(
        cfg.spatial_filter(),
        renderer::sampling::SpatialFilter::Gaussian
    );
    let sigma = cfg.spatial_sigma();
    let normal = Normal::new(0.0, 1.0).unwrap();
    let frame = |f: u32| {
        let sampler = FrameSampler::new(cfg, seed, f).unwrap();
        let mut out = Vec::new();
        for y in 0..SIZE {
            for x in 0..SIZE {
                let h = renderer::hash::hash(77, &[x as u64, y as u64]);
                let angle = renderer::hash::unit_f64(h) * std::f64::consts::TAU;
                let d = renderer::hash::unit_f64(h.rotate_left(32)) - 0.5;
                let (c, s) = (angle.cos(), angle.sin());
                let px = sampler.pixel(x, y);
                let hits = (0..sampler.spp())
                    .filter(|&i| {
                        let p = px.sample(i);
                        c * p.dx as f64 + s * p.dy as f64 > d
                    })
                    .count();
                let exact = normal.cdf(-d / sigma);
                out.push(hits as f64 / sampler.spp() as f64 - exact);
            }
        }
        out
    };
    [frame(0), frame(1)]
}

/// (correlation, T) of two frames' residuals.
fn dependence(r: &[Vec<f64>; 2]) -> (f64, f64) {
    let (a, b) = (&r[0], &r[1]);
    let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let aa: f64 = a.iter().map(|x| x * x).sum();
    let bb: f64 = b.iter().map(|y| y * y).sum();
    let sandwich: f64 = a.iter().zip(b).map(|(x, y)| (x * y).powi(2)).sum();
    (dot / (aa * bb).sqrt(), dot / sandwich.sqrt())
}

/// Two-sided standard normal quantile for family-wise level 0.001 over `m` tests.
fn critical(m: usize) -> f64 {
    Normal::new(0.0, 1.0)
        .unwrap()
        .inverse_cdf(1.0 - 0.001 / (2.0 * m as f64))
}

/// Every point set under `options`: (name, correlation, T).
fn measure(options: &SamplingOptions) -> Vec<(&'static str, f64, f64)> {
    pointset::ALL
        .iter()
        .map(|set| {
            let kind = set.name().parse().unwrap();
            let cfg = stimulus_sampling(kind, SPP, TimeFilter::TruncatedBox, options)
                .over(&SamplingConfig::default());
            let (r, t) = dependence(&residuals(&cfg, 2013));
            (set.name(), r, t)
        })
        .collect()
}

fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

/// The sampling options a job lays over every scene, with both scopes set by the job itself
/// (so no scene's own settings can change them).
fn job_options(job: &JobFile) -> &SamplingOptions {
    let o = &job.overrides.sampling;
    assert!(
        o.point_set_scope.is_some() && o.shift_scope.is_some(),
        "the job must say its scopes: {o:?}"
    );
    o
}

#[test]
fn in_the_thesis_jobs_every_set_has_independent_noise_from_frame_to_frame() {
    let json: JobFile =
        serde_json::from_str(&std::fs::read_to_string(repo("scenes/thesis/job.json")).unwrap())
            .unwrap();
    let figure12 = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/thesis/figure12.job");
    let (text, _) =
        line_format::read(&std::fs::read_to_string(&figure12).unwrap(), &figure12).unwrap();
    for job in [&json, &text] {
        let o = job_options(job);
        assert_eq!(
            (o.point_set_scope, o.shift_scope),
            (Some(Scope::Frame), Some(Scope::Frame))
        );
        let found = measure(o);
        let z = critical(found.len());
        for &(set, r, t) in &found {
            assert!(
                t.abs() < z,
                "{set}: r = {r:.4}, T = {t:.2}, |T| must be < {z:.2}"
            );
        }
        // Equally independent: no two sets differ by more than the difference of two
        // independent standard normals allows.
        for a in &found {
            for b in &found {
                assert!((a.2 - b.2).abs() < z * 2f64.sqrt(), "{a:?} vs {b:?}");
            }
        }
    }
}

/// The test has the power to see frozen noise, and shows why the job must set the scopes. With
/// the scene defaults (sets per frame, shifts per sequence) Hammersley — the same set every
/// frame — repeats its samples exactly (r = 1), while for the sets made anew each frame the
/// shared shift correlates consecutive frames by an amount that depends on how the two frames'
/// sets happen to overlap (measured r from -0.36 to +0.37 over seeds 1, 2, 3 and 2013 at 8
/// spp): neither independent nor frozen, and different for every set. With both scopes per
/// sequence every set repeats its samples.
#[test]
fn frozen_noise_is_detected_and_the_scene_defaults_treat_sets_differently() {
    let defaults = measure(&SamplingOptions::default());
    for &(set, r, t) in &defaults {
        if set == "hammersley" {
            assert!(r > 0.999, "{set}: r = {r}");
        } else {
            assert!(r < 0.9, "{set}: r = {r:.4}, T = {t:.2}");
        }
    }
    let dependent = defaults
        .iter()
        .filter(|d| d.2.abs() > critical(defaults.len()))
        .count();
    assert!(
        dependent >= 3,
        "shared shifts correlate the frames: {defaults:?}"
    );
    let frozen = SamplingOptions {
        point_set_scope: Some(Scope::Sequence),
        shift_scope: Some(Scope::Sequence),
        ..Default::default()
    };
    for (set, r, _) in measure(&frozen) {
        assert!(r > 0.999, "{set}: r = {r}");
    }
}
