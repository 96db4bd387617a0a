//! The outputs of a check: `envelope.csv` (one row per train and speed, units in the
//! header), `acceleration.svg/.png` (peak deck acceleration against speed, one curve per
//! train, the limit and the resonance speeds `v = n₀·D/i`), `dynamic-factor.svg/.png`, and
//! `report.md` (inputs, figures, the governing case and the verdict).

use super::envelope::{Outcome, KMH};
use super::interaction::VehicleModel;
use super::Results;
use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use std::fmt::Write as _;
use std::path::Path;

/// Colours of the trains' curves, in turn.
const COLOURS: [&str; 12] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#393b79", "#637939",
];

/// The rows of `envelope.csv`.
pub fn csv(r: &Results) -> String {
    let mut s = String::from(
        "train [-],model [-],speed [km/h],acceleration [m/s²],acceleration station [m],acceleration time [s],deflection [m],deflection station [m],static deflection [m],dynamic factor [-],phi_dyn [-]\n",
    );
    for o in &r.outcomes {
        let _ = writeln!(
            s,
            "{},{},{},{:.6},{:.3},{:.4},{:.6e},{:.3},{:.6e},{:.5},{:.5}",
            r.trains[o.train].name,
            o.model.name(),
            o.speed,
            o.acceleration,
            o.acc_station,
            o.acc_time,
            o.deflection,
            o.defl_station,
            o.static_deflection,
            o.dynamic_factor(),
            o.dynamic_factor() - 1.0
        );
    }
    s
}

/// Resonance speeds (km/h) `v_i = n₀·λ/i` of a train's regular spacing within `[lo, hi]`
/// (EN 1991-2 Eq. 6.9), `i = 1, 2, 3, 4`.
pub fn resonance_speeds(n0: f64, spacing: f64, lo: f64, hi: f64) -> Vec<f64> {
    (1..=4)
        .map(|i| n0 * spacing / i as f64 * KMH)
        .filter(|v| (lo..=hi).contains(v))
        .collect()
}

/// One curve per train and model: a train's colour, moving forces solid, sprung masses
/// dashed, full vehicles as markers (named so in the legend when several ran).
fn curves(r: &Results, y: &dyn Fn(&Outcome) -> f64) -> Vec<Series> {
    let models = r.plan.analysis.model.list();
    let mut out = Vec::new();
    for (i, t) in r.trains.iter().enumerate() {
        for &m in &models {
            let (xs, ys): (Vec<f64>, Vec<f64>) = r
                .outcomes
                .iter()
                .filter(|o| o.train == i && o.model == m)
                .map(|o| (o.speed, y(o)))
                .unzip();
            let (name, style) = match (m, models.len()) {
                (_, 1) => (t.name.clone(), Style::Line),
                (VehicleModel::MovingForces, _) => (format!("{} forces", t.name), Style::Line),
                (VehicleModel::SprungMasses, _) => (format!("{} sprung", t.name), Style::Dashed),
                (VehicleModel::FullVehicles, _) => (format!("{} vehicles", t.name), Style::Markers),
            };
            out.push(Series::new(
                &name,
                xs,
                ys,
                style,
                COLOURS[i % COLOURS.len()],
            ));
        }
    }
    out
}

/// Writes every output into `out`.
pub fn write(r: &Results, out: &Path) -> Result<(), FemError> {
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("envelope.csv");
    std::fs::write(&p, csv(r)).map_err(|e| FemError::output(&p, e))?;
    let speeds: Vec<f64> = r.outcomes.iter().map(|o| o.speed).collect();
    let lo = speeds.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = speeds.iter().cloned().fold(0.0, f64::max);
    let limit = r.limit();
    let n0 = r.frequencies[0];
    let top = r.outcomes.iter().fold(limit, |m, o| m.max(o.acceleration));
    let mut acc = Panel::new(
        &format!(
            "Peak deck acceleration (cut-off {:.1} Hz, ζ = {:.2} %)",
            r.cutoff,
            r.damping.0 * 100.0
        ),
        "speed (km/h)",
        "peak acceleration (m/s²)",
    );
    for s in curves(r, &|o| o.acceleration) {
        acc = acc.with(s);
    }
    acc = acc.with(Series::new(
        &format!("limit {limit} m/s² ({} track)", r.plan.bridge.track.name()),
        vec![lo, hi],
        vec![limit, limit],
        Style::Dashed,
        "black",
    ));
    let mut rx = Vec::new();
    for t in &r.trains {
        if let Some(d) = t.regular_spacing {
            rx.extend(resonance_speeds(n0, d, lo, hi));
        }
    }
    if !rx.is_empty() {
        let ry = vec![0.02 * top; rx.len()];
        acc = acc.with(Series::new(
            "resonance speeds n0·D/i",
            rx,
            ry,
            Style::Squares,
            "black",
        ));
    }
    let p = out.join("acceleration.svg");
    Figure::new()
        .with(acc)
        .write_svg_and_png(&p)
        .map_err(|e| FemError::output(&p, e))?;
    let mut dynf = Panel::new(
        "Dynamic factor max|y_dyn| / max|y_stat| (= 1 + φ'_dyn)",
        "speed (km/h)",
        "dynamic factor (-)",
    );
    for s in curves(r, &|o| o.dynamic_factor()) {
        dynf = dynf.with(s);
    }
    let p = out.join("dynamic-factor.svg");
    Figure::new()
        .with(dynf)
        .write_svg_and_png(&p)
        .map_err(|e| FemError::output(&p, e))?;
    let p = out.join("report.md");
    std::fs::write(&p, markdown(r)).map_err(|e| FemError::output(&p, e))?;
    Ok(())
}

/// The one-page report.
pub fn markdown(r: &Results) -> String {
    let b = &r.plan.bridge;
    let limit = r.limit();
    let mut s = String::from("# Bridge dynamic check (EN 1991-2 §6.4.6)\n\n## Inputs\n\n");
    match &b.model {
        Some(m) => {
            let _ = writeln!(
                s,
                "- Bridge: model file `{}`, deck path of {} elements ({} equations); spans {:?} m",
                m.display(),
                b.deck.len(),
                r.equations,
                b.spans
            );
        }
        None => {
            let _ = writeln!(
                s,
                "- Bridge: {} spans {:?} m, EI = {:.4e} N·m², μ = {:.1} kg/m, {} elements per span ({} equations)",
                match b.support {
                    super::bridge::Support::SimplySupported => "simply supported",
                    super::bridge::Support::Continuous => "continuous",
                },
                b.spans,
                b.ei.unwrap_or(0.0),
                b.mass.unwrap_or(0.0),
                b.elements_per_span
                    .unwrap_or(super::bridge::DEFAULT_ELEMENTS_PER_SPAN),
                r.equations
            );
        }
    }
    let _ = writeln!(
        s,
        "- Track: {} → acceleration limit {limit} m/s² (EN 1990 A2.4.4.2.1(4)P)",
        b.track.name()
    );
    let _ = writeln!(
        s,
        "- Damping: ζ = {:.3} % — {}; Rayleigh α = {:.4e} 1/s, β = {:.4e} s (ζ at n₀ and at the cut-off)",
        r.damping.0 * 100.0,
        r.damping.1,
        r.rayleigh.0,
        r.rayleigh.1
    );
    let f: Vec<String> = r
        .frequencies
        .iter()
        .take(6)
        .map(|f| format!("{f:.3}"))
        .collect();
    let _ = writeln!(s, "- Vertical bending frequencies: {} Hz", f.join(", "));
    let n0 = r.frequencies[0];
    match super::bridge::frequency_limits(r.length) {
        Some((lo, hi)) => {
            let inside = (lo..=hi).contains(&n0);
            let _ = writeln!(
                s,
                "- EN 1991-2 Fig. 6.10 at L = {:.2} m: {lo:.2} Hz ≤ n₀ ≤ {hi:.2} Hz; n₀ = {n0:.3} Hz is {}; with a line speed of {} km/h {} (Fig. 6.9)",
                r.length,
                if inside { "inside" } else { "outside" },
                r.plan.speeds.max_line_speed,
                if r.plan.speeds.max_line_speed > 200.0 || !inside {
                    "a dynamic analysis is required"
                } else {
                    "a dynamic analysis may not be required for a simple structure"
                }
            );
        }
        None => {
            let _ = writeln!(
                s,
                "- EN 1991-2 Fig. 6.10 covers 4 m ≤ L ≤ 100 m; L = {:.2} m is outside it",
                r.length
            );
        }
    }
    let _ = writeln!(
        s,
        "- Cut-off {:.2} Hz = max(30 Hz, 1.5·n₀, n₃) (EN 1991-2 §6.4.6.5(3)); Δt = {:.3e} s (Newmark average acceleration)",
        r.cutoff, r.dt
    );
    let _ = writeln!(
        s,
        "- Speeds {} to {} km/h (1.2 × {} km/h) by {} km/h, {} halvings around each local maximum; trains: {}",
        r.plan.speeds.min,
        1.2 * r.plan.speeds.max_line_speed,
        r.plan.speeds.max_line_speed,
        r.plan.speeds.step,
        r.plan.speeds.refine,
        r.trains
            .iter()
            .map(|t| t.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "- {} train–speed runs in {:.2} s on {} threads ({:.1} ms a run a thread); whole check {:.2} s\n",
        r.outcomes.len(),
        r.seconds.0,
        r.threads,
        r.seconds.0 * r.threads as f64 / r.outcomes.len().max(1) as f64 * 1e3,
        r.seconds.1
    );
    s.push_str("## Figures\n\n![peak acceleration](acceleration.png)\n\n![dynamic factor](dynamic-factor.png)\n\n## Per train\n\n| train | model | peak acceleration [m/s²] | at speed [km/h] | station [m] | time [s] | max dynamic factor [-] |\n|---|---|---|---|---|---|---|\n");
    for (i, t) in r.trains.iter().enumerate() {
        for m in r.plan.analysis.model.list() {
            let row = r.outcomes.iter().filter(|o| o.train == i && o.model == m);
            let best = row
                .clone()
                .max_by(|a, b| a.acceleration.total_cmp(&b.acceleration));
            let phi = row.fold(0.0f64, |m, o| m.max(o.dynamic_factor()));
            if let Some(o) = best {
                let _ = writeln!(
                    s,
                    "| {} | {} | {:.3} | {:.1} | {:.2} | {:.3} | {:.3} |",
                    t.name,
                    m.name(),
                    o.acceleration,
                    o.speed,
                    o.acc_station,
                    o.acc_time,
                    phi
                );
            }
        }
    }
    simplified_table(r, &mut s);
    s.push_str("\n## Verdict\n\n");
    if let Some(g) = r.governing() {
        let pass = g.acceleration <= limit;
        let _ = writeln!(
            s,
            "Governing: **{}** ({}) at **{:.1} km/h**: peak deck acceleration **{:.3} m/s²** at {:.2} m along the deck, {:.3} s after the first axle entered; deflection {:.3e} m (dynamic factor {:.3}).\n",
            r.trains[g.train].name,
            g.model.name().replace('_', " "),
            g.speed,
            g.acceleration,
            g.acc_station,
            g.acc_time,
            g.deflection,
            g.dynamic_factor()
        );
        let _ = writeln!(
            s,
            "**{}**: {:.3} m/s² {} the limit of {limit} m/s² ({:.0} % of it).",
            if pass { "PASSES" } else { "FAILS" },
            g.acceleration,
            if pass { "is within" } else { "exceeds" },
            100.0 * g.acceleration / limit
        );
    }
    if let Some((fa, ma, fd, md)) = r.reference {
        let _ = writeln!(
            s,
            "\nModal reference (30 exact sine modes, same filter) at the governing case: acceleration {ma:.4} m/s² (FE {:+.3} %), deflection {md:.4e} m (FE {:+.3} %).",
            100.0 * (fa / ma - 1.0),
            100.0 * (fd / md - 1.0)
        );
    }
    if let [f, rest @ ..] = r.models_compared.as_slice() {
        if !rest.is_empty() {
            let part = |o: &Outcome, x: fn(&Outcome) -> f64, unit: &str, digits: bool| {
                let name = o.model.name().replace('_', " ");
                let v = if digits {
                    format!("{:.4}", x(o))
                } else {
                    format!("{:.4e}", x(o))
                };
                if o.model == VehicleModel::MovingForces {
                    format!("{name} {v} {unit}")
                } else {
                    format!(
                        "{name} {v} {unit} ({:+.2} % against the moving forces)",
                        100.0 * (x(o) / x(f) - 1.0)
                    )
                }
            };
            let all = &r.models_compared;
            let acc: Vec<String> = all
                .iter()
                .map(|o| part(o, |o| o.acceleration, "m/s²", true))
                .collect();
            let defl: Vec<String> = all
                .iter()
                .map(|o| part(o, |o| o.deflection, "m", false))
                .collect();
            let _ = writeln!(
                s,
                "\nThe models at the governing train and speed ({}, {:.1} km/h): {}; deflection: {}.",
                r.trains[f.train].name,
                f.speed,
                acc.join(", "),
                defl.join(", ")
            );
        }
    }
    s
}

/// The DER and LIR table of a simply supported span beside the FE peaks of moving forces.
fn simplified_table(r: &Results, s: &mut String) {
    if r.simplified.is_empty() {
        return;
    }
    s.push_str("\n## Simplified methods (ERRI D214, first mode at midspan)\n\nDER and LIR over the speed range every 0.5 km/h beside the FE envelope's peak of moving forces (every station, modes up to the cut-off); neither method counts modes above the first.\n\n| train | FE peak [m/s²] | DER [m/s²] | at [km/h] | LIR [m/s²] | at [km/h] | DER/FE [-] | LIR/FE [-] |\n|---|---|---|---|---|---|---|---|\n");
    for row in &r.simplified {
        let fe = r
            .outcomes
            .iter()
            .filter(|o| o.train == row.train && o.model == VehicleModel::MovingForces)
            .fold(0.0f64, |m, o| m.max(o.acceleration));
        if fe <= 0.0 {
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {fe:.3} | {:.3} | {:.1} | {:.3} | {:.1} | {:.2} | {:.2} |",
            r.trains[row.train].name,
            row.der.0,
            row.der.1,
            row.lir.0,
            row.lir.1,
            row.der.0 / fe,
            row.lir.0 / fe
        );
    }
}
