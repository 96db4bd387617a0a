//! CPU time of this process: the cost of a run that other processes' load does not
//! stretch, and that equals its wall time when the run has a core to itself.
//!
//! The kernel's `CLOCK_PROCESS_CPUTIME_ID` counts the time every thread of this process
//! spent on a core. A run that computes on one thread and waits for nothing accrues it at
//! the rate of wall time on a quiet machine; under load it is descheduled, and its wall
//! time grows while its CPU time does not (only cache and memory-bandwidth contention,
//! which slow the instructions themselves, still reach it). With several computing
//! threads it is the sum over them, more than the wall time.

/// CPU time consumed by this process so far (s), all its threads together; NaN where the
/// clock is not available (not a Unix system, or the call failed).
pub fn process_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec for the duration of the call, and
        // CLOCK_PROCESS_CPUTIME_ID is a clock every POSIX system defines.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
        if rc == 0 {
            ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
        } else {
            f64::NAN
        }
    }
    #[cfg(not(unix))]
    {
        f64::NAN
    }
}
