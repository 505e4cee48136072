//! The thesis's Tables 1 and 2 as printed (`--preset thesis`): one row per pair and level in
//! the thesis's order, the columns Test / p value / t value / Significant (p = 0.05) under
//! "Results of t test (Degrees of Freedom = N)", p and t in the thesis's number style; the same
//! rows with full-precision numbers in `thesis_tables.csv`. Beside them, the thesis's JND
//! reading next to the fitted JND.

use super::Report;
use super::rows::ci_text;
use crate::comparisons::Comparison;
use crate::data::Grouping;
use serde::Serialize;
use std::fmt::Write as _;

/// The thesis's two tables: number, family, title.
pub const TABLES: [(u8, Grouping, &str); 2] = [
    (
        1,
        Grouping::Scene,
        "Results of t-tests for determining statistical significance between scenes",
    ),
    (
        2,
        Grouping::PointSet,
        "Results of t-tests for determining statistical significance between point sets",
    ),
];

/// A row of `thesis_tables.csv`: the thesis's four columns first, then what identifies the
/// test.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ThesisRow {
    pub table: u8,
    /// "Plane Scene vs. Spheres Scene, 27 spp".
    pub test: String,
    pub p_value: Option<f64>,
    pub t_value: Option<f64>,
    /// `Yes` or `No` at the preset's alpha; empty when the test is undefined.
    pub significant: String,
    pub degrees_of_freedom: Option<f64>,
    pub a: String,
    pub b: String,
    pub level: u32,
    /// Pairs (paired test) or observations of the first group.
    pub n: usize,
    pub undefined_reason: String,
}

/// The thesis's name for a scene or point set of its design; other labels as they are.
pub fn display_name(family: Grouping, label: &str) -> String {
    let name = match (family, label) {
        (Grouping::Scene, "plane") => "Plane Scene",
        (Grouping::Scene, "spheres") => "Spheres Scene",
        (Grouping::PointSet, "hammersley") => "Hammersley",
        (Grouping::PointSet, "stratified") => "Stratified Monte Carlo",
        (Grouping::PointSet, "poisson") => "Poisson",
        _ => label,
    };
    name.to_string()
}

/// What Chapter V says about a group's JND, for the groups of its design.
fn chapter_v(family: Grouping, label: &str) -> &'static str {
    match (family, label) {
        (Grouping::Scene, "plane") => "roughly 40; close to halfway between 27 and 64",
        (Grouping::Scene, "spheres") => "roughly 100; close to 125",
        (Grouping::PointSet, "hammersley" | "stratified" | "poisson") => "between 64 and 125",
        _ => "",
    }
}

/// p as the thesis prints it: four decimals (0.0027, 0.5190), below 0.0001 two significant
/// digits written out (0.000025), below 1e-6 in exponent form.
pub fn format_p(p: f64) -> String {
    if p >= 1e-4 {
        format!("{p:.4}")
    } else if p >= 1e-6 {
        let decimals = (1.0 - p.log10().floor()) as usize;
        format!("{p:.decimals$}")
    } else {
        format!("{p:.1e}")
    }
}

/// t as the thesis prints it: four significant digits (-3.275, -5.000, -0.6571, 1.073).
pub fn format_t(t: f64) -> String {
    if t == 0.0 {
        return "0.000".into();
    }
    let decimals = (3.0 - t.abs().log10().floor()).max(0.0) as usize;
    format!("{t:.decimals$}")
}

fn yes_no(b: Option<bool>) -> String {
    match b {
        Some(true) => "Yes".into(),
        Some(false) => "No".into(),
        None => String::new(),
    }
}

fn row(table: u8, c: &Comparison) -> ThesisRow {
    let st = c.test.result.as_ref().ok();
    ThesisRow {
        table,
        test: format!(
            "{} vs. {}, {} spp",
            display_name(c.family, &c.a),
            display_name(c.family, &c.b),
            c.level
        ),
        p_value: st.map(|s| s.p),
        t_value: st.map(|s| s.t),
        significant: yes_no(c.significant),
        degrees_of_freedom: st.map(|s| s.df),
        a: c.a.clone(),
        b: c.b.clone(),
        level: c.level,
        n: c.test.n1,
        undefined_reason: c.test.result.as_ref().err().cloned().unwrap_or_default(),
    }
}

impl Report {
    /// The rows of Tables 1 and 2, in the order of the comparisons (the preset's pair order,
    /// levels ascending).
    pub fn thesis_rows(&self) -> Vec<ThesisRow> {
        TABLES
            .iter()
            .flat_map(|&(table, family, _)| {
                self.comparisons
                    .iter()
                    .filter(move |c| c.family == family)
                    .map(move |c| row(table, c))
            })
            .collect()
    }

    /// Tables 1 and 2 in Markdown, as the thesis lays them out.
    pub(super) fn thesis_tables(&self, md: &mut String) {
        let alpha = self.settings.comparisons.alpha;
        let rows = self.thesis_rows();
        for (table, _, title) in TABLES {
            let rows: Vec<&ThesisRow> = rows.iter().filter(|r| r.table == table).collect();
            if rows.is_empty() {
                continue;
            }
            let mut dfs: Vec<String> = rows
                .iter()
                .filter_map(|r| r.degrees_of_freedom.map(|d| format!("{d}")))
                .collect();
            dfs.dedup();
            let df = match dfs.as_slice() {
                [one] => format!("Degrees of Freedom = {one}"),
                [] => "Degrees of Freedom: none defined".to_string(),
                many => format!("Degrees of Freedom differ by row: {}", many.join(", ")),
            };
            let _ = writeln!(md, "## Table {table}: {title}\n");
            let _ = writeln!(md, "Results of t test ({df})\n");
            let _ = writeln!(
                md,
                "| Test | p value | t value | Significant (p = {alpha}) |"
            );
            let _ = writeln!(md, "|---|---|---|---|");
            for r in rows {
                match (r.p_value, r.t_value) {
                    (Some(p), Some(t)) => {
                        let _ = writeln!(
                            md,
                            "| {} | {} | {} | {} |",
                            r.test,
                            format_p(p),
                            format_t(t),
                            r.significant
                        );
                    }
                    _ => {
                        let _ = writeln!(
                            md,
                            "| {} | undefined | - | - ({}) |",
                            r.test, r.undefined_reason
                        );
                    }
                }
            }
            let _ = writeln!(md);
        }
    }

    /// The thesis's JND reading (where the plotted mean curve crosses the target) beside the
    /// fitted JND, and what Chapter V says for the groups of its design.
    pub(super) fn thesis_jnd_table(&self, md: &mut String) {
        let s = &self.settings;
        let _ = writeln!(
            md,
            "\n## JNDs: the thesis's reading beside the fit\n\n\
             The thesis read each JND where its plotted curve (the mean over subjects of the \
             per-subject proportions correct) crosses p = {}; here that curve is joined by \
             straight lines in ln spp. The fitted JND and its interval are this analysis's.\n",
            s.target
        );
        let _ = writeln!(
            md,
            "| Group | Thesis's reading (mean curve) | Fitted JND | {:.0}% CI | Chapter V says |",
            100.0 * s.bootstrap.confidence
        );
        let _ = writeln!(md, "|---|---|---|---|---|");
        for family in [Grouping::Scene, Grouping::PointSet] {
            let mut groups: Vec<_> = self.groups_of(family).collect();
            groups.sort_by_key(|g| (s.comparisons.order.rank(family, &g.key.label), &g.key.label));
            for g in groups {
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} |",
                    display_name(family, &g.key.label),
                    g.mean_crossing.display(),
                    g.threshold.display(),
                    ci_text(&g.bootstrap),
                    chapter_v(family, &g.key.label)
                );
            }
        }
        let _ = writeln!(md);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_printed_in_the_thesis_style() {
        // The thesis's own values (Tables 1 and 2), from the unrounded statistics that would
        // print as they did.
        assert_eq!(format_p(0.002_740), "0.0027");
        assert_eq!(format_p(2.541e-5), "0.000025");
        assert_eq!(format_p(0.519_0), "0.5190");
        assert_eq!(format_p(0.047_7), "0.0477");
        assert_eq!(format_p(3.2e-9), "3.2e-9");
        assert_eq!(format_t(-3.2751), "-3.275");
        assert_eq!(format_t(-5.0), "-5.000");
        assert_eq!(format_t(-0.657_12), "-0.6571");
        assert_eq!(format_t(1.0731), "1.073");
        assert_eq!(format_t(12.345_6), "12.35");
        assert_eq!(format_t(0.0), "0.000");
    }

    /// Half a unit in the last digit of a printed number.
    fn half_unit(text: &str) -> f64 {
        let decimals = text.split('.').nth(1).map_or(0, str::len);
        0.5 * 10f64.powi(-(decimals as i32))
    }

    #[test]
    fn the_thesis_p_values_are_two_sided_student_t_at_df_29_and_19() {
        // Chapter V, Tables 1 (df 29) and 2 (df 19), as printed: (t, p).
        let table_1 = [
            ("-3.275", "0.0027"),
            ("-5.000", "0.000025"),
            ("-1.560", "0.1296"),
            ("2.067", "0.0477"),
        ];
        let table_2 = [
            ("-1.285", "0.2141"),
            ("-1.189", "0.2492"),
            ("-0.6571", "0.5190"),
            ("-0.2239", "0.8252"),
            ("-0.4175", "0.6810"),
            ("-0.1523", "0.8805"),
            ("0.8254", "0.4194"),
            ("1.073", "0.2967"),
            ("0.4592", "0.6513"),
        ];
        let rows = table_1
            .iter()
            .map(|r| (29.0, r))
            .chain(table_2.iter().map(|r| (19.0, r)));
        for (df, (t_text, p_text)) in rows {
            // The t that prints as `t_text` lies within half a unit of its last digit; the p of
            // that range must meet the range of p that prints as `p_text`.
            let t: f64 = t_text.parse().unwrap();
            let p: f64 = p_text.parse().unwrap();
            let (ht, hp) = (half_unit(t_text), half_unit(p_text));
            let p_lo = crate::student_t::two_sided_p(t.abs() + ht, df);
            let p_hi = crate::student_t::two_sided_p(t.abs() - ht, df);
            assert!(
                p_lo <= p + hp && p_hi >= p - hp,
                "t = {t_text}, df = {df}: p in [{p_lo}, {p_hi}], printed {p_text}"
            );
            // And the table's own style prints the statistic the thesis printed.
            assert_eq!(format_t(t), *t_text);
        }
        // Neither df fits the thesis's 12 subjects tested per subject (11) or Student's
        // two-sample test (22): at df 11 the first row's p would print otherwise.
        let p11 = crate::student_t::two_sided_p(3.275, 11.0);
        assert!((p11 - 0.0027).abs() > 0.0027 * 0.5, "{p11}");
    }
}
