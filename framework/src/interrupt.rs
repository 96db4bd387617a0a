//! The request to stop a run early: one process-wide flag.
//!
//! The command line sets it from its SIGINT/SIGTERM handler ([`request`]); every time loop
//! (the driver's, the curve case's, the train–bridge's) reads it after each completed step
//! ([`requested`]) and, when set, flushes its recorders and returns
//! [`FemError::Interrupted`](crate::FemError::Interrupted) with the time reached. A step in
//! progress is never cut, so every output ends on a whole line and a whole step.
//!
//! Commands made of whole units of work — the cases of a critical-radius sweep, of `stress`,
//! `pareto` and `bench`, the load steps of a static analysis — read it between units
//! ([`check_after`]): the unit in progress finishes, the ones not started are dropped, the
//! tables hold the completed units, and the command returns
//! [`FemError::InterruptedAfter`](crate::FemError::InterruptedAfter) naming them.

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

/// Asks every running analysis to stop at the end of its current step (async-signal safe:
/// one atomic store).
pub fn request() {
    STOP.store(true, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// Clears the request (tests, and a library caller that runs again after a stop).
pub fn clear() {
    STOP.store(false, Ordering::SeqCst);
}

/// `Err(Interrupted { t })` if a stop was asked for, for a time loop at time `t` (s).
pub fn check(t: f64) -> Result<(), crate::FemError> {
    if requested() {
        Err(crate::FemError::Interrupted { t })
    } else {
        Ok(())
    }
}

/// `Err(InterruptedAfter { after: done() })` if a stop was asked for, for a command between
/// two units of work (`done` says what is complete: `"3 of 9 cases"`).
pub fn check_after(done: impl FnOnce() -> String) -> Result<(), crate::FemError> {
    if requested() {
        Err(crate::FemError::InterruptedAfter { after: done() })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_turns_the_check_into_the_time_reached() {
        clear();
        assert_eq!(check(1.5), Ok(()));
        request();
        assert_eq!(check(1.5), Err(crate::FemError::Interrupted { t: 1.5 }));
        let e = check_after(|| "2 of 5 cases".into()).unwrap_err();
        assert_eq!(e.to_string(), "interrupted after 2 of 5 cases");
        clear();
        assert!(!requested());
    }
}
