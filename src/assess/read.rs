//! Reading a run's wheel signals from its output directory: every CSV file whose header
//! names wheel forces. What is recognised (per wheel prefix `W`, units in the header):
//!
//! - `W_Q [N]` and `W_Y [N]` (the `moving_axle` outputs through an element recorder of
//!   `railfem run`, and `wheels.csv` of `railfem train-bridge`), or `W_Q_fe [N]` and
//!   `W_Y_fe [N]` (`curve.csv` of `railfem curve`);
//! - the station `W_station [m]`, else a file-wide `station [m]`, else `time [s]` times
//!   the speed given to the command;
//! - the wear number `W_t_gamma [N]` (if recorded), and the most loaded contact point's
//!   `W_c1_fx`, `W_c1_fy`, `W_p1_fn` (N), `W_c1_a`, `W_c1_b` (m) for the fatigue index.
//!
//! Wheels pair into wheelsets in the order of their columns (left, right: the order every
//! railfem writer uses).

use crate::framework::FemError;
use std::path::{Path, PathBuf};

/// The most loaded contact point's histories (outputs `c1_*` and `p1_fn`), for the
/// surface fatigue index.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FirstPoint {
    /// Creep forces on the wheel at the point (N).
    pub fx: Vec<f64>,
    /// See `fx`.
    pub fy: Vec<f64>,
    /// The point's normal force (N).
    pub fn_: Vec<f64>,
    /// Semi-axes of the point's patch ellipse (m); zero without a creep law.
    pub a: Vec<f64>,
    /// See `a`.
    pub b: Vec<f64>,
}

/// One wheel's histories.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Wheel {
    /// Column prefix (`12`, `w1L`).
    pub name: String,
    /// Time (s).
    pub t: Vec<f64>,
    /// Station (m).
    pub s: Vec<f64>,
    /// Vertical wheel force Q (N).
    pub q: Vec<f64>,
    /// Lateral wheel force Y (N).
    pub y: Vec<f64>,
    /// The wear number Tγ of the whole wheel (N = J/m), if recorded (`t_gamma`).
    pub t_gamma: Option<Vec<f64>>,
    /// The most loaded point, if recorded.
    pub first: Option<FirstPoint>,
}

/// A parsed CSV: column names (without units), units and rows.
struct Table {
    names: Vec<String>,
    units: Vec<String>,
    cols: Vec<Vec<f64>>,
}

fn split_unit(h: &str) -> (String, String) {
    let h = h.trim();
    match (h.rfind(" ["), h.ends_with(']')) {
        (Some(i), true) => (h[..i].to_string(), h[i + 2..h.len() - 1].to_string()),
        _ => (h.to_string(), String::new()),
    }
}

/// The table of `path` if its header names a wheel's forces (`W_Q [N]` with `W_Y [N]`, or
/// `W_Q_fe [N]` with `W_Y_fe [N]`);
/// other files (a run's other outputs, several tables in one file) are not read.
fn read_table(path: &Path) -> Result<Option<Table>, FemError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| FemError::input(path.display().to_string(), e.to_string()))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let (names, units): (Vec<String>, Vec<String>) = header.split(',').map(split_unit).unzip();
    let has = |name: String| {
        names
            .iter()
            .zip(&units)
            .any(|(n, u)| *n == name && u == "N")
    };
    let wheel_force = names.iter().any(|n| {
        n.strip_suffix("_Q")
            .is_some_and(|p| has(format!("{p}_Q")) && has(format!("{p}_Y")))
            || n.strip_suffix("_Q_fe")
                .is_some_and(|p| has(format!("{p}_Q_fe")) && has(format!("{p}_Y_fe")))
    });
    if !wheel_force {
        return Ok(None);
    }
    let mut cols = vec![Vec::new(); names.len()];
    for (row, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != names.len() {
            return Err(FemError::input(
                path.display().to_string(),
                format!(
                    "line {}: {} values under a header of {} columns; the file is cut or not a railfem output",
                    row + 2,
                    cells.len(),
                    names.len()
                ),
            ));
        }
        for (c, v) in cols.iter_mut().zip(cells) {
            c.push(v.trim().parse::<f64>().unwrap_or(f64::NAN));
        }
    }
    Ok(Some(Table { names, units, cols }))
}

/// The CSV files of `dir` (sorted), without the assessment's own outputs.
fn csv_files(dir: &Path) -> Result<Vec<PathBuf>, FemError> {
    let rd = std::fs::read_dir(dir).map_err(|e| {
        FemError::input(
            dir.display().to_string(),
            format!("{e}; give the output directory of a run (railfem run --out DIR, curve, train-bridge)"),
        )
    })?;
    let mut v: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("assessment"))
        })
        .collect();
    v.sort();
    Ok(v)
}

/// Every wheel recorded in `dir`; `speed` (m/s) turns time into station where no station
/// was recorded.
pub fn wheels(dir: &Path, speed: Option<f64>) -> Result<Vec<Wheel>, FemError> {
    let mut out = Vec::new();
    for path in csv_files(dir)? {
        let Some(t) = read_table(&path)? else {
            continue;
        };
        let col = |name: &str, unit: &str| {
            t.names
                .iter()
                .zip(&t.units)
                .position(|(n, u)| n == name && u == unit)
                .map(|i| &t.cols[i])
        };
        let time = col("time", "s");
        for (i, name) in t.names.iter().enumerate() {
            if t.units[i] != "N" {
                continue;
            }
            let (prefix, ysuffix) = if let Some(p) = name.strip_suffix("_Q_fe") {
                (p, "_Y_fe")
            } else if let Some(p) = name.strip_suffix("_Q") {
                (p, "_Y")
            } else {
                continue;
            };
            let Some(y) = col(&format!("{prefix}{ysuffix}"), "N") else {
                continue;
            };
            let Some(time) = time else {
                return Err(FemError::input(
                    path.display().to_string(),
                    "no `time [s]` column; give a CSV written by a railfem run".to_string(),
                ));
            };
            let s = match (col(&format!("{prefix}_station"), "m"), col("station", "m"), speed) {
                (Some(s), _, _) | (None, Some(s), _) => s.clone(),
                (None, None, Some(v)) => time.iter().map(|t| t * v).collect(),
                (None, None, None) => {
                    return Err(FemError::input(
                        path.display().to_string(),
                        format!("wheel `{prefix}` has no station column; give --speed V (m/s) to measure distance as V·t, or record `station`"),
                    ))
                }
            };
            let get = |f: &str, u: &str| col(&format!("{prefix}_{f}"), u).cloned();
            let first = match (get("c1_fx", "N"), get("c1_fy", "N"), get("p1_fn", "N")) {
                (Some(fx), Some(fy), Some(fn_)) => Some(FirstPoint {
                    a: get("c1_a", "m").unwrap_or_else(|| vec![0.0; fx.len()]),
                    b: get("c1_b", "m").unwrap_or_else(|| vec![0.0; fx.len()]),
                    fx,
                    fy,
                    fn_,
                }),
                _ => None,
            };
            out.push(Wheel {
                name: prefix.to_string(),
                t: time.clone(),
                s,
                q: t.cols[i].clone(),
                y: y.clone(),
                t_gamma: get("t_gamma", "N"),
                first,
            });
        }
    }
    if out.is_empty() {
        return Err(FemError::input(
            dir.display().to_string(),
            "no wheel forces found (columns `W_Q [N]` and `W_Y [N]`); record the moving_axle outputs `station`, `Q`, `Y` with an element recorder, or assess the output of curve or train-bridge".to_string(),
        ));
    }
    Ok(out)
}
