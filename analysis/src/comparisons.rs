//! The families of t-tests of the thesis's Tables 1 and 2: scenes against each other and point
//! sets against each other (all pairs), at chosen levels, on per-subject proportions correct
//! pooled over the other factors. Holm's correction runs within each family.

use crate::data::{Dataset, Group, Grouping};
use crate::ttest::{TTest, TestKind, holm, t_test};
use serde::Serialize;

/// What to compare.
#[derive(Clone, Debug, Serialize)]
pub struct ComparisonSettings {
    pub kind: TestKind,
    /// Levels for every family (the thesis: 27, 64, 125 spp).
    pub levels: Vec<u32>,
    /// Extra levels for the scene family (the thesis added 216 spp to Table 1).
    pub scene_extra_levels: Vec<u32>,
    pub alpha: f64,
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
        let groups: Vec<&Group> = ds.groups_of(family).collect();
        let mut rows = Vec::new();
        for i in 0..groups.len() {
            for j in i + 1..groups.len() {
                for &level in &levels {
                    rows.push(Comparison {
                        family,
                        a: groups[i].key.label.clone(),
                        b: groups[j].key.label.clone(),
                        level,
                        test: test_at(ds, groups[i], groups[j], level, s.kind),
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

fn test_at(ds: &Dataset, a: &Group, b: &Group, level: u32, kind: TestKind) -> TTest {
    if !ds.levels.contains(&level) {
        return TTest {
            kind,
            n1: 0,
            n2: 0,
            mean1: 0.0,
            mean2: 0.0,
            result: Err(format!("{level} spp was not tested")),
        };
    }
    let pa = a.subject_proportions(level);
    let pb = b.subject_proportions(level);
    match kind {
        TestKind::Paired => {
            // Pair by subject; a subject missing either side cannot be paired.
            let (mut xa, mut xb) = (Vec::new(), Vec::new());
            for &(s, p) in &pa {
                if let Some(&(_, q)) = pb.iter().find(|(t, _)| *t == s) {
                    xa.push(p);
                    xb.push(q);
                }
            }
            t_test(kind, &xa, &xb)
        }
        TestKind::Student | TestKind::Welch => {
            let xa: Vec<f64> = pa.iter().map(|x| x.1).collect();
            let xb: Vec<f64> = pb.iter().map(|x| x.1).collect();
            t_test(kind, &xa, &xb)
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
}
