//! The suite's limits on sizes, counts and magnitudes, in one place.
//!
//! Every input that can carry one of these quantities (command line, scene, job, design,
//! observer, session log) checks it against the same constant here where it enters, so that
//! no file or flag can make a command allocate without bound or hand the tracer a number that
//! floats cannot represent. `docs/limits.md` lists them and what each kind of bad input gets.
//! Add a limit here rather than beside the reader that first needs it.

/// Largest image side in pixels (a typo guard: 16384² pixels is 3 GB of film).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Most samples per pixel of one render: the point sets' largest set (Owen-scrambled Sobol
/// stops at 2^16; no study needs more per pixel, and the limit keeps Poisson elimination and
/// memory bounded).
pub const MAX_SPP: u32 = 1 << 16;

/// Largest magnitude of any number in a scene (coordinates, sizes, velocities, intensities,
/// times), and of any velocity times the largest |time| of the animation. Why 1e7: the tracer
/// computes in 32-bit floats, whose spacing at 1e7 is one unit, and squares such numbers (a
/// sphere's radius², a ray's length²) where 1e20 overflows to infinity and the object vanishes.
/// A scene in feet or metres with detail near one unit stays far inside it.
pub const MAX_MAGNITUDE: f64 = 1e7;

/// Largest side of an image the suite reads (environment maps, EXR frames): real sky captures
/// are at most 16384 x 8192.
pub const MAX_MAP_SIDE: u32 = 32768;

/// Most pixels of an image the suite reads: 2^28 texels (16384 x 16384), 3 GB as RGB f32.
pub const MAX_MAP_TEXELS: usize = 1 << 28;

/// Most subjects of one study, simulated (`simulate --subjects`, the demo) or planned (each of
/// `plan --subjects`): psychophysical studies have tens; a thousand simulated subjects of a
/// 100 000-trial design is already 10^8 trials. `plan --subjects 1000000000` used to run until
/// killed.
pub const MAX_SUBJECTS: usize = 1000;

/// Most simulated studies per subject count (`plan --replications`). The interval of a rate
/// from 10 000 replications is +-0.01 at worst; every replication's outcome is held in memory
/// until summarised, and `plan --replications 1000000000` grew by 0.3 GB/s until killed.
pub const MAX_REPLICATIONS: u64 = 10_000;

/// Most bootstrap resamples per fit (`analyze --bootstrap`, `--subject-bootstrap`, `plan
/// --resamples`, the demo's `--bootstrap`): a reported interval needs about 2000; each resample
/// is a fit, so 10^5 of them is already minutes per pooled group.
pub const MAX_RESAMPLES: usize = 100_000;

/// An image of `w` x `h` pixels that the suite may read (at least one pixel, within
/// [`MAX_MAP_SIDE`] and [`MAX_MAP_TEXELS`]).
pub fn check_texels(w: usize, h: usize) -> anyhow::Result<()> {
    let side = MAX_MAP_SIDE as usize;
    if w == 0 || h == 0 || w > side || h > side || w * h > MAX_MAP_TEXELS {
        anyhow::bail!(
            "expected 1 to {side} pixels a side and at most {MAX_MAP_TEXELS} in all (a corrupt \
             header?)"
        );
    }
    Ok(())
}

/// `v` as a side of an image: 1 to [`MAX_IMAGE_SIDE`] pixels.
pub fn check_side(v: u32) -> Result<u32, String> {
    if (1..=MAX_IMAGE_SIDE).contains(&v) {
        Ok(v)
    } else {
        Err(format!("is {v}; expected 1 to {MAX_IMAGE_SIDE} pixels"))
    }
}

/// A whole number from `lo` to `hi` on the command line; negative numbers and others get a
/// message saying what was expected (clap's own would suggest `-- -1`). Flags using it set
/// `allow_hyphen_values` so that `-1` reaches it.
fn whole<T: TryFrom<i128>>(s: &str, lo: u64, hi: u64, unit: &str) -> Result<T, String> {
    match s.trim().parse::<i128>() {
        Ok(v) if (lo as i128..=hi as i128).contains(&v) => {
            T::try_from(v).map_err(|_| format!("`{s}`: too large here"))
        }
        _ => Err(format!(
            "`{s}`: expected a whole number of {unit} from {lo} to {hi}"
        )),
    }
}

/// A clap value parser of a real number in `lo..=hi` (`open`: both ends excluded), named
/// `what` in the message; `-0.5` and `1.5` get the range instead of clap's `-- -0.5` hint or
/// a silent accept.
pub fn real(
    lo: f64,
    hi: f64,
    open: bool,
    what: &'static str,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let inside = |v: f64| {
            if open {
                v > lo && v < hi
            } else {
                v >= lo && v <= hi
            }
        };
        match s.trim().parse::<f64>() {
            Ok(v) if inside(v) => Ok(v),
            _ => {
                let (l, r) = if open { ("(", ")") } else { ("[", "]") };
                Err(format!("`{s}`: expected {what} in {l}{lo}, {hi}{r}"))
            }
        }
    }
}

/// clap value parser of an image side (`--width`, `--height`).
pub fn parse_side(s: &str) -> Result<u32, String> {
    whole(s, 1, MAX_IMAGE_SIDE as u64, "pixels")
}

/// clap value parser of samples per pixel (`--spp`, levels).
pub fn parse_spp(s: &str) -> Result<u32, String> {
    whole(s, 1, MAX_SPP as u64, "samples per pixel")
}

/// `x` for a message in its shortest form: `1e308` and `1e-300` rather than Rust's `{}`,
/// which writes every digit (309 of them for 1e308, 300 zeros for 1e-300).
pub fn shortest(x: f64) -> String {
    let plain = format!("{x}");
    let sci = format!("{x:e}");
    if sci.len() < plain.len() { sci } else { plain }
}

/// clap value parser of a seed (`--seed`): any whole number from 0 to 2^64 - 1; `-1` gets
/// this range, not clap's `-- -1` hint.
pub fn parse_seed(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(v) => Ok(v),
        Err(_) => Err(format!(
            "`{s}`: expected a seed, a whole number from 0 to {}",
            u64::MAX
        )),
    }
}

/// clap value parser of `--cpus-per-task`: 1 to 4096 CPUs.
pub fn parse_cpus(s: &str) -> Result<u32, String> {
    whole(s, 1, 4096, "CPUs per task")
}

/// clap value parser of a subject count (`simulate --subjects`, each of `plan --subjects`).
pub fn parse_subjects(s: &str) -> Result<usize, String> {
    whole(s, 1, MAX_SUBJECTS as u64, "subjects")
}

/// clap value parser of `plan --replications`.
pub fn parse_replications(s: &str) -> Result<u64, String> {
    whole(s, 1, MAX_REPLICATIONS, "replications")
}

/// clap value parser of a bootstrap's resample count; `min` is the fewest that give the
/// interval the flag reports (0 where the bootstrap can be switched off).
pub fn resamples(min: u64) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync {
    move |s: &str| whole(s, min, MAX_RESAMPLES as u64, "resamples")
}

/// The same limits for a library caller: `what` names the count (a flag or a field).
pub fn check_count(what: &str, v: u64, lo: u64, hi: u64) -> anyhow::Result<()> {
    if !(lo..=hi).contains(&v) {
        anyhow::bail!("{what} is {v}; expected {lo} to {hi} (renderer::limits)");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_messages_take_their_shortest_form() {
        assert_eq!(shortest(1e308), "1e308");
        assert_eq!(shortest(1e-300), "1e-300");
        assert_eq!(shortest(0.25), "0.25");
        assert_eq!(shortest(125.0), "125");
        assert_eq!(shortest(-1.0), "-1");
        assert_eq!(shortest(f64::NAN), "NaN");
    }

    #[test]
    fn command_line_numbers_say_what_was_expected() {
        assert_eq!(parse_side("768"), Ok(768));
        for bad in ["-1", "0", "100000", "1.5", "x"] {
            let e = parse_side(bad).unwrap_err();
            assert!(e.contains("from 1 to 16384"), "{e}");
        }
        assert_eq!(parse_spp("65536"), Ok(65536));
        assert!(parse_spp("65537").is_err());
        assert!(parse_spp("-1").unwrap_err().contains("samples per pixel"));
        assert!(check_side(100_000).is_err() && check_side(16384).is_ok());
        assert_eq!(parse_subjects("1000"), Ok(1000));
        assert!(
            parse_subjects("1000000000")
                .unwrap_err()
                .contains("1 to 1000")
        );
        assert!(parse_subjects("-3").is_err() && parse_subjects("0").is_err());
        assert!(parse_replications("99999999999999999999999").is_err());
        assert_eq!(resamples(0)("0"), Ok(0));
        assert!(resamples(19)("18").is_err());
    }

    #[test]
    fn real_numbers_keep_their_range() {
        let p = real(0.0, 1.0, true, "a probability");
        assert_eq!(p("0.8"), Ok(0.8));
        for bad in ["1.5", "1", "0", "-0.5", "NaN", "inf", "x"] {
            let e = p(bad).unwrap_err();
            assert!(e.contains("expected a probability in (0, 1)"), "{bad}: {e}");
        }
        let q = real(0.0, 1.0, false, "a share");
        assert_eq!(q("0"), Ok(0.0));
        assert_eq!(q("1"), Ok(1.0));
        assert!(q("NaN").is_err());
    }
}
