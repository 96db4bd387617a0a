//! `railfem contact`: the contact of a wheelset on straight track, evaluated without a
//! dynamic run. For each lateral shift `y` of the axle centre (and a yaw `ψ`): per wheel, the contact points on
//! wheel and rail, rolling radius, contact angle, the wheelset roll and `Δr(y)` (rigid
//! profiles, `railfem_elements::rail::creep::conicity`), Hertz's ellipse (`creep::hertz`),
//! the creepages of steady rolling and the creep forces of the three tangential laws
//! (`creep::law`); the equivalent conicity `λ_e(ŷ)` (EN 15302, harmonic linearisation); a
//! figure of `Δr(y)` and of the contact positions. Outputs: `contact.csv`,
//! `conicity.csv`, `contact.svg` and `.png` (docs/contact-tool.md).
//!
//! What lives elsewhere: the profile pairs and their placement on the track ([`profiles`]).
//!
//! # Contact mechanics of one wheel (the formulas)
//!
//! - Normal load: `N = Q/cos δ`, `Q` the vertical wheel load and `δ` the contact angle (the
//!   vertical component of the lateral creep force is left out; docs/contact-tool.md
//!   shows its size).
//! - Hertz: the wheel's longitudinal radius in the contact's normal plane is `r/cos δ`
//!   (Meusnier's theorem for the surface of revolution), its transverse curvature that of
//!   the profile curve, the rail's longitudinal curvature 0 and its transverse curvature
//!   that of its profile curve, convex positive.
//! - Creepages of steady rolling at speed `V` with the wheelset turning at `V/r0` (no
//!   traction), yaw `ψ` and `ẏ = 0`, in the contact plane (the nonlinear form of the
//!   linear-wheelset creepages of `creep::linear_wheelset`):
//!   `ξx = (r0 − r)/r0`, `ξy = −ψ/cos δ`, `φ = ∓sin δ/r` (left/right wheel).

pub mod manchester;
pub mod profiles;

use crate::elements::rail::creep::conicity::{
    equivalent_conicity, secant_conicity, ConicityError, SideContact, WheelsetContact,
    WheelsetGeometry,
};
use crate::elements::rail::creep::fastsim::FastsimGrid;
use crate::elements::rail::creep::hertz::{hertz_ellipse, Curvatures, HertzEllipse};
use crate::elements::rail::creep::kalker::kalker_coefficients;
use crate::elements::rail::creep::law::{
    creep_forces, EllipseShape, Material, TangentialLaw, POLACH_DRY,
};
use crate::elements::rail::profiles::Inclination;
use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use profiles::{PlacedProfiles, ProfileSet};
use std::fmt::Write as _;
use std::path::Path;

/// Amplitudes (m) at which `conicity.csv` gives `λ_e`: 1 … 8 mm (EN 15302 quotes 3 mm).
pub const CONICITY_AMPLITUDES_MM: [f64; 8] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0];

/// A wheelset on a track and its operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactCase {
    /// Profiles.
    pub profiles: ProfileSet,
    /// Track gauge (m).
    pub gauge: f64,
    /// Back-to-back distance of the wheels (m).
    pub back_to_back: f64,
    /// Nominal rolling radius r0 (m).
    pub radius: f64,
    /// Yaw angle ψ (rad).
    pub yaw: f64,
    /// Vertical load on each wheel Q (N).
    pub load: f64,
    /// Speed V (m/s).
    pub speed: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Young's modulus of wheel and rail (Pa).
    pub young: f64,
    /// Poisson's ratio of wheel and rail.
    pub poisson: f64,
}

impl Default for ContactCase {
    fn default() -> Self {
        Self {
            profiles: ProfileSet::S1002On60E1(Inclination::OneIn40),
            gauge: 1.435,
            back_to_back: 1.360,
            radius: 0.46,
            yaw: 0.0,
            load: 50e3,
            speed: 20.0,
            mu: 0.3,
            young: 210e9,
            poisson: 0.28,
        }
    }
}

/// Creep forces `(Fx, Fy)` (N) on the wheel, in the contact plane, of the three laws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawForces {
    /// Kalker's linear theory saturated by Shen–Hedrick–Elkins.
    pub kalker: (f64, f64),
    /// Polach (2005), dry-rail reduction factors, with spin.
    pub polach: (f64, f64),
    /// FASTSIM on 20 × 20 elements.
    pub fastsim: (f64, f64),
}

/// One wheel's contact patch at one shift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// The geometric contact.
    pub geometry: SideContact,
    /// Normal load N (N).
    pub normal: f64,
    /// Hertz's ellipse, `None` where the surfaces conform (`B ≤ 0`).
    pub hertz: Option<HertzEllipse>,
    /// Creepages `ξx`, `ξy` (−) and spin `φ` (1/m).
    pub creepage: [f64; 3],
    /// Creep forces, `None` without an ellipse.
    pub forces: Option<LawForces>,
}

/// The wheelset at one shift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShiftResult {
    /// Lateral shift of the axle centre (m).
    pub y_axle: f64,
    /// Rigid contact geometry (its `shift` is that of the tape-circle level).
    pub contact: WheelsetContact,
    /// Left wheel.
    pub left: Patch,
    /// Right wheel.
    pub right: Patch,
}

/// The wheelset geometry of `case` with its profiles.
pub fn geometry(case: &ContactCase) -> Result<(WheelsetGeometry, PlacedProfiles), FemError> {
    let placed = case.profiles.load()?;
    let g = WheelsetGeometry::new(
        placed.wheel.clone(),
        &placed.rail,
        0.5 * case.back_to_back + placed.flange_back,
        0.5 * case.gauge - placed.gauge_y,
        case.radius,
    )
    .map_err(conicity_error)?;
    Ok((g, placed))
}

fn conicity_error(e: ConicityError) -> FemError {
    let message = match e {
        ConicityError::NoOverlap { side, shift } => format!(
            "at a lateral shift of {shift} m the {side} wheel has no point over its rail; \
             fix: a smaller --y or --y-max, or check --gauge and --back-to-back"
        ),
        e => e.to_string(),
    };
    FemError::input("railfem contact", message)
}

/// Signed curvature (1/m) of a plane curve with first and second derivatives `d`, `dd`:
/// `(x'y'' − y'x'')/|r'|³`, positive when it turns counter-clockwise.
fn curvature(d: nalgebra::Vector2<f64>, dd: nalgebra::Vector2<f64>) -> f64 {
    (d.x * dd.y - d.y * dd.x) / d.norm().powi(3)
}

fn patch(
    case: &ContactCase,
    geom: &WheelsetGeometry,
    c: &SideContact,
    side: f64,
) -> Result<Patch, FemError> {
    let (cd, sd) = (c.contact_angle.cos(), c.contact_angle.sin());
    let normal = case.load / cd;
    let spline = geom.wheel.spline();
    // The wheel is traversed towards the field side with its material above: a tread
    // convex towards the rail turns counter-clockwise.
    let kw = curvature(
        spline.derivative(c.wheel_t),
        spline.second_derivative(c.wheel_t),
    );
    let rail = geom.rail_surface();
    let (dz, ddz) = (rail.derivative(c.rail_y), rail.second_derivative(c.rail_y));
    let kr = -ddz / (1.0 + dz * dz).powf(1.5);
    let curv = Curvatures {
        wheel_rolling_radius: c.rolling_radius / cd,
        wheel_transverse: kw,
        rail_transverse: kr,
    };
    let creepage = [
        (case.radius - c.rolling_radius) / case.radius,
        -case.yaw / cd,
        -side * sd / c.rolling_radius,
    ];
    let hertz = hertz_ellipse(&curv, normal, case.young, case.poisson).ok();
    let forces = match hertz {
        None => None,
        Some(h) => {
            let coeff = kalker_coefficients(h.a / h.b, case.poisson)
                .map_err(|e| FemError::input("railfem contact", e.to_string()))?;
            let shape = EllipseShape {
                n_ref: normal,
                a_ref: h.a,
                b_ref: h.b,
                c: coeff,
            };
            let mat = Material {
                shear_modulus: case.young / (2.0 * (1.0 + case.poisson)),
                mu: case.mu,
            };
            let input = [creepage[0], creepage[1], creepage[2], normal];
            let f = |law: &TangentialLaw| {
                let (fx, fy) = creep_forces(law, &shape, &mat, case.speed, input);
                (fx.v, fy.v)
            };
            Some(LawForces {
                kalker: f(&TangentialLaw::KalkerLinear),
                polach: f(&TangentialLaw::Polach {
                    ka: POLACH_DRY.ka,
                    ks: POLACH_DRY.ks,
                    a: POLACH_DRY.a,
                    b: POLACH_DRY.b,
                    spin: true,
                }),
                fastsim: f(&TangentialLaw::fastsim(FastsimGrid::DEFAULT)),
            })
        }
    };
    Ok(Patch {
        geometry: *c,
        normal,
        hertz,
        creepage,
        forces,
    })
}

/// Bisection steps of [`contact_at_axle_shift`] (the bracket shrinks to 2⁻⁶⁰ of its width).
const AXLE_SHIFT_STEPS: usize = 60;

/// The rigid contact at the lateral shift `y_axle` (m) of the **axle centre**.
///
/// The conicity module's pose shifts the wheelset's tape-circle level by `y` and rolls it
/// by `φ` about that level; the axle centre, `r0` above it, then stands at
/// `y_axle = y − r0·sin φ` (pose formula of `creep::conicity` with `(Y, Z) = (0, r0)`).
/// Codes and the Manchester benchmark give the shift of the wheelset centre, which differs
/// from `y` by `r0·φ` — 2 to 5 mm in flange contact, where the roll reaches 4–11 mrad. The
/// root of `g(y) = y − r0·sin φ(y) − y_axle` is bracketed from `y = y_axle` (where
/// `g = −r0 sin φ`, of the sign opposite to the roll's) by steps of 1 mm outward, then
/// bisected. Where `g` is not monotone (a contact jump, `r0·φ' > 1`), the root nearest to
/// `y_axle` is taken.
pub fn contact_at_axle_shift(
    geom: &WheelsetGeometry,
    y_axle: f64,
) -> Result<WheelsetContact, ConicityError> {
    let r0 = geom.nominal_radius;
    let g = |c: &WheelsetContact| c.shift - r0 * c.roll.sin() - y_axle;
    let mut lo = geom.contact(y_axle)?;
    let g_lo = g(&lo);
    if g_lo == 0.0 {
        return Ok(lo);
    }
    let dir = -g_lo.signum();
    let mut hi = lo;
    for k in 1..=40 {
        hi = geom.contact(y_axle + dir * 1e-3 * k as f64)?;
        if g(&hi) * g_lo <= 0.0 {
            break;
        }
        lo = hi;
    }
    if g(&hi) * g_lo > 0.0 {
        return Err(ConicityError::NotConverged {
            shift: y_axle,
            gap_left: g(&hi),
            gap_right: g_lo,
        });
    }
    for _ in 0..AXLE_SHIFT_STEPS {
        let mid = geom.contact(0.5 * (lo.shift + hi.shift))?;
        if g(&mid) * g_lo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if (hi.shift - lo.shift).abs() < 1e-12 {
            break;
        }
    }
    Ok(if g(&lo).abs() < g(&hi).abs() { lo } else { hi })
}

/// The wheelset at the axle-centre shift `y_axle` (m, positive to the left).
pub fn evaluate(
    case: &ContactCase,
    geom: &WheelsetGeometry,
    y_axle: f64,
) -> Result<ShiftResult, FemError> {
    let contact = contact_at_axle_shift(geom, y_axle).map_err(conicity_error)?;
    Ok(ShiftResult {
        y_axle,
        contact,
        left: patch(case, geom, &contact.left, 1.0)?,
        right: patch(case, geom, &contact.right, -1.0)?,
    })
}

/// CSV header of `contact.csv`.
pub const CONTACT_HEADER: &str =
    "y [m],y_tape [m],wheel [-],roll [rad],delta_r [m],wheel_y [m],rail_y [m],\
lateral_position [m],rolling_radius [m],contact_angle [rad],N [N],a [m],b [m],xi_x [-],\
xi_y [-],spin [1/m],Fx_kalker [N],Fy_kalker [N],Fx_polach [N],Fy_polach [N],\
Fx_fastsim [N],Fy_fastsim [N]";

/// The rows of `contact.csv`.
pub fn contact_csv(results: &[ShiftResult]) -> String {
    let mut s = String::from(CONTACT_HEADER);
    s.push('\n');
    for r in results {
        for (name, p) in [("left", &r.left), ("right", &r.right)] {
            let g = &p.geometry;
            let (a, b) = p.hertz.map_or((f64::NAN, f64::NAN), |h| (h.a, h.b));
            let nan = (f64::NAN, f64::NAN);
            let f = p
                .forces
                .map_or([nan; 3], |f| [f.kalker, f.polach, f.fastsim]);
            let _ = writeln!(
                s,
                "{},{:.9e},{name},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6e},\
                 {:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
                r.y_axle,
                r.contact.shift,
                r.contact.roll,
                r.contact.delta_r(),
                g.wheel_y,
                g.rail_y,
                g.lateral_position,
                g.rolling_radius,
                g.contact_angle,
                p.normal,
                a,
                b,
                p.creepage[0],
                p.creepage[1],
                p.creepage[2],
                f[0].0,
                f[0].1,
                f[1].0,
                f[1].1,
                f[2].0,
                f[2].1
            );
        }
    }
    s
}

/// The figure: `Δr(y)`, and the contact positions on wheel and rail over `y` (mm).
pub fn figure(results: &[ShiftResult]) -> Figure {
    let y: Vec<f64> = results.iter().map(|r| r.y_axle * 1e3).collect();
    let col = |f: &dyn Fn(&ShiftResult) -> f64| results.iter().map(|r| f(r) * 1e3).collect();
    Figure::new()
        .with(
            Panel::new(
                "Rolling-radius difference",
                "lateral shift of the axle y [mm]",
                "Δr = r_L − r_R [mm]",
            )
            .with(Series::new(
                "Δr",
                y.clone(),
                col(&|r| r.contact.delta_r()),
                Style::Line,
                "#1f77b4",
            )),
        )
        .with(
            Panel::new(
                "Contact positions (profile coordinates, + towards the field side)",
                "lateral shift of the axle y [mm]",
                "position [mm]",
            )
            .with(Series::new(
                "left wheel",
                y.clone(),
                col(&|r| r.left.geometry.wheel_y),
                Style::Line,
                "#1f77b4",
            ))
            .with(Series::new(
                "right wheel",
                y.clone(),
                col(&|r| r.right.geometry.wheel_y),
                Style::Dashed,
                "#1f77b4",
            ))
            .with(Series::new(
                "left rail",
                y.clone(),
                col(&|r| r.left.geometry.rail_y),
                Style::Line,
                "#d62728",
            ))
            .with(Series::new(
                "right rail",
                y,
                col(&|r| r.right.geometry.rail_y),
                Style::Dashed,
                "#d62728",
            )),
        )
}

/// The shifts of a sweep `0, step, …, y_max` (both signs of `y_max` allowed).
pub fn sweep(y_max: f64, step: f64) -> Vec<f64> {
    let n = (y_max.abs() / step).round() as usize;
    (0..=n)
        .map(|k| (k as f64 * step).min(y_max.abs()) * y_max.signum())
        .collect()
}

/// `railfem contact`'s outputs: the contact of `case` at each lateral shift of `shifts`
/// (m), written into `out` as `contact.csv`, `conicity.csv` and (for a sweep) `contact.svg`.
pub fn write_shifts(case: &ContactCase, shifts: &[f64], out: &Path) -> Result<(), FemError> {
    let (geom, _) = geometry(case)?;
    let results = shifts
        .iter()
        .map(|&y| evaluate(case, &geom, y))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    write(&out.join("contact.csv"), &contact_csv(&results))?;
    let mut con = String::from("amplitude [m],lambda_e [-],secant [-]\n");
    for amp in CONICITY_AMPLITUDES_MM.map(|v| v * 1e-3) {
        let le = equivalent_conicity(&geom, amp).map_err(conicity_error)?;
        let ls = secant_conicity(&geom, amp).map_err(conicity_error)?;
        let _ = writeln!(con, "{amp},{le:.6},{ls:.6}");
        if amp == 3e-3 {
            println!("equivalent conicity λ_e(3 mm) = {le:.4} (EN 15302 amplitude)");
        }
    }
    write(&out.join("conicity.csv"), &con)?;
    if results.len() > 1 {
        figure(&results)
            .write_svg_and_png(out.join("contact.svg"))
            .map_err(|e| FemError::output(out.join("contact.svg"), e))?;
    }
    println!(
        "{} shifts: contact.csv, conicity.csv{} in {}",
        results.len(),
        if results.len() > 1 {
            ", contact.svg"
        } else {
            ""
        },
        out.display()
    );
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<(), FemError> {
    std::fs::write(path, text).map_err(|e| FemError::output(path, e))
}
