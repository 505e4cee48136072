//! Exploring the CSF's shape on ModelFest (issue 25, fifth pass): the responses of the 43
//! stimuli over a grid of poolings and CSF shapes ([`analysis::observer::model::shape::Shape`]),
//! written once to a CSV file and refitted from it, so that a grid is paid for once and
//! profiled and restricted at will.
//!
//! `cargo run -p analysis --example modelfest_shapes -- DIR RESPONSES.csv [name=v1,v2,...]...`
//!
//! Names: `beta`, `ap` (aperture sd, deg; `inf` for none), `w`, `c`, `centre`, `fh` (roll-off
//! frequency, cpd; `inf` for none), `p` (roll-off power), `s` (frequency scale). If
//! RESPONSES.csv exists it is read and the names restrict its grid; otherwise the grid they
//! span (defaults: the committed model's point) is computed and written. Printed: the fit on
//! all 43 stimuli, its leave-one-out RMS (refitting every free parameter), each parameter's
//! profile (best in-sample RMS with that parameter held) and the left-out fits that move away
//! from the full fit's point (what one stimulus alone identifies).

use analysis::observer::datasets::modelfest::fit::{
    Params, Responses, fit, markdown, responses, validate,
};
use analysis::observer::datasets::modelfest::{Stimulus, load};
use analysis::observer::model::pooling::{Grid, Pooling};
use analysis::observer::model::shape::{FITTED, Shape};
use anyhow::{Context, Result, bail};
use renderer::progress::NoProgress;
use std::collections::BTreeMap;
use std::path::Path;

/// The names of a point's coordinates, in the CSV's order.
const NAMES: [&str; 8] = ["beta", "ap", "w", "c", "centre", "fh", "p", "s"];

fn coordinates(p: &Params) -> [f64; 8] {
    let (pl, sh) = (p.pooling, p.shape);
    [
        pl.space,
        pl.aperture_deg,
        sh.oblique,
        sh.narrowing,
        sh.centre_cpd,
        sh.rolloff_cpd,
        sh.rolloff_power,
        sh.scale,
    ]
}

fn point(x: &[f64]) -> Params {
    Params {
        pooling: Pooling {
            channels: 2.0,
            space: x[0],
            aperture_deg: x[1],
        },
        shape: Shape {
            oblique: x[2],
            narrowing: x[3],
            centre_cpd: x[4],
            rolloff_cpd: x[5],
            rolloff_power: x[6],
            scale: x[7],
        },
    }
}

/// `name=v1,v2` arguments; every name gets its values or the committed model's.
fn axes(args: &[String]) -> Result<BTreeMap<&'static str, Vec<f64>>> {
    let committed = coordinates(&Params {
        shape: FITTED,
        pooling: analysis::observer::model::pooling::FITTED,
    });
    let mut out: BTreeMap<&'static str, Vec<f64>> = NAMES
        .iter()
        .zip(committed)
        .map(|(&n, v)| (n, vec![v]))
        .collect();
    for a in args {
        let (name, list) = a.split_once('=').context("expected name=v1,v2,...")?;
        let Some(&key) = NAMES.iter().find(|&&n| n == name) else {
            bail!("unknown name {name}; expected one of {NAMES:?}");
        };
        let values = list
            .split(',')
            .map(|v| match v {
                "inf" => Ok(f64::INFINITY),
                _ => v.parse::<f64>().with_context(|| format!("{name}: {v}")),
            })
            .collect::<Result<_>>()?;
        out.insert(key, values);
    }
    Ok(out)
}

fn compute(stimuli: &[Stimulus], axes: &BTreeMap<&str, Vec<f64>>) -> Result<Responses> {
    let grid = Grid {
        channels: vec![2.0],
        space: axes["beta"].clone(),
        apertures: axes["ap"].clone(),
    };
    let mut shapes = vec![];
    for &w in &axes["w"] {
        for &c in &axes["c"] {
            for &centre in &axes["centre"] {
                for &fh in &axes["fh"] {
                    for &p in &axes["p"] {
                        for &s in &axes["s"] {
                            shapes.push(point(&[0.0, 0.0, w, c, centre, fh, p, s]).shape);
                        }
                    }
                }
            }
        }
    }
    responses(stimuli, &grid, &shapes, &NoProgress)
}

fn write(path: &Path, r: &Responses) -> Result<()> {
    let mut s = String::new();
    for (j, p) in r.pairs.iter().enumerate() {
        let mut row: Vec<String> = coordinates(p).iter().map(|v| v.to_string()).collect();
        row.extend(r.q1.iter().map(|q| q[j].to_string()));
        s.push_str(&row.join(","));
        s.push('\n');
    }
    renderer::atomic::write_atomic(path, s.as_bytes())
}

fn read(path: &Path, n: usize) -> Result<Responses> {
    let text = std::fs::read_to_string(path)?;
    let mut pairs = vec![];
    let mut q1 = vec![vec![]; n];
    for line in text.lines() {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.parse::<f64>())
            .collect::<Result<_, _>>()?;
        pairs.push(point(&v[..8]));
        for (i, q) in v[8..].iter().enumerate() {
            q1[i].push(*q);
        }
    }
    Ok(Responses { pairs, q1 })
}

/// The points of `r` whose coordinates lie in `axes` (only the names given on the command line).
fn restrict(r: &Responses, keep: impl Fn(&[f64; 8]) -> bool) -> Responses {
    let js: Vec<usize> = (0..r.pairs.len())
        .filter(|&j| keep(&coordinates(&r.pairs[j])))
        .collect();
    Responses {
        pairs: js.iter().map(|&j| r.pairs[j]).collect(),
        q1: r
            .q1
            .iter()
            .map(|q| js.iter().map(|&j| q[j]).collect())
            .collect(),
    }
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        bail!("usage: modelfest_shapes DIR RESPONSES.csv [name=v1,v2,...]...");
    }
    let stimuli = load(Path::new(&args[0]))?;
    let path = Path::new(&args[1]);
    let given: Vec<&str> = args[2..]
        .iter()
        .filter_map(|a| a.split_once('=').map(|x| x.0))
        .collect();
    let axes = axes(&args[2..])?;
    let r = if path.exists() {
        let all = read(path, stimuli.len())?;
        restrict(&all, |x| {
            NAMES
                .iter()
                .enumerate()
                .all(|(i, n)| !given.contains(n) || axes[n].contains(&x[i]))
        })
    } else {
        let t = std::time::Instant::now();
        let r = compute(&stimuli, &axes)?;
        write(path, &r)?;
        eprintln!(
            "{} points x {} stimuli in {:.1} s",
            r.pairs.len(),
            stimuli.len(),
            t.elapsed().as_secs_f64()
        );
        r
    };
    let v = validate(&stimuli, &r)?;
    println!("{}\n", markdown(&v));
    println!(
        "points {}; RMS {:.3} dB, leave-one-out {:.3} dB",
        r.pairs.len(),
        v.rms_db(),
        v.loo_rms_db()
    );
    let measured: Vec<f64> = stimuli.iter().map(|s| s.measured).collect();
    let all: Vec<usize> = (0..stimuli.len()).collect();
    let best = coordinates(&v.fit.params);
    for (i, name) in NAMES.iter().enumerate() {
        let mut values = axes[name].clone();
        values.sort_by(f64::total_cmp);
        values.dedup();
        if values.len() < 2 {
            continue;
        }
        let profile: Vec<String> = values
            .iter()
            .filter_map(|&value| {
                let sub = restrict(&r, |x| x[i] == value);
                let f = fit(&measured, &sub, &all).ok()?;
                Some(format!("{value}: {:.3}", 20.0 * f.rms_log10))
            })
            .collect();
        println!("profile {name}: {}", profile.join(", "));
    }
    for (i, s) in stimuli.iter().enumerate() {
        let rest: Vec<usize> = all.iter().copied().filter(|&j| j != i).collect();
        let f = fit(&measured, &r, &rest)?;
        let x = coordinates(&f.params);
        let moved: Vec<String> = NAMES
            .iter()
            .enumerate()
            .filter(|&(j, _)| x[j] != best[j])
            .map(|(j, n)| format!("{n} {}", x[j]))
            .collect();
        if !moved.is_empty() {
            println!(
                "#{} left out: {} (error {:+.2} dB)",
                s.number,
                moved.join(", "),
                v.lines[i].left_out * 20.0 - v.lines[i].measured * 20.0
            );
        }
    }
    Ok(())
}
