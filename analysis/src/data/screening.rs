//! `exclusions.csv` (issue 49): every subject's screening facts
//! ([`experiment::screening`]) and the criteria they fail.

pub use experiment::screening::*;

/// `exclusions.csv`: one row per subject with every fact and the reasons (empty: kept).
pub fn csv(rows: &[(SubjectFacts, Vec<String>)], min_rt_ms: Option<f64>) -> String {
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.4}"));
    let mut out = String::from(
        "subject,main_trials,planned,finished,catch_trials,catch_accuracy,bad_frame_share,\
         fast_share,pixels_per_degree,viewing_distance_mm,refresh_hz,excluded,reasons\n",
    );
    for (f, why) in rows {
        let d = f.displays.first();
        let hz = f
            .refresh_ms
            .first()
            .filter(|&&ms| ms > 0.0)
            .map(|ms| 1000.0 / ms);
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},\"{}\"\n",
            f.subject,
            f.main_done,
            f.planned,
            f.finished(),
            f.catch_trials,
            opt(f.catch_accuracy()),
            opt(f.bad_frame_share()),
            opt(min_rt_ms.and_then(|m| f.fast_share(m))),
            opt(d.map(|d| d.pixels_per_degree)),
            opt(d.map(|d| d.viewing_distance_mm)),
            opt(hz),
            !why.is_empty(),
            why.join("; ").replace('"', "'")
        ));
    }
    out
}
