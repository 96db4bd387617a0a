//! The paper's Section 4 on shortened tracks: FE against the simple theory (Eqs. 21–26).
//! The full cases run from the command line (`railfem curve`, `railfem critical-radius`)
//! and are reported in docs/validation/paper.md.

use railfem::critical::{self, Criterion, CriticalCase};
use railfem::curve::{self, CurveCase};

/// Fig. 6 analogue on a short five-segment track (60 / 300 / 700 / 300 / 60 m) at 80 m/s,
/// Ct = 200 m, R = 6250 m: on the arc, 400 m after its start (transients of the entry have
/// decayed: the carriage's lateral response to the end of the clothoid decays with a time
/// constant of about 1 s, and 400 m take 5 s), every
/// wheel's normal force equals rigid-body statics within 0.5 % and every wheelset's
/// lateral force (mean of its two wheels) equals Eq. 26 within 0.5 %. The linear vehicle
/// model cannot add anything statics does not have except dynamics, so what is left is
/// the residual motion of the carriage. Eq. 25 as printed differs by several per cent
/// (its moment term is half the statics one).
#[test]
fn fig6_short_track_matches_statics() {
    let case = CurveCase {
        lengths: [60.0, 300.0, 700.0, 300.0, 60.0],
        ..CurveCase::default()
    };
    let r = curve::run(&case, None, &mut |_| {}).expect("runs");
    assert!(
        r.max_rel_normal_statics < 5e-3,
        "normal vs statics {:e}",
        r.max_rel_normal_statics
    );
    assert!(
        r.max_rel_shear < 5e-3,
        "axle shear vs Eq. 26 {:e}",
        r.max_rel_shear
    );
    assert!(
        r.max_rel_normal_printed > 2e-2,
        "printed Eq. 25 should differ: {:e}",
        r.max_rel_normal_printed
    );
    assert!(r.first_slide.is_none(), "the case is meant to stick");
}

/// Fig. 7 points: the radius where Eq. 24 first holds for the FE wheel forces, found in
/// one run through a clothoid, equals the theory's critical radius within 1 %; a clothoid
/// twice as long gives the same radius (the onset is quasi-static).
#[test]
fn fig7_sliding_radius_matches_theory() {
    for (speed, ct, mu) in [(120.0, 200.0, 0.3), (100.0, 400.0, 0.1)] {
        let mut case = CriticalCase {
            criterion: Criterion::Sliding,
            speed,
            ct,
            mu,
            clothoid: 1000.0,
            dt: 0.01,
            geometry: Default::default(),
            tangential: Default::default(),
            polach_spin: None,
        };
        let r = critical::run(&case).expect("runs");
        let (fe, th) = (r.fe.expect("FE slides"), r.theory.expect("theory slides"));
        assert!(
            (fe - th).abs() / th < 1e-2,
            "V {speed} Ct {ct} mu {mu}: FE {fe} theory {th}"
        );
        case.clothoid = 2000.0;
        let r2 = critical::run(&case).expect("runs");
        let fe2 = r2.fe.expect("FE slides");
        assert!(
            (fe2 - fe).abs() / fe < 2e-3,
            "not quasi-static: {fe} vs {fe2}"
        );
    }
}

/// Fig. 9 point (Ct = 200 m, V = 220 m/s, μ = 0.3): the carriage first slides outwards
/// onto its flanges, then the inner wheels unload. The radius where the FE's inner normal
/// force reaches zero equals, within 1 %, the overturning radius of the rigid carriage
/// pivoting on the outer contact point the FE found (statics: the moment of the body
/// forces about that point vanishes). The printed Eq. 25 predicts about half the radius.
#[test]
fn fig9_separation_radius_matches_statics_about_the_contact() {
    let case = CriticalCase {
        criterion: Criterion::Separation,
        speed: 220.0,
        ct: 200.0,
        mu: 0.3,
        clothoid: 2000.0,
        dt: 0.01,
        geometry: Default::default(),
        tangential: Default::default(),
        polach_spin: None,
    };
    let r = critical::run(&case).expect("runs");
    let fe = r.fe.expect("the inner wheel separates");
    let th = r
        .theory_at_contact
        .expect("statics about the contact point");
    assert!((fe - th).abs() / th < 1e-2, "FE {fe} vs statics {th}");
    let printed = r.theory_printed.expect("printed Eq. 25 radius");
    assert!(printed < 0.6 * fe, "printed {printed} vs FE {fe}");
    // The contact moved onto the outer flange: inwards of the tread position (−0.75 m).
    let c = r.outer_contact.expect("outer contact");
    assert!(c[0] > -0.745, "outer contact at {c:?}");
}
