//! An analytic sky with a sun disc, mountains and ground, written as a lat-long
//! (equirectangular) Radiance `.hdr` map: the stand-in for the thesis's `CedarCity.hdr`. Values
//! are linear radiance: the sky about 0.1-1, clouds up to 1.7, the sun's glow up to 2 and its
//! disc 60, so one sample that sees the sun in a reflection is a speckle far above white, yet
//! a 512-spp stimulus resolves it (`scenes/README.md`, "CedarCity.hdr").
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
    /// Angular radius of the disc, degrees (the real sun's is 0.27).
    pub sun_radius_deg: f32,
    /// Radiance of the disc.
    pub sun_radiance: Vec3,
    /// Glow around the disc: radiance `aureole * exp(-angle / aureole_width)` (radians).
    pub aureole: Vec3,
    pub aureole_width: f32,
    pub zenith: Vec3,
    pub horizon: Vec3,
    /// The ground below the horizon, and the colour of scattered scrub on it.
    pub ground: Vec3,
    pub scrub: Vec3,
    /// Fraction of the sky covered by clouds, 0..1.
    pub cloud_cover: f32,
    /// Mountains along the horizon, if any.
    pub ridge: Option<Ridge>,
    /// Seed of the cloud, ridge and ground texture.
    pub seed: u64,
}

/// A mountain ridge around the horizon: its elevation varies with azimuth between `low_deg`
/// and `high_deg`, highest towards `peak_azimuth_deg`; the rock is banded in strata.
#[derive(Clone, Debug, PartialEq)]
pub struct Ridge {
    pub low_deg: f32,
    pub high_deg: f32,
    pub peak_azimuth_deg: f32,
    pub rock: Vec3,
    /// Share of the horizon colour mixed in (distance haze), 0..1.
    pub haze: f32,
}

impl SkyParams {
    /// The stand-in for the thesis's `CedarCity.hdr`: a clear high-desert afternoon sky over
    /// Cedar City, Utah — deep blue zenith, a few cumulus, red-rock cliffs along the horizon
    /// (highest to the east, the Markagunt Plateau's edge), red desert floor with sage scrub —
    /// and the sun. `scenes/README.md` gives the reasons for the sun's radiance and size.
    pub fn cedar_city() -> Self {
        Self {
            width: 2048,
            height: 1024,
            sun_elevation_deg: 40.0,
            sun_azimuth_deg: 160.0,
            sun_radius_deg: 1.5,
            sun_radiance: Vec3::new(60.0, 57.0, 52.0),
            aureole: Vec3::new(2.0, 1.9, 1.7),
            aureole_width: 0.12,
            zenith: Vec3::new(0.09, 0.2, 0.62),
            horizon: Vec3::new(0.62, 0.74, 0.92),
            ground: Vec3::new(0.34, 0.19, 0.11),
            scrub: Vec3::new(0.13, 0.15, 0.09),
            cloud_cover: 0.3,
            ridge: Some(Ridge {
                low_deg: 1.5,
                high_deg: 12.0,
                peak_azimuth_deg: 90.0,
                rock: Vec3::new(0.62, 0.24, 0.1),
                haze: 0.15,
            }),
            seed: 1,
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

/// Periodic 1D value noise along the horizon: `turns` in [0, 1) around it, `f` cells per turn.
fn horizon_noise(seed: u64, turns: f32, f: u32) -> f32 {
    let x = turns.rem_euclid(1.0) * f as f32;
    let (i, t) = (x.floor() as u32, x.fract());
    let at = |k: u32| hash::unit_f32(hash::hash(seed, &[f as u64, (k % f) as u64]));
    let s = t * t * (3.0 - 2.0 * t);
    at(i) + (at(i + 1) - at(i)) * s
}

/// Elevation of the ridge's crest at azimuth `phi` (radians, mapping above), radians.
fn ridge_crest(p: &SkyParams, r: &Ridge, phi: f32) -> f32 {
    let turns = phi / (2.0 * PI);
    let n = (0..6)
        .map(|o| horizon_noise(p.seed ^ 0x51d9e, turns, 5 << o) / (1 << o) as f32)
        .sum::<f32>()
        / 1.97;
    // Highest towards the peak azimuth, lowest opposite it; flat-topped where the noise is
    // high (plateaus edged by cliffs, as the Markagunt Plateau's rim).
    let toward = 0.5 + 0.5 * (phi - r.peak_azimuth_deg.to_radians()).cos();
    let shape = (2.0 * n - 0.4).clamp(0.0, 1.0);
    let h = r.low_deg + (r.high_deg - r.low_deg) * shape * (0.25 + 0.75 * toward);
    h.to_radians()
}

/// Radiance seen in direction `d`.
pub fn radiance(p: &SkyParams, d: Vec3) -> Vec3 {
    let sun = sun_direction(p);
    let cos_angle = d.dot(sun).clamp(-1.0, 1.0);
    let angle = cos_angle.acos();
    if d.y < 0.0 {
        // Ground: desert floor with patches of scrub, fading to haze at the horizon.
        let t = (-d.y).max(1e-3);
        let (gx, gz) = (6.0 * d.x / t, 6.0 * d.z / t);
        let g = fractal(p.seed ^ 0x6a, gx, gz);
        let scrub = ((fractal(p.seed ^ 0x5c, 3.0 * gx, 3.0 * gz) - 0.62) / 0.08).clamp(0.0, 1.0);
        let floor = p.ground * (0.6 + 0.8 * g) * (1.0 - scrub) + p.scrub * scrub;
        // Haze between the floor's colour and the horizon's.
        let haze = (-20.0 * t).exp();
        return floor * (1.0 - haze) + (p.horizon * 0.35 + p.ground * 0.6) * haze;
    }
    let elev = d.y.asin();
    if let Some(r) = &p.ridge {
        let phi = d.x.atan2(-d.z);
        let crest = ridge_crest(p, r, phi);
        if elev < crest {
            // Red rock in strata, lit brighter towards the sun's side, hazed by distance.
            let band = fractal(p.seed ^ 0x7b, 8.0 * phi, 120.0 * elev);
            let strata = 0.85 + 0.15 * (elev * 180.0 + 6.0 * band).sin();
            let lit = 0.7 + 0.3 * (phi - p.sun_azimuth_deg.to_radians()).cos();
            let rock = r.rock * strata * lit * (0.8 + 0.4 * band);
            return rock * (1.0 - r.haze) + p.horizon * r.haze;
        }
    }
    let w = (1.0 - d.y).powi(4);
    let mut c = p.zenith * (1.0 - w) + p.horizon * w;
    c += p.aureole * (-angle / p.aureole_width).exp();
    // Clouds on a plane above: coverage from thresholded fractal noise.
    let t = d.y.max(0.02);
    let n = fractal(p.seed, 0.8 * d.x / t, 0.8 * d.z / t);
    let cover = ((n - (1.0 - p.cloud_cover)) / 0.15).clamp(0.0, 1.0) * (d.y * 8.0).min(1.0);
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
        let p = SkyParams::cedar_city();
        let sun = radiance(&p, sun_direction(&p));
        assert_eq!(sun, p.sun_radiance);
        // Opposite the sun (below the horizon) and at the zenith: far dimmer than the disc.
        for d in [-sun_direction(&p), Vec3::Y] {
            let c = radiance(&p, d);
            assert!(c.max_element() < 2.0, "{d}: {c}");
        }
    }

    #[test]
    fn map_is_finite_and_holds_the_sun() {
        let p = small(SkyParams::cedar_city());
        let px = render(&p);
        assert_eq!(px.len(), 128 * 64);
        assert!(px.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        let max = px.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
        assert!(max > 20.0, "brightest texel {max}");
    }

    #[test]
    fn hdr_file_decodes_to_the_same_size() {
        let p = small(SkyParams::cedar_city());
        let bytes = hdr_bytes(&p).unwrap();
        let img = image::load_from_memory(&bytes).unwrap();
        assert_eq!((img.width(), img.height()), (128, 64));
    }
}
