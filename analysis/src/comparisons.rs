//! The families of t-tests of the thesis's Tables 1 and 2: scenes against each other and point
//! sets against each other (all pairs), at chosen levels, on proportions correct per unit of
//! observation. Holm's correction runs within each family.
//!
//! The unit is the subject (default: each subject's trials pooled over the other factors, one
//! value per subject) or the subject x other-factor cell (the thesis's Tables 1 and 2: one value
//! per subject and point set in the scene test, per subject and scene in the point-set test).
//! The cells of one subject share that subject's eye and criterion, so they are not
//! independent; the cell unit counts them as if they were (more degrees of freedom, smaller p).

use crate::data::{Dataset, Group, Grouping};
use crate::ttest::{TTest, TestKind, holm, t_test};
use serde::Serialize;

/// The unit of observation of the t-tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Unit {
    /// One value per subject, pooled over the other factors (df = subjects - 1 when paired).
    #[default]
    Subject,
    /// One value per subject x other-factor cell, as the thesis did (df = cells - 1 when
    /// paired: 29 and 19 with 10 subjects).
    Cell,
}

renderer::named!(Unit, "unit", [Subject => "subject", Cell => "cell"]);

/// The order of each family's groups: pairs are (earlier, later) and t > 0 when the earlier
/// has the higher proportion correct. Labels not listed follow, alphabetically.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PairOrder {
    pub scenes: Vec<String>,
    pub point_sets: Vec<String>,
    pub time_filters: Vec<String>,
}

impl PairOrder {
    /// The thesis's order: plane before spheres (Table 1); Hammersley, Stratified Monte Carlo,
    /// Poisson (Table 2: H vs S, H vs P, S vs P), under the names of `scenes/thesis/design.json`.
    pub fn thesis() -> Self {
        let v = |names: &[&str]| names.iter().map(|s| s.to_string()).collect();
        PairOrder {
            scenes: v(&["plane", "spheres"]),
            point_sets: v(&["hammersley", "stratified", "poisson"]),
            time_filters: Vec::new(),
        }
    }

    fn of(&self, family: Grouping) -> &[String] {
        match family {
            Grouping::Scene => &self.scenes,
            Grouping::PointSet => &self.point_sets,
            Grouping::TimeFilter => &self.time_filters,
            Grouping::Condition => &[],
        }
    }

    /// Sort key: position in the list (unlisted labels after all listed ones), then label.
    pub fn rank(&self, family: Grouping, label: &str) -> usize {
        let list = self.of(family);
        list.iter().position(|l| l == label).unwrap_or(list.len())
    }
}

/// What to compare.
#[derive(Clone, Debug, Serialize)]
pub struct ComparisonSettings {
    pub kind: TestKind,
    /// Levels for every family (the thesis: 27, 64, 125 spp).
    pub levels: Vec<u32>,
    /// Extra levels for the scene family (the thesis added 216 spp to Table 1).
    pub scene_extra_levels: Vec<u32>,
    pub alpha: f64,
    pub unit: Unit,
    pub order: PairOrder,
}

/// One row of a table.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// `scene`, `point_set` or `time_filter`.
    pub family: Grouping,
    pub a: String,
    pub b: String,
    pub level: u32,
    pub test: TTest,
    /// Holm-adjusted p within the family (None when the test is undefined).
    pub p_holm: Option<f64>,
    /// Decision at alpha on the unadjusted p, as the thesis reported.
    pub significant: Option<bool>,
    /// Decision at alpha on the Holm-adjusted p.
    pub significant_holm: Option<bool>,
}

/// All families present in the data (time filters only when there are several).
pub fn compare(ds: &Dataset, s: &ComparisonSettings) -> Vec<Comparison> {
    let mut out = Vec::new();
    for family in [Grouping::Scene, Grouping::PointSet, Grouping::TimeFilter] {
        let mut levels = s.levels.clone();
        if family == Grouping::Scene {
            levels.extend(&s.scene_extra_levels);
        }
        levels.sort_unstable();
        levels.dedup();
        let mut groups: Vec<&Group> = ds.groups_of(family).collect();
        groups.sort_by_key(|g| (s.order.rank(family, &g.key.label), &g.key.label));
        let mut rows = Vec::new();
        for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                for &level in &levels {
                    rows.push(Comparison {
                        family,
                        a: groups[i].key.label.clone(),
                        b: groups[j].key.label.clone(),
                        level,
                        test: test_at(ds, family, [groups[i], groups[j]], level, s),
                        p_holm: None,
                        significant: None,
                        significant_holm: None,
                    });
                }
            }
        }
        let p: Vec<Option<f64>> = rows
            .iter()
            .map(|r| r.test.result.as_ref().ok().map(|st| st.p))
            .collect();
        for (row, adj) in rows.iter_mut().zip(holm(&p)) {
            row.p_holm = adj;
            row.significant = row.test.result.as_ref().ok().map(|st| st.p < s.alpha);
            row.significant_holm = adj.map(|q| q < s.alpha);
        }
        out.extend(rows);
    }
    out
}

/// A unit of observation: the subject's index and, for the cell unit, the other factors.
type UnitKey = (usize, Vec<String>);

/// Proportions correct at `level` per unit of observation of one group of `family`.
fn unit_values(
    ds: &Dataset,
    family: Grouping,
    g: &Group,
    level: u32,
    unit: Unit,
) -> Vec<(UnitKey, f64)> {
    match unit {
        Unit::Subject => g
            .subject_proportions(level)
            .into_iter()
            .map(|(s, p)| ((s, Vec::new()), p))
            .collect(),
        Unit::Cell => {
            let at = match family {
                Grouping::Scene => 0,
                Grouping::PointSet => 1,
                _ => 2,
            };
            let mut values = Vec::new();
            for c in ds.groups_of(Grouping::Condition) {
                let Some(f) = &c.condition else { continue };
                if f[at] != g.key.label {
                    continue;
                }
                let others: Vec<String> =
                    (0..3).filter(|&k| k != at).map(|k| f[k].clone()).collect();
                for (s, p) in c.subject_proportions(level) {
                    values.push(((s, others.clone()), p));
                }
            }
            values.sort_by(|a, b| a.0.cmp(&b.0));
            values
        }
    }
}

fn test_at(
    ds: &Dataset,
    family: Grouping,
    [a, b]: [&Group; 2],
    level: u32,
    s: &ComparisonSettings,
) -> TTest {
    if !ds.levels.contains(&level) {
        return TTest {
            kind: s.kind,
            n1: 0,
            n2: 0,
            mean1: 0.0,
            mean2: 0.0,
            result: Err(format!("{level} spp was not tested")),
        };
    }
    let pa = unit_values(ds, family, a, level, s.unit);
    let pb = unit_values(ds, family, b, level, s.unit);
    match s.kind {
        TestKind::Paired => {
            // Pair by unit; a unit missing either side cannot be paired.
            let (mut xa, mut xb) = (Vec::new(), Vec::new());
            for (key, p) in &pa {
                if let Some((_, q)) = pb.iter().find(|(k, _)| k == key) {
                    xa.push(*p);
                    xb.push(*q);
                }
            }
            t_test(s.kind, &xa, &xb)
        }
        TestKind::Student | TestKind::Welch => {
            let xa: Vec<f64> = pa.iter().map(|x| x.1).collect();
            let xb: Vec<f64> = pb.iter().map(|x| x.1).collect();
            t_test(s.kind, &xa, &xb)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Observation;

    /// Subject s answers correctly at `level` in scene `scene` on `k` of 4 trials per point set.
    fn obs(subject: &str, scene: &str, ps: &str, level: u32, k: u32) -> Vec<Observation> {
        (0..4)
            .map(|i| Observation {
                subject: subject.into(),
                scene: scene.into(),
                point_set: ps.into(),
                time_filter: "box".into(),
                level,
                correct: i < k,
            })
            .collect()
    }

    #[test]
    fn scene_table_pairs_subjects_and_adds_the_extra_level() {
        let mut o = Vec::new();
        // Three subjects; plane easier to tell apart... spheres: noise more visible.
        for (s, kp, ks) in [("a", 2, 4), ("b", 3, 4), ("c", 2, 3)] {
            for ps in ["ham", "poisson"] {
                o.extend(obs(s, "plane", ps, 64, kp));
                o.extend(obs(s, "spheres", ps, 64, ks));
            }
        }
        let ds = Dataset::from_observations(&o);
        let rows = compare(
            &ds,
            &ComparisonSettings {
                kind: TestKind::Paired,
                levels: vec![64],
                scene_extra_levels: vec![216],
                alpha: 0.05,
                unit: Unit::Subject,
                order: PairOrder::default(),
            },
        );
        let scene: Vec<_> = rows
            .iter()
            .filter(|r| r.family == Grouping::Scene)
            .collect();
        assert_eq!(scene.len(), 2);
        // Per subject (pooled over the two point sets): plane 0.5, 0.75, 0.5; spheres 1, 1, 0.75.
        // Differences -0.5, -0.25, -0.25: mean -1/3, sd 0.144338, t = -4.0, df 2.
        let st = scene[0].test.result.clone().unwrap();
        assert_eq!(
            (scene[0].a.as_str(), scene[0].b.as_str()),
            ("plane", "spheres")
        );
        assert!((st.t + 4.0).abs() < 1e-12, "{st:?}");
        assert_eq!(st.df, 2.0);
        // 216 spp was not tested: undefined, outside the Holm family (p_holm = p).
        assert!(scene[1].test.result.is_err());
        assert_eq!(scene[0].p_holm, Some(st.p));
        // Point sets: identical per-subject data -> zero variance, undefined.
        let ps: Vec<_> = rows
            .iter()
            .filter(|r| r.family == Grouping::PointSet)
            .collect();
        assert_eq!(ps.len(), 1);
        assert!(
            ps[0]
                .test
                .result
                .as_ref()
                .unwrap_err()
                .contains("zero variance")
        );
        assert_eq!(ps[0].significant, None);
    }

    #[test]
    fn cell_unit_pairs_subject_by_other_factor_cells_in_the_given_order() {
        let mut o = Vec::new();
        for (s, kp, ks) in [("a", 2, 4), ("b", 3, 4), ("c", 2, 3)] {
            for ps in ["ham", "poisson"] {
                o.extend(obs(s, "plane", ps, 64, kp));
                o.extend(obs(s, "spheres", ps, 64, ks));
            }
        }
        // Point set "poisson" is easier in subject a's plane cell only.
        o.retain(|x| !(x.subject == "a" && x.scene == "plane" && x.point_set == "poisson"));
        o.extend(obs("a", "plane", "poisson", 64, 4));
        let ds = Dataset::from_observations(&o);
        let settings = ComparisonSettings {
            kind: TestKind::Paired,
            levels: vec![64],
            scene_extra_levels: vec![],
            alpha: 0.05,
            unit: Unit::Cell,
            order: PairOrder {
                scenes: vec!["spheres".into()],
                point_sets: vec!["poisson".into(), "ham".into()],
                time_filters: vec![],
            },
        };
        let rows = compare(&ds, &settings);
        // Scenes: spheres listed first, so the pair is spheres vs plane and t is positive.
        // Cells (subject x point set): differences spheres - plane are 0.5, 0.0 (a), 0.25,
        // 0.25 (b), 0.25, 0.25 (c): mean 0.25, SD sqrt(0.025), t = 0.25 / sqrt(0.025 / 6)
        // = sqrt(15), df = 5.
        let scene = &rows[0];
        assert_eq!((scene.a.as_str(), scene.b.as_str()), ("spheres", "plane"));
        let st = scene.test.result.clone().unwrap();
        assert_eq!((scene.test.n1, st.df), (6, 5.0));
        assert!((st.t - 15f64.sqrt()).abs() < 1e-12, "{st:?}");
        // Point sets in the given order; cells are subject x scene: differences poisson - ham
        // are 0.5 (a, plane) and 0 in the five other cells: mean 1/12, SD sqrt(1/24),
        // t = (1/12) / sqrt(1/144) = 1, df = 5.
        let ps = &rows[1];
        assert_eq!((ps.a.as_str(), ps.b.as_str()), ("poisson", "ham"));
        let st = ps.test.result.clone().unwrap();
        assert_eq!(st.df, 5.0);
        assert!((st.t - 1.0).abs() < 1e-12, "{st:?}");
        // The subject unit of the same data: 3 pairs, df = 2.
        let by_subject = compare(
            &ds,
            &ComparisonSettings {
                unit: Unit::Subject,
                ..settings
            },
        );
        assert_eq!(by_subject[1].test.result.clone().unwrap().df, 2.0);
    }
}
