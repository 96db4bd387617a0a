//! The data check before a run: everything `railfem run` verifies before its first step,
//! so that `railfem check` can verify the same without running (Abaqus's `datacheck`).
//!
//! [`Driver::preflight`] works on a driver that is built (model read, elements built,
//! equations numbered, the pattern and the constant matrices assembled) and adds what no
//! earlier stage sees:
//!
//! - **structural singularity**: an equation without stiffness where the first solve needs
//!   it, found from the constant matrices' diagonals and the variable elements' declared
//!   connectivity, without a factorization (below);
//! - **conditional stability** of a Newmark pair outside the unconditionally stable range,
//!   with the Δt limit for the model's highest frequency (a warning; [`newmark_limit`]);
//! - the **size** of the model: nodes, elements, equations, entries of K, the memory of the
//!   matrices and (for `check`) of the factor, and the number of steps.
//!
//! What is singular depends on the analysis. The first matrix factored is `K` for a static
//! or modal analysis and for the initial static equilibrium of a transient that has loads
//! at t = 0; otherwise it is `K_eff = c_K·K + c_M·M + c_C·C`. For a positive semi-definite
//! matrix a zero diagonal means a zero row and column, so an equation whose diagonal is zero
//! in every matrix that enters is singular whatever the other equations do: a free rotation
//! without stiffness but with rotary inertia is fine in a transient and singular in a static
//! analysis. "Zero" is below 1e-14 of the largest diagonal of the same DOF kind
//! (translations, rotations) — round-off of a rotated zero stiffness, not a soft spring. An
//! equation a variable element (moving, nonlinear) touches counts as stiff: its matrices
//! are not known before the element is evaluated. Mechanisms spread over several
//! equations (an unsupported beam) are not seen here; the factorization names them, and
//! `railfem check` runs it too on models up to a size ([`crate::mechanism`]).

use crate::driver::{Driver, DIRECT_DENSE_LIMIT};
use crate::linear::{cholesky_factor_entries, LinearSolver, SparseCholesky};
use railfem_framework::error::FemError;
use railfem_framework::model::{AnalysisKind, IntegratorKind};
use railfem_framework::sparse::CscMatrix;

/// Relative size below which a diagonal counts as zero (see the module documentation).
pub const ZERO_DIAGONAL: f64 = 1e-14;

/// The size of a model, as `railfem check` prints it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ModelSize {
    /// Nodes (internal ones included).
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Equations (free DOFs).
    pub equations: usize,
    /// Stored entries of the global pattern (K, M and C share it).
    pub nonzeros: usize,
    /// Bytes of the assembled global matrices the run keeps.
    pub matrix_bytes: usize,
    /// Entries of the direct solver's factor (symbolic analysis), when estimated.
    pub factor_entries: Option<usize>,
    /// Steps of the analysis (load steps, time steps; 1 for modal).
    pub steps: usize,
}

impl ModelSize {
    /// Bytes of the factor: 8 per entry (dense for small systems), when estimated.
    pub fn factor_bytes(&self) -> Option<usize> {
        self.factor_entries.map(|e| e * 8)
    }
}

/// What [`Driver::preflight`] found short of an error.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Preflight {
    /// The model's size.
    pub size: ModelSize,
    /// Warnings (one line each): accepted, but the user should know.
    pub warnings: Vec<String>,
}

/// Newmark's stability limit `Ω = ω·Δt` for `(β, γ)`, undamped: `None` when the pair is
/// stable for every Δt (`2β ≥ γ ≥ ½`), else `Ω_crit = 1/√(γ/2 − β)` (Hughes 1987,
/// Table 9.1.1, with ξ = 0; damping only raises it).
pub fn newmark_limit(beta: f64, gamma: f64) -> Option<f64> {
    (2.0 * beta < gamma).then(|| 1.0 / (0.5 * gamma - beta).sqrt())
}

/// Whether `(β, γ)` lies in the unconditionally stable range with the high frequencies
/// damped monotonically: `γ ≥ ½` and `β ≥ (γ + ½)²/4`.
pub fn newmark_unconditional(beta: f64, gamma: f64) -> bool {
    gamma >= 0.5 && beta >= 0.25 * (gamma + 0.5).powi(2) - 1e-15
}

fn human_bytes(b: usize) -> String {
    let b = b as f64;
    match b {
        _ if b >= 1e9 => format!("{:.2} GB", b / 1e9),
        _ if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        _ if b >= 1e3 => format!("{:.1} kB", b / 1e3),
        _ => format!("{b} B"),
    }
}

impl std::fmt::Display for ModelSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} nodes, {} elements, {} equations, {} nonzeros in K, matrices {}",
            self.nodes,
            self.elements,
            self.equations,
            self.nonzeros,
            human_bytes(self.matrix_bytes)
        )?;
        if let Some(b) = self.factor_bytes() {
            write!(f, ", factor ≈ {}", human_bytes(b))?;
        }
        write!(f, ", {} steps", self.steps)
    }
}

/// The principal submatrix of `a` on the equations with `keep[i]`, renumbered.
fn principal(a: &CscMatrix, keep: &[bool]) -> (CscMatrix, Vec<usize>) {
    let mut new = vec![usize::MAX; a.n];
    let mut old = Vec::new();
    for (i, k) in keep.iter().enumerate() {
        if *k {
            new[i] = old.len();
            old.push(i);
        }
    }
    let mut t = Vec::new();
    for j in 0..a.n {
        if new[j] == usize::MAX {
            continue;
        }
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            let i = a.row_idx[p];
            if new[i] != usize::MAX {
                t.push((new[i], new[j], a.values[p]));
            }
        }
    }
    (CscMatrix::from_triplets(old.len(), &t), old)
}

/// Estimate of the largest `ω` of `K·φ = ω²·M·φ` on the equations that have mass, by
/// power iteration on `M⁻¹K` (40 iterations, Rayleigh quotient). Equations without mass
/// are dropped with their rows of K (which only raises the estimate: the massless DOFs
/// condensed out soften the rest). The iteration converges from below; `None` if M cannot
/// be factored.
pub fn highest_frequency(k: &CscMatrix, m: &CscMatrix) -> Option<f64> {
    let scale = (0..m.n).map(|i| m.get(i, i)).fold(0.0f64, f64::max);
    let keep: Vec<bool> = (0..m.n)
        .map(|i| m.get(i, i) > ZERO_DIAGONAL * scale)
        .collect();
    let (ks, _) = principal(k, &keep);
    let (ms, _) = principal(m, &keep);
    let n = ks.n;
    if n == 0 {
        return None;
    }
    let mut chol = SparseCholesky::new();
    chol.factor(&ms).ok()?;
    // A start vector with every component and no symmetry (not an eigenvector).
    let mut x: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 101) as f64 / 101.0)
        .collect();
    let mut lambda = 0.0;
    let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..40 {
        ks.mul_vec(&x, &mut kx);
        ms.mul_vec(&x, &mut mx);
        let num: f64 = x.iter().zip(&kx).map(|(a, b)| a * b).sum();
        let den: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
        // M is positive definite here (factored above), so only NaN fails this.
        if den.is_nan() || den <= 0.0 {
            return None;
        }
        lambda = num / den;
        chol.solve_in_place(&mut kx).ok()?;
        let norm = kx.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        x.iter_mut().zip(&kx).for_each(|(a, b)| *a = b / norm);
    }
    (lambda.is_finite() && lambda > 0.0).then(|| lambda.sqrt())
}

impl Driver {
    /// Whether the first factorization of a run is one of `K` alone: a static or modal
    /// analysis, or the initial static equilibrium of a transient with loads at t = 0.
    pub(crate) fn static_first(&mut self) -> Result<bool, FemError> {
        let spec = self.model.analysis.clone();
        Ok(match spec.kind {
            AnalysisKind::Static | AnalysisKind::Modal => true,
            AnalysisKind::Transient => {
                spec.initial_static && {
                    let mut f = vec![0.0; self.neq()];
                    self.asm.external_force(&self.model, 0.0, 1.0, &mut f)?;
                    f.iter().any(|v| *v != 0.0)
                }
            }
        })
    }

    /// The checks every run makes before its first step (module documentation). Problems
    /// come back as one error ([`FemError::Many`] for several, each naming its node and
    /// DOF); warnings and the size in the [`Preflight`]. `estimate_factor` adds the direct
    /// solver's factor size (a symbolic analysis: cheap, but not free at a million
    /// equations).
    pub fn preflight(&mut self, estimate_factor: bool) -> Result<Preflight, FemError> {
        let spec = self.model.analysis.clone();
        let n = self.neq();
        let static_first = self.static_first()?;
        // The diagonals of the constant matrices (no copy of them: at a million equations
        // one is hundreds of MB; a rank of a shared model holds only some columns, and the
        // whole diagonals); the variable elements are accounted for by their connectivity.
        let k = &self.asm.k_const;
        let [kd, md, cd] = self
            .asm
            .constant_diagonals()
            .map(|d| d.into_iter().map(f64::abs).collect::<Vec<f64>>());
        let (var, var_mass) = self.asm.variable_cover();
        // Largest diagonal per DOF kind (translation, rotation) for the "zero" threshold.
        let kind = |i: usize| usize::from(self.asm.dofmap.dof_of(i).1.index() >= 3);
        let mut top = [[0.0f64; 2]; 3];
        for i in 0..n {
            for (t, d) in top.iter_mut().zip([&kd, &md, &cd]) {
                t[kind(i)] = t[kind(i)].max(d[i]);
            }
        }
        let nonzero =
            |d: &[f64], which: usize, i: usize| d[i] > ZERO_DIAGONAL * top[which][kind(i)];
        let mut problems = Vec::new();
        for i in 0..n {
            let stiff = var[i] || nonzero(&kd, 0, i);
            let inertial = var[i] || var_mass[i] || nonzero(&md, 1, i) || nonzero(&cd, 2, i);
            let (node, d) = self.asm.dofmap.dof_of(i);
            let name = self.model.dof_name(node, d);
            if static_first && !stiff {
                let why = match (spec.kind, inertial) {
                    (AnalysisKind::Transient, true) => " (it has mass, but the initial static equilibrium under the t = 0 loads needs stiffness; or set `initial_static = false`)",
                    (AnalysisKind::Transient, false) => " (the initial static equilibrium under the t = 0 loads needs it)",
                    (_, true) => " (it has mass only; a static or modal analysis needs stiffness)",
                    _ => "",
                };
                problems.push(FemError::Singular(format!(
                    "{}: no stiffness at {name} (equation {i}){why}: a mechanism (a zero-energy mode); fix that DOF, connect it to an element, or add a spring",
                    self.model.origin
                )));
            } else if !static_first && !stiff && !inertial {
                problems.push(FemError::Singular(format!(
                    "{}: no stiffness, mass or damping at {name} (equation {i}); fix that DOF, connect it to an element, or add a spring or a mass",
                    self.model.origin
                )));
            }
        }
        FemError::from_list(problems)?;
        let mut warnings = Vec::new();
        if spec.kind == AnalysisKind::Transient
            && spec.integrator == IntegratorKind::Newmark
            && !newmark_unconditional(spec.beta, spec.gamma)
        {
            warnings.push(self.newmark_warning());
        }
        let steps = match spec.kind {
            AnalysisKind::Static => spec.steps,
            AnalysisKind::Modal => 1,
            AnalysisKind::Transient => {
                let s = (spec.duration / spec.dt - 1e-9).ceil().max(1.0);
                if s < usize::MAX as f64 {
                    s as usize
                } else {
                    usize::MAX
                }
            }
        };
        // The assembler keeps K, M, C (and the variable parts on the pattern); the driver
        // one effective matrix: values and row indices, 16 bytes per entry.
        let a = &self.asm;
        let stored = [
            &a.k_const, &a.m_const, &a.c_const, &a.k_var, &a.m_var, &a.c_var,
        ]
        .iter()
        .map(|m| m.nnz() * 16 + m.col_ptr.len() * 8)
        .sum::<usize>()
            + k.nnz() * 16;
        let factor_entries = if !estimate_factor || a.off_pattern() {
            None
        } else if n <= DIRECT_DENSE_LIMIT {
            Some(n * n)
        } else {
            cholesky_factor_entries(k).ok()
        };
        Ok(Preflight {
            size: ModelSize {
                nodes: self.model.nodes.len(),
                elements: self.model.elements.len(),
                equations: n,
                nonzeros: k.nnz(),
                matrix_bytes: stored,
                factor_entries,
                steps,
            },
            warnings,
        })
    }

    /// The warning for a Newmark pair outside the unconditionally stable range, with the
    /// Δt limit for the model's highest frequency (constant matrices).
    fn newmark_warning(&self) -> String {
        let spec = &self.model.analysis;
        let (beta, gamma, dt) = (spec.beta, spec.gamma, spec.dt);
        let head = format!(
            "{}: [analysis] Newmark beta = {beta}, gamma = {gamma} is outside the unconditionally stable range (gamma ≥ 1/2, beta ≥ (gamma + 1/2)²/4 = {:.6})",
            self.model.origin,
            0.25 * (gamma + 0.5).powi(2)
        );
        let Some(omega_crit) = newmark_limit(beta, gamma) else {
            return format!(
                "{head}: stable for every Δt since 2·beta ≥ gamma, but high frequencies are not damped monotonically; beta = 0.25, gamma = 0.5 is the default"
            );
        };
        // A rank holding some columns of K and M cannot estimate it alone.
        let whole = !self.asm.constant_columns_kept();
        match whole
            .then(|| highest_frequency(&self.asm.k_const, &self.asm.m_const))
            .flatten()
        {
            Some(w) => {
                let limit = omega_crit / w;
                let verdict = if dt > limit {
                    format!("Δt = {dt} s is ABOVE it: the run will grow without bound")
                } else {
                    format!("Δt = {dt} s is below it")
                };
                format!(
                    "{head}: stable only for ω·Δt ≤ {omega_crit:.4}; the highest frequency of the constant matrices is ω ≈ {w:.4e} rad/s (power iteration), so Δt ≤ {limit:.4e} s; {verdict}; use beta = 0.25, gamma = 0.5 or a smaller `dt`"
                )
            }
            None => format!(
                "{head}: stable only for ω·Δt ≤ {omega_crit:.4} (ω the highest frequency; it could not be estimated: {}); use beta = 0.25, gamma = 0.5",
                if whole {
                    "the mass matrix is not positive definite on its DOFs"
                } else {
                    "each rank holds only its columns of K and M"
                }
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central difference (β = 0 limit) has Ω_crit = 2; Fox–Goodwin (β = 1/12) √6;
    /// linear acceleration (β = 1/6) 2√3 — the classical values.
    #[test]
    fn newmark_limits_are_the_classical_ones() {
        assert!((newmark_limit(1e-300, 0.5).unwrap() - 2.0).abs() < 1e-12);
        assert!((newmark_limit(1.0 / 12.0, 0.5).unwrap() - 6f64.sqrt()).abs() < 1e-12);
        assert!((newmark_limit(1.0 / 6.0, 0.5).unwrap() - 12f64.sqrt()).abs() < 1e-12);
        assert_eq!(newmark_limit(0.25, 0.5), None);
        assert!(newmark_unconditional(0.25, 0.5));
        assert!(!newmark_unconditional(0.3, 0.7));
        assert!(newmark_unconditional(0.36, 0.7));
    }

    /// Two masses m on springs k (ground–1–2): ω² = (3 ± √5)/2 · k/m, the largest
    /// ω = √((3 + √5)/2 · k/m).
    #[test]
    fn power_iteration_finds_the_highest_frequency_of_a_chain() {
        let (k, m) = (4.0e6, 2.0);
        let kk = CscMatrix::from_triplets(2, &[(0, 0, 2.0 * k), (0, 1, -k), (1, 0, -k), (1, 1, k)]);
        let mm = CscMatrix::from_triplets(2, &[(0, 0, m), (1, 1, m)]);
        let w = highest_frequency(&kk, &mm).unwrap();
        let exact = ((3.0 + 5f64.sqrt()) / 2.0 * k / m).sqrt();
        assert!((w - exact).abs() < 1e-9 * exact, "{w} vs {exact}");
    }
}
