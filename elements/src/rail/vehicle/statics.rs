//! Static state of a vehicle standing on straight, level track: the compressive force in
//! every suspension and the load on every wheel, from a small linear solve of the bodies on
//! their vertical springs with the wheelsets held.
//!
//! Each body that is not a wheelset has three unknowns in vehicle axes: heave `w`, roll `φ`
//! (about x) and pitch `θ` (about y). A point (x, y) of a body with mass centre (x_b, y_b)
//! moves up by `w + φ·(y − y_b) − θ·(x − x_b)` (small rotations). A suspension's vertical
//! spring `k_z` at (x, y) between lower body L and upper body U has the compression
//! `N = −k_z·(u_U − u_L)`; its roll and pitch springs (`k_rot`) and the anti-roll bars act on
//! the relative rotations. Gravity `m·g` acts down at every mass centre. Wheelsets are held,
//! so the stiffness matrix assembled on the free bodies is positive definite as soon as
//! every free body is held in heave, roll and pitch; it is solved by Cholesky.
//!
//! A wheelset's wheels then carry its own weight plus the forces of the suspensions on it,
//! shared between the left and right contact points (±b) by the roll moment:
//! `Q_left − Q_right = (Σ N·(y − y_ws) − M_bar)/b`.

use super::definition::VehicleDef;

/// The static state: compression of each suspension (N, normalized order) and the load of
/// each wheel (left, right per wheelset, N).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticState {
    /// Compressive force of each suspension's vertical spring (N).
    pub suspension: Vec<f64>,
    /// Wheel loads, left then right per wheelset (N).
    pub wheels: Vec<f64>,
}

/// The static state under gravity `g` (m/s²) of a validated, normalized definition; the
/// contact offset `b` of each wheelset is given. `Err` names a body the springs do not hold.
pub fn solve(v: &VehicleDef, g: f64, contact_offsets: &[f64]) -> Result<StaticState, String> {
    let n = v.bodies.len();
    let held: Vec<bool> = (0..n)
        .map(|i| v.wheelsets.iter().any(|w| w.body == v.bodies[i].name))
        .collect();
    // Unknown numbers of free bodies.
    let mut index = vec![usize::MAX; n];
    let mut m = 0;
    for i in 0..n {
        if !held[i] {
            index[i] = m;
            m += 3;
        }
    }
    let mut k = vec![0.0; m * m];
    let mut f = vec![0.0; m];
    // Row of a point's vertical displacement in terms of body i's unknowns.
    let shape = |i: usize, x: f64, y: f64| -> [f64; 3] {
        let b = &v.bodies[i];
        [1.0, y - b.y, -(x - b.x)]
    };
    // Adds `kk·(a·q)(a·q)` for a relative measure `a·q` (entries (body, coefficients)).
    let add = |k: &mut Vec<f64>, kk: f64, terms: &[(usize, [f64; 3])]| {
        for (bi, ai) in terms {
            if held[*bi] {
                continue;
            }
            for (bj, aj) in terms {
                if held[*bj] {
                    continue;
                }
                for r in 0..3 {
                    for c in 0..3 {
                        k[(index[*bi] + r) * m + index[*bj] + c] += kk * ai[r] * aj[c];
                    }
                }
            }
        }
    };
    let body = |name: &str| v.body_index(name).expect("validated");
    for s in &v.suspensions {
        let (lo, up) = (body(&s.lower), body(&s.upper));
        let (sl, su) = (shape(lo, s.at[0], s.at[1]), shape(up, s.at[0], s.at[1]));
        add(&mut k, s.k[2], &[(up, su), (lo, sl.map(|a| -a))]);
        add(
            &mut k,
            s.k_rot[0],
            &[(up, [0.0, 1.0, 0.0]), (lo, [0.0, -1.0, 0.0])],
        );
        add(
            &mut k,
            s.k_rot[1],
            &[(up, [0.0, 0.0, 1.0]), (lo, [0.0, 0.0, -1.0])],
        );
    }
    for a in &v.anti_roll_bars {
        let (lo, up) = (body(&a.lower), body(&a.upper));
        add(
            &mut k,
            a.k_roll,
            &[(up, [0.0, 1.0, 0.0]), (lo, [0.0, -1.0, 0.0])],
        );
    }
    for i in 0..n {
        if !held[i] {
            f[index[i]] = -v.bodies[i].mass * g;
        }
    }
    let q = cholesky_solve(&mut k, &mut f, m).map_err(|row| {
        let bi = index.iter().position(|&s| s != usize::MAX && s == row / 3 * 3);
        let name = bi.map_or("?", |i| v.bodies[i].name.as_str());
        format!(
            "body \"{name}\" is not held in {} by the suspensions and anti-roll bars, so their static preloads cannot be found; join it with vertical springs at two or more points, or give every suspension its `carries`",
            ["heave", "roll", "pitch"][row % 3]
        )
    })?;
    let disp = |i: usize, x: f64, y: f64| -> f64 {
        if held[i] {
            return 0.0;
        }
        let a = shape(i, x, y);
        (0..3).map(|r| a[r] * q[index[i] + r]).sum()
    };
    let roll = |i: usize| if held[i] { 0.0 } else { q[index[i] + 1] };
    let mut suspension = Vec::new();
    for s in &v.suspensions {
        let (lo, up) = (body(&s.lower), body(&s.upper));
        let d = disp(up, s.at[0], s.at[1]) - disp(lo, s.at[0], s.at[1]);
        suspension.push(-s.k[2] * d);
    }
    let mut wheels = Vec::new();
    for (w, b) in v.wheelsets.iter().zip(contact_offsets) {
        let i = body(&w.body);
        let yb = v.bodies[i].y;
        let mut total = v.bodies[i].mass * g;
        let mut moment = 0.0;
        for (s, n) in v.suspensions.iter().zip(&suspension) {
            // Compression pushes the lower body down and the upper body up.
            let sign = if body(&s.lower) == i {
                1.0
            } else if body(&s.upper) == i {
                -1.0
            } else {
                continue;
            };
            total += sign * n;
            moment += sign * n * (s.at[1] - yb);
            let other = if sign > 0.0 {
                body(&s.upper)
            } else {
                body(&s.lower)
            };
            // Its roll spring's moment on the wheelset about x: k·(φ_other − φ_ws).
            moment -= s.k_rot[0] * (roll(other) - roll(i));
        }
        for a in &v.anti_roll_bars {
            let other = if body(&a.lower) == i {
                body(&a.upper)
            } else if body(&a.upper) == i {
                body(&a.lower)
            } else {
                continue;
            };
            // The bar's moment on the wheelset about x: k·(φ_other − φ_ws).
            moment -= a.k_roll * (roll(other) - roll(i));
        }
        let diff = moment / b;
        wheels.push(0.5 * (total + diff));
        wheels.push(0.5 * (total - diff));
    }
    Ok(StaticState { suspension, wheels })
}

/// Solves `K q = f` in place for a symmetric positive definite `K` (n × n, row major);
/// `Err(row)` where a pivot is not positive (the unknown not held).
fn cholesky_solve(k: &mut [f64], f: &mut [f64], n: usize) -> Result<Vec<f64>, usize> {
    let scale = (0..n).map(|i| k[i * n + i].abs()).fold(0.0, f64::max);
    for j in 0..n {
        let mut d = k[j * n + j];
        for p in 0..j {
            d -= k[j * n + p] * k[j * n + p];
        }
        if d.is_nan() || d <= 1e-12 * scale {
            return Err(j);
        }
        let d = d.sqrt();
        k[j * n + j] = d;
        for i in j + 1..n {
            let mut s = k[i * n + j];
            for p in 0..j {
                s -= k[i * n + p] * k[j * n + p];
            }
            k[i * n + j] = s / d;
        }
    }
    for i in 0..n {
        let mut s = f[i];
        for p in 0..i {
            s -= k[i * n + p] * f[p];
        }
        f[i] = s / k[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = f[i];
        for p in i + 1..n {
            s -= k[p * n + i] * f[p];
        }
        f[i] = s / k[i * n + i];
    }
    Ok(f.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::vehicle::CarriageData;

    /// The sks700 carriage is statically determinate by symmetry: each secondary carries
    /// a quarter of the car body, each axle box an eighth of car body and bogies, each wheel
    /// an eighth of the whole carriage (hand statics).
    #[test]
    fn carriage_statics_follow_the_share_rule() {
        let c = CarriageData {
            anti_roll: 2e6,
            ..CarriageData::sks700()
        };
        let v = c.expand();
        let g = 9.81;
        let st = solve(&v, g, &[0.75; 4]).expect("solvable");
        for (s, n) in v.suspensions.iter().zip(&st.suspension) {
            let want = s.carries.expect("template sets it") * g;
            assert!(
                (n - want).abs() < 1e-9 * want,
                "{:?}: {n} vs {want}",
                s.name
            );
        }
        let w = c.total_mass() * g / 8.0;
        for q in &st.wheels {
            assert!((q - w).abs() < 1e-9 * w, "{q} vs {w}");
        }
    }

    /// An eccentric car body on one wheelset of two springs at ±a: the springs share its
    /// weight by the lever rule, N_left = W·(a + e)/(2a), and the wheels (at ±b) carry
    /// `(W + m_ws g)/2 ± W·e/(2b)`.
    #[test]
    fn lever_rule_for_an_eccentric_body() {
        use crate::rail::vehicle::definition::*;
        let (a, e, b, m, mw, g) = (1.0, 0.2, 0.75, 1000.0, 500.0, 10.0);
        let body = |name: &str, mass: f64, y: f64, z: f64| BodyDef {
            name: name.into(),
            mass,
            ixx: 1.0,
            iyy: 1.0,
            izz: 1.0,
            ixy: 0.0,
            ixz: 0.0,
            iyz: 0.0,
            x: 0.0,
            y,
            z,
        };
        let spring = |y: f64, x: f64| SuspensionDef {
            name: None,
            lower: "ws".into(),
            upper: "car".into(),
            at: [x, y, 0.6],
            k: [1e5, 1e5, 1e5],
            c: [0.0; 3],
            k_rot: [0.0; 3],
            c_rot: [0.0; 3],
            mirror: false,
            carries: None,
            force_table: None,
            bump_stop: None,
        };
        // Two springs at each side (x = ±1) so that the body is held in pitch too.
        let v = VehicleDef {
            description: String::new(),
            length: 5.0,
            coupler_body: None,
            bodies: vec![body("car", m, e, 1.0), body("ws", mw, 0.0, 0.4)],
            suspensions: vec![
                spring(a, 1.0),
                spring(a, -1.0),
                spring(-a, 1.0),
                spring(-a, -1.0),
            ],
            anti_roll_bars: vec![],
            wheelsets: vec![WheelsetDef {
                body: "ws".into(),
                contact_offset: None,
                wheel: Default::default(),
                defects: Default::default(),
            }],
            sensors: vec![],
        };
        let st = solve(&v, g, &[b]).expect("solvable");
        let w = m * g;
        let left = w * (a + e) / (2.0 * a) / 2.0;
        assert!(
            (st.suspension[0] - left).abs() < 1e-9 * w,
            "{:?}",
            st.suspension
        );
        let ql = 0.5 * (w + mw * g) + w * e / (2.0 * b);
        assert!((st.wheels[0] - ql).abs() < 1e-9 * w, "{:?}", st.wheels);
        assert!((st.wheels[0] + st.wheels[1] - (w + mw * g)).abs() < 1e-9 * w);
    }
}
