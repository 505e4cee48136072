//! The thesis's spellings of point set and time filter names, and the suite's.
//!
//! - Point sets: Figure 12 writes `stratifiedmc` (Stratified Monte Carlo) for the suite's
//!   `stratified`; both are read, `stratifiedmc` is written. Every other name is the sampler's.
//! - Time filters: the thesis's renderer had two time warps, `inverseTruncatedBox` and
//!   `inverseTriangle` (Figure 16), and its text explores "two time filters, namely the
//!   truncated box filter and the triangle filter" (Chapter II), while Figure 12's job lists the
//!   two as `box triangle`. In the thesis's formats `box` therefore means the thesis's box
//!   filter, the **truncated box** (the suite's `truncated_box`); `truncatedbox` is read as the
//!   same. The full-shutter box, which the thesis never used, is `fullbox` (the suite's `box`).
//!   The writers write `box`, `fullbox` and `triangle`.
//!
//! Every suite name is read as itself too (`stratified`, `truncated_box`), except `box`.

use crate::condition::{PointSetKind, TimeFilter};

/// The words a text file may use for a point set.
pub const POINT_SET_WORDS: [&str; 7] = [
    "random",
    "stratifiedmc",
    "stratified",
    "hammersley",
    "poisson",
    "sobol",
    "halton",
];

/// The words a text file may use for a time filter.
pub const TIME_FILTER_WORDS: [&str; 5] = [
    "fullbox",
    "box",
    "truncatedbox",
    "truncated_box",
    "triangle",
];

/// The point set a word of a text file names; the error lists [`POINT_SET_WORDS`].
pub fn point_set_from_text(word: &str) -> Result<PointSetKind, String> {
    match word {
        "stratifiedmc" => Ok(PointSetKind::Stratified),
        w => w.parse().map_err(|_| {
            format!(
                "unknown point set {w:?}; expected one of {}",
                POINT_SET_WORDS.join(", ")
            )
        }),
    }
}

/// The text files' word for a point set.
pub fn point_set_to_text(set: PointSetKind) -> &'static str {
    match set {
        PointSetKind::Stratified => "stratifiedmc",
        s => s.name(),
    }
}

/// The time filter a word of a text file names; the error lists [`TIME_FILTER_WORDS`].
pub fn time_filter_from_text(word: &str) -> Result<TimeFilter, String> {
    match word {
        "box" | "truncatedbox" => Ok(TimeFilter::TruncatedBox),
        "fullbox" => Ok(TimeFilter::Box),
        w => w.parse().map_err(|_| {
            format!(
                "unknown time filter {w:?}; expected one of {} (`box` is the thesis's \
                 truncated box)",
                TIME_FILTER_WORDS.join(", ")
            )
        }),
    }
}

/// The text files' word for a time filter.
pub fn time_filter_to_text(filter: TimeFilter) -> &'static str {
    match filter {
        TimeFilter::TruncatedBox => "box",
        TimeFilter::Box => "fullbox",
        f => f.name(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_round_trips_and_the_thesis_spellings_map() {
        for set in PointSetKind::ALL {
            let text = point_set_to_text(set);
            assert!(POINT_SET_WORDS.contains(&text));
            assert_eq!(point_set_from_text(text), Ok(set));
            assert_eq!(
                point_set_from_text(set.name()),
                Ok(set),
                "suite names read too"
            );
        }
        for f in TimeFilter::ALL {
            let text = time_filter_to_text(f);
            assert!(TIME_FILTER_WORDS.contains(&text));
            assert_eq!(time_filter_from_text(text), Ok(f));
        }
        for w in POINT_SET_WORDS {
            assert!(point_set_from_text(w).is_ok(), "{w}");
        }
        for w in TIME_FILTER_WORDS {
            assert!(time_filter_from_text(w).is_ok(), "{w}");
        }
        assert_eq!(
            point_set_from_text("stratifiedmc"),
            Ok(PointSetKind::Stratified)
        );
        assert_eq!(time_filter_from_text("box"), Ok(TimeFilter::TruncatedBox));
        assert_eq!(
            time_filter_from_text("truncatedbox"),
            Ok(TimeFilter::TruncatedBox)
        );
        assert_eq!(
            time_filter_from_text("truncated_box"),
            Ok(TimeFilter::TruncatedBox)
        );
        assert_eq!(time_filter_from_text("fullbox"), Ok(TimeFilter::Box));
        assert_eq!(time_filter_from_text("triangle"), Ok(TimeFilter::Triangle));
        let e = point_set_from_text("jittered").unwrap_err();
        assert!(e.contains("random, stratifiedmc, stratified"), "{e}");
        let e = time_filter_from_text("tent").unwrap_err();
        assert!(e.contains("fullbox, box"), "{e}");
    }
}
