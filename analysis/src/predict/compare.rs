//! Predicted against recovered JNDs: for every pooled group of an analysed simulation, the
//! JND its observer implies (the 0.75 crossing of the population's pooled curve: the cells'
//! mean proportion correct, subjects' factors integrated) next to the JND the analysis
//! recovered from the simulated sessions. With a predicted observer the first column is the
//! prediction from the stimuli.

use crate::data::Grouping;
use crate::jnd::Threshold;
use crate::plan::cells_of;
use crate::report::Report;
use experiment::psychometric::TARGET;
use experiment::{Design, Observer};
use std::fmt::Write as _;

/// One group's two JNDs.
#[derive(Clone, Debug)]
pub struct JndPair {
    pub grouping: Grouping,
    pub label: String,
    pub predicted: Threshold,
    pub recovered: Threshold,
    pub interval: Option<String>,
}

/// The population's pooled crossing of a group, never outside the design's levels.
pub fn population_jnd(
    design: &Design,
    observer: &Observer,
    grouping: Grouping,
    label: &str,
) -> Threshold {
    let cells = cells_of(design, grouping, label);
    let levels = &design.file.levels;
    let (Some(&lo), Some(&hi)) = (levels.iter().min(), levels.iter().max()) else {
        return Threshold::Undefined {
            reason: "no levels".into(),
        };
    };
    let mean = |spp: f64| -> Option<f64> {
        let mut s = 0.0;
        for c in &cells {
            s += observer.p_population(c, spp)?;
        }
        Some(s / cells.len().max(1) as f64)
    };
    let (Some(p_lo), Some(p_hi)) = (mean(lo as f64), mean(hi as f64)) else {
        return Threshold::Undefined {
            reason: "the observer does not cover the group".into(),
        };
    };
    if p_lo < TARGET {
        return Threshold::BelowRange { bound: lo };
    }
    if p_hi > TARGET {
        return Threshold::AboveRange { bound: hi };
    }
    let (mut a, mut b) = ((lo as f64).ln(), (hi as f64).ln());
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if mean(m.exp()).unwrap_or(0.5) > TARGET {
            a = m;
        } else {
            b = m;
        }
    }
    Threshold::Value {
        spp: (0.5 * (a + b)).exp(),
    }
}

/// Every pooled group of the report (scenes, point sets, time filters, conditions).
pub fn side_by_side(report: &Report, design: &Design, observer: &Observer) -> Vec<JndPair> {
    let order = [
        Grouping::Scene,
        Grouping::PointSet,
        Grouping::TimeFilter,
        Grouping::Condition,
    ];
    order
        .iter()
        .flat_map(|&grouping| report.groups_of(grouping))
        .map(|g| JndPair {
            grouping: g.key.grouping,
            label: g.key.label.clone(),
            predicted: population_jnd(design, observer, g.key.grouping, &g.key.label),
            recovered: g.threshold.clone(),
            interval: crate::bootstrap::interval_text(
                &g.bootstrap.ci_lower,
                &g.bootstrap.ci_upper,
                " to ",
            ),
        })
        .collect()
}

/// The pairs as a Markdown table.
pub fn markdown(pairs: &[JndPair], observer: &str) -> String {
    let mut s = format!(
        "| grouping | label | JND of the observer ({observer}) | recovered JND | 95% CI |\n|---|---|---|---|---|\n"
    );
    for p in pairs {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            p.grouping.name(),
            p.label,
            p.predicted.display(),
            p.recovered.display(),
            p.interval.as_deref().unwrap_or("none")
        );
    }
    s
}
