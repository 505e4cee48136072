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
//!    area adds nothing, and a bigger patch of the same difference is more visible. The
//!    exponent beta is fitted to ModelFest ([`super::modelfest`], [`FITTED`]);
//! 3. time, the same exponent as a mean over the video's frames: Q = (mean_t Q_t^beta)^(1/beta).
//!    A trial loops its videos, so the mean is the Minkowski integral over a fixed window of
//!    the loop (the window's length is a constant that k holds); ModelFest's presentation is
//!    shown as a 1 s video holding the whole 0.5 s time course, so its mean is the integral
//!    over the presentation. ModelFest's stimuli share one time course, so they cannot fit a
//!    separate temporal exponent: one exponent serves both (documented in docs/predict.md).

/// The two pooling exponents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exponents {
    /// beta_c, over bands at each pixel (the temporal channels add linearly within a band).
    pub channels: f64,
    /// beta, over space and time.
    pub space: f64,
}

/// The exponents fitted, with [`super::decision::DEFAULT_K`], to the 43 ModelFest thresholds
/// by least squares on log thresholds (`blurlab predict validate modelfest`).
pub const FITTED: Exponents = Exponents {
    channels: 2.0,
    space: 2.8,
};

/// A grid of exponent pairs to evaluate in one pass of the pipeline: every channel exponent
/// with every space exponent, channel-major ([`Grid::pairs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub channels: Vec<f64>,
    pub space: Vec<f64>,
}

impl Grid {
    pub fn one(e: Exponents) -> Self {
        Self {
            channels: vec![e.channels],
            space: vec![e.space],
        }
    }

    /// The pairs in the order of the pipeline's outputs.
    pub fn pairs(&self) -> Vec<Exponents> {
        self.channels
            .iter()
            .flat_map(|&c| {
                self.space.iter().map(move |&s| Exponents {
                    channels: c,
                    space: s,
                })
            })
            .collect()
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
        for (e, sum) in self.exponents.iter().zip(self.sums.iter_mut()) {
            for ((acc, &a), &b) in sum.iter_mut().zip(sustained).zip(transient) {
                *acc += power(a.abs() + b.abs(), *e);
            }
        }
    }

    /// Q_t of every (channel, space) pair of `grid` (whose channel exponents are these).
    pub fn frame_q(&self, grid: &Grid, pixels_per_degree: f64) -> Vec<f64> {
        let pixel_deg2 = pixels_per_degree.powi(-2);
        let mut out = Vec::with_capacity(grid.channels.len() * grid.space.len());
        for (bc, sum) in self.exponents.iter().zip(&self.sums) {
            for &b in &grid.space {
                // D^beta = (sum |d|^beta_c)^(beta / beta_c).
                let r = (b / bc) as f32;
                let total: f64 = if r == 1.0 {
                    sum.iter().map(|&v| v as f64).sum()
                } else {
                    sum.iter()
                        .filter(|v| **v > 0.0)
                        .map(|&v| v.powf(r) as f64)
                        .sum()
                };
                out.push((total * pixel_deg2).powf(1.0 / b));
            }
        }
        out
    }
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
            },
            ppd,
        )
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
        };
        let q = c.frame_q(&grid, 1.0);
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
