//! The sampling options both text formats share (`docs/sampling.md`): `spatialfilter
//! gaussian|box`, `spatialsigma S`, `density joint|temporal K|spatial K`, `pointsetscope
//! frame|sequence`, `shiftscope frame|sequence` and `randomization shift|scramble` (an
//! extension: the thesis had only the shift). A job's scopes may also be `scene` (leave
//! it to each scene's settings), because a job's scopes default to `frame` (see
//! [`JOB_SCOPE_DEFAULT`]).

use super::{Entries, Out};
use crate::sampling::{Density, Randomization, SamplingOptions, Scope, SpatialFilter};
use anyhow::Result;

/// The scopes of a `.job` without `pointsetscope`/`shiftscope` lines: every point set gets a
/// new set and new pixel shifts every frame (`docs/sampling.md`, "Temporal structure").
pub const JOB_SCOPE_DEFAULT: Scope = Scope::Frame;

/// Which format reads or writes the options.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Host {
    /// A scene's settings block: unset options are unset (the sampler's defaults).
    Scene,
    /// A job: scopes default to [`JOB_SCOPE_DEFAULT`]; `scene` leaves them unset.
    Job,
}

fn scope_word(s: Option<Scope>) -> &'static str {
    match s {
        Some(Scope::Frame) => "frame",
        Some(Scope::Sequence) => "sequence",
        None => "scene",
    }
}

/// Read the options; `field` is the model path of the options (`sampling`, `overrides.sampling`).
pub fn read(e: &mut Entries, field: &str, host: Host) -> Result<SamplingOptions> {
    let f = |name: &str| format!("{field}.{name}");
    let spatial_filter = e
        .choice("spatialfilter", &f("spatial_filter"), &["gaussian", "box"])?
        .map(|w| match w.as_str() {
            "box" => SpatialFilter::Box,
            _ => SpatialFilter::Gaussian,
        });
    let spatial_sigma = e.f64("spatialsigma", &f("spatial_sigma"))?;
    let density = match e.take("density", &f("density")) {
        None => None,
        Some(entry) => Some(density(e, &entry)?),
    };
    let mut scope = |key: &'static str, name: &str| -> Result<Option<Scope>> {
        let options: &[&str] = match host {
            Host::Scene => &["frame", "sequence"],
            Host::Job => &["frame", "sequence", "scene"],
        };
        Ok(match e.choice(key, &f(name), options)?.as_deref() {
            Some("frame") => Some(Scope::Frame),
            Some("sequence") => Some(Scope::Sequence),
            Some(_) => None,
            None if host == Host::Job => Some(JOB_SCOPE_DEFAULT),
            None => None,
        })
    };
    let point_set_scope = scope("pointsetscope", "point_set_scope")?;
    let shift_scope = scope("shiftscope", "shift_scope")?;
    // Unset without a line in both formats: the scene's, else the thesis's shift.
    let randomization = e
        .choice("randomization", &f("randomization"), &["shift", "scramble"])?
        .map(|w| match w.as_str() {
            "scramble" => Randomization::Scramble,
            _ => Randomization::Shift,
        });
    Ok(SamplingOptions {
        spatial_filter,
        spatial_sigma,
        density,
        point_set_scope,
        shift_scope,
        randomization,
    })
}

fn density(e: &Entries, entry: &super::Entry) -> Result<Density> {
    let expected = "expects `joint`, `temporal K` or `spatial K`";
    let count = |w: &str| -> Result<u32> {
        w.parse()
            .map_err(|_| e.error(entry, format!("{expected}; `{w}` is not a whole number")))
    };
    match entry.values.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["joint"] => Ok(Density::Joint),
        ["temporal", k] => Ok(Density::Temporal(count(k)?)),
        ["spatial", k] => Ok(Density::Spatial(count(k)?)),
        _ => Err(e.error(
            entry,
            format!("{expected}; found `{}`", entry.values.join(" ")),
        )),
    }
}

/// Write the options that differ from what `host`'s reader would assume without a line.
pub fn write(o: &SamplingOptions, out: &mut Out, host: Host) {
    if let Some(f) = o.spatial_filter {
        out.word(
            "spatialfilter",
            match f {
                SpatialFilter::Gaussian => "gaussian",
                SpatialFilter::Box => "box",
            },
        );
    }
    if let Some(s) = o.spatial_sigma {
        out.number("spatialsigma", s);
    }
    match o.density {
        None => {}
        Some(Density::Joint) => out.raw(&["density", "joint"]),
        Some(Density::Temporal(k)) => out.raw(&["density", "temporal", &k.to_string()]),
        Some(Density::Spatial(k)) => out.raw(&["density", "spatial", &k.to_string()]),
    }
    for (key, s) in [
        ("pointsetscope", o.point_set_scope),
        ("shiftscope", o.shift_scope),
    ] {
        // A job always says its scopes: they are what makes the point sets comparable.
        if host == Host::Job || s.is_some() {
            out.raw(&[key, scope_word(s)]);
        }
    }
    if let Some(r) = o.randomization {
        out.word("randomization", r.name());
    }
}
