//! Comparisons from the multilevel model: for each pair of scenes, point sets (or time
//! filters), one model of both groups with each subject's offset shared between them, the
//! difference of their population ln JNDs with a Wald interval and test, a likelihood-ratio
//! test against the model with one threshold for both, a subject-bootstrap interval, and
//! with a margin the two one-sided tests (TOST) of equivalence for point sets and time filters.
//!
//! The shared offset is the model's assumption: a subject more sensitive in one scene is as
//! much more sensitive in the other (no subject x group interaction). The subject bootstrap
//! does not assume it: resampling whole subjects keeps each subject's two curves together.

use super::subjects::{SubjectBootstrap, replicates, summarize};
use super::{Context, Estimate, fit_informative, informative, t_quantile};
use crate::comparisons::PairOrder;
use crate::data::{Curve, Dataset, Group, Grouping};
use crate::sigmoid::erfc;
use crate::student_t::{sf, two_sided_p};
use renderer::hash::name_id;
use serde::Serialize;

/// The two one-sided tests of |difference| < margin.
#[derive(Clone, Debug, Serialize)]
pub struct Equivalence {
    /// The margin in ln JND (0.2: +-22%).
    pub margin: f64,
    /// The 90% Wald interval (1 - 2 x 0.05) of the difference.
    pub lower: f64,
    pub upper: f64,
    /// max of the two one-sided p-values; equivalence is shown when it is below 0.05, i.e. when
    /// the 90% interval lies inside (-margin, margin).
    pub p: f64,
    pub equivalent: bool,
}

/// The size of the TOST: each one-sided test at this level.
pub const TOST_ALPHA: f64 = 0.05;

/// One pair's model-based comparison.
#[derive(Clone, Debug, Serialize)]
pub struct ModelComparison {
    pub family: Grouping,
    pub a: String,
    pub b: String,
    pub subjects: usize,
    /// ln JND(a) - ln JND(b): > 0 when a needs more spp.
    pub difference: f64,
    pub se: Option<f64>,
    /// Wald interval at the settings' confidence, Student t with subjects - 1 df.
    pub ci_lower: Option<f64>,
    pub ci_upper: Option<f64>,
    pub wald_t: Option<f64>,
    pub wald_p: Option<f64>,
    /// 2 (ln L(model) - ln L(one threshold for both)), and its chi-square (1 df) p.
    pub lr: f64,
    pub lr_p: f64,
    pub bootstrap: Option<SubjectBootstrap>,
    pub equivalence: Option<Equivalence>,
}

/// Every pair within each family present in the data, in the t-tests' pair order.
pub fn compare_models(ds: &Dataset, order: &PairOrder, cx: &Context) -> Vec<ModelComparison> {
    let mut out = Vec::new();
    for family in [Grouping::Scene, Grouping::PointSet, Grouping::TimeFilter] {
        let mut groups: Vec<&Group> = ds.groups_of(family).collect();
        groups.sort_by_key(|g| (order.rank(family, &g.key.label), &g.key.label));
        for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                out.extend(compare_pair(family, groups[i], groups[j], cx));
            }
        }
    }
    out
}

/// The comparison of two groups of one family; `None` when the model is not identified.
pub fn compare_pair(
    family: Grouping,
    a: &Group,
    b: &Group,
    cx: &Context,
) -> Option<ModelComparison> {
    let kept = [a, b].map(|g| informative(&g.per_subject, cx.same_video_levels));
    let curves: [&[Curve]; 2] = [&kept[0], &kept[1]];
    let (full, counts) = fit_informative(&curves, false, cx, None)?;
    let (null, _) = fit_informative(&curves, true, cx, None)?;
    let n = counts.subjects.len();
    let df = (n - 1) as f64;
    let (d, se) = difference(&full);
    let tq = t_quantile(1.0 - 0.5 * (1.0 - cx.settings.confidence), df);
    let lr = (2.0 * (full.log_likelihood - null.log_likelihood)).max(0.0);
    let key = name_id(&format!(
        "{}:{}|{}",
        family.name(),
        a.key.label,
        b.key.label
    ));
    let bootstrap = (cx.settings.resamples > 0)
        .then(|| {
            let reps = replicates(&curves, false, cx, &full.vector, key, |e| {
                e.params.thresholds[0] - e.params.thresholds[1]
            });
            summarize(reps, cx.settings.resamples, cx.settings.confidence)
        })
        .flatten();
    Some(ModelComparison {
        family,
        a: a.key.label.clone(),
        b: b.key.label.clone(),
        subjects: n,
        difference: d,
        se,
        ci_lower: se.map(|s| d - tq * s),
        ci_upper: se.map(|s| d + tq * s),
        wald_t: se.map(|s| d / s),
        wald_p: se.map(|s| two_sided_p(d / s, df)),
        lr,
        // P(chi2_1 >= lr) = erfc(sqrt(lr / 2)).
        lr_p: erfc((0.5 * lr).sqrt()),
        bootstrap,
        // Scenes are chosen to differ; equivalence is asked of point sets and time filters.
        equivalence: (family != Grouping::Scene)
            .then_some(cx.settings.equivalence)
            .flatten()
            .zip(se)
            .map(|(m, s)| tost(d, s, df, m)),
    })
}

/// The first group's ln JND minus the second's in a two-group model, and its Wald standard
/// error (`None` without a covariance).
pub fn difference(e: &Estimate) -> (f64, Option<f64>) {
    let d = e.params.thresholds[0] - e.params.thresholds[1];
    let se = e.covariance.as_ref().and_then(|c| {
        let v = c[0][0] + c[1][1] - 2.0 * c[0][1];
        (v > 0.0).then(|| v.sqrt())
    });
    (d, se)
}

/// Two one-sided tests of |d| < margin at [`TOST_ALPHA`] each, from an estimate `d` with
/// standard error `se` and Student t with `df` degrees of freedom.
pub fn tost(d: f64, se: f64, df: f64, margin: f64) -> Equivalence {
    let p_low = sf((d + margin) / se, df);
    let p_high = sf((margin - d) / se, df);
    let q = t_quantile(1.0 - TOST_ALPHA, df);
    let p = p_low.max(p_high);
    Equivalence {
        margin,
        lower: d - q * se,
        upper: d + q * se,
        p,
        equivalent: p < TOST_ALPHA,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tost_is_the_90_percent_interval_inside_the_margin() {
        // df 11: t_0.95 = 1.795884818704 (published tables: 1.796).
        let e = tost(0.05, 0.05, 11.0, 0.2);
        assert!((e.upper - e.lower - 2.0 * 1.795_884_818_704 * 0.05).abs() < 1e-9);
        assert!(e.equivalent && e.upper < 0.2 && e.lower > -0.2);
        // The interval's end on the margin is p = 0.05 exactly.
        let q = t_quantile(0.95, 11.0);
        let edge = tost(0.2 - q * 0.05, 0.05, 11.0, 0.2);
        assert!((edge.p - 0.05).abs() < 1e-9, "{edge:?}");
        // Far from zero, or too uncertain: not shown.
        assert!(!tost(0.25, 0.01, 11.0, 0.2).equivalent);
        assert!(!tost(0.0, 0.2, 11.0, 0.2).equivalent);
    }
}
