//! The readings of Figure 13's geometry and, for each, where the airliner is on screen: how
//! many frames some of it, all of it and its centre are in view, how fast its centre moves and
//! how long it gets, at 768 x 768 over the 210 frames, from the independent projection in
//! `renderer/tests/figure13/mod.rs` (the one `tests/figure13_readings.rs` checks against
//! renders). Prints the table of `docs/replication.md`.
//!
//! ```text
//! cargo run -p renderer --example figure13_readings
//! ```

#[path = "../tests/figure13/mod.rs"]
mod figure13;

use figure13::{Plane, read_as, readings, track};

/// `[a, b, c, e, f]` as `a-c, e-f`.
fn ranges(frames: &[u32]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < frames.len() {
        let mut j = i;
        while j + 1 < frames.len() && frames[j + 1] == frames[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            frames[i].to_string()
        } else {
            format!("{}-{}", frames[i], frames[j])
        });
        i = j + 1;
    }
    if out.is_empty() {
        "none".into()
    } else {
        out.join(", ")
    }
}

fn main() {
    const SIZE: f64 = 768.0;
    const FPS: f64 = 30.0;
    println!(
        "| reading | some in view (frames) | whole in view | centre in view | s of centre at {FPS} fps | peak px/frame | longest px |"
    );
    println!("|---|---|---|---|---|---|---|");
    for r in readings() {
        let t = track(&Plane::from_json(read_as(&r)), SIZE);
        println!(
            "| {} | {} ({}) | {} ({}) | {} ({}) | {:.2} | {:.0} | {:.0} |",
            r.name,
            ranges(&t.any),
            t.any.len(),
            ranges(&t.whole),
            t.whole.len(),
            ranges(&t.centre),
            t.centre.len(),
            t.centre.len() as f64 / FPS,
            t.peak_px_per_frame,
            t.longest_px,
        );
    }
    println!();
    for r in readings() {
        println!(
            "- {}: {}",
            r.name,
            r.what.split_whitespace().collect::<Vec<_>>().join(" ")
        );
    }
}
