//! Fuzz target: the wheel–rail contact search and the moving-axle element's contact
//! response, without a solver. The fuzz bytes are decoded (see [`Bytes`]) into profile
//! parameters (wheel sampling and an optional perturbation of its points, rail node count,
//! inclination and perturbation) and a wheelset pose (lateral shift, roll, yaw, vertical
//! approach, rail bending, a committed slip history).
//!
//! 1. Geometry: every rail node, rolled, shifted and pressed against the wheel spline, is
//!    measured with `rail_node_gap`; asserts finite results, unit normal and tangent, the
//!    closest point orthogonality `(p − c)·τ ≈ 0`, `|gap| = |p − c|`, and that
//!    `contact_nodes` returns exactly the nodes whose gap is ≤ 0.
//! 2. Element: the conformance sample wheel (S1002 on 60E1, flexible rails) updated at the
//!    decoded pose after committing the decoded history: finite force and tangent, every
//!    contact point inside the friction cone in its plane (`|f_u| ≤ μ·f_n`), zero contact
//!    force when no point touches, and no contact at all for the wheelset lifted clear.

#![no_main]

use libfuzzer_sys::fuzz_target;
use nalgebra::Vector2;
use railfem::elements::rail::contact::contact_geometry::{contact_nodes, rail_node_gap};
use railfem::elements::rail::contact::contact_law::SlidingTangent;
use railfem::elements::rail::wheels::moving_axle::{sample_states, MovingAxle};
use railfem::elements::rail::contact::profiles::{Inclination, RailProfile, WheelProfile};
use railfem::framework::element::{Element, TrialState};

/// Reads numbers from the fuzz bytes; past the end every read is 0 (the middle of a range).
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u16(&mut self) -> u16 {
        let (a, rest) = self.0.split_at(self.0.len().min(2));
        self.0 = rest;
        match a {
            [x, y] => u16::from_le_bytes([*x, *y]),
            [x] => u16::from(*x) << 8,
            _ => 0x8000,
        }
    }
    /// A number in `[lo, hi]`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * f64::from(self.u16()) / f64::from(u16::MAX)
    }
    fn byte(&mut self) -> u8 {
        (self.u16() >> 8) as u8
    }
}

fn geometry(b: &mut Bytes) {
    let wheel_points = 8 + usize::from(b.byte() % 200);
    let mut wheel = WheelProfile::s1002(wheel_points);
    let noise = b.range(0.0, 1e-3) * f64::from(b.byte() % 2);
    if noise > 0.0 {
        // Perturb the points (self-intersections are refused, never a panic).
        let pts: Vec<Vector2<f64>> = wheel
            .points()
            .iter()
            .map(|p| p + Vector2::new(b.range(-noise, noise), b.range(-noise, noise)))
            .collect();
        match WheelProfile::from_points(&pts) {
            Ok(w) => wheel = w,
            Err(e) => {
                assert!(!e.to_string().contains('\n'));
                return;
            }
        }
    }
    let incl = [
        Inclination::None,
        Inclination::OneIn40,
        Inclination::OneIn20,
    ][usize::from(b.byte() % 3)];
    let rail = RailProfile::uic60(4 + usize::from(b.byte() % 120), incl);
    let rail = if b.byte() % 2 == 0 {
        rail
    } else {
        rail.mirrored()
    };
    let wheel = if b.byte() % 4 == 0 {
        wheel.mirrored()
    } else {
        wheel
    };
    let shift = Vector2::new(b.range(-0.08, 0.08), b.range(-0.01, 0.01));
    let roll = b.range(-0.1, 0.1);
    let (s, c) = roll.sin_cos();
    let nodes: Vec<Vector2<f64>> = rail
        .nodes()
        .iter()
        .map(|p| Vector2::new(c * p.x - s * p.y, s * p.x + c * p.y) + shift)
        .collect();
    let spline = wheel.spline();
    let mut touching = Vec::new();
    for (i, p) in nodes.iter().enumerate() {
        let Some(cp) = rail_node_gap(spline, *p) else {
            continue;
        };
        assert!(cp.gap.is_finite() && cp.t.is_finite(), "node {i}: {cp:?}");
        assert!((cp.normal.norm() - 1.0).abs() < 1e-12, "{cp:?}");
        assert!((cp.tangent.norm() - 1.0).abs() < 1e-12, "{cp:?}");
        assert!(cp.normal.dot(&cp.tangent).abs() < 1e-12, "{cp:?}");
        let r = p - cp.point;
        // A stationary point of the distance: r ⟂ τ up to the Newton tolerance (1e-15 of
        // the curve length, times the curvature-weighted lever); 1e-9 m is far above it.
        assert!(
            r.dot(&cp.tangent).abs() <= 1e-9 * (1.0 + r.norm()),
            "node {i}: {cp:?} p {p:?}"
        );
        assert!(
            (cp.gap.abs() - r.norm()).abs() <= 1e-9 * (1.0 + r.norm()),
            "{cp:?}"
        );
        if cp.gap <= 0.0 {
            touching.push(i);
        }
    }
    // The window (wheel extent + 5 cm) covers every node that can touch.
    let found: Vec<usize> = contact_nodes(spline, &nodes, 0.05, 0.0)
        .iter()
        .map(|n| n.node)
        .collect();
    let sorted_by_y = nodes.windows(2).all(|w| w[1].x > w[0].x);
    if sorted_by_y {
        assert!(
            found.iter().all(|i| touching.contains(i)),
            "{found:?} vs {touching:?}"
        );
        let (y0, y1) = spline.lateral_extent();
        let inside: Vec<usize> = touching
            .iter()
            .copied()
            .filter(|&i| nodes[i].x >= y0 - 0.05 && nodes[i].x <= y1 + 0.05)
            .collect();
        assert_eq!(found, inside);
    }
}

fn evaluate(e: &mut dyn Element, u: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let z = vec![0.0; u.len()];
    e.update(&TrialState {
        time: 0.0,
        dt: 0.0,
        disp: u,
        vel: &z,
        acc: &z,
    })
    .expect("a wheel on its rail element updates");
    let mut f = vec![0.0; u.len()];
    e.resisting_force(&mut f);
    let mut k = nalgebra::DMatrix::zeros(u.len(), u.len());
    e.tangent_stiffness(&mut k);
    (f, k.as_slice().to_vec())
}

/// Element DOFs: B (0..3, wheel frame), K (3..9), rail nodes I (9..15), J (15..21).
fn pose(b: &mut Bytes) -> Vec<f64> {
    let lateral = b.range(-0.012, 0.012);
    let approach = b.range(-2e-3, 2e-4);
    let roll = b.range(-2e-3, 2e-3);
    let yaw = b.range(-5e-3, 5e-3);
    let spring = b.range(-1e-4, 1e-4);
    let mut u = vec![0.0; 21];
    u[0] = lateral + b.range(-1e-5, 1e-5);
    u[1] = -approach + spring;
    u[2] = b.range(-1e-4, 1e-4);
    u[3] = lateral;
    u[4] = -approach;
    u[5] = u[2] + b.range(-1e-5, 1e-5);
    u[6] = b.range(-1e-4, 1e-4);
    u[7] = yaw;
    u[8] = roll;
    for x in &mut u[9..] {
        *x = b.range(-2e-5, 2e-5);
    }
    u
}

fn element(b: &mut Bytes) {
    let tangent = if b.byte() % 2 == 0 {
        SlidingTangent::Symmetric
    } else {
        SlidingTangent::Consistent
    };
    let mut sample = sample_states(tangent).swap_remove(0);
    let e = sample.element.as_mut();
    if b.byte() % 2 == 1 {
        let history = pose(b);
        evaluate(e, &history);
        e.commit();
    }
    let u = pose(b);
    let (f, k) = evaluate(e, &u);
    assert!(
        f.iter().chain(&k).all(|x| x.is_finite()),
        "non-finite force or tangent at {u:?}"
    );
    let wheel = e
        .as_any()
        .and_then(|a| a.downcast_ref::<MovingAxle>())
        .expect("a moving axle");
    let mu = 0.3;
    let mut any = false;
    for (i, st, _, _) in wheel.contact_points() {
        any = true;
        assert!(st.f_n >= 0.0, "node {i}: tensile normal force {}", st.f_n);
        assert!(
            st.f_u.abs() <= mu * st.f_n * (1.0 + 1e-9),
            "node {i}: {st:?}"
        );
    }
    if !any {
        assert_eq!(
            wheel.contact_force().norm(),
            0.0,
            "force without contact at {u:?}"
        );
    }
    // The wheelset raised 5 mm (B and K together, no rotation, rails at rest) touches
    // nowhere: the sample starts 1 nm into the rail, far less than the lift.
    let mut lifted = vec![0.0; 21];
    lifted[1] = 5e-3;
    lifted[4] = 5e-3;
    evaluate(e, &lifted);
    let wheel = e
        .as_any()
        .and_then(|a| a.downcast_ref::<MovingAxle>())
        .expect("a moving axle");
    assert_eq!(
        wheel.contact_points().count(),
        0,
        "contact 5 mm above the rail"
    );
    assert_eq!(wheel.contact_force().norm(), 0.0);
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    if b.byte() % 2 == 0 {
        geometry(&mut b);
    } else {
        element(&mut b);
    }
});
