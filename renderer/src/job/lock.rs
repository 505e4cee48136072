//! Who is rendering into a job folder: one lock file per running `render job`
//! (`.render-<part>.<pid>.lock`, `<part>` = `all` or `shard-K-of-N`), so that two runs that
//! would write the same frames do not overlap. Shards of one job cooperate (each renders its
//! own units); a whole-job run refuses to start beside any other live run, and a shard refuses
//! beside a whole-job run or a run of the same shard. A lock of a process that no longer exists
//! (killed with -9) is stale and removed. Temporary files (`.name.PID.tmp`) of dead processes
//! are removed by [`remove_stale_temporaries`]; a live run's are left alone.

use super::shard::Shard;
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// A held lock; dropping it removes the file.
#[derive(Debug)]
pub struct JobLock {
    path: PathBuf,
}

/// What a lock file's name says about its run.
struct Holder {
    part: String,
    pid: u32,
    path: PathBuf,
}

fn part_of(shard: Shard) -> String {
    if shard == Shard::WHOLE {
        "all".into()
    } else {
        format!("shard-{}-of-{}", shard.index, shard.count)
    }
}

fn holders(dir: &Path) -> Vec<Holder> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let rest = name.strip_prefix(".render-")?.strip_suffix(".lock")?;
            let (part, pid) = rest.rsplit_once('.')?;
            Some(Holder {
                part: part.to_string(),
                pid: pid.parse().ok()?,
                path: e.path(),
            })
        })
        .collect()
}

/// Whether process `pid` exists. Where `/proc` is absent (not Linux), every process counts as
/// alive, so a stale lock is reported instead of taken over.
pub fn alive(pid: u32) -> bool {
    pid == std::process::id()
        || !Path::new("/proc/self").exists()
        || Path::new(&format!("/proc/{pid}")).exists()
}

impl JobLock {
    /// Take the lock of `shard`'s run in `job_dir` (created if needed), or say which run holds
    /// the folder.
    pub fn acquire(job_dir: &Path, shard: Shard) -> Result<Self> {
        std::fs::create_dir_all(job_dir)
            .with_context(|| format!("cannot create folder {}", job_dir.display()))?;
        let part = part_of(shard);
        let me = std::process::id();
        let path = job_dir.join(format!(".render-{part}.{me}.lock"));
        std::fs::write(&path, format!("{me}\n"))
            .with_context(|| format!("cannot write lock file {}", path.display()))?;
        let lock = Self { path };
        for h in holders(job_dir) {
            if h.pid == me {
                continue;
            }
            if !alive(h.pid) {
                let _ = std::fs::remove_file(&h.path);
                continue;
            }
            if part == "all" || h.part == "all" || h.part == part {
                let theirs = if h.part == "all" {
                    "the whole job".to_string()
                } else {
                    h.part.replace('-', " ")
                };
                bail!(
                    "{} is being rendered by another `blurlab render job` (process {}, {theirs}; lock \
                     file {}). Wait for it to finish, or run disjoint shards side by side \
                     (--shard K/N); if process {} is not a render, delete the lock file",
                    job_dir.display(),
                    h.pid,
                    h.path.display(),
                    h.pid
                );
            }
        }
        Ok(lock)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for JobLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Remove temporary files (`.name.PID.tmp`) in `dir` whose writer is gone: an interrupted run
/// (a kill during a frame or the manifest write) leaves them; a live run's are kept.
pub fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
            continue;
        };
        // The writer's pid is the last dot-separated part (`.frame_0001.png.1234.tmp`); a
        // name without one is an older run's and stale.
        let pid = rest.rsplit('.').next().and_then(|p| p.parse::<u32>().ok());
        if pid.is_none_or(|p| p != std::process::id() && !alive(p)) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dead_pid() -> u32 {
        // Past the kernel's pid_max (at most 2^22): never a running process.
        (1 << 22) + 7
    }

    #[test]
    #[cfg(unix)]
    fn shards_share_a_folder_a_whole_run_does_not() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let one = JobLock::acquire(d, Shard { index: 1, count: 2 }).unwrap();
        // Another live holder of shard 2 (ourselves under another name would be skipped, so
        // fake one with the pid of this test's parent, which is alive).
        let parent = std::os::unix::process::parent_id();
        let other = d.join(format!(".render-shard-2-of-2.{parent}.lock"));
        std::fs::write(&other, "x").unwrap();
        drop(one);
        let e = JobLock::acquire(d, Shard::WHOLE).unwrap_err().to_string();
        assert!(
            e.contains(&format!("process {parent}")) && e.contains("shard 2 of 2"),
            "{e}"
        );
        let e = JobLock::acquire(d, Shard { index: 2, count: 2 }).unwrap_err();
        assert!(e.to_string().contains("lock file"), "{e}");
        assert!(JobLock::acquire(d, Shard { index: 1, count: 2 }).is_ok());
        std::fs::remove_file(&other).unwrap();
        // A killed run's lock is stale: taken over.
        let stale = d.join(format!(".render-all.{}.lock", dead_pid()));
        std::fs::write(&stale, "x").unwrap();
        let whole = JobLock::acquire(d, Shard::WHOLE).unwrap();
        assert!(!stale.exists() && whole.path().exists());
        let p = whole.path().to_path_buf();
        drop(whole);
        assert!(!p.exists());
    }

    #[test]
    #[cfg(unix)]
    fn only_dead_writers_temporaries_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let parent = std::os::unix::process::parent_id();
        let names = [
            format!(".manifest.json.{}.tmp", dead_pid()),
            format!(".frame_0001.png.{parent}.tmp"),
            ".old.tmp".to_string(),
            "frame_0001.png".to_string(),
        ];
        for n in &names {
            std::fs::write(d.join(n), "x").unwrap();
        }
        remove_stale_temporaries(d);
        let left: Vec<bool> = names.iter().map(|n| d.join(n).exists()).collect();
        assert_eq!(left, [false, true, false, true]);
    }
}
