//! How a stimulus samples its pixels: the `settings.sampling` block of a scene, the job's
//! choices laid over it, and the defaults that reproduce the thesis.
//!
//! The settings beyond point set, spp and time filter are optional: unset means "the scene's
//! value, else the thesis default" (see [`SamplingConfig::over`]), so a job can change one of
//! them for every stimulus without knowing the others, and older files keep their meaning.

pub use crate::condition::SpatialFilter;
use crate::condition::{PointSetKind, TimeFilter};
use serde::{Deserialize, Serialize};

/// Thesis default: Gaussian spatial warp with a standard deviation of half a pixel (Figure 16
/// divides the Box-Muller output by 2).
pub const DEFAULT_SPATIAL_SIGMA: f64 = 0.5;

/// How a stimulus samples its pixels. Lives in a scene's `settings.sampling` block; a job sets
/// point set, spp and time filter per stimulus and may set the others for every stimulus.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SamplingConfig {
    /// Point set name: `random`, `stratified`, `hammersley`, `poisson`, `sobol`, `halton`.
    #[serde(default = "default_point_set")]
    pub point_set: PointSetKind,
    /// Samples per pixel.
    #[serde(default = "default_spp")]
    pub spp: u32,
    /// Time filter name: `box`, `truncated_box`, `triangle`.
    #[serde(default = "default_time_filter")]
    pub time_filter: TimeFilter,
    /// Spatial filter (importance-sampled by warping): `gaussian` (default) or `box`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spatial_filter: Option<SpatialFilter>,
    /// Standard deviation of the Gaussian spatial filter in pixels (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spatial_sigma: Option<f64>,
    /// How the samples split between space and time (default `joint`: one 3D set).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<Density>,
    /// How often the point set is regenerated: `frame` (default) or `sequence`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_set_scope: Option<Scope>,
    /// How often each pixel's shift is redrawn: `sequence` (default) or `frame`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift_scope: Option<Scope>,
    /// How each pixel gets its own copy of the set: `shift` (default, the thesis's toroidal
    /// shift) or `scramble` (a per-pixel randomization that keeps the set's strata).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub randomization: Option<Randomization>,
}

/// The optional settings of [`SamplingConfig`] on their own: what a job's
/// `overrides.sampling` may set for every stimulus. (The fields are repeated rather than
/// flattened into `SamplingConfig`: serde cannot flatten into a struct that refuses unknown
/// fields, and a misspelt setting must be an error, not silently ignored.)
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SamplingOptions {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spatial_filter: Option<SpatialFilter>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spatial_sigma: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<Density>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_set_scope: Option<Scope>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift_scope: Option<Scope>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub randomization: Option<Randomization>,
}

/// How a pixel turns the frame's point set into its own samples (docs/sampling.md,
/// "Per-pixel randomization").
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Randomization {
    /// The thesis's Cranley-Patterson rotation (Figure 14): add the pixel's offset, wrap.
    Shift,
    /// A per-pixel scramble that keeps the set's strata: Owen scrambling for Sobol, Hammersley
    /// and Halton, a fresh jitter per stratum for stratified, fresh points for random; Poisson
    /// has no strata and keeps the shift ([`crate::sampling::scramble`]).
    Scramble,
}

// The names used in scene, job and text files.
crate::named!(Randomization, "randomization", [Shift => "shift", Scramble => "scramble"]);

/// How many distinct positions each axis gets.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Density {
    /// One point set of `spp` points over the (u, v, t) cube: the thesis's equal density.
    Joint,
    /// `spp / K` spatial points x K times: the product of a 2D set and a 1D set.
    Temporal(u32),
    /// K spatial points x `spp / K` times: the product of a 2D set and a 1D set.
    Spatial(u32),
}

/// How long a random choice lasts.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Scope {
    /// Drawn anew for every frame.
    Frame,
    /// Drawn once for the whole stimulus.
    Sequence,
}

fn default_point_set() -> PointSetKind {
    PointSetKind::Random
}
fn default_spp() -> u32 {
    16
}
fn default_time_filter() -> TimeFilter {
    TimeFilter::Box
}

impl Default for SamplingConfig {
    fn default() -> Self {
        Self {
            point_set: default_point_set(),
            spp: default_spp(),
            time_filter: default_time_filter(),
            spatial_filter: None,
            spatial_sigma: None,
            density: None,
            point_set_scope: None,
            shift_scope: None,
            randomization: None,
        }
    }
}

impl SamplingConfig {
    /// This stimulus's choices laid over a scene's `settings.sampling` block: point set, spp
    /// and time filter from `self`; every optional setting from `self` where set, else from
    /// `scene` (else the default).
    pub fn over(&self, scene: &SamplingConfig) -> SamplingConfig {
        SamplingConfig {
            point_set: self.point_set,
            spp: self.spp,
            time_filter: self.time_filter,
            ..scene.clone()
        }
        .with_options(&self.options())
    }

    /// The optional settings of this config.
    pub fn options(&self) -> SamplingOptions {
        SamplingOptions {
            spatial_filter: self.spatial_filter,
            spatial_sigma: self.spatial_sigma,
            density: self.density,
            point_set_scope: self.point_set_scope,
            shift_scope: self.shift_scope,
            randomization: self.randomization,
        }
    }

    /// This config with every setting that `options` sets replaced.
    pub fn with_options(mut self, o: &SamplingOptions) -> SamplingConfig {
        self.spatial_filter = o.spatial_filter.or(self.spatial_filter);
        self.spatial_sigma = o.spatial_sigma.or(self.spatial_sigma);
        self.density = o.density.or(self.density);
        self.point_set_scope = o.point_set_scope.or(self.point_set_scope);
        self.shift_scope = o.shift_scope.or(self.shift_scope);
        self.randomization = o.randomization.or(self.randomization);
        self
    }

    /// The spatial filter in effect (default Gaussian, as in the thesis).
    pub fn spatial_filter(&self) -> SpatialFilter {
        self.spatial_filter.unwrap_or(SpatialFilter::Gaussian)
    }

    /// The Gaussian's standard deviation in pixels in effect.
    pub fn spatial_sigma(&self) -> f64 {
        self.spatial_sigma.unwrap_or(DEFAULT_SPATIAL_SIGMA)
    }

    /// The density split in effect (default one joint 3D set).
    pub fn density(&self) -> Density {
        self.density.unwrap_or(Density::Joint)
    }

    /// How often the point set is regenerated (default every frame: thesis Chapter III).
    pub fn point_set_scope(&self) -> Scope {
        self.point_set_scope.unwrap_or(Scope::Frame)
    }

    /// How often pixel shifts are redrawn (default once per stimulus; see docs/sampling.md).
    pub fn shift_scope(&self) -> Scope {
        self.shift_scope.unwrap_or(Scope::Sequence)
    }

    /// How each pixel randomizes the set (default the thesis's shift).
    pub fn randomization(&self) -> Randomization {
        self.randomization.unwrap_or(Randomization::Shift)
    }
}

impl SamplingOptions {
    /// Whether nothing is set.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn old_files_parse_and_get_the_thesis_defaults() {
        let c: SamplingConfig =
            serde_json::from_str(r#"{"point_set": "hammersley", "spp": 64}"#).unwrap();
        assert_eq!(c.time_filter, TimeFilter::Box);
        assert_eq!(c.spatial_filter(), SpatialFilter::Gaussian);
        assert_eq!(c.spatial_sigma(), 0.5);
        assert_eq!(c.density(), Density::Joint);
        assert_eq!(c.point_set_scope(), Scope::Frame);
        assert_eq!(c.shift_scope(), Scope::Sequence);
        assert_eq!(c.randomization(), Randomization::Shift);
        // Unset options are not written, so stamps of older configs stay byte-identical.
        let text = serde_json::to_string(&c).unwrap();
        assert_eq!(
            text,
            r#"{"point_set":"hammersley","spp":64,"time_filter":"box"}"#
        );
    }

    #[test]
    fn every_setting_round_trips_and_typos_are_refused() {
        let text = r#"{"point_set": "poisson", "spp": 512, "time_filter": "triangle",
            "spatial_filter": "box", "spatial_sigma": 0.7, "density": {"temporal": 8},
            "point_set_scope": "sequence", "shift_scope": "frame", "randomization": "scramble"}"#;
        let c: SamplingConfig = serde_json::from_str(text).unwrap();
        assert_eq!(c.density(), Density::Temporal(8));
        assert_eq!(c.shift_scope(), Scope::Frame);
        assert_eq!(c.randomization(), Randomization::Scramble);
        let back: SamplingConfig =
            serde_json::from_str(&serde_json::to_string(&c).unwrap()).unwrap();
        assert_eq!(back, c);
        let e = serde_json::from_str::<SamplingConfig>(r#"{"shfit_scope": "frame"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("shfit_scope"), "{e}");
        let e = serde_json::from_str::<SamplingConfig>(r#"{"spatial_filter": "gauss"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("gaussian"), "{e}");
        let e = serde_json::from_str::<SamplingConfig>(r#"{"randomization": "owen"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("shift") && e.contains("scramble"), "{e}");
    }

    #[test]
    fn a_stimulus_lays_its_choices_over_the_scene_block() {
        let scene = SamplingConfig {
            point_set: PointSetKind::Sobol,
            spp: 4,
            time_filter: TimeFilter::Triangle,
            spatial_sigma: Some(0.8),
            shift_scope: Some(Scope::Frame),
            randomization: Some(Randomization::Scramble),
            ..Default::default()
        };
        let job = SamplingConfig {
            point_set: PointSetKind::Hammersley,
            spp: 27,
            time_filter: TimeFilter::TruncatedBox,
            spatial_filter: Some(SpatialFilter::Box),
            shift_scope: Some(Scope::Sequence),
            ..Default::default()
        };
        let c = job.over(&scene);
        assert_eq!((c.point_set, c.spp), (PointSetKind::Hammersley, 27));
        assert_eq!(c.time_filter, TimeFilter::TruncatedBox);
        assert_eq!(c.spatial_filter(), SpatialFilter::Box, "job wins where set");
        assert_eq!(c.shift_scope(), Scope::Sequence, "job wins where set");
        assert_eq!(c.spatial_sigma(), 0.8, "scene where the job is silent");
        assert_eq!(c.density(), Density::Joint, "default where both are");
        // A scene's randomization reaches the stimuli of a job that leaves it unset (how a
        // study puts shift and scramble in one job: docs/sampling.md), and a job's wins.
        assert_eq!(c.randomization(), Randomization::Scramble);
        let shift = SamplingConfig {
            randomization: Some(Randomization::Shift),
            ..job
        };
        assert_eq!(shift.over(&scene).randomization(), Randomization::Shift);
    }
}
