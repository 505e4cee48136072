//! Maximum likelihood for the multilevel model: Nelder-Mead over the parameter vector from a
//! few starts, then the covariance from the curvature of the log-likelihood at the optimum.

use super::model::{Bounds, Layout, Likelihood, Params};
use super::quadrature::Integral;
use crate::optimizer::{Tolerance, nelder_mead};

/// The maximum-likelihood estimate of one model.
#[derive(Clone, Debug)]
pub struct Estimate {
    pub layout: Layout,
    pub bounds: Bounds,
    pub vector: Vec<f64>,
    pub params: Params,
    pub log_likelihood: f64,
    /// Covariance of `vector` (inverse observed information); rows and columns of coordinates
    /// at a bound are 0. `None` when the curvature is not positive definite.
    pub covariance: Option<Vec<Vec<f64>>>,
    /// Each subject's offset given the data at the estimate (shrunken estimates).
    pub subjects: Vec<Integral>,
    /// The subjects' scores: the gradient of each subject's ln marginal likelihood at the
    /// estimate (rows in subject order; 0 at coordinates at a bound). Computed with the
    /// covariance; empty otherwise.
    pub scores: Vec<Vec<f64>>,
}

impl Estimate {
    /// Standard error of coordinate i, if the covariance exists and i is not at a bound.
    pub fn se(&self, i: usize) -> Option<f64> {
        let v = self.covariance.as_ref()?[i][i];
        (v > 0.0).then(|| v.sqrt())
    }

    /// The cluster-robust (sandwich) covariance with subjects as clusters, scaled by
    /// n / (n - 1) (CR1): C (sum_s g_s g_s^T) C n / (n - 1), C the model's covariance and g_s
    /// subject s's score. It needs neither the normal spread of the subjects nor the binomial
    /// model to be right, only independent subjects (Liang and Zeger 1986).
    pub fn robust_covariance(&self) -> Option<Vec<Vec<f64>>> {
        let c = self.covariance.as_ref()?;
        let n = self.scores.len();
        if n < 2 {
            return None;
        }
        let d = c.len();
        let mut meat = vec![vec![0.0; d]; d];
        for g in &self.scores {
            for i in 0..d {
                for j in 0..d {
                    meat[i][j] += g[i] * g[j];
                }
            }
        }
        let scale = n as f64 / (n - 1) as f64;
        let product = |a: &[Vec<f64>], b: &[Vec<f64>]| -> Vec<Vec<f64>> {
            (0..d)
                .map(|i| {
                    (0..d)
                        .map(|j| (0..d).map(|k| a[i][k] * b[k][j]).sum())
                        .collect()
                })
                .collect()
        };
        let v = product(&product(c, &meat), c);
        Some(
            v.into_iter()
                .map(|r| r.into_iter().map(|x| scale * x).collect())
                .collect(),
        )
    }

    /// The robust standard error of coordinate i ([`Self::robust_covariance`]).
    pub fn robust_se(&self, i: usize) -> Option<f64> {
        let v = self.robust_covariance()?[i][i];
        (v > 0.0).then(|| v.sqrt())
    }
}

/// Maximise the likelihood from each start (then once more from the best point); the
/// covariance only when asked (a bootstrap replicate needs the estimate alone).
pub fn estimate(
    lik: &Likelihood,
    layout: Layout,
    starts: &[Vec<f64>],
    with_covariance: bool,
) -> Estimate {
    let bounds = Bounds::new(lik.counts);
    let f = |v: &[f64]| -lik.ln_value(&layout.params(v, &bounds));
    let (v, value) = if with_covariance {
        let mut best: Option<(Vec<f64>, f64)> = None;
        for s in starts {
            let r = minimise(&f, s, 0.5, Tolerance::default());
            if best.as_ref().is_none_or(|b| r.1 < b.1) {
                best = Some(r);
            }
        }
        let (v, _) = best.expect("at least one start");
        minimise(&f, &v, 0.1, Tolerance::default())
    } else {
        // A bootstrap replicate from the original estimate: one small simplex, stopped once
        // the parameters are known to 1e-4 (a thousandth of their standard errors).
        let tol = Tolerance {
            value: 1e-9,
            position: 1e-4,
            max_evaluations: 1500,
        };
        minimise(&f, &starts[0], 0.2, tol)
    };
    let params = layout.params(&v, &bounds);
    let fixed = layout.at_bound(&v, &bounds);
    let per_subject = |w: &[f64]| -> Vec<f64> {
        let p = layout.params(w, &bounds);
        lik.subjects(&p).iter().map(|i| i.ln_value).collect()
    };
    let subjects = lik.subjects(&params);
    Estimate {
        covariance: if with_covariance {
            covariance(&f, &v, &fixed)
        } else {
            None
        },
        scores: if with_covariance {
            scores(&per_subject, subjects.len(), &v, &fixed)
        } else {
            Vec::new()
        },
        subjects,
        layout,
        bounds,
        vector: v,
        params,
        log_likelihood: -value,
    }
}

/// Nelder-Mead over a vector of 2 to 6 coordinates (one or two groups, lapse fixed or free;
/// 2 for a one-group model with its threshold held, [`super::profile`]).
pub(super) fn minimise(f: &Objective, start: &[f64], edge: f64, tol: Tolerance) -> (Vec<f64>, f64) {
    fn run<const N: usize>(f: &Objective, s: &[f64], edge: f64, tol: Tolerance) -> (Vec<f64>, f64) {
        let start: [f64; N] = s.try_into().expect("length matched");
        let m = nelder_mead(&mut |x: &[f64; N]| f(x), start, edge, tol);
        (m.x.to_vec(), m.value)
    }
    match start.len() {
        2 => run::<2>(f, start, edge, tol),
        3 => run::<3>(f, start, edge, tol),
        4 => run::<4>(f, start, edge, tol),
        5 => run::<5>(f, start, edge, tol),
        6 => run::<6>(f, start, edge, tol),
        n => unreachable!("a multilevel model has 3 to 6 parameters (2 to 5 held), not {n}"),
    }
}

/// The negative log-likelihood over the parameter vector.
pub(super) type Objective<'a> = dyn Fn(&[f64]) -> f64 + 'a;

/// Inverse of the numerical Hessian of `f` (the negative log-likelihood) over the coordinates
/// not `fixed`; central differences with step 2e-3 (the parameters are in ln units).
fn covariance(f: &Objective, v: &[f64], fixed: &[bool]) -> Option<Vec<Vec<f64>>> {
    let free: Vec<usize> = (0..v.len()).filter(|&i| !fixed[i]).collect();
    let h = 2e-3;
    let at = |d: &[(usize, f64)]| {
        let mut w = v.to_vec();
        for &(i, s) in d {
            w[i] += s;
        }
        f(&w)
    };
    let f0 = f(v);
    let n = free.len();
    let mut hess = vec![vec![0.0; n]; n];
    for a in 0..n {
        let i = free[a];
        hess[a][a] = (at(&[(i, h)]) - 2.0 * f0 + at(&[(i, -h)])) / (h * h);
        for b in 0..a {
            let j = free[b];
            let d = at(&[(i, h), (j, h)]) - at(&[(i, h), (j, -h)]) - at(&[(i, -h), (j, h)])
                + at(&[(i, -h), (j, -h)]);
            hess[a][b] = d / (4.0 * h * h);
            hess[b][a] = hess[a][b];
        }
    }
    let inv = spd_inverse(&hess)?;
    let mut cov = vec![vec![0.0; v.len()]; v.len()];
    for a in 0..n {
        for b in 0..n {
            cov[free[a]][free[b]] = inv[a][b];
        }
    }
    Some(cov)
}

/// Each of the `n` subjects' gradient of its ln marginal likelihood at `v` by central
/// differences (step 2e-3, as the Hessian), 0 at the `fixed` coordinates.
fn scores(
    per_subject: &dyn Fn(&[f64]) -> Vec<f64>,
    n: usize,
    v: &[f64],
    fixed: &[bool],
) -> Vec<Vec<f64>> {
    let h = 2e-3;
    let mut g = vec![vec![0.0; v.len()]; n];
    for i in (0..v.len()).filter(|&i| !fixed[i]) {
        let mut w = v.to_vec();
        w[i] = v[i] + h;
        let up = per_subject(&w);
        w[i] = v[i] - h;
        let down = per_subject(&w);
        for s in 0..n {
            g[s][i] = (up[s] - down[s]) / (2.0 * h);
        }
    }
    g
}

/// The inverse of a symmetric positive definite matrix by Cholesky; `None` if it is not.
pub fn spd_inverse(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s = a[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    // Columns of L^-1 by forward substitution, then A^-1 = L^-T L^-1.
    let mut li = vec![vec![0.0; n]; n];
    #[allow(clippy::needless_range_loop)] // triangular index arithmetic reads clearest
    for c in 0..n {
        for i in c..n {
            let known: f64 = (c..i).map(|k| l[i][k] * li[k][c]).sum();
            li[i][c] = (f64::from(i == c) - known) / l[i][i];
        }
    }
    Some(
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (0..n).map(|k| li[k][i] * li[k][j]).sum())
                    .collect()
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spd_inverse_inverts_and_refuses_indefinite_matrices() {
        let a = vec![
            vec![4.0, 2.0, 0.6],
            vec![2.0, 5.0, 1.0],
            vec![0.6, 1.0, 3.0],
        ];
        let inv = spd_inverse(&a).unwrap();
        for (i, row) in a.iter().enumerate() {
            for j in 0..3 {
                let p: f64 = row.iter().zip(&inv).map(|(r, col)| r * col[j]).sum();
                assert!((p - f64::from(i == j)).abs() < 1e-14, "{i} {j} {p}");
            }
        }
        assert!(spd_inverse(&[vec![1.0, 2.0], vec![2.0, 1.0]]).is_none());
        assert!(spd_inverse(&[vec![0.0]]).is_none());
    }

    #[test]
    fn robust_covariance_is_the_scaled_sandwich() {
        // C = diag(2, 1), scores (1, 0), (-1, 2), (0, -2): meat [[2, -2], [-2, 8]], C meat C
        // = [[8, -4], [-4, 8]], times n / (n - 1) = 3/2.
        let e = Estimate {
            layout: Layout {
                groups: 1,
                shared_threshold: false,
                free_lapse: false,
            },
            bounds: Bounds {
                t: (0.0, 1.0),
                ln_beta: (0.0, 1.0),
                ln_sigma: (0.0, 1.0),
            },
            vector: vec![0.0; 2],
            params: Params {
                thresholds: vec![0.0],
                slopes: vec![1.0],
                sigma: 1.0,
                lapse: 0.0,
            },
            log_likelihood: 0.0,
            covariance: Some(vec![vec![2.0, 0.0], vec![0.0, 1.0]]),
            subjects: Vec::new(),
            scores: vec![vec![1.0, 0.0], vec![-1.0, 2.0], vec![0.0, -2.0]],
        };
        let v = e.robust_covariance().unwrap();
        assert_eq!(v, vec![vec![12.0, -6.0], vec![-6.0, 12.0]]);
        assert_eq!(e.robust_se(0), Some(12f64.sqrt()));
        let one = Estimate {
            scores: vec![vec![1.0, 0.0]],
            ..e
        };
        assert!(one.robust_covariance().is_none());
    }
}
