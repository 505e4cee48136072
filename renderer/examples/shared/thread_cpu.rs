//! CPU time of the calling thread, shared by the timing examples (included with `#[path]`).
//!
//! Read with `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`, which the kernel brings up to date at the
//! call, in nanoseconds. `/proc/thread-self/schedstat`, used before, moves only at scheduler
//! ticks (4 ms steps on the development machine): a 12-16 ms frame then reads as 12 or 16 ms, and
//! ratios against a peer timed with a fine clock came out bimodal.

use anyhow::{Result, bail};

/// CPU time of the calling thread, nanoseconds.
#[cfg(unix)]
pub fn thread_cpu_ns() -> Result<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) } != 0 {
        bail!(
            "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed: {}",
            std::io::Error::last_os_error()
        );
    }
    Ok(ts.tv_sec as f64 * 1e9 + ts.tv_nsec as f64)
}

/// CPU time of the calling thread: not available off Unix.
#[cfg(not(unix))]
pub fn thread_cpu_ns() -> Result<f64> {
    bail!("the thread CPU clock (CLOCK_THREAD_CPUTIME_ID) needs a Unix system")
}
