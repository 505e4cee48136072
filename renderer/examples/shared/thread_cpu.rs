//! CPU clocks shared by the timing examples and the trace bench (included with `#[path]`).
//!
//! Read with `clock_gettime`, which the kernel brings up to date at the call, in nanoseconds.
//! `/proc/thread-self/schedstat`, used before, moves only at scheduler ticks (4 ms steps on the
//! development machine): a 12-16 ms frame then reads as 12 or 16 ms, and ratios against a peer
//! timed with a fine clock came out bimodal.

// Each includer uses one of the two clocks.
#![allow(dead_code)]

use anyhow::{Result, bail};

/// CPU time of the calling thread, nanoseconds.
pub fn thread_cpu_ns() -> Result<f64> {
    #[cfg(unix)]
    return clock_ns(libc::CLOCK_THREAD_CPUTIME_ID, "CLOCK_THREAD_CPUTIME_ID");
    #[cfg(not(unix))]
    bail!("the thread CPU clock (CLOCK_THREAD_CPUTIME_ID) needs a Unix system")
}

/// CPU time of every thread of this process, live or finished, nanoseconds.
pub fn process_cpu_ns() -> Result<f64> {
    #[cfg(unix)]
    return clock_ns(libc::CLOCK_PROCESS_CPUTIME_ID, "CLOCK_PROCESS_CPUTIME_ID");
    #[cfg(not(unix))]
    bail!("the process CPU clock (CLOCK_PROCESS_CPUTIME_ID) needs a Unix system")
}

#[cfg(unix)]
fn clock_ns(clock: libc::clockid_t, name: &str) -> Result<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    if unsafe { libc::clock_gettime(clock, &mut ts) } != 0 {
        bail!(
            "clock_gettime({name}) failed: {}",
            std::io::Error::last_os_error()
        );
    }
    Ok(ts.tv_sec as f64 * 1e9 + ts.tv_nsec as f64)
}
