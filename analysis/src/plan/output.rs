//! The plan's table (`plan.md`, `plan.csv`), figures (`plan_power.svg|png`,
//! `plan_intervals.svg|png`) and recommendation line.

use super::duration::SessionDuration;
use super::{Plan, TestRow};
use crate::figures::{
    Drawable, FONT, PALETTE, err, legend, level_line, line_swatch, register_font, save,
};
use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Criteria of the recommendation.
#[derive(Clone, Copy, Debug)]
pub struct Criteria {
    /// Required probability (of a narrow interval, of a significant test).
    pub probability: f64,
    /// Differences in proportion correct smaller than this do not drive the recommendation.
    pub min_difference: f64,
}

/// The smallest subject count meeting the criteria, as a sentence.
pub fn recommendation(plan: &Plan, c: Criteria) -> String {
    for row in &plan.counts {
        let intervals_ok = row.intervals.iter().all(|i| i.narrow >= c.probability);
        let tests_ok = meaningful_pairs(&row.tests, c.min_difference)
            .into_iter()
            .all(|(_, best)| best >= c.probability);
        if intervals_ok && tests_ok {
            return format!(
                "Recommendation: {} subjects: every pooled JND's 95% interval is narrower than a \
                 factor {} with probability >= {}, and every test whose true difference reaches \
                 {} in proportion correct is significant at its best level with probability >= {}.",
                row.subjects, plan.factor, c.probability, c.min_difference, c.probability
            );
        }
    }
    let last = plan.counts.last().map_or(0, |r| r.subjects);
    format!(
        "Recommendation: none of the subject counts tried (up to {last}) meets the criteria \
         (intervals narrower than a factor {} and power >= {} for differences >= {}); try more \
         subjects, more repeats or levels nearer the JNDs.",
        plan.factor, c.probability, c.min_difference
    )
}

/// Per comparison pair with a true difference >= `min` at some level: its best power.
fn meaningful_pairs(tests: &[TestRow], min: f64) -> Vec<((String, String, String), f64)> {
    let mut out: Vec<((String, String, String), f64)> = Vec::new();
    for t in tests.iter().filter(|t| t.true_difference.abs() >= min) {
        let key = (t.family.name().to_string(), t.a.clone(), t.b.clone());
        match out.iter_mut().find(|(k, _)| *k == key) {
            Some((_, best)) => *best = best.max(t.significant),
            None => out.push((key, t.significant)),
        }
    }
    out
}

/// `plan.md`.
pub fn markdown(plan: &Plan, duration: Option<&SessionDuration>, recommendation: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Study plan: design {}, observer {}\n\n{} replications per subject count, {:.1} s.\n\n{recommendation}\n",
        plan.design, plan.observer, plan.replications, plan.wall_seconds
    );
    let _ = writeln!(
        s,
        "## Pooled JNDs: P(95% interval narrower than a factor {})\n",
        plan.factor
    );
    let mut header = String::from("| group |");
    let mut rule = String::from("|---|");
    for c in &plan.counts {
        let _ = write!(header, " {} subjects |", c.subjects);
        rule.push_str("---|");
    }
    let _ = writeln!(s, "{header}\n{rule}");
    if let Some(first) = plan.counts.first() {
        for (i, row) in first.intervals.iter().enumerate() {
            let _ = write!(s, "| {} {} |", row.group.grouping.name(), row.group.label);
            for c in &plan.counts {
                let _ = write!(s, " {:.2} |", c.intervals[i].narrow);
            }
            s.push('\n');
        }
    }
    let _ = writeln!(
        s,
        "\n## t-tests: rate significant at alpha = {} (power where the observer's population differs, false-positive rate where it does not)\n",
        plan.alpha
    );
    let _ = writeln!(
        s,
        "| family | a | b | spp | true difference in p |{}",
        &header["| group |".len()..]
    );
    let _ = writeln!(s, "|---|---|---|---|---|{}", &rule["|---|".len()..]);
    if let Some(first) = plan.counts.first() {
        for (i, t) in first.tests.iter().enumerate() {
            let truth = if t.has_difference() {
                format!("{:+.3}", t.true_difference)
            } else {
                "none (false-positive rate)".into()
            };
            let _ = write!(
                s,
                "| {} | {} | {} | {} | {truth} |",
                t.family.name(),
                t.a,
                t.b,
                t.level
            );
            for c in &plan.counts {
                let _ = write!(s, " {:.3} |", c.tests[i].significant);
            }
            s.push('\n');
        }
    }
    let _ = writeln!(s, "\n## Session duration\n");
    match duration {
        Some(d) => {
            let _ = writeln!(
                s,
                "{} trials (practice included) of {:.1} s ({:.1} s videos) and {} breaks: {:.0} min per subject.\n",
                d.trials,
                d.trial_seconds,
                d.video_seconds,
                d.breaks,
                d.session_seconds / 60.0
            );
            let _ = writeln!(s, "| subjects | subject-hours |\n|---|---|");
            for c in &plan.counts {
                let _ = writeln!(
                    s,
                    "| {} | {:.1} |",
                    c.subjects,
                    c.subjects as f64 * d.session_seconds / 3600.0
                );
            }
        }
        None => {
            let _ = writeln!(
                s,
                "Unknown: the design's manifest is not rendered; pass --video-seconds."
            );
        }
    }
    s
}

/// `plan.csv`: one row per subject count x (interval or test).
pub fn csv_text(plan: &Plan) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "subjects",
        "kind",
        "family",
        "a",
        "b",
        "spp",
        "true_difference",
        "probability",
        "probability_holm",
    ])?;
    for c in &plan.counts {
        for i in &c.intervals {
            w.write_record([
                c.subjects.to_string(),
                format!("interval_narrower_than_{}", plan.factor),
                i.group.grouping.name().into(),
                i.group.label.clone(),
                String::new(),
                String::new(),
                String::new(),
                i.narrow.to_string(),
                String::new(),
            ])?;
        }
        for t in &c.tests {
            w.write_record([
                c.subjects.to_string(),
                "significant".into(),
                t.family.name().into(),
                t.a.clone(),
                t.b.clone(),
                t.level.to_string(),
                t.true_difference.to_string(),
                t.significant.to_string(),
                t.significant_holm.to_string(),
            ])?;
        }
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// Write plan.md, plan.csv and the two figures into `dir`.
pub fn write(
    plan: &Plan,
    duration: Option<&SessionDuration>,
    recommendation: &str,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow!("cannot create folder {}: {e}", dir.display()))?;
    let md = dir.join("plan.md");
    renderer::atomic::write_atomic(&md, markdown(plan, duration, recommendation).as_bytes())?;
    let csv = dir.join("plan.csv");
    renderer::atomic::write_atomic(&csv, csv_text(plan)?.as_bytes())?;
    let mut files = vec![md, csv];
    register_font()?;
    // Power: per test pair with a true difference, its best level; intervals: per group.
    let mut power: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut fp: Vec<(f64, f64)> = Vec::new();
    for c in &plan.counts {
        let x = c.subjects as f64;
        let mut best: Vec<(String, f64)> = Vec::new();
        let (mut fp_sum, mut fp_n) = (0.0, 0);
        for t in &c.tests {
            if t.has_difference() {
                let name = format!("{} {} vs {}", t.family.name(), t.a, t.b);
                match best.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, b)) => *b = b.max(t.significant),
                    None => best.push((name, t.significant)),
                }
            } else {
                fp_sum += t.significant;
                fp_n += 1;
            }
        }
        for (name, b) in best {
            match power.iter_mut().find(|(n, _)| *n == name) {
                Some((_, pts)) => pts.push((x, b)),
                None => power.push((name, vec![(x, b)])),
            }
        }
        if fp_n > 0 {
            fp.push((x, fp_sum / fp_n as f64));
        }
    }
    if !fp.is_empty() {
        power.push(("false-positive rate (no true difference)".into(), fp));
    }
    let intervals: Vec<(String, Vec<(f64, f64)>)> = plan
        .counts
        .first()
        .map(|first| {
            first
                .intervals
                .iter()
                .enumerate()
                .map(|(i, row)| {
                    let pts = plan
                        .counts
                        .iter()
                        .map(|c| (c.subjects as f64, c.intervals[i].narrow))
                        .collect();
                    (
                        format!("{} {}", row.group.grouping.name(), row.group.label),
                        pts,
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    for (name, title, series) in [
        (
            "plan_power",
            "Power of each test at its best level".to_string(),
            &power,
        ),
        (
            "plan_intervals",
            format!("P(95% interval narrower than x{})", plan.factor),
            &intervals,
        ),
    ] {
        let figure = LineFigure {
            title: &title,
            series,
            alpha: plan.alpha,
        };
        files.extend(save(dir, name, &figure)?);
    }
    Ok(files)
}

/// Probability against subject count, one line per series.
struct LineFigure<'a> {
    title: &'a str,
    series: &'a [(String, Vec<(f64, f64)>)],
    alpha: f64,
}

impl Drawable for LineFigure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        chart(root, self.title, self.series, self.alpha)
    }
}

fn chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    series: &[(String, Vec<(f64, f64)>)],
    alpha: f64,
) -> Result<()> {
    root.fill(&WHITE).map_err(err)?;
    let xs: Vec<f64> = series
        .iter()
        .flat_map(|(_, p)| p.iter().map(|q| q.0))
        .collect();
    let x1 = xs.iter().copied().fold(1.0, f64::max) + 1.0;
    let mut c = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0f64..x1, 0f64..1.02f64)
        .map_err(err)?;
    c.configure_mesh()
        .x_desc("subjects")
        .y_desc("probability")
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    for (y, colour) in [(0.8, RED), (alpha, GREEN)] {
        c.draw_series(level_line(y, (0.0, x1), colour.stroke_width(1)))
            .map_err(err)?;
    }
    for (i, (name, pts)) in series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        c.draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
            .map_err(err)?
            .label(name.clone())
            .legend(line_swatch(colour, 2));
        c.draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
            .map_err(err)?;
    }
    legend(&mut c, 13, SeriesLabelPosition::LowerRight)
}
