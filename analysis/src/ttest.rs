//! t-tests on per-subject proportions correct, with effect sizes and Holm's correction.
//!
//! Paired (the default: every subject saw every condition), Student (pooled variance) and
//! Welch (Satterthwaite degrees of freedom). Cohen's d follows the test: d_z = mean difference /
//! SD of the differences (paired), d_s = mean difference / pooled SD (Student), and
//! mean difference / sqrt((s1^2 + s2^2) / 2) (Welch). A test whose standard error is zero, or
//! with too few subjects, is undefined and says why; it never yields an infinite t.

use crate::student_t::two_sided_p;
use serde::Serialize;

/// Which t-test.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TestKind {
    Paired,
    Student,
    Welch,
}

renderer::named!(TestKind, "t-test", [
    Paired => "paired",
    Student => "student",
    Welch => "welch",
]);

impl TestKind {
    /// Which Cohen's d the test reports.
    pub fn effect_size_name(self) -> &'static str {
        match self {
            TestKind::Paired => "d_z (mean diff / sd of diffs)",
            TestKind::Student => "d_s (mean diff / pooled sd)",
            TestKind::Welch => "d_av (mean diff / sqrt of mean variance)",
        }
    }
}

/// A computed test statistic.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Statistic {
    pub t: f64,
    pub df: f64,
    /// Two-sided p-value.
    pub p: f64,
    /// Cohen's d of the kind the test names.
    pub d: f64,
}

/// One test's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TTest {
    pub kind: TestKind,
    /// Observations in each sample (pairs for the paired test).
    pub n1: usize,
    pub n2: usize,
    pub mean1: f64,
    pub mean2: f64,
    /// `Err(reason)` when the statistic is undefined.
    pub result: Result<Statistic, String>,
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// Sample variance (n - 1 denominator), two-pass for accuracy.
fn variance(x: &[f64]) -> f64 {
    let m = mean(x);
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (x.len() as f64 - 1.0)
}

/// All values equal up to rounding: their spread is at most 64 ulps of the largest magnitude.
/// Proportions correct that are mathematically equal can differ in the last bits (7/12 - 3/12
/// and 11/12 - 7/12 differ by 1 ulp), and their sample variance is then ~1e-33 instead of 0,
/// which would turn a zero-variance test into t ~ 1e16. Genuinely different proportions k/n
/// with n below a few thousand trials differ by far more than 64 ulps.
fn constant(x: &[f64]) -> bool {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let scale = lo.abs().max(hi.abs());
    hi - lo <= 64.0 * f64::EPSILON * scale
}

fn mean_or_zero(x: &[f64]) -> f64 {
    if x.is_empty() { 0.0 } else { mean(x) }
}

/// Run a test of `a` against `b` (t > 0 when a's mean is larger). For the paired test `a[i]`
/// and `b[i]` belong to the same subject and the lengths must match.
pub fn t_test(kind: TestKind, a: &[f64], b: &[f64]) -> TTest {
    let result = match kind {
        TestKind::Paired => paired(a, b),
        TestKind::Student => student(a, b),
        TestKind::Welch => welch(a, b),
    };
    TTest {
        kind,
        n1: a.len(),
        n2: b.len(),
        mean1: mean_or_zero(a),
        mean2: mean_or_zero(b),
        result,
    }
}

fn paired(a: &[f64], b: &[f64]) -> Result<Statistic, String> {
    if a.len() != b.len() {
        return Err(format!(
            "paired samples of different sizes ({} and {})",
            a.len(),
            b.len()
        ));
    }
    let n = a.len();
    if n < 2 {
        return Err(format!(
            "{n} paired subject(s); a paired t-test needs at least 2"
        ));
    }
    let diff: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let (m, v) = (mean(&diff), variance(&diff));
    if constant(&diff) {
        let scale = a.iter().chain(b).fold(0.0f64, |s, v| s.max(v.abs()));
        let zero = m.abs() <= 64.0 * f64::EPSILON * scale;
        return Err(format!(
            "zero variance: every subject's difference is {}, so t is {}",
            if zero { 0.0 } else { m },
            if zero { "0/0" } else { "infinite" }
        ));
    }
    let t = m / (v / n as f64).sqrt();
    let df = (n - 1) as f64;
    Ok(Statistic {
        t,
        df,
        p: two_sided_p(t, df),
        d: m / v.sqrt(),
    })
}

fn student(a: &[f64], b: &[f64]) -> Result<Statistic, String> {
    let (n1, n2) = (a.len(), b.len());
    if n1 < 2 || n2 < 2 {
        return Err(format!(
            "samples of {n1} and {n2}; Student's t-test needs at least 2 in each"
        ));
    }
    let (v1, v2) = (variance(a), variance(b));
    let df = (n1 + n2 - 2) as f64;
    let pooled = ((n1 - 1) as f64 * v1 + (n2 - 1) as f64 * v2) / df;
    if constant(a) && constant(b) {
        return Err("zero variance: both samples are constant".into());
    }
    let md = mean(a) - mean(b);
    let t = md / (pooled * (1.0 / n1 as f64 + 1.0 / n2 as f64)).sqrt();
    Ok(Statistic {
        t,
        df,
        p: two_sided_p(t, df),
        d: md / pooled.sqrt(),
    })
}

fn welch(a: &[f64], b: &[f64]) -> Result<Statistic, String> {
    let (n1, n2) = (a.len(), b.len());
    if n1 < 2 || n2 < 2 {
        return Err(format!(
            "samples of {n1} and {n2}; Welch's t-test needs at least 2 in each"
        ));
    }
    let (v1, v2) = (variance(a), variance(b));
    let (s1, s2) = (v1 / n1 as f64, v2 / n2 as f64);
    let se2 = s1 + s2;
    if constant(a) && constant(b) {
        return Err("zero variance: both samples are constant".into());
    }
    let df = se2 * se2 / (s1 * s1 / (n1 - 1) as f64 + s2 * s2 / (n2 - 1) as f64);
    let md = mean(a) - mean(b);
    let t = md / se2.sqrt();
    Ok(Statistic {
        t,
        df,
        p: two_sided_p(t, df),
        d: md / (0.5 * (v1 + v2)).sqrt(),
    })
}

/// Holm's step-down adjustment over a family; `None` entries (undefined tests) are not part of
/// the family and stay `None`.
pub fn holm(p: &[Option<f64>]) -> Vec<Option<f64>> {
    let mut idx: Vec<usize> = (0..p.len()).filter(|&i| p[i].is_some()).collect();
    idx.sort_by(|&a, &b| p[a].unwrap_or(1.0).total_cmp(&p[b].unwrap_or(1.0)));
    let m = idx.len();
    let mut out = vec![None; p.len()];
    let mut running = 0.0f64;
    for (rank, &i) in idx.iter().enumerate() {
        let adj = ((m - rank) as f64 * p[i].unwrap_or(1.0)).min(1.0);
        running = running.max(adj);
        out[i] = Some(running);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // Student (1908) / Cushny & Peebles: extra hours of sleep with two drugs, 10 patients
    // (R's `sleep` data). Published results (R 4.x, t.test):
    //   paired:  t = -4.0621, df = 9, p-value = 0.002833
    //   Welch:   t = -1.8608, df = 17.776, p-value = 0.07939
    //   Student: t = -1.8608, df = 18, p-value = 0.07919
    const DRUG1: [f64; 10] = [0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0];
    const DRUG2: [f64; 10] = [1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4];

    fn stat(t: &TTest) -> Statistic {
        t.result.clone().expect("defined")
    }

    #[test]
    fn sleep_data_paired() {
        let s = stat(&t_test(TestKind::Paired, &DRUG1, &DRUG2));
        // Published values are rounded to the digits shown: half a unit in the last place.
        assert!((s.t + 4.0621).abs() < 5e-5, "{s:?}");
        assert_eq!(s.df, 9.0);
        assert!((s.p - 0.002833).abs() < 5e-7, "{s:?}");
        // d_z = mean diff / sd diff = -1.58 / 1.2299955 = -1.284558 (hand computation).
        assert!((s.d + 1.58 / 1.229_995_5).abs() < 1e-6, "{s:?}");
    }

    #[test]
    fn sleep_data_welch_and_student() {
        let w = stat(&t_test(TestKind::Welch, &DRUG1, &DRUG2));
        assert!((w.t + 1.8608).abs() < 5e-5, "{w:?}");
        assert!((w.df - 17.776).abs() < 5e-4, "{w:?}");
        assert!((w.p - 0.07939).abs() < 5e-6, "{w:?}");
        let s = stat(&t_test(TestKind::Student, &DRUG1, &DRUG2));
        assert!((s.t + 1.8608).abs() < 5e-5, "{s:?}");
        assert_eq!(s.df, 18.0);
        assert!((s.p - 0.07919).abs() < 5e-6, "{s:?}");
    }

    #[test]
    fn zero_variance_is_undefined_with_a_reason() {
        let a = [0.75, 0.5, 1.0];
        let same = t_test(TestKind::Paired, &a, &a);
        assert!(same.result.unwrap_err().contains("zero variance"));
        let shifted: Vec<f64> = a.iter().map(|v| v - 0.25).collect();
        let r = t_test(TestKind::Paired, &a, &shifted).result.unwrap_err();
        assert!(r.contains("infinite"), "{r}");
        let c = [1.0, 1.0, 1.0];
        assert!(t_test(TestKind::Student, &c, &c).result.is_err());
        assert!(t_test(TestKind::Welch, &c, &c).result.is_err());
        assert!(t_test(TestKind::Paired, &[1.0], &[0.5]).result.is_err());
        // Differences equal in exact arithmetic (4/12 each) but not in floating point: the
        // sample variance comes out ~1e-33, which must not become t ~ 1e16.
        let a: Vec<f64> = [7.0, 5.0, 9.0, 11.0].iter().map(|k| k / 12.0).collect();
        let b: Vec<f64> = [3.0, 1.0, 5.0, 7.0].iter().map(|k| k / 12.0).collect();
        assert!(a.iter().zip(&b).any(|(x, y)| x - y != a[0] - b[0]));
        let r = t_test(TestKind::Paired, &a, &b).result.unwrap_err();
        assert!(r.contains("zero variance") && r.contains("infinite"), "{r}");
        let tenth = [0.1, 0.1, 0.1];
        assert!(
            t_test(TestKind::Welch, &tenth, &[0.3, 0.3, 0.3])
                .result
                .is_err()
        );
        assert!(
            t_test(TestKind::Student, &tenth, &[0.3, 0.3, 0.3])
                .result
                .is_err()
        );
        // One constant sample is fine for Student and Welch (the other carries the variance).
        assert!(
            t_test(TestKind::Welch, &tenth, &[0.2, 0.3, 0.4])
                .result
                .is_ok()
        );
        assert!(t_test(TestKind::Welch, &[], &[0.5, 0.7]).result.is_err());
    }

    #[test]
    fn holm_matches_hand_computation() {
        // Sorted p: 0.01, 0.02, 0.04 (m = 3) -> 0.03, 0.04, 0.04 (monotone), undefined kept.
        let adj = holm(&[Some(0.04), None, Some(0.01), Some(0.02)]);
        let want = [Some(0.04), None, Some(0.03), Some(0.04)];
        for (a, w) in adj.iter().zip(want) {
            match (a, w) {
                (Some(a), Some(w)) => assert!((a - w).abs() < 1e-15),
                (None, None) => {}
                _ => panic!("{adj:?}"),
            }
        }
        assert_eq!(holm(&[Some(0.6), Some(0.9)]), vec![Some(1.0), Some(1.0)]);
    }
}
