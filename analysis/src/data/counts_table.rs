//! Reading counts tables (CSV: subject, condition, level, correct, trials) into a
//! [`Dataset`], for data collected elsewhere.

use super::{Dataset, Observation, Source};
use anyhow::{Result, bail};
use experiment::design::MAX_TRIALS;
use std::path::PathBuf;

impl Dataset {
    /// Read counts tables: CSV with a header naming the columns `subject`, `scene`,
    /// `point_set`, `time_filter`, `level` (spp, or any stimulus whose detection falls as it
    /// rises, as a positive integer), `correct` and `trials` (in any order; other columns are
    /// ignored). Rows of the same subject, condition and level are summed. Errors name the file
    /// and line.
    pub fn read_counts(files: &[PathBuf]) -> Result<Self> {
        #[derive(serde::Deserialize)]
        struct Row {
            subject: String,
            scene: String,
            point_set: String,
            time_filter: String,
            level: u32,
            correct: u32,
            trials: u32,
        }
        let mut obs = Vec::new();
        for f in files {
            let mut reader = csv::Reader::from_path(f)
                .map_err(|e| anyhow::anyhow!("cannot read counts table {}: {e}", f.display()))?;
            for (i, row) in reader.deserialize::<Row>().enumerate() {
                let line =
                    |e: &csv::Error| e.position().map_or(i as u64 + 2, |p| p.line()).to_string();
                let r = row.map_err(|e| {
                    anyhow::anyhow!(
                        "{}:{}: {e} (expected the columns subject, scene, point_set, \
                         time_filter, level, correct, trials)",
                        f.display(),
                        line(&e)
                    )
                })?;
                let at = format!("{}:{}", f.display(), i + 2);
                if r.level == 0 {
                    bail!("{at}: field `level` is 0; expected a positive integer (spp >= 1)");
                }
                if u64::from(r.trials) > MAX_TRIALS {
                    bail!(
                        "{at}: field `trials` is {}; expected at most {MAX_TRIALS} (a subject's \
                         trials in a whole design; each trial is held in memory)",
                        r.trials
                    );
                }
                if r.correct > r.trials {
                    bail!(
                        "{at}: field `correct` is {} but `trials` is {}; expected correct <= trials",
                        r.correct,
                        r.trials
                    );
                }
                for k in 0..r.trials {
                    obs.push(Observation {
                        subject: r.subject.clone(),
                        scene: r.scene.clone(),
                        point_set: r.point_set.clone(),
                        time_filter: r.time_filter.clone(),
                        level: r.level,
                        correct: k < r.correct,
                    });
                }
            }
        }
        if obs.is_empty() {
            let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
            bail!(
                "{}: no rows with trials; expected a header line and rows of counts",
                names.join(", ")
            );
        }
        let mut ds = Self::from_observations(&obs);
        ds.design = match files {
            [one] => one
                .file_stem()
                .map_or("counts".into(), |s| s.to_string_lossy().into_owned()),
            _ => "counts tables".into(),
        };
        ds.files = files.to_vec();
        ds.source = Source::CountsTables;
        Ok(ds)
    }
}
