//! `railfem contact` (docs/contact-tool.md): the rigid contact geometry of the Manchester
//! contact benchmark against CONTACT's published reference output, and the command's
//! symmetry and bad input.

use railfem::contact_tool::manchester::{Comparison, Pair, CONTACT_A22};
use std::process::Command;
use std::sync::OnceLock;

/// The benchmark compared once for all tests of this file.
fn compare() -> &'static [Comparison] {
    static ROWS: OnceLock<Vec<Comparison>> = OnceLock::new();
    ROWS.get_or_init(|| railfem::contact_tool::manchester::compare().unwrap())
}

fn rel(p: Pair) -> f64 {
    (p.ours / p.contact - 1.0).abs()
}

/// CONTACT's numbers are those of an elastic patch at 10 kN (its contact reference point,
/// the patch centre; elastic approach 0.016 mm), ours of rigid profiles (the first touch
/// point); both codes shift the axle centre. Away from the contact jumps of this pair
/// (0 → 0.5 mm and 4.5 → 5 mm, where the patch spans both contact zones), i.e. at
/// 1.5–4.5 mm and 5.5–10 mm (flange contact from 6.5 mm), the patch is small and nearly
/// symmetric about the rigid point: positions agree to 0.25 mm (a tenth of the smallest
/// patch half-width, 2.5 mm), contact angles to 1 mrad or 2 % (CONTACT prints 0.1 mrad;
/// the patch's mean normal differs from the point's by the profile curvature over the
/// patch), Δr to 2.5 % and the roll to 5 % (differences of the order of the elastic
/// approach, 0.02 mm in Δr, 0.02 mrad in roll). Next to the jumps (1 and 5 mm, and
/// 6.5 mm, the first shift in flange contact: Δr grows by 12 mm over the 0.5 mm before
/// it, so a 0.01 mm later onset changes it by 3 %) the bounds are 0.6 mm, 4 % (angles),
/// 6 % (Δr) and 8 % (roll). Both yaw the wheelset by 2.4·y rad/m and find the contact
/// ahead of the axle (`contact_tool::yawed`).
#[test]
fn manchester_benchmark_geometry_agrees_with_contact() {
    let rows = compare();
    assert_eq!(rows.len(), CONTACT_A22.len());
    let mut checked = 0;
    for c in rows.iter().filter(|c| c.y_mm >= 1.0) {
        checked += 1;
        let near_jump = c.y_mm == 1.0 || c.y_mm == 5.0 || c.y_mm == 6.5;
        let (pos, dr, roll, angle) = if near_jump {
            (0.6, 0.06, 0.08, 0.04)
        } else {
            (0.25, 0.025, 0.05, 0.02)
        };
        assert!(rel(c.roll) < roll, "y {} roll {:?}", c.y_mm, c.roll);
        assert!(rel(c.delta_r) < dr, "y {} Δr {:?}", c.y_mm, c.delta_r);
        for (k, w) in c.wheels.iter().enumerate() {
            for (what, p) in [("wheel_y", w[0]), ("rail_y", w[1])] {
                assert!(
                    (p.ours - p.contact).abs() < pos,
                    "y {} wheel {k} {what} {p:?}",
                    c.y_mm
                );
            }
            let d = w[2];
            assert!(
                (d.ours - d.contact).abs() < (1.0f64).max(angle * d.contact.abs()),
                "y {} wheel {k} δ {d:?}",
                c.y_mm
            );
        }
    }
    assert_eq!(checked, 19);
    // Centred, both contacts lie on the field side of the tape circle, as CONTACT's patch
    // centre does (1.87 mm), within the 16 mm wide patch it finds there.
    let c0 = &rows[0];
    for w in &c0.wheels {
        assert!(
            w[0].ours > 0.0 && (w[0].ours - w[0].contact).abs() < 2.0,
            "{w:?}"
        );
    }
}

/// The normal load balances the wheel load with the lateral creep force (FASTSIM at the
/// benchmark's yaw 2.4·y rad/m and CONTACT's pitch rates), as CONTACT's does. On the flange
/// the creep force carries 35–40 % of the load (`Fy sin δ`), so our Fy, within 4.5 % of
/// CONTACT's there (below), moves N by at most 0.045·0.4 ≈ 1.8 %; the contact angles
/// differ by < 1.5 % (`cos δ` by < 4 % at 6.5 mm, where the two partly compensate). On the
/// treads `Fy sin δ` is 0.3 % of the load. Bound: 2 % at every shift, the jumps included
/// (at 6.5 mm the difference was 69 % with `N = Q/cos δ`).
#[test]
fn manchester_benchmark_normal_load_balances_the_creep_force() {
    let rows = compare();
    for c in rows {
        for w in &c.wheels {
            assert!(rel(w[3]) < 0.02, "y {} N {:?}", c.y_mm, w[3]);
        }
    }
    let flange = rows.iter().find(|c| c.y_mm == 6.5).unwrap();
    assert!(flange.wheels[0][3].contact > 15e3);
}

/// The benchmark's operating point (yaw 2.4·y rad/m, CONTACT's pitch rates; creepages over
/// the mean rolling speed) gives CONTACT's creepages. Away from the jumps (0–1 mm, 5 mm):
/// - `ξy·cos δ` (the lateral slip over the rolling speed, without the contact angle, which
///   differs by up to 0.8 % on the flange) within 1.5 %: both codes put the contact ahead
///   of the axle, where the roll adds `Ω·x·sin φ_r` to the lateral slip (1.1 % at 10 mm),
///   CONTACT at its elastic patch's reference point, we at the rigid touch point;
/// - `ξx` within 3.5 %: the rolling radii differ by 0.1–0.15 mm on the flange (Δr, above),
///   1.3 % of `ξx`; 3 % at 6 mm next to the jump;
/// - the spin within 5 %: the tread's contact angle is 3–5 % below CONTACT's (a mean over
///   a wide patch, docs/contact-tool.md).
#[test]
fn manchester_benchmark_creepages_agree_with_contact() {
    let rows = compare();
    let deltas = |c: &Comparison, k: usize| {
        let d = c.wheels[k][2];
        ((d.ours * 1e-3).cos(), (d.contact * 1e-3).cos())
    };
    for c in rows.iter().filter(|c| c.y_mm >= 1.5 && c.y_mm != 5.0) {
        for (k, w) in c.creep.iter().enumerate() {
            let (co, cc) = deltas(c, k);
            let slip = Pair {
                ours: w[1].ours * co,
                contact: w[1].contact * cc,
            };
            assert!(rel(slip) < 0.015, "y {} wheel {k} ξy {:?}", c.y_mm, w[1]);
            assert!(rel(w[0]) < 0.035, "y {} wheel {k} ξx {:?}", c.y_mm, w[0]);
            assert!(rel(w[2]) < 0.05, "y {} wheel {k} φ {:?}", c.y_mm, w[2]);
        }
    }
}

/// Creep forces of FASTSIM (20 × 20, Hertz patch) against CONTACT's exact theory on its
/// non-Hertzian patch, at 1–10 mm. The lateral force is close to saturation on every wheel
/// (`|F|/μN` = 0.93–0.99): the resultant is set by the traction bound, within 2 %. The
/// lateral force Fy, the dominant component, within 5 % (FASTSIM's accuracy for combined
/// lateral creep and spin is a few %, docs/creep.md). Fx, 10–40 % of Fy, is set by the
/// direction of slip in a patch that slides almost everywhere, FASTSIM's weak point (its
/// single flexibility per direction), and differs by up to 16 %: docs/contact-tool.md
/// explains it; not asserted beyond its sign.
#[test]
fn manchester_benchmark_creep_forces_agree_with_contact() {
    let rows = compare();
    for c in rows.iter().filter(|c| c.y_mm >= 1.0) {
        for (k, w) in c.creep.iter().enumerate() {
            let (fx, fy) = (w[3], w[4]);
            let res = Pair {
                ours: fx.ours.hypot(fy.ours),
                contact: fx.contact.hypot(fy.contact),
            };
            assert!(rel(res) < 0.02, "y {} wheel {k} |F| {res:?}", c.y_mm);
            assert!(rel(fy) < 0.05, "y {} wheel {k} Fy {fy:?}", c.y_mm);
            assert!(
                fx.ours * fx.contact > 0.0,
                "y {} wheel {k} Fx {fx:?}",
                c.y_mm
            );
        }
    }
}

/// Flange contact (contact angle above 1 rad) starts at 6.5 mm in both codes, on the
/// flange-side wheel only.
#[test]
fn manchester_benchmark_flange_contact_onset() {
    let rows = compare();
    let onset = |ours: bool| {
        rows.iter()
            .find(|c| {
                let d = c.wheels[0][2];
                (if ours { d.ours } else { d.contact }) > 1000.0
            })
            .map(|c| c.y_mm)
    };
    assert_eq!(onset(false), Some(6.5));
    assert_eq!(onset(true), Some(6.5));
    assert!(rows.iter().all(|c| c.wheels[1][2].ours < 100.0));
}

fn railfem(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .output()
        .unwrap()
}

/// Column `name` of the first patches' rows (`patch [-]` = 1) of `contact.csv`.
fn column(csv: &str, name: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head.iter().position(|h| *h == name).unwrap();
    let patch = head.iter().position(|h| *h == "patch [-]").unwrap();
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|c| c[patch] == "1")
        .map(|c| c[k].parse().unwrap())
        .collect()
}

/// Mirror symmetry of the track: Δr and the roll are odd in the shift, and the left wheel
/// at −y is the right wheel at +y (same rolling radius, contact angle and creep force
/// magnitude). Centred, Δr and the roll vanish.
#[test]
fn contact_command_is_mirror_symmetric() {
    let dir = std::env::temp_dir().join(format!("railfem-contact-{}", std::process::id()));
    let mut rows = Vec::new();
    for y in ["0.004", "-0.004", "0"] {
        let out = dir.join(y);
        let o = railfem(&["contact", "--y", y, "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        rows.push(std::fs::read_to_string(out.join("contact.csv")).unwrap());
    }
    let (p, m, z) = (&rows[0], &rows[1], &rows[2]);
    let dr = |s: &str| column(s, "delta_r [m]")[0];
    assert!(
        dr(p) > 1e-4 && (dr(p) + dr(m)).abs() < 1e-9,
        "{} {}",
        dr(p),
        dr(m)
    );
    assert!(dr(z).abs() < 1e-9 && column(z, "roll [rad]")[0].abs() < 1e-9);
    for name in [
        "rolling_radius [m]",
        "contact_angle [rad]",
        "N [N]",
        "Fx_kalker [N]",
    ] {
        let (a, b) = (column(p, name), column(m, name));
        for (i, j) in [(0, 1), (1, 0)] {
            assert!(
                (a[i] - b[j]).abs() <= 1e-6 * a[i].abs().max(1e-3),
                "{name}: {} vs {}",
                a[i],
                b[j]
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn contact_command_refuses_bad_input_with_exit_2() {
    for (args, says) in [
        (vec!["--y-step", "0"], "--y-step"),
        (vec!["--profiles", "s1003"], "--profiles s1003"),
        (vec!["--wheel", "w.csv"], "--wheel and --rail"),
        (vec!["--y", "0.001", "--y-max", "0.01"], "--y and --y-max"),
        (vec!["--y", "0.2"], "shift"),
        (vec!["--inclination", "1:30"], "--inclination"),
        (vec!["--balance", "coulomb"], "--balance coulomb"),
    ] {
        let mut all = vec!["contact"];
        all.extend(args.iter());
        let o = railfem(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
}

/// The gauge point 14 mm below the top of the upright 60E1 lies on its R13 gauge corner
/// (centre (−23.016, −14.949) mm): y = −23.016 − √(13² − 0.949²) = −35.9813 mm. Linear
/// interpolation between nodes 0.4 mm apart on R13 errs by less than 0.4²/(8·13) mm.
#[test]
fn gauge_point_of_60e1_lies_on_its_gauge_corner() {
    use railfem::contact_tool::profiles::gauge_point;
    use railfem::elements::rail::contact::profiles::{Inclination, RailProfile};
    let rail = RailProfile::uic60(401, Inclination::None);
    let y = gauge_point(rail.nodes()).unwrap() * 1e3;
    let exact = -23.016 - (13.0f64 * 13.0 - 0.949 * 0.949).sqrt();
    assert!((y - exact).abs() < 2e-3, "{y} vs {exact}");
}

/// The benchmark rail's gauge point, found in its file, places the rail where CONTACT puts
/// it: CONTACT's centred contact is at YCP(TR) = 751.8726 mm, YCP(R) = −8.66 mm from the
/// rail origin, so the origin is at 760.5326 mm and the gauge point (at 717.5 mm) at
/// −43.0326 mm. CONTACT interpolates the file's nodes by splines, we linearly between
/// nodes about 0.15 mm apart on the gauge face, which moves the 14 mm crossing by a few
/// micrometres: 5 µm.
#[test]
fn manchester_rail_sits_where_contact_puts_it() {
    let p = railfem::contact_tool::profiles::manchester().unwrap();
    assert!((p.gauge_y * 1e3 + 43.0326).abs() < 5e-3, "{}", p.gauge_y);
}

/// A yawed wheelset's contact leads the axle (module doc of `contact_tool::yawed`). Closed
/// form: a cone of slope λ on rails whose heads are circular cylinders of radius `R` along
/// the track. The rail head touches the wheel where the line of the cylinder's axis touches
/// the cone offset outward by `R` (radius `ρ(Y) + R·√(1 + λ²)` at axle coordinate `Y`),
/// and the contact has the `x` of that point of the line. For a point `(x, c_r, −R)` of the
/// line, with the axle through `(0, 0, z + r0)` along `a = (−sin ψ, cos ψ, 0)`: axle
/// coordinate `Y = −x sin ψ + c_r cos ψ`, distance from the axle `d = √(|q|² − Y²)`; the
/// radial gap `F(x) = d − ρ_R(Y)` is stationary where `(x + Y sin ψ)/d = λ sin ψ`
/// (`dρ_R/dY = −λ`), solved here by bisection, and zero there when the wheelset touches.
/// Centred (`y = 0`), yawed wheelsets on this track do not roll (symmetry), so the lift is
/// the only unknown; ours must make `F` vanish at the stationary point (1e-10 m) and put
/// the contact at its `x` (1e-8 m: the crown is a cubic spline through nodes 0.1 mm apart,
/// whose slope errs by ~1e-8, and the lead is `r·tan δ·tan ψ` ≈ 0.5 mm). The first-order
/// lead `r·λ·ψ` is met within 1 % (second-order terms, `ψ²` and `λ²`).
#[test]
fn yawed_cone_on_cylinder_rails_leads_as_the_closed_form() {
    use railfem::contact_tool::yawed;
    use railfem::elements::rail::contact::creep::conicity::{cone_profile, WheelsetGeometry};
    use railfem::elements::rail::contact::profiles::{Inclination, RailProfile};
    let (lambda, r_c, r0, c_w, c_r) = (0.05, 0.01, 0.46, 0.75, 0.75);
    let nodes: Vec<nalgebra::Vector2<f64>> = (0..=160)
        .map(|i| {
            let y = -0.008 + 1e-4 * i as f64;
            nalgebra::Vector2::new(y, (r_c * r_c - y * y).sqrt() - r_c)
        })
        .collect();
    let rail = RailProfile::from_nodes(&nodes, Inclination::None).unwrap();
    let geom =
        WheelsetGeometry::new(cone_profile(lambda, -0.03, 0.03), &rail, c_w, c_r, r0).unwrap();
    let rho_r = |y: f64| r0 - lambda * (y - c_w) + r_c * (1.0 + lambda * lambda).sqrt();
    for psi in [0.005, 0.02, -0.02] {
        let found = yawed::contact(&geom, 0.0, psi).unwrap();
        assert!(found.contact.roll.abs() < 1e-12, "{}", found.contact.roll);
        let z = found.contact.lift;
        let (sp, cp) = (psi.sin(), psi.cos());
        let zeta = -r_c - z - r0;
        let f = |x: f64| {
            let y = -x * sp + c_r * cp;
            let d = (x * x + c_r * c_r + zeta * zeta - y * y).sqrt();
            (d - rho_r(y), (x + y * sp) / d - lambda * sp)
        };
        let (mut lo, mut hi) = (-0.1, 0.1);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid).1 < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let x = 0.5 * (lo + hi);
        assert!(f(x).0.abs() < 1e-10, "ψ {psi}: radial gap {}", f(x).0);
        let left = found.left;
        assert!((left.x - x).abs() < 1e-8, "ψ {psi}: x {} vs {x}", left.x);
        // The right wheel is the left one turned about the vertical: its contact trails.
        assert!((found.right.lead + left.lead).abs() < 1e-9);
        let first_order = found.contact.left.rolling_radius * lambda * psi.tan();
        assert!(
            (left.lead / first_order - 1.0).abs() < 0.01,
            "ψ {psi}: lead {} vs r·λ·tan ψ {first_order}",
            left.lead
        );
    }
}

/// Without yaw the yawed search is `creep::conicity`'s: the same roll and lift (1e-9),
/// contact points and radii (1e-8 m: on the steep flange the two golden sections stop at
/// points a few nanometres apart along the profile) and contact angles (taken
/// from the rail's slope here, the wheel's there: equal at the tangent point, 1e-6 rad).
#[test]
fn unyawed_search_is_the_conicity_search() {
    use railfem::contact_tool::yawed;
    let case = railfem::contact_tool::ContactCase::default();
    let (geom, _) = railfem::contact_tool::geometry(&case).unwrap();
    for y in [0.0, 0.003, -0.006, 0.008] {
        let a = geom.contact(y).unwrap();
        let b = yawed::contact(&geom, y, 0.0).unwrap();
        assert!((a.lift - b.contact.lift).abs() < 1e-9 && (a.roll - b.contact.roll).abs() < 1e-9);
        for (p, q) in [(a.left, b.contact.left), (a.right, b.contact.right)] {
            for (u, v) in [
                (p.wheel_y, q.wheel_y),
                (p.rail_y, q.rail_y),
                (p.rolling_radius, q.rolling_radius),
                (p.lateral_position, q.lateral_position),
            ] {
                assert!((u - v).abs() < 1e-8, "y {y}: {u} vs {v}");
            }
            assert!((p.contact_angle - q.contact_angle).abs() < 1e-6);
        }
        assert_eq!(b.left.lead, 0.0);
    }
}

/// Two-point contact by construction: a cylindrical wheel (cone of slope 0) on rails whose
/// heads have two circular crowns of radii 10 and 30 mm, tops at the same height 12 mm
/// apart. Centred, each wheel touches both tops at once (both gaps 0, both contact angles
/// 0). Two Hertz springs in parallel under one approach `d`: `N_i = N·(d/d_i(N))^{3/2}`
/// (`d_i(N)` Hertz's approach of patch `i` at any load `N`, `d ∝ N^{2/3}`), so
/// `N_1/N_2 = (d_2(N)/d_1(N))^{3/2}` and `N_1 + N_2 = Q` (δ = 0, no creep in the balance),
/// both to 1e-6 (the bisection on the approach stops at 1e-15 relative). The springs are
/// built here from the patches' relative curvatures `A`, `B` as reported; those match the
/// crowns, `B = (1/R)/2`, to 1e-3 (a cubic spline through nodes 0.1 mm apart on a 10 mm
/// circle, curvature error O(h²/R²)).
#[test]
fn two_point_contact_shares_the_load_as_two_hertz_springs() {
    use railfem::contact_tool::two_point::hertz_approach;
    use railfem::contact_tool::{evaluate, Balance, ContactCase};
    use railfem::elements::rail::contact::creep::conicity::{cone_profile, WheelsetGeometry};
    use railfem::elements::rail::contact::creep::hertz::{hertz_ellipse, Curvatures};
    use railfem::elements::rail::contact::profiles::{Inclination, RailProfile};
    let crowns = [(-0.006, 0.01), (0.006, 0.03)];
    let nodes: Vec<nalgebra::Vector2<f64>> = (0..=300)
        .map(|i| {
            let y = -0.015 + 1e-4 * i as f64;
            let z = crowns
                .iter()
                .filter(|(c, r)| (y - c).abs() < *r)
                .map(|(c, r)| (r * r - (y - c) * (y - c)).sqrt() - r)
                .fold(-0.003, f64::max);
            nalgebra::Vector2::new(y, z)
        })
        .collect();
    let rail = RailProfile::from_nodes(&nodes, Inclination::None).unwrap();
    let geom =
        WheelsetGeometry::new(cone_profile(0.0, -0.03, 0.03), &rail, 0.75, 0.75, 0.46).unwrap();
    let case = ContactCase {
        balance: Balance::Vertical,
        load: 50e3,
        ..ContactCase::default()
    };
    let r = evaluate(&case, &geom, 0.0).unwrap();
    for (first, second) in [(&r.left, &r.second[0]), (&r.right, &r.second[1])] {
        let second = second.as_ref().expect("a second patch");
        let (h1, h2) = (first.hertz.unwrap(), second.hertz.unwrap());
        // Which crown each patch sits on: rail_y at −6 mm is the 10 mm crown.
        let (p10, p30) = if first.geometry.rail_y < 0.0 {
            (h1, h2)
        } else {
            (h2, h1)
        };
        assert!(
            (p10.b_curv / (0.5 / 0.01) - 1.0).abs() < 1e-3,
            "{}",
            p10.b_curv
        );
        assert!(
            (p30.b_curv / (0.5 / 0.03) - 1.0).abs() < 1e-3,
            "{}",
            p30.b_curv
        );
        assert!(second.gap.abs() < 1e-12 && first.geometry.contact_angle.abs() < 1e-9);
        let approach = |a: f64, b: f64| {
            let c = Curvatures {
                wheel_rolling_radius: 0.5 / a,
                wheel_transverse: 2.0 * b,
                rail_transverse: 0.0,
            };
            let h = hertz_ellipse(&c, 1e4, case.young, case.poisson).unwrap();
            hertz_approach(&h, case.young, case.poisson)
        };
        let ratio = (approach(h2.a_curv, h2.b_curv) / approach(h1.a_curv, h1.b_curv)).powf(1.5);
        assert!(
            (first.normal / second.normal / ratio - 1.0).abs() < 1e-6,
            "N1/N2 {} vs {ratio}",
            first.normal / second.normal
        );
        assert!(((first.normal + second.normal) / case.load - 1.0).abs() < 1e-6);
    }
}
