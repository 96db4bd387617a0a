//! `railfem assess RUN_DIR`: the running-safety and track-loading quantities of EN 14363
//! and UIC 518 from a run's wheel forces, with their limits (docs/assessment.md).
//!
//! What lives here: the evaluation of one run ([`assess`]: filtering, sliding means,
//! percentiles, limits, per wheel and wheelset), its outputs (`assessment.csv`,
//! `assessment-summary.csv`, `assessment.svg`/`.png`) and the command. The signal
//! processing is in [`signals`], the limits and indices in [`limits`], the reading of the
//! run's CSV files in [`read`].

pub mod limits;
pub mod read;
pub mod signals;

use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use limits::{prudhomme, surface_fatigue_index, AssessLimits};
use signals::{low_pass, percentile, sliding_mean};
use std::fmt::Write as _;
use std::path::Path;

/// Where the quasi-static values are taken: stations `from..=to` (m); `None` = the run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Section {
    /// First station (m).
    pub from: Option<f64>,
    /// Last station (m).
    pub to: Option<f64>,
}

impl Section {
    fn contains(&self, s: f64) -> bool {
        self.from.is_none_or(|f| s >= f) && self.to.is_none_or(|t| s <= t)
    }
}

/// The processed histories of one wheel.
#[derive(Debug, Clone, Default)]
pub struct WheelResult {
    /// The wheel's column prefix.
    pub name: String,
    /// The wheel's station (m).
    pub s: Vec<f64>,
    /// Static wheel load Q0 (N).
    pub q0: f64,
    /// Filtered Q and Y (N).
    pub q: Vec<f64>,
    /// See `q`.
    pub y: Vec<f64>,
    /// Y/Q on the sliding mean (-).
    pub yq_mean: Vec<f64>,
    /// Wheel unloading ΔQ/Q0 = (Q0 − Q)/Q0 of the filtered Q (-).
    pub dqq: Vec<f64>,
    /// The wheel's wear number Tγ (N = J/m), empty if not recorded.
    pub t_gamma: Vec<f64>,
    /// Surface fatigue index at the most loaded contact point (-), empty if not recorded.
    pub fi_surf: Vec<f64>,
}

/// One row of the summary: a quantity of one wheel or wheelset, its value and limit.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryRow {
    /// The quantity (`Y/Q 2 m`, `ΣY 2 m`, …).
    pub quantity: String,
    /// The wheel or wheelset.
    pub item: String,
    /// Value (in `unit`).
    pub value: f64,
    /// Limit (NaN: none).
    pub limit: f64,
    /// Unit of value and limit.
    pub unit: String,
    /// Station where the value occurs (m; NaN for a percentile or a sum).
    pub at: f64,
}

impl SummaryRow {
    /// The margin `(limit − value)/limit`, or `limit − value` for a limit of zero (the
    /// fatigue index): positive when the value is inside its limit (NaN without a limit).
    pub fn margin(&self) -> f64 {
        if self.limit == 0.0 {
            -self.value
        } else {
            (self.limit - self.value) / self.limit
        }
    }
}

/// A whole assessment.
#[derive(Debug, Clone, Default)]
pub struct Assessment {
    /// Stations (m) and times (s) of the samples (of the first wheel's file).
    pub s: Vec<f64>,
    /// See `s`.
    pub t: Vec<f64>,
    /// Per wheel.
    pub wheels: Vec<WheelResult>,
    /// Per wheelset: its name, the left wheel's station (m) and ΣY on the sliding mean (N).
    pub sum_y: Vec<(String, Vec<f64>, Vec<f64>)>,
    /// The summary table.
    pub summary: Vec<SummaryRow>,
    /// Σ over the wheels of Tγ·Δs (J): the creep forces' work over the run.
    pub wear_work: f64,
}

/// The index and value of the largest `|x|` (finite values only).
fn abs_max(x: &[f64]) -> (usize, f64) {
    let abs: Vec<f64> = x.iter().map(|v| v.abs()).collect();
    arg_max(&abs)
}

/// The index and value of the largest finite value of `x` (`(0, NaN)` for none).
fn arg_max(x: &[f64]) -> (usize, f64) {
    x.iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .fold((0, f64::NAN), |(i0, m), (i, &v)| {
            if m.is_nan() || v > m {
                (i, v)
            } else {
                (i0, m)
            }
        })
}

/// The sampling frequency of `t` (Hz) from its median step; NaN for fewer than 2 samples.
fn sampling_rate(t: &[f64]) -> f64 {
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return f64::NAN;
    }
    d.sort_by(f64::total_cmp);
    1.0 / d[d.len() / 2]
}

/// Assesses the wheels `wheels` (as [`read::wheels`] gives them) with `lim` over `section`.
/// `q0`: the static wheel load (N), or `None` for each wheelset's mean wheel load over the
/// run.
pub fn assess(
    wheels: &[read::Wheel],
    lim: &AssessLimits,
    section: Section,
    q0: Option<f64>,
) -> Assessment {
    let mut out = Assessment {
        s: wheels.first().map(|w| w.s.clone()).unwrap_or_default(),
        t: wheels.first().map(|w| w.t.clone()).unwrap_or_default(),
        ..Default::default()
    };
    let row =
        |quantity: &str, item: &str, value: f64, limit: f64, unit: &str, at: f64| SummaryRow {
            quantity: quantity.into(),
            item: item.into(),
            value,
            limit,
            unit: unit.into(),
            at,
        };
    let mean = |x: &[f64]| {
        let v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    for pair in wheels.chunks(2) {
        let set_q0 =
            q0.unwrap_or_else(|| pair.iter().map(|w| mean(&w.q)).sum::<f64>() / pair.len() as f64);
        let mut filtered_y = Vec::new();
        for w in pair {
            let fs = sampling_rate(&w.t);
            let q = low_pass(&w.q, fs, lim.cutoff);
            let y = low_pass(&w.y, fs, lim.cutoff);
            let ratio: Vec<f64> = q
                .iter()
                .zip(&y)
                .map(|(q, y)| if *q > 0.0 { y / q } else { f64::NAN })
                .collect();
            let yq_mean = sliding_mean(&w.s, &ratio, lim.window);
            let dqq: Vec<f64> = q.iter().map(|q| (set_q0 - q) / set_q0).collect();
            let (i, v) = abs_max(&yq_mean);
            let at = |i: usize| w.s.get(i).copied().unwrap_or(f64::NAN);
            out.summary
                .push(row("Y/Q 2 m", &w.name, v, lim.yq(), "-", at(i)));
            let (i, v) = arg_max(&dqq);
            out.summary
                .push(row("dQ/Q0", &w.name, v, lim.dqq_limit, "-", at(i)));
            let abs_y: Vec<f64> = y.iter().map(|v| v.abs()).collect();
            let (i, v) = abs_max(&abs_y);
            out.summary
                .push(row("Ymax", &w.name, v, f64::NAN, "N", at(i)));
            out.summary.push(row(
                &format!("Y {}%", lim.max_percentile),
                &w.name,
                percentile(&abs_y, lim.max_percentile),
                f64::NAN,
                "N",
                f64::NAN,
            ));
            let (i, v) = abs_max(&q);
            out.summary
                .push(row("Qmax", &w.name, v, lim.q_max_add + set_q0, "N", at(i)));
            out.summary.push(row(
                &format!("Q {}%", lim.max_percentile),
                &w.name,
                percentile(&q, lim.max_percentile),
                lim.q_max_add + set_q0,
                "N",
                f64::NAN,
            ));
            let in_section = |x: &[f64]| -> Vec<f64> {
                x.iter()
                    .zip(&w.s)
                    .filter(|(_, s)| section.contains(**s))
                    .map(|(v, _)| *v)
                    .collect()
            };
            out.summary.push(row(
                "Yqst",
                &w.name,
                percentile(&in_section(&abs_y), lim.quasi_static_percentile),
                lim.y_qst_limit,
                "N",
                f64::NAN,
            ));
            out.summary.push(row(
                "Qqst",
                &w.name,
                percentile(&in_section(&q), lim.quasi_static_percentile),
                lim.q_qst_limit,
                "N",
                f64::NAN,
            ));
            let tg = w.t_gamma.clone().unwrap_or_default();
            // The element dissipates each step's creep work at the step's end state, so
            // the sum takes each sample's Tγ over the distance rolled since the last one.
            for k in 1..tg.len() {
                if tg[k].is_finite() {
                    out.wear_work += tg[k] * (w.s[k] - w.s[k - 1]);
                }
            }
            if !tg.is_empty() {
                let (i, v) = abs_max(&tg);
                out.summary
                    .push(row("Tgamma", &w.name, v, f64::NAN, "N", at(i)));
            }
            // Surface fatigue index at the most loaded point: its traction coefficient
            // |F|/N (the point's share of its patch's forces and load is the same), and
            // the shakedown term with the wheel's whole Q on the patch (exact for one
            // patch; with two, Q over-states the patch load, which lowers the shakedown
            // term: the index is then over-stated, on the safe side; docs/assessment.md).
            let fi: Vec<f64> = match &w.first {
                None => Vec::new(),
                Some(p) => (0..p.fx.len())
                    .map(|k| {
                        if p.a[k] > 0.0 && p.fn_[k] > 0.0 {
                            let f = p.fx[k].hypot(p.fy[k]) / p.fn_[k];
                            surface_fatigue_index(
                                f * w.q[k],
                                w.q[k],
                                p.a[k],
                                p.b[k],
                                lim.shear_yield,
                            )
                        } else {
                            f64::NAN
                        }
                    })
                    .collect(),
            };
            if fi.iter().any(|v| v.is_finite()) {
                let (i, v) = arg_max(&fi);
                out.summary
                    .push(row("FI_surf", &w.name, v, 0.0, "-", at(i)));
            }
            filtered_y.push(y.clone());
            out.wheels.push(WheelResult {
                name: w.name.clone(),
                s: w.s.clone(),
                q0: set_q0,
                q,
                y,
                yq_mean,
                dqq,
                t_gamma: tg,
                fi_surf: fi,
            });
        }
        if pair.len() == 2 {
            let name = format!("{}+{}", pair[0].name, pair[1].name);
            let n = filtered_y[0].len().min(filtered_y[1].len());
            let sum: Vec<f64> = (0..n)
                .map(|k| filtered_y[0][k] + filtered_y[1][k])
                .collect();
            let m = sliding_mean(&pair[0].s[..n], &sum, lim.window);
            let (i, v) = abs_max(&m);
            out.summary.push(row(
                "SumY 2 m",
                &name,
                v,
                prudhomme(lim.alpha, set_q0),
                "N",
                pair[0].s.get(i).copied().unwrap_or(f64::NAN),
            ));
            out.sum_y.push((name, pair[0].s[..n].to_vec(), m));
        }
    }
    out
}

/// Formats a number for the summary (`-` for NaN).
fn cell(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6e}")
    } else {
        String::new()
    }
}

/// Writes `assessment.csv` (the processed histories), `assessment-summary.csv` and the
/// figure `assessment.svg` (and `.png`) into `dir`.
pub fn write(a: &Assessment, dir: &Path) -> Result<(), FemError> {
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |e: std::io::Error| FemError::output(&p, e)
    };
    let path = dir.join("assessment.csv");
    let mut text = String::from("time [s],station [m]");
    for w in &a.wheels {
        let _ = write!(
            text,
            ",{0}_Q_filtered [N],{0}_Y_filtered [N],{0}_YQ_2m [-],{0}_dQQ0 [-]",
            w.name
        );
        if !w.t_gamma.is_empty() {
            let _ = write!(text, ",{}_Tgamma [N]", w.name);
        }
        if !w.fi_surf.is_empty() {
            let _ = write!(text, ",{}_FI_surf [-]", w.name);
        }
    }
    for (name, _, _) in &a.sum_y {
        let _ = write!(text, ",{name}_SumY_2m [N]");
    }
    text.push('\n');
    for i in 0..a.s.len() {
        let _ = write!(text, "{},{}", a.t[i], a.s[i]);
        for w in &a.wheels {
            for v in [&w.q, &w.y, &w.yq_mean, &w.dqq] {
                let _ = write!(text, ",{}", cell(v.get(i).copied().unwrap_or(f64::NAN)));
            }
            if !w.t_gamma.is_empty() {
                let _ = write!(
                    text,
                    ",{}",
                    cell(w.t_gamma.get(i).copied().unwrap_or(f64::NAN))
                );
            }
            if !w.fi_surf.is_empty() {
                let _ = write!(
                    text,
                    ",{}",
                    cell(w.fi_surf.get(i).copied().unwrap_or(f64::NAN))
                );
            }
        }
        for (_, _, m) in &a.sum_y {
            let _ = write!(text, ",{}", cell(m.get(i).copied().unwrap_or(f64::NAN)));
        }
        text.push('\n');
    }
    std::fs::write(&path, text).map_err(io(&path))?;
    let path = dir.join("assessment-summary.csv");
    let mut text = String::from(
        "quantity [-],item [-],value [as unit],limit [as unit],margin [-],unit [-],station [m]\n",
    );
    for r in &a.summary {
        let _ = writeln!(
            text,
            "{},{},{},{},{},{},{}",
            r.quantity,
            r.item,
            cell(r.value),
            cell(r.limit),
            cell(r.margin()),
            r.unit,
            cell(r.at)
        );
    }
    let _ = writeln!(
        text,
        "frictional work sum(Tgamma ds),all wheels,{},,,J,",
        cell(a.wear_work)
    );
    std::fs::write(&path, text).map_err(io(&path))?;
    figure(a)
        .write_svg_and_png(dir.join("assessment.svg"))
        .map_err(io(&dir.join("assessment.svg")))?;
    Ok(())
}

/// The summary as a text table (value, limit, margin), for the terminal.
pub fn table(a: &Assessment) -> String {
    let mut t = format!(
        "{:<22} {:<14} {:>13} {:>13} {:>9}\n",
        "quantity", "item", "value", "limit", "margin"
    );
    for r in &a.summary {
        let num = |v: f64| {
            if v.is_finite() {
                format!("{v:.4}")
            } else {
                "-".into()
            }
        };
        let margin = if r.limit == 0.0 {
            format!("{:.4}", r.margin())
        } else if r.margin().is_finite() {
            format!("{:.1} %", 100.0 * r.margin())
        } else {
            "-".into()
        };
        let _ = writeln!(
            t,
            "{:<22} {:<14} {:>13} {:>13} {:>9}",
            format!("{} [{}]", r.quantity, r.unit),
            r.item,
            num(r.value),
            num(r.limit),
            margin
        );
    }
    let _ = writeln!(
        t,
        "frictional work of the wheels, sum of Tgamma·ds: {:.6e} J",
        a.wear_work
    );
    t
}

const COLORS: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// Y/Q on the sliding mean per wheel with the Y/Q limit, and ΣY per wheelset with
/// Prud'homme's limit, over the station.
fn figure(a: &Assessment) -> Figure {
    let lim_of = |q: &str, item: &str| {
        a.summary
            .iter()
            .find(|r| r.quantity == q && r.item == item)
            .map_or(f64::NAN, |r| r.limit)
    };
    let ends = |s: &[f64]| -> Vec<f64> {
        vec![
            s.first().copied().unwrap_or(0.0),
            s.last().copied().unwrap_or(0.0),
        ]
    };
    let mut p1 = Panel::new("Y/Q, 2 m sliding mean", "station s (m)", "Y/Q (-)");
    for (k, w) in a.wheels.iter().enumerate() {
        p1 = p1.with(Series::new(
            &w.name,
            w.s.clone(),
            w.yq_mean.clone(),
            Style::Line,
            COLORS[k % 8],
        ));
    }
    if let Some(w) = a.wheels.first() {
        let l = lim_of("Y/Q 2 m", &w.name);
        p1 = p1.with(Series::new(
            "+limit",
            ends(&a.s),
            vec![l, l],
            Style::Dashed,
            "black",
        ));
        p1 = p1.with(Series::new(
            "-limit",
            ends(&a.s),
            vec![-l, -l],
            Style::Dashed,
            "black",
        ));
    }
    let mut p2 = Panel::new(
        "ΣY per wheelset, 2 m sliding mean",
        "station s (m)",
        "ΣY (kN)",
    );
    for (k, (name, s, m)) in a.sum_y.iter().enumerate() {
        let kn: Vec<f64> = m.iter().map(|v| v / 1e3).collect();
        p2 = p2.with(Series::new(name, s.clone(), kn, Style::Line, COLORS[k % 8]));
        let l = lim_of("SumY 2 m", name) / 1e3;
        p2 = p2.with(Series::new(
            &format!("limit {name}"),
            ends(&a.s),
            vec![l, l],
            Style::Dashed,
            COLORS[k % 8],
        ));
    }
    Figure::new().with(p1).with(p2)
}

/// Reads, assesses and writes `run_dir` (into `out`), printing the summary table.
pub fn run_assessment(
    run_dir: &Path,
    out: &Path,
    speed: Option<f64>,
    lim: &AssessLimits,
    section: Section,
    q0: Option<f64>,
) -> Result<Assessment, FemError> {
    let wheels = read::wheels(run_dir, speed)?;
    let a = assess(&wheels, lim, section, q0);
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    write(&a, out)?;
    print!("{}", table(&a));
    println!(
        "assessment of {} wheels: assessment.csv, assessment-summary.csv, assessment.svg in {}",
        a.wheels.len(),
        out.display()
    );
    Ok(a)
}

/// The `--assess` option of `run`, `curve` and `train-bridge`: the defaults, into the
/// run's own directory.
pub fn after_run(dir: &Path, speed: Option<f64>) -> Result<(), FemError> {
    run_assessment(
        dir,
        dir,
        speed,
        &AssessLimits::default(),
        Section::default(),
        None,
    )
    .map(|_| ())
}
