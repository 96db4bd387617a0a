//! The study's outputs: the columns of `study.csv` (units in the headers), one row per case
//! formatted deterministically (every number `{:.6e}`, the same text whichever thread, rank
//! or run computed it), the table itself (rows sorted by case id), the `study.json` sidecar
//! and the summary figure (max ΔQ/Q and max Y/Q over the first two axes with the limits).

use super::cases::Case;
use super::plan::{Base, Plan};
use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use std::collections::BTreeMap;
use std::path::Path;

/// Derailment-safety limits drawn on the figure: ΔQ/Q (wheel unloading) 0.6 and Y/Q
/// (Nadal-type derailment quotient) 0.8, the values the issue names (EN 14363 uses 0.8 for
/// Y/Q; 0.6 is the common limit for ΔQ/Q in Japanese and Korean practice).
pub const LIMIT_DQQ: f64 = 0.6;
/// See [`LIMIT_DQQ`].
pub const LIMIT_YQ: f64 = 0.8;

/// Unit of a case key as a header suffix.
pub fn unit(key: &str) -> &'static str {
    match key {
        "speed" => "[m/s]",
        "span" | "element_length" | "radius" | "ct" | "pier_height" => "[m]",
        "duration" | "dt" | "quake_duration" => "[s]",
        "penalty" => "[N/m]",
        "pga" => "[g]",
        "anti_roll" => "[N m/rad]",
        "lengths" => "[m]",
        "quake" => "[file]",
        "cars" | "spans" | "seed" | "midspans" | "tangential" | "geometry" => "[-]",
        "first_active_set" => "[-]",
        "mu" | "quake_scale" => "[-]",
        _ => "[model units]",
    }
}

/// Wheels of the widest train of a train–bridge plan (8 per carriage).
fn wheels(plan: &Plan) -> usize {
    let mut cars = 12.0f64;
    for (k, v) in &plan.options {
        if let (true, super::plan::AxisValue::Num(x)) = (k == "cars", v) {
            cars = *x;
        }
    }
    for a in plan.axes.iter().filter(|a| a.name == "cars") {
        cars = a
            .values
            .iter()
            .filter_map(|v| match v {
                super::plan::AxisValue::Num(x) => Some(*x),
                _ => None,
            })
            .fold(0.0, f64::max);
    }
    8 * cars.clamp(1.0, 1e4) as usize
}

/// Name of wheel `i` (`w<axle><L|R>`, axles from the front), as `railfem train-bridge`.
pub fn wheel_name(i: usize) -> String {
    format!("w{}{}", i / 2 + 1, if i % 2 == 0 { "L" } else { "R" })
}

/// The result columns of the plan's base (after `case`, the axes, `status`, `error`).
pub fn result_columns(plan: &Plan) -> Vec<String> {
    let extremes = [
        "max_YQ [-]",
        "max_YQ_wheel",
        "t_max_YQ [s]",
        "max_dQQ [-]",
        "max_dQQ_wheel",
        "t_max_dQQ [s]",
        "min_Q [N]",
        "min_Q_wheel",
        "t_min_Q [s]",
    ];
    let mut c: Vec<String> = Vec::new();
    match &plan.base {
        Base::TrainBridge => {
            c.extend(extremes.iter().map(|s| s.to_string()));
            c.extend(
                [
                    "max_deflection [m]",
                    "max_deflection_span",
                    "t_max_deflection [s]",
                    "max_deck_acc [m/s2]",
                    "max_deck_acc_span",
                    "t_max_deck_acc [s]",
                ]
                .iter()
                .map(|s| s.to_string()),
            );
            for w in 0..wheels(plan) {
                let n = wheel_name(w);
                for (q, u) in [
                    ("max_YQ", "[-]"),
                    ("t_max_YQ", "[s]"),
                    ("max_dQQ", "[-]"),
                    ("t_max_dQQ", "[s]"),
                    ("min_Q", "[N]"),
                    ("t_min_Q", "[s]"),
                ] {
                    c.push(format!("{n}_{q} {u}"));
                }
            }
        }
        Base::Curve => {
            c.extend(extremes.iter().map(|s| s.to_string()));
            c.extend(
                [
                    "slid [0/1]",
                    "first_slide [s]",
                    "separated [0/1]",
                    "first_separation [s]",
                    "max_rel_normal_statics [-]",
                ]
                .iter()
                .map(|s| s.to_string()),
            );
        }
        Base::Model { .. } => {
            c.extend(
                [
                    "steps [-]",
                    "newton_iterations [-]",
                    "step_cuts [-]",
                    "max_abs_disp_end [m]",
                ]
                .iter()
                .map(|s| s.to_string()),
            );
            c.extend(extremes.iter().map(|s| s.to_string()));
        }
    }
    c
}

/// The header line of `study.csv`.
pub fn header(plan: &Plan) -> String {
    let mut h = vec!["case".to_string()];
    h.extend(
        plan.axes
            .iter()
            .map(|a| format!("{} {}", a.name, unit(&a.name))),
    );
    h.push("status".into());
    h.push("error".into());
    h.extend(result_columns(plan));
    h.join(",")
}

/// A number as every table prints it.
pub fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.6e}")
    } else {
        String::new()
    }
}

/// A CSV field: quoted when it holds a comma, a quote or a line break (RFC 4180), line
/// breaks replaced by spaces so that one case is one line.
pub fn field(text: &str) -> String {
    let t = text.replace(['\n', '\r'], " ");
    if t.contains([',', '"']) {
        format!("\"{}\"", t.replace('"', "\"\""))
    } else {
        t
    }
}

/// The row of a case: id, axis values, status, error, then `results` (already formatted;
/// empty cells for a failed case).
pub fn row(plan: &Plan, case: &Case, outcome: &Result<Vec<String>, String>) -> String {
    let mut r = vec![case.id.clone()];
    r.extend(case.values.iter().map(|v| field(&v.label())));
    let ncols = result_columns(plan).len();
    match outcome {
        Ok(cells) => {
            r.push("ok".into());
            r.push(String::new());
            r.extend(cells.iter().cloned());
            r.resize(r.len() + ncols.saturating_sub(cells.len()), String::new());
        }
        Err(e) => {
            r.push("failed".into());
            r.push(field(e));
            r.extend(std::iter::repeat_n(String::new(), ncols));
        }
    }
    r.join(",")
}

/// Writes `study.csv` (header, then the rows sorted by case id) whole, through a temporary
/// name ([`crate::atomic_file`]).
pub fn write_csv(plan: &Plan, rows: &BTreeMap<String, String>, dir: &Path) -> Result<(), FemError> {
    let mut s = header(plan);
    s.push('\n');
    for line in rows.values() {
        s.push_str(line);
        s.push('\n');
    }
    crate::atomic_file::write(&dir.join("study.csv"), s.as_bytes())
}

/// The summary figure `study.svg`/`.png`: for a train–bridge plan, max ΔQ/Q and max Y/Q of
/// every finished case against the first numeric axis, one series per value of the second
/// axis, with the limit lines; `None` when the plan has no numeric axis or no result.
pub fn write_figure(
    plan: &Plan,
    cases: &[Case],
    rows: &BTreeMap<String, String>,
    dir: &Path,
) -> Result<Option<std::path::PathBuf>, FemError> {
    if !matches!(plan.base, Base::TrainBridge | Base::Curve) {
        return Ok(None);
    }
    let numeric: Vec<usize> = (0..plan.axes.len())
        .filter(|&k| {
            plan.axes[k]
                .values
                .iter()
                .all(|v| matches!(v, super::plan::AxisValue::Num(_)))
                && plan.axes[k].values.len() > 1
        })
        .collect();
    // x: the speed axis if there is one, else the first numeric axis.
    let Some(&xa) = numeric
        .iter()
        .find(|&&k| plan.axes[k].name == "speed")
        .or(numeric.first())
    else {
        return Ok(None);
    };
    // Series: the intensity scale if it is an axis, else the numeric axis with the fewest
    // values (a legend of a few lines).
    let sa = numeric
        .iter()
        .copied()
        .filter(|&k| k != xa)
        .min_by_key(|&k| {
            (
                plan.axes[k].name != "quake_scale",
                plan.axes[k].values.len(),
                k,
            )
        });
    let col = |name: &str| {
        header(plan)
            .split(',')
            .position(|h| h == name)
            .expect("a result column")
    };
    let (c_dqq, c_yq) = (col("max_dQQ [-]"), col("max_YQ [-]"));
    let colors = [
        "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
    ];
    let series_values: Vec<Option<&super::plan::AxisValue>> = match sa {
        Some(k) => plan.axes[k].values.iter().map(Some).collect(),
        None => vec![None],
    };
    let xs_axis: Vec<f64> = plan.axes[xa]
        .values
        .iter()
        .filter_map(|v| match v {
            super::plan::AxisValue::Num(x) => Some(*x),
            _ => None,
        })
        .collect();
    let (x0, x1) = xs_axis
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    let xlabel = format!("{} {}", plan.axes[xa].name, unit(&plan.axes[xa].name));
    let mut any = false;
    let mut panels = Vec::new();
    for (c, what, limit) in [
        (c_dqq, "max ΔQ/Q [-]", LIMIT_DQQ),
        (c_yq, "max Y/Q [-]", LIMIT_YQ),
    ] {
        let mut panel = Panel::new(
            &format!(
                "{what} over {} (worst case of the other axes)",
                plan.axes[xa].name
            ),
            &xlabel,
            what,
        );
        for (si, sv) in series_values.iter().enumerate() {
            // Per x: the largest value over every case with this series value.
            let mut best: BTreeMap<u64, f64> = BTreeMap::new();
            for case in cases {
                if let (Some(k), Some(v)) = (sa, sv) {
                    if &&case.values[k] != v {
                        continue;
                    }
                }
                let Some(line) = rows.get(&case.id) else {
                    continue;
                };
                let cells = split_csv(line);
                let Some(y) = cells.get(c).and_then(|t| t.parse::<f64>().ok()) else {
                    continue;
                };
                let super::plan::AxisValue::Num(x) = case.values[xa] else {
                    continue;
                };
                let e = best.entry(x.to_bits()).or_insert(f64::NEG_INFINITY);
                *e = e.max(y);
            }
            let mut pts: Vec<(f64, f64)> =
                best.iter().map(|(x, y)| (f64::from_bits(*x), *y)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            if pts.is_empty() {
                continue;
            }
            any = true;
            let label = match (sa, sv) {
                (Some(k), Some(v)) => format!("{} = {}", plan.axes[k].name, v.label()),
                _ => "cases".into(),
            };
            panel = panel.with(Series::new(
                &label,
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
                Style::Line,
                colors[si % colors.len()],
            ));
        }
        panel = panel.with(Series::new(
            &format!("limit {limit}"),
            vec![x0, x1],
            vec![limit, limit],
            Style::Dashed,
            "#000000",
        ));
        panels.push(panel);
    }
    if !any {
        return Ok(None);
    }
    let mut fig = Figure::new();
    for p in panels {
        fig = fig.with(p);
    }
    let svg = dir.join("study.svg");
    fig.write_svg_and_png(&svg)
        .map_err(|e| FemError::output(&svg, e))?;
    Ok(Some(svg))
}

/// Splits one CSV line of this module's making (quoted fields as [`field`] writes them).
pub fn split_csv(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    out.push(cur);
    out
}
