//! `railfem contact` (docs/contact-tool.md): the rigid contact geometry of the Manchester
//! contact benchmark against CONTACT's published reference output, and the command's
//! symmetry and bad input.

use railfem::contact_tool::manchester::{compare, Pair, CONTACT_A22};
use std::process::Command;

fn rel(p: Pair) -> f64 {
    (p.ours / p.contact - 1.0).abs()
}

/// Shifts 1 … 4.5 mm: one contact per wheel on the treads, away from the contact jumps
/// (0 → 0.5 mm and 4.5 → 5.5 mm, where the patch is a band of several millimetres and
/// CONTACT's reference point, its centre, is not a rigid touch point). There the elastic
/// patch (half-width 1.5–6 mm at 10 kN) is nearly symmetric about the rigid touch point:
/// positions agree to 0.5 mm (a tenth of a patch width); angles, Δr and roll, which vary
/// smoothly along the tread, to 5 %. CONTACT ran with yaw 2.4·y rad/m, ours without: on the
/// tread the yaw's lead of the contact, r0·tan δ·ψ < 0.1 mm, changes none of these by more
/// than 1e-3 (docs/contact-tool.md).
#[test]
fn manchester_benchmark_tread_geometry_agrees_with_contact() {
    let rows = compare().unwrap();
    assert_eq!(rows.len(), CONTACT_A22.len());
    let mut checked = 0;
    for c in rows.iter().filter(|c| (1.0..=4.5).contains(&c.y_mm)) {
        checked += 1;
        assert!(rel(c.roll) < 0.05, "y {} roll {:?}", c.y_mm, c.roll);
        assert!(rel(c.delta_r) < 0.05, "y {} Δr {:?}", c.y_mm, c.delta_r);
        for (k, w) in c.wheels.iter().enumerate() {
            for (what, p) in [("wheel_y", w[0]), ("rail_y", w[1])] {
                assert!(
                    (p.ours - p.contact).abs() < 0.5,
                    "y {} wheel {k} {what} {p:?}",
                    c.y_mm
                );
            }
            assert!(rel(w[2]) < 0.05, "y {} wheel {k} δ {:?}", c.y_mm, w[2]);
        }
    }
    assert_eq!(checked, 8);
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

/// Flange contact is reached between 6 and 7.5 mm (CONTACT: 6.5 mm; the jump of the
/// contact angle above 1 rad) on the flange-side wheel only.
#[test]
fn manchester_benchmark_flange_contact_onset() {
    let rows = compare().unwrap();
    let onset = |ours: bool| {
        rows.iter()
            .find(|c| {
                let d = c.wheels[0][2];
                (if ours { d.ours } else { d.contact }) > 1000.0
            })
            .map(|c| c.y_mm)
    };
    assert_eq!(onset(false), Some(6.5));
    let ours = onset(true).unwrap();
    assert!((6.0..=7.5).contains(&ours), "flange contact from {ours} mm");
    assert!(rows.iter().all(|c| c.wheels[1][2].ours < 100.0));
}

fn railfem(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .output()
        .unwrap()
}

fn column(csv: &str, name: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let k = lines
        .next()
        .unwrap()
        .split(',')
        .position(|h| h == name)
        .unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
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
