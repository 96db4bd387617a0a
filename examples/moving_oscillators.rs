//! Convergence study of the moving oscillators against their modal solutions
//! (docs/moving-oscillators.md): `cargo run --release --example moving_oscillators [OUT]`.
//!
//! For each case (sprung mass at constant speed, sprung mass braking, moving mass on a speed
//! table) it prints the modal solution's own convergence (modes, RK4 step), then the finite
//! element errors against it over the time step (32 elements) and over the mesh (small
//! step), as markdown tables, and writes `moving-oscillators.svg` (FE against modal; the
//! rolling mass's contact acceleration, which converges in neither model, is not drawn) and
//! the histories as CSV into OUT (default `target/moving-oscillators`).

use railfem::framework::plot::{Corner, Figure, Panel, Series, Style};
use railfem::oscillators::{compare, fe_run, modal, modal_difference, Case, Histories, Rider};
use std::io::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/moving-oscillators".into());
    std::fs::create_dir_all(&out)?;
    let t1 = 2.0 * std::f64::consts::PI / railfem::pareto::omega(1);
    let mut figure_panels = Vec::new();
    for case in [
        Case::sprung_constant(),
        Case::sprung_braking(),
        Case::rolling_table(),
    ] {
        println!("\n## {}\n", case.name);
        // The reference's convergence: modes and RK4 step on the same 2000-sample grid
        // (the step is h = courant/ω_N).
        let base = modal(&case, 60, 2000, 0.5);
        let fewer = modal(&case, 30, 2000, 0.5);
        let coarser = modal(&case, 60, 2000, 1.0);
        println!(
            "modal: 30 vs 60 modes: midspan {:.2e}, acceleration {:.2e}; RK4 h = 1/ω_N vs 0.5/ω_N: midspan {:.2e}, acceleration {:.2e}",
            modal_difference(&fewer.midspan, &base.midspan),
            modal_difference(&fewer.rider_acc, &base.rider_acc),
            modal_difference(&coarser.midspan, &base.midspan),
            modal_difference(&coarser.rider_acc, &base.rider_acc),
        );
        let more = modal(&case, 120, 2000, 0.5);
        println!(
            "modal: 60 vs 120 modes: midspan {:.2e}, acceleration {:.2e}",
            modal_difference(&base.midspan, &more.midspan),
            modal_difference(&base.rider_acc, &more.rider_acc),
        );
        println!("\n| elements | dt | midspan error | rate | acceleration error | rate |\n|---:|---:|---:|---:|---:|---:|");
        let mut prev: Option<(f64, f64)> = None;
        let mut best: Option<Histories> = None;
        for spp in [40.0, 80.0, 160.0, 320.0, 640.0] {
            let fe = fe_run(&case, 32, t1 / spp)?;
            let (em, ea) = compare(&fe, &base);
            let rate = |e: f64, p: Option<f64>| {
                p.map(|p| format!("{:.2}", (p / e).log2()))
                    .unwrap_or_default()
            };
            println!(
                "| 32 | T1/{spp} | {em:.3e} | {} | {ea:.3e} | {} |",
                rate(em, prev.map(|p| p.0)),
                rate(ea, prev.map(|p| p.1))
            );
            prev = Some((em, ea));
            if spp == 160.0 {
                best = Some(fe);
            }
        }
        println!("\n| elements | dt | midspan error | rate | acceleration error | rate |\n|---:|---:|---:|---:|---:|---:|");
        let mut prev: Option<(f64, f64)> = None;
        for ne in [2, 4, 8, 16, 32] {
            let fe = fe_run(&case, ne, t1 / 1280.0)?;
            let (em, ea) = compare(&fe, &base);
            let rate = |e: f64, p: Option<f64>| {
                p.map(|p| format!("{:.2}", (p / e).log2()))
                    .unwrap_or_default()
            };
            println!(
                "| {ne} | T1/1280 | {em:.3e} | {} | {ea:.3e} | {} |",
                rate(em, prev.map(|p| p.0)),
                rate(ea, prev.map(|p| p.1))
            );
            prev = Some((em, ea));
        }
        let fe = best.expect("run");
        let slug = case.name.replace([' ', ','], "_");
        let mut f = std::fs::File::create(format!("{out}/{slug}.csv"))?;
        writeln!(
            f,
            "t [s],fe_midspan [m],modal_midspan [m],fe_rider_acc [m/s²],modal_rider_acc [m/s²]"
        )?;
        let interp = |h: &Histories, y: &[f64], t: f64| {
            let i = h.t.partition_point(|v| *v <= t).clamp(1, h.t.len() - 1);
            let fr = ((t - h.t[i - 1]) / (h.t[i] - h.t[i - 1])).clamp(0.0, 1.0);
            y[i - 1] * (1.0 - fr) + y[i] * fr
        };
        for (i, &t) in fe.t.iter().enumerate() {
            writeln!(
                f,
                "{t:.6},{:.6e},{:.6e},{:.6e},{:.6e}",
                fe.midspan[i],
                interp(&base, &base.midspan, t),
                fe.rider_acc[i],
                interp(&base, &base.rider_acc, t)
            )?;
        }
        let mm = |v: &[f64]| v.iter().map(|x| x * 1e3).collect::<Vec<f64>>();
        let mut p = Panel::new(
            &format!("{}: midspan deflection", case.name),
            "time t (s)",
            "midspan deflection (mm)",
        );
        p.legend = Corner::BottomRight;
        p = p
            .with(Series::new(
                "modal (60 modes, RK4)",
                base.t.clone(),
                mm(&base.midspan),
                Style::Line,
                "black",
            ))
            .with(Series::new(
                "FE, 32 elements, dt = T1/160",
                fe.t.clone(),
                mm(&fe.midspan),
                Style::Dashed,
                "#d62728",
            ));
        figure_panels.push(p);
        if matches!(case.rider, Rider::Rolling { .. }) {
            // The contact point's acceleration of a rolling mass converges in neither model
            // (docs/moving-oscillators.md): not drawn.
            continue;
        }
        let mut p = Panel::new(
            &format!("{}: rider acceleration", case.name),
            "time t (s)",
            "vertical acceleration (m/s²)",
        );
        p.legend = Corner::TopRight;
        p = p
            .with(Series::new(
                "modal (60 modes, RK4)",
                base.t.clone(),
                base.rider_acc.clone(),
                Style::Line,
                "black",
            ))
            .with(Series::new(
                "FE, 32 elements, dt = T1/160",
                fe.t.clone(),
                fe.rider_acc.clone(),
                Style::Dashed,
                "#d62728",
            ));
        figure_panels.push(p);
    }
    let mut fig = Figure::new();
    for p in figure_panels {
        fig = fig.with(p);
    }
    fig.write_svg(std::path::Path::new(&format!(
        "{out}/moving-oscillators.svg"
    )))?;
    println!("\nwrote {out}/moving-oscillators.svg");
    Ok(())
}
