//! The renderer's view of sampling: [`FrameSampler`] is built once per frame and answers
//! "sample i of pixel (x, y)" with a sub-pixel offset and a shutter time, after the pixel's
//! shift (or scramble) and both warps (thesis Figure 14, then Figure 16).

use super::config::{Density, Randomization, SamplingConfig, Scope};
use super::pointset::PointSet;
use super::time_filter::TimeFilter;
use super::warp::SpatialWarp;
use super::{density, pointset, shift};
use crate::hash;
use anyhow::{Result, bail};

/// Hash tags separating the random streams of a stimulus.
const POINTS_TAG: u64 = 0x5e7;
const SHIFT_TAG: u64 = 0x5817;
const SCRAMBLE_TAG: u64 = 0x5c2a;

/// The largest f32 below 1, where f64 coordinates that round up to 1 go.
const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// One sample of a pixel after shift and warps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSample {
    /// Offset from the pixel's centre, in pixels (x to the right, y down); may exceed 0.5 under a
    /// wide spatial filter.
    pub dx: f32,
    pub dy: f32,
    /// Fraction of the frame's shutter interval, in [0, 1].
    pub t: f32,
}

/// Everything needed to produce every pixel's samples for one frame.
#[derive(Clone, Debug)]
pub struct FrameSampler {
    points: Vec<[f32; 3]>,
    shift_key: u64,
    /// Set under `randomization: scramble` for sets that have a per-pixel scramble.
    scramble: Option<Scrambled>,
    spatial: SpatialWarp,
    time: TimeFilter,
}

/// A frame whose pixels each scramble the set on their own (`crate::sampling::scramble`).
#[derive(Clone)]
struct Scrambled {
    set: &'static dyn PointSet,
    /// Points of the joint set, or of the (u, v) set of a density split (0 for joint).
    joint: usize,
    /// (spatial, temporal) counts of a density split.
    product: Option<(usize, usize)>,
    /// The frame's points key: with the shift key it seeds each pixel's scramble, so the
    /// pixel's points change when either scope says so.
    points_key: u64,
}

impl std::fmt::Debug for Scrambled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scrambled")
            .field("set", &self.set.name())
            .field("joint", &self.joint)
            .field("product", &self.product)
            .finish()
    }
}

/// One pixel's view of a [`FrameSampler`]: the shift (or the scramble's keys) is computed once
/// for all its samples.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler<'a> {
    frame: &'a FrameSampler,
    shift: [f32; 3],
    /// The pixel's scramble keys: the joint set's (or the spatial set's) and the temporal set's.
    keys: [u64; 2],
}

/// The key of a random stream that lasts a whole stimulus or one frame.
fn scoped(seed: u64, tag: u64, scope: Scope, frame: u32) -> u64 {
    match scope {
        Scope::Sequence => hash::hash(seed, &[tag]),
        Scope::Frame => hash::hash(seed, &[tag, frame as u64]),
    }
}

impl FrameSampler {
    /// The sampler for `frame` of a stimulus with master `seed`. Errors name the setting and
    /// what it must be (stratified counts that are not cubes, ...); point set and time filter
    /// are typed, checked when the scene or job was read.
    pub fn new(config: &SamplingConfig, seed: u64, frame: u32) -> Result<Self> {
        if config.spp == 0 {
            bail!("field `spp` must be at least 1");
        }
        let sigma = config.spatial_sigma();
        if !(sigma.is_finite() && sigma > 0.0) {
            bail!("field `spatial_sigma` is {sigma}; expected a positive number of pixels");
        }
        let time = config.time_filter;
        let set = pointset::of(config.point_set);
        let key = scoped(seed, POINTS_TAG, config.point_set_scope(), frame);
        let spp = config.spp as usize;
        let points = density::points(set, spp, config.density(), key)?
            .into_iter()
            .map(|p| p.map(|c| (c as f32).min(BELOW_ONE)))
            .collect();
        let scramble =
            (config.randomization() == Randomization::Scramble && set.scrambles()).then(|| {
                Scrambled {
                    set,
                    joint: spp,
                    // density::points checked the split above.
                    product: match config.density() {
                        Density::Joint => None,
                        Density::Temporal(k) => Some((spp / k as usize, k as usize)),
                        Density::Spatial(k) => Some((k as usize, spp / k as usize)),
                    },
                    points_key: key,
                }
            });
        Ok(Self {
            points,
            scramble,
            shift_key: scoped(seed, SHIFT_TAG, config.shift_scope(), frame),
            spatial: SpatialWarp::new(config.spatial_filter(), sigma),
            time,
        })
    }

    /// Samples per pixel.
    pub fn spp(&self) -> usize {
        self.points.len()
    }

    /// The frame's (u, v, t) points before shift and warps.
    pub fn points(&self) -> &[[f32; 3]] {
        &self.points
    }

    /// The frame's points when every pixel shifts them (not scrambled), so that sample `i` of
    /// a pixel is point `i` wrapped by the pixel's shift and then warped by
    /// [`FrameSampler::spatial`] and [`FrameSampler::time_filter`] (what
    /// `render/sample_lanes.rs` computes in lanes); `None` when the pixels scramble the set.
    pub fn shifted_points(&self) -> Option<&[[f32; 3]]> {
        self.scramble.is_none().then_some(&self.points[..])
    }

    /// The frame's spatial warp.
    pub fn spatial(&self) -> SpatialWarp {
        self.spatial
    }

    /// The frame's time filter.
    pub fn time_filter(&self) -> TimeFilter {
        self.time
    }

    /// Whether the pixels scramble the set (`randomization: scramble` on a set that has a
    /// scramble) rather than shift it.
    pub fn scrambles(&self) -> bool {
        self.scramble.is_some()
    }

    /// Pixel (x, y): hash its shift (or scramble keys) once, then ask it for each sample
    /// (cheaper than [`FrameSampler::sample`] per sample).
    #[inline(always)]
    pub fn pixel(&self, x: u32, y: u32) -> PixelSampler<'_> {
        match &self.scramble {
            None => PixelSampler {
                frame: self,
                shift: shift::pixel_shift(self.shift_key, x, y),
                keys: [0; 2],
            },
            Some(s) => {
                let pixel = ((x as u64) << 32) | y as u64;
                let key = hash::hash(self.shift_key, &[SCRAMBLE_TAG, pixel, s.points_key]);
                // The split's two sets get independent keys, as `density::points` gives them.
                let keys = match s.product {
                    None => [key, 0],
                    Some(_) => [hash::hash(key, &[2]), hash::hash(key, &[1])],
                };
                PixelSampler {
                    frame: self,
                    shift: [0.0; 3],
                    keys,
                }
            }
        }
    }

    /// Sample `i` (< spp) of pixel `(x, y)`.
    #[inline]
    pub fn sample(&self, x: u32, y: u32, i: usize) -> PixelSample {
        self.pixel(x, y).sample(i)
    }
}

impl PixelSampler<'_> {
    /// The pixel's shift in (u, v, t), each in [0, 1) (zero when the pixel scrambles).
    pub fn shift(&self) -> [f32; 3] {
        self.shift
    }

    /// Point `i` (< spp) of the pixel in the unit cube, before the warps: the frame's point
    /// shifted with wrap-around, or the pixel's own scrambled point.
    #[inline]
    pub fn point(&self, i: usize) -> [f32; 3] {
        let Some(s) = &self.frame.scramble else {
            let p = self.frame.points[i];
            return [0, 1, 2].map(|d| shift::wrap(p[d], self.shift[d]));
        };
        let p = match s.product {
            None => s.set.scrambled(s.joint, 3, i, self.keys[0]),
            Some((spatial, temporal)) => {
                let a = s.set.scrambled(spatial, 2, i / temporal, self.keys[0]);
                let b = s.set.scrambled(temporal, 1, i % temporal, self.keys[1]);
                [a[0], a[1], b[0]]
            }
        };
        p.map(|c| (c as f32).min(BELOW_ONE))
    }

    /// Sample `i` (< spp): point i, shifted with wrap-around (or scrambled), then warped.
    #[inline(always)]
    pub fn sample(&self, i: usize) -> PixelSample {
        let [u, v, t] = self.point(i);
        let (dx, dy) = self.frame.spatial.offset(u, v);
        PixelSample {
            dx,
            dy,
            t: self.frame.time.warp(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::config::SpatialFilter;
    use crate::sampling::ks::{ks_critical, ks_statistic};
    use crate::sampling::pointset::ALL;
    use rayon::prelude::*;

    fn config(point_set: &str, spp: u32, time_filter: &str) -> SamplingConfig {
        SamplingConfig {
            point_set: point_set.parse().unwrap(),
            spp,
            time_filter: time_filter.parse().unwrap(),
            ..Default::default()
        }
    }

    fn all_samples(s: &FrameSampler, w: u32, h: u32) -> Vec<PixelSample> {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .flat_map(|(x, y)| (0..s.spp()).map(move |i| s.sample(x, y, i)))
            .collect()
    }

    /// Every sample of a `side` x `side` frame (seed 12, frame 3), rows drawn in parallel on
    /// a pool of `threads`: the same as [`all_samples`] whatever the thread count.
    fn parallel_samples(cfg: &SamplingConfig, side: u32, threads: usize) -> Vec<PixelSample> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let s = FrameSampler::new(cfg, 12, 3).unwrap();
            let spp = s.spp();
            (0..side)
                .into_par_iter()
                .flat_map_iter(|y| {
                    let s = &s;
                    (0..side).flat_map(move |x| (0..spp).map(move |i| s.sample(x, y, i)))
                })
                .collect()
        })
    }

    #[test]
    fn samples_are_finite_and_in_range_for_every_set_and_filter() {
        for set in ALL {
            for tf in TimeFilter::ALL {
                let s = FrameSampler::new(&config(set.name(), 27, tf.name()), 3, 1).unwrap();
                for p in all_samples(&s, 16, 16) {
                    assert!(p.dx.is_finite() && p.dy.is_finite(), "{}", set.name());
                    assert!(p.dx.hypot(p.dy) < 0.5 * 5.8, "beyond the clamp: {p:?}");
                    assert!((0.0..=1.0).contains(&p.t), "{p:?}");
                }
            }
        }
    }

    #[test]
    fn box_filters_keep_samples_inside_the_pixel_and_the_window() {
        let cfg = SamplingConfig {
            spatial_filter: Some(SpatialFilter::Box),
            ..config("hammersley", 64, "truncated_box")
        };
        let s = FrameSampler::new(&cfg, 3, 0).unwrap();
        for p in all_samples(&s, 8, 8) {
            assert!(
                (-0.5..0.5).contains(&p.dx) && (-0.5..0.5).contains(&p.dy),
                "{p:?}"
            );
            assert!((0.25..=0.75).contains(&p.t), "{p:?}");
        }
    }

    #[test]
    fn a_pixel_sees_the_whole_set_shifted_by_its_own_offset() {
        // Stratified with box filters: undoing the pixel's shift (mod 1) gives the set back.
        let cfg = SamplingConfig {
            spatial_filter: Some(SpatialFilter::Box),
            ..config("stratified", 27, "box")
        };
        let s = FrameSampler::new(&cfg, 5, 2).unwrap();
        let px = s.pixel(7, 3);
        let sh = px.shift();
        for i in 0..27 {
            let q = px.sample(i);
            let shifted = [q.dx + 0.5, q.dy + 0.5, q.t];
            for (d, (a, b)) in shifted.iter().zip(sh).enumerate() {
                let diff = ((a - b).rem_euclid(1.0) - s.points()[i][d]).abs();
                assert!(diff.min(1.0 - diff) < 1e-6, "sample {i} axis {d}");
            }
        }
        assert_ne!(s.pixel(7, 3).shift(), s.pixel(8, 3).shift());
    }

    #[test]
    fn scopes_decide_what_changes_between_frames() {
        for (ps, sh) in [
            (Scope::Frame, Scope::Sequence),
            (Scope::Sequence, Scope::Frame),
        ] {
            let cfg = SamplingConfig {
                point_set_scope: Some(ps),
                shift_scope: Some(sh),
                ..config("poisson", 8, "box")
            };
            let a = FrameSampler::new(&cfg, 4, 0).unwrap();
            let b = FrameSampler::new(&cfg, 4, 1).unwrap();
            assert_eq!(a.points() == b.points(), ps == Scope::Sequence);
            assert_eq!(
                a.pixel(2, 2).shift() == b.pixel(2, 2).shift(),
                sh == Scope::Sequence
            );
        }
        // Another stimulus seed changes both.
        let cfg = config("random", 8, "box");
        let (a, b) = (
            FrameSampler::new(&cfg, 1, 0).unwrap(),
            FrameSampler::new(&cfg, 2, 0).unwrap(),
        );
        assert_ne!(a.points(), b.points());
        assert_ne!(a.pixel(0, 0).shift(), b.pixel(0, 0).shift());
    }

    #[test]
    fn samples_do_not_depend_on_the_thread_count() {
        let cfg = config("sobol", 16, "triangle");
        let one = parallel_samples(&cfg, 32, 1);
        assert_eq!(one, parallel_samples(&cfg, 32, 3));
        let serial = all_samples(&FrameSampler::new(&cfg, 12, 3).unwrap(), 32, 32);
        assert_eq!(one, serial);
    }

    #[test]
    fn a_moving_edge_blurs_into_each_time_filter_s_cdf() {
        // An edge sweeping L = 64 pixels to the right during the shutter lights a sample at
        // x + 1/2 + dx when t > (x + 1/2 + dx) / L, so pixel x converges to 1 - F((x + 1/2)/L)
        // up to the pixel's own width. Tolerance: the spatial box blurs F by at most
        // max pdf x (1/2)/L (= 1/64 for pdf <= 2); 1024 samples in each of 8 rows give a
        // standard error of at most sqrt(1/4/1024/8) = 0.0055 even for random points; 5 of
        // them plus the blur is 0.044.
        const L: f32 = 64.0;
        for tf in TimeFilter::ALL {
            let cfg = SamplingConfig {
                spatial_filter: Some(SpatialFilter::Box),
                ..config("hammersley", 1024, tf.name())
            };
            let s = FrameSampler::new(&cfg, 21, 0).unwrap();
            for x in 0..L as u32 {
                let lit: usize = (0..8)
                    .map(|y| {
                        let px = s.pixel(x, y);
                        (0..s.spp())
                            .filter(|&i| {
                                let p = px.sample(i);
                                x as f32 + 0.5 + p.dx < L * p.t
                            })
                            .count()
                    })
                    .sum();
                let value = lit as f64 / (8 * s.spp()) as f64;
                let expect = 1.0 - tf.cdf((x as f64 + 0.5) / L as f64);
                assert!(
                    (value - expect).abs() < 0.044,
                    "{} at x = {x}: {value} vs {expect}",
                    tf.name()
                );
            }
        }
    }

    /// A digest of every sample of a 9 x 7 patch under `cfg` (seed 2013, frame 5).
    fn digest(cfg: &SamplingConfig) -> u64 {
        let s = FrameSampler::new(cfg, 2013, 5).unwrap();
        all_samples(&s, 9, 7).iter().fold(0, |h, p| {
            hash::hash(
                h,
                &[
                    p.dx.to_bits() as u64,
                    p.dy.to_bits() as u64,
                    p.t.to_bits() as u64,
                ],
            )
        })
    }

    /// [`digest`] of the samples as libm's Box-Muller made them before the warp took
    /// [`crate::math`]'s `ln` and `sin_cos` (issue 30, sixth pass), and the largest distance
    /// of today's offsets from them, in pixels (the times must be the same bits).
    fn libm_digest(cfg: &SamplingConfig) -> (u64, f32) {
        let s = FrameSampler::new(cfg, 2013, 5).unwrap();
        let SpatialWarp::Gaussian { sigma } = s.spatial else {
            panic!("the default spatial filter is Gaussian")
        };
        let mut far = 0.0f32;
        let mut h = 0;
        for (x, y) in (0..7).flat_map(|y| (0..9).map(move |x| (x, y))) {
            let pixel = s.pixel(x, y);
            for i in 0..s.spp() {
                let [u, v, t] = pixel.point(i);
                let r = sigma * (-2.0 * (1.0 - u).max(1.0 / (1u32 << 24) as f32).ln()).sqrt();
                let (sin, cos) = (std::f32::consts::TAU * v).sin_cos();
                let (dx, dy, t) = (r * cos, r * sin, s.time.warp(t));
                let today = pixel.sample(i);
                assert_eq!(today.t.to_bits(), t.to_bits());
                far = far.max((today.dx - dx).abs()).max((today.dy - dy).abs());
                let bits = [dx, dy, t].map(|c| c.to_bits() as u64);
                h = hash::hash(h, &bits);
            }
        }
        (h, far)
    }

    #[test]
    fn the_default_randomization_gives_the_same_samples_as_before_it_existed() {
        // Digests recorded on main before `randomization` existed (commit 9becc42), of the
        // samples libm's Box-Muller made: unset and an explicit `shift` must give those
        // points, and today's offsets must lie within rounding of them (a radius of at most
        // 5.8 sigma times the functions' relative errors, a few 1e-7 pixel).
        let before: [(&str, u32, u64); 6] = [
            ("random", 16, 0x70f5_7ea7_7f18_352c),
            ("stratified", 27, 0x4909_c267_ed0b_bd6e),
            ("hammersley", 64, 0x190b_6037_474c_7597),
            ("poisson", 16, 0x3cc3_d523_e2ed_2da4),
            ("sobol", 16, 0x238b_77c4_12ca_a5dd),
            ("halton", 27, 0x52ae_fe86_7e6d_5dab),
        ];
        for (set, spp, expect) in before {
            let cfg = config(set, spp, "triangle");
            let (libm, far) = libm_digest(&cfg);
            assert_eq!(libm, expect, "{set}");
            assert!(far < 1e-6, "{set}: offsets {far} pixel from libm's");
            let shift = SamplingConfig {
                randomization: Some(Randomization::Shift),
                ..cfg.clone()
            };
            assert_eq!(
                libm_digest(&shift).0,
                expect,
                "{set} with an explicit shift"
            );
            assert_eq!(digest(&shift), digest(&cfg), "{set} with an explicit shift");
            let scramble = SamplingConfig {
                randomization: Some(Randomization::Scramble),
                ..cfg.clone()
            };
            // Poisson has no scramble and keeps the shift; every other set changes.
            assert_eq!(
                digest(&scramble) == digest(&cfg),
                set == "poisson",
                "{set} scrambled"
            );
        }
    }

    fn scrambled(point_set: &str, spp: u32) -> SamplingConfig {
        SamplingConfig {
            randomization: Some(Randomization::Scramble),
            ..config(point_set, spp, "box")
        }
    }

    /// How many of `pts` fall in each box of a grid of `cells[d]` equal intervals per axis.
    fn box_counts(pts: &[[f32; 3]], cells: [usize; 3]) -> Vec<usize> {
        let mut counts = vec![0; cells.iter().product()];
        for p in pts {
            let c = (0..3).fold(0, |acc, d| {
                acc * cells[d] + ((p[d] as f64 * cells[d] as f64) as usize).min(cells[d] - 1)
            });
            counts[c] += 1;
        }
        counts
    }

    #[test]
    fn scrambled_pixels_keep_their_strata() {
        // Every pixel's own set must hold exactly one point in every box of these grids (the
        // strata its unscrambled set fills), at several pixels: Sobol and Hammersley at
        // N = 2^m are (0, m, 2)-nets in (u, v) (every 2^a x 2^(m-a) grid); 72 Halton points
        // fill the 8 x 9 grid of (φ_2, φ_3) and 125 fill 125 intervals of φ_5; 27 Hammersley
        // points fill 27 intervals of φ_3; stratified fills its cells.
        let mut cases: Vec<(&str, u32, [usize; 3])> = Vec::new();
        for m in [6u32, 8] {
            for a in 0..=m {
                for set in ["sobol", "hammersley"] {
                    cases.push((set, 1 << m, [1 << a, 1 << (m - a), 1]));
                }
            }
        }
        cases.extend([
            ("halton", 72, [8, 9, 1]),
            ("halton", 125, [1, 1, 125]),
            ("hammersley", 27, [1, 1, 27]),
            ("stratified", 27, [3, 3, 3]),
            ("stratified", 512, [8, 8, 8]),
        ]);
        for (set, n, cells) in cases {
            let s = FrameSampler::new(&scrambled(set, n), 17, 4).unwrap();
            assert!(s.scrambles());
            for (x, y) in [(0, 0), (5, 9), (100, 3), (767, 767)] {
                let px = s.pixel(x, y);
                let pts: Vec<[f32; 3]> = (0..s.spp()).map(|i| px.point(i)).collect();
                let counts = box_counts(&pts, cells);
                let full = n as usize / counts.len();
                assert!(
                    counts.iter().all(|&c| c == full),
                    "{set} n={n} grid {cells:?} pixel ({x}, {y}): {counts:?}"
                );
            }
        }
        // Hammersley at N = 27 is no 2-adic net, but every 2-adic interval of u = i/N holds
        // floor or ceil of N times its length, before and after the scramble.
        let s = FrameSampler::new(&scrambled("hammersley", 27), 17, 4).unwrap();
        let pts: Vec<[f32; 3]> = (0..27).map(|i| s.pixel(3, 3).point(i)).collect();
        for k in 1..=4 {
            let expect = 27.0 / (1 << k) as f64;
            for c in box_counts(&pts, [1 << k, 1, 1]) {
                assert!(
                    c == expect.floor() as usize || c == expect.ceil() as usize,
                    "{c}"
                );
            }
        }
    }

    #[test]
    fn scrambled_points_are_uniform_and_differ_between_pixels() {
        // Point i of 4096 pixels, each coordinate against the uniform CDF: KS at α = 1e-4 per
        // test (critical D = 2.23 / 64 = 0.035; 45 tests, family-wise below 0.005). Point 0
        // of the unscrambled Hammersley set is the origin: only the scramble moves it.
        for set in ["random", "stratified", "hammersley", "sobol", "halton"] {
            let s = FrameSampler::new(&scrambled(set, 64), 23, 1).unwrap();
            for i in [0, 1, 63] {
                let pts: Vec<[f32; 3]> = (0..64)
                    .flat_map(|y| (0..64).map(move |x| (x, y)))
                    .map(|(x, y)| s.pixel(x, y).point(i))
                    .collect();
                for d in 0..3 {
                    let mut v: Vec<f64> = pts.iter().map(|p| p[d] as f64).collect();
                    let dn = ks_statistic(&mut v, |x| x);
                    assert!(
                        dn < ks_critical(4096, 1e-4),
                        "{set} point {i} axis {d}: D = {dn}"
                    );
                }
            }
            let set_of = |x, y| {
                let px = s.pixel(x, y);
                (0..64).map(|i| px.point(i)).collect::<Vec<_>>()
            };
            assert_ne!(set_of(7, 3), set_of(8, 3), "{set}");
            assert_ne!(set_of(7, 3), set_of(3, 7), "{set}");
        }
        // Poisson has no scramble: it keeps the shift.
        let s = FrameSampler::new(&scrambled("poisson", 64), 23, 1).unwrap();
        assert!(!s.scrambles());
    }

    #[test]
    fn scrambles_follow_the_scopes_and_the_thread_count() {
        for (ps, sh) in [
            (Scope::Frame, Scope::Sequence),
            (Scope::Sequence, Scope::Frame),
            (Scope::Sequence, Scope::Sequence),
        ] {
            for set in ["hammersley", "sobol", "stratified"] {
                let cfg = SamplingConfig {
                    point_set_scope: Some(ps),
                    shift_scope: Some(sh),
                    ..scrambled(set, 27)
                };
                let a = FrameSampler::new(&cfg, 4, 0).unwrap();
                let b = FrameSampler::new(&cfg, 4, 1).unwrap();
                let same = (0..27).all(|i| a.pixel(2, 2).point(i) == b.pixel(2, 2).point(i));
                assert_eq!(same, ps == sh, "{set} {ps:?} {sh:?}");
            }
        }
        let cfg = SamplingConfig {
            density: Some(Density::Temporal(4)),
            ..scrambled("halton", 64)
        };
        let one = parallel_samples(&cfg, 16, 1);
        assert_eq!(one, parallel_samples(&cfg, 16, 2));
        assert_eq!(
            one,
            all_samples(&FrameSampler::new(&cfg, 12, 3).unwrap(), 16, 16)
        );
        // The split keeps its product structure: 16 positions x 4 times per pixel.
        let s = FrameSampler::new(&cfg, 12, 3).unwrap();
        let px = s.pixel(1, 1);
        let pts: Vec<[f32; 3]> = (0..64).map(|i| px.point(i)).collect();
        let distinct = |f: fn(&[f32; 3]) -> Vec<u32>| {
            pts.iter()
                .map(f)
                .collect::<std::collections::BTreeSet<_>>()
                .len()
        };
        assert_eq!(distinct(|p| vec![p[0].to_bits(), p[1].to_bits()]), 16);
        assert_eq!(distinct(|p| vec![p[2].to_bits()]), 4);
    }

    #[test]
    fn bad_configs_name_the_setting() {
        let err = |cfg: SamplingConfig| format!("{:#}", FrameSampler::new(&cfg, 0, 0).unwrap_err());
        let e = err(config("stratified", 100, "box"));
        assert!(e.contains("64 and 125"), "{e}");
        assert!(err(config("random", 0, "box")).contains("`spp`"));
        let e = err(SamplingConfig {
            spatial_sigma: Some(-1.0),
            ..config("random", 8, "box")
        });
        assert!(e.contains("`spatial_sigma`"), "{e}");
        let e = err(SamplingConfig {
            density: Some(Density::Temporal(5)),
            ..config("random", 8, "box")
        });
        assert!(e.contains("`density`"), "{e}");
        assert!(err(config("sobol", 70_000, "box")).contains("65536"));
    }
}
