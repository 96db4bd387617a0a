//! Progress of a long run on stderr, the same for every command (run, curve,
//! critical-radius, train-bridge, stress, pareto, bench).
//!
//! - On a terminal (stderr [`IsTerminal`]): an indicatif bar with the count, the rate
//!   (steps/s) and the ETA.
//! - In a pipe or a log: plain lines, one each 10 % of the work or each 10 s, whichever comes
//!   first — never `\r` frames. A run done within its first second prints none.
//! - With `--quiet` ([`set_quiet`]): nothing.
//!
//! Progress goes to stderr only; stdout keeps the results.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

static QUIET: AtomicBool = AtomicBool::new(false);

/// Silences every progress display of this process (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether `--quiet` was given.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Interval of the plain lines when the work advances slowly.
const LINE_EVERY: Duration = Duration::from_secs(10);
/// No plain line before the run is this old: quick runs stay silent in logs.
const LINE_AFTER: Duration = Duration::from_secs(1);

enum Display {
    Bar(ProgressBar),
    Lines { last: Instant, last_tenth: u64 },
    Silent,
}

/// The progress of one piece of work of `total` units (steps, points, cases).
pub struct Progress {
    label: String,
    unit: String,
    total: u64,
    done: u64,
    start: Instant,
    display: Display,
}

impl Progress {
    /// Starts showing the progress of `label` (`"curve"`), `total` `unit`s (`"steps"`).
    pub fn new(label: &str, total: u64, unit: &str) -> Progress {
        let total = total.max(1);
        let display = if quiet() {
            Display::Silent
        } else if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(total);
            let template = format!(
                "{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {unit} ({{per_sec}}, ETA {{eta}})"
            );
            if let Ok(style) = ProgressStyle::with_template(&template) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_prefix(label.to_string());
            Display::Bar(bar)
        } else {
            Display::Lines {
                last: Instant::now(),
                last_tenth: 0,
            }
        };
        Progress {
            label: label.to_string(),
            unit: unit.to_string(),
            total,
            done: 0,
            start: Instant::now(),
            display,
        }
    }

    /// Sets the units done so far.
    pub fn set(&mut self, done: u64) {
        self.done = done.min(self.total);
        match &mut self.display {
            Display::Bar(b) => b.set_position(self.done),
            Display::Lines { last, last_tenth } => {
                let tenth = self.done * 10 / self.total;
                let now = Instant::now();
                let due = tenth > *last_tenth || now - *last >= LINE_EVERY;
                if due && now - self.start >= LINE_AFTER && self.done < self.total {
                    *last = now;
                    *last_tenth = tenth;
                    eprintln!("{}", self.line());
                }
            }
            Display::Silent => {}
        }
    }

    /// Sets the fraction done (0..1).
    pub fn fraction(&mut self, f: f64) {
        let f = if f.is_finite() {
            f.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.set((f * self.total as f64).round() as u64);
    }

    /// One plain progress line: `curve: 40 % (4800/12000 steps, 250 steps/s, ETA 28 s)`.
    fn line(&self) -> String {
        let secs = self.start.elapsed().as_secs_f64().max(1e-9);
        let rate = self.done as f64 / secs;
        let eta = if rate > 0.0 {
            format!("{:.0} s", (self.total - self.done) as f64 / rate)
        } else {
            "unknown".into()
        };
        format!(
            "{}: {} % ({}/{} {}, {:.3} {}/s, ETA {})",
            self.label,
            self.done * 100 / self.total,
            self.done,
            self.total,
            self.unit,
            rate,
            self.unit,
            eta
        )
    }

    /// A message about the work (one finished run of a grid): above the bar on a terminal,
    /// a plain line in a pipe, nothing with `--quiet`.
    pub fn note(&self, message: &str) {
        match &self.display {
            Display::Bar(b) => b.println(message),
            Display::Lines { .. } => eprintln!("{message}"),
            Display::Silent => {}
        }
    }

    /// Ends the display (clears the bar; the command prints its own summary).
    pub fn finish(&mut self) {
        if let Display::Bar(b) = &self.display {
            b.finish_and_clear();
        }
        self.display = Display::Silent;
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
