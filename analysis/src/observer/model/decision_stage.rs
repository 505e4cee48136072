//! The decision stage: how the observer compares a test video with its reference, the last
//! stage before the pooling over space ([`super::video`]).
//!
//! - [`DecisionStage::Difference`]: the difference T - R at each place, masked by the
//!   reference's contrast ([`super::masking`]): a flicker or overlay comparison, or
//!   ModelFest's 2IFC against a blank field (what the model was fitted with).
//! - [`DecisionStage::SideBySide`]: the two videos side by side or in sequence, as the suite's
//!   trials show them, so that they cannot be subtracted place by place: each video's local
//!   contrast amplitude per band and orientation channel ([`super::orientation`]), masked by
//!   the channel's local energy through the Weber-like transducer of [`super::transducer`],
//!   and the two videos' amplitudes compared channel by channel (docs/predict.md, "Decision
//!   stages"). The scene's content and the noise both raise the energy, so each masks the
//!   other within its channel. Its settings are a [`SideBySide`].
//!
//! The names are the command line's (`blurlab predict --decision`) and the report's.

use super::orientation::{self, OrientationMasking};
use super::pooling::FITTED;
use super::proportion_correct::{CRITERION, DEFAULT_K, two_ifc_d_prime_for};
use super::transducer::knee;

/// How the observer compares a test video with its reference (see the module's text).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DecisionStage {
    /// T - R at each place (the default of [`super::video::Filters::new`]).
    #[default]
    Difference,
    /// Each video's local amplitudes compared, with the committed [`SideBySide`].
    SideBySide,
}

renderer::named!(DecisionStage, "decision stage", [
    Difference => "difference",
    SideBySide => "side-by-side",
]);

/// The side-by-side stage's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideBySide {
    /// beta, the space exponent of the local energies compared (the pooling's).
    pub space: f64,
    /// a0, the transducer's knee (infinite: no compression, the local energies compared as
    /// they are).
    pub knee: f32,
    /// The orientation channels the videos are compared in; `None`: each band's amplitudes
    /// pooled over orientation before the comparison, the stage as first built.
    pub orientation: Option<OrientationMasking>,
}

impl SideBySide {
    /// The committed stage at space exponent `space`: the knee is the detection threshold of
    /// ModelFest's fit ([`knee`] with [`DEFAULT_K`] and the fitted aperture), and the videos
    /// are compared per orientation channel ([`orientation::COMMITTED`]).
    pub fn committed(space: f64) -> Self {
        let d84 = two_ifc_d_prime_for(CRITERION).expect("the criterion is inside (0.5, 1)");
        Self {
            space,
            knee: knee(d84, DEFAULT_K, FITTED.aperture_deg, space),
            orientation: Some(orientation::COMMITTED),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stages_are_named_as_the_command_line_spells_them() {
        assert_eq!(DecisionStage::SideBySide.name(), "side-by-side");
        assert_eq!(
            "difference".parse::<DecisionStage>().unwrap(),
            DecisionStage::Difference
        );
        let e = DecisionStage::by_name("overlay").unwrap_err().to_string();
        assert!(e.contains("difference, side-by-side"), "{e}");
    }

    #[test]
    fn the_committed_knee_is_the_detection_threshold() {
        // a0 = (d'_84 / k) (beta / (2 pi s^2))^(1/beta) at the fitted pooling.
        let s = SideBySide::committed(FITTED.space);
        let d84 = two_ifc_d_prime_for(CRITERION).unwrap();
        let area = 2.0 * std::f64::consts::PI * 0.25 / FITTED.space;
        let want = d84 / DEFAULT_K / area.powf(1.0 / FITTED.space);
        assert!((s.knee as f64 / want - 1.0).abs() < 1e-6, "{}", s.knee);
        assert_eq!(s.orientation, Some(orientation::COMMITTED));
    }
}
