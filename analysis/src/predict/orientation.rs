//! Orientation channels for the side-by-side stage's masking: each spatial band split into K
//! orientation channels, so that a masker of one orientation masks mostly its own (Meese et
//! al. 2007's cross-orientation masking, [`super::meese`]: an orthogonal grating of 45%
//! contrast raises a grating's threshold about 3x at 1 c/deg and not at all at 7 c/deg, where
//! masking pooled over every orientation of the band raises it about 50x).
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
/// meese2007`: w = 0, the grid's least error, 4.55 dB; leave-one-out 5.27 dB).
pub const COMMITTED: OrientationMasking = OrientationMasking {
    orientations: ORIENTATIONS,
    cross_weight: 0.0,
};

/// W_o at frequency (fx, fy) of a split into `k` orientations.
pub fn window(k: usize, o: usize, fx: f64, fy: f64) -> f64 {
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
}
