//! An analytic sky with a sun disc, written as a lat-long (equirectangular) Radiance `.hdr`
//! map: the stand-in for the thesis's HDR environment maps. Values are linear radiance; the
//! sky is about 0.2-1.5 and the sun disc thousands, so reflections of the sun saturate and
//! streak under motion blur as in the thesis's Spheres scene.
//!
//! Mapping (y up): column u in [0, 1) is the azimuth phi = 2 pi (u - 0.5) measured from -z
//! towards +x, row v in [0, 1] the polar angle theta = pi v from +y, so the direction of
//! (u, v) is (sin theta sin phi, cos theta, -sin theta cos phi).

use crate::hash;
use anyhow::{Context, Result};
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;

/// Parameters of the sky.
#[derive(Clone, Debug, PartialEq)]
pub struct SkyParams {
    pub width: u32,
    pub height: u32,
    /// Sun elevation above the horizon and azimuth (mapping above), degrees.
    pub sun_elevation_deg: f32,
    pub sun_azimuth_deg: f32,
    /// Angular radius of the disc, degrees (the real sun is 0.27; larger reads better at
    /// stimulus resolutions).
    pub sun_radius_deg: f32,
    /// Radiance of the disc.
    pub sun_radiance: Vec3,
    pub zenith: Vec3,
    pub horizon: Vec3,
    pub ground: Vec3,
    /// Fraction of the sky covered by clouds, 0..1.
    pub cloud_cover: f32,
    /// Seed of the cloud and ground texture.
    pub seed: u64,
}

impl SkyParams {
    /// Daylight sky with scattered clouds, for the `plane` scene.
    pub fn day() -> Self {
        Self {
            width: 1024,
            height: 512,
            sun_elevation_deg: 38.0,
            sun_azimuth_deg: 35.0,
            sun_radius_deg: 1.5,
            sun_radiance: Vec3::new(1000.0, 950.0, 850.0),
            zenith: Vec3::new(0.12, 0.25, 0.7),
            horizon: Vec3::new(0.75, 0.85, 1.0),
            ground: Vec3::new(0.18, 0.16, 0.13),
            cloud_cover: 0.35,
            seed: 1,
        }
    }

    /// Low, very bright sun over a clear sky, for the `spheres` scene.
    pub fn bright_sun() -> Self {
        Self {
            sun_elevation_deg: 22.0,
            sun_azimuth_deg: -20.0,
            sun_radius_deg: 2.0,
            sun_radiance: Vec3::new(5000.0, 4500.0, 3800.0),
            zenith: Vec3::new(0.08, 0.18, 0.55),
            horizon: Vec3::new(0.9, 0.8, 0.7),
            ground: Vec3::new(0.12, 0.12, 0.12),
            cloud_cover: 0.15,
            seed: 2,
            ..Self::day()
        }
    }
}

/// The unit direction of lat-long coordinates (u, v).
pub fn direction(u: f32, v: f32) -> Vec3 {
    let phi = 2.0 * PI * (u - 0.5);
    let theta = PI * v;
    Vec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

fn sun_direction(p: &SkyParams) -> Vec3 {
    let (e, a) = (
        p.sun_elevation_deg.to_radians(),
        p.sun_azimuth_deg.to_radians(),
    );
    Vec3::new(e.cos() * a.sin(), e.sin(), -e.cos() * a.cos())
}

/// Smooth value noise in 2D from the counter hash (no sequential generator).
fn value_noise(seed: u64, x: f32, y: f32) -> f32 {
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let s = |t: f32| t * t * (3.0 - 2.0 * t);
    let at = |dx: f32, dy: f32| {
        let (i, j) = ((x0 + dx) as i64, (y0 + dy) as i64);
        hash::unit_f32(hash::hash(seed, &[i as u64, j as u64]))
    };
    let top = at(0.0, 0.0) + (at(1.0, 0.0) - at(0.0, 0.0)) * s(fx);
    let bottom = at(0.0, 1.0) + (at(1.0, 1.0) - at(0.0, 1.0)) * s(fx);
    top + (bottom - top) * s(fy)
}

fn fractal(seed: u64, x: f32, y: f32) -> f32 {
    (0..4)
        .map(|o| {
            let f = (1 << o) as f32;
            value_noise(seed.wrapping_add(o), x * f, y * f) / f
        })
        .sum::<f32>()
        / 1.875
}

/// Radiance seen in direction `d`.
pub fn radiance(p: &SkyParams, d: Vec3) -> Vec3 {
    let sun = sun_direction(p);
    let cos_angle = d.dot(sun).clamp(-1.0, 1.0);
    let angle = cos_angle.acos();
    if d.y < 0.0 {
        // Ground: a darker textured plane fading to haze at the horizon.
        let t = (-d.y).max(1e-3);
        let g = fractal(p.seed ^ 0x6a, 40.0 * d.x / t * 0.05, 40.0 * d.z / t * 0.05);
        let haze = (-12.0 * t).exp();
        return p.ground * (0.6 + 0.8 * g) * (1.0 - haze) + p.horizon * 0.6 * haze;
    }
    let elev = d.y;
    let w = (1.0 - elev).powi(4);
    let mut c = p.zenith * (1.0 - w) + p.horizon * w;
    // Aureole around the sun.
    c += p.sun_radiance * 2e-4 * (-angle / 0.12).exp();
    // Clouds on a plane above: coverage from thresholded fractal noise.
    let t = elev.max(0.02);
    let n = fractal(p.seed, 1.5 * d.x / t, 1.5 * d.z / t);
    let cover = ((n - (1.0 - p.cloud_cover)) / 0.15).clamp(0.0, 1.0) * (elev * 8.0).min(1.0);
    let lit = 0.9 + 0.8 * (cos_angle * 0.5 + 0.5);
    c = c * (1.0 - cover) + Vec3::splat(lit) * cover;
    if angle < p.sun_radius_deg.to_radians() {
        c = p.sun_radiance;
    }
    c
}

/// Render the sky map, rows from the zenith down, each texel averaged over 2x2 sub-samples.
pub fn render(p: &SkyParams) -> Vec<[f32; 3]> {
    let (w, h) = (p.width as usize, p.height as usize);
    let mut px = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            for (sx, sy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                let d = direction((x as f32 + sx) / w as f32, (y as f32 + sy) / h as f32);
                sum += radiance(p, d);
            }
            let c = sum / 4.0;
            px.push([c.x, c.y, c.z]);
        }
    }
    px
}

/// Encode the sky as Radiance RGBE (`.hdr`) bytes.
pub fn hdr_bytes(p: &SkyParams) -> Result<Vec<u8>> {
    let pixels: Vec<image::Rgb<f32>> = render(p).into_iter().map(image::Rgb).collect();
    let mut out = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut out)
        .encode(&pixels, p.width as usize, p.height as usize)
        .context("cannot encode sky as .hdr")?;
    Ok(out)
}

/// Write the sky to `path` (`.hdr`), atomically.
pub fn write_hdr(p: &SkyParams, path: &Path) -> Result<()> {
    crate::atomic::write_atomic(path, &hdr_bytes(p)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small(mut p: SkyParams) -> SkyParams {
        p.width = 128;
        p.height = 64;
        p
    }

    #[test]
    fn mapping_puts_zenith_on_top_and_minus_z_in_the_middle() {
        assert!((direction(0.3, 0.0) - Vec3::Y).length() < 1e-6);
        assert!((direction(0.5, 0.5) - Vec3::NEG_Z).length() < 1e-6);
        assert!((direction(0.75, 0.5) - Vec3::X).length() < 1e-6);
    }

    #[test]
    fn sun_is_far_above_one_and_sky_is_not() {
        for p in [SkyParams::day(), SkyParams::bright_sun()] {
            let sun = radiance(&p, sun_direction(&p));
            assert!(sun.min_element() > 500.0, "{sun}");
            let away = radiance(&p, -sun_direction(&p));
            assert!(away.max_element() < 2.0, "{away}");
        }
    }

    #[test]
    fn map_is_finite_and_holds_the_sun() {
        let p = small(SkyParams::bright_sun());
        let px = render(&p);
        assert_eq!(px.len(), 128 * 64);
        assert!(px.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        let max = px.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
        assert!(max > 100.0, "brightest texel {max}");
    }

    #[test]
    fn hdr_file_decodes_to_the_same_size() {
        let p = small(SkyParams::day());
        let bytes = hdr_bytes(&p).unwrap();
        let img = image::load_from_memory(&bytes).unwrap();
        assert_eq!((img.width(), img.height()), (128, 64));
    }
}
