//! The side-by-side decision stage on a frame ([`DecisionStage::SideBySide`]): each video's
//! band magnitudes, test (e + c) and reference (c), masked through the transducer's slope at
//! their local amplitude, and the two videos' local amplitudes compared: per orientation
//! channel (`add_oriented`), or, without orientation channels, pooled over orientation
//! before the comparison (the stage as first built: `add_videos`, `compare_pooled`).
//!
//! [`DecisionStage::SideBySide`]: super::super::decision_stage::DecisionStage::SideBySide

use super::super::bands::frequencies;
use super::super::decision_stage::SideBySide;
use super::super::local::LocalMean;
use super::super::orientation::{self, OrientationMasking};
use super::super::pooling::{ChannelSums, FITTED, Grid, Placement};
use super::super::transducer::gain;
use super::linear::Linear;
use super::viewing::{ADAPTATION_SIGMA_DEG, Viewing};
use rustfft::num_complex::Complex32;

/// The side-by-side stage built for one viewing: its settings, its local means, and with
/// orientation channels their windows.
pub struct SideBySideFilters {
    /// beta, the space exponent of the energies compared.
    space: f64,
    /// a0, the transducer's knee.
    knee: f32,
    /// The neighbourhood of each band's local energy (the adaptation's Gaussian).
    local: LocalMean,
    oriented: Option<Oriented>,
    /// Scratch: one band image of the difference and of the reference.
    e_band: Vec<Complex32>,
    c_band: Vec<Complex32>,
    /// Without orientation channels, each video's own sums over bands, test then reference.
    own: [ChannelSums; 2],
}

/// The orientation channels of the side-by-side stage.
struct Oriented {
    /// The split, with at least two orientations.
    masking: OrientationMasking,
    /// Each channel's window W_o^(1/beta_c) per coefficient.
    windows: Vec<Vec<f32>>,
    /// The cue's neighbourhood: the fitted aperture itself (its weight on D^beta, a Gaussian
    /// of sd s / sqrt(beta)), so the cue is read at the aperture's place
    /// ([`read_at_aperture`]) instead of summed under it.
    cue_local: LocalMean,
}

impl SideBySideFilters {
    /// The stage `s` on the viewing and channel exponent of `linear`.
    pub fn new(linear: &Linear, s: SideBySide) -> Self {
        let v = linear.viewing();
        let root = 1.0 / linear.channel_exponent();
        let oriented = s.orientation.map(|m| {
            let k = m.orientations.max(2);
            let windows = (0..k)
                .map(|o| {
                    frequencies(v.width, v.height, v.pixels_per_degree)
                        .map(|(fx, fy)| orientation::window(k, o, fx, fy).powf(root) as f32)
                        .collect()
                })
                .collect();
            Oriented {
                masking: OrientationMasking {
                    orientations: k,
                    ..m
                },
                windows,
                cue_local: LocalMean::new(
                    v.width,
                    v.height,
                    v.pixels_per_degree,
                    cue_sd_deg(s.space),
                ),
            }
        });
        let pixels = v.width * v.height;
        let exponents = [linear.channel_exponent()];
        Self {
            space: s.space,
            knee: s.knee,
            local: LocalMean::new(v.width, v.height, v.pixels_per_degree, ADAPTATION_SIGMA_DEG),
            oriented,
            e_band: vec![Complex32::default(); pixels],
            c_band: vec![Complex32::default(); pixels],
            own: [0, 1].map(|_| ChannelSums::new(&exponents, pixels)),
        }
    }

    /// Whether the frame's sums are read at the aperture's place ([`read_at_aperture`])
    /// rather than pooled under it.
    pub fn reads_at_aperture(&self) -> bool {
        self.oriented.is_some()
    }

    /// One frame's cue into `sums` (cleared), from the spectra of the difference and the
    /// reference, `packs` ([`Linear::channels`]).
    pub fn add_frame(
        &mut self,
        linear: &mut Linear,
        packs: (&[Complex32], &[Complex32]),
        sums: &mut ChannelSums,
    ) {
        if self.oriented.is_some() {
            for b in 0..linear.bands() {
                self.add_oriented(linear, sums, packs, b);
            }
            return;
        }
        self.own.iter_mut().for_each(ChannelSums::clear);
        for b in 0..linear.bands() {
            linear.band(packs.0, b, None, &mut self.e_band);
            linear.band(packs.1, b, None, &mut self.c_band);
            self.add_videos();
        }
        self.compare_pooled(linear.channel_exponent(), sums);
    }

    /// Add one band of each video, test (e + c) and reference (c), masked: each video's band
    /// magnitude n_V = |v_S| + |v_T| times the gain of the band's local contrast,
    /// g = R'(m) = min(1, (m / a0)^-eps) ([`super::super::transducer`]), with m the local
    /// amplitude of the two videos' mean band energy, m = (G * (n_T^beta + n_R^beta) / 2)^(1/beta).
    /// Both videos' noise and the scene's content in the band raise m: each masks the other.
    fn add_videos(&mut self) {
        let (nt, nr): (Vec<f32>, Vec<f32>) = self
            .e_band
            .iter()
            .zip(&self.c_band)
            .map(|(e, c)| {
                (
                    (e.re + c.re).abs() + (e.im + c.im).abs(),
                    c.re.abs() + c.im.abs(),
                )
            })
            .unzip();
        let b = self.space as f32;
        let energy: Vec<f32> = nt
            .iter()
            .zip(&nr)
            .map(|(t, r)| 0.5 * (t.powf(b) + r.powf(b)))
            .collect();
        let zero = vec![0.0; nt.len()];
        let (m, _) = self.local.pair(&energy, &zero);
        let a0 = self.knee;
        let gain: Vec<f32> = m
            .iter()
            .map(|&m| gain(m.max(0.0).powf(1.0 / b), a0))
            .collect();
        for (sums, n) in self.own.iter_mut().zip([nt, nr]) {
            let masked: Vec<f32> = n.iter().zip(&gain).map(|(n, g)| n * g).collect();
            sums.add(&masked, &zero);
        }
    }

    /// One band of each video split into orientation channels ([`super::super::orientation`]),
    /// compared channel by channel: each channel's signal n_V,o is masked by its own local
    /// energy and, weighted by w, the mean of the other channels' (m_o^beta = G * (E_o + w
    /// mean_{o' != o} E_o'), E the two videos' mean energy n^beta), each video's local
    /// amplitude of it taken, a_V,o = (G * (g_o n_V,o)^beta)^(1/beta), and |a_T,o - a_R,o|
    /// added to `sums` as one more channel of the Minkowski sum over bands and channels.
    /// Comparing per channel, not the videos' summed amplitudes, is what keeps energy in one
    /// channel from masking another (summed, a mask adds in quadrature to the target's
    /// channel: Meese's orthogonal mask then masks as a parallel one would). `packs` are the
    /// spectra of the difference and the reference.
    fn add_oriented(
        &mut self,
        linear: &mut Linear,
        sums: &mut ChannelSums,
        packs: (&[Complex32], &[Complex32]),
        b: usize,
    ) {
        let Self {
            space,
            knee,
            local,
            oriented,
            e_band,
            c_band,
            ..
        } = self;
        let Oriented {
            masking: m,
            windows,
            cue_local,
        } = oriented.as_mut().expect("oriented filters");
        let beta = *space as f32;
        let powers: Vec<[Vec<f32>; 2]> = windows
            .iter()
            .map(|win| {
                linear.band(packs.0, b, Some(win), e_band);
                linear.band(packs.1, b, Some(win), c_band);
                band_powers(e_band, c_band, beta)
            })
            .collect();
        let maskers = maskers(local, &powers, m.cross_weight as f32);
        // g^beta = (m / a0)^(-eps beta) = (m^beta / a0^beta)^-eps above the knee, 1 below: the
        // gain raised to beta is the gain of m^beta at the knee a0^beta, one power instead of a
        // root and two powers.
        let knee = knee.powf(beta);
        let inv = 1.0 / beta;
        for ([nt, nr], masker) in powers.iter().zip(&maskers) {
            let g: Vec<f32> = masker.iter().map(|&e| gain(e, knee)).collect();
            let masked = |n: &[f32]| -> Vec<f32> { n.iter().zip(&g).map(|(n, g)| n * g).collect() };
            let (at, ar) = cue_local.pair(&masked(nt), &masked(nr));
            let cue: Vec<f32> = at
                .iter()
                .zip(&ar)
                .map(|(&t, &r)| (root(t, inv) - root(r, inv)).abs())
                .collect();
            sums.add_one(&cue);
        }
    }

    /// The pooled side-by-side cue into `sums`: each video's local amplitude of its masked
    /// band norm, a_V = (G * N_V^beta)^(1/beta), and sums = |a_T - a_R|^beta_c, so that the
    /// pooling's (sums)^(beta / beta_c) is |a_T - a_R|^beta. Against a blank field below the
    /// knee, a_R = 0 and a_T^beta = G * D^beta, whose sum over the frame is the difference
    /// stage's.
    fn compare_pooled(&mut self, channel_exponent: f64, sums: &mut ChannelSums) {
        let r = (self.space / channel_exponent) as f32;
        let [nt, nr] = [0, 1].map(|k| {
            self.own[k].sums[0]
                .iter()
                .map(|&v| v.powf(r))
                .collect::<Vec<f32>>()
        });
        let (et, er) = self.local.pair(&nt, &nr);
        let (inv, bc) = (1.0 / self.space as f32, channel_exponent as f32);
        // The means can leave -1e-9 where the energy is 0: clamped before the root.
        let amp = |v: f32| v.max(0.0).powf(inv);
        for ((acc, t), r) in sums.sums[0].iter_mut().zip(&et).zip(&er) {
            *acc = (amp(*t) - amp(*r)).abs().powf(bc);
        }
    }
}

/// v^(1 / beta) of a local mean, which can leave -1e-9 where the energy is 0 (clamped), and
/// 0 without a power where it is 0.
fn root(v: f32, inv: f32) -> f32 {
    if v > 0.0 { v.powf(inv) } else { 0.0 }
}

/// Each video's band norm raised to beta, n_T^beta and n_R^beta, from one channel's band
/// images of the difference (e) and the reference (c): the test video is e + c.
fn band_powers(e_band: &[Complex32], c_band: &[Complex32], beta: f32) -> [Vec<f32>; 2] {
    let pow = |v: f32| if v > 0.0 { v.powf(beta) } else { 0.0 };
    e_band
        .iter()
        .zip(c_band)
        .map(|(e, c)| {
            (
                pow((e.re + c.re).abs() + (e.im + c.im).abs()),
                pow(c.re.abs() + c.im.abs()),
            )
        })
        .unzip::<_, _, Vec<f32>, Vec<f32>>()
        .into()
}

/// Each channel's masker m_o^beta = G * (E_o + w mean_{o' != o} E_o'), with E the two videos'
/// mean energy (n_T^beta + n_R^beta) / 2; the local means two channels to a transform pair.
fn maskers(local: &mut LocalMean, powers: &[[Vec<f32>; 2]], w: f32) -> Vec<Vec<f32>> {
    let energy = |[t, r]: &[Vec<f32>; 2]| -> Vec<f32> {
        t.iter().zip(r).map(|(t, r)| 0.5 * (t + r)).collect()
    };
    let mut means = Vec::with_capacity(powers.len());
    for two in powers.chunks(2) {
        let a = energy(&two[0]);
        let b = two.get(1).map_or_else(|| vec![0.0; a.len()], energy);
        let (ma, mb) = local.pair(&a, &b);
        means.push(ma);
        if two.len() == 2 {
            means.push(mb);
        }
    }
    if w == 0.0 {
        return means;
    }
    let others = w / (means.len() - 1) as f32;
    let total: Vec<f32> = (0..means[0].len())
        .map(|i| means.iter().map(|m| m[i]).sum())
        .collect();
    means
        .iter()
        .map(|own| {
            own.iter()
                .zip(&total)
                .map(|(&e, &all)| e + others * (all - e))
                .collect()
        })
        .collect()
}

/// The sd (deg) of the oriented side-by-side stage's cue neighbourhood: the fitted aperture's
/// weight on D^beta, exp(-beta r^2 / (2 s^2)), a Gaussian of sd s / sqrt(beta).
fn cue_sd_deg(space: f64) -> f64 {
    FITTED.aperture_deg / space.sqrt()
}

/// Q_t of the oriented side-by-side stage: its cue D is already a local amplitude over the
/// aperture's own window (normalised to sum 1), so Q^beta = 2 pi (s^2 / beta) D^beta read at
/// one place, the aperture's: the centre, or the most visible place. Against a blank field
/// below the knee that is the difference stage's aperture-weighted sum exactly (one channel;
/// several mix through beta_c as they do at a pixel). An infinite aperture sums D^beta over
/// the frame instead.
pub fn read_at_aperture(
    sums: &ChannelSums,
    grid: &Grid,
    v: Viewing,
    placement: Placement,
) -> Vec<f64> {
    let bc = sums.exponents[0];
    let sum = &sums.sums[0];
    let mut out = Vec::new();
    for p in grid.space_pairs(bc) {
        let r = (p.space / bc) as f32;
        let d: Vec<f64> = sum.iter().map(|&x| x.max(0.0).powf(r) as f64).collect();
        let q_beta = if !p.aperture_deg.is_finite() {
            d.iter().sum::<f64>() / v.pixels_per_degree.powi(2)
        } else {
            let read = match placement {
                Placement::MostVisible => d.iter().cloned().fold(0.0, f64::max),
                Placement::Centre => {
                    let (w, h) = (v.width, v.height);
                    let (x0, y0) = ((w - 1) / 2, (h - 1) / 2);
                    let (x1, y1) = (w / 2, h / 2);
                    0.25 * (d[y0 * w + x0] + d[y0 * w + x1] + d[y1 * w + x0] + d[y1 * w + x1])
                }
            };
            2.0 * std::f64::consts::PI * p.aperture_deg.powi(2) / p.space * read
        };
        out.push(q_beta.powf(1.0 / p.space));
    }
    out
}
