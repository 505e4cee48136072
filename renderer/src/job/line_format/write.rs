//! Writing a [`JobFile`] as a `.job` file: the seven lines as in Figure 12, then every
//! extension line that carries information — always `scene`, `reference`, `seed` and the two
//! scopes (they decide whether point sets are comparable), the rest when set.

use crate::job::{JOB_FORMAT, JobFile, ReferenceSpec};
use crate::text::sampling::{self as options, Host};
use crate::text::{Out, names, quote};
use anyhow::{Result, bail};

/// The text of `f`. Fails only for what the seven lines cannot say: another format version, an
/// empty list (its line would be blank, and blank lines are skipped).
pub fn write(f: &JobFile) -> Result<String> {
    if f.format != JOB_FORMAT {
        bail!(
            "field `format` is {:?}; the seven-line format holds {JOB_FORMAT:?} jobs",
            f.format
        );
    }
    let point_sets = spelled(&f.point_sets, names::point_set_to_text);
    let time_filters = spelled(&f.time_filters, names::time_filter_to_text);
    let levels: Vec<String> = f.levels.iter().map(u32::to_string).collect();
    let mut out = Out::default();
    out.bare(
        "# blurlab job: the thesis's seven lines (Figure 12), then extension lines; see \
         docs/thesis-formats.md",
    );
    out.bare(&quote(&f.name));
    for (field, list) in [
        ("levels", &levels),
        ("point_sets", &point_sets),
        ("time_filters", &time_filters),
    ] {
        if list.is_empty() {
            bail!("field `{field}` is empty; a job lists at least one");
        }
        out.bare(&list.len().to_string());
        let words: Vec<String> = list.iter().map(|w| quote(w).into_owned()).collect();
        out.bare(&words.join(" "));
    }
    for s in &f.scenes {
        out.word("scene", s);
    }
    match &f.reference {
        ReferenceSpec::HighestLevel => out.raw(&["reference", "highestlevel"]),
        ReferenceSpec::Independent(r) => {
            out.number("reference", r.spp);
            if let Some(ps) = r.point_set {
                out.word("referencepointset", names::point_set_to_text(ps));
            }
            if let Some(tf) = r.time_filter {
                out.word("referencetimefilter", names::time_filter_to_text(tf));
            }
        }
    }
    out.number("seed", f.seed);
    let o = &f.overrides;
    for (key, v) in [
        ("width", o.width),
        ("height", o.height),
        ("frames", o.frames),
        ("firstframe", o.first_frame),
    ] {
        if let Some(v) = v {
            out.number(key, v);
        }
    }
    if let Some(exr) = o.exr {
        out.number("exr", exr);
    }
    options::write(&o.sampling, &mut out, Host::Job);
    if let Some(n) = f.frames_per_unit {
        out.number("framesperunit", n);
    }
    Ok(out.text)
}

/// The text spellings of `names`, or an error naming the field of one that has none.
fn spelled<T: Copy>(list: &[T], to_text: fn(T) -> &'static str) -> Vec<String> {
    list.iter().map(|&n| to_text(n).to_string()).collect()
}
