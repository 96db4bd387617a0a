//! Kalker's FASTSIM: the creep forces of his simplified theory of rolling contact on an
//! elliptic patch, with the exact gradient of the discrete algorithm (on [`D4`] numbers).
//!
//! **Theory** (J.J. Kalker, "A fast algorithm for the simplified theory of rolling
//! contact", Vehicle System Dynamics 11 (1982) 1–13; the three-flexibility form of
//! Kalker's book, *Three-dimensional elastic bodies in rolling contact*, 1990, §2.3.4).
//! The surface displacement is `u = L·p` with one flexibility per direction. In steady
//! rolling along −x (the leading edge at `x = +a(y)`), where the contact adheres the slip
//! vanishes, `∂p/∂x = w/L` with the rigid slip `w_x = ξx − φ·y`, `w_y = ξy + φ·x`; where
//! the traction would exceed the bound `g = μ·p_z` it slides at the bound. Integrating
//! from the leading edge (`p = 0`) gives, in full adhesion, `Fx = −(8a²b/3)·ξx/L1` and
//! `Fy = −(8a²b/3)·ξy/L2 − (πa³b/4)·φ/L3`; equal to Kalker's linear theory
//! (`−G·a·b·C11·ξx`, `−G·a·b·C22·ξy − G·(ab)^{3/2}·C23·φ`, [`super::kalker`]) for
//! `L1 = 8a/(3·G·C11)`, `L2 = 8a/(3·G·C22)`, `L3 = π·a·√(a/b)/(4·G·C23)` (Kalker 1982).
//!
//! **Discretisation.** `strips` strips of equal width `2b/strips` across the patch, each
//! cut into `elements` elements of equal length `2a(y)/elements` with
//! `a(y) = a·√(1 − y²/b²)` at the strip's centre line. Per strip the traction is marched
//! node by node from the leading edge: `p ← p − Δx·(w_x/L1 − …)` with `w` at the element's
//! centre, then projected onto the disc `|p| ≤ g` at the node; the force is the trapezoidal
//! sum. The traction bound is Kalker's parabolic one, `p_z = p0·(1 − x²/a² − y²/b²)` (the
//! pressure of the simplified theory itself). Two choices make the discrete law meet its
//! limits exactly rather than to the quadrature error:
//! - `p0` is set so that the *discrete* pressure carries `N` (so full sliding in one
//!   direction gives `μN` to rounding, not to `O(1/elements²)`);
//! - the constants `8/3` and `π/4` in `L1, L2, L3` are replaced by the same quadrature's
//!   sums ([`PatchSums`]) in full adhesion, so the small-creepage limit is Kalker's linear
//!   theory to rounding. Both sums tend to the continuous constants as the grid is refined
//!   (checked in the tests).
//!
//! **Gradient.** Every operation is carried out on [`D4`] numbers, so the forces come with
//! their exact derivatives with respect to `(ξx, ξy, φ, N)` for the current set of sliding
//! nodes; the law is continuous, with kinks where a node changes between adhesion and slip.

use super::dual::D4;
use super::kalker::CreepCoefficients;

/// The patch discretisation of FASTSIM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FastsimGrid {
    /// Strips across the patch (lateral direction).
    pub strips: usize,
    /// Elements per strip (rolling direction).
    pub elements: usize,
}

impl FastsimGrid {
    /// Fewest strips or elements accepted (below, the patch is a caricature).
    pub const MIN: usize = 2;
    /// Most strips or elements accepted (the cost grows as their product).
    pub const MAX: usize = 400;
    /// The `moving_axle` default: 20 × 20 elements.
    pub const DEFAULT: FastsimGrid = FastsimGrid {
        strips: 20,
        elements: 20,
    };
}

/// Discrete sums of the patch quadrature in coordinates scaled by the semi-axes
/// (`a = b = 1`): the adhesion force per unit `w/L` (`k_creep → 8/3`), the adhesion
/// lateral force per unit spin (`k_spin → π/4`) and the integral of the parabolic bound
/// shape (`k_load → π/2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchSums {
    /// `Σ` of the adhesion traction of a unit creepage (→ 8/3).
    pub k_creep: f64,
    /// `Σ` of the adhesion lateral traction of a unit spin (→ π/4).
    pub k_spin: f64,
    /// `Σ` of `1 − x² − y²` over the nodes (→ π/2).
    pub k_load: f64,
}

/// Strip `j`'s centre line `η = y/b` and its half-length `√(1 − η²)` (scaled by `a`).
fn strip(grid: &FastsimGrid, j: usize) -> (f64, f64) {
    let eta = -1.0 + (2 * j + 1) as f64 / grid.strips as f64;
    (eta, (1.0 - eta * eta).sqrt())
}

/// Node `i`'s scaled position along a strip, `t = x/a(y)`, from the leading edge `t = 1`.
fn node_t(grid: &FastsimGrid, i: usize) -> f64 {
    1.0 - 2.0 * i as f64 / grid.elements as f64
}

impl PatchSums {
    /// The sums of `grid`, from the same march as [`fastsim`] in full adhesion (the
    /// trailing node, where the bound is zero, carries no traction there either).
    pub fn of(grid: &FastsimGrid) -> PatchSums {
        let (mut k_creep, mut k_spin, mut k_load) = (0.0, 0.0, 0.0);
        let dy = 2.0 / grid.strips as f64;
        let m = grid.elements;
        for j in 0..grid.strips {
            let (eta, s) = strip(grid, j);
            let dx = 2.0 * s / m as f64;
            let (mut pc, mut ps) = (0.0_f64, 0.0_f64);
            for i in 1..=m {
                let t_mid = 0.5 * (node_t(grid, i - 1) + node_t(grid, i));
                let (mut nc, mut ns) = (pc + dx, ps + dx * s * t_mid);
                if i == m {
                    (nc, ns) = (0.0, 0.0);
                }
                k_creep += 0.5 * (pc + nc) * dx * dy;
                k_spin += 0.5 * (ps + ns) * dx * dy;
                let shape = |t: f64| (1.0 - eta * eta) * (1.0 - t * t);
                k_load += 0.5 * (shape(node_t(grid, i - 1)) + shape(node_t(grid, i))) * dx * dy;
                (pc, ps) = (nc, ns);
            }
        }
        PatchSums {
            k_creep,
            k_spin,
            k_load,
        }
    }
}

/// FASTSIM's creep forces `(Fx, Fy)` on the wheel (N) for the semi-axes `(a, b)` (m) at
/// the current load, shear modulus `g` (Pa), Kalker's coefficients `c`, friction `mu` and
/// the inputs `[ξx, ξy, φ (1/m), N (N)]`, in the sign convention of Kalker's linear theory
/// (the force opposes the creepage).
pub fn fastsim(
    grid: &FastsimGrid,
    sums: &PatchSums,
    (a, b): (D4, D4),
    g: f64,
    c: &CreepCoefficients,
    mu: f64,
    [x, y, sp, n]: [D4; 4],
) -> (D4, D4) {
    // Flexibilities (module doc): L = k·a/(G·C), with the quadrature's sums for 8/3, π/4.
    let l1 = a * (sums.k_creep / (g * c.c11));
    let l2 = a * (sums.k_creep / (g * c.c22));
    let l3 = a * (a / b).sqrt() * (sums.k_spin / (g * c.c23));
    // Traction bound at a node: μ·p0·(1 − η²)(1 − t²), p0 so that the nodes carry N.
    let mu_p0 = n * mu / (a * b * sums.k_load);
    let m = grid.elements;
    let dy = b * (2.0 / grid.strips as f64);
    let (mut fx, mut fy) = (D4::c(0.0), D4::c(0.0));
    for j in 0..grid.strips {
        let (eta, s) = strip(grid, j);
        let dx = a * (2.0 * s / m as f64);
        // Slip terms constant along the strip, per unit length rolled and divided by L.
        let gx = x / l1 - sp * b * eta / l3;
        let (gy, gspin) = (y / l2, sp * a * s / l3);
        let (mut px, mut py) = (D4::c(0.0), D4::c(0.0));
        let (mut sx, mut sy) = (D4::c(0.0), D4::c(0.0));
        for i in 1..=m {
            let t_mid = 0.5 * (node_t(grid, i - 1) + node_t(grid, i));
            let mut nx = px - dx * gx;
            let mut ny = py - dx * (gy + gspin * t_mid);
            let t = node_t(grid, i);
            let bound = (1.0 - eta * eta) * (1.0 - t * t);
            if i == m || bound <= 0.0 {
                (nx, ny) = (D4::c(0.0), D4::c(0.0));
            } else {
                let limit = mu_p0 * bound;
                let mag2 = nx * nx + ny * ny;
                if mag2.v > limit.v * limit.v {
                    let k = limit / mag2.sqrt();
                    (nx, ny) = (nx * k, ny * k);
                }
            }
            sx = sx + (px + nx);
            sy = sy + (py + ny);
            (px, py) = (nx, ny);
        }
        fx = fx + sx * dx * 0.5;
        fy = fy + sy * dx * 0.5;
    }
    (fx * dy, fy * dy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::contact::creep::kalker::kalker_coefficients;
    use std::f64::consts::PI;

    fn run(grid: &FastsimGrid, ab: (f64, f64), c: &CreepCoefficients, inp: [f64; 4]) -> (D4, D4) {
        let sums = PatchSums::of(grid);
        let v: Vec<D4> = (0..4).map(|i| D4::var(inp[i], i)).collect();
        fastsim(
            grid,
            &sums,
            (D4::c(ab.0), D4::c(ab.1)),
            8.2e10,
            c,
            0.3,
            [v[0], v[1], v[2], v[3]],
        )
    }

    /// The quadrature's sums tend to the continuous constants 8/3, π/4, π/2: within
    /// 1/(2·strips²)-type errors (midpoint rule across the strips, trapezoid along them).
    #[test]
    fn patch_sums_converge_to_the_continuous_constants() {
        let mut prev = f64::INFINITY;
        for n in [10, 20, 40, 80, 160] {
            let s = PatchSums::of(&FastsimGrid {
                strips: n,
                elements: n,
            });
            let errs = [
                (s.k_creep / (8.0 / 3.0) - 1.0).abs(),
                (s.k_spin / (PI / 4.0) - 1.0).abs(),
                (s.k_load / (PI / 2.0) - 1.0).abs(),
            ];
            let worst = errs.iter().cloned().fold(0.0, f64::max);
            assert!(worst < 4.0 / n as f64, "n = {n}: {errs:?}");
            assert!(worst < prev, "n = {n}: no convergence");
            prev = worst;
        }
    }

    /// Small creepages (full adhesion but for the trailing node): Kalker's linear theory,
    /// `Fx = −G·a·b·C11·ξx`, `Fy = −G·a·b·C22·ξy − G·(ab)^{3/2}·C23·φ`, within 1 % (the
    /// brief's bound; the flexibilities from the quadrature's own sums make it 1e-9 here),
    /// for long, round and wide patches, each creepage alone and all three together.
    #[test]
    fn small_creepage_is_kalkers_linear_theory() {
        for (a, b) in [(8e-3, 4e-3), (5e-3, 5e-3), (3e-3, 7e-3)] {
            let c = kalker_coefficients(a / b, 0.28).unwrap();
            for grid in [
                FastsimGrid::DEFAULT,
                FastsimGrid {
                    strips: 7,
                    elements: 31,
                },
            ] {
                for inp in [
                    [1e-6, 0.0, 0.0, 8e4],
                    [0.0, -2e-6, 0.0, 8e4],
                    [0.0, 0.0, 1e-3, 8e4],
                    [1e-6, 2e-6, -1e-3, 8e4],
                ] {
                    let (fx, fy) = run(&grid, (a, b), &c, inp);
                    let g = 8.2e10;
                    let lx = -g * a * b * c.c11 * inp[0];
                    let ly = -g * a * b * c.c22 * inp[1] - g * (a * b).powf(1.5) * c.c23 * inp[2];
                    let scale = lx.abs().max(ly.abs());
                    assert!(
                        (fx.v - lx).abs() <= 0.01 * scale,
                        "{inp:?}: {} vs {lx}",
                        fx.v
                    );
                    assert!(
                        (fy.v - ly).abs() <= 0.01 * scale,
                        "{inp:?}: {} vs {ly}",
                        fy.v
                    );
                    assert!((fx.v - lx).abs() <= 1e-9 * scale && (fy.v - ly).abs() <= 1e-9 * scale);
                }
            }
        }
    }

    /// Large creepage: the resultant saturates at μN. With the linear force 200 to 1000
    /// times μN, |F| is within 0.5 % of μN (the brief's bound), in every direction and with
    /// a spin whose slip `φ·a` is at most 2.4 % of the creepage (a larger spin turns the
    /// sliding tractions across the patch and their resultant falls below μN: 0.6 % at
    /// ξ = 0.05, φ = 2 1/m, a = 6 mm, which is physics, not discretisation); pure translational creepage slides at every node in one direction, so |F| is
    /// μN to rounding there (the discrete pressure carries N exactly), opposite to
    /// `(C11·ξx, C22·ξy)` as in Shen–Hedrick–Elkins.
    #[test]
    fn large_creepage_saturates_at_mu_n() {
        let (a, b, n) = (6e-3, 4e-3, 1e5);
        let c = kalker_coefficients(a / b, 0.28).unwrap();
        let mu_n = 0.3 * n;
        for grid in [
            FastsimGrid::DEFAULT,
            FastsimGrid {
                strips: 9,
                elements: 13,
            },
        ] {
            for k in 0..8 {
                let ang = k as f64 * PI / 4.0 + 0.3;
                for mag in [0.5, 1.0] {
                    for spin in [0.0, 0.5, -2.0] {
                        let inp = [mag * ang.cos(), mag * ang.sin(), spin, n];
                        let (fx, fy) = run(&grid, (a, b), &c, inp);
                        let f = fx.v.hypot(fy.v);
                        assert!((f / mu_n - 1.0).abs() <= 0.005, "{inp:?}: |F| = {f}");
                        if spin == 0.0 {
                            assert!((f / mu_n - 1.0).abs() <= 1e-12, "{inp:?}: |F| = {f}");
                            // Opposite to the slip of the flexibilities, (ξx/L1, ξy/L2)
                            // ∝ (C11·ξx, C22·ξy): FASTSIM's direction at full sliding.
                            let (ux, uy) = (c.c11 * inp[0], c.c22 * inp[1]);
                            assert!((fx.v / f + ux / ux.hypot(uy)).abs() < 1e-9);
                        }
                    }
                }
            }
        }
    }

    /// The Hertzian reference case with lateral creepage and spin that ships with
    /// E. Vollebregt's CONTACT (examples/fastsim.inp and fastsim.ref_out, Apache-2.0;
    /// User guide §5.13): a = 8 mm, b = 4 mm, N = 82 kN, G = 82 GPa, ν = 0.28, μ = 0.3,
    /// ξ = 0, η = −0.000625, φ = 0.000625 1/mm. CONTACT's exact half-space solution gives
    /// Fy/(μN) = −0.6074. Its FASTSIM (three flexibilities, parabolic bound) gives −0.6118
    /// on 40 × 40 and −0.6359 on 200 × 200 elements in the patch: FASTSIM converges at first
    /// order (Vollebregt & Wilders, "FASTSIM2: a second-order accurate frictional rolling
    /// contact algorithm", Comput. Mech. 47 (2011) 105–116), so Richardson's extrapolation
    /// of the two, `(200·F200 − 40·F40)/160 = −0.6419`, is CONTACT's FASTSIM on an infinite
    /// grid. Here: our FASTSIM on 200 × 200 (traction projected at the nodes, trapezoidal
    /// sum: it converges faster, −0.6503 / −0.6489 / −0.6477 / −0.6475 on 50 / 100 / 400 /
    /// 800 in a script of the same march) within 1 % of that limit, and within 7 % of the
    /// exact value (measured +6.5 %: the simplified theory's own error with this much spin,
    /// which no grid removes); the default 20 × 20 grid within 2 % of the fine grid.
    #[test]
    fn hertzian_lateral_creep_and_spin_against_contact() {
        let (a, b, n) = (8e-3, 4e-3, 82e3);
        let c = kalker_coefficients(a / b, 0.28).unwrap();
        let inp = [0.0, -6.25e-4, 0.625, n];
        let fine = FastsimGrid {
            strips: 200,
            elements: 200,
        };
        let (fx, fy) = run(&fine, (a, b), &c, inp);
        let r = fy.v / (0.3 * n);
        let exact = -0.6074;
        let contact_limit = (200.0 * -0.6359 - 40.0 * -0.6118) / 160.0;
        eprintln!(
            "Fy/μN: fine {r:.4}, vs CONTACT FASTSIM extrapolated {contact_limit:.4} {:+.2} %, vs exact {:+.2} %",
            100.0 * (r / contact_limit - 1.0),
            100.0 * (r / exact - 1.0)
        );
        assert!(fx.v.abs() < 1e-9 * n);
        assert!((r / contact_limit - 1.0).abs() < 0.01, "{r}");
        assert!((r / exact - 1.0).abs() < 0.07, "{r}");
        let (_, fy20) = run(&FastsimGrid::DEFAULT, (a, b), &c, inp);
        let r20 = fy20.v / (0.3 * n);
        eprintln!("Fy/μN: 20 × 20 {r20:.4}");
        assert!((r20 / r - 1.0).abs() < 0.02, "{r20} vs {r}");
    }

    /// The gradient is the exact derivative of the discrete law: central differences
    /// agree to 1e-6 of the force scale at partial slip (away from a node's switch
    /// between adhesion and slip, which the small step does not cross here).
    #[test]
    fn gradient_matches_central_differences() {
        let (a0, b0, n0) = (6e-3, 4e-3, 5e4);
        let c = kalker_coefficients(a0 / b0, 0.28).unwrap();
        let grid = FastsimGrid::DEFAULT;
        let sums = PatchSums::of(&grid);
        // The semi-axes follow the load as in the element: a ∝ N^{1/3}.
        let eval = |inp: [f64; 4]| {
            let v: Vec<D4> = (0..4).map(|i| D4::var(inp[i], i)).collect();
            let s = (v[3] * (1.0 / n0)).cbrt();
            fastsim(
                &grid,
                &sums,
                (s * a0, s * b0),
                8.2e10,
                &c,
                0.3,
                [v[0], v[1], v[2], v[3]],
            )
        };
        for x0 in [
            [2e-4, -1e-4, 0.05, 4e4],
            [1.3e-3, 7e-4, -0.4, 6e4],
            [4e-3, 6e-3, 0.3, 5e4],
        ] {
            let (fx, fy) = eval(x0);
            let scale = fx.v.abs().max(fy.v.abs());
            for i in 0..4 {
                let h = 1e-7 * x0[i].abs();
                let (mut p, mut m) = (x0, x0);
                p[i] += h;
                m[i] -= h;
                let ((px, py), (mx, my)) = (eval(p), eval(m));
                for (d, hi, lo) in [(fx.d[i], px.v, mx.v), (fy.d[i], py.v, my.v)] {
                    let fd = (hi - lo) / (2.0 * h);
                    assert!(
                        (fd - d).abs() * x0[i].abs() < 1e-6 * scale,
                        "{x0:?} input {i}: {fd} vs {d}"
                    );
                }
            }
        }
    }
}
