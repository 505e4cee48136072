//! The environment map: a lat-long (equirectangular) HDR image seen by every ray that leaves
//! the scene, primary or reflected, looked up with bilinear filtering.
//!
//! A direction's texel coordinates take `atan2` and `acos` from [`crate::math`] (the lanes'
//! polynomials, within 4 ulp of the exact values), not libm's, in the scalar lookup and in
//! the lanes alike: the same bits in both, libm's coordinates to rounding (about 1e-7 of a
//! texel's width).
//!
//! The mapping is the one of [`crate::procedural::sky::direction`]: u = 0.5 looks along -z,
//! u = 0.75 along +x, row 0 is the zenith (+y). Loading sanitises the texels so that no NaN or
//! infinity can reach a frame: NaN becomes 0, values above [`MAX_RADIANCE`] (infinity
//! included) are clamped to it, with a warning naming the file. Negative values (lossy EXR
//! compression leaves some around -0.003; a DWAB-compressed capture held thousands, down to
//! -3894) are counted with the share of the map's energy they carry: clamped to 0 with a
//! warning up to [`MAX_NEGATIVE_SHARE`], refused above it unless the scene says how to treat
//! them (`environment.negatives`, `docs/limits.md`).

mod lanes;
mod texels;

use texels::Texels;

use glam::{Vec3, Vec3A};
use rayon::prelude::*;
use std::f32::consts::PI;
use std::path::Path;

use crate::math;
use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};

/// Largest radiance kept from a map. Real HDR captures peak around 1e5 (the sun; half floats
/// stop at 65504), so this only removes broken values while keeping sums of thousands of
/// samples far from f32 overflow.
pub const MAX_RADIANCE: f32 = 1e6;

/// Largest share of a map's energy (absolute values, weighted by each texel's solid angle) that
/// its negative texels may carry before loading refuses the map, unless the scene sets
/// `environment.negatives`. Compression noise around zero carries orders of magnitude less; a
/// map above 0.1% has lost light in a way that clamping would visibly change (clamping adds
/// that energy to the sky).
pub const MAX_NEGATIVE_SHARE: f64 = 1e-3;

/// How a scene asks negative texels to be treated (`environment.negatives`; absent: by
/// [`MAX_NEGATIVE_SHARE`]).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum NegativeTexels {
    /// Set them to 0 whatever energy they carry (the map gains that energy).
    Clamp,
    /// Refuse a map with any negative texel.
    Refuse,
}

crate::named!(NegativeTexels, "negative texel policy", [Clamp => "clamp", Refuse => "refuse"]);

#[derive(Clone, Debug)]
pub struct Environment {
    width: usize,
    height: usize,
    /// Row-major texels: four bytes each where that is exact, else three floats (`texels`).
    texels: Texels,
    intensity: f32,
    /// cos and sin of the map's turn about +y.
    turn: (f32, f32),
}

/// What sanitising changed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Repairs {
    pub nan: usize,
    pub too_large: usize,
    pub negative: usize,
    /// Share of the map's energy carried by the negative values (see [`MAX_NEGATIVE_SHARE`]).
    pub negative_share: f64,
}

impl Environment {
    /// A map from row-major texels (row 0 at the zenith), sanitised, with what was repaired.
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Vec3>,
        intensity: f32,
        rotation_degrees: f32,
    ) -> (Self, Repairs) {
        let flat = texels.iter().flat_map(|t| t.to_array()).collect();
        Self::from_flat(width, height, flat, intensity, rotation_degrees)
    }

    /// [`Self::new`] from three floats per texel.
    fn from_flat(
        width: usize,
        height: usize,
        mut texels: Vec<f32>,
        intensity: f32,
        rotation_degrees: f32,
    ) -> (Self, Repairs) {
        assert_eq!(texels.len(), 3 * width * height, "texel count");
        // Real maps are clean: one branch-free pass (NaN fails both comparisons) proves it and
        // skips the two slower passes, which would change nothing and find nothing. The pass is
        // shared between the threads: loading is the part of a render they cannot share.
        let clean = texels.par_chunks(1 << 16).all(|part| {
            // A fold over short runs vectorises where `all`'s early exit per texel does not
            // (2.4x faster on a 2048 x 1024 map).
            part.chunks(64).all(|run| {
                run.iter()
                    .fold(true, |ok, c| ok & (0.0..=MAX_RADIANCE).contains(c))
            })
        });
        let repairs = if clean {
            Repairs::default()
        } else {
            let negative_share = negative_share(&texels, width, height);
            Repairs {
                negative_share,
                ..sanitise(&mut texels)
            }
        };
        let r = rotation_degrees.to_radians();
        (
            Self {
                width,
                height,
                texels: Texels::new(texels),
                intensity,
                turn: (r.cos(), r.sin()),
            },
            repairs,
        )
    }

    /// Load a `.hdr` or `.exr` map; the second value is a warning naming the file when broken
    /// values had to be repaired.
    pub fn load(
        path: &Path,
        intensity: f32,
        rotation_degrees: f32,
        negatives: Option<NegativeTexels>,
    ) -> Result<(Self, Option<String>)> {
        let (texels, w, h) = read_texels(path)?;
        if w == 0 || h == 0 {
            bail!("{}: the environment map is empty", path.display());
        }
        let (env, r) = Self::from_flat(w, h, texels, intensity, rotation_degrees);
        check_negatives(path, &r, negatives)?;
        let mut notes = Vec::new();
        if r.nan + r.too_large > 0 {
            notes.push(format!(
                "{} texels held NaN and {} infinity or values above {MAX_RADIANCE:e}; NaN was \
                 replaced by 0 and the others clamped to {MAX_RADIANCE:e}",
                r.nan, r.too_large
            ));
        }
        if r.negative > 0 {
            notes.push(format!(
                "{} negative texel values, carrying {} of the map's energy, were clamped to 0",
                r.negative,
                percent(r.negative_share)
            ));
        }
        let warning =
            (!notes.is_empty()).then(|| format!("{}: {}", path.display(), notes.join("; ")));
        Ok((env, warning))
    }

    /// Radiance arriving along direction `d` (pointing away from the scene, any length).
    #[inline]
    pub fn radiance(&self, d: Vec3A) -> Vec3 {
        let (c, s) = self.turn;
        // Undo the map's turn about +y.
        let x = d.x * c - d.z * s;
        let z = d.x * s + d.z * c;
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            return Vec3::ZERO;
        }
        let u = math::atan2(x, -z) * (0.5 / PI) + 0.5;
        let v = math::acos((d.y / len).clamp(-1.0, 1.0)) * (1.0 / PI);
        self.bilinear(u, v) * self.intensity
    }

    /// Bilinear lookup at texture coordinates (u wraps around, v clamps at the poles).
    fn bilinear(&self, u: f32, v: f32) -> Vec3 {
        let fx = u * self.width as f32 - 0.5;
        let fy = (v * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (floor(fx), floor(fy));
        let (ax, ay) = (fx - x0, fy - y0);
        let col = |x: i64| wrap_column(x, self.width);
        let (c0, c1) = (col(x0 as i64), col(x0 as i64 + 1));
        let r0 = y0 as usize;
        let r1 = (r0 + 1).min(self.height - 1);
        let at = |r: usize, c: usize| self.texels.get(r * self.width + c);
        let top = at(r0, c0).lerp(at(r0, c1), ax);
        let bottom = at(r1, c0).lerp(at(r1, c1), ax);
        top.lerp(bottom, ay)
    }
}

/// Column `x` of a map `width` texels wide, wrapped around. Only u at the seam leaves
/// `[0, width)`, so the remainder's integer division is taken there only.
#[inline(always)]
fn wrap_column(x: i64, width: usize) -> usize {
    let w = width as i64;
    if (0..w).contains(&x) {
        x as usize
    } else {
        x.rem_euclid(w) as usize
    }
}

/// `x.floor()` without a call: baseline x86-64 has no rounding instruction, so `f32::floor`
/// is a libm call (2% of a sky-filled frame's samples). The same value for every `x`: below
/// 2^23 in magnitude an f32 truncates exactly through an integer, above it every f32 is an
/// integer already (and NaN or infinity goes to `f32::floor`).
#[inline(always)]
fn floor(x: f32) -> f32 {
    if x.abs() < 8_388_608.0 {
        let t = x as i32 as f32;
        // Truncation rounds towards zero: one less below zero when it rounded up. A `-0.0`
        // stays `-0.0` as `f32::floor` keeps it (`t = +0.0`, not above it: `-0.0` is kept).
        if t > x {
            t - 1.0
        } else if t == 0.0 {
            x * 0.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// Refuse a map whose negative texels the scene does not accept (see [`MAX_NEGATIVE_SHARE`]).
fn check_negatives(path: &Path, r: &Repairs, policy: Option<NegativeTexels>) -> Result<()> {
    let share = percent(r.negative_share);
    match policy {
        _ if r.negative == 0 => Ok(()),
        Some(NegativeTexels::Clamp) => Ok(()),
        Some(NegativeTexels::Refuse) => bail!(
            "{}: {} texel values are negative ({share} of the map's energy) and the \
             scene's `environment.negatives` is \"refuse\"",
            path.display(),
            r.negative
        ),
        None if r.negative_share > MAX_NEGATIVE_SHARE => bail!(
            "{}: {} texel values are negative, carrying {share} of the map's energy \
             (more than {}%): clamping them to 0 would add that much light. Fix the map, or \
             set the scene's `environment.negatives` to \"clamp\" (clamp anyway) or \
             \"refuse\" (envmapnegatives in a .scene; docs/limits.md)",
            path.display(),
            r.negative,
            100.0 * MAX_NEGATIVE_SHARE
        ),
        None => Ok(()),
    }
}

/// A share as a percentage a reader can compare: two decimals, or two digits when smaller.
fn percent(share: f64) -> String {
    let p = 100.0 * share;
    if p >= 0.01 || p == 0.0 {
        format!("{p:.2}%")
    } else {
        format!("{p:.1e}%")
    }
}

/// Σ|negative values| / Σ|all finite values|, each texel weighted by its solid angle in the
/// lat-long mapping (sin θ of its row's centre): the share of the map's energy that clamping
/// negatives to 0 changes.
fn negative_share(texels: &[f32], width: usize, height: usize) -> f64 {
    let (mut negative, mut all) = (0.0f64, 0.0f64);
    for (row, line) in texels.chunks(3 * width.max(1)).enumerate() {
        let w = (std::f64::consts::PI * (row as f64 + 0.5) / height as f64).sin();
        for &c in line {
            let c = c as f64;
            if c.is_finite() {
                all += w * c.abs().min(MAX_RADIANCE as f64);
                if c < 0.0 {
                    negative += w * (-c).min(MAX_RADIANCE as f64);
                }
            }
        }
    }
    if all > 0.0 { negative / all } else { 0.0 }
}

fn sanitise(texels: &mut [f32]) -> Repairs {
    let mut r = Repairs::default();
    for t in texels.chunks_mut(3) {
        for c in t {
            if c.is_nan() {
                r.nan += 1;
                *c = 0.0;
            } else if *c > MAX_RADIANCE {
                r.too_large += 1;
                *c = MAX_RADIANCE;
            } else if *c < 0.0 {
                r.negative += 1;
                *c = 0.0;
            }
        }
    }
    r
}

/// Three floats per texel, row-major.
fn read_texels(path: &Path) -> Result<(Vec<f32>, usize, usize)> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "exr" => {
            let (px, w, h) = crate::frame_io::exr::read_exr(path).with_context(|| {
                format!(
                    "cannot read environment map {} as an OpenEXR image (the scene's sky)",
                    path.display()
                )
            })?;
            Ok((px.into_iter().flatten().collect(), w as usize, h as usize))
        }
        "hdr" => {
            let img = open_bounded(path)
                .with_context(|| {
                    format!(
                        "cannot read environment map {} as a Radiance HDR image (the scene's sky)",
                        path.display()
                    )
                })?
                .into_rgb32f();
            let (w, h) = img.dimensions();
            Ok((img.into_raw(), w as usize, h as usize))
        }
        _ => bail!(
            "{}: environment maps must be .hdr or .exr files",
            path.display()
        ),
    }
}

/// `image::open` with the map's size bounded before any pixel buffer is allocated.
fn open_bounded(path: &Path) -> Result<image::DynamicImage> {
    let mut reader = image::ImageReader::open(path)?;
    let mut limits = image::Limits::default();
    let side = crate::limits::MAX_MAP_SIDE;
    limits.max_image_width = Some(side);
    limits.max_image_height = Some(side);
    limits.max_alloc = Some(crate::limits::MAX_MAP_TEXELS as u64 * 16);
    reader.limits(limits);
    Ok(reader.decode()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::sky;

    /// A 8x4 map whose texel (x, y) holds (x, y, 1).
    fn ramp() -> Environment {
        let px = (0..4)
            .flat_map(|y| (0..8).map(move |x| Vec3::new(x as f32, y as f32, 1.0)))
            .collect();
        Environment::new(8, 4, px, 1.0, 0.0).0
    }

    #[test]
    fn lookup_inverts_the_procedural_sky_mapping_at_texel_centres() {
        let env = ramp();
        for (x, y) in [(0, 0), (3, 1), (5, 2), (7, 3)] {
            let d = sky::direction((x as f32 + 0.5) / 8.0, (y as f32 + 0.5) / 4.0);
            let c = env.radiance(Vec3A::from(d) * 3.0);
            assert!(
                (c - Vec3::new(x as f32, y as f32, 1.0)).length() < 1e-4,
                "{x},{y}: {c}"
            );
        }
    }

    #[test]
    fn lookup_interpolates_and_wraps_around_the_seam() {
        let env = ramp();
        // Halfway between texels 7 and 0 of row 1: u = 1.0 (the seam).
        let d = sky::direction(1.0, 1.5 / 4.0);
        let c = env.radiance(Vec3A::from(d));
        assert!((c.x - 3.5).abs() < 1e-3 && (c.y - 1.0).abs() < 1e-4, "{c}");
        // Quarter of the way from row 1 to row 2 at texel column 2.
        let d = sky::direction(2.5 / 8.0, 1.75 / 4.0);
        let c = env.radiance(Vec3A::from(d));
        assert!((c - Vec3::new(2.0, 1.25, 1.0)).length() < 1e-3, "{c}");
    }

    #[test]
    fn floor_without_a_call_is_f32_floor_to_the_bit() {
        let mut values = vec![
            0.0f32,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            8_388_607.5,
            -8_388_607.5,
        ];
        values.extend([8_388_608.0, 1e30, -1e30, f32::INFINITY, f32::NEG_INFINITY]);
        values.extend([f32::MIN_POSITIVE, -f32::MIN_POSITIVE, 1e-45, -1e-45]);
        for i in 0..100_000u64 {
            let bits = crate::hash::hash(3, &[i]) as u32;
            values.push(f32::from_bits(bits));
            values.push(crate::hash::unit_f32(crate::hash::hash(4, &[i])) * 4096.0 - 2048.0);
        }
        for x in values {
            let (ours, std) = (floor(x), x.floor());
            assert!(
                ours.to_bits() == std.to_bits() || (ours.is_nan() && std.is_nan()),
                "floor({x:e}): {ours:e} against {std:e}"
            );
        }
    }

    #[test]
    fn rotation_turns_the_map_about_y() {
        let px = (0..4)
            .flat_map(|y| (0..8).map(move |x| Vec3::new(x as f32, y as f32, 1.0)))
            .collect();
        let (env, _) = Environment::new(8, 4, px, 2.0, 90.0);
        // Turned by 90° about +y, what the map shows at -z (u = 0.5) is now seen at
        // R_y(90°)(-z) = -x; intensity doubles it.
        let c = env.radiance(Vec3A::NEG_X);
        let plain = ramp().radiance(Vec3A::NEG_Z);
        assert!((c - 2.0 * plain).length() < 1e-3, "{c} vs {plain}");
    }

    #[test]
    fn one_broken_value_anywhere_in_a_large_map_is_found() {
        // The clean pass runs in parts of 65,536 values and runs of 64: a broken value in any
        // part, at either end of a run, must still send the map through the repairs.
        let (w, h) = (300, 250);
        for at in [0, 63, 64, 65_535, 65_536, 3 * w * h - 1] {
            for bad in [f32::NAN, -1.0, 2.0 * MAX_RADIANCE] {
                let mut flat = vec![0.5; 3 * w * h];
                flat[at] = bad;
                let (env, r) = Environment::from_flat(w, h, flat, 1.0, 0.0);
                assert_eq!(r.nan + r.too_large + r.negative, 1, "value {bad} at {at}");
                assert!((0.0..=MAX_RADIANCE).contains(&env.texels.floats()[at]));
            }
        }
    }

    #[test]
    fn broken_texels_are_repaired_and_counted() {
        let px = vec![
            Vec3::new(f32::NAN, 1.0, 2.0),
            Vec3::new(f32::INFINITY, 1e30, -0.003),
            Vec3::ONE,
            Vec3::new(f32::NEG_INFINITY, 0.5, 0.5),
        ];
        let (env, r) = Environment::new(2, 2, px, 1.0, 0.0);
        assert_eq!(
            r,
            Repairs {
                nan: 1,
                too_large: 2,
                negative: 2,
                negative_share: r.negative_share,
            }
        );
        assert!(r.negative_share > 0.0 && r.negative_share < 1e-3);
        let texels = env.texels.floats();
        assert!(texels.iter().all(|t| t.is_finite() && *t >= 0.0));
        assert!(texels.iter().all(|t| *t <= MAX_RADIANCE));
        for d in [Vec3A::X, Vec3A::Y, Vec3A::NEG_Z, Vec3A::ZERO, Vec3A::NAN] {
            assert!(env.radiance(d).is_finite());
        }
    }

    fn exr_map(dir: &Path, texels: &[[f32; 3]], w: u32, h: u32) -> std::path::PathBuf {
        let path = dir.join("map.exr");
        let bytes = crate::frame_io::exr::exr_bytes(texels, w, h).unwrap();
        std::fs::write(&path, bytes).unwrap();
        path
    }

    #[test]
    fn negative_texels_are_clamped_below_the_share_and_refused_above_it() {
        let dir = tempfile::tempdir().unwrap();
        // 4 x 2 map of radiance 1; one texel value -0.003 (compression noise), then -2.
        let mut texels = vec![[1.0f32; 3]; 8];
        texels[5][1] = -0.003;
        let path = exr_map(dir.path(), &texels, 4, 2);
        let (env, warning) = Environment::load(&path, 1.0, 0.0, None).unwrap();
        let w = warning.unwrap();
        assert!(
            w.contains("1 negative texel values") && w.contains("clamped to 0"),
            "{w}"
        );
        assert!(env.texels.floats().iter().all(|t| *t >= 0.0));
        let e = Environment::load(&path, 1.0, 0.0, Some(NegativeTexels::Refuse)).unwrap_err();
        assert!(format!("{e:#}").contains("map.exr"), "{e:#}");
        texels[5][1] = -2.0;
        let path = exr_map(dir.path(), &texels, 4, 2);
        let e = format!(
            "{:#}",
            Environment::load(&path, 1.0, 0.0, None).unwrap_err()
        );
        // Σ|c| sin θ: rows at θ = π/4 and 3π/4 weigh alike, so the share is 2 / 25 = 8%.
        assert!(
            e.contains("map.exr") && e.contains("8.00% of the map's energy"),
            "{e}"
        );
        let (_, w) = Environment::load(&path, 1.0, 0.0, Some(NegativeTexels::Clamp)).unwrap();
        assert!(w.unwrap().contains("carrying 8.00% of"));
    }
}
