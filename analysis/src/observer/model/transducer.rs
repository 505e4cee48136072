//! The discrimination of suprathreshold contrast energy: how much a local contrast amplitude
//! must change to be seen, given the amplitude already there. The side-by-side stage
//! ([`super::decision_stage`]) passes each video's local amplitude a (the Minkowski norm of
//! its CSF-weighted band contrasts over a Gaussian neighbourhood, [`super::video`]) through a
//! transducer R and compares R(a_test) with R(a_reference).
//!
//! The increment threshold of a pedestal grows with the pedestal once the pedestal is visible:
//! Legge & Foley (1980, "Contrast masking in human vision", JOSA 70(12):1458-1471) measured
//! the threshold-versus-contrast function's rising limb as a power of the masker contrast with
//! exponent about 0.6-0.7 (Weber's law is exponent 1; Bird, Henning & Wichmann 2002, JOSA A
//! 19(7):1267, could not reject it); Foley (1994, JOSA A 11(6):1710) fitted the same limb with
//! the transducer C^p / (z + C^q), p - q = 0.4 (slope 1 - (p - q) / p = 0.6-0.7 for p = 2-2.4).
//! Here the slope is the masking exponent of [`super::masking::EPSILON`] (0.7), the value
//! DCTune (Watson 1993) took from Legge & Foley, and the transducer is the integral of the
//! inverse of that threshold-versus-contrast law:
//!
//! ```text
//! R(a) = a                                              for a <= a0,
//! R(a) = a0 (1 + ((a / a0)^(1 - eps) - 1) / (1 - eps))    above,
//! ```
//!
//! so dR/da = min(1, (a / a0)^-eps): a just-visible increment Delta a grows as a^eps above a0.
//! Below a0 it is the identity, so against a blank field (a_reference = 0) the stage is
//! detection, as fitted to ModelFest. The knee a0 is not a new free parameter: it is the local
//! amplitude of a field-filling pattern at its detection threshold ([`knee`]), where Legge &
//! Foley's masking functions leave the detection threshold (their rising limb extrapolates
//! through a threshold-contrast pedestal with a threshold increment). Not modelled: the dipper
//! (facilitation by pedestals near threshold), which would need an accelerating transducer
//! below a0 and so break the reduction to detection.

use super::masking::EPSILON;

/// R(a) with knee `a0` (see the module's text).
pub fn respond(a: f32, a0: f32) -> f32 {
    if a <= a0 {
        return a;
    }
    let e = 1.0 - EPSILON;
    a0 * (1.0 + ((a / a0).powf(e) - 1.0) / e)
}

/// The knee a0: the local amplitude of a pattern filling the field at its detection
/// threshold, a0 = (d'_84 / k) (beta / (2 pi s^2))^(1/beta). A uniform field of local
/// amplitude a under the pooling's Gaussian aperture of sd s (deg) pools to
/// Q^beta = a^beta 2 pi s^2 / beta, so at ModelFest's threshold Q = d'_84 / k its a is a0; a
/// smaller pattern at threshold has a smaller local amplitude (the stage's local mean has
/// the aperture's sd, and for a centred disc the ratio a^beta / Q^beta grows with the disc to
/// the uniform field's). `k` the sensitivity constant, `d84` the d' at ModelFest's
/// criterion, `beta` the space exponent.
pub fn knee(d84: f64, k: f64, aperture_deg: f64, beta: f64) -> f32 {
    let area = 2.0 * std::f64::consts::PI * aperture_deg * aperture_deg / beta;
    (d84 / (k * area.powf(1.0 / beta))) as f32
}

/// dR/da of [`respond`], the gain of a local amplitude `a`: 1 up to the knee, (a / a0)^-eps
/// above.
pub fn gain(a: f32, a0: f32) -> f32 {
    if a <= a0 {
        1.0
    } else {
        (a / a0).powf(-EPSILON)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_below_the_knee_power_law_above() {
        for a in [0.0, 0.1, 0.28, 0.3] {
            assert_eq!(respond(a, 0.3), a);
        }
        // Continuous at the knee, slope (a / a0)^-eps above: the increment a just-visible step
        // needs grows as a^0.7 (Legge & Foley's rising limb).
        let a0 = 0.3;
        assert!((respond(a0 * (1.0 + 1e-4), a0) - a0).abs() < 1e-4);
        for a in [1.0f32, 10.0, 100.0] {
            let h = a * 1e-3;
            let slope = (respond(a + h, a0) - respond(a - h, a0)) / (2.0 * h);
            let want = (a / a0).powf(-EPSILON);
            assert!((slope / want - 1.0).abs() < 1e-2, "{a}: {slope} vs {want}");
        }
        // Monotone: more contrast never responds less.
        let mut last = -1.0;
        for i in 0..1000 {
            let r = respond(i as f32 * 0.05, a0);
            assert!(r >= last);
            last = r;
        }
    }
}
