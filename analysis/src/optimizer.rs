//! Nelder-Mead simplex minimisation in a few dimensions.
//!
//! The psychometric likelihood is minimised over an unconstrained reparameterisation (bounded
//! parameters are mapped through tanh / logistic), so a derivative-free simplex is robust: it
//! never divides by a vanishing Hessian on flat or separated data, and with a finite objective
//! it always returns a finite point. Standard coefficients (reflection 1, expansion 2,
//! contraction 1/2, shrink 1/2); a non-finite objective value is treated as +infinity.

/// Where a minimisation ended.
#[derive(Clone, Copy, Debug)]
pub struct Minimum<const N: usize> {
    pub x: [f64; N],
    pub value: f64,
    pub evaluations: usize,
}

/// Stopping rule: the simplex's spread in value and in position.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub value: f64,
    pub position: f64,
    pub max_evaluations: usize,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            value: 1e-11,
            position: 1e-7,
            max_evaluations: 1500,
        }
    }
}

fn guarded(v: f64) -> f64 {
    if v.is_nan() { f64::INFINITY } else { v }
}

/// Minimise `f` from `start` with an initial simplex of edge `step` along each axis.
pub fn nelder_mead<const N: usize>(
    f: &mut impl FnMut(&[f64; N]) -> f64,
    start: [f64; N],
    step: f64,
    tol: Tolerance,
) -> Minimum<N> {
    let mut evals = 0usize;
    let mut eval = |x: &[f64; N], evals: &mut usize| {
        *evals += 1;
        guarded(f(x))
    };
    // N + 1 vertices; stored in a Vec because const-generic `N + 1` arrays are not stable.
    let mut pts: Vec<[f64; N]> = Vec::with_capacity(N + 1);
    pts.push(start);
    for i in 0..N {
        let mut p = start;
        p[i] += step;
        pts.push(p);
    }
    let mut vals: Vec<f64> = pts.iter().map(|p| eval(p, &mut evals)).collect();
    loop {
        // Order best..worst.
        let mut order: Vec<usize> = (0..=N).collect();
        order.sort_by(|&a, &b| vals[a].total_cmp(&vals[b]));
        pts = order.iter().map(|&i| pts[i]).collect();
        vals = order.iter().map(|&i| vals[i]).collect();
        let spread_v = (vals[N] - vals[0]).abs();
        let spread_x = (1..=N)
            .flat_map(|i| (0..N).map(move |j| (i, j)))
            .map(|(i, j)| (pts[i][j] - pts[0][j]).abs())
            .fold(0.0, f64::max);
        let converged = vals[0].is_finite()
            && spread_v <= tol.value * (1.0 + vals[0].abs())
            && spread_x <= tol.position;
        if converged || evals >= tol.max_evaluations {
            break;
        }
        let mut centroid = [0.0; N];
        for p in &pts[..N] {
            for j in 0..N {
                centroid[j] += p[j] / N as f64;
            }
        }
        let along = |t: f64| {
            let mut q = [0.0; N];
            for j in 0..N {
                q[j] = centroid[j] + t * (pts[N][j] - centroid[j]);
            }
            q
        };
        let xr = along(-1.0);
        let fr = eval(&xr, &mut evals);
        if fr < vals[0] {
            let xe = along(-2.0);
            let fe = eval(&xe, &mut evals);
            if fe < fr {
                pts[N] = xe;
                vals[N] = fe;
            } else {
                pts[N] = xr;
                vals[N] = fr;
            }
            continue;
        }
        if fr < vals[N - 1] {
            pts[N] = xr;
            vals[N] = fr;
            continue;
        }
        // Contract outside (towards the reflected point) or inside.
        let (xc, fc) = if fr < vals[N] {
            let xc = along(-0.5);
            (xc, eval(&xc, &mut evals))
        } else {
            let xc = along(0.5);
            (xc, eval(&xc, &mut evals))
        };
        if fc < vals[N].min(fr) {
            pts[N] = xc;
            vals[N] = fc;
            continue;
        }
        // Shrink towards the best vertex.
        let best = pts[0];
        for (p, v) in pts.iter_mut().zip(vals.iter_mut()).skip(1) {
            for (pj, bj) in p.iter_mut().zip(best) {
                *pj = bj + 0.5 * (*pj - bj);
            }
            *v = eval(p, &mut evals);
        }
    }
    Minimum {
        x: pts[0],
        value: vals[0],
        evaluations: evals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_rosenbrock_minimum() {
        let mut f = |x: &[f64; 2]| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2);
        let tol = Tolerance {
            max_evaluations: 5000,
            ..Tolerance::default()
        };
        let m = nelder_mead(&mut f, [-1.2, 1.0], 0.5, tol);
        assert!(
            (m.x[0] - 1.0).abs() < 1e-4 && (m.x[1] - 1.0).abs() < 1e-4,
            "{m:?}"
        );
    }

    #[test]
    fn nan_objective_is_treated_as_infinite() {
        // NaN outside the unit disc; minimum of (x-0.3)^2 + y^2 inside.
        let mut f = |x: &[f64; 2]| {
            if x[0] * x[0] + x[1] * x[1] > 1.0 {
                f64::NAN
            } else {
                (x[0] - 0.3).powi(2) + x[1] * x[1]
            }
        };
        let m = nelder_mead(&mut f, [0.0, 0.0], 0.8, Tolerance::default());
        assert!(m.value.is_finite());
        assert!((m.x[0] - 0.3).abs() < 1e-4, "{m:?}");
    }

    #[test]
    fn flat_objective_stops_at_start() {
        let mut f = |_: &[f64; 3]| 1.0;
        let m = nelder_mead(&mut f, [1.0, 2.0, 3.0], 0.1, Tolerance::default());
        assert!(m.x.iter().all(|v| v.is_finite()));
        assert!(m.evaluations <= Tolerance::default().max_evaluations + 4);
    }
}
