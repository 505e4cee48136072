//! Pooling the visible difference over channels, space and time into one number Q per video
//! (and one per frame, for the spread over frames), as a detector pools: by Minkowski
//! summation, so that adding area or time without a difference never lowers Q.
//!
//! With d_{b,k}(x, t) the masked, CSF-weighted difference in spatial band b and temporal
//! channel k (in threshold units):
//!
//! 1. temporal channels linearly within a band, as stelaCSF adds its sustained and transient
//!    mechanisms; then bands, a Minkowski sum with exponent beta_c:
//!    D(x, t) = (sum_b (|d_{b,S}(x, t)| + |d_{b,T}(x, t)|)^beta_c)^(1/beta_c). With beta_c = 1
//!    (linear, as FovVideoVDP pools its bands) a broadband pattern
//!    such as noise or a natural scene sums its bands' magnitudes and comes out far more
//!    visible than people find it (ModelFest #35 and #43); larger beta_c is the classic
//!    multi-channel detector (Watson 1983; Graham 1989), whose channels are detected
//!    independently. beta_c is fitted to ModelFest from {1, 2, 3, 4} ([`FITTED`]). The band
//!    windows' beta_c-th powers sum to 1 ([`super::video::Filters::new`]), so a single
//!    grating's D is its CSF-weighted contrast at any beta_c, between band centres too;
//! 2. space, a Minkowski sum over the picture as an integral over visual angle (deg^2):
//!    Q_t = (sum_x |D(x, t)|^beta / ppd^2)^(1/beta), the spatial pooling of Watson &
//!    Ahumada's standard spatial observer (2005, JOV 5(9):6). A sum, not a mean: noise-free
//!    area adds nothing, and a bigger patch of the same difference is more visible. Under a
//!    Gaussian aperture of sd s (the standard observer's), D is weighted by
//!    w(x) = exp(-r^2 / (2 s^2)) before the power; the window is centred on ModelFest's stimuli
//!    (their fixation mark) and, in the suite's videos, frame by frame where the windowed sum is
//!    largest ([`Placement`]). beta and s are fitted to ModelFest ([`modelfest`], [`FITTED`]);
//! 3. time, the same exponent as a mean over the video's frames: Q = (mean_t Q_t^beta)^(1/beta).
//!    A trial loops its videos, so the mean is the Minkowski integral over a fixed window of
//!    the loop (the window's length is a constant that k holds); ModelFest's presentation is
//!    shown as a 1 s video holding the whole 0.5 s time course, so its mean is the integral
//!    over the presentation. ModelFest's stimuli share one time course, so they cannot fit a
//!    separate temporal exponent: one exponent serves both (documented in docs/predict.md).
//!
//! [`modelfest`]: crate::observer::datasets::modelfest

/// How the visible difference is pooled: the two exponents and the spatial aperture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pooling {
    /// beta_c, over bands at each pixel (the temporal channels add linearly within a band).
    pub channels: f64,
    /// beta, over space and time.
    pub space: f64,
    /// Standard deviation of the Gaussian aperture, degrees (infinite: no aperture).
    pub aperture_deg: f64,
}

/// The pooling fitted, with [`DEFAULT_K`] and [`super::shape::FITTED`], to the 43 ModelFest
/// thresholds by least squares on log thresholds (`blurlab predict validate modelfest`).
///
/// [`DEFAULT_K`]: super::proportion_correct::DEFAULT_K
pub const FITTED: Pooling = Pooling {
    channels: 2.0,
    space: 2.4,
    aperture_deg: 0.5,
};

/// A grid of poolings to evaluate in one pass of the pipeline: every channel exponent with
/// every space exponent and every aperture, in that order ([`Grid::pairs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub channels: Vec<f64>,
    pub space: Vec<f64>,
    pub apertures: Vec<f64>,
}

impl Grid {
    pub fn one(p: Pooling) -> Self {
        Self {
            channels: vec![p.channels],
            space: vec![p.space],
            apertures: vec![p.aperture_deg],
        }
    }

    /// The poolings in the order of the pipeline's outputs.
    pub fn pairs(&self) -> Vec<Pooling> {
        let mut out = Vec::new();
        for &channels in &self.channels {
            out.extend(self.space_pairs(channels));
        }
        out
    }

    /// The poolings of one channel exponent, in the order of [`ChannelSums::frame_q`].
    pub fn space_pairs(&self, channels: f64) -> Vec<Pooling> {
        let mut out = Vec::new();
        for &space in &self.space {
            for &aperture_deg in &self.apertures {
                out.push(Pooling {
                    channels,
                    space,
                    aperture_deg,
                });
            }
        }
        out
    }
}

/// |v|^e, by multiplication for the integer exponents the fit searches.
#[inline]
pub fn power(v: f32, e: f64) -> f32 {
    let a = v.abs();
    match e {
        1.0 => a,
        2.0 => a * a,
        3.0 => a * a * a,
        4.0 => (a * a) * (a * a),
        _ => a.powf(e as f32),
    }
}

/// Per-pixel sums over bands, sum_b (|d_S| + |d_T|)^beta_c, for each channel exponent.
pub struct ChannelSums {
    pub exponents: Vec<f64>,
    pub sums: Vec<Vec<f32>>,
}

impl ChannelSums {
    pub fn new(exponents: &[f64], pixels: usize) -> Self {
        Self {
            exponents: exponents.to_vec(),
            sums: vec![vec![0.0; pixels]; exponents.len()],
        }
    }

    pub fn clear(&mut self) {
        self.sums.iter_mut().for_each(|s| s.fill(0.0));
    }

    /// Add one band's two channel outputs (already divided by their threshold elevations).
    pub fn add(&mut self, sustained: &[f32], transient: &[f32]) {
        self.add_scaled(sustained, transient, 1.0, 1.0);
    }

    /// Add one channel's output alone (a channel with no transient partner).
    pub fn add_one(&mut self, channel: &[f32]) {
        for (e, sum) in self.exponents.iter().zip(self.sums.iter_mut()) {
            for (acc, &a) in sum.iter_mut().zip(channel) {
                *acc += power(a, *e);
            }
        }
    }

    /// Add one band's two channel outputs, each times its factor.
    pub fn add_scaled(&mut self, sustained: &[f32], transient: &[f32], fs: f32, ft: f32) {
        for (e, sum) in self.exponents.iter().zip(self.sums.iter_mut()) {
            for ((acc, &a), &b) in sum.iter_mut().zip(sustained).zip(transient) {
                *acc += power((fs * a).abs() + (ft * b).abs(), *e);
            }
        }
    }

    /// Q_t of every pooling of `grid` (whose channel exponents are these), in the order of
    /// [`Grid::pairs`], for a frame `width` pixels wide; an aperture sits where `placement`
    /// puts it.
    pub fn frame_q(
        &self,
        grid: &Grid,
        pixels_per_degree: f64,
        width: usize,
        placement: Placement,
    ) -> Vec<f64> {
        let pixel_deg2 = pixels_per_degree.powi(-2);
        let pixels = self.sums.first().map_or(0, Vec::len);
        let mut out = Vec::with_capacity(grid.pairs().len());
        let centred: Vec<Option<Vec<f32>>> = grid
            .apertures
            .iter()
            .map(|&a| {
                (a.is_finite() && placement == Placement::Centre)
                    .then(|| log_aperture(width, pixels, pixels_per_degree, a))
            })
            .collect();
        for (bc, sum) in self.exponents.iter().zip(&self.sums) {
            let logs: Vec<f32> = sum.iter().map(|&v| v.ln()).collect();
            for &b in &grid.space {
                // D^beta w^beta = exp((beta / beta_c) ln sum + beta ln w).
                let r = (b / bc) as f32;
                for (&a, w) in grid.apertures.iter().zip(&centred) {
                    let total: f64 = match w {
                        _ if a.is_finite() && placement == Placement::MostVisible => {
                            let d: Vec<f32> = logs.iter().map(|&l| (r * l).exp()).collect();
                            most_visible(&d, width, a * pixels_per_degree / b.sqrt())
                        }
                        None if r == 1.0 => sum.iter().map(|&v| v as f64).sum(),
                        None => logs.iter().map(|&l| (r * l).exp() as f64).sum(),
                        Some(w) => logs
                            .iter()
                            .zip(w)
                            .map(|(&l, &lw)| (r * l + b as f32 * lw).exp() as f64)
                            .sum(),
                    };
                    out.push((total * pixel_deg2).powf(1.0 / b));
                }
            }
        }
        out
    }
}

/// Where the spatial aperture sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// On the frame's centre: ModelFest's stimuli, centred on the observers' fixation mark.
    Centre,
    /// Where the windowed sum is largest, frame by frame: an observer who looks at the most
    /// visible place (the suite's videos, where nobody tells the subject where to look).
    MostVisible,
}

/// The largest sum of `d` (a frame `width` pixels wide) under a Gaussian window of standard
/// deviation `sd_px` pixels, over the window's positions on pixel centres: the largest value
/// of d blurred (unnormalised, zero outside the frame) by exp(-r^2 / (2 sd^2)).
pub fn most_visible(d: &[f32], width: usize, sd_px: f64) -> f64 {
    most_visible_at(d, width, sd_px).0
}

/// [`most_visible`] and where: (the largest windowed sum, its column, its row).
pub fn most_visible_at(d: &[f32], width: usize, sd_px: f64) -> (f64, usize, usize) {
    let height = d.len() / width.max(1);
    let reach = (4.0 * sd_px).ceil() as usize;
    let k: Vec<f64> = (0..=reach)
        .map(|i| (-0.5 * (i as f64 / sd_px).powi(2)).exp())
        .collect();
    let blur = |get: &dyn Fn(usize) -> f64, n: usize, i: usize| -> f64 {
        let lo = i.saturating_sub(reach);
        let hi = (i + reach).min(n - 1);
        (lo..=hi).map(|j| get(j) * k[j.abs_diff(i)]).sum()
    };
    let mut rows = vec![0f64; d.len()];
    for y in 0..height {
        let row = &d[y * width..(y + 1) * width];
        for x in 0..width {
            rows[y * width + x] = blur(&|j| row[j] as f64, width, x);
        }
    }
    let mut best = (0f64, 0, 0);
    for x in 0..width {
        for y in 0..height {
            let v = blur(&|j| rows[j * width + x], height, y);
            if v > best.0 {
                best = (v, x, y);
            }
        }
    }
    best
}

/// ln of a Gaussian aperture of standard deviation `sd_deg` centred on a frame `width` pixels
/// wide: -r^2 / (2 sd^2), r the distance from the frame's centre in degrees.
pub fn log_aperture(width: usize, pixels: usize, pixels_per_degree: f64, sd_deg: f64) -> Vec<f32> {
    let height = pixels / width.max(1);
    let (cx, cy) = ((width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0);
    let s = 2.0 * (sd_deg * pixels_per_degree).powi(2);
    (0..pixels)
        .map(|i| {
            let (x, y) = ((i % width) as f64 - cx, (i / width) as f64 - cy);
            (-(x * x + y * y) / s) as f32
        })
        .collect()
}

/// Q of the whole video from its frames' Q_t: (mean Q_t^beta)^(1/beta).
pub fn video_q(frames: &[f64], beta: f64) -> f64 {
    if frames.is_empty() {
        return 0.0;
    }
    (frames.iter().map(|q| q.powf(beta)).sum::<f64>() / frames.len() as f64).powf(1.0 / beta)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q_of(d: &[f32], channels: &[f64], space: &[f64], ppd: f64) -> Vec<f64> {
        let mut c = ChannelSums::new(channels, d.len());
        c.add(d, &vec![0.0; d.len()]);
        c.frame_q(
            &Grid {
                channels: channels.to_vec(),
                space: space.to_vec(),
                apertures: vec![f64::INFINITY],
            },
            ppd,
            d.len(),
            Placement::Centre,
        )
    }

    #[test]
    fn an_aperture_weighs_by_its_gaussian_and_is_centred() {
        // D = 1 over a 12-deg square at 20 ppd: with an aperture of sd s the integral of
        // w^beta is 2 pi s^2 / beta (the square holds > 6 sd); without, the square's area.
        let (side, ppd) = (240, 20.0);
        let mut c = ChannelSums::new(&[2.0], side * side);
        c.add(&vec![1.0; side * side], &vec![0.0; side * side]);
        let grid = Grid {
            channels: vec![2.0],
            space: vec![2.0, 3.0],
            apertures: vec![f64::INFINITY, 1.0, 0.5],
        };
        let q = c.frame_q(&grid, ppd, side, Placement::Centre);
        assert_eq!(grid.pairs().len(), q.len());
        for (p, got) in grid.pairs().iter().zip(&q) {
            let s = p.aperture_deg;
            let want = if s.is_finite() {
                2.0 * std::f64::consts::PI * s * s / p.space
            } else {
                144.0
            };
            let want = want.powf(1.0 / p.space);
            assert!((got / want - 1.0).abs() < 1e-4, "{p:?}: {got} vs {want}");
        }
        // A patch of D = 1 off the frame's centre: the centred window sees its edge, the
        // most visible place is on it and sees what a centred window on a centred patch sees.
        let patch = |x0: usize| {
            let mut c = ChannelSums::new(&[2.0], side * side);
            let d: Vec<f32> = (0..side * side)
                .map(|i| {
                    let (x, y) = (i % side, i / side);
                    f32::from(x.abs_diff(x0) < 30 && y.abs_diff(side / 2) < 30)
                })
                .collect();
            c.add(&d, &vec![0.0; d.len()]);
            c
        };
        let one = Grid {
            channels: vec![2.0],
            space: vec![2.8],
            apertures: vec![0.5],
        };
        let centred = patch(side / 2).frame_q(&one, ppd, side, Placement::Centre)[0];
        let off = patch(40);
        let moved = off.frame_q(&one, ppd, side, Placement::MostVisible)[0];
        assert!((moved / centred - 1.0).abs() < 2e-3, "{moved} vs {centred}");
        assert!(off.frame_q(&one, ppd, side, Placement::Centre)[0] < 0.01 * centred);
        // Centred: the window's weight is 1 in the middle of the frame (between four pixels
        // here) and falls alike on each side.
        let w = log_aperture(4, 16, 1.0, 1.0);
        assert_eq!(w[5], w[10]);
        assert_eq!(w[0], w[15]);
        assert!((w[5] as f64 + 0.25).abs() < 1e-6);
    }

    #[test]
    fn a_sinusoid_pools_to_its_minkowski_integral() {
        // 3 cos over 64 pixels of 1/64 deg^2 each (8 ppd): the integral of |D|^beta is
        // 3^beta times the mean of |cos|^beta (a deg^2 in all), whatever the channel exponent.
        let n = 64;
        let d: Vec<f32> = (0..n)
            .map(|i| 3.0 * (2.0 * std::f32::consts::PI * 4.0 * i as f32 / n as f32).cos())
            .collect();
        let q = q_of(&d, &[1.0, 3.0], &[2.0, 4.0], 8.0);
        // Means of cos^beta: 1/2, 3/8.
        let want: Vec<f64> = [(2.0, 0.5), (4.0, 0.375)]
            .iter()
            .map(|&(b, m): &(f64, f64)| (3f64.powf(b) * m).powf(1.0 / b))
            .collect();
        for (got, want) in q.iter().zip(want.iter().chain(&want)) {
            assert!((got - want).abs() < 1e-5 * want, "{got} vs {want}");
        }
        assert!((video_q(&[3.0, 4.0], 2.0) - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(video_q(&[], 2.0), 0.0);
    }

    #[test]
    fn channels_sum_by_their_exponent() {
        // Two bands of 3 and 4 at one pixel (the second's channels 1 and -3, added as
        // magnitudes): linear 7, energy 5, exponent 4 (81+256)^(1/4).
        let mut c = ChannelSums::new(&[1.0, 2.0, 4.0, 2.5], 1);
        c.add(&[3.0], &[0.0]);
        c.add(&[1.0], &[-3.0]);
        let grid = Grid {
            channels: vec![1.0, 2.0, 4.0, 2.5],
            space: vec![1.0],
            apertures: vec![f64::INFINITY],
        };
        let q = c.frame_q(&grid, 1.0, 1, Placement::Centre);
        let want = [
            7.0,
            5.0,
            337f64.powf(0.25),
            (3f64.powf(2.5) + 4f64.powf(2.5)).powf(0.4),
        ];
        for (g, w) in q.iter().zip(want) {
            assert!((g - w).abs() < 1e-5 * w, "{g} vs {w}");
        }
    }

    #[test]
    fn noise_free_area_adds_nothing_and_more_difference_adds() {
        let d = vec![0.5f32, -2.0, 1.0];
        let mut padded = d.clone();
        padded.extend([0.0; 100]);
        let doubled = [d.clone(), d.clone()].concat();
        for beta in [1.0, 1.7, 2.0, 3.5] {
            let a = q_of(&d, &[1.0, 2.0], &[beta], 10.0);
            assert_eq!(a, q_of(&padded, &[1.0, 2.0], &[beta], 10.0));
            let b = q_of(&doubled, &[1.0, 2.0], &[beta], 10.0);
            assert!(b[0] > a[0] && b[1] > a[1]);
        }
    }
}
