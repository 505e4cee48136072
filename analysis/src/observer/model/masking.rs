//! Contrast masking by the reference: a difference is harder to see on top of visible
//! structure in the same spatial band and temporal channel. The threshold elevation follows the
//! threshold-versus-contrast law of Legge & Foley (1980, "Contrast masking in human vision",
//! JOSA 70(12)): no masking while the masker is below its own detection threshold, a power law
//! above it,
//!
//! ```text
//! T_e = max(1, |m|^epsilon),   epsilon = 0.7,
//! ```
//!
//! with m the reference's CSF-weighted band contrast at the same place, time, band and channel
//! (so |m| = 1 is the masker at its threshold) and the exponent of Watson's DCTune (1993,
//! "DCTune: a technique for visual optimization of DCT quantization matrices", SID Digest),
//! which took it from Legge & Foley. The masker is the reference alone: test and reference
//! differ only by noise, which is small where the prediction matters (near the JND).
//! Not modelled: masking across bands or orientations, phase uncertainty (m is the band
//! signal's value, which crosses zero inside a grating's period), facilitation at low masker
//! contrast (the "dipper").

/// The masking exponent epsilon.
pub const EPSILON: f32 = 0.7;

/// Threshold elevation of a masker of CSF-weighted contrast `m`.
pub fn threshold_elevation(m: f32) -> f32 {
    let a = m.abs();
    if a <= 1.0 { 1.0 } else { a.powf(EPSILON) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_masking_below_threshold_power_law_above() {
        assert_eq!(threshold_elevation(0.0), 1.0);
        assert_eq!(threshold_elevation(-0.9), 1.0);
        assert!((threshold_elevation(10.0) - 10f32.powf(0.7)).abs() < 1e-5);
        assert!((threshold_elevation(-100.0) - 100f32.powf(0.7)).abs() < 1e-3);
    }
}
