//! Figure 13's plane scene moves the airliner across the view as its values say: the airliner's
//! on-screen extent in rendered frames (held still at each frame's mid-shutter time) against an
//! independent pinhole projection, written from the scene file's numbers and the model's
//! vertices (`figure13/mod.rs`); and the crossing the projection predicts is the one `scenes/README.md` describes
//! (centre enters at the right edge near frame 88, leaves at the left after frame 98, up to
//! about 81 px per frame at 768 x 768).

mod figure13;

use figure13::{Plane, rendered_extent, scene_path};
use renderer::scene::Scene;

#[test]
fn the_airliner_crosses_the_view_as_figure_13s_values_project_it() {
    const SIZE: u32 = 192;
    let plane = Plane::load();
    let mut scene = Scene::load(&scene_path()).unwrap();
    scene.settings.width = SIZE;
    scene.settings.height = SIZE;
    scene.environment = None;
    let size = SIZE as f64;
    // A pixel shows the airliner when one of its 8 samples hits it: a predicted edge lies
    // inside the outermost pixel found, give or take one pixel for thin tips the samples miss.
    let tol = 1.5;
    let mut seen = Vec::new();
    let mut whole = 0;
    for frame in 78..=106 {
        let predicted = plane.extent(frame, size).expect("in front of the camera");
        let inside = predicted[1] > 2.0 && predicted[0] < size - 2.0;
        let outside = predicted[1] < -2.0 || predicted[0] > size + 2.0;
        let rendered = rendered_extent(&scene, frame, SIZE);
        match rendered {
            Some(r) => {
                assert!(
                    !outside,
                    "frame {frame}: rendered at {r:?}, predicted {predicted:?}"
                );
                seen.push(frame);
                let r = r.map(|v| v as f64);
                // Edges the image does not cut must match the projection.
                if predicted[0] > 1.0 {
                    assert!(
                        (r[0] + 0.5 - predicted[0]).abs() < tol,
                        "frame {frame} left: {r:?} vs {predicted:?}"
                    );
                }
                if predicted[1] < size - 1.0 {
                    assert!(
                        (r[1] + 0.5 - predicted[1]).abs() < tol,
                        "frame {frame} right: {r:?} vs {predicted:?}"
                    );
                }
                // Top and bottom when the whole airliner is in view (the image's edge may cut
                // off the fin or a wing tip).
                if predicted[0] > 1.0 && predicted[1] < size - 1.0 {
                    assert!(
                        (r[2] + 0.5 - predicted[2]).abs() < tol,
                        "frame {frame} top: {r:?} vs {predicted:?}"
                    );
                    assert!(
                        (r[3] + 0.5 - predicted[3]).abs() < tol,
                        "frame {frame} bottom: {r:?} vs {predicted:?}"
                    );
                    whole += 1;
                }
            }
            None => assert!(
                !inside,
                "frame {frame}: predicted at {predicted:?}, not rendered"
            ),
        }
    }
    // On screen without a break from its nose entering at the right to its tail leaving at
    // the left.
    eprintln!("airliner in view in frames {seen:?}, whole in {whole}");
    assert!(
        whole >= 3,
        "the airliner was whole in view in {whole} frames only"
    );
    assert!(
        seen.len() > 10 && seen.windows(2).all(|w| w[1] == w[0] + 1),
        "{seen:?}"
    );
    assert!(seen[0] > 78 && *seen.last().unwrap() < 106, "{seen:?}");
}

#[test]
fn the_projected_crossing_is_the_one_the_scene_notes_describe() {
    // At the thesis size, from the same projection as above: the numbers in scenes/README.md.
    let plane = Plane::load();
    let x = |f: u32| plane.centre(f, 768.0).unwrap().0;
    let inside: Vec<u32> = (60..130)
        .filter(|&f| {
            plane
                .centre(f, 768.0)
                .is_some_and(|(x, _)| (0.0..768.0).contains(&x))
        })
        .collect();
    assert_eq!((inside[0], *inside.last().unwrap()), (88, 98), "{inside:?}");
    let speeds: Vec<f64> = (88..=98).map(|f| x(f) - x(f + 1)).collect();
    let peak = speeds.iter().cloned().fold(0.0, f64::max);
    assert!(
        (80.0..83.0).contains(&peak),
        "peak {peak:.1} px per frame ({speeds:?})"
    );
    assert!(speeds.iter().all(|&s| s > 35.0), "{speeds:?}");
    // Near the centre line vertically all the way across (within 10% of the height).
    for f in 88..=98 {
        let y = plane.centre(f, 768.0).unwrap().1;
        assert!((y - 384.0).abs() < 77.0, "frame {f}: y = {y:.0}");
    }
    // Far away and small, but in view, at the start and the end of the animation.
    for f in [0, plane.frames - 1] {
        let (x, y) = plane.centre(f, 768.0).unwrap();
        assert!(
            (0.0..768.0).contains(&x) && (0.0..768.0).contains(&y),
            "frame {f}: {x}, {y}"
        );
    }
}
