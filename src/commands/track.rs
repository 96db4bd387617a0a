//! `railfem track`: the paper's five-segment track with arc radius `--radius` and cant θ = Ct/R, written as `track.csv` and `track.svg`.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem track`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct TrackCmd {
    /// Arc radius R in m [default: 6250].
    #[arg(value_parser = crate::command::number(), long, value_name = "R")]
    pub radius: Option<f64>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(value_parser = crate::command::number(), long, value_name = "CT")]
    pub ct: Option<f64>,
    /// Output directory [default: out/track].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

impl Command for TrackCmd {
    const NAME: &'static str = "track";
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/track")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        use crate::elements::rail::geometry::cant::Track;
        let radius = self.radius.unwrap_or(6250.0);
        let ct = self.ct.unwrap_or(200.0);
        let min = crate::elements::rail::geometry::alignment::MIN_RADIUS;
        if radius < min {
            return Err(FemError::input(
                "command line",
                format!("--radius {radius}: give the arc radius in m, ≥ {min} (the tightest curve a wheelset can take)"),
            ));
        }
        if ct < 0.0 || ct / radius >= std::f64::consts::FRAC_PI_2 {
            return Err(FemError::input(
                "command line",
                format!("--ct {ct}: give Ct in m, >= 0 and below R·π/2 (θ = Ct/R, Eq. 21)"),
            ));
        }
        let out = ctx.out();
        let t = Track::paper(radius, ct);
        crate::elements::rail::geometry::railline::write_track_report(&t, out)
            .map_err(|e| FemError::output(out, e))?;
        println!(
            "track: R = {radius} m, Ct = {ct} m (θ = {:.6} rad on the arc), {:.4} m long; track.csv and track.svg in {}",
            ct / radius,
            t.alignment.length(),
            out.display()
        );
        Ok(0)
    }
}
