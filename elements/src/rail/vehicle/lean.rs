//! Quasi-static wheel loads of a carriage on a canted arc **with body lean**: the rigid-body
//! statics of the paper's Section 3 (Eqs. 21–26) extended by the displaced positions of the
//! car body and the bogies on their suspensions. An independent reference for the
//! finite element model in nonlinear geometry; it shares only the carriage data and the
//! spring law with it.
//!
//! # Derivation
//!
//! Work in the cross-section plane of the wheel frame (axis 1 lateral, positive towards
//! the left rail, the inner one on a left-hand curve; axis 2 normal to the rail-top plane;
//! moments about axis 3, positive from 1 to 2: the moment of a force `(F1, F2)` at `(y, z)`
//! is `y·F2 − z·F1`). On a steady arc a carriage is symmetric fore and aft, so both bogies
//! and all four wheelsets are in the same state and the problem is planar.
//!
//! *Bodies.* Car body `c`, bogie `b` (two), wheelset `w` (four) with mass centres at
//! `(0, H_i)` in the state the data describe (loaded ride heights on straight, level
//! track). Each carries the load of Eqs. 22–23 at its mass centre, `F1_i = W_i sinθ −
//! m_i V²cosθ/R`, `F2_i = −W_i cosθ − m_i V² sinθ/R` (gravity and Eq. 5's centrifugal
//! term). The car body and the bogie move by `(y_i, v_i, φ_i)` (lateral, vertical, roll);
//! the wheelsets stay on the rails (their contact deflections are micrometres).
//!
//! *Springs.* A suspension between a lower body `L` and an upper body `U` sits at
//! `(λ, h)` (λ = ± semi-span, h its height). With `Q(φ)` the plane rotation, its seats are
//! `p_L = x_L + Q(φ_L)·(λ, h − H_L)` and `p_U = x_U + Q(φ_U)·(λ, h − H_U)`, its deflection
//! in the lower body's axes `d = Q(φ_L)ᵀ·(p_U − p_L)`, its force in those axes
//! `g = (k_y·d₁, k_z·d₂ − P)` with `P` the static preload (the share of the weight above
//! it on straight, level track: `P₂ = m_c·g/4` per secondary, `P₁ = (m_c + 2m_b)·g/8` per
//! axle box) and `G = Q(φ_L)·g`. The spring pushes the upper body with `−G` and the lower
//! one with `+G`, both along one line through `p_U` (that is what makes a spring whose
//! seats have separated balance moments; it is the law of the `suspension` element). An
//! anti-roll bar adds the moment `−k_r·(φ_c − φ_b)` on the car body and its opposite on
//! the bogie.
//!
//! *Equilibrium.* Car body (four secondaries) and one bogie (two secondaries above, four
//! axle boxes below): force and moment balance of each, six equations in
//! `(y_c, v_c, φ_c, y_b, v_b, φ_b)`, solved by Newton's method with a central-difference
//! Jacobian to `|residual| < 1e-10·W`.
//!
//! *Wheel loads.* The internal forces of every spring cancel in force and moment, so the
//! moment balance of the whole carriage about the track centre line at rail-top level
//! involves only the body loads at their displaced mass centres and the contact forces:
//! the normal loads `Q_in` at `+a`, `Q_out` at `−a` (`2a` the contact spacing) and the
//! lateral forces at rail-top level (no moment). With four identical wheelsets,
//!
//! `Q_in + Q_out = −Σ n_i·F2_i / 4`,  `Q_in − Q_out = Σ n_i·(z_i·F1_i − y_i·F2_i) / (4a)`,
//!
//! `n = (1, 2, 4)`, `z_i = H_i + v_i`. With `y = v = 0` this is the rigid-body statics of
//! [`crate::rail::vehicle::theory`] (`± 2·ΣF1·H/(N·G)`); the lean adds `−y_i·F2_i` (the weight acting
//! off-centre) and the change of height.

use crate::rail::vehicle::theory::body_forces;
use crate::rail::vehicle::CarriageData;
use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

/// Displaced state of the car body and a bogie: lateral (m), vertical (m), roll (rad).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LeanState {
    /// Car body `(y, v, φ)`.
    pub car_body: [f64; 3],
    /// Bogie `(y, v, φ)`.
    pub bogie: [f64; 3],
}

/// Wheel loads with and without lean (N) and the displaced state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeanLoads {
    /// Inner and outer wheel normal loads with body lean.
    pub lean: [f64; 2],
    /// Inner and outer wheel normal loads of rigid-body statics (no lean).
    pub rigid: [f64; 2],
    /// The displaced state.
    pub state: LeanState,
    /// Newton iterations used.
    pub iterations: usize,
    /// Moment of the body loads at their displaced mass centres about the outer contact
    /// line ([`ArcPoint::pivot`]) (N·m); the inner wheels unload where it vanishes.
    pub pivot_moment: f64,
}

/// One operating point: speed (m/s), curvature (1/m, positive left-hand), cant (rad),
/// gravity (m/s²) and contact spacing `2a` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPoint {
    /// Speed V (m/s).
    pub speed: f64,
    /// Curvature 1/R (1/m).
    pub curvature: f64,
    /// Cant θ (rad).
    pub cant: f64,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Lateral spacing of the inner and outer contact points (m).
    pub spacing: f64,
    /// The outer contact line `(y_o, z_o)` in the wheel frame (m) for
    /// [`LeanLoads::pivot_moment`]; `None` = `(−spacing/2, 0)`.
    pub pivot: Option<(f64, f64)>,
}

fn rot(phi: f64) -> Matrix2<f64> {
    let (s, c) = phi.sin_cos();
    Matrix2::new(c, -s, s, c)
}

fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// A body's pose: mass-centre position and roll.
struct Pose {
    x: Vector2<f64>,
    phi: f64,
    height: f64,
}

impl Pose {
    fn new(height: f64, s: &[f64]) -> Pose {
        Pose {
            x: Vector2::new(s[0], height + s[1]),
            phi: s[2],
            height,
        }
    }
}

/// Force `G` of a suspension (the upper body receives `−G`, the lower `+G`, along a line
/// through the upper seat) and that seat `p_U`.
fn spring(
    lower: &Pose,
    upper: &Pose,
    seat: (f64, f64),
    k: (f64, f64),
    preload: f64,
) -> (Vector2<f64>, Vector2<f64>) {
    let (lat, h) = seat;
    let q_l = rot(lower.phi);
    let p_l = lower.x + q_l * Vector2::new(lat, h - lower.height);
    let p_u = upper.x + rot(upper.phi) * Vector2::new(lat, h - upper.height);
    let d = q_l.transpose() * (p_u - p_l);
    let g = Vector2::new(k.0 * d.x, k.1 * d.y - preload);
    (q_l * g, p_u)
}

/// Solves the lean and returns the wheel loads. `None` if Newton does not converge (a
/// carriage that overturns on its suspension).
pub fn wheel_loads(c: &CarriageData, op: &ArcPoint) -> Option<LeanLoads> {
    let g = op.gravity;
    let load = |m: f64| {
        let (f1, f2) = body_forces(m * g, op.cant, op.curvature, op.speed, g);
        Vector2::new(f1, f2)
    };
    let (f_c, f_b, f_w) = (
        load(c.car_body.mass),
        load(c.bogie.mass),
        load(c.wheelset.mass),
    );
    let p2 = c.car_body.mass * g / 4.0;
    let p1 = (c.car_body.mass + 2.0 * c.bogie.mass) * g / 8.0;
    let (s2, s1) = (&c.secondary, &c.primary);
    let residual = |x: &SVector<f64, 6>| -> SVector<f64, 6> {
        let car = Pose::new(c.car_body.height, &x.as_slice()[0..3]);
        let bogie = Pose::new(c.bogie.height, &x.as_slice()[3..6]);
        let wheelset = Pose::new(c.wheelset.height, &[0.0; 3]);
        let mut r = SVector::<f64, 6>::zeros();
        // Applied loads and their moments about the origin.
        let mut fc = f_c;
        let mut mc = cross(&car.x, &f_c);
        let mut fb = f_b;
        let mut mb = cross(&bogie.x, &f_b);
        let roll = c.anti_roll * (car.phi - bogie.phi);
        mc -= 2.0 * roll;
        mb += roll;
        for lat in [c.secondary_span, -c.secondary_span] {
            let (gs, pu) = spring(&bogie, &car, (lat, s2.height), (s2.ky, s2.kz), p2);
            // Two bogies' secondaries act on the car body; one bogie's on the bogie.
            fc -= 2.0 * gs;
            mc -= 2.0 * cross(&pu, &gs);
            fb += gs;
            mb += cross(&pu, &gs);
        }
        for lat in [c.primary_span, -c.primary_span] {
            let (gp, pu) = spring(&wheelset, &bogie, (lat, s1.height), (s1.ky, s1.kz), p1);
            // Two wheelsets per bogie.
            fb -= 2.0 * gp;
            mb -= 2.0 * cross(&pu, &gp);
        }
        r[0] = fc.x;
        r[1] = fc.y;
        r[2] = mc;
        r[3] = fb.x;
        r[4] = fb.y;
        r[5] = mb;
        r
    };
    let w_total = c.total_mass() * g;
    let mut x = SVector::<f64, 6>::zeros();
    let mut iterations = 0;
    loop {
        let r = residual(&x);
        if r.amax() < 1e-10 * w_total {
            break;
        }
        if iterations == 50 {
            return None;
        }
        iterations += 1;
        let mut jac = SMatrix::<f64, 6, 6>::zeros();
        for j in 0..6 {
            let h = 1e-7;
            let mut xp = x;
            xp[j] += h;
            let mut xm = x;
            xm[j] -= h;
            jac.set_column(j, &((residual(&xp) - residual(&xm)) / (2.0 * h)));
        }
        x -= jac.lu().solve(&r)?;
    }
    let a = 0.5 * op.spacing;
    let (y_o, z_o) = op.pivot.unwrap_or((-a, 0.0));
    let split = |yz: [(f64, f64); 3]| {
        let sum_f2 = f_c.y + 2.0 * f_b.y + 4.0 * f_w.y;
        let mut m = 0.0;
        for ((n, f), (y, z)) in [(1.0, f_c), (2.0, f_b), (4.0, f_w)].into_iter().zip(yz) {
            m += n * (z * f.x - y * f.y);
        }
        let (mean, diff) = (-sum_f2 / 8.0, m / (8.0 * a));
        [mean + diff, mean - diff]
    };
    // Moment of the body loads about the outer contact line (y_o, z_o) (N·m): the inner
    // wheels unload when it reaches zero.
    let pivot_moment = {
        let mut m = 0.0;
        let pts = [
            (1.0, f_c, x[0], c.car_body.height + x[1]),
            (2.0, f_b, x[3], c.bogie.height + x[4]),
            (4.0, f_w, 0.0, c.wheelset.height),
        ];
        for (n, f, y, z) in pts {
            m += n * ((y - y_o) * f.y - (z - z_o) * f.x);
        }
        m
    };
    let heights = (c.car_body.height, c.bogie.height, c.wheelset.height);
    let lean = split([
        (x[0], heights.0 + x[1]),
        (x[3], heights.1 + x[4]),
        (0.0, heights.2),
    ]);
    let rigid = split([(0.0, heights.0), (0.0, heights.1), (0.0, heights.2)]);
    Some(LeanLoads {
        lean,
        rigid,
        state: LeanState {
            car_body: [x[0], x[1], x[2]],
            bogie: [x[3], x[4], x[5]],
        },
        iterations,
        pivot_moment,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::vehicle::theory::{self, Carriage, Operation, TrackParams, Variant};

    fn fig6() -> ArcPoint {
        ArcPoint {
            speed: 80.0,
            curvature: 1.0 / 6250.0,
            cant: 200.0 / 6250.0,
            gravity: 9.81,
            spacing: 1.507,
            pivot: None,
        }
    }

    /// Without lean the loads are the rigid-body statics of `theory` (an independent
    /// implementation of the same Eq. 25 statics).
    #[test]
    fn rigid_part_is_the_theory() {
        let c = CarriageData::sks700();
        let r = wheel_loads(&c, &fig6()).expect("converges");
        let t = theory::evaluate(
            &Carriage::sks700_standin_with_gravity(9.81),
            &TrackParams {
                gauge: 1.507,
                gravity: 9.81,
            },
            &Operation {
                speed: 80.0,
                cant_constant: 200.0,
                mu: 0.3,
            },
            6250.0,
            Variant::Statics,
        )
        .unwrap();
        assert!((r.rigid[0] - t.normal_inner).abs() < 1e-9 * t.normal_inner);
        assert!((r.rigid[1] - t.normal_outer).abs() < 1e-9 * t.normal_outer);
    }

    /// On straight, level track the preloads hold the bodies where the data put them.
    #[test]
    fn no_sag_on_straight_level_track() {
        let c = CarriageData::sks700();
        let op = ArcPoint {
            curvature: 0.0,
            cant: 0.0,
            ..fig6()
        };
        let r = wheel_loads(&c, &op).expect("converges");
        assert!(r.iterations == 0, "{:?}", r.state);
        assert!((r.lean[0] - r.lean[1]).abs() < 1e-9 * r.lean[0]);
    }

    /// First order check of the car body's lateral shift on the Fig. 6 arc: the car body's
    /// lateral load over the lateral rates of 4 secondaries and 8 primaries in series,
    /// plus the lean of the roll, is a few centimetres outwards (negative axis 1); the
    /// lean moves load outwards.
    #[test]
    fn car_body_moves_outwards_and_loads_the_outer_wheels() {
        let c = CarriageData::sks700();
        let r = wheel_loads(&c, &fig6()).expect("converges");
        let (f1, _) = body_forces(
            c.car_body.mass * 9.81,
            200.0 / 6250.0,
            1.0 / 6250.0,
            80.0,
            9.81,
        );
        let series = f1 / (4.0 * c.secondary.ky) + (f1) / (8.0 * c.primary.ky);
        assert!(r.state.car_body[0] < series, "{:?} vs {series}", r.state);
        assert!(r.state.car_body[0] > -0.2);
        assert!(r.lean[1] > r.rigid[1] && r.lean[0] < r.rigid[0]);
    }
}
