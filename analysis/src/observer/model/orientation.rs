//! Orientation channels for the side-by-side stage's masking: each spatial band split into K
//! orientation channels, so that a masker of one orientation masks mostly its own (Meese et
//! al. 2007's cross-orientation masking, [`meese`]: an orthogonal grating of 45% contrast
//! raises a grating's threshold about 3x at 1 c/deg and not at all at 7 c/deg, where masking
//! pooled over every orientation of the band raises it about 50x).
//!
//! Windows: raised cosines in orientation theta (mod 180 deg), centred at o 180 / K deg,
//!
//! ```text
//! W_o(theta) = cos^2(pi / 2 d_o / Delta) for d_o < Delta, 0 beyond;   Delta = 180 / K deg,
//! ```
//!
//! d_o the angular distance to the centre. Neighbours cross at half height, so the windows sum
//! to 1 at every orientation, and W_o(f) = W_o(-f), so a real band stays real. The filters
//! use W_o^(1/beta_c), as the bands do ([`super::video::Filters::new`]): a grating pools over
//! orientations to the contrast it had in the unsplit band. K = 4 gives a half-width at half
//! height of 22.5 deg, inside the 15-30 deg that masking measures for the orientation
//! bandwidth of spatial mechanisms (Phillips & Wilson 1984, "Orientation bandwidths of spatial
//! mechanisms measured by masking", JOSA A 1(2):226-232: about 30 deg at 0.5 c/deg falling to
//! 15 deg at 11 c/deg). The mean (f = 0) goes to every channel equally.
//!
//! The masker of channel o pools its own energy and, with weight w, the other channels':
//! m_o^beta = G * (E_o + w mean_{o' != o} E_o'), and the two videos are compared channel by
//! channel ([`super::video`]). w = 0 masks within orientation only, w = 1 with every
//! orientation alike. w is the one parameter fitted, to Meese's elevations
//! (`blurlab predict validate meese2007`, [`COMMITTED`]).
//!
//! [`meese`]: crate::observer::datasets::meese

/// The orientation split and the weight of the other orientations' energy in each channel's
/// masker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientationMasking {
    /// K, the number of orientation channels per band (at least 2).
    pub orientations: usize,
    /// w in [0, 1], the cross-orientation weight.
    pub cross_weight: f64,
}

/// The committed split: four orientations (see the module's text).
pub const ORIENTATIONS: usize = 4;

/// The side-by-side stage's orientation masking: [`ORIENTATIONS`] channels, the
/// cross-orientation weight fitted to Meese et al. 2007's elevations (`blurlab predict validate
/// meese2007`: w = 0, the grid's least error, 4.03 dB; leave-one-out 4.03 dB).
pub const COMMITTED: OrientationMasking = OrientationMasking {
    orientations: ORIENTATIONS,
    cross_weight: 0.0,
};

/// W_o at frequency (fx, fy) (c/deg) of a split into `k` orientations: the oriented window
/// [`angular`] from [`super::bands::LOWEST_CENTRE_CPD`] up, 1 / K (no orientation) an octave
/// below it and under, and between them a cos^2 blend over log frequency, as the bands blend.
pub fn window(k: usize, o: usize, fx: f64, fy: f64) -> f64 {
    let s = oriented_share(fx.hypot(fy));
    s * angular(k, o, fx, fy) + (1.0 - s) / k as f64
}

/// How much of a frequency rho (c/deg) is split by orientation: 1 from the lowest band
/// centre up, 0 an octave below. Below the lowest centre the bank has no band-pass channel,
/// only the low-pass residual, which is isotropic (as a steerable pyramid's is). Split there,
/// the channels' kernels would be the angular windows' own, scale-free with tails like
/// 1 / r^2: a large stimulus (ModelFest's Gaussian 26) spread over the frame, which space
/// pooling at beta > beta_c penalises (ModelFest 1.39 dB against 0.995 with the blend).
pub fn oriented_share(rho: f64) -> f64 {
    let top = super::bands::LOWEST_CENTRE_CPD;
    if rho >= top {
        1.0
    } else if rho <= 0.5 * top {
        0.0
    } else {
        (0.5 * std::f64::consts::PI * (rho / top).log2())
            .cos()
            .powi(2)
    }
}

/// The raised-cosine window in orientation alone (at f = 0, 1 / K).
fn angular(k: usize, o: usize, fx: f64, fy: f64) -> f64 {
    if fx == 0.0 && fy == 0.0 {
        return 1.0 / k as f64;
    }
    let pi = std::f64::consts::PI;
    let delta = pi / k as f64;
    let theta = fy.atan2(fx).rem_euclid(pi);
    let centre = o as f64 * delta;
    let d = (theta - centre).rem_euclid(pi);
    let d = d.min(pi - d);
    if d >= delta {
        0.0
    } else {
        (0.5 * pi * d / delta).cos().powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_windows_sum_to_one_and_are_even() {
        for k in [2, 4, 6] {
            for i in 0..360 {
                let a = (i as f64 + 0.37).to_radians();
                let (fx, fy) = (3.0 * a.cos(), 3.0 * a.sin());
                let sum: f64 = (0..k).map(|o| window(k, o, fx, fy)).sum();
                assert!((sum - 1.0).abs() < 1e-12, "k {k} at {i} deg: {sum}");
                for o in 0..k {
                    assert!((window(k, o, fx, fy) - window(k, o, -fx, -fy)).abs() < 1e-12);
                }
            }
            let dc: f64 = (0..k).map(|o| window(k, o, 0.0, 0.0)).sum();
            assert!((dc - 1.0).abs() < 1e-12);
        }
        // K = 4: a horizontal frequency (vertical bars) is all channel 0, half height at
        // 22.5 deg, nothing in the orthogonal channel.
        assert_eq!(window(4, 0, 1.0, 0.0), 1.0);
        assert!(
            (window(4, 0, 22.5f64.to_radians().cos(), 22.5f64.to_radians().sin()) - 0.5).abs()
                < 1e-12
        );
        assert_eq!(window(4, 2, 1.0, 0.0), 0.0);
        assert_eq!(window(4, 2, 0.0, 1.0), 1.0);
    }

    #[test]
    fn below_the_lowest_band_the_split_fades_to_isotropic() {
        // An octave below the lowest band centre every channel takes 1 / K; half-way (in log
        // frequency) the oriented share is cos^2(pi / 4) = 1 / 2.
        let top = super::super::bands::LOWEST_CENTRE_CPD;
        for rho in [0.0, 0.1 * top, 0.5 * top] {
            for o in 0..4 {
                assert_eq!(window(4, o, rho, 0.0), 0.25, "rho {rho}");
            }
        }
        let mid = top / 2f64.sqrt();
        assert!((oriented_share(mid) - 0.5).abs() < 1e-12);
        assert!((window(4, 0, mid, 0.0) - (0.5 + 0.5 * 0.25)).abs() < 1e-12);
        assert!((window(4, 2, mid, 0.0) - 0.5 * 0.25).abs() < 1e-12);
        // Monotone from 0 to 1 across the octave.
        let shares: Vec<f64> = (0..=20)
            .map(|i| oriented_share(top * 2f64.powf(-1.0 + i as f64 / 20.0)))
            .collect();
        assert!(shares.windows(2).all(|p| p[0] <= p[1]), "{shares:?}");
        assert_eq!((shares[0], shares[20]), (0.0, 1.0));
    }
}
