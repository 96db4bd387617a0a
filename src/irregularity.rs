//! `railfem irregularity`: generates a track irregularity from a standard spectrum and
//! checks it — the profile as CSV (`irregularity.csv`, mm), its Welch PSD beside the
//! target (`psd.csv`) and a plot of both (`irregularity-psd.svg`, log10 values on linear
//! axes: the plot writer has no logarithmic axes).

use crate::elements::rail::irregularity::csv::{write_table, IrregularityTable};
use crate::elements::rail::irregularity::generate::{welch, PsdRequest};
use crate::elements::rail::irregularity::psd::{band_variance, Component, PsdClass};
use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

/// What one component came out as.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentReport {
    /// The component.
    pub component: Component,
    /// RMS of the generated profile (m).
    pub rms: f64,
    /// √(∫ S dΩ) over the band (m).
    pub target_rms: f64,
}

/// The Welch segment (samples) for `n` samples: the largest power of two ≤ n/4, so that
/// at least seven half-overlapping segments are averaged.
pub fn segment_for(n: usize) -> usize {
    let q = (n / 4).max(8);
    1usize << (usize::BITS - 1 - q.leading_zeros())
}

/// Generates `components` of `req`, writes the three files into `out` and returns the
/// RMS of each against its target.
pub fn run(
    req: &PsdRequest,
    components: &[Component],
    out: &Path,
) -> Result<Vec<ComponentReport>, FemError> {
    let cl = "command line";
    let part = crate::elements::rail::irregularity::generate_part(req, 0.0, components)
        .map_err(|m| FemError::input(cl, m))?;
    let table: IrregularityTable = part.table();
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let csv_path = out.join("irregularity.csv");
    std::fs::write(&csv_path, write_table(&table)).map_err(|e| FemError::output(&csv_path, e))?;
    crate::framework::interrupt::check_after(|| {
        "irregularity.csv (psd.csv and the figure not written)".into()
    })?;
    let h = req.step;
    let seg = segment_for(table.stations.len());
    let [lmin, lmax] = req.wavelengths;
    let (wlo, whi) = (2.0 * PI / lmax, 2.0 * PI / lmin);
    let mut fig = Figure::new();
    let mut psd_csv =
        String::from("component [-],omega [rad/m],welch [m²/(rad/m)],target [m²/(rad/m)]\n");
    let mut reports = Vec::new();
    for (c, z) in &table.columns {
        let rms = (z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64).sqrt();
        let target_rms = band_variance(req.class, *c, wlo, whi).sqrt();
        reports.push(ComponentReport {
            component: *c,
            rms,
            target_rms,
        });
        let Some((om, s)) = welch(z, h, seg) else {
            continue;
        };
        let (mut x, mut yw, mut yt) = (Vec::new(), Vec::new(), Vec::new());
        for (w, v) in om.iter().zip(&s) {
            if *w < wlo || *w > whi {
                continue;
            }
            let t = req.class.density(*c, *w).unwrap_or(f64::NAN);
            let _ = writeln!(psd_csv, "{},{w},{v},{t}", c.name());
            x.push(*w);
            yw.push(*v);
            yt.push(t);
        }
        fig = fig.with(
            Panel::new(
                &format!(
                    "{} {}: RMS {:.3} mm (target {:.3} mm), Welch over {} m segments",
                    req.class.name(),
                    c.name(),
                    rms * 1e3,
                    target_rms * 1e3,
                    seg as f64 * h
                ),
                "spatial frequency Ω (rad/m)",
                "PSD S (m²/(rad/m))",
            )
            .log_log()
            .with(Series::new(
                "Welch estimate",
                x.clone(),
                yw,
                Style::Line,
                "#1f77b4",
            ))
            .with(Series::new("target PSD", x, yt, Style::Dashed, "black")),
        );
    }
    let p = out.join("psd.csv");
    std::fs::write(&p, psd_csv).map_err(|e| FemError::output(&p, e))?;
    let p = out.join("irregularity-psd.svg");
    fig.write_svg_and_png(&p)
        .map_err(|e| FemError::output(&p, e))?;
    Ok(reports)
}

/// Parses a list `a,b` of numbers for `--key`.
fn pair(key: &str, v: &str) -> Result<[f64; 2], FemError> {
    let nums: Option<Vec<f64>> = v.split(',').map(|x| x.trim().parse().ok()).collect();
    match nums.as_deref() {
        Some([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        _ => Err(FemError::input(
            "command line",
            format!("--{key} {v}: give two numbers `λmin,λmax` in m, e.g. 1,50"),
        )),
    }
}

/// The command: options parsed from `args` (see `railfem help`).
pub fn command(a: &crate::args::Args) -> Result<i32, FemError> {
    let cl = "command line";
    let name = a.opt("psd").ok_or_else(|| {
        FemError::input(
            cl,
            format!(
                "`railfem irregularity` needs --psd CLASS; the spectra are: {}",
                PsdClass::NAMES.join(", ")
            ),
        )
    })?;
    let class = PsdClass::parse(name).ok_or_else(|| {
        FemError::input(
            cl,
            format!(
                "--psd {name} is not offered; the spectra are: {}",
                PsdClass::NAMES.join(", ")
            ),
        )
    })?;
    let seed = match a.opt("seed") {
        None => 1,
        Some(v) => v
            .parse::<u64>()
            .map_err(|_| FemError::input(cl, format!("--seed {v}: give an integer ≥ 0")))?,
    };
    let wavelengths = match a.opt("wavelengths") {
        None => [1.0, 50.0],
        Some(v) => pair("wavelengths", v)?,
    };
    let req = PsdRequest {
        class,
        seed,
        wavelengths,
        step: a.num("step")?.unwrap_or(wavelengths[0] / 8.0),
        length: a.num("length")?.unwrap_or(2000.0),
    };
    req.validate().map_err(|m| {
        // The checks name the model-file keys; here they are options.
        let m = ["wavelengths", "step", "length"]
            .iter()
            .fold(m, |m, k| m.replace(&format!("`{k}`"), &format!("--{k}")));
        FemError::input(cl, m)
    })?;
    let components = match a.opt("components") {
        None => class.components().to_vec(),
        Some(list) => {
            let mut out = Vec::new();
            for n in list.split(',') {
                let c = Component::parse(n)
                    .filter(|c| class.components().contains(c))
                    .ok_or_else(|| {
                        FemError::input(
                            cl,
                            format!(
                                "--components: `{n}` is not given by {}; choose from {}",
                                class.name(),
                                class
                                    .components()
                                    .iter()
                                    .map(|c| c.name())
                                    .collect::<Vec<_>>()
                                    .join(",")
                            ),
                        )
                    })?;
                if !out.contains(&c) {
                    out.push(c);
                }
            }
            out
        }
    };
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| std::path::PathBuf::from("out/irregularity"));
    let reports = run(&req, &components, &out)?;
    for r in &reports {
        println!(
            "{} {}: RMS {:.4} mm, target √∫S dΩ = {:.4} mm ({:+.2} %)",
            class.name(),
            r.component.name(),
            r.rms * 1e3,
            r.target_rms * 1e3,
            (r.rms / r.target_rms - 1.0) * 100.0
        );
    }
    println!(
        "irregularity.csv, psd.csv and irregularity-psd.svg in {}",
        out.display()
    );
    Ok(0)
}
