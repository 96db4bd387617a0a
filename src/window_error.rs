//! The activity window's error against the full model: two `railfem train-bridge` output
//! directories of the same case — one run with `--window off`, one windowed — compared
//! sample by sample over the samples both wrote. What is measured is what issue 34 sets
//! targets for (`docs/activity-window.md`, "Error against the full model"):
//!
//! - every wheel's `Q`, `ΔQ/Q` and `Y/Q` (`wheels.csv`): the largest |difference| over all
//!   wheels and samples, against the largest |value| of the quantity over all wheels in
//!   the full run (the "peak" of the targets), and also against each wheel's own peak;
//! - the midspan deflections (`midspan.csv`), as the train's part `w − w(0)`: the
//!   self-weight deflection `w(0)` is the same static state in both runs (the window opens
//!   after the static solve), so the difference is that of `w`, and the peak is that of
//!   the train's part, not of the self-weight. Over every span, and over the spans under
//!   the train at each sample (the target's spans: a span behind the train, held once it
//!   has rung down, keeps the state it was held at);
//! - the energy balance (`energy.csv`, when both runs wrote one): the ledger's integrator
//!   residual `D_num = W_ext − ΔT − U − D_c − D_f − D_p` at the last common step, which
//!   is what the balance closes to (`railfem_solvers::energy`). A held block's interior
//!   stops working, so what the window changes shows up there.
//!
//! `cargo run --release --example window_error -- FULL_DIR WINDOWED_DIR...` prints one row
//! per windowed directory.

use crate::framework::FemError;
use crate::train_bridge::TrainBridgeCase;
use std::path::Path;

/// A CSV file's header and columns (every cell a number).
pub struct Columns {
    /// Header cells, with their units.
    pub head: Vec<String>,
    /// Column values, one vector per header cell.
    pub cols: Vec<Vec<f64>>,
}

/// Reads `path` (a header line, then rows of numbers).
pub fn read_columns(path: &Path) -> Result<Columns, FemError> {
    let text = std::fs::read_to_string(path).map_err(|e| FemError::output(path, e))?;
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(String::from)
        .collect();
    let mut cols = vec![Vec::new(); head.len()];
    for (n, l) in lines.enumerate() {
        let cells: Vec<&str> = l.split(',').collect();
        // A run stopped while writing leaves a short last line: stop at it.
        if cells.len() != head.len() {
            break;
        }
        let row: Result<Vec<f64>, _> = cells.iter().map(|c| c.parse::<f64>()).collect();
        let row = row.map_err(|_| {
            FemError::input(
                path.display().to_string(),
                format!("line {}: not a row of numbers", n + 2),
            )
        })?;
        for (c, v) in cols.iter_mut().zip(row) {
            c.push(v);
        }
    }
    Ok(Columns { head, cols })
}

/// The largest difference of one quantity between two runs.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Difference {
    /// Largest |windowed − full| over the columns and common samples.
    pub largest: f64,
    /// Largest |full| over the same columns and samples (the quantity's peak).
    pub peak: f64,
    /// Largest of each column's |windowed − full| divided by that column's own peak.
    pub own: f64,
}

impl Difference {
    /// `largest / peak` (0 when the peak is 0).
    pub fn relative(&self) -> f64 {
        if self.peak > 0.0 {
            self.largest / self.peak
        } else {
            0.0
        }
    }
}

/// Over the columns of `full` and `win` whose header ends with `suffix` (time excluded),
/// taken relative to their first sample when `from_start`: the largest difference over the
/// first `n` samples, the full run's peak and the largest difference against a column's
/// own peak. The two files must have the same header.
pub fn difference(
    full: &Columns,
    win: &Columns,
    suffix: &str,
    from_start: bool,
    n: usize,
) -> Result<Difference, FemError> {
    difference_where(full, win, suffix, from_start, n, &|_, _| true)
}

/// [`difference`] over the samples `k` of each column `c` (0 is time) where `keep(c, k)`.
pub fn difference_where(
    full: &Columns,
    win: &Columns,
    suffix: &str,
    from_start: bool,
    n: usize,
    keep: &dyn Fn(usize, usize) -> bool,
) -> Result<Difference, FemError> {
    if full.head != win.head {
        return Err(FemError::input(
            "window comparison",
            "the two runs' CSV headers differ; compare runs of the same case",
        ));
    }
    let mut d = Difference::default();
    for (c, (h, (x, y))) in full
        .head
        .iter()
        .zip(full.cols.iter().zip(&win.cols))
        .enumerate()
    {
        if !h.ends_with(suffix) || h.starts_with("time") {
            continue;
        }
        let (x0, y0) = match (from_start, x.first(), y.first()) {
            (true, Some(a), Some(b)) => (*a, *b),
            _ => (0.0, 0.0),
        };
        let (mut diff, mut peak) = (0.0f64, 0.0f64);
        for (k, (u, v)) in x.iter().zip(y).take(n).enumerate() {
            if !keep(c, k) {
                continue;
            }
            diff = diff.max(((u - x0) - (v - y0)).abs());
            peak = peak.max((u - x0).abs());
        }
        d.largest = d.largest.max(diff);
        d.peak = d.peak.max(peak);
        if peak > 0.0 {
            d.own = d.own.max(diff / peak);
        }
    }
    Ok(d)
}

/// The energy ledger's rows (`energy.csv` in `dir`), or `None` when the file is missing.
fn ledger(dir: &Path) -> Result<Option<Columns>, FemError> {
    let p = dir.join(crate::framework::outputs::ENERGY_CSV);
    if !p.exists() {
        return Ok(None);
    }
    read_columns(&p).map(Some)
}

/// Column `prefix…` of `c` at row `k`.
fn cell(c: &Columns, prefix: &str, k: usize) -> Option<f64> {
    let i = c.head.iter().position(|h| h.starts_with(prefix))?;
    c.cols[i].get(k).copied()
}

/// The integrator residuals of `full` and `win` and the full run's external work at their
/// last common row (both runs take the same steps, so rows are the same times).
fn balance(full: &Columns, win: &Columns) -> Option<[f64; 3]> {
    let len = |c: &Columns| c.cols.first().map_or(0, Vec::len);
    let k = len(full).min(len(win)).checked_sub(1)?;
    Some([
        cell(full, "integrator", k)?,
        cell(win, "integrator", k)?,
        cell(full, "external_work", k)?,
    ])
}

/// One windowed run against the full one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowError {
    /// Samples compared (those both runs wrote).
    pub samples: usize,
    /// Wheel–rail normal force `Q` (N).
    pub q: Difference,
    /// `ΔQ/Q` (-).
    pub dqq: Difference,
    /// `Y/Q` (-).
    pub yq: Difference,
    /// Midspan deflection's train part `w − w(0)` (m), every recorded span.
    pub deflection: Difference,
    /// The same over the spans under the train at each sample (the target's spans).
    pub deflection_under: Difference,
    /// Integrator residual `D_num` of the full and the windowed run at the last common
    /// step, and the full run's external work there (J); `None` without `energy.csv`.
    pub energy: Option<[f64; 3]>,
}

/// Compares the run in `windowed` with the full run in `full` (module documentation);
/// `under(span, t)` says whether span `span` (1-based) is under the train at time `t` (s),
/// for [`WindowError::deflection_under`].
pub fn compare(
    full: &Path,
    windowed: &Path,
    under: &dyn Fn(usize, f64) -> bool,
) -> Result<WindowError, FemError> {
    let (wf, ww) = (
        read_columns(&full.join("wheels.csv"))?,
        read_columns(&windowed.join("wheels.csv"))?,
    );
    let (mf, mw) = (
        read_columns(&full.join("midspan.csv"))?,
        read_columns(&windowed.join("midspan.csv"))?,
    );
    let len = |c: &Columns| c.cols.first().map_or(0, Vec::len);
    let n = len(&wf).min(len(&ww)).min(len(&mf)).min(len(&mw));
    let energy = match (ledger(full)?, ledger(windowed)?) {
        (Some(a), Some(b)) => balance(&a, &b),
        _ => None,
    };
    Ok(WindowError {
        samples: n,
        q: difference(&wf, &ww, "_Q [N]", false, n)?,
        dqq: difference(&wf, &ww, "_dQQ [-]", false, n)?,
        yq: difference(&wf, &ww, "_YQ [-]", false, n)?,
        deflection: difference(&mf, &mw, " [m]", true, n)?,
        deflection_under: {
            // Column `c` of midspan.csv is span `spanN [m]`; column 0 the time.
            let spans: Vec<usize> = mf
                .head
                .iter()
                .map(|h| {
                    h.trim_start_matches("span")
                        .trim_end_matches(" [m]")
                        .parse()
                        .unwrap_or(0)
                })
                .collect();
            let t = &mf.cols[0];
            difference_where(&mf, &mw, " [m]", true, n, &|c, k| under(spans[c], t[k]))?
        },
        energy,
    })
}

/// Whether span `k` (1-based) of `case`'s viaduct is under its train at time `t` (s):
/// the span `[a + (k − 1)·L, a + k·L]` (`a` the approach's length, where the first
/// abutment is) overlaps the train's extent ([`crate::train_window::train_extent`]).
pub fn span_under_train(case: &TrainBridgeCase) -> impl Fn(usize, f64) -> bool {
    let track = case.window_track();
    let (a, l) = (case.approach(), case.span);
    move |k, t| {
        let [rear, front] = crate::train_window::train_extent(&track, t);
        let (lo, hi) = (a + (k as f64 - 1.0) * l, a + k as f64 * l);
        k >= 1 && lo <= front && hi >= rear
    }
}

/// The case of a `railfem train-bridge` run from its `run.json` (the options that place
/// the train and the spans: `cars`, `span`, `speed`, `train-start`; the others as the
/// command's defaults).
pub fn case_of_run(dir: &Path) -> Result<TrainBridgeCase, FemError> {
    let p = dir.join(crate::sidecar::RUN_JSON);
    let text = std::fs::read_to_string(&p).map_err(|e| FemError::output(&p, e))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| FemError::input(p.display().to_string(), e.to_string()))?;
    let opt = |k: &str| v["options"][k].as_f64();
    let mut c = TrainBridgeCase::default();
    if let Some(x) = opt("cars") {
        c.cars = x as usize;
    }
    for (k, x) in [
        ("span", &mut c.span),
        ("speed", &mut c.speed),
        ("train-start", &mut c.train_start),
    ] {
        if let Some(y) = opt(k) {
            *x = y;
        }
    }
    Ok(c)
}
