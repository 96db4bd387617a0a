//! `railfem curve`: the paper's Section 4 case ([`crate::curve`]), FE against theory.

use crate::command::{Command, Context};
use crate::elements::rail::contact::creep::law::Tangential;
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem curve`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct CurveCmd {
    /// Output directory: curve.csv, figures, run.json [default: out/curve].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Arc radius R in m [default: 6250].
    #[arg(value_parser = crate::command::number(), long, value_name = "R")]
    pub radius: Option<f64>,
    /// Cant parameter Ct in m (cant θ = Ct/R, Eq. 21) [default: 200].
    #[arg(value_parser = crate::command::number(), long, value_name = "CT")]
    pub ct: Option<f64>,
    /// Train speed V in m/s [default: 80].
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Wheel-rail friction coefficient μ [default: 0.3].
    #[arg(value_parser = crate::command::number(), long, value_name = "MU")]
    pub mu: Option<f64>,
    /// Time step in s [default: 0.01].
    #[arg(value_parser = crate::command::number(), long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Contact penalty stiffness in N/m [default: 1e10].
    #[arg(value_parser = crate::command::number(), long, value_name = "K")]
    pub penalty: Option<f64>,
    /// Duration in s [default: 0 = the whole track].
    #[arg(value_parser = crate::command::number(), long, value_name = "T")]
    pub duration: Option<f64>,
    /// Write a VTK frame every N steps [default: 0 = none].
    #[arg(value_parser = crate::command::number(), long, value_name = "EVERY")]
    pub vtk: Option<f64>,
    /// The five segment lengths in m: straight, clothoid, arc, clothoid, straight
    /// [default: 500,2000,10908.3078,2000,800].
    #[arg(value_parser = crate::command::text(), long, value_name = "L0,L1,L2,L3,L4")]
    pub lengths: Option<String>,
    /// Short track (60,300,700,300,60 m) for a quick look.
    #[arg(long)]
    pub quick: bool,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(value_parser = crate::command::text(), long, value_name = "linear|nonlinear")]
    pub geometry: Option<String>,
    /// Contact statuses of each step's first Newton iteration: found (the rails are rigid,
    /// nothing to hold) or committed (those of the last converged step) [default: found].
    #[arg(value_parser = crate::command::text(), long, value_name = "found|committed")]
    pub first_active_set: Option<String>,
    /// Anti-roll bar stiffness in N·m/rad [default: 0].
    #[arg(value_parser = crate::command::number(), long, value_name = "K")]
    pub anti_roll: Option<f64>,
    /// Tangential contact law of the wheels: coulomb (the paper's), kalker_linear, polach
    /// or fastsim (rolling-contact creep, docs/creep.md) [default: coulomb].
    #[arg(value_parser = crate::command::text(), long, value_name = "coulomb|kalker_linear|polach|fastsim")]
    pub tangential: Option<String>,
    /// Polach's spin term with `--tangential polach`: off (his 2005 law) or polach_1999 (his
    /// spin-corrected lateral creepage and force, docs/creep.md) [default: off].
    #[arg(value_parser = crate::command::text(), long, value_name = "off|polach_1999")]
    pub polach_spin: Option<String>,
    /// Assess the wheel forces afterwards with the defaults of `railfem assess`.
    #[arg(long)]
    pub assess: bool,
}

impl Command for CurveCmd {
    const NAME: &'static str = "curve";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/curve")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let mut case = crate::curve::CurveCase::default();
        let set = |x: &mut f64, v: Option<f64>| {
            if let Some(v) = v {
                *x = v;
            }
        };
        set(&mut case.radius, self.radius);
        set(&mut case.ct, self.ct);
        set(&mut case.speed, self.speed);
        set(&mut case.mu, self.mu);
        set(&mut case.dt, self.dt);
        set(&mut case.penalty, self.penalty);
        set(&mut case.duration, self.duration);
        if let Some(v) = self.vtk {
            case.vtk_every = v as usize;
        }
        set(&mut case.anti_roll, self.anti_roll);
        if let Some(l) = &self.lengths {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            if v.len() != 5 || v.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(FemError::input(
                    "command line",
                    format!("--lengths {l}: give five positive lengths in m, comma-separated"),
                ));
            }
            case.lengths = [v[0], v[1], v[2], v[3], v[4]];
        }
        if self.quick {
            case.lengths = [60.0, 300.0, 700.0, 300.0, 60.0];
        }
        if let Some(t) = &self.tangential {
            case.tangential = crate::choice::parse("command line", "--tangential", t)?;
        }
        case.polach_spin =
            crate::command::polach_spin(self.polach_spin.as_deref(), case.tangential)?;
        case.geometry = crate::command::geometry(self.geometry.as_deref())?;
        case.first_active_set = crate::command::first_active_set(
            self.first_active_set.as_deref(),
            case.first_active_set,
        )?;
        let out = ctx.out();
        let steps = case.steps_estimate();
        let mut bar = crate::progress::Progress::new("curve", steps, "steps");
        let r = crate::curve::run(&case, Some(out), &mut |f| bar.fraction(f))?;
        bar.finish();
        println!(
            "curve: R = {} m, Ct = {} m, V = {} m/s, mu = {}, dt = {} s{}: {} steps, {} Newton iterations, {:.2} s",
            case.radius, case.ct, case.speed, case.mu, case.dt,
            if case.tangential == Tangential::Coulomb { String::new() } else { format!(", tangential {}", case.tangential.name()) },
            r.steps, r.iterations, r.wall
        );
        println!(
            "on the arc, largest relative difference FE vs theory: normal vs statics {:.3e}, axle shear vs Eq. 26 {:.3e} (single wheel {:.3e}); normal vs Eq. 25 as printed {:.3e}",
            r.max_rel_normal_statics, r.max_rel_shear, r.max_rel_shear_wheel, r.max_rel_normal_printed
        );
        println!(
            "statics with body lean (quasi-static reference): normal FE vs reference {:.3e}; settled-arc mean FE normal inner {:.1} N, outer {:.1} N (geometry {})",
            r.max_rel_normal_lean,
            r.arc_mean_normal[0],
            r.arc_mean_normal[1],
            case.geometry.name()
        );
        let arc = crate::elements::rail::vehicle::lean::ArcPoint {
            speed: case.speed,
            curvature: 1.0 / case.radius,
            cant: case.ct / case.radius,
            gravity: case.gravity,
            spacing: r.contact_spacing,
            pivot: None,
        };
        if let Some(l) = crate::elements::rail::vehicle::lean::wheel_loads(&case.carriage(), &arc) {
            let (c, b) = (l.state.car_body, l.state.bogie);
            println!(
                "lean reference on the arc: car body lateral {:.4} m, vertical {:.4} m, roll {:.5} rad; bogie {:.4} m, {:.4} m, {:.5} rad; wheel loads inner {:.1} N, outer {:.1} N (statics {:.1} N, {:.1} N)",
                c[0], c[1], c[2], b[0], b[1], b[2], l.lean[0], l.lean[1], l.rigid[0], l.rigid[1]
            );
        }
        println!(
            "contact spacing used by the statics: {:.4} m; results in {}",
            r.contact_spacing,
            out.display()
        );
        if let Some(e) = &r.energy_summary {
            println!("{e}");
        }
        if self.assess {
            crate::assess::after_run(out, None)?;
        }
        Ok(0)
    }
}
