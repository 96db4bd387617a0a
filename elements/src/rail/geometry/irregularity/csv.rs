//! Irregularity tables as CSV: reading a measured (or generated) profile with its units
//! checked, and writing one.
//!
//! Format: blank lines and `#` comments are skipped; the first other line is the header,
//! one column `station_m` and any of `vertical`, `alignment`, `cross_level`, `gauge`, each
//! with its unit as a suffix, `_mm` or `_m` (as wheel-profile files state `y_mm,z_mm`), or
//! in brackets as railfem's output CSVs write units (`station [m],vertical [mm]`); then one
//! row per station, the numbers comma-separated. Stations strictly increase.
//!
//! A unit slip is caught by magnitude. Declared in metres, a value above
//! [`MAX_IRREGULARITY_M`] = 0.1 m is refused as "millimetres declared as metres": the
//! worst track still open to traffic (FRA class 1, 49 CFR 213.63) allows a 3-inch (76 mm)
//! deviation of profile over a 62-ft chord, and a 100 mm deviation of the rail head from
//! its mean is a derailment hazard, not a geometry record — while the same file in
//! millimetres (a few mm) read as metres is 1000 times larger. Declared in millimetres, a
//! column whose largest value is below 1e-3 mm (1 µm, below any track-recording
//! resolution) but not zero is refused as "metres declared as millimetres".

use super::psd::Component;
use railfem_framework::csv_input::{self, Bound};
use railfem_framework::limits;
use thiserror::Error;

/// Largest irregularity value a file declared in metres may hold (m), see the module doc.
pub const MAX_IRREGULARITY_M: f64 = 0.1;

/// The bound of every irregularity value ([`MAX_IRREGULARITY_M`], whatever the column's
/// unit).
const VALUE_BOUND: Bound = Bound {
    max_si: MAX_IRREGULARITY_M,
    si_unit: "m",
    why: "no track in service deviates that far from its mean (FRA class 1 allows 76 mm)",
};

/// The bound of a station: [`railfem_framework::modelfile::MAX_COORDINATE`].
const STATION_BOUND: Bound = Bound {
    max_si: railfem_framework::modelfile::MAX_COORDINATE,
    si_unit: "m",
    why: "a track that long would circle the Earth",
};

/// Smallest nonzero largest value of a column declared in millimetres (mm).
pub const MIN_IRREGULARITY_MM: f64 = 1e-3;

/// Bytes one table row costs once read and interpolated (per column: value and the
/// spline's five arrays), for the size guard.
pub const BYTES_PER_VALUE: f64 = 6.0 * 8.0;

/// A bad irregularity file: one line naming the file, the line and the fix.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}:{line}: {what}")]
pub struct IrregularityError {
    /// File name.
    pub file: String,
    /// 1-based line (0: the whole file).
    pub line: usize,
    /// What is wrong and how to fix it.
    pub what: String,
}

/// An irregularity table in SI units: stations (m) and component columns (m).
#[derive(Debug, Clone, PartialEq)]
pub struct IrregularityTable {
    /// Stations (m), strictly increasing.
    pub stations: Vec<f64>,
    /// The columns, in file order.
    pub columns: Vec<(Component, Vec<f64>)>,
}

const HEADER_FIX: &str = "give a header like `station_m,vertical_mm,alignment_mm,cross_level_mm,gauge_mm` (any of the four components, each with `_mm` or `_m`, or `station [m],vertical [mm]`)";

/// A header column as `(name, unit)`: `vertical [mm]` or `vertical_mm` (the unit after the
/// last underscore); `None` without a unit.
fn name_and_unit(column: &str) -> Option<(&str, &str)> {
    match column.split_once(" [") {
        Some((n, rest)) => rest.strip_suffix(']').map(|u| (n.trim(), u.trim())),
        None => column.rsplit_once('_'),
    }
}

/// Reads an irregularity table from CSV `text`; `file` names it in errors.
pub fn read_table(text: &str, file: &str) -> Result<IrregularityTable, IrregularityError> {
    let err = |line: usize, what: String| IrregularityError {
        file: file.into(),
        line,
        what,
    };
    // A byte-order mark would hide a first comment line (`\u{feff}# ...` is not `#`).
    let text = csv_input::strip_bom(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((hline, header)) = lines.next() else {
        return Err(err(0, format!("no header and no rows; {HEADER_FIX}")));
    };
    // Header: station_m then components with a unit each.
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let station = names
        .first()
        .and_then(|n| name_and_unit(n))
        .map(|(n, u)| (n.to_ascii_lowercase(), u.to_ascii_lowercase()));
    if station != Some(("station".into(), "m".into())) {
        return Err(err(
            hline,
            format!("header `{header}`: the first column must be `station_m`; {HEADER_FIX}"),
        ));
    }
    let mut cols: Vec<(Component, f64)> = Vec::new();
    // The header text and unit of each component column, for the bounds' messages.
    let mut labels: Vec<(&str, &str)> = Vec::new();
    for n in &names[1..] {
        let parsed = name_and_unit(n).and_then(|(c, u)| {
            let scale = match u.to_ascii_lowercase().as_str() {
                "mm" => 1e-3,
                "m" => 1.0,
                _ => return None,
            };
            Component::parse(c).map(|c| (c, scale))
        });
        let Some((c, scale)) = parsed else {
            return Err(err(
                hline,
                format!("header column `{n}` is not a component with units; {HEADER_FIX}"),
            ));
        };
        if cols.iter().any(|(d, _)| *d == c) {
            return Err(err(
                hline,
                format!(
                    "header names `{}` twice; keep one column per component",
                    c.name()
                ),
            ));
        }
        cols.push((c, scale));
        labels.push((n, if scale == 1.0 { "m" } else { "mm" }));
    }
    if cols.is_empty() {
        return Err(err(
            hline,
            format!("header `{header}` has no component column; {HEADER_FIX}"),
        ));
    }
    // Size guard before reading the rows.
    let rows = text.lines().count() as f64;
    limits::check_memory(
        file,
        rows,
        "irregularity rows",
        BYTES_PER_VALUE * (cols.len() + 1) as f64,
        "resample the file to a coarser station step",
    )
    .map_err(|m| err(0, m))?;
    let mut stations = Vec::new();
    let mut values: Vec<Vec<f64>> = vec![Vec::new(); cols.len()];
    let mut line_of = Vec::new();
    for (line, row) in lines {
        let nums: Option<Vec<f64>> = row.split(',').map(|f| f.trim().parse().ok()).collect();
        let Some(nums) = nums.filter(|v| v.len() == cols.len() + 1) else {
            return Err(err(
                line,
                format!(
                    "cannot read `{row}` as {} numbers; write one row per station, `station, {}`",
                    cols.len() + 1,
                    cols.iter()
                        .map(|(c, _)| c.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        };
        if let Some(v) = nums.iter().find(|v| !v.is_finite()) {
            return Err(err(
                line,
                format!("{v} is not a finite number; correct or remove that row"),
            ));
        }
        let bounded = |k: usize, bound: &Bound| {
            let (column, unit, scale) = match k {
                0 => (names[0], "m", 1.0),
                k => (labels[k - 1].0, labels[k - 1].1, cols[k - 1].1),
            };
            csv_input::check_bound(column, nums[k], unit, scale, bound).map_err(|m| err(line, m))
        };
        bounded(0, &STATION_BOUND)?;
        for k in 1..nums.len() {
            // Metre columns get the millimetre slip's own message below; here only values
            // that are not even plausible as millimetres.
            let bound = if cols[k - 1].1 == 1.0 {
                Bound {
                    max_si: MAX_IRREGULARITY_M * 1e3,
                    ..VALUE_BOUND
                }
            } else {
                VALUE_BOUND
            };
            bounded(k, &bound)?;
        }
        if let Some(&prev) = stations.last() {
            if nums[0] <= prev {
                return Err(err(
                    line,
                    format!(
                        "station {} m does not follow {prev} m (stations must strictly increase); sort the rows by station and remove repeats",
                        nums[0]
                    ),
                ));
            }
        }
        stations.push(nums[0]);
        for (k, (_, scale)) in cols.iter().enumerate() {
            values[k].push(nums[k + 1] * scale);
        }
        line_of.push(line);
    }
    if stations.len() < 4 {
        return Err(err(
            line_of.last().copied().unwrap_or(hline),
            format!(
                "only {} rows; give at least 4 stations (the cubic spline needs four)",
                stations.len()
            ),
        ));
    }
    // Unit slips, by magnitude.
    for (k, (c, scale)) in cols.iter().enumerate() {
        let (imax, vmax) = values[k]
            .iter()
            .map(|v| v.abs())
            .enumerate()
            .fold((0, 0.0f64), |a, (i, v)| if v > a.1 { (i, v) } else { a });
        if *scale == 1.0 && vmax > MAX_IRREGULARITY_M {
            return Err(err(
                line_of[imax],
                format!(
                    "`{}_m` = {vmax} m, more than the {MAX_IRREGULARITY_M} m no track in service deviates; these look like millimetres: declare `{}_mm` in the header",
                    c.name(),
                    c.name()
                ),
            ));
        }
        if *scale == 1e-3 && vmax > 0.0 && vmax * 1e3 < MIN_IRREGULARITY_MM {
            return Err(err(
                line_of[imax],
                format!(
                    "the largest `{}_mm` is {} mm, below any recording's resolution; these look like metres: declare `{}_m` in the header",
                    c.name(),
                    vmax * 1e3,
                    c.name()
                ),
            ));
        }
    }
    Ok(IrregularityTable {
        stations,
        columns: cols.iter().map(|(c, _)| *c).zip(values).collect(),
    })
}

/// Reads an irregularity table from a file (size-checked before reading).
pub fn read_table_file(path: &std::path::Path) -> Result<IrregularityTable, IrregularityError> {
    let file = path.display().to_string();
    limits::check_file(path, "the irregularity file").map_err(|what| IrregularityError {
        file: file.clone(),
        line: 0,
        what,
    })?;
    let text = std::fs::read_to_string(path).map_err(|e| IrregularityError {
        file: file.clone(),
        line: 0,
        what: format!(
            "cannot read the irregularity file ({e}); check the path (relative to the model file)"
        ),
    })?;
    read_table(&text, &file)
}

/// Writes a table as CSV in millimetres: `station [m],<component> [mm],…` (the units in
/// brackets, as every output CSV), values with the shortest decimal that reads back to the
/// same f64 (of the value in mm). [`read_table`] reads it back.
pub fn write_table(t: &IrregularityTable) -> String {
    let mut out = String::from("station [m]");
    for (c, _) in &t.columns {
        out.push_str(&format!(",{} [mm]", c.name()));
    }
    out.push('\n');
    for (i, s) in t.stations.iter().enumerate() {
        out.push_str(&format!("{s}"));
        for (_, v) in &t.columns {
            out.push_str(&format!(",{}", v[i] * 1e3));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_units_and_columns() {
        let t = read_table(
            "# a measured run\nstation_m, vertical_mm, gauge_m\n0,1.5,0.001\n1,2,0\n2,-1,0\n3,0,0.002\n",
            "x.csv",
        )
        .unwrap();
        assert_eq!(t.stations, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(t.columns[0].0, Component::Vertical);
        assert!((t.columns[0].1[0] - 1.5e-3).abs() < 1e-18);
        assert_eq!(t.columns[1].1[3], 0.002);
        // The bracketed units of railfem's own output CSVs read the same.
        let u = read_table(
            "station [m], vertical [mm], gauge [m]\n0,1.5,0.001\n1,2,0\n2,-1,0\n3,0,0.002\n",
            "x.csv",
        )
        .unwrap();
        assert_eq!(u, t);
        let e = read_table("station [m],vertical [in]\n", "x.csv").unwrap_err();
        assert!(e.to_string().contains("not a component with units"), "{e}");
    }

    #[test]
    fn refuses_bad_tables() {
        let bad = |text: &str, expect: &str| {
            let e = read_table(text, "x.csv").unwrap_err().to_string();
            assert!(e.contains(expect), "{e}");
        };
        bad("station_m,vertical\n0,1\n", "not a component with units");
        bad("s,vertical_mm\n", "first column must be `station_m`");
        bad(
            "station_m,vertical_mm\n0,1\n2,1\n1,1\n3,1\n",
            "x.csv:4: station 1 m does not follow 2 m",
        );
        bad(
            "station_m,vertical_mm\n0,1\n1,1\n1,1\n3,1\n",
            "strictly increase",
        );
        bad(
            "station_m,vertical_m\n0,1\n1,2.5\n2,1\n3,1\n",
            "x.csv:3: `vertical_m` = 2.5 m",
        );
        bad(
            "station_m,vertical_mm\n0,0.0001\n1,0.0002\n2,0\n3,0\n",
            "look like metres",
        );
        bad(
            "station_m,vertical_mm\n0,1\n1,NaN\n2,0\n3,0\n",
            "not a finite",
        );
        bad("station_m,vertical_mm\n0,1\n1,1\n", "at least 4");
        bad("station_m,vertical_mm,vertical_m\n", "twice");
    }

    #[test]
    fn write_then_read() {
        let t = IrregularityTable {
            stations: vec![0.0, 0.25, 0.5, 0.75, 1.0],
            columns: vec![
                (
                    Component::Vertical,
                    vec![1e-3, -2.5e-3, 3.3e-4, 0.0, 1.234_567e-3],
                ),
                (Component::Gauge, vec![0.0, 1e-4, 2e-4, -1e-4, 0.0]),
            ],
        };
        let back = read_table(&write_table(&t), "w.csv").unwrap();
        assert_eq!(back.stations, t.stations);
        for ((c, a), (d, b)) in back.columns.iter().zip(&t.columns) {
            assert_eq!(c, d);
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() <= 1e-15 * y.abs().max(1e-3), "{x} vs {y}");
            }
        }
    }
}
