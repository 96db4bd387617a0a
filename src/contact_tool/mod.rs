//! `railfem contact`: the contact of a wheelset on straight track, evaluated without a
//! dynamic run. For each lateral shift `y` of the axle centre and a yaw `ψ`: per wheel, the
//! contact points on wheel and rail, rolling radius, contact angle, the contact's lead
//! ahead of the axle, the wheelset roll and `Δr(y)` (rigid profiles, [`yawed`], which is
//! `railfem_elements::rail::contact::creep::conicity`'s search for a yawed wheelset), Hertz's ellipse
//! (`creep::hertz`),
//! the creepages of steady rolling and the creep forces of the three tangential laws
//! (`creep::law`); the equivalent conicity `λ_e(ŷ)` (EN 15302, harmonic linearisation); a
//! figure of `Δr(y)` and of the contact positions. Outputs: `contact.csv`,
//! `conicity.csv`, `contact.svg` and `.png` (docs/contact-tool.md).
//!
//! What lives elsewhere: the profile pairs and their placement on the track ([`profiles`]),
//! the normal-load balance ([`balance`]), the yawed contact search ([`yawed`]), the
//! Manchester benchmark's reference numbers ([`manchester`]).
//!
//! # Contact mechanics of one wheel (the formulas)
//!
//! - Normal load: from the vertical balance `Q = N cos δ ± Fy(N) sin δ` with the lateral
//!   creep force of a chosen law ([`balance`]), or `N = Q/cos δ` ([`Balance::Vertical`]);
//!   `Q` the vertical wheel load and `δ` the contact angle in the track frame.
//! - Hertz: the wheel's longitudinal radius in the contact's normal plane is `r/cos δ`
//!   (Meusnier's theorem for the surface of revolution), its transverse curvature that of
//!   the profile curve, the rail's longitudinal curvature 0 and its transverse curvature
//!   that of its profile curve, convex positive.
//! - Creepages of steady rolling ([`creepages`]): the wheelset moves at `V` along the
//!   track, turns at the pitch rate `Ω` (`V/r0` unless prescribed) about its axle, which is
//!   yawed by `ψ` and rolled by `φ_r`; `ẏ = 0`. The slip of the wheel's contact point over
//!   the rail, in the contact plane, divided by the mean rolling speed `V̄ = (V + Ωr)/2`
//!   (Kalker's convention, CONTACT's):
//!   to first order `ξx = (V − Ωr cos ψ)/V̄`, `ξy = −Ωr sin ψ/(V̄ cos δ)`,
//!   `φ = ∓Ω(cos ψ cos φ_r sin δ ∓ sin φ_r cos δ)/V̄` (left/right wheel; [`creepages`]
//!   derives the exact forms with the contact's lead).

pub mod balance;
pub mod manchester;
pub mod profiles;
pub mod two_point;
pub mod yawed;

use crate::elements::rail::contact::creep::conicity::{
    equivalent_conicity, secant_conicity, ConicityError, SideContact, WheelsetContact,
    WheelsetGeometry,
};
use crate::elements::rail::contact::creep::dual::D4;
use crate::elements::rail::contact::creep::fastsim::FastsimGrid;
use crate::elements::rail::contact::creep::hertz::{hertz_ellipse, Curvatures, HertzEllipse};
use crate::elements::rail::contact::creep::kalker::kalker_coefficients;
use crate::elements::rail::contact::creep::law::{
    creep_forces, EllipseShape, Material, TangentialLaw, POLACH_DRY,
};
use crate::elements::rail::contact::profiles::Inclination;
use crate::framework::plot::{Figure, Panel, Series, Style};
use crate::framework::FemError;
use profiles::{PlacedProfiles, ProfileSet};
use std::fmt::Write as _;
use std::path::Path;
use two_point::Spring;
use yawed::{Lead, SecondPoint, YawedContact};

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
    /// Yaw angle ψ (rad) at zero shift.
    pub yaw: f64,
    /// Yaw per lateral shift of the axle (rad/m): the yaw at shift `y` is
    /// `yaw + yaw_per_shift·y` (the Manchester benchmark's case A-2.2: 2.4 rad/m).
    pub yaw_per_shift: f64,
    /// Pitch rate of the wheelset Ω (rad/s); `None`: free rolling, `V/r0`.
    pub pitch_rate: Option<f64>,
    /// How the normal load follows from the vertical load.
    pub balance: Balance,
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
            yaw_per_shift: 0.0,
            pitch_rate: None,
            balance: Balance::Creep(CreepLaw::Fastsim),
            load: 50e3,
            speed: 20.0,
            mu: 0.3,
            young: 210e9,
            poisson: 0.28,
        }
    }
}

/// One of the tool's three creep laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CreepLaw {
    /// Kalker's linear theory saturated by Shen–Hedrick–Elkins (`kalker_linear`).
    KalkerLinear,
    /// Polach (2005) with the dry-rail factors and his spin term (`polach`).
    Polach,
    /// FASTSIM on 20 × 20 elements (`fastsim`).
    Fastsim,
}

impl CreepLaw {
    /// The law with the tool's constants.
    pub fn law(self) -> TangentialLaw {
        match self {
            CreepLaw::KalkerLinear => TangentialLaw::KalkerLinear,
            CreepLaw::Polach => TangentialLaw::Polach {
                ka: POLACH_DRY.ka,
                ks: POLACH_DRY.ks,
                a: POLACH_DRY.a,
                b: POLACH_DRY.b,
                spin: true,
            },
            CreepLaw::Fastsim => TangentialLaw::fastsim(FastsimGrid::DEFAULT),
        }
    }
}

/// How a wheel's normal load follows from its vertical load `Q`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Balance {
    /// `N = Q/cos δ`: the creep force carries no share of `Q` (`--balance none`).
    Vertical,
    /// `Q = N cos δ ± Fy sin δ` with the lateral creep force of the law ([`balance`]).
    Creep(CreepLaw),
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
    /// Where the contact lies along the track (yaw).
    pub lead: Lead,
    /// Vertical gap of the rigid profiles at this point (m): 0 for the first patch.
    pub gap: f64,
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
    /// Yaw of the wheelset (rad).
    pub yaw: f64,
    /// Rigid contact geometry (its `shift` is that of the tape-circle level).
    pub contact: WheelsetContact,
    /// Left wheel.
    pub left: Patch,
    /// Right wheel.
    pub right: Patch,
    /// Each wheel's (left, right) second patch of a two-point contact.
    pub second: [Option<Patch>; 2],
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

/// The creepages `[ξx, ξy, φ]` (−, −, 1/m) of one wheel's contact `c` on side `side` (+1
/// left, −1 right) of a wheelset yawed by `yaw` and rolled by `roll` (rad), moving at
/// `speed` and turning at `omega` (rad/s) about its axle, the contact `theta` (rad) ahead
/// of the wheel's bottom ([`yawed`]).
///
/// Derivation (track frame `x` ahead, `y` left, `z` up; wheelset rotation `Rz(ψ)·Rx(φ_r)`).
/// The axle points along `a = (−sin ψ cos φ_r, cos ψ cos φ_r, sin φ_r)`; the contact, at
/// `ρ_w = (r sin θ, l, −r cos θ)` from the wheel's centre in the wheelset frame (`r` the
/// rolling radius), moves at `V·x̂ + Ω·a × ρ = V·x̂ + Ω·R·(ŷ × ρ_w)
/// = V·x̂ − Ω r·R·(cos θ, 0, sin θ)`:
///
/// ```text
/// v = (V − Ωr(cos θ cos ψ + sin θ sin φ_r sin ψ),
///      −Ωr(cos θ sin ψ − sin θ sin φ_r cos ψ),
///      −Ωr sin θ cos φ_r)
/// ```
///
/// The rail is at rest, so `v` is the slip; at the contact of [`yawed`] it is tangent to the
/// surfaces (`v·n = 0` is that module's condition on `θ`). Its components along `x̂` and
/// along the contact plane's lateral axis `t = (0, cos δ, ±sin δ)` (left/right) are `ξx`
/// and `ξy`; for `θ = 0` (no yaw) `v_z = 0`, and for small angles
/// `ξy ≈ −Ωr sin ψ/cos δ`, the classical form. The spin is the wheel's angular velocity
/// about the normal `n = (0, ∓sin δ, cos δ)`: `Ω·a·n = ∓Ω(cos ψ cos φ_r sin δ ∓ sin φ_r
/// cos δ)` (the rail does not turn). All three are divided by the mean rolling speed
/// `V̄ = (V + Ωr)/2` (Kalker, *Three-dimensional elastic bodies in rolling contact*, 1990,
/// §1.3; CONTACT's `VELOC`). With `Ω = V/r0` and small angles these are the creepages of
/// `creep::linear_wheelset` to first order.
pub fn creepages(
    c: &SideContact,
    side: f64,
    speed: f64,
    omega: f64,
    pose: (f64, f64, f64),
) -> [f64; 3] {
    let (yaw, roll, theta) = pose;
    let (cd, sd) = (c.contact_angle.cos(), c.contact_angle.sin());
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = yaw.sin_cos();
    let (sf, cf) = roll.sin_cos();
    let w = omega * c.rolling_radius;
    let mean = 0.5 * (speed + w);
    let vx = speed - w * (ct * cp + st * sf * sp);
    let vy = -w * (ct * sp - st * sf * cp);
    let vz = -w * st * cf;
    [
        vx / mean,
        (vy * cd + side * vz * sd) / mean,
        -side * omega * (cp * cf * sd - side * sf * cd) / mean,
    ]
}

fn balance_error(side: f64, y_axle: f64, delta: f64) -> FemError {
    FemError::input(
        "railfem contact",
        format!(
            "at y = {y_axle} m the {} wheel's lateral creep force pulls it down its flange \
             (δ = {delta:.3} rad) harder than any normal force can lift it: no normal load \
             balances the wheel load; fix: --balance none, or a smaller yaw or --mu",
            if side > 0.0 { "left" } else { "right" }
        ),
    )
}

/// One contact point's mechanics before its normal load is known: curvatures, creepages,
/// and (unless the surfaces conform) Kalker's coefficients of its Hertz ellipse at the load
/// `Q/cos δ`.
struct PointModel {
    c: SideContact,
    lead: Lead,
    creepage: [f64; 3],
    curv: Curvatures,
    /// The ellipse at `Q/cos δ` and its load-independent shape; `None` where `B ≤ 0`.
    hertz: Option<(HertzEllipse, EllipseShape)>,
    mat: Material,
}

impl PointModel {
    fn new(
        case: &ContactCase,
        geom: &WheelsetGeometry,
        c: &SideContact,
        lead: Lead,
        side: f64,
        pose: (f64, f64),
    ) -> Result<Self, FemError> {
        let (yaw, roll) = pose;
        let cd = c.contact_angle.cos();
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
        let omega = case.pitch_rate.unwrap_or(case.speed / case.radius);
        let creepage = creepages(c, side, case.speed, omega, (yaw, roll, lead.theta));
        let n_ref = case.load / cd;
        let hertz = match hertz_ellipse(&curv, n_ref, case.young, case.poisson) {
            Err(_) => None,
            Ok(h) => {
                let coeff = kalker_coefficients(h.a / h.b, case.poisson)
                    .map_err(|e| FemError::input("railfem contact", e.to_string()))?;
                let shape = EllipseShape {
                    n_ref,
                    a_ref: h.a,
                    b_ref: h.b,
                    c: coeff,
                };
                Some((h, shape))
            }
        };
        Ok(PointModel {
            c: *c,
            lead,
            creepage,
            curv,
            hertz,
            mat: Material {
                shear_modulus: case.young / (2.0 * (1.0 + case.poisson)),
                mu: case.mu,
            },
        })
    }

    /// `(Fx, Fy)` of `law` at normal load `n` (zero without an ellipse).
    fn force(&self, case: &ContactCase, law: &TangentialLaw, n: f64) -> (D4, D4) {
        match &self.hertz {
            None => (D4::c(0.0), D4::c(0.0)),
            Some((_, shape)) => {
                let [x, y, sp] = self.creepage;
                creep_forces(law, shape, &self.mat, case.speed, [x, y, sp, n])
            }
        }
    }

    /// The patch at normal load `normal`.
    fn patch(&self, case: &ContactCase, normal: f64, gap: f64) -> Patch {
        let pair = |l: CreepLaw| {
            let (fx, fy) = self.force(case, &l.law(), normal);
            (fx.v, fy.v)
        };
        let hertz = self
            .hertz
            .and_then(|_| hertz_ellipse(&self.curv, normal, case.young, case.poisson).ok());
        Patch {
            geometry: self.c,
            lead: self.lead,
            gap,
            normal,
            hertz,
            creepage: self.creepage,
            forces: hertz.map(|_| LawForces {
                kalker: pair(CreepLaw::KalkerLinear),
                polach: pair(CreepLaw::Polach),
                fastsim: pair(CreepLaw::Fastsim),
            }),
        }
    }
}

/// The law of the balance, `None` for [`Balance::Vertical`].
fn balance_law(case: &ContactCase) -> Option<TangentialLaw> {
    match case.balance {
        Balance::Vertical => None,
        Balance::Creep(l) => Some(l.law()),
    }
}

/// One wheel's patch, or two where a second point of the profiles lies within the elastic
/// approach ([`two_point`]).
fn wheel_patches(
    case: &ContactCase,
    geom: &WheelsetGeometry,
    first: (&SideContact, Lead),
    second: Option<SecondPoint>,
    side: f64,
    pose: (f64, f64, f64),
) -> Result<(Patch, Option<Patch>), FemError> {
    let (y_axle, yaw, roll) = pose;
    let c = first.0;
    let one = PointModel::new(case, geom, c, first.1, side, (yaw, roll))?;
    let law = balance_law(case);
    let lateral = |m: &PointModel, n: f64| {
        law.as_ref().map_or((0.0, 0.0), |l| {
            let fy = m.force(case, l, n).1;
            (fy.v, fy.d[3])
        })
    };
    let n_ref = case.load / c.contact_angle.cos();
    if one.hertz.is_none() {
        return Ok((one.patch(case, n_ref, 0.0), None));
    }
    if let Some(p) = second {
        let two = PointModel::new(case, geom, &p.contact, p.lead, side, (yaw, roll))?;
        if let (Some((h1, _)), Some((h2, _))) = (one.hertz, two.hertz) {
            let n2_ref = case.load / p.contact.contact_angle.cos();
            let springs = [
                Spring::new(c.contact_angle, 0.0, n_ref, &h1, case.young, case.poisson),
                Spring::new(
                    p.contact.contact_angle,
                    p.gap,
                    n2_ref,
                    &h2,
                    case.young,
                    case.poisson,
                ),
            ];
            let models = [&one, &two];
            let n = two_point::share(case.load, side, &springs, |i, n| lateral(models[i], n).0)
                .ok_or_else(|| balance_error(side, y_axle, c.contact_angle))?;
            if n[1] > 0.0 {
                return Ok((
                    one.patch(case, n[0], 0.0),
                    Some(two.patch(case, n[1], p.gap)),
                ));
            }
        }
    }
    let normal = match law {
        None => n_ref,
        Some(_) => balance::normal_load(case.load, c.contact_angle, side, |n| lateral(&one, n))
            .ok_or_else(|| balance_error(side, y_axle, c.contact_angle))?,
    };
    Ok((one.patch(case, normal, 0.0), None))
}

/// Bisection steps of [`contact_at_axle_shift`] (the bracket shrinks to 2⁻⁶⁰ of its width).
const AXLE_SHIFT_STEPS: usize = 60;

/// The rigid contact at the lateral shift `y_axle` (m) of the **axle centre** and yaw
/// `yaw` (rad), found by [`yawed::contact`].
///
/// The conicity module's pose shifts the wheelset's tape-circle level by `y` and rolls it
/// by `φ` about that level; the axle centre, `r0` above it, then stands at
/// `y_axle = y − r0·sin φ·cos ψ` (the pose of [`yawed`] with the point `(0, 0, r0)`).
/// Codes and the Manchester benchmark give the shift of the wheelset centre, which differs
/// from `y` by `r0·φ` — 2 to 5 mm in flange contact, where the roll reaches 4–11 mrad. The
/// root of `g(y) = y − r0·sin φ(y)·cos ψ − y_axle` is bracketed from `y = y_axle` (where
/// `g = −r0 sin φ`, of the sign opposite to the roll's) by steps of 1 mm outward, then
/// bisected. Where `g` is not monotone (a contact jump, `r0·φ' > 1`), the root nearest to
/// `y_axle` is taken.
pub fn contact_at_axle_shift(
    geom: &WheelsetGeometry,
    y_axle: f64,
    yaw: f64,
) -> Result<YawedContact, ConicityError> {
    let r0 = geom.nominal_radius;
    let g = |c: &YawedContact| c.contact.shift - r0 * c.contact.roll.sin() * yaw.cos() - y_axle;
    let mut lo = yawed::contact(geom, y_axle, yaw)?;
    let g_lo = g(&lo);
    if g_lo == 0.0 {
        return Ok(lo);
    }
    let dir = -g_lo.signum();
    let mut hi = lo;
    for k in 1..=40 {
        hi = yawed::contact(geom, y_axle + dir * 1e-3 * k as f64, yaw)?;
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
        let mid = yawed::contact(geom, 0.5 * (lo.contact.shift + hi.contact.shift), yaw)?;
        if g(&mid) * g_lo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if (hi.contact.shift - lo.contact.shift).abs() < 1e-12 {
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
    let yaw = case.yaw + case.yaw_per_shift * y_axle;
    let found = contact_at_axle_shift(geom, y_axle, yaw).map_err(conicity_error)?;
    let contact = found.contact;
    let pose = (y_axle, yaw, contact.roll);
    let [second_l, second_r] = yawed::second_points(geom, &found);
    let (left, left_2) =
        wheel_patches(case, geom, (&contact.left, found.left), second_l, 1.0, pose)?;
    let (right, right_2) = wheel_patches(
        case,
        geom,
        (&contact.right, found.right),
        second_r,
        -1.0,
        pose,
    )?;
    Ok(ShiftResult {
        y_axle,
        yaw,
        contact,
        left,
        right,
        second: [left_2, right_2],
    })
}

/// CSV header of `contact.csv`.
pub const CONTACT_HEADER: &str =
    "y [m],y_tape [m],wheel [-],patch [-],roll [rad],delta_r [m],wheel_y [m],rail_y [m],\
lateral_position [m],rolling_radius [m],contact_angle [rad],N [N],a [m],b [m],xi_x [-],\
xi_y [-],spin [1/m],Fx_kalker [N],Fy_kalker [N],Fx_polach [N],Fy_polach [N],\
Fx_fastsim [N],Fy_fastsim [N],yaw [rad],lead [m],x_contact [m],gap [m]";

/// The rows of `contact.csv`: per shift and wheel one row per patch (`patch` 1, and 2 for
/// the second patch of a two-point contact).
pub fn contact_csv(results: &[ShiftResult]) -> String {
    let mut s = String::from(CONTACT_HEADER);
    s.push('\n');
    for r in results {
        let rows = [
            ("left", 1, Some(&r.left)),
            ("left", 2, r.second[0].as_ref()),
            ("right", 1, Some(&r.right)),
            ("right", 2, r.second[1].as_ref()),
        ];
        for (name, k, p) in rows {
            let Some(p) = p else { continue };
            let g = &p.geometry;
            let (a, b) = p.hertz.map_or((f64::NAN, f64::NAN), |h| (h.a, h.b));
            let nan = (f64::NAN, f64::NAN);
            let f = p
                .forces
                .map_or([nan; 3], |f| [f.kalker, f.polach, f.fastsim]);
            let _ = writeln!(
                s,
                "{},{:.9e},{name},{k},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.6e},{:.6e},{:.6e},\
                 {:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.9e},{:.9e},{:.9e},{:.9e}",
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
                f[2].1,
                r.yaw,
                p.lead.lead,
                p.lead.x,
                p.gap
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
