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
/// message saying what was expected (clap's own would suggest `-- -1`).
fn whole(s: &str, lo: u32, hi: u32, unit: &str) -> Result<u32, String> {
    match s.trim().parse::<i64>() {
        Ok(v) if (lo as i64..=hi as i64).contains(&v) => Ok(v as u32),
        _ => Err(format!(
            "`{s}`: expected a whole number of {unit} from {lo} to {hi}"
        )),
    }
}

/// clap value parser of an image side (`--width`, `--height`).
pub fn parse_side(s: &str) -> Result<u32, String> {
    whole(s, 1, MAX_IMAGE_SIDE, "pixels")
}

/// clap value parser of samples per pixel (`--spp`, levels).
pub fn parse_spp(s: &str) -> Result<u32, String> {
    whole(s, 1, MAX_SPP, "samples per pixel")
}

#[cfg(test)]
mod tests {
    use super::*;

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
    }
}
