//! The impact force history of the flat-wheel example (docs/defects.md):
//! `cargo run --release --example flat_wheel_plot -- OUT` after
//! `railfem run examples/models/flat_wheel.toml --out OUT`.
//!
//! Reads `OUT/wheels.csv` (every wheel's outputs; the first two wheels are the front
//! wheelset's left — the flat one — and right), prints each strike's largest and smallest
//! load of the flat wheel, and draws `OUT/flat-wheel.svg` and `.png`: Q against time for
//! both front wheels.

use railfem::framework::plot::{Corner, Figure, Panel, Series, Style};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "out/flat_wheel".into());
    let text = std::fs::read_to_string(format!("{out}/wheels.csv"))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or("wheels.csv is empty")?
        .split(',')
        .collect();
    let q_cols: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| h.ends_with("_Q [N]"))
        .map(|(i, _)| i)
        .take(2)
        .collect();
    if q_cols.len() < 2 {
        return Err("wheels.csv has fewer than two `_Q [N]` columns".into());
    }
    let mut t = Vec::new();
    let mut q = [Vec::new(), Vec::new()];
    for line in lines {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()?;
        t.push(v[0]);
        for (k, &c) in q_cols.iter().enumerate() {
            q[k].push(v[c] / 1e3);
        }
    }
    let q0 = q[0][0];
    println!("static load of the flat wheel {q0:.2} kN");
    // Strikes: stretches where the flat wheel's load leaves ±5 % of the static load.
    let mut strike: Option<(f64, f64, f64, f64)> = None;
    for (i, &x) in q[0].iter().enumerate() {
        let off = (x - q0).abs() > 0.05 * q0;
        match (&mut strike, off) {
            (None, true) => strike = Some((t[i], t[i], x, x)),
            (Some(s), true) => {
                s.1 = t[i];
                s.2 = s.2.max(x);
                s.3 = s.3.min(x);
            }
            (Some(s), false) if t[i] - s.1 > 0.02 => {
                println!(
                    "strike at {:.4}–{:.4} s: largest Q {:.1} kN ({:.2}×static), smallest {:.1} kN",
                    s.0,
                    s.1,
                    s.2,
                    s.2 / q0,
                    s.3
                );
                strike = None;
            }
            _ => {}
        }
    }
    if let Some(s) = strike {
        println!(
            "strike at {:.4}–{:.4} s (to the end): largest Q {:.1} kN, smallest {:.1} kN",
            s.0, s.1, s.2, s.3
        );
    }
    // The first strike, magnified: from 2 ms before the load first leaves ±5 % of the
    // static load to 30 ms after.
    let first = t
        .iter()
        .zip(&q[0])
        .find(|(_, x)| (**x - q0).abs() > 0.05 * q0)
        .map(|(t, _)| *t)
        .unwrap_or(0.0);
    let window: Vec<usize> = (0..t.len())
        .filter(|&i| t[i] >= first - 0.002 && t[i] <= first + 0.03)
        .collect();
    let pick = |v: &[f64]| window.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let ms: Vec<f64> = window.iter().map(|&i| 1e3 * t[i]).collect();
    let mut zoom = Panel::new("the first strike", "time t (ms)", "wheel load Q (kN)");
    zoom.legend = Corner::TopRight;
    zoom = zoom
        .with(Series::new(
            "front left wheel (flat)",
            ms.clone(),
            pick(&q[0]),
            Style::Line,
            "#d62728",
        ))
        .with(Series::new(
            "front right wheel (round)",
            ms,
            pick(&q[1]),
            Style::Dashed,
            "black",
        ));
    let mut p = Panel::new(
        "flat wheel, 25 m/s, sleepered track: wheel loads",
        "time t (s)",
        "wheel load Q (kN)",
    );
    p.legend = Corner::TopLeft;
    p = p
        .with(Series::new(
            "front left wheel (80 mm rounded flat, 0.7 mm deep)",
            t.clone(),
            q[0].clone(),
            Style::Line,
            "#d62728",
        ))
        .with(Series::new(
            "front right wheel (round)",
            t.clone(),
            q[1].clone(),
            Style::Dashed,
            "black",
        ));
    Figure::new()
        .with(p)
        .with(zoom)
        .write_svg_and_png(format!("{out}/flat-wheel.svg"))?;
    println!("wrote {out}/flat-wheel.svg and .png");
    Ok(())
}
