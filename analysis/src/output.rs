//! Writing a [`Report`] into its folder: `jnd.csv`, `fits.csv`, `ttests.csv`, `report.json`
//! (format `blurlab-report/1`), `thesis_tables.csv` with `--preset thesis`, the figures and
//! `report.md`, each file atomically. Above both the report and the figures, so that neither
//! imports the other.

use crate::report::{Preset, REPORT_FORMAT, Report};
use anyhow::Result;
use serde::Serialize;
use std::path::Path;

/// Write the CSV, JSON and Markdown files (and the figures) of `report` into `dir`, each
/// atomically.
pub fn write(report: &Report, dir: &Path) -> Result<()> {
    write_csv(&dir.join("jnd.csv"), &report.jnd_rows())?;
    write_csv(&dir.join("fits.csv"), &report.fit_rows())?;
    write_csv(&dir.join("ttests.csv"), &report.ttest_rows())?;
    let mut json = serde_json::json!({
        "format": REPORT_FORMAT,
        "design": report.design,
        "design_hash": report.design_hash,
        "subjects": report.subjects,
        "files": report.files,
        "trials": report.trials,
        "warnings": report.warnings,
        "source": report.source,
        "excluded": report.excluded,
        "settings": report.settings,
        "jnd": report.jnd_rows(),
        "fits": report.fit_rows(),
        "ttests": report.ttest_rows(),
    });
    if let Some(m) = &report.multilevel {
        json["multilevel"] = serde_json::to_value(m)?;
    }
    renderer::atomic::write_atomic(
        &dir.join("report.json"),
        (serde_json::to_string_pretty(&json)? + "\n").as_bytes(),
    )?;
    let thesis_csv = dir.join("thesis_tables.csv");
    if report.settings.preset == Some(Preset::Thesis) {
        write_csv(&thesis_csv, &report.thesis_rows())?;
    } else if thesis_csv.is_file() {
        // A preset run's tables left in this folder would no longer match the report.
        std::fs::remove_file(&thesis_csv)?;
    }
    let figures = crate::figures::draw_all(report, &dir.join("figures"))?;
    renderer::atomic::write_atomic(&dir.join("report.md"), report.markdown(&figures).as_bytes())
}

/// A tidy CSV: a header line, then one line per row. With no rows the header comes from a
/// default row, so that an empty table (e.g. no t-tests with a single scene and point set)
/// still names its columns.
fn write_csv<T: Serialize + Default>(path: &Path, rows: &[T]) -> Result<()> {
    renderer::atomic::write_atomic_with(path, |w| {
        if rows.is_empty() {
            let mut probe = csv::Writer::from_writer(Vec::new());
            probe.serialize(T::default())?;
            let text = probe.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
            let header = text.split(|&b| b == b'\n').next().unwrap_or_default();
            w.write_all(header)?;
            w.write_all(b"\n")?;
            return Ok(());
        }
        let mut c = csv::Writer::from_writer(w);
        for r in rows {
            c.serialize(r)?;
        }
        c.flush()?;
        Ok(())
    })
}
