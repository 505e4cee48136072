//! The readings of Figure 13's geometry (`docs/replication.md`): for each, the frames the
//! airliner is on screen and how fast it moves come from the independent projection in
//! `figure13/mod.rs`; here that projection is checked against renders of the scene so read, at
//! 96 x 96 and three frames each (the frame where it is widest on screen, the next, and one
//! where the projection puts it out of view).

mod figure13;

use figure13::{Plane, read_as, readings, rendered_extent, scene_path, track};
use renderer::scene::Scene;

const SIZE: u32 = 96;

/// The scene under a reading, at SIZE x SIZE, without the sky (the airliner alone is lit).
fn scene(json: &serde_json::Value) -> Scene {
    let mut s = Scene::from_json(&json.to_string(), &scene_path()).unwrap();
    s.settings.width = SIZE;
    s.settings.height = SIZE;
    s.environment = None;
    s
}

/// Frames to render for a track: the frame where the airliner is widest, the next one, and a
/// frame out of view (the first, if any).
fn probe_frames(plane: &Plane, any: &[u32]) -> Vec<u32> {
    let size = SIZE as f64;
    let mut frames: Vec<u32> = Vec::new();
    let widest = any
        .iter()
        .copied()
        .max_by(|&a, &b| {
            let w = |f| plane.extent(f, size).map_or(0.0, |e| e[1] - e[0]);
            w(a).total_cmp(&w(b))
        })
        .unwrap();
    frames.push(widest);
    frames.push((widest + 1).min(plane.frames - 1));
    if let Some(out) = (0..plane.frames).find(|f| !any.contains(f)) {
        frames.push(out);
    }
    frames.dedup();
    frames
}

#[test]
fn each_reading_s_projection_matches_its_renders() {
    // A pixel shows the airliner when one of its 8 samples hits it: a predicted edge lies
    // inside the outermost pixel found, give or take one pixel for thin tips the samples miss.
    let tol = 1.5;
    let size = SIZE as f64;
    for r in readings()
        .iter()
        .filter(|r| ["suite", "centred model", "half-angle fov"].contains(&r.name))
    {
        let json = read_as(r);
        let plane = Plane::from_json(json.clone());
        let t = track(&plane, size);
        let scene = scene(&json);
        for f in probe_frames(&plane, &t.any) {
            let rendered = rendered_extent(&scene, f, SIZE);
            let predicted = plane.extent(f, size);
            let in_view = t.any.contains(&f);
            match (rendered, predicted) {
                (Some(e), Some(p)) => {
                    let e = e.map(|v| v as f64);
                    // Edges the image does not cut must match the projection.
                    let checks = [
                        (p[0] > 1.0, e[0] + 0.5, p[0]),
                        (p[1] < size - 1.0, e[1] + 0.5, p[1]),
                        (p[2] > 1.0, e[2] + 0.5, p[2]),
                        (p[3] < size - 1.0, e[3] + 0.5, p[3]),
                    ];
                    for (uncut, got, want) in checks {
                        assert!(
                            !uncut || (got - want).abs() < tol,
                            "{}: frame {f}: rendered {e:?}, projected {p:?}",
                            r.name
                        );
                    }
                    assert!(in_view, "{}: frame {f} rendered but out of view", r.name);
                }
                (None, _) => assert!(
                    // A speck (or sliver at the edge) under 1.5 px across may fall between the
                    // 8 samples.
                    !in_view
                        || predicted.is_some_and(|p| {
                            let across = |a: f64, b: f64| b.min(size) - a.max(0.0);
                            across(p[0], p[1]).min(across(p[2], p[3])) < 1.5
                        }),
                    "{}: frame {f}: projected {predicted:?} in view, nothing rendered",
                    r.name
                ),
                (Some(e), None) => panic!("{}: frame {f}: rendered {e:?}, behind the eye", r.name),
            }
        }
    }
}

#[test]
fn the_readings_tracks_are_the_ones_docs_replication_md_prints() {
    // At 768 x 768. The suite's reading: the crossing scenes/README.md describes.
    let all = readings();
    let t = |name: &str| {
        let r = all.iter().find(|r| r.name == name).unwrap();
        track(&Plane::from_json(read_as(r)), 768.0)
    };
    let suite = t("suite");
    assert_eq!(
        suite
            .whole
            .iter()
            .filter(|&&f| (85..102).contains(&f))
            .count(),
        6
    );
    assert!((80.0..83.0).contains(&suite.peak_px_per_frame));
    // Centred on its origin the airliner never crosses the view during its pass.
    let centred = t("centred model");
    assert!(
        !centred.any.iter().any(|f| (85..102).contains(f)),
        "{centred:?}"
    );
    // Frames 1/30 s apart: the animation ends 5.5 s before the pass.
    let short = t("frametime = shutter");
    assert!(short.peak_px_per_frame < 5.0, "{short:?}");
}
