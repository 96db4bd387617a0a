//! Finite rotations of rigid bodies: nonlinear rigid links against a closed form, and the
//! carriage on the canted arc in nonlinear geometry against the quasi-static reference
//! with body lean (`railfem::elements::rail::vehicle::lean`), on shortened tracks.

use railfem::curve::{self, CurveCase};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec, Geometry};
use railfem::framework::DofSet;
use railfem::solvers::Driver;
use serde_json::json;

/// A lever of length L on a hinge about z, its tip a rigid-link slave held by a
/// grounded lateral spring k (along y only), turned by a moment M at the hinge. Nonlinear
/// links: the tip stays on the circle, the spring force `k·L·sin φ` acts at lever arm
/// `L·cos φ`, so `M = k·L²·sin φ·cos φ`; with `M = 0.4·k·L²`, `sin 2φ = 0.8`,
/// φ = 0.4636 rad and the tip at `(L cos φ, L sin φ)`. Linear links: `φ = M/(k·L²)` = 0.4
/// and the tip moves straight up by `L·φ`. Rotations about one fixed axis commute, so the
/// additive update of the present driver is exact here.
fn lever(geometry: Geometry) -> (f64, f64, f64) {
    let (l, k) = (2.0, 1e6);
    let mut b = ModelBuilder::new("lever");
    let free_rz = DofSet::from_bits(DofSet::ALL.bits() & !(1 << 5));
    b.node_fixed(1, [0.0; 3], free_rz);
    b.node(2, [l, 0.0, 0.0]);
    b.rigid_link(1, 2, DofSet::ALL);
    b.element(
        "spring_damper",
        1,
        &[2],
        &json!({"k": [0.0, k, 0.0, 0.0, 0.0, 0.0]}),
    );
    b.load(LoadSpec::Nodal {
        node: 1,
        dof: railfem::framework::Dof::Rz,
        value: 0.4 * k * l * l,
        series: TimeSeries::Constant,
    });
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        geometry,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().expect("model")).expect("driver");
    d.static_solve(0.0, 4).expect("static solve");
    let phi = d
        .displacement(1, railfem::framework::Dof::Rz)
        .expect("hinge rz");
    // The tip is not in the equations under nonlinear links: reconstruct it from the
    // master (what the adapter does), and read the spring's force, which the element
    // computed from the slave's displacement it was given.
    let mut out = Vec::new();
    d.model.elements[0].element.outputs(&mut out);
    (phi, out.get(1).copied().unwrap_or(f64::NAN), k)
}

#[test]
fn nonlinear_link_keeps_the_tip_on_its_circle() {
    let (phi, fy, k) = lever(Geometry::Nonlinear);
    let want = 0.5 * 0.8f64.asin();
    assert!((phi - want).abs() < 1e-9, "φ = {phi}, want {want}");
    // Spring force k·u_y with u_y = L·sin φ.
    assert!((fy - k * 2.0 * want.sin()).abs() < 1e-6 * fy.abs(), "{fy}");
    // Linear links: the slave is in the equations (a linear element is never updated, so
    // its outputs are not read here).
    let (phi_lin, _, _) = lever(Geometry::Linear);
    assert!((phi_lin - 0.4).abs() < 1e-12, "{phi_lin}");
}

fn quick(
    speed: f64,
    radius: f64,
    ct: f64,
    geometry: Geometry,
    anti_roll: f64,
) -> curve::CurveReport {
    let case = CurveCase {
        lengths: [60.0, 300.0, 700.0, 300.0, 60.0],
        speed,
        radius,
        ct,
        geometry,
        anti_roll,
        ..CurveCase::default()
    };
    curve::run(&case, None, &mut |_| {}).expect("runs")
}

/// The carriage on the Fig. 6 arc (V = 80 m/s, R = 6250 m, Ct = 200 m) and on a
/// cant-deficient one (V = 70 m/s, R = 4000 m, Ct = 0), nonlinear geometry: every
/// wheel's normal load on the settled arc equals the quasi-static reference with body lean
/// within 0.5 % (the requirement; the measured difference is below 1e-3), and the lean
/// moves load outwards by several per cent of Q, so rigid-body statics is off by more than
/// 5 % — the effect is real and the test could not pass with the linear model, which is
/// checked too (it matches statics and misses the reference by the same margin).
#[test]
fn carriage_leans_into_the_curve_as_the_reference_says() {
    for (v, r, ct) in [(80.0, 6250.0, 200.0), (70.0, 4000.0, 0.0)] {
        let nl = quick(v, r, ct, Geometry::Nonlinear, 0.0);
        assert!(
            nl.max_rel_normal_lean < 5e-3,
            "V {v} R {r} Ct {ct}: FE vs lean reference {:e}",
            nl.max_rel_normal_lean
        );
        assert!(
            nl.max_rel_normal_statics > 5e-2,
            "{:e}",
            nl.max_rel_normal_statics
        );
        let lin = quick(v, r, ct, Geometry::Linear, 0.0);
        assert!(lin.max_rel_normal_statics < 5e-3);
        assert!(lin.max_rel_normal_lean > 5e-2);
    }
}

/// An anti-roll bar of 2 MN·m/rad per bogie (3.5 times the roll stiffness of the
/// secondary springs, 2·k_z·b² = 0.57 MN·m/rad) stiffens the car body's roll:
/// the FE follows the reference with the bar within 0.5 % and unloads the inner wheel
/// less than without it.
#[test]
fn anti_roll_bar_reduces_the_lean() {
    let with = quick(80.0, 6250.0, 200.0, Geometry::Nonlinear, 2e6);
    assert!(
        with.max_rel_normal_lean < 5e-3,
        "{:e}",
        with.max_rel_normal_lean
    );
    let without = quick(80.0, 6250.0, 200.0, Geometry::Nonlinear, 0.0);
    assert!(with.arc_mean_normal[0] > without.arc_mean_normal[0] + 500.0);
}

/// Fig. 9 point (V = 220 m/s, Ct = 200 m, μ = 0.3) in nonlinear geometry: the inner wheels
/// lift off where statics with body lean about the FE's outer contact point says, within
/// 3 % (measured 1.8 %; the FE carriage, running down the 2000 m clothoid in 9 s, lags the
/// quasi-static lean by its ≈ 1 s lateral and roll response, so it separates slightly
/// later, on a tighter curve), and on a far wider curve than the rigid carriage (+60 %).
#[test]
fn separation_with_lean_follows_the_lean_statics() {
    use railfem::critical::{self, Criterion, CriticalCase};
    let case = CriticalCase {
        criterion: Criterion::Separation,
        speed: 220.0,
        ct: 200.0,
        mu: 0.3,
        clothoid: 2000.0,
        dt: 0.01,
        geometry: Geometry::Nonlinear,
        tangential: Default::default(),
        polach_spin: None,
    };
    let r = critical::run(&case).expect("runs");
    let fe = r.fe.expect("the inner wheel separates");
    let lean = r
        .lean_at_contact
        .expect("lean statics about the contact point");
    assert!(
        (fe - lean).abs() / lean < 3e-2,
        "FE {fe} vs lean statics {lean}"
    );
    let rigid = r
        .theory_at_contact
        .expect("rigid statics about the contact point");
    assert!(fe > 1.4 * rigid, "FE {fe} vs rigid statics {rigid}");
}
