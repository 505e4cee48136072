//! Compressed videos through the `ffmpeg` program, when it is installed: FFV1 in Matroska
//! (bit-exact lossless RGB, planar `gbrp`) or H.264 in MP4 (`libx264`, `-qp 0`: lossless in
//! Y'CbCr 4:4:4, the "High 4:4:4 Predictive" profile; RGB -> Y'CbCr conversion still rounds).

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A codec reached through ffmpeg.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Codec {
    Ffv1,
    H264,
}

impl Codec {
    /// File extension of the container used for this codec.
    pub fn extension(self) -> &'static str {
        match self {
            Codec::Ffv1 => "mkv",
            Codec::H264 => "mp4",
        }
    }

    fn args(self) -> &'static [&'static str] {
        match self {
            Codec::Ffv1 => &[
                "-c:v", "ffv1", "-level", "3", "-pix_fmt", "gbrp", "-f", "matroska",
            ],
            Codec::H264 => &[
                "-c:v",
                "libx264",
                "-preset",
                "medium",
                "-qp",
                "0",
                "-pix_fmt",
                "yuv444p",
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ],
        }
    }
}

/// The `ffmpeg` program to call: `$BLURLAB_FFMPEG` if set, else `ffmpeg` on the PATH.
pub fn ffmpeg_program() -> PathBuf {
    std::env::var_os("BLURLAB_FFMPEG")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("ffmpeg"))
}

/// Whether ffmpeg can be started.
pub fn ffmpeg_available() -> bool {
    Command::new(ffmpeg_program())
        .arg("-version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// The full argument list encoding `frames` (PNG files named `<prefix>NNNN.png`, consecutive
/// from `start`) at `fps` into `out`.
pub fn encode_args(pattern: &Path, start: u32, fps: f64, codec: Codec, out: &Path) -> Vec<String> {
    let mut args: Vec<String> = ["-y", "-nostdin", "-loglevel", "error", "-framerate"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.push(format!("{fps}"));
    args.extend(["-start_number".into(), start.to_string()]);
    args.extend(["-i".into(), pattern.display().to_string()]);
    args.extend(codec.args().iter().map(|s| s.to_string()));
    args.push(out.display().to_string());
    args
}

/// Encode a stimulus's PNG frames (which must be `frame_NNNN.png`, consecutive) into `out`,
/// atomically (ffmpeg writes a temporary file that is renamed when it succeeds).
pub fn encode(frames: &[PathBuf], fps: f64, codec: Codec, out: &Path) -> Result<()> {
    let (pattern, start) = frame_pattern(frames)?;
    let tmp = crate::atomic::temp_path(out);
    let args = encode_args(&pattern, start, fps, codec, &tmp);
    let result = Command::new(ffmpeg_program()).args(&args).output();
    let output = match result {
        Ok(o) => o,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
            "`ffmpeg` is not installed (not found on PATH; set BLURLAB_FFMPEG to its path). \
             Install it (e.g. `apt install ffmpeg`) or export with `--format y4m`, which needs \
             no external program"
        ),
        Err(e) => return Err(e).context("cannot start ffmpeg"),
    };
    if !output.status.success() {
        let _ = std::fs::remove_file(&tmp);
        bail!(
            "ffmpeg failed writing {}: {}",
            out.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    std::fs::rename(&tmp, out)
        .with_context(|| format!("cannot move {} to {}", tmp.display(), out.display()))
}

/// The printf pattern (`dir/frame_%04d.png`) and first number of consecutive frame files.
fn frame_pattern(frames: &[PathBuf]) -> Result<(PathBuf, u32)> {
    let number = |p: &PathBuf| -> Option<u32> {
        let name = p.file_name()?.to_str()?;
        let digits = name.strip_prefix("frame_")?.strip_suffix(".png")?;
        (digits.len() == 4).then(|| digits.parse().ok())?
    };
    let Some(first) = frames.first() else {
        bail!("no frames to encode");
    };
    let start = number(first)
        .with_context(|| format!("{}: expected a frame named frame_NNNN.png", first.display()))?;
    for (i, p) in frames.iter().enumerate() {
        if number(p) != Some(start + i as u32) || p.parent() != first.parent() {
            bail!(
                "{}: frames must be consecutive frame_NNNN.png files in one folder",
                p.display()
            );
        }
    }
    Ok((first.with_file_name("frame_%04d.png"), start))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_name_codec_rate_and_pattern() {
        let args = encode_args(
            Path::new("s/a/frame_%04d.png"),
            0,
            30.0,
            Codec::Ffv1,
            Path::new("a.mkv"),
        );
        let line = args.join(" ");
        assert!(
            line.contains("-framerate 30 -start_number 0 -i s/a/frame_%04d.png"),
            "{line}"
        );
        assert!(
            line.contains("-c:v ffv1") && line.contains("gbrp"),
            "{line}"
        );
        assert!(line.ends_with("a.mkv"));
    }

    #[test]
    fn frames_must_be_consecutive() {
        let f = |n: u32| PathBuf::from(format!("d/frame_{n:04}.png"));
        assert_eq!(frame_pattern(&[f(3), f(4)]).unwrap().1, 3);
        assert!(frame_pattern(&[f(0), f(2)]).is_err());
        assert!(frame_pattern(&[PathBuf::from("d/x.png")]).is_err());
    }

    #[test]
    fn a_missing_ffmpeg_gives_an_actionable_message() {
        if ffmpeg_available() {
            eprintln!("ffmpeg is installed; the missing-program message is not exercised");
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let frame = dir.path().join("frame_0000.png");
        image::RgbImage::new(2, 2).save(&frame).unwrap();
        let err = encode(&[frame], 30.0, Codec::H264, &dir.path().join("v.mp4")).unwrap_err();
        let msg = format!("{err:#}");
        assert!(
            msg.contains("not installed") && msg.contains("y4m"),
            "{msg}"
        );
    }
}
