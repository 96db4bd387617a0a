//! The coefficients of an effective matrix `K_eff = k·K + m·M + c·C`: what a time
//! integrator hands the assembly and the linear solvers, as one typed value instead of three
//! numbers in an order each caller must remember.
//!
//! An implicit integrator linearises its balance in the displacement increment `Δu`; the
//! tangent of `M·a + C·v + f_int(u)` with respect to `Δu` is `k·K + m·M + c·C`, where `k`,
//! `m` and `c` are `∂u/∂Δu`, `∂a/∂Δu` and `∂v/∂Δu` weighted by where the balance is
//! enforced (see `railfem_solvers::integrator`). A static step is [`Coefficients::STATIC`],
//! the initial acceleration's mass solve [`Coefficients::MASS`].

/// Coefficients of `K_eff = k·K + m·M + c·C`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// Weight of the stiffness `K` (1/1).
    pub k: f64,
    /// Weight of the mass `M` (1/s²).
    pub m: f64,
    /// Weight of the damping `C` (1/s).
    pub c: f64,
}

impl Coefficients {
    /// `K` alone: a static Newton step.
    pub const STATIC: Coefficients = Coefficients {
        k: 1.0,
        m: 0.0,
        c: 0.0,
    };

    /// `M` alone: the mass matrix (the initial acceleration's solve, modal analysis).
    pub const MASS: Coefficients = Coefficients {
        k: 0.0,
        m: 1.0,
        c: 0.0,
    };

    /// The three weights in the order `[k, m, c]`, as a key that identifies the values of an
    /// effective matrix formed from constant `K`, `M` and `C` (a factor cache compares it).
    pub fn key(self) -> [f64; 3] {
        [self.k, self.m, self.c]
    }

    /// The weighted terms `(weight, matrix)` in the order `k, m, c`.
    pub fn weigh<T>(self, k: T, m: T, c: T) -> [(f64, T); 3] {
        [(self.k, k), (self.m, m), (self.c, c)]
    }
}
