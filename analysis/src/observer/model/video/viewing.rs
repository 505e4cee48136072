//! What a video pair's comparison depends on besides its frames: the size and timing of the
//! videos and the viewing, and the constants of the local adaptation and of the CSF's area.

/// Standard deviation of the local adaptation's Gaussian, degrees.
pub const ADAPTATION_SIGMA_DEG: f64 = 0.5;
/// Lowest adaptation luminance, cd/m^2 (below it Weber contrast is not a model of vision).
pub const ADAPTATION_FLOOR: f32 = 1.0;
/// The stimulus area at which the CSF is evaluated, deg^2: ModelFest's field (256 pixels at
/// 120 ppd, 2.133 deg square), the data the pooling was fitted on. stelaCSF's area term is
/// spatial summation; the Minkowski pooling ([`super::super::pooling`]) now sums over the
/// picture, so the CSF keeps the area of the data that fitted that summation instead of the
/// video's (which would count the summation twice on a large video).
pub const CSF_AREA_DEG2: f64 = (256.0 / 120.0) * (256.0 / 120.0);

/// The size and timing of a video pair, and the viewing conditions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing {
    pub width: usize,
    pub height: usize,
    pub frames: usize,
    pub fps: f64,
    pub pixels_per_degree: f64,
    /// The reference's mean luminance over all pixels and frames (the CSF's adaptation level).
    pub mean_luminance: f64,
}
