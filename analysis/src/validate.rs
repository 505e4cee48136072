//! Every main trial of a session log checked before it counts: the answer is one of the two
//! pairs, `correct` agrees with `response` and `diff_pair`, the index lies inside the plan the
//! header announces, a subject's logs are all of one mode (a person's or a simulated
//! observer's), and — with `analyze --design` — the trial is the one the design plans for that
//! subject and index (condition, level, stimuli, pairs; for an adaptive procedure, the trial it
//! gives after the subject's earlier answers, replayed) and its stimuli are ones the design's
//! manifest lists, rendered for the trial's condition and level. A log written by the suite passes
//! every check; a failed one means the file was edited, mixed or written elsewhere. Each
//! finding names the file, the line and the field.

use experiment::Design;
use experiment::log::{SessionLog, TrialRecord};
use experiment::procedure;
use experiment::trials::{Trial, plan};
use renderer::manifest::Manifest;
use std::collections::HashMap;

/// One trial that does not count, with why.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// Index into the logs given to [`check`].
    pub log: usize,
    /// Index into that log's `trials`.
    pub trial: usize,
    pub message: String,
}

/// Every finding over `logs` (checked against `design` and its `manifest` when given).
pub fn check(
    logs: &[SessionLog],
    design: Option<&Design>,
    manifest: Option<&Manifest>,
) -> Vec<Finding> {
    let mut found = Vec::new();
    let mut modes: HashMap<&str, (&str, usize)> = HashMap::new();
    // (subject, session, index) -> where it was first seen: a trial counted twice (a log
    // copied under another name, given twice, or edited) would silently double its weight.
    let mut seen: HashMap<(&str, u32, u32), String> = HashMap::new();
    for (li, log) in logs.iter().enumerate() {
        let h = &log.header;
        let (mode, first) = *modes.entry(h.subject.as_str()).or_insert((&h.mode, li));
        // A log of another design is reported by the design-hash check, not trial by trial.
        let planned = design
            .filter(|d| d.hash == h.design_hash)
            .map(|d| expected_main(d, log));
        let adaptive = design.is_some_and(|d| !d.file.procedure.is_constant());
        // The first main index missing from an adaptive log: the procedure chose every later
        // trial from the answers before, so it cannot be replayed past the gap.
        let mut next_index = 0u32;
        let mut gap: Option<u32> = None;
        for (ti, t) in log.trials.iter().enumerate().filter(|(_, t)| !t.practice) {
            let at = format!("{}:{}", log.path.display(), log.trial_lines[ti]);
            let mut problem = |message: String| {
                found.push(Finding {
                    log: li,
                    trial: ti,
                    message: format!("{at}: {message}"),
                })
            };
            // A lab (`gui`) and a browser (`web`) session of one subject are both a person's
            // answers; a simulated log beside either is not.
            if is_simulated(mode) != is_simulated(&h.mode) {
                problem(format!(
                    "subject {:?}: header field `mode` is {:?}, but {} is {mode:?}; a subject's \
                     logs must hold one kind of answers",
                    h.subject,
                    h.mode,
                    logs[first].path.display()
                ));
                continue;
            }
            let key = (h.subject.as_str(), h.session, t.index);
            if let Some(first) = seen.get(&key) {
                problem(format!(
                    "field `index` is {}: main trial {} of subject {:?}, session {} is already at \
                     {first}; each trial must be counted once (is a log given twice or copied?)",
                    t.index, t.index, key.0, key.1
                ));
                continue;
            }
            seen.insert(key, at.clone());
            if adaptive && gap.is_none() && t.index > next_index {
                gap = Some(next_index);
            }
            next_index = next_index.max(t.index + 1);
            if let Some(m) = answer_problem(t) {
                problem(m);
            } else if t.index >= h.trials_planned {
                problem(format!(
                    "field `index` is {}; the header plans {} main trials (indices 0 to {})",
                    t.index,
                    h.trials_planned,
                    h.trials_planned.saturating_sub(1)
                ));
            } else if let Some(missing) = gap.filter(|&g| t.index > g) {
                problem(format!(
                    "field `index` is {}, but main trial {missing} is missing from the log; the \
                     adaptive procedure chose each trial from the answers before it, so trials \
                     after the missing one cannot be checked (was a line deleted?)",
                    t.index
                ));
            } else if let Some(m) = design.is_none().then(|| id_problem(t)).flatten() {
                problem(m);
            } else if let Some(m) = planned
                .as_ref()
                .and_then(|main| plan_problem(t, main.get(t.index as usize), &h.subject))
            {
                problem(m);
            } else if let Some(m) = manifest.and_then(|m| manifest_problem(t, m)) {
                problem(m);
            }
        }
    }
    found
}

/// Whether a header's `mode` is an observer model's rather than a person's (`gui`, `web`).
fn is_simulated(mode: &str) -> bool {
    mode == "simulated"
}

/// The main trials the design puts in a log, by index: the constant-stimuli plan, or an
/// adaptive procedure replayed over the log's answers up to and including the first trial it
/// did not give (past that its state is unknown, so later trials have nothing to match).
fn expected_main(d: &Design, log: &SessionLog) -> Vec<Trial> {
    // Catch trials (`procedure::catch`) are placed by the procedure, so replay it then.
    if d.file.procedure.is_constant() && d.file.catch_trials.is_none() {
        return plan(d, &log.header.subject).main;
    }
    let mut p = procedure::start(d, &log.header.subject);
    let replay = procedure::replay(p.as_mut(), log.main_trials());
    let mut expected = replay.expected;
    // A record at another index than the procedure's trial there is a missing (or repeated)
    // trial, which `check` names: that place gets no expected trial.
    if let Some(at) = replay.mismatch
        && let (Some(t), Some(r)) = (expected.get(at), log.main_trials().nth(at))
        && t.index != r.index
    {
        expected.truncate(at);
    }
    expected
}

/// Without a design, the one check of a trial's condition there is: its test stimulus's id, when
/// it is one the renderer names (`scene-point_set-time_filter-NNNN`), names the trial's own
/// scene, point set, time filter and level. An edited field (a scene no design knows) is named
/// with its line instead of becoming a group of its own. Ids of another form are not checked.
fn id_problem(t: &TrialRecord) -> Option<String> {
    let id = &t.test_stimulus;
    let (scene, points, filter, spp) = renderer::ids::parse_stimulus_id(id)?;
    let named = [
        ("scene", scene.to_string(), t.scene.clone()),
        ("point_set", points.to_string(), t.point_set.to_string()),
        ("time_filter", filter.to_string(), t.time_filter.to_string()),
        ("level", spp.to_string(), t.level.to_string()),
    ];
    let (field, want, got) = named.into_iter().find(|(_, want, got)| want != got)?;
    Some(format!(
        "field `{field}` is {got:?}, but the trial's `test_stimulus` {id:?} names {want:?}; was \
         the log edited? (`--design` checks every trial against the design's plan)"
    ))
}

/// How a trial's stimuli disagree with the manifest they were rendered into.
fn manifest_problem(t: &TrialRecord, m: &Manifest) -> Option<String> {
    for (field, id) in [
        ("test_stimulus", &t.test_stimulus),
        ("reference_stimulus", &t.reference_stimulus),
    ] {
        if m.get(id).is_none() {
            return Some(format!(
                "field `{field}` is {id:?}, which the manifest of job {:?} does not list",
                m.job
            ));
        }
    }
    let s = m.get(&t.test_stimulus)?;
    let rendered = [
        ("scene", s.scene.clone(), t.scene.clone()),
        (
            "point_set",
            s.point_set.to_string(),
            t.point_set.to_string(),
        ),
        (
            "time_filter",
            s.time_filter.to_string(),
            t.time_filter.to_string(),
        ),
        ("level", s.spp.to_string(), t.level.to_string()),
    ];
    let (field, want, got) = rendered.into_iter().find(|(_, want, got)| want != got)?;
    Some(format!(
        "field `{field}` is {got:?}, but the manifest rendered its test stimulus {:?} with {want:?}",
        t.test_stimulus
    ))
}

/// What is wrong with a trial's answer fields on their own.
fn answer_problem(t: &TrialRecord) -> Option<String> {
    for (field, v) in [("response", t.response), ("diff_pair", t.diff_pair)] {
        if !(1..=2).contains(&v) {
            return Some(format!("field `{field}` is {v}; expected 1 or 2 (a pair)"));
        }
    }
    if t.level == 0 {
        return Some("field `level` is 0; expected samples per pixel >= 1".into());
    }
    let implied = t.response == t.diff_pair;
    (t.correct != implied).then(|| {
        format!(
            "field `correct` is {}, but `response` {} and `diff_pair` {} make it {implied}",
            t.correct, t.response, t.diff_pair
        )
    })
}

/// How a trial differs from the one the design plans at its index.
fn plan_problem(t: &TrialRecord, planned: Option<&Trial>, subject: &str) -> Option<String> {
    let Some(p) = planned else {
        return Some(format!(
            "field `index` is {}; the design plans fewer main trials for subject {subject:?} (an \
             adaptive procedure: or an earlier trial was not the one it gave)",
            t.index
        ));
    };
    if p.matches(t) {
        return None;
    }
    let fields: [(&str, String, String); 7] = [
        ("scene", t.scene.clone(), p.condition.scene.clone()),
        (
            "point_set",
            t.point_set.to_string(),
            p.condition.point_set.to_string(),
        ),
        (
            "time_filter",
            t.time_filter.to_string(),
            p.condition.time_filter.to_string(),
        ),
        ("level", t.level.to_string(), p.level.to_string()),
        (
            "test_stimulus",
            t.test_stimulus.clone(),
            p.test_stimulus.clone(),
        ),
        (
            "reference_stimulus",
            t.reference_stimulus.clone(),
            p.reference_stimulus.clone(),
        ),
        (
            "diff_pair",
            t.diff_pair.to_string(),
            p.diff_pair.to_string(),
        ),
    ];
    let (field, got, want) = fields
        .into_iter()
        .find(|(_, got, want)| got != want)
        .unwrap_or((
            "test_side",
            format!("{:?}", t.test_side),
            format!("{:?}", p.test_side),
        ));
    Some(format!(
        "field `{field}` is {got:?}; the design plans {want:?} for main trial {} of subject \
         {subject:?}",
        t.index
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use experiment::Observer;
    use experiment::log::LogLine;
    use std::path::Path;

    const DESIGN: &str = r#"{
        "format": "blurlab-design/1", "name": "adaptive", "manifest": "none",
        "factors": {"scenes": ["plane", "spheres"], "point_sets": ["hammersley"],
                    "time_filters": ["box"]},
        "levels": [1, 8, 27, 64, 125], "seed": {"master": 5},
        "procedure": {"quest_plus": {"trials": 10}}
    }"#;

    const OBSERVER: &str = r#"{"format": "blurlab-observer/1", "name": "o", "slope": 1.5,
        "thresholds": [{"spp": 30}]}"#;

    /// DESIGN in a fresh folder with subject s01's simulated log (`s01.jsonl`) beside it.
    fn simulated_subject() -> (tempfile::TempDir, Design) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("design.json");
        std::fs::write(&path, DESIGN).unwrap();
        let design = Design::load(&path).unwrap();
        let observer = Observer::parse(Path::new("o.json"), OBSERVER).unwrap();
        let log = dir.path().join("s01.jsonl");
        experiment::simulate::simulate_subject(&design, &observer, "s01", &log).unwrap();
        (dir, design)
    }

    /// A simulated QUEST+ subject's log passes; a trial whose level was edited is found, and
    /// the trials after it (whose expected level is unknown) are too.
    #[test]
    fn adaptive_logs_are_checked_against_the_procedure_replayed() {
        let (dir, design) = simulated_subject();
        let log_path = dir.path().join("s01.jsonl");
        let log = SessionLog::read(&log_path).unwrap();
        assert_eq!(log.main_trials().count(), 20);
        assert!(check(std::slice::from_ref(&log), Some(&design), None).is_empty());

        let text = std::fs::read_to_string(&log_path).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        // Line 0 is the header, then 4 practice trials; edit main trial 5.
        let k = 1 + 4 + 5;
        let mut line: LogLine = serde_json::from_str(&lines[k]).unwrap();
        let LogLine::Trial(t) = &mut line else {
            panic!("line {k} is not a trial");
        };
        assert!(!t.practice && t.index == 5);
        let other = if t.level == 1 { 8 } else { 1 };
        t.test_stimulus = t
            .test_stimulus
            .replace(&format!("{:04}", t.level), &format!("{other:04}"));
        t.level = other;
        lines[k] = serde_json::to_string(&line).unwrap();
        std::fs::write(&log_path, lines.join("\n") + "\n").unwrap();
        let log = SessionLog::read(&log_path).unwrap();
        let found = check(&[log], Some(&design), None);
        assert_eq!(found.len(), 15, "{found:?}");
        assert!(
            found[0].message.contains("field `level`"),
            "{}",
            found[0].message
        );
        assert!(
            found[1].message.contains("earlier trial"),
            "{}",
            found[1].message
        );
    }

    /// A main trial deleted from an adaptive log: the next is named with the missing index
    /// (issue 42: it was "the design plans fewer main trials").
    #[test]
    fn a_missing_trial_of_an_adaptive_log_is_named() {
        let (dir, design) = simulated_subject();
        let log_path = dir.path().join("s01.jsonl");
        let text = std::fs::read_to_string(&log_path).unwrap();
        let mut lines: Vec<&str> = text.lines().collect();
        lines.remove(1 + 4 + 7); // main trial 7
        std::fs::write(&log_path, lines.join("\n") + "\n").unwrap();
        let log = SessionLog::read(&log_path).unwrap();
        let found = check(&[log], Some(&design), None);
        assert_eq!(found.len(), 12, "{found:?}");
        for f in &found {
            assert!(
                f.message.contains("main trial 7 is missing from the log"),
                "{}",
                f.message
            );
        }
        assert!(
            found[0].message.contains("field `index` is 8"),
            "{}",
            found[0].message
        );
    }

    /// Without `--design`, a trial whose scene was edited to one no design knows is named with
    /// its file and line (issue 51: it became a group of its own); the untouched log passes.
    #[test]
    fn without_a_design_an_edited_scene_is_named_by_its_line() {
        let (dir, _) = simulated_subject();
        let log_path = dir.path().join("s01.jsonl");
        let log = SessionLog::read(&log_path).unwrap();
        assert!(check(std::slice::from_ref(&log), None, None).is_empty());
        let text = std::fs::read_to_string(&log_path).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let k = 1 + 4 + 2;
        let mut line: LogLine = serde_json::from_str(&lines[k]).unwrap();
        let LogLine::Trial(t) = &mut line else {
            panic!("line {k} is not a trial");
        };
        t.scene = "nosuch".into();
        lines[k] = serde_json::to_string(&line).unwrap();
        std::fs::write(&log_path, lines.join("\n") + "\n").unwrap();
        let log = SessionLog::read(&log_path).unwrap();
        let found = check(&[log], None, None);
        assert_eq!(found.len(), 1, "{found:?}");
        let m = &found[0].message;
        assert!(m.contains(&format!("s01.jsonl:{}", k + 1)), "{m}");
        assert!(m.contains("field `scene` is \"nosuch\""), "{m}");
    }
}
