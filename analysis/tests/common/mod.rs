//! Checks shared by the integration tests.

use std::path::Path;

/// No report file holds a non-finite number: no word `NaN`, `inf` or `infinity` (as words, so
/// that "infinite slope" in a note does not count). serde_json would write a NaN as `null`;
/// the CSV twins, which hold the same rows, would show it as `NaN`.
pub fn assert_report_is_finite(dir: &Path) {
    for f in [
        "jnd.csv",
        "fits.csv",
        "ttests.csv",
        "report.json",
        "report.md",
    ] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        let bad: Vec<&str> = text
            .split(|c: char| !c.is_ascii_alphanumeric())
            .filter(|w| ["nan", "inf", "infinity"].contains(&w.to_lowercase().as_str()))
            .collect();
        assert!(bad.is_empty(), "{f}: {bad:?}");
    }
}
