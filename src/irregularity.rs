//! `railfem irregularity`: generates a track irregularity from a standard spectrum and
//! checks it — the profile as CSV (`irregularity.csv`, mm), its Welch PSD beside the
//! target (`psd.csv`) and a plot of both (`irregularity-psd.svg`, log10 values on linear
//! axes: the plot writer has no logarithmic axes).

use crate::elements::rail::geometry::irregularity::csv::{write_table, IrregularityTable};
use crate::elements::rail::geometry::irregularity::generate::{welch, PsdRequest};
use crate::elements::rail::geometry::irregularity::psd::{band_variance, Component};
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
    let part = crate::elements::rail::geometry::irregularity::generate_part(req, 0.0, components)
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
