//! The thesis scenes' stimuli converge (issue 12's criterion, `render converge`), in a version
//! small enough for CI: 32 x 32 pixels, two frames per scene, levels 8, 64 and 512 of the
//! scene's own point set (Hammersley) with the thesis's truncated box, against a 2048-spp
//! Sobol render with its own seed.
//!
//! What it shows: at this size the display error falls from 8 to 64 to 512 spp, by at least 4x
//! overall, and at 512 spp no pixel of the 2048 compared is more than 32 levels off (the 0.01%
//! bound allows none here) — a scene whose HDR highlights cannot resolve by 512 spp (as the
//! former spheres scene, sun radiance 5000) fails it. What it cannot show: the per-step fall
//! between close levels (343 to 512 is a 1.2x step, within this size's estimate noise), the
//! other point sets, or the share of speckled pixels at the thesis size, where a highlight
//! covers many more pixels. The full measurement (768 x 768, one frame per scene, all seven
//! levels 8..512, three point sets) is `blurlab render converge`, tables in BENCHMARKS.md and
//! docs/benchmarks/convergence.md.

use renderer::display_convergence::{Criterion, Plan, judge, measure};
use renderer::progress::NoProgress;
use renderer::scene::Scene;
use std::path::Path;

fn check(name: &str, frames: Vec<u32>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/thesis/{name}.json"));
    let mut scene = Scene::load(&path).unwrap();
    scene.settings.width = 32;
    scene.settings.height = 32;
    let plan = Plan {
        levels: vec![8, 64, 512],
        point_sets: vec![scene.settings.sampling.point_set],
        ..Plan::thesis(renderer::condition::TimeFilter::TruncatedBox, frames)
    };
    assert_eq!(plan.reference_spp, 2048);
    let rows = measure(&scene, &plan, &NoProgress, |_| {}).unwrap();
    let verdict = &judge(&rows, &Criterion::thesis())[0];
    assert!(verdict.pass, "{name}: {verdict:?}\n{rows:#?}");
}

#[test]
fn the_plane_scene_converges_at_ci_size() {
    // The airliner crossing the view, and the sky and ground streaking before it arrives.
    check("plane", vec![60, 94]);
}

#[test]
fn the_spheres_scene_converges_at_ci_size() {
    check("spheres", vec![30, 100]);
}
