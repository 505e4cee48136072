//! The scene renderer against theory: a moving edge's blur profile is the time filter's CDF, a
//! Lambertian sphere matches its closed form per pixel, zero velocity equals no motion byte for
//! byte, output does not depend on the thread count, and hard cases give no NaN or infinity.
//! Renders are tiny (16-64 px) so the suite stays fast.

use glam::Vec3;
use renderer::film::Film;
use renderer::progress::NoProgress;
use renderer::render::{FrameStats, render_frame};
use renderer::sampling::{SamplingConfig, SpatialFilter, TimeFilter};
use renderer::scene::Scene;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

#[path = "support/progress.rs"]
mod recorder;
#[path = "../../tests/support/test_assets.rs"]
mod test_assets;
use recorder::Recorder;

fn load(v: &Value, dir: &Path) -> Scene {
    Scene::from_json(&v.to_string(), &dir.join("test.json")).unwrap()
}

/// Random points with a box pixel filter: each sample uniform over its pixel, so a pixel's
/// expected value is the plain mean over the pixel and its noise the plain Monte Carlo one.
fn sampling(spp: u32) -> SamplingConfig {
    SamplingConfig {
        spp,
        spatial_filter: Some(SpatialFilter::Box),
        ..SamplingConfig::default()
    }
}

fn render(scene: &Scene, spp: u32, frame: u32) -> (Film, FrameStats) {
    render_frame(scene, &sampling(spp), 7, frame, &NoProgress).unwrap()
}

fn assert_all_finite(film: &Film, stats: &FrameStats, what: &str) {
    assert_eq!(stats.non_finite, 0, "{what}: non-finite samples");
    assert!(
        film.pixels.iter().all(|p| p.is_finite()),
        "{what}: a pixel is not finite"
    );
}

/// A camera looking down -z from `distance` whose view at z = 0 spans exactly `half` units
/// either side of the centre across the image's shorter side (the side `fov` is measured on):
/// a plane facing the camera maps linearly onto the film.
fn camera(distance: f32, half: f32) -> Value {
    let fov = 2.0 * (half / distance).atan().to_degrees();
    json!({"location": [0, 0, distance], "look_at": [0, 0, 0], "fov": fov})
}

fn settings(size: [u32; 2], extra: Value) -> Value {
    let mut s = json!({
        "start_time": 0.0, "frame_time": 1.0, "frames": 2,
        "width": size[0], "height": size[1],
    });
    for (k, v) in extra.as_object().unwrap() {
        s[k] = v.clone();
    }
    s
}

#[test]
fn a_moving_edge_is_blurred_by_the_time_filters_cdf() {
    // A square of radiance 1 (ambient only: no lights, no shadow rays) on black, its right edge
    // sweeping from x = -24 to x = +24 during frame 0's shutter [0, 1 s]. One pixel is one unit
    // at z = 0 (the view's shorter side, h, spans h units), so column c (centre X = c + 0.5 - 32) is covered while the edge is right of X:
    // value(X) = 1 - F((X + 24) / 48), F the CDF of the warped shutter time.
    let (w, h) = (64u32, 16u32);
    let sweep = 48.0f32;
    let half_extent = 200.0f32;
    let dir = tempfile::tempdir().unwrap();
    for filter in TimeFilter::ALL {
        // The filter's CDF over the shutter fraction and its largest density (for the bias
        // bound below), from the sampler's own definition of the filter.
        let cdf = |s: f32| filter.cdf(s as f64) as f32;
        let max_density = (0..=1000)
            .map(|k| filter.pdf(k as f64 / 1000.0))
            .fold(0.0, f64::max) as f32;
        let spp = 256;
        let scene = load(
            &json!({
                "format": "blurlab-scene/1",
                "materials": [{"name": "flat", "ambient": [1, 1, 1]}],
                "objects": [{
                    "name": "square", "type": "plane", "material": "flat",
                    "half_extent": [half_extent, half_extent],
                    "rotation": [90, 0, 0],
                    "location": [-24.0 - half_extent, 0, 0], "velocity": [sweep, 0, 0]
                }],
                "camera": camera(1000.0, h as f32 / 2.0),
                "settings": settings([w, h], json!({"ambient_light": [1, 1, 1]})),
            }),
            dir.path(),
        );
        let cfg = SamplingConfig {
            time_filter: filter,
            ..sampling(spp)
        };
        let filter = filter.name();
        let (film, stats) = render_frame(&scene, &cfg, 3, 0, &NoProgress).unwrap();
        assert_all_finite(&film, &stats, filter);
        // Tolerance. Noise: each sample is 0 or 1 (variance <= 1/4) and pixels' estimates are
        // uncorrelated (independent per-pixel shifts), so a column mean over h rows has
        // standard error <= 0.5 / sqrt(h * spp); allow 5 of them. Bias: the sub-pixel offset
        // moves the point seen by |dx| on average <= 0.5 px (box: 0.25; the default Gaussian,
        // sigma 0.5: 0.4), and value(X) changes by at most max_density / sweep per unit.
        let noise = 5.0 * 0.5 / ((h * spp) as f32).sqrt();
        let bias = max_density * 0.5 / sweep;
        for c in 0..w {
            let mean: f32 = (0..h)
                .map(|y| film.pixels[(y * w + c) as usize].x)
                .sum::<f32>()
                / h as f32;
            let x = c as f32 + 0.5 - w as f32 / 2.0;
            let expect = 1.0 - cdf((x + 24.0) / sweep);
            assert!(
                (mean - expect).abs() <= noise + bias,
                "{filter}: column {c}: {mean} vs {expect} (tolerance {})",
                noise + bias
            );
        }
    }
}

/// Where the ray from `eye` along `d` meets the sphere of radius `r` at the origin (in f64,
/// with `d` normalised in f64: |o|² - r² must not lose r² to rounding).
fn sphere_hit(eye: Vec3, d: Vec3, r: f32) -> Option<Vec3> {
    let (eye, d) = (eye.as_dvec3(), d.as_dvec3().normalize());
    let b = eye.dot(d);
    let c = eye.length_squared() - (r as f64).powi(2);
    let disc = b * b - c;
    (disc >= 0.0).then(|| (eye + d * (-b - disc.sqrt())).as_vec3())
}

#[test]
fn a_lambertian_sphere_matches_its_closed_form_per_pixel() {
    // Sphere of radius 1 seen from 20 units (rays nearly parallel), lit by a directional
    // light of irradiance 1 from l: radiance kd * max(0, n·l) where the ray meets the sphere,
    // black elsewhere (no ambient, no environment). Each pixel's expected value is the mean of
    // that closed form over the pixel (box filter), by a 64x64 midpoint rule.
    let (size, spp, kd) = (40u32, 256u32, 0.8f32);
    let (distance, half) = (20.0f32, 1.25f32);
    let l = Vec3::new(1.0, 1.0, 1.0).normalize();
    let dir = tempfile::tempdir().unwrap();
    let scene = load(
        &json!({
            "format": "blurlab-scene/1",
            "materials": [{"name": "matte", "diffuse": [kd, kd, kd]}],
            "objects": [{"name": "ball", "type": "sphere", "radius": 1.0, "material": "matte"}],
            "lights": [{"type": "directional", "direction": (-l).to_array()}],
            "camera": camera(distance, half),
            "settings": settings([size, size], json!({})),
        }),
        dir.path(),
    );
    let (film, stats) = render(&scene, spp, 0);
    assert_all_finite(&film, &stats, "sphere");
    let eye = Vec3::new(0.0, 0.0, distance);
    let tan = half / distance;
    let radiance = |fx: f32, fy: f32| {
        let sx = (2.0 * fx / size as f32 - 1.0) * tan;
        let sy = (1.0 - 2.0 * fy / size as f32) * tan;
        let d = Vec3::new(sx, sy, -1.0);
        sphere_hit(eye, d, 1.0).map_or(0.0, |p| kd * p.normalize().dot(l).max(0.0))
    };
    const M: usize = 64;
    let mut checked_inside = 0;
    for y in 0..size {
        for x in 0..size {
            let vals: Vec<f32> = (0..M * M)
                .map(|k| {
                    let (i, j) = (k % M, k / M);
                    radiance(
                        x as f32 + (i as f32 + 0.5) / M as f32,
                        y as f32 + (j as f32 + 0.5) / M as f32,
                    )
                })
                .collect();
            let mean = vals.iter().sum::<f32>() / vals.len() as f32;
            let var = vals.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / vals.len() as f32;
            let (lo, hi) = vals
                .iter()
                .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            // Noise: the per-sample standard deviation over the pixel (uniform sub-pixel
            // samples) over sqrt(spp), 5 of them. Quadrature: a curve crossing the pixel cuts
            // at most ~4M of the M² cells, each off by at most the pixel's range (hi - lo).
            // Float: 1e-4 (f32 hit points and normals at distance 20 are good to ~1e-6).
            let tol = 5.0 * var.sqrt() / (spp as f32).sqrt() + (hi - lo) * 4.0 / M as f32 + 1e-4;
            let got = film.pixels[(y * size + x) as usize];
            assert!(
                (got.x - mean).abs() <= tol,
                "pixel ({x}, {y}): {} vs closed form {mean} (tolerance {tol})",
                got.x
            );
            assert_eq!(got.x, got.y, "grey material, white light");
            if lo > 0.05 {
                checked_inside += 1;
            }
        }
    }
    assert!(checked_inside > 200, "the sphere covers the view's middle");
}

/// A scene with every kind of object, a moving camera option and the motion fields given as
/// zeros (`zeros = true`) or left out.
fn motion_scene(dir: &Path, zeros: bool) -> Value {
    let obj = dir.join("tri.obj");
    std::fs::write(
        &obj,
        "v -1 0 0\nv 1 0 0\nv 0 1.5 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 2 4 3\n",
    )
    .unwrap();
    let z = [0.0, 0.0, 0.0];
    let mut v = json!({
        "format": "blurlab-scene/1",
        "materials": [
            {"name": "m", "diffuse": [0.6, 0.5, 0.4], "specular": [0.3, 0.3, 0.3],
             "ambient": [0.1, 0.1, 0.1], "fresnel": {"min": 0.2, "max": 1.0, "exponent": 5}},
            {"name": "floor", "diffuse": [0.5, 0.5, 0.5]}
        ],
        "objects": [
            {"name": "model", "type": "model", "file": "tri.obj", "material": "m",
             "location": [0.5, 0, 0], "rotation": [0, 20, 0]},
            {"name": "ball", "type": "sphere", "radius": 0.5, "material": "m",
             "location": [-1, 0.5, 0]},
            {"name": "floor", "type": "plane", "material": "floor"}
        ],
        "instances": [{"name": "ball2", "object": "ball", "location": [1.5, 0.5, -1]}],
        "groups": [{"name": "g", "children": ["model", "ball2"], "location": [0, 0.1, 0]}],
        "lights": [
            {"type": "point", "position": [2, 3, 2], "intensity": 8},
            {"type": "directional", "direction": [-1, -2, -1]}
        ],
        "camera": {"location": [0, 1.5, 5], "look_at": [0, 0.5, 0], "fov": 45},
        "settings": settings([24, 20], json!({"ambient_light": [0.3, 0.3, 0.4]})),
    });
    if zeros {
        for o in ["objects", "instances", "groups"] {
            for item in v[o].as_array_mut().unwrap() {
                item["velocity"] = json!(z);
                item["angular_velocity"] = json!(z);
            }
        }
        for f in ["location_velocity", "look_at_velocity", "up_velocity"] {
            v["camera"][f] = json!(z);
        }
    }
    v
}

#[test]
fn zero_velocity_renders_byte_identically_to_no_motion() {
    let dir = tempfile::tempdir().unwrap();
    let still = load(&motion_scene(dir.path(), false), dir.path());
    let zeros = load(&motion_scene(dir.path(), true), dir.path());
    assert!(!still.has_motion() && !zeros.has_motion());
    let a = render(&still, 8, 1).0.develop(1.0);
    let b = render(&zeros, 8, 1).0.develop(1.0);
    assert_eq!(a.display, b.display);
    let bits = |f: &[[f32; 3]]| f.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.linear), bits(&b.linear));
    // And something was drawn: the frame is not uniform.
    assert!(a.display.iter().any(|&v| v != a.display[0]));
}

#[test]
fn frames_are_the_same_bytes_with_one_or_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let mut v = motion_scene(dir.path(), false);
    v["objects"][1]["velocity"] = json!([2, 0, 0]);
    v["groups"][0]["angular_velocity"] = json!([0, 90, 0]);
    v["camera"]["location_velocity"] = json!([0.3, 0, 0]);
    let scene = load(&v, dir.path());
    assert!(scene.has_motion());
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| render(&scene, 6, 1).0)
    };
    let (one, two) = (run(1), run(2));
    let bits = |f: &Film| {
        f.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .map(f32::to_bits)
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
}

/// Write an RGB float EXR that may hold NaN and infinity (the project's own EXR writer cleans
/// them, so this uses the exr crate directly).
fn write_raw_exr(path: &Path, w: usize, h: usize, px: &[[f32; 3]]) {
    use exr::prelude::*;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = px[y * w + x];
        (p[0], p[1], p[2])
    });
    Image::from_encoded_channels((w, h), Encoding::UNCOMPRESSED, channels)
        .write()
        .to_file(path)
        .unwrap();
}

#[test]
fn hard_cases_give_no_nan_or_infinity_in_any_pixel() {
    let dir = tempfile::tempdir().unwrap();
    // A mesh with zero-area triangles (repeated and collinear corners), a zero normal, and a
    // normal triangle, placed around 1e4; a quad lying in the camera's horizontal plane (rays
    // along its plane); an environment map holding NaN, infinity and 1e30.
    std::fs::write(
        dir.path().join("bad.obj"),
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\n\
         vn 0 0 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n\
         f 1//1 2//2 3//3\nf 1//1 1//1 4//4\nf 1//1 2//2 4//4\nf 2//2 5//5 4//4\n",
    )
    .unwrap();
    let (w, h) = (16usize, 8usize);
    let mut px: Vec<[f32; 3]> = (0..w * h).map(|i| [0.5, 0.6, (i % 3) as f32]).collect();
    px[3] = [f32::NAN, 1.0, 1.0];
    px[20] = [f32::INFINITY, f32::NEG_INFINITY, 1e30];
    px[77] = [1e30, 1e30, 1e30];
    let map = dir.path().join("broken.exr");
    write_raw_exr(&map, w, h, &px);
    let base = Vec3::splat(1e4);
    let at = |x: f32, y: f32, z: f32| (base + Vec3::new(x, y, z)).to_array();
    let v = json!({
        "format": "blurlab-scene/1",
        "materials": [{"name": "m", "diffuse": [0.5, 0.5, 0.5], "specular": [1, 1, 1],
                       "fresnel": {"min": 0.5, "max": 1, "exponent": 5}}],
        "objects": [
            {"name": "bad", "type": "model", "file": "bad.obj", "material": "m",
             "location": at(-0.5, -0.5, 0.0), "velocity": [0.5, 0, 0]},
            {"name": "edge_on", "type": "model", "file": "bad.obj", "material": "m",
             "location": at(-1.0, 0.0, -2.0), "rotation": [90, 0, 0]},
            {"name": "ball", "type": "sphere", "radius": 0.3, "material": "m",
             "location": at(0.8, 0.6, 0.5)}
        ],
        "lights": [{"type": "point", "position": at(0.0, 0.0, 1e-3), "intensity": 1},
                   {"type": "directional", "direction": [0, 0, -1]}],
        "camera": {"location": at(0.0, 0.0, 4.0), "look_at": at(0.0, 0.0, 0.0), "fov": 50},
        "settings": settings([24, 24], json!({
            "environment": {"file": "broken.exr"}, "max_depth": 4,
            "ambient_light": [1, 1, 1]
        })),
    });
    let scene = load(&v, dir.path());
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].contains("broken.exr"),
        "{}",
        scene.warnings[0]
    );
    for frame in 0..2 {
        let (film, stats) = render(&scene, 16, frame);
        assert_all_finite(&film, &stats, "hard cases");
        let developed = film.develop(scene.settings.exposure);
        assert!(developed.linear.iter().flatten().all(|v| v.is_finite()));
    }
}

fn files_with(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

#[test]
fn third_party_models_and_maps_load_and_render_without_nan() {
    let Some(assets) = test_assets::folder() else {
        return;
    };
    let models = files_with(&assets, "obj");
    let maps = files_with(&assets, "exr");
    assert!(
        !models.is_empty() && !maps.is_empty(),
        "{}",
        assets.display()
    );
    for (i, model) in models.iter().enumerate() {
        let map = &maps[i % maps.len()];
        let mesh = renderer::geometry::TriangleMesh::from_obj(model).unwrap();
        // Frame the model whatever its units: look at its bounds' centre from 2.5 diagonals.
        let b = mesh.bounds();
        let centre = Vec3::from((b.min + b.max) * 0.5);
        let diag = (b.max - b.min).length();
        let v = json!({
            "format": "blurlab-scene/1",
            "materials": [{"name": "m", "diffuse": [0.6, 0.6, 0.6], "specular": [0.5, 0.5, 0.5],
                           "ambient": [0.2, 0.2, 0.2],
                           "fresnel": {"min": 0.1, "max": 1, "exponent": 5}}],
            "objects": [{"name": "model", "type": "model", "file": model, "material": "m",
                         "velocity": [diag * 0.1, 0.0, 0.0], "angular_velocity": [0, 30, 0]}],
            "lights": [{"type": "directional", "direction": [-1, -1, -1]}],
            "camera": {"location": (centre + Vec3::new(0.3, 0.5, 2.5) * diag).to_array(),
                       "look_at": centre.to_array(), "fov": 40},
            "settings": settings([24, 24], json!({
                "environment": {"file": map, "negatives": "clamp"}, "ambient_light": [0.5, 0.5, 0.5]
            })),
        });
        let (film, stats) = render(&load(&v, &assets), 4, 0);
        let what = format!("{} under {}", model.display(), map.display());
        assert_all_finite(&film, &stats, &what);
        let mut bare = v.clone();
        bare["objects"][0]["hidden"] = json!(true);
        assert_ne!(
            film,
            render(&load(&bare, &assets), 4, 0).0,
            "{what}: model not seen"
        );
    }
}

/// Real maps' negative texels (a DWAB-compressed capture holds thousands): counted with the
/// energy they carry, refused above the documented share unless the scene says to clamp them,
/// clamped with a warning below it.
#[test]
fn third_party_maps_negative_texels_are_counted_and_refused_above_the_share() {
    use renderer::environment::{Environment, MAX_NEGATIVE_SHARE, NegativeTexels};
    let Some(assets) = test_assets::folder() else {
        return;
    };
    for map in files_with(&assets, "exr") {
        let (_, warning) = Environment::load(&map, 1.0, 0.0, Some(NegativeTexels::Clamp)).unwrap();
        let plain = Environment::load(&map, 1.0, 0.0, None);
        let refuse = Environment::load(&map, 1.0, 0.0, Some(NegativeTexels::Refuse));
        eprintln!("{}: {warning:?}", map.display());
        match warning
            .as_deref()
            .and_then(|w| w.split(" negative texel values, carrying ").nth(1))
        {
            None => assert!(plain.is_ok() && refuse.is_ok(), "{}", map.display()),
            Some(rest) => {
                let pct: f64 = rest.split('%').next().unwrap().parse().unwrap();
                assert!(pct > 0.0, "{rest}");
                let e = format!("{:#}", refuse.unwrap_err());
                assert!(e.contains("\"refuse\""), "{e}");
                if pct / 100.0 > MAX_NEGATIVE_SHARE {
                    let e = format!("{:#}", plain.unwrap_err());
                    assert!(
                        e.contains("of the map's energy") && e.contains("negatives"),
                        "{e}"
                    );
                } else {
                    assert!(plain.unwrap().1.is_some());
                }
            }
        }
    }
}

/// The sequence path (tiles, and with two threads a writer thread overlapping the next frame)
/// writes the same files, in full, whatever the thread count; sizes that are not a multiple of
/// the tile side included.
#[test]
fn sequences_write_the_same_files_with_one_or_two_threads() {
    use renderer::render::sequence::{SequenceOptions, render_sequence};
    let dir = tempfile::tempdir().unwrap();
    let mut v = motion_scene(dir.path(), false);
    v["objects"][1]["velocity"] = json!([2, 0, 0]);
    let mut scene = load(&v, dir.path());
    scene.settings.width = 37;
    scene.settings.height = 21;
    let frames = 0..scene.settings.frames.min(3);
    let run = |threads: usize| {
        let out = dir.path().join(format!("out{threads}"));
        let opts = SequenceOptions {
            out_dir: out.clone(),
            frames: frames.clone(),
            seed: 3,
            exr: true,
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let progress = Recorder::default();
        let report = pool
            .install(|| render_sequence(&scene, &sampling(4), &opts, &progress))
            .unwrap();
        assert_eq!(report.frames as usize, frames.len());
        assert_eq!(report.stats.samples, 37 * 21 * 4 * frames.len() as u64);
        // One start with every sample of the run, advanced to the end by tiles, one message
        // per frame, then finished.
        let seen = progress.seen();
        assert_eq!(seen.totals, [report.stats.samples]);
        assert_eq!(seen.advances.iter().sum::<u64>(), report.stats.samples);
        assert_eq!(
            seen.advances.len(),
            3 * 2 * frames.len(),
            "3 x 2 tiles a frame"
        );
        assert_eq!(seen.messages.len(), frames.len());
        assert_eq!(
            seen.messages[0],
            format!("frame 1/{} (scene frame 0)", frames.len())
        );
        assert!(seen.finished);
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                let name = e.file_name().to_string_lossy().into_owned();
                (name, std::fs::read(e.path()).unwrap())
            })
            .collect();
        files.sort();
        files
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(
        one.len(),
        2 * frames.len(),
        "a PNG and an EXR per frame, no temporaries"
    );
    assert_eq!(one, two);
}

/// A frame advances its caller's progress once per tile, by the tile's samples, to exactly the
/// frame's samples; it neither starts nor finishes (its caller knows the whole work).
#[test]
fn a_frame_advances_progress_by_its_tiles_samples() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = load(&motion_scene(dir.path(), false), dir.path());
    scene.settings.width = 37;
    scene.settings.height = 21;
    let progress = Recorder::default();
    let (_, stats) = render_frame(&scene, &sampling(3), 7, 0, &progress).unwrap();
    assert_eq!(stats.samples, 37 * 21 * 3);
    let mut seen = progress.seen();
    assert!(seen.totals.is_empty() && seen.messages.is_empty() && !seen.finished);
    assert_eq!(seen.advances.iter().sum::<u64>(), stats.samples);
    // 3 x 2 tiles, finishing in any order: 16 x 16 twice, 5 x 16, 16 x 5 twice, 5 x 5.
    seen.advances.sort_unstable();
    let tile = |w: u64, h: u64| w * h * 3;
    let mut want = vec![
        tile(16, 16),
        tile(16, 16),
        tile(5, 16),
        tile(16, 5),
        tile(16, 5),
        tile(5, 5),
    ];
    want.sort_unstable();
    assert_eq!(seen.advances, want);
}
