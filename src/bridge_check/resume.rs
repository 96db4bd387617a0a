//! The journal of a check, `DIR/bridge-check.checkpoint`: every finished train–speed run,
//! so that a check stopped (Ctrl-C, `--stop-after`, a kill) goes on where it stopped when
//! the same command runs again, and writes the same `envelope.csv` byte for byte.
//!
//! The format follows the study checkpoint's (`src/study/checkpoint.rs`, whose row
//! checksum it uses): a first line naming the format and the check's fingerprint (FNV-1a
//! over the plan's text, the trains' axles and suspensions, the deck's frequencies, the
//! step and the cut-off: change any and the journal belongs to another check), then one
//! line per run, `CHECKSUM ROW`, the row being the train's index, the model and the
//! speed and results as the hexadecimal bits of their `f64` (so that a resumed run's
//! numbers are the computed ones exactly). Lines are appended and flushed as runs end.
//!
//! On resume every line is verified before any is used; a bad one is refused with one line
//! naming the journal, the line and the fix (delete the row, or start afresh with
//! `--restart`). A last line cut by a kill (no line end) is dropped: that run runs again.

use super::interaction::VehicleModel;
use super::outcome::Outcome;
use crate::framework::FemError;
use crate::study::cases::fnv1a;
use crate::study::checkpoint::{line, row_sum};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// File name of the journal in the output folder.
pub const FILE: &str = "bridge-check.checkpoint";

/// The fix every refused row names.
const FIX: &str = "delete the row, or start afresh with `--restart`";

/// A run's key: train, model, speed's bits.
type Key = (usize, VehicleModel, u64);

/// The open journal: the runs it holds and the file to append to.
pub struct Journal {
    done: HashMap<Key, Outcome>,
    path: PathBuf,
    file: Mutex<std::fs::File>,
    fingerprint: u64,
    /// Runs this process may still compute (`--stop-after`).
    budget: AtomicUsize,
    /// The first failed append.
    error: Mutex<Option<FemError>>,
    /// Runs recorded by this process.
    recorded: AtomicUsize,
}

/// The fingerprint of a check from the words that define it.
pub fn fingerprint(parts: &[&str]) -> u64 {
    let mut bytes = Vec::new();
    for p in parts {
        bytes.extend_from_slice(p.as_bytes());
        bytes.push(0);
    }
    fnv1a(&bytes)
}

fn head(fingerprint: u64) -> String {
    format!("railfem-bridge-check-checkpoint v1 check={fingerprint:016x}")
}

fn model_of(name: &str) -> Option<VehicleModel> {
    [
        VehicleModel::MovingForces,
        VehicleModel::SprungMasses,
        VehicleModel::FullVehicles,
    ]
    .into_iter()
    .find(|m| m.name() == name)
}

/// The row of an outcome (module documentation).
fn row(o: &Outcome) -> String {
    let f = [
        o.speed,
        o.acceleration,
        o.acc_station,
        o.acc_time,
        o.deflection,
        o.defl_station,
    ];
    let bits: Vec<String> = f.iter().map(|x| format!("{:016x}", x.to_bits())).collect();
    format!("{} {} {}", o.train, o.model.name(), bits.join(" "))
}

/// The outcome of a verified row; `statics` gives the train's static deflection.
fn parse(fp: u64, text: &str, statics: &[f64]) -> Result<Outcome, String> {
    let (sum, r) = match (text.get(..16), text.get(16..17), text.get(17..)) {
        (Some(s), Some(" "), Some(r)) => (s, r),
        _ => return Err("the row is damaged: it does not start with its checksum".into()),
    };
    if u64::from_str_radix(sum, 16).ok() != Some(row_sum(fp, r)) {
        return Err("the row's checksum does not match it: the row was changed".into());
    }
    let w: Vec<&str> = r.split(' ').collect();
    let train = w.first().and_then(|t| t.parse::<usize>().ok());
    let model = w.get(1).and_then(|m| model_of(m));
    let nums: Vec<Option<f64>> = w
        .iter()
        .skip(2)
        .map(|x| u64::from_str_radix(x, 16).ok().map(f64::from_bits))
        .collect();
    match (train, model, nums.as_slice()) {
        (Some(t), Some(m), [Some(v), Some(a), Some(sa), Some(ta), Some(d), Some(sd)])
            if t < statics.len() =>
        {
            Ok(Outcome {
                train: t,
                model: m,
                speed: *v,
                acceleration: *a,
                acc_station: *sa,
                acc_time: *ta,
                deflection: *d,
                defl_station: *sd,
                static_deflection: statics[t],
            })
        }
        _ => Err("the row does not hold a run of this check".into()),
    }
}

impl Journal {
    /// Opens the journal in `dir` for the check of fingerprint `fp` (trains' static
    /// deflections `statics`), verifying every row, or starts it afresh when there is none
    /// or `restart` asks so; `stop_after` limits the runs this process computes.
    pub fn open(
        dir: &Path,
        fp: u64,
        statics: &[f64],
        restart: bool,
        stop_after: Option<usize>,
    ) -> Result<Journal, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let path = dir.join(FILE);
        let want = head(fp);
        let mut text = match std::fs::read(&path) {
            Ok(_) if restart => String::new(),
            Ok(b) => String::from_utf8_lossy(&b).into_owned(),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(e) => return Err(FemError::output(&path, e)),
        };
        let cut = !text.ends_with('\n') && !text.is_empty();
        if cut {
            text.truncate(text.rfind('\n').map_or(0, |i| i + 1));
        }
        let mut done = HashMap::new();
        if let Some(first) = text.lines().next() {
            if first != want {
                return Err(FemError::input(
                    format!("{}: line 1", path.display()),
                    "it belongs to another check (the plan, its trains or its deck changed); start afresh with `--restart`, or give another --out",
                ));
            }
            for (k, l) in text.lines().enumerate().skip(1) {
                let place = format!("{}: line {}", path.display(), k + 1);
                let o = parse(fp, l, statics)
                    .map_err(|why| FemError::input(&place, format!("{why}; {FIX}")))?;
                if done
                    .insert((o.train, o.model, o.speed.to_bits()), o)
                    .is_some()
                {
                    return Err(FemError::input(
                        place,
                        format!("the run is in the journal twice; {FIX}"),
                    ));
                }
            }
        }
        if text.is_empty() || cut {
            if text.is_empty() {
                text = format!("{want}\n");
            }
            crate::atomic_file::write(&path, text.as_bytes())?;
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| FemError::output(&path, e))?;
        Ok(Journal {
            done,
            path,
            file: Mutex::new(file),
            fingerprint: fp,
            budget: AtomicUsize::new(stop_after.unwrap_or(usize::MAX)),
            error: Mutex::new(None),
            recorded: AtomicUsize::new(0),
        })
    }

    /// Runs the journal already holds.
    pub fn len(&self) -> usize {
        self.done.len()
    }

    /// Runs the journal holds now: those it was opened with and those recorded since.
    pub fn len_now(&self) -> usize {
        self.done.len() + self.recorded.load(Ordering::Relaxed)
    }

    /// Whether the journal holds no run.
    pub fn is_empty(&self) -> bool {
        self.done.is_empty()
    }

    /// The journal's outcome of train `i`, `model`, `speed` (km/h), if it holds it.
    pub fn get(&self, i: usize, model: VehicleModel, speed: f64) -> Option<Outcome> {
        self.done.get(&(i, model, speed.to_bits())).copied()
    }

    /// Takes one run from the budget; `false` once `--stop-after` runs were taken or an
    /// append failed.
    pub fn may_run(&self) -> bool {
        let failed = self.error.lock().map_or(true, |e| e.is_some());
        !failed
            && self
                .budget
                .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |b| b.checked_sub(1))
                .is_ok()
    }

    /// Appends a finished run (one write, flushed). A failed write is kept and stops the
    /// check ([`Journal::take_error`]).
    pub fn record(&self, o: &Outcome) {
        let text = line(self.fingerprint, &row(o)) + "\n";
        let Ok(mut f) = self.file.lock() else { return };
        match f.write_all(text.as_bytes()).and_then(|_| f.flush()) {
            Ok(()) => {
                self.recorded.fetch_add(1, Ordering::Relaxed);
            }
            Err(e) => {
                if let Ok(mut g) = self.error.lock() {
                    g.get_or_insert(FemError::output(&self.path, e));
                }
            }
        }
    }

    /// The first failed append, if any.
    pub fn take_error(&self) -> Option<FemError> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }
}
