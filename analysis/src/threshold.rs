//! A threshold as the data support it, and the empirical crossing: where observed proportions,
//! joined by straight lines in ln spp, fall through the target. Apart from [`crate::jnd`] (the
//! fitted function's threshold) because the fitter's starts read the empirical crossing: this
//! module imports nothing of the fitter, so `psychometric -> starts -> threshold` is no cycle.

use crate::data::Curve;
use serde::Serialize;

/// A threshold as the data support it.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Threshold {
    /// Crosses the target at this spp, inside the tested range.
    Value { spp: f64 },
    /// A step: the crossing lies between these two tested levels (exclusive of `upper`).
    Between { lower: u32, upper: u32 },
    /// A step through a tested level: the likelihood is maximised by an infinitely steep
    /// function passing exactly through `level` (its fitted proportion strictly between the
    /// plateaus), so the crossing is that level. `lower` and `upper` bracket the step: the
    /// neighbouring tested levels (the level itself at an end of the tested range).
    AtLevel { level: u32, lower: u32, upper: u32 },
    /// Already below the target at the lowest tested level.
    BelowRange { bound: u32 },
    /// Still above the target at the highest tested level.
    AboveRange { bound: u32 },
    /// No threshold can be read (no data).
    Undefined { reason: String },
}

impl Threshold {
    pub fn kind(&self) -> &'static str {
        match self {
            Threshold::Value { .. } => "value",
            Threshold::Between { .. } => "between",
            Threshold::AtLevel { .. } => "at_level",
            Threshold::BelowRange { .. } => "below_range",
            Threshold::AboveRange { .. } => "above_range",
            Threshold::Undefined { .. } => "undefined",
        }
    }

    /// A short human reading: "41.3", "27-64", "64 [27-125]", "< 1", "> 512",
    /// "undefined (...)".
    pub fn display(&self) -> String {
        match self {
            Threshold::Value { spp } => format!("{spp:.1}"),
            Threshold::Between { lower, upper } => format!("{lower}-{upper}"),
            Threshold::AtLevel {
                level,
                lower,
                upper,
            } => format!("{level} [{lower}-{upper}]"),
            Threshold::BelowRange { bound } => format!("< {bound}"),
            Threshold::AboveRange { bound } => format!("> {bound}"),
            Threshold::Undefined { reason } => format!("undefined ({reason})"),
        }
    }

    /// The threshold as a number of spp, when it is one (a value, or a step through a level).
    pub fn spp(&self) -> Option<f64> {
        match self {
            Threshold::Value { spp } => Some(*spp),
            Threshold::AtLevel { level, .. } => Some(*level as f64),
            _ => None,
        }
    }

    /// The range of ln spp the threshold may occupy, for ordering bootstrap replicates:
    /// below range is -inf, above range +inf, an interval its two ends.
    pub fn ln_bounds(&self) -> Option<(f64, f64)> {
        match self {
            Threshold::Value { spp } => Some((spp.ln(), spp.ln())),
            Threshold::Between { lower, upper } => {
                Some(((*lower as f64).ln(), (*upper as f64).ln()))
            }
            Threshold::AtLevel { level, .. } => Some(((*level as f64).ln(), (*level as f64).ln())),
            Threshold::BelowRange { .. } => Some((f64::NEG_INFINITY, f64::NEG_INFINITY)),
            Threshold::AboveRange { .. } => Some((f64::INFINITY, f64::INFINITY)),
            Threshold::Undefined { .. } => None,
        }
    }
}

/// The thesis's reading: where the empirical curve (observed proportions joined by straight
/// lines in ln spp) first falls through the target.
pub fn empirical_threshold(curve: &Curve, target: f64) -> Threshold {
    let points: Vec<(u32, f64)> = curve
        .points
        .iter()
        .map(|p| (p.level, p.proportion()))
        .collect();
    crossing(&points, target)
}

/// Where a curve of (level, proportion) points, sorted by level and joined by straight lines in
/// ln spp, first falls through the target; out of range with the bound when it never does.
pub fn crossing(points: &[(u32, f64)], target: f64) -> Threshold {
    let (Some(&(first, p_first)), Some(&(last, _))) = (points.first(), points.last()) else {
        return Threshold::Undefined {
            reason: "no trials".into(),
        };
    };
    if p_first < target {
        return Threshold::BelowRange { bound: first };
    }
    for w in points.windows(2) {
        let ((l0, p0), (l1, p1)) = (w[0], w[1]);
        if p0 >= target && p1 < target {
            let (x0, x1) = ((l0 as f64).ln(), (l1 as f64).ln());
            let f = (p0 - target) / (p0 - p1);
            return Threshold::Value {
                spp: (x0 + f * (x1 - x0)).exp(),
            };
        }
    }
    Threshold::AboveRange { bound: last }
}
