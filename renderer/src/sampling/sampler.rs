//! The renderer's view of sampling: [`FrameSampler`] is built once per frame and answers
//! "sample i of pixel (x, y)" with a sub-pixel offset and a shutter time, after the pixel's
//! shift and both warps (thesis Figure 14, then Figure 16).

use super::config::{SamplingConfig, Scope};
use super::time_filter::TimeFilter;
use super::warp::SpatialWarp;
use super::{density, pointset, shift};
use crate::hash;
use anyhow::{Result, bail};

/// Hash tags separating the random streams of a stimulus.
const POINTS_TAG: u64 = 0x5e7;
const SHIFT_TAG: u64 = 0x5817;

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
    spatial: SpatialWarp,
    time: TimeFilter,
}

/// One pixel's view of a [`FrameSampler`]: the shift is computed once for all its samples.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler<'a> {
    frame: &'a FrameSampler,
    shift: [f32; 3],
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
    /// what it must be (unknown names, stratified counts that are not cubes, ...).
    pub fn new(config: &SamplingConfig, seed: u64, frame: u32) -> Result<Self> {
        if config.spp == 0 {
            bail!("field `spp` must be at least 1");
        }
        let sigma = config.spatial_sigma();
        if !(sigma.is_finite() && sigma > 0.0) {
            bail!("field `spatial_sigma` is {sigma}; expected a positive number of pixels");
        }
        let time = TimeFilter::by_name(&config.time_filter)?;
        let set = pointset::by_name(&config.point_set)?;
        let key = scoped(seed, POINTS_TAG, config.point_set_scope(), frame);
        let points = density::points(set, config.spp as usize, config.density(), key)?
            .into_iter()
            .map(|p| p.map(|c| (c as f32).min(BELOW_ONE)))
            .collect();
        Ok(Self {
            points,
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

    /// Pixel (x, y): hash its shift once, then ask it for each sample (cheaper than
    /// [`FrameSampler::sample`] per sample).
    #[inline]
    pub fn pixel(&self, x: u32, y: u32) -> PixelSampler<'_> {
        PixelSampler {
            frame: self,
            shift: shift::pixel_shift(self.shift_key, x, y),
        }
    }

    /// Sample `i` (< spp) of pixel `(x, y)`.
    #[inline]
    pub fn sample(&self, x: u32, y: u32, i: usize) -> PixelSample {
        self.pixel(x, y).sample(i)
    }
}

impl PixelSampler<'_> {
    /// The pixel's shift in (u, v, t), each in [0, 1).
    pub fn shift(&self) -> [f32; 3] {
        self.shift
    }

    /// Sample `i` (< spp): point i, shifted with wrap-around, then warped.
    #[inline]
    pub fn sample(&self, i: usize) -> PixelSample {
        let p = self.frame.points[i];
        let [u, v, t] = [0, 1, 2].map(|d| shift::wrap(p[d], self.shift[d]));
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
    use crate::sampling::config::{Density, SpatialFilter};
    use crate::sampling::pointset::ALL;
    use rayon::prelude::*;

    fn config(point_set: &str, spp: u32, time_filter: &str) -> SamplingConfig {
        SamplingConfig {
            point_set: point_set.into(),
            spp,
            time_filter: time_filter.into(),
            ..Default::default()
        }
    }

    fn all_samples(s: &FrameSampler, w: u32, h: u32) -> Vec<PixelSample> {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .flat_map(|(x, y)| (0..s.spp()).map(move |i| s.sample(x, y, i)))
            .collect()
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
        let render = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let s = FrameSampler::new(&cfg, 12, 3).unwrap();
                (0..32u32)
                    .into_par_iter()
                    .flat_map_iter(|y| {
                        let s = &s;
                        (0..32u32).flat_map(move |x| (0..16).map(move |i| s.sample(x, y, i)))
                    })
                    .collect::<Vec<_>>()
            })
        };
        let one = render(1);
        assert_eq!(one, render(3));
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

    #[test]
    fn bad_configs_name_the_setting() {
        let err = |cfg: SamplingConfig| format!("{:#}", FrameSampler::new(&cfg, 0, 0).unwrap_err());
        let e = err(config("stratified", 100, "box"));
        assert!(e.contains("64 and 125"), "{e}");
        assert!(err(config("nope", 8, "box")).contains("unknown point set"));
        assert!(err(config("random", 8, "nope")).contains("unknown time filter"));
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
