//! Where the likelihood search starts.
//!
//! The psychometric likelihood of few or non-monotone counts is multimodal: a steep function
//! has one local maximum per gap between levels it can fall in, the best point can lie on the
//! edge of the location range (the far tail of a sigmoid) on a ridge narrower than a coarse
//! grid, and where p is flat at every level (within 1e-6 of 0.5 or of 1 - lapse) the simplex
//! sees no slope at all and stops. Nelder-Mead from a few hand-picked starts was found stuck in
//! each of these ways by the stress test in `psychometric.rs`. So a cold fit starts from every
//! basin a data-adapted grid can see, from the edges of the location range and from every gap;
//! a warm refit (a bootstrap replicate, drawn from a monotone fit) from the previous optimum and
//! the best point of a small grid. Flat functions need no start: the closed-form step covers
//! them exactly.

use super::{Data, LAPSE_MAX, Model, Space};
use crate::data::Curve;
use crate::threshold::{Threshold, empirical_threshold};

/// Local maxima of the cold grid started from.
const BASINS: usize = 4;

/// A grid point: log-likelihood, flat at every level, unconstrained coordinates.
type Point = (f64, bool, [f64; 3]);

/// Log-likelihoods over locations x log-slopes for each lapse: `values[lapse][alpha][beta]`.
struct Grid {
    values: Vec<Vec<Vec<Point>>>,
}

impl Grid {
    fn new(space: &Space, data: &Data, alphas: &[f64], slopes: usize) -> Self {
        let values = lapses(space)
            .iter()
            .map(|&lapse| {
                alphas
                    .iter()
                    .map(|&a| {
                        (0..=slopes)
                            .map(|j| point(space, data, a, beta_at(space, j, slopes), lapse))
                            .collect()
                    })
                    .collect()
            })
            .collect();
        Grid { values }
    }

    fn best(&self) -> [f64; 3] {
        let all = self.values.iter().flatten().flatten();
        all.max_by(|a, b| a.0.total_cmp(&b.0))
            .expect("non-empty grid")
            .2
    }

    /// The most likely non-flat points that are at least as likely as their (up to 8)
    /// neighbours in location x log-slope.
    fn basins(&self, n: usize) -> Vec<[f64; 3]> {
        let mut maxima: Vec<&Point> = Vec::new();
        for slice in &self.values {
            for (i, row) in slice.iter().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    if !v.1 && is_local_max(slice, i, j) {
                        maxima.push(v);
                    }
                }
            }
        }
        maxima.sort_by(|a, b| b.0.total_cmp(&a.0));
        maxima.iter().take(n).map(|v| v.2).collect()
    }
}

fn is_local_max(slice: &[Vec<Point>], i: usize, j: usize) -> bool {
    let v = slice[i][j].0;
    let (i0, i1) = (i.saturating_sub(1), (i + 1).min(slice.len() - 1));
    let (j0, j1) = (j.saturating_sub(1), (j + 1).min(slice[i].len() - 1));
    (i0..=i1).all(|a| (j0..=j1).all(|b| slice[a][b].0 <= v))
}

fn lapses(space: &Space) -> &'static [f64] {
    if space.free_lapse {
        &[0.0, 0.5 * LAPSE_MAX, LAPSE_MAX]
    } else {
        &[0.0]
    }
}

/// `n + 1` locations evenly over the search range, bounds included.
fn even_alphas(space: &Space, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| space.mid + space.half * (2.0 * i as f64 / n as f64 - 1.0))
        .collect()
}

fn beta_at(space: &Space, j: usize, n: usize) -> f64 {
    (space.ln_b_lo + (space.ln_b_hi - space.ln_b_lo) * j as f64 / n as f64).exp()
}

fn point(space: &Space, data: &Data, alpha: f64, beta: f64, lapse: f64) -> Point {
    let m = Model {
        sigmoid: space.sigmoid,
        alpha,
        beta,
        lapse,
        guess: space.guess,
    };
    let (ll, flat) = data.log_likelihood_flat(&m);
    (ll, flat, space.coords(alpha, beta, lapse))
}

/// Starts of a warm refit besides the previous optimum: the best point of a 9 x 7 grid.
pub(super) fn warm(space: &Space, data: &Data) -> [f64; 3] {
    Grid::new(space, data, &even_alphas(space, 8), 6).best()
}

/// Starts of a cold fit: the best point of a grid of 41 log-slopes x locations evenly over the
/// range (25) plus every level and every gap's middle (where a steep function's modes lie);
/// its best non-flat local maxima; on each edge of the location range the best non-flat point
/// of a line of 81 log-slopes; the empirical crossing of (1 + g) / 2 (halfway from the guess
/// rate g to 1, 0.75 for two alternatives) with the function falling over about
/// a quarter of the span; and one start in every gap with the function falling across it
/// (z changes by 4 across the gap).
pub(super) fn cold(curve: &Curve, space: &Space, data: &Data) -> Vec<[f64; 3]> {
    let x = &data.x;
    let mut alphas = even_alphas(space, 24);
    alphas.extend(x);
    alphas.extend(x.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    alphas.sort_by(f64::total_cmp);
    alphas.dedup();
    let grid = Grid::new(space, data, &alphas, 40);
    let mut starts = vec![grid.best()];
    starts.extend(grid.basins(BASINS));
    let bounds = even_alphas(space, 1);
    let edge = Grid::new(space, data, &bounds, 80);
    for side in 0..bounds.len() {
        let line = edge.values.iter().flat_map(|slice| &slice[side]);
        let best = line.filter(|v| !v.1).max_by(|a, b| a.0.total_cmp(&b.0));
        starts.extend(best.map(|v| v.2));
    }
    let span = x[x.len() - 1] - x[0];
    if let Threshold::Value { spp } = empirical_threshold(curve, 0.5 * (1.0 + space.guess)) {
        starts.push(space.coords(spp.ln(), 8.0 / span, 0.01));
    }
    for w in x.windows(2) {
        let beta = (4.0 / (w[1] - w[0])).min(space.ln_b_hi.exp());
        starts.push(space.coords(0.5 * (w[0] + w[1]), beta, 0.01));
    }
    let mut unique: Vec<[f64; 3]> = Vec::with_capacity(starts.len());
    for s in starts {
        if !unique.contains(&s) {
            unique.push(s);
        }
    }
    unique
}
