//! Where a lat-long environment map's sun is, in the renderer's mapping
//! (`renderer::procedural::sky`: column u is the azimuth 2 pi (u - 1/2) from -z towards +x, row
//! v the polar angle pi v from +y), and the light block's `direction` that matches it (from the
//! sun towards the scene). The sun is the luminance-weighted centroid of the texels brighter
//! than half the peak; the map's luminance percentiles say what an exposure would clip.
//!
//! ```text
//! cargo run -p renderer --example map_sun -- /path/to/CedarCity.hdr
//! ```

use anyhow::{Context, Result};
use std::f64::consts::PI;

fn main() -> Result<()> {
    let path = std::env::args().nth(1).context("usage: map_sun MAP.hdr")?;
    let img = image::open(&path)
        .with_context(|| format!("cannot read {path}"))?
        .into_rgb32f();
    let (w, h) = img.dimensions();
    let lum: Vec<f64> = img
        .pixels()
        .map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64)
        .collect();
    let peak = lum.iter().cloned().fold(0.0, f64::max);
    let (mut sx, mut sy, mut sw) = (0.0, 0.0, 0.0);
    for (i, &l) in lum.iter().enumerate() {
        if l > 0.5 * peak {
            sx += (i as u32 % w) as f64 * l;
            sy += (i as u32 / w) as f64 * l;
            sw += l;
        }
    }
    let (u, v) = ((sx / sw + 0.5) / w as f64, (sy / sw + 0.5) / h as f64);
    let (phi, theta) = (2.0 * PI * (u - 0.5), PI * v);
    let sun = [
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    ];
    println!("{path}: {w} x {h}, peak luminance {peak:.2}");
    println!(
        "sun: u {u:.4}, v {v:.4}: azimuth {:.1} deg, elevation {:.1} deg",
        phi.to_degrees(),
        90.0 - theta.to_degrees()
    );
    println!(
        "light direction (from the sun): [{:.3}, {:.3}, {:.3}]",
        -sun[0], -sun[1], -sun[2]
    );
    let mut sorted = lum.clone();
    sorted.sort_by(f64::total_cmp);
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q) as usize];
    println!(
        "luminance: median {:.3}, 90% {:.3}, 99% {:.3}, 99.9% {:.3}",
        at(0.5),
        at(0.9),
        at(0.99),
        at(0.999)
    );
    Ok(())
}
