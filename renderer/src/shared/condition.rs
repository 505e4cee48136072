//! What a study compares: a scene sampled with a point set and filtered in time and space. The
//! names are enums, checked when a scene, job, manifest, design or log is read, so an unknown
//! name is refused with its file and field instead of failing mid-render.
//!
//! Every name is spelt exactly as the files have always spelt it (serde, [`std::fmt::Display`]
//! and [`std::str::FromStr`] agree), so files and stimulus ids keep their bytes. Names order
//! alphabetically, as the strings they replace did, so sorted tables keep their rows' order.
//! This module depends only on std, serde and anyhow: the experiment and the analysis use it
//! without the tracer. The thesis text formats' own spellings (`stratifiedmc`, `box` for the
//! truncated box) live in `crate::text::names`.

use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::fmt;

/// The file vocabulary of a [`crate::named!`] enum: serde by name (an unknown name's error
/// lists the known ones), `Debug` as the quoted name, and the order by name.
macro_rules! by_name_in_files {
    ($($ty:ident),+) => {$(
        impl Serialize for $ty {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        /// From the name; an unknown name's error lists the known ones (with the field path,
        /// file, line and column added by the reader).
        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = String::deserialize(d)?;
                Self::by_name(&name).map_err(|e| serde::de::Error::custom(e))
            }
        }

        /// The quoted name, as the strings these names replaced printed, so that messages
        /// built with `{:?}` keep their words.
        impl fmt::Debug for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{:?}", self.name())
            }
        }

        /// By name, as the strings these names replaced sorted.
        impl Ord for $ty {
            fn cmp(&self, other: &Self) -> Ordering {
                self.name().cmp(other.name())
            }
        }

        impl PartialOrd for $ty {
            fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
                Some(self.cmp(other))
            }
        }
    )+};
}

/// A point set (thesis Chapter II "Point Sets for Sampling"); the sets themselves are in
/// `crate::sampling::pointset`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub enum PointSetKind {
    /// Independent uniform points.
    Random,
    /// Jittered strata (the thesis's "stratified Monte Carlo").
    Stratified,
    Hammersley,
    /// Poisson-disk points by dart throwing and elimination.
    Poisson,
    Sobol,
    Halton,
}

crate::named!(PointSetKind, "point set", [
    Random => "random",
    Stratified => "stratified",
    Hammersley => "hammersley",
    Poisson => "poisson",
    Sobol => "sobol",
    Halton => "halton",
]);

/// A time filter over the shutter interval [0, 1] (thesis Chapter II "Temporal Filtering
/// Kernels"); its density and warp are in `crate::sampling::time_filter`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub enum TimeFilter {
    /// Uniform over the whole interval (no warp).
    Box,
    /// Uniform over the middle 50%: zero for the first and last quarter.
    TruncatedBox,
    /// Tent peaking at the middle, zero at both ends.
    Triangle,
}

crate::named!(TimeFilter, "time filter", [
    Box => "box",
    TruncatedBox => "truncated_box",
    Triangle => "triangle",
]);

/// The reconstruction filter over the pixel, realised by warping (filter importance sampling,
/// Ernst 2006): every sample then has the same weight. Set per scene or job
/// (`settings.sampling.spatial_filter`), not a factor of a study's conditions.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpatialFilter {
    /// 2D Gaussian by Box-Muller (thesis Figure 16); may reach beyond the pixel.
    Gaussian,
    /// Uniform over the pixel (no warp): what analytic tests need.
    Box,
}

crate::named!(SpatialFilter, "spatial filter", [
    Gaussian => "gaussian",
    Box => "box",
]);

by_name_in_files!(PointSetKind, TimeFilter, SpatialFilter);

/// One condition of a study: a scene rendered with a point set and a time filter (the cell of
/// a design without the level). Manifest entries, trials, log records, predictions and the
/// analysis's observations name theirs with these three fields.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Condition {
    /// The scene's name (its file's stem).
    pub scene: String,
    pub point_set: PointSetKind,
    pub time_filter: TimeFilter,
}

impl Condition {
    pub fn new(scene: impl Into<String>, point_set: PointSetKind, time_filter: TimeFilter) -> Self {
        Self {
            scene: scene.into(),
            point_set,
            time_filter,
        }
    }
}

impl fmt::Display for Condition {
    /// `scene-point_set-time_filter`, the prefix of the condition's stimulus ids.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}-{}", self.scene, self.point_set, self.time_filter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::str::FromStr;

    fn round_trips<T>(all: &[T])
    where
        T: Copy + fmt::Debug + fmt::Display + FromStr + PartialEq + Serialize,
        T: serde::de::DeserializeOwned,
        <T as FromStr>::Err: fmt::Debug,
    {
        for &v in all {
            let name = v.to_string();
            assert_eq!(name.parse::<T>().unwrap(), v);
            let json = serde_json::to_string(&v).unwrap();
            assert_eq!(json, format!("\"{name}\""), "serde writes the name");
            assert_eq!(serde_json::from_str::<T>(&json).unwrap(), v);
        }
    }

    #[test]
    fn every_variant_round_trips_through_serde_and_its_name() {
        round_trips(&PointSetKind::ALL);
        round_trips(&TimeFilter::ALL);
        round_trips(&SpatialFilter::ALL);
        let names = |v: &[&str]| v.join(" ");
        assert_eq!(
            names(&PointSetKind::ALL.map(PointSetKind::name)),
            "random stratified hammersley poisson sobol halton"
        );
        assert_eq!(
            names(&TimeFilter::ALL.map(TimeFilter::name)),
            "box truncated_box triangle"
        );
        assert_eq!(
            names(&SpatialFilter::ALL.map(SpatialFilter::name)),
            "gaussian box"
        );
    }

    #[test]
    fn unknown_names_are_refused_with_the_known_ones() {
        let e = "jittered".parse::<PointSetKind>().unwrap_err().to_string();
        assert!(e.contains("unknown point set \"jittered\""), "{e}");
        assert!(e.contains("random, stratified, hammersley"), "{e}");
        let e = TimeFilter::by_name("tent").unwrap_err().to_string();
        assert!(e.contains("box, truncated_box, triangle"), "{e}");
        // serde's message is the same; the thesis spelling is not a JSON name.
        let e = serde_json::from_str::<PointSetKind>("\"stratifiedmc\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown point set \"stratifiedmc\""), "{e}");
        assert!(e.contains("random, stratified, hammersley"), "{e}");
        let e = serde_json::from_str::<SpatialFilter>("\"gauss\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("gaussian, box"), "{e}");
    }

    #[test]
    fn names_sort_as_the_strings_did() {
        let mut sets = PointSetKind::ALL;
        sets.sort();
        let mut names = PointSetKind::ALL.map(PointSetKind::name);
        names.sort();
        assert_eq!(sets.map(PointSetKind::name), names);
        assert!(
            TimeFilter::Triangle < TimeFilter::TruncatedBox,
            "as \"triangle\" < \"truncated_box\""
        );
        assert_eq!(
            format!("{:?}", TimeFilter::TruncatedBox),
            "\"truncated_box\""
        );
        let c = Condition::new("plane", PointSetKind::Hammersley, TimeFilter::TruncatedBox);
        assert_eq!(c.to_string(), "plane-hammersley-truncated_box");
        assert_eq!(
            serde_json::to_string(&c).unwrap(),
            r#"{"scene":"plane","point_set":"hammersley","time_filter":"truncated_box"}"#
        );
    }
}
