//! Stimulus ids, the names every later part uses for a rendered stimulus: the manifest's
//! entries, the design's trials, the session logs and the analysis all refer to stimuli by
//! them (`plane-hammersley-truncated_box-0064`, `plane-reference`). They live in the light core
//! so that the experiment and the analysis can build them without the tracer.

use crate::condition::{PointSetKind, TimeFilter};

/// The id of a test stimulus, from the names of its scene, point set and time filter. Levels
/// are zero-padded to four digits so ids sort by level.
pub fn stimulus_id(
    scene: &str,
    point_set: PointSetKind,
    time_filter: TimeFilter,
    spp: u32,
) -> String {
    format!("{scene}-{point_set}-{time_filter}-{spp:04}")
}

/// The parts of an id [`stimulus_id`] made (scene, point set, time filter, spp); `None` for
/// an id of any other form (a reference's, or one written elsewhere).
pub fn parse_stimulus_id(id: &str) -> Option<(&str, PointSetKind, TimeFilter, u32)> {
    let mut parts = id.rsplitn(4, '-');
    let (spp, filter, points, scene) = (parts.next()?, parts.next()?, parts.next()?, parts.next()?);
    let level = spp.parse().ok().filter(|_| spp.len() >= 4)?;
    let parsed = (
        scene,
        PointSetKind::by_name(points).ok()?,
        TimeFilter::by_name(filter).ok()?,
        level,
    );
    (stimulus_id(parsed.0, parsed.1, parsed.2, parsed.3) == id).then_some(parsed)
}

/// The id of a scene's reference.
pub fn reference_id(scene: &str) -> String {
    format!("{scene}-reference")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_sort_by_level_and_name_their_parts() {
        assert_eq!(
            stimulus_id("plane", PointSetKind::Hammersley, TimeFilter::Box, 8),
            "plane-hammersley-box-0008"
        );
        let id = |spp| stimulus_id("s", PointSetKind::Sobol, TimeFilter::Triangle, spp);
        assert!(id(64) < id(512));
        assert_eq!(reference_id("plane"), "plane-reference");
        // Parsing gives back the parts, scene names with dashes included; other forms are none.
        let made = stimulus_id("a-b", PointSetKind::Poisson, TimeFilter::TruncatedBox, 64);
        assert_eq!(
            parse_stimulus_id(&made),
            Some(("a-b", PointSetKind::Poisson, TimeFilter::TruncatedBox, 64))
        );
        for other in [
            "plane-reference",
            "plane-hammersley-box-64",
            "x-nosuch-box-0064",
            "x",
        ] {
            assert_eq!(parse_stimulus_id(other), None, "{other}");
        }
    }
}
