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
//! Other names pass through unchanged, so a point set or filter added to the sampler needs no
//! change here; the sampler decides whether a name exists.

/// The suite's point set name for a name in a text file.
pub fn point_set_from_text(word: &str) -> String {
    match word {
        "stratifiedmc" => "stratified",
        w => w,
    }
    .to_string()
}

/// The text files' point set name for a suite name, or `None` if a text file could not say it
/// (a name the reader would turn into another).
pub fn point_set_to_text(name: &str) -> Option<&str> {
    match name {
        "stratified" => Some("stratifiedmc"),
        "stratifiedmc" => None,
        n => Some(n),
    }
}

/// The suite's time filter name for a name in a text file.
pub fn time_filter_from_text(word: &str) -> String {
    match word {
        "box" | "truncatedbox" => "truncated_box",
        "fullbox" => "box",
        w => w,
    }
    .to_string()
}

/// The text files' time filter name for a suite name, or `None` if a text file could not say
/// it.
pub fn time_filter_to_text(name: &str) -> Option<&str> {
    match name {
        "truncated_box" => Some("box"),
        "box" => Some("fullbox"),
        "fullbox" | "truncatedbox" => None,
        n => Some(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::TimeFilter;
    use crate::sampling::pointset;

    #[test]
    fn every_sampler_name_round_trips_and_the_thesis_spellings_map() {
        for set in pointset::ALL {
            let text = point_set_to_text(set.name()).unwrap();
            assert_eq!(point_set_from_text(text), set.name());
        }
        for f in TimeFilter::ALL {
            let text = time_filter_to_text(f.name()).unwrap();
            assert_eq!(time_filter_from_text(text), f.name());
        }
        assert_eq!(point_set_from_text("stratifiedmc"), "stratified");
        assert_eq!(point_set_from_text("stratified"), "stratified");
        assert_eq!(time_filter_from_text("box"), "truncated_box");
        assert_eq!(time_filter_from_text("truncatedbox"), "truncated_box");
        assert_eq!(time_filter_from_text("fullbox"), "box");
        assert_eq!(time_filter_from_text("triangle"), "triangle");
        // Names a reader would change cannot be written.
        assert_eq!(point_set_to_text("stratifiedmc"), None);
        assert_eq!(time_filter_to_text("fullbox"), None);
    }
}
