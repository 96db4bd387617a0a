//! The conformance kit: mechanical checks every element kind must pass, run on the sample
//! states each kind provides ([`ElementKind::samples`]).
//!
//! What lives here: the eight checks ([`CHECKS`]), [`check_kind`] for one kind,
//! [`check_all`] for every registered kind (built-in and plugin) and the [`Report`] that
//! `railfem conformance` prints. What does not: the element kinds themselves and the
//! time-stepping driver (railfem-solvers depends on this crate, not the other way round, so
//! the energy check carries its own dense average-acceleration Newmark for the element's
//! DOFs — it keeps the kit independent of the solver it is meant to feed).
//!
//! Every sample is used *prepared*: built, then (if `committed_disp` is given) updated to
//! that displacement and committed, then updated to `disp` with velocities `vel` and zero
//! accelerations at time [`KIT_TIME`] with step [`KIT_DT`]. Checks that perturb a
//! path-dependent element call `revert` between perturbations so that they never move its
//! history. Each check is run under `catch_unwind`: a panicking element fails the check
//! instead of stopping the kit.
//!
//! The limits are public constants with their justification; the measured number is
//! reported beside pass/fail so a near miss is visible.
//!
//! **Large rotations.** For an element declaring `finite_rotations`, the rotational
//! perturbations of the tangent check are spins composed onto the nodal rotation (the
//! driver's update, [`crate::rotation`]), the energy check steps rotations the same way,
//! and the rigid-body check adds a finite rigid motion ([`FINITE_RIGID_ANGLE`] about a skew
//! axis plus [`FINITE_RIGID_SHIFT`]) of the reference and of the sample state, under which
//! the force must turn with the body. Such elements should give samples at strongly
//! deformed states (rotations of order 1 rad).

use crate::element::{Element, NodeKinematics, TrialState};
use crate::error::FemError;
use crate::registry::{self, BuildContext, ElementKind, ElementSpec, Sample};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Time of every trial state the kit sets (s).
pub const KIT_TIME: f64 = 0.0;
/// Step length of every trial state the kit sets outside the energy check (s).
pub const KIT_DT: f64 = 1e-3;

/// Tangent vs central differences, `max|K − K_fd| / max|K|`. Central differences with a
/// relative step `fd_step` (1e-6 typically) have truncation error `O(fd_step²)` and
/// round-off `≈ ε/fd_step ≈ 1e-10` relative; 1e-5 leaves four orders of margin for curved
/// elements while any wrong term of practical size (a sign, a missing geometric term) is
/// far above it.
pub const LIMIT_TANGENT: f64 = 1e-5;
/// Relative asymmetry `max|K − Kᵀ| / max|K|` of an element declaring `symmetric`: a
/// symmetric formula evaluated in floating point is symmetric to a few ulps.
pub const LIMIT_SYMMETRY: f64 = 1e-10;
/// Resisting force of a rigid motion relative to `max|K|·|motion|`. Translations are exact
/// up to round-off; the infinitesimal rotation `θ×(x − x0)` with `θ` = [`RIGID_THETA`] is
/// rigid only to first order, so geometrically nonlinear elements see `O(θ) = 1e-8` plus
/// round-off `ε/θ ≈ 2e-8` relative; 1e-6 keeps margin.
pub const LIMIT_RIGID: f64 = 1e-6;
/// Rotation angle of the rigid-rotation check (rad).
pub const RIGID_THETA: f64 = 1e-8;
/// Angle of the finite rigid rotation applied to elements that declare finite rotations
/// (rad), about the skew axis (1, −2, 0.5).
pub const FINITE_RIGID_ANGLE: f64 = 1.0;
/// Translation applied with it (m): large against any sample element.
pub const FINITE_RIGID_SHIFT: [f64; 3] = [40.0, -25.0, 12.0];
/// Mass matrix: asymmetry, negative eigenvalues and the error of the translational total
/// against `declared_mass`, all relative (round-off of sums of a few entries).
pub const LIMIT_MASS: f64 = 1e-12;
/// Energy balance of the small dynamic run, relative to the largest energy of the run. The
/// average-acceleration identity `ΔE_kin = −Σ ½(f_n + f_{n+1})·Δu` is exact for the
/// discrete equations, so the balance is violated only by the Newton residual (driven below
/// 1e-12 relative each step) and round-off over 50 steps: ≲ 1e-10. A tolerance of 1e-3
/// (enough for a time-discretisation error) would hide an inconsistent force or a broken
/// commit; 1e-8 does not.
pub const LIMIT_ENERGY: f64 = 1e-8;
/// Steps of the energy check.
pub const ENERGY_STEPS: usize = 50;

/// One check of the kit. Its name ([`Check::name`]) is the column of the table `railfem
/// conformance` prints; a failure line names the check and what its number measures
/// ([`Check::measure`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Check {
    /// Tangent against central differences of the resisting force ([`LIMIT_TANGENT`]).
    Tangent,
    /// Symmetry of the tangent of an element declaring `symmetric` ([`LIMIT_SYMMETRY`]).
    Symmetry,
    /// No force under a rigid-body motion ([`LIMIT_RIGID`]).
    RigidBody,
    /// Mass matrix symmetric, positive and of the declared total ([`LIMIT_MASS`]).
    Mass,
    /// `revert` restores the committed state exactly.
    Revert,
    /// The parameters survive a serde round trip.
    Serde,
    /// Force and tangent finite at the sample.
    Finite,
    /// Energy balance of a short dynamic run ([`LIMIT_ENERGY`]).
    Energy,
    /// The kind's sample generator itself (no samples, or it panicked): nothing else ran.
    Samples,
}

impl Check {
    /// The check's name as the table and the failure lines print it (`"rigid_body"`).
    pub fn name(self) -> &'static str {
        match self {
            Check::Tangent => "tangent",
            Check::Symmetry => "symmetry",
            Check::RigidBody => "rigid_body",
            Check::Mass => "mass",
            Check::Revert => "revert",
            Check::Serde => "serde",
            Check::Finite => "finite",
            Check::Energy => "energy",
            Check::Samples => "samples",
        }
    }

    /// What the check's measured number is, for the line of a failure: every number the
    /// kit compares with a limit is relative (dimensionless); a check that fails on
    /// something else (a dissipation that decreased, a non-finite value) says so in its
    /// note instead.
    pub fn measure(self) -> &'static str {
        match self {
            Check::Tangent => "relative difference from central differences",
            Check::Symmetry => "relative asymmetry",
            Check::RigidBody => "relative force under a rigid-body motion",
            Check::Mass => "relative mass error",
            Check::Revert => "relative difference after revert",
            Check::Serde => "relative difference after the serde round trip",
            Check::Energy => "relative energy-balance error",
            Check::Finite | Check::Samples => "relative measure",
        }
    }
}

impl std::fmt::Display for Check {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// A check compares equal to its name, so results can be looked up as
/// `r.check == "rigid_body"` as well as `r.check == Check::RigidBody`.
impl PartialEq<&str> for Check {
    fn eq(&self, other: &&str) -> bool {
        self.name() == *other
    }
}

/// The checks run on every sample, in table order.
pub const CHECKS: [Check; 8] = [
    Check::Tangent,
    Check::Symmetry,
    Check::RigidBody,
    Check::Mass,
    Check::Revert,
    Check::Serde,
    Check::Finite,
    Check::Energy,
];

/// Outcome of one check on one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// The check ran and passed.
    Pass,
    /// The check ran and failed (or could not run: see the note).
    Fail,
    /// The check does not apply (the element does not declare the property).
    Skipped,
}

/// The result of one check on one sample state of one kind.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckResult {
    /// Element type name.
    pub kind: String,
    /// Sample name (empty when the kind has no samples).
    pub sample: String,
    /// The check ([`CHECKS`], or [`Check::Samples`] when the kind could not be sampled).
    pub check: Check,
    /// Pass, fail or skipped.
    pub outcome: Outcome,
    /// The measured number (relative, dimensionless); NaN when not measured.
    pub value: f64,
    /// The limit it is compared with.
    pub limit: f64,
    /// Why it failed or was skipped, or extra numbers.
    pub note: String,
}

impl CheckResult {
    /// Whether the check did not fail.
    pub fn passed(&self) -> bool {
        self.outcome != Outcome::Fail
    }
}

/// Results of [`check_all`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Every result, grouped by kind and sample.
    pub results: Vec<CheckResult>,
}

impl Report {
    /// Whether no check failed.
    pub fn passed(&self) -> bool {
        self.results.iter().all(CheckResult::passed)
    }

    /// The failed checks.
    pub fn failures(&self) -> Vec<&CheckResult> {
        self.results.iter().filter(|r| !r.passed()).collect()
    }

    /// A text table: one row per element and sample, one column per check, each cell
    /// `ok <value>`, `FAIL <value>` or `-` (not applicable); then the notes of failures and
    /// a summary line.
    pub fn table(&self) -> String {
        let mut rows: Vec<(String, String)> = Vec::new();
        for r in &self.results {
            let key = (r.kind.clone(), r.sample.clone());
            if !rows.contains(&key) {
                rows.push(key);
            }
        }
        let w0 = rows
            .iter()
            .map(|(k, s)| k.len() + s.len() + 3)
            .max()
            .unwrap_or(10)
            .max(16);
        let mut out = format!("{:<w0$}", "element / sample");
        for c in CHECKS {
            out.push_str(&format!(" {c:<13}"));
        }
        out.push('\n');
        for (k, s) in &rows {
            let name = if s.is_empty() {
                k.clone()
            } else {
                format!("{k} / {s}")
            };
            out.push_str(&format!("{name:<w0$}"));
            let mine: Vec<&CheckResult> = self
                .results
                .iter()
                .filter(|r| &r.kind == k && &r.sample == s)
                .collect();
            if let Some(r) = mine.iter().find(|r| r.check == Check::Samples) {
                out.push_str(&format!(" FAIL  {}", r.note));
            } else {
                for c in CHECKS {
                    let cell = match mine.iter().find(|r| r.check == c) {
                        None => "?".to_string(),
                        Some(r) => match r.outcome {
                            Outcome::Skipped => "-".to_string(),
                            Outcome::Pass => format!("ok {}", num(r.value)),
                            Outcome::Fail => format!("FAIL {}", num(r.value)),
                        },
                    };
                    out.push_str(&format!(" {cell:<13}"));
                }
            }
            out.push('\n');
        }
        let fails = self.failures();
        for f in &fails {
            if f.check != Check::Samples {
                let measured = if f.value.is_nan() {
                    String::new()
                } else {
                    format!(
                        "{} {} (limit {}) ",
                        f.check.measure(),
                        num(f.value),
                        num(f.limit)
                    )
                };
                out.push_str(&format!(
                    "FAIL {} / {} / {} check: {measured}{}\n",
                    f.kind, f.sample, f.check, f.note
                ));
            }
        }
        let kinds = {
            let mut k: Vec<&str> = rows.iter().map(|(k, _)| k.as_str()).collect();
            k.dedup();
            k.len()
        };
        out.push_str(&format!(
            "{} kinds, {} samples, {} checks run, {} failed\n",
            kinds,
            rows.len(),
            self.results
                .iter()
                .filter(|r| r.outcome != Outcome::Skipped)
                .count(),
            fails.len()
        ));
        out
    }
}

fn num(v: f64) -> String {
    if v.is_nan() {
        "n/a".into()
    } else if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.1e}")
    }
}

/// Runs every check on every registered kind whose name contains `filter` (all when
/// `None`).
///
/// # Example
///
/// The built-in `spring_damper` passes every check; its tangent is constant, so central
/// differences reproduce it to round-off (far below [`LIMIT_TANGENT`]).
///
/// ```
/// use railfem_framework::conformance::{check_all, Outcome};
///
/// railfem_elements::link(); // this crate does not depend on the built-in kinds: name them
/// let report = check_all(Some("spring_damper"));
/// assert!(!report.results.is_empty());
/// assert!(report.passed(), "{}", report.table());
/// for r in report.results.iter().filter(|r| r.check == "tangent") {
///     assert_eq!(r.outcome, Outcome::Pass);
///     assert!(r.value < 1e-8, "{}: {:e}", r.sample, r.value);
/// }
/// ```
pub fn check_all(filter: Option<&str>) -> Report {
    let mut results = Vec::new();
    for k in registry::kinds() {
        if filter.is_none_or(|f| k.name.contains(f)) {
            results.extend(check_kind(&k));
        }
    }
    Report { results }
}

/// Runs every check on every sample state of `kind`. A kind without samples gets one
/// failed `"samples"` result: it cannot be checked.
pub fn check_kind(kind: &ElementKind) -> Vec<CheckResult> {
    let samples = match catch_unwind(AssertUnwindSafe(kind.samples)) {
        Ok(s) => s,
        Err(p) => {
            return vec![fail_row(
                kind,
                "",
                Check::Samples,
                format!("the sample generator panicked: {}", panic_text(p.as_ref())),
            )]
        }
    };
    if samples.is_empty() {
        return vec![fail_row(
            kind,
            "",
            Check::Samples,
            "no sample states: give the kind a sample generator (elastic, yielded, …)".into(),
        )];
    }
    let names: Vec<String> = samples.iter().map(|s| s.name.clone()).collect();
    drop(samples);
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let cx = Cx { kind, index: i };
        type CheckFn = fn(&Cx) -> Result<Measured, String>;
        let checks: [CheckFn; 8] = [
            check_tangent,
            check_symmetry,
            check_rigid,
            check_mass,
            check_revert,
            check_serde,
            check_finite,
            check_energy,
        ];
        for (check, f) in CHECKS.into_iter().zip(checks) {
            let r = catch_unwind(AssertUnwindSafe(|| f(&cx)));
            let row = match r {
                Ok(Ok(m)) => CheckResult {
                    kind: kind.name.to_string(),
                    sample: name.clone(),
                    check,
                    outcome: m.outcome,
                    value: m.value,
                    limit: m.limit,
                    note: m.note,
                },
                Ok(Err(note)) => CheckResult {
                    kind: kind.name.to_string(),
                    sample: name.clone(),
                    check,
                    outcome: Outcome::Fail,
                    value: f64::NAN,
                    limit: f64::NAN,
                    note,
                },
                Err(p) => CheckResult {
                    kind: kind.name.to_string(),
                    sample: name.clone(),
                    check,
                    outcome: Outcome::Fail,
                    value: f64::NAN,
                    limit: f64::NAN,
                    note: format!("panicked: {}", panic_text(p.as_ref())),
                },
            };
            out.push(row);
        }
    }
    out
}

fn fail_row(kind: &ElementKind, sample: &str, check: Check, note: String) -> CheckResult {
    CheckResult {
        kind: kind.name.to_string(),
        sample: sample.to_string(),
        check,
        outcome: Outcome::Fail,
        value: f64::NAN,
        limit: f64::NAN,
        note,
    }
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_default()
}

/// What a check measured.
struct Measured {
    outcome: Outcome,
    value: f64,
    limit: f64,
    note: String,
}

impl Measured {
    fn against(value: f64, limit: f64, note: String) -> Measured {
        Measured {
            outcome: if value <= limit {
                Outcome::Pass
            } else {
                Outcome::Fail
            },
            value,
            limit,
            note,
        }
    }
    fn skipped(note: &str) -> Measured {
        Measured {
            outcome: Outcome::Skipped,
            value: f64::NAN,
            limit: f64::NAN,
            note: note.to_string(),
        }
    }
}

/// Which sample of which kind a check works on.
struct Cx<'a> {
    kind: &'a ElementKind,
    index: usize,
}

impl Cx<'_> {
    /// A fresh copy of the sample (the generator is called again: elements are not Clone).
    fn fresh(&self) -> Result<Sample, String> {
        let s = (self.kind.samples)()
            .into_iter()
            .nth(self.index)
            .ok_or("the sample generator returned fewer samples the second time")?;
        let n = s.element.ndof();
        if s.disp.len() != n || s.vel.len() != n {
            return Err(format!(
                "sample has {} displacements and {} velocities for {n} element DOFs",
                s.disp.len(),
                s.vel.len()
            ));
        }
        if s.committed_disp.as_ref().is_some_and(|c| c.len() != n) {
            return Err("sample's committed_disp has the wrong length".into());
        }
        Ok(s)
    }

    /// A fresh copy, prepared (see the module documentation).
    fn prepared(&self) -> Result<Sample, String> {
        let mut s = self.fresh()?;
        prepare(
            &mut *s.element,
            s.committed_disp.as_deref(),
            &s.disp,
            &s.vel,
        )?;
        Ok(s)
    }
}

fn prepare(
    e: &mut dyn Element,
    committed: Option<&[f64]>,
    disp: &[f64],
    vel: &[f64],
) -> Result<(), String> {
    let z = vec![0.0; disp.len()];
    if let Some(c) = committed {
        trial(e, c, &z, &z)?;
        e.commit();
    }
    trial(e, disp, vel, &z)
}

/// Force and tangent of `e` at the static trial state `u` (time 0, Δt 0, zero velocity
/// and acceleration), for element authors' own tests.
pub fn static_force_tangent(
    e: &mut dyn Element,
    u: &[f64],
) -> Result<(Vec<f64>, DMatrix<f64>), crate::element::ElementError> {
    let z = vec![0.0; u.len()];
    e.update(&TrialState {
        time: 0.0,
        dt: 0.0,
        disp: u,
        vel: &z,
        acc: &z,
    })?;
    Ok((force(e), tangent(e)))
}

fn trial(e: &mut dyn Element, u: &[f64], v: &[f64], a: &[f64]) -> Result<(), String> {
    e.update(&TrialState {
        time: KIT_TIME,
        dt: KIT_DT,
        disp: u,
        vel: v,
        acc: a,
    })
    .map_err(|err| format!("update failed: {err}"))
}

fn force(e: &dyn Element) -> Vec<f64> {
    let mut f = vec![0.0; e.ndof()];
    e.resisting_force(&mut f);
    f
}

fn tangent(e: &dyn Element) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(e.ndof(), e.ndof());
    e.tangent_stiffness(&mut k);
    k
}

fn mass(e: &dyn Element) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(e.ndof(), e.ndof());
    if e.properties().has_mass {
        e.mass(&mut m);
    }
    m
}

fn damping(e: &dyn Element) -> DMatrix<f64> {
    let mut c = DMatrix::zeros(e.ndof(), e.ndof());
    if e.properties().has_damping {
        e.damping(&mut c);
    }
    c
}

fn outputs(e: &dyn Element) -> Vec<f64> {
    let mut o = Vec::new();
    e.outputs(&mut o);
    o
}

/// Everything the element reports at its trial state, for bitwise comparisons.
fn snapshot(e: &dyn Element) -> Vec<f64> {
    let mut s = force(e);
    s.extend_from_slice(tangent(e).as_slice());
    s.extend(outputs(e));
    s.push(e.dissipated_energy());
    s
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn bitwise_equal(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Relative size `num / den`, with `0/0 = 0`.
fn rel(num: f64, den: f64) -> f64 {
    if num == 0.0 {
        0.0
    } else {
        num / den.max(f64::MIN_POSITIVE)
    }
}

/// Displacement scale of a sample: `max(1e-3, max|u|)` (m or rad).
fn scale(u: &[f64]) -> f64 {
    max_abs(u).max(1e-3)
}

/// A fixed pattern of magnitude ≤ 1 with mixed signs, for perturbations.
fn pattern(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let s = if i % 2 == 0 { 1.0 } else { -1.0 };
            s * (1.0 - 0.1 * (i % 5) as f64)
        })
        .collect()
}

/// Start indices (in element order) of the rotation triples an element that declares
/// finite rotations reads as rotation vectors: nodes where it uses rx, ry and rz. Empty for
/// every other element (its rotations are additive).
fn rotation_slots(e: &dyn Element) -> Vec<usize> {
    if !e.properties().finite_rotations {
        return Vec::new();
    }
    let mut slots = Vec::new();
    let mut k = 0;
    for nd in e.connectivity() {
        let rot = crate::dof::DofSet::ROTATIONS;
        if nd.dofs.bits() & rot.bits() == rot.bits() {
            let before = nd.dofs.iter().take_while(|d| d.index() < 3).count();
            slots.push(k + before);
        }
        k += nd.dofs.count();
    }
    slots
}

/// `u` with entry `j` moved by `h`: added, or, inside a rotation triple of `slots`, the spin
/// `h·e` composed onto the rotation vector (the driver's update, [`crate::rotation`]).
fn perturbed(u: &[f64], j: usize, h: f64, slots: &[usize]) -> Vec<f64> {
    let mut d = vec![0.0; u.len()];
    d[j] = h;
    corrected(u, &d, slots)
}

/// `u ⊕ d`: the sum, with composition on the rotation triples at `slots`.
fn corrected(u: &[f64], d: &[f64], slots: &[usize]) -> Vec<f64> {
    let mut out: Vec<f64> = u.iter().zip(d).map(|(a, b)| a + b).collect();
    for &k in slots {
        let psi = Vector3::new(u[k], u[k + 1], u[k + 2]);
        let c = crate::rotation::compose(&psi, &Vector3::new(d[k], d[k + 1], d[k + 2]));
        out[k..k + 3].copy_from_slice(c.as_slice());
    }
    out
}

/// The increment from `a` to `b`: the difference, with the incremental rotation vector
/// `log(R_b·R_aᵀ)` on the rotation triples at `slots`.
fn increment(a: &[f64], b: &[f64], slots: &[usize]) -> Vec<f64> {
    let mut out: Vec<f64> = b.iter().zip(a).map(|(x, y)| x - y).collect();
    for &k in slots {
        let th = crate::rotation::increment(
            &Vector3::new(a[k], a[k + 1], a[k + 2]),
            &Vector3::new(b[k], b[k + 1], b[k + 2]),
        );
        out[k..k + 3].copy_from_slice(th.as_slice());
    }
    out
}

/// Check 1: tangent against central differences of the resisting force, reverting to the
/// committed state between perturbations. For an element declaring finite rotations the
/// rotational perturbation is a spin composed onto the nodal rotation, as the driver does,
/// so the tangent is checked as conjugate to the spatial spin (also at the strongly rotated
/// sample states such elements provide).
fn check_tangent(cx: &Cx) -> Result<Measured, String> {
    let mut s = cx.prepared()?;
    let e = &mut *s.element;
    let k = tangent(e);
    let n = e.ndof();
    let mut kfd = DMatrix::zeros(n, n);
    let slots = rotation_slots(e);
    for j in 0..n {
        let h = s.fd_step * s.disp[j].abs().max(1e-3);
        let u = perturbed(&s.disp, j, h, &slots);
        e.revert();
        trial(e, &u, &s.vel, &vec![0.0; n])?;
        let fp = force(e);
        let u = perturbed(&s.disp, j, -h, &slots);
        e.revert();
        trial(e, &u, &s.vel, &vec![0.0; n])?;
        let fm = force(e);
        for i in 0..n {
            kfd[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    let err = rel(
        max_diff(k.as_slice(), kfd.as_slice()),
        max_abs(k.as_slice()),
    );
    Ok(Measured::against(
        err,
        LIMIT_TANGENT,
        if err > LIMIT_TANGENT {
            format!("max|K| = {:.3e}", max_abs(k.as_slice()))
        } else {
            String::new()
        },
    ))
}

/// Check 2: symmetry of the tangent (and damping) of elements that declare it.
fn check_symmetry(cx: &Cx) -> Result<Measured, String> {
    let s = cx.prepared()?;
    let e = &*s.element;
    let p = e.properties();
    if !p.symmetric {
        return Ok(Measured::skipped("declares an unsymmetric tangent"));
    }
    let k = tangent(e);
    let mut err = rel(
        max_diff(k.as_slice(), k.transpose().as_slice()),
        max_abs(k.as_slice()),
    );
    if p.has_damping {
        let c = damping(e);
        err = err.max(rel(
            max_diff(c.as_slice(), c.transpose().as_slice()),
            max_abs(c.as_slice()),
        ));
    }
    Ok(Measured::against(err, LIMIT_SYMMETRY, String::new()))
}

/// Per element DOF: the node index and the DOF index 0..6.
fn dof_list(e: &dyn Element) -> Vec<(usize, usize)> {
    e.connectivity()
        .iter()
        .flat_map(|nd| nd.dofs.iter().map(move |d| (nd.node, d.index())))
        .collect()
}

/// Element vector of a rigid motion: translation `t` and rotation `w` (global) about `x0`,
/// expressed in each node's axes.
fn rigid_motion(
    dofs: &[(usize, usize)],
    nodes: &[NodeKinematics],
    t: Vector3<f64>,
    w: Vector3<f64>,
    x0: Vector3<f64>,
) -> Result<Vec<f64>, String> {
    dofs.iter()
        .map(|&(node, d)| {
            let nk = nodes.get(node).ok_or_else(|| {
                format!(
                    "the element uses node index {node} but the sample has {} nodes",
                    nodes.len()
                )
            })?;
            let frame: Matrix3<f64> = nk.frame;
            let v = if d < 3 {
                frame.transpose() * (t + w.cross(&(nk.position - x0)))
            } else {
                frame.transpose() * w
            };
            Ok(v[d % 3])
        })
        .collect()
}

/// Check 3: rigid translations on top of the sample state, and infinitesimal rigid
/// rotations from the reference, produce no resisting force (objective elements only).
fn check_rigid(cx: &Cx) -> Result<Measured, String> {
    let mut s = cx.prepared()?;
    if !s.element.properties().objective {
        return Ok(Measured::skipped("not declared objective"));
    }
    let n = s.element.ndof();
    let dofs = dof_list(&*s.element);
    let e = &mut *s.element;
    let f0 = force(e);
    let kmax = max_abs(tangent(e).as_slice());
    let c = scale(&s.disp);
    let z = vec![0.0; n];
    let mut worst = 0.0f64;
    let mut note = String::new();
    for a in 0..3 {
        let r = rigid_motion(
            &dofs,
            &s.nodes,
            Vector3::ith(a, c),
            Vector3::zeros(),
            Vector3::zeros(),
        )?;
        if max_abs(&r) == 0.0 {
            continue;
        }
        let u: Vec<f64> = s.disp.iter().zip(&r).map(|(x, y)| x + y).collect();
        e.revert();
        trial(e, &u, &s.vel, &z)?;
        let err = rel(max_diff(&force(e), &f0), kmax * max_abs(&r));
        if err > worst {
            worst = err;
            note = format!("translation along axis {a}");
        }
    }
    // Rotations from the reference state of a fresh element.
    let mut fresh = cx.fresh()?;
    let used: Vec<usize> = dofs.iter().map(|d| d.0).collect();
    let x0 = used
        .iter()
        .filter_map(|&i| fresh.nodes.get(i).map(|k| k.position))
        .fold(Vector3::zeros(), |acc, p| acc + p)
        / used.len().max(1) as f64;
    for a in 0..3 {
        let r = rigid_motion(
            &dofs,
            &fresh.nodes,
            Vector3::zeros(),
            Vector3::ith(a, RIGID_THETA),
            x0,
        )?;
        if max_abs(&r) == 0.0 {
            continue;
        }
        let e = &mut *fresh.element;
        // Compare with the reference state's own force (an element may be preloaded there).
        trial(e, &z, &z, &z)?;
        let f_ref = force(e);
        trial(e, &r, &z, &z)?;
        let k = max_abs(tangent(e).as_slice()).max(kmax);
        let err = rel(max_diff(&force(e), &f_ref), k * max_abs(&r));
        if err > worst {
            worst = err;
            note = format!("rotation about axis {a}");
        }
    }
    if fresh.element.properties().finite_rotations {
        let (err, what) = finite_rigid_motion(&mut *fresh.element, &fresh.nodes, &s.disp, x0)?;
        // Round-off of an objective element under a finite motion: the forces are rotated
        // exactly, so the error is ε·|x|·max|K| relative; compared with the same scale as
        // the infinitesimal checks.
        let err = err / (kmax * c).max(f64::MIN_POSITIVE);
        if err > worst {
            worst = err;
            note = what;
        }
    }
    if worst <= LIMIT_RIGID {
        note.clear();
    }
    Ok(Measured::against(worst, LIMIT_RIGID, note))
}

/// The finite rigid motion of the large-rotation check: a rotation by
/// [`FINITE_RIGID_ANGLE`] about the skew axis (1, −2, 0.5) about `x0`, then a translation
/// [`FINITE_RIGID_SHIFT`].
fn finite_rigid_rotation() -> (Matrix3<f64>, Vector3<f64>) {
    let axis = Vector3::new(1.0, -2.0, 0.5).normalize();
    (
        crate::rotation::exp(&(axis * FINITE_RIGID_ANGLE)),
        Vector3::from(FINITE_RIGID_SHIFT),
    )
}

/// For an element declaring finite rotations on global-axis nodes: the largest change of
/// its force, beyond the rotation `Q` of the force itself, when the reference state and the
/// sample state are moved as a rigid body by [`finite_rigid_rotation`]: positions
/// `x ↦ Q·(x − x0) + x0 + t`, triads `R ↦ Q·R`. Objective elements give `f' = Q·f` (forces
/// and moments both turn with the body). Returns the absolute error and which state.
fn finite_rigid_motion(
    e: &mut dyn Element,
    nodes: &[NodeKinematics],
    disp: &[f64],
    x0: Vector3<f64>,
) -> Result<(f64, String), String> {
    let (q, t) = finite_rigid_rotation();
    let slots = rotation_slots(e);
    // Element-order start of each node's translations (nodes using all three).
    let mut trans = Vec::new();
    let mut k = 0;
    for nd in e.connectivity() {
        let node = nodes
            .get(nd.node)
            .ok_or("the sample has fewer nodes than the element uses")?;
        if node.frame != Matrix3::identity() {
            return Err("the finite rigid-motion check needs nodes with the global axes".into());
        }
        if nd.dofs.bits() & 0b111 == 0b111 {
            trans.push((k, node.position));
        }
        k += nd.dofs.count();
    }
    let n = e.ndof();
    let z = vec![0.0; n];
    let mut worst = (0.0f64, String::new());
    for (name, base) in [("reference", z.clone()), ("sample state", disp.to_vec())] {
        e.revert();
        trial(e, &base, &z, &z)?;
        let f0 = force(e);
        let mut moved = base.clone();
        for &(k, x) in &trans {
            let cur = x + Vector3::new(base[k], base[k + 1], base[k + 2]);
            let new = q * (cur - x0) + x0 + t;
            moved[k..k + 3].copy_from_slice((new - x).as_slice());
        }
        for &k in &slots {
            let r = crate::rotation::exp(&Vector3::new(base[k], base[k + 1], base[k + 2]));
            moved[k..k + 3].copy_from_slice(crate::rotation::log(&(q * r)).as_slice());
        }
        e.revert();
        trial(e, &moved, &z, &z)?;
        let f1 = force(e);
        // Expected: every translational and rotational triple of f0 turned by Q.
        let mut want = f0.clone();
        for &k in trans.iter().map(|(k, _)| k).chain(slots.iter()) {
            let v = q * Vector3::new(f0[k], f0[k + 1], f0[k + 2]);
            want[k..k + 3].copy_from_slice(v.as_slice());
        }
        let err = max_diff(&f1, &want);
        if err > worst.0 {
            worst = (
                err,
                format!("finite rigid motion ({FINITE_RIGID_ANGLE} rad about a skew axis) of the {name}"),
            );
        }
    }
    e.revert();
    Ok(worst)
}

/// Check 4: the mass matrix is symmetric positive semi-definite and its translational total
/// along each axis equals `declared_mass`.
fn check_mass(cx: &Cx) -> Result<Measured, String> {
    let s = cx.prepared()?;
    let e = &*s.element;
    let p = e.properties();
    if !p.has_mass {
        return Ok(Measured::skipped("no mass"));
    }
    let m = mass(e);
    let mmax = max_abs(m.as_slice());
    let asym = rel(max_diff(m.as_slice(), m.transpose().as_slice()), mmax);
    let sym = (&m + m.transpose()) * 0.5;
    let eig = sym.symmetric_eigenvalues();
    let emax = eig.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let emin = eig.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let neg = if emin < 0.0 { rel(-emin, emax) } else { 0.0 };
    let mut worst = asym.max(neg);
    let mut note = format!("asymmetry {}, negative eigenvalue {}", num(asym), num(neg));
    if let Some(declared) = p.declared_mass {
        let dofs = dof_list(e);
        for a in 0..3 {
            let r = rigid_motion(
                &dofs,
                &s.nodes,
                Vector3::ith(a, 1.0),
                Vector3::zeros(),
                Vector3::zeros(),
            )?;
            if max_abs(&r) == 0.0 {
                continue;
            }
            let r = DVector::from_vec(r);
            let total = (r.transpose() * &m * &r)[(0, 0)];
            let err = rel((total - declared).abs(), declared.abs());
            if err > worst {
                worst = err;
                note = format!("translation along axis {a}: rᵀMr = {total:.6e} kg vs declared {declared:.6e} kg");
            }
        }
    }
    if worst <= LIMIT_MASS {
        note.clear();
    }
    Ok(Measured::against(worst, LIMIT_MASS, note))
}

/// Check 5: `update(x)` + `revert` + `update(y)` reports bitwise what `update(y)` on a fresh
/// copy does, and commit/revert are idempotent.
fn check_revert(cx: &Cx) -> Result<Measured, String> {
    let n = cx.fresh()?.element.ndof();
    let z = vec![0.0; n];
    let mut a = cx.prepared()?;
    let c = scale(&a.disp);
    let x: Vec<f64> = a
        .disp
        .iter()
        .zip(pattern(n))
        .map(|(u, d)| u + 5.0 * c * d)
        .collect();
    // update(x), revert, update(y) vs fresh update(y).
    trial(&mut *a.element, &x, &a.vel, &z)?;
    a.element.revert();
    trial(&mut *a.element, &a.disp, &a.vel, &z)?;
    let sa = snapshot(&*a.element);
    let b = cx.prepared()?;
    let sb = snapshot(&*b.element);
    if !bitwise_equal(&sa, &sb) {
        return Ok(Measured::against(
            max_diff(&sa, &sb).max(f64::MIN_POSITIVE),
            0.0,
            "update(x) + revert + update(y) differs from update(y) on a fresh copy: revert does not restore the committed state".into(),
        ));
    }
    // Commit at y, then revert twice / commit twice, then update(x): all the same.
    let reference = {
        let mut d = cx.prepared()?;
        d.element.commit();
        trial(&mut *d.element, &x, &d.vel, &z)?;
        snapshot(&*d.element)
    };
    let mut cc = cx.prepared()?;
    cc.element.commit();
    cc.element.revert();
    cc.element.revert();
    trial(&mut *cc.element, &x, &cc.vel, &z)?;
    let s1 = snapshot(&*cc.element);
    let mut ee = cx.prepared()?;
    ee.element.commit();
    ee.element.commit();
    trial(&mut *ee.element, &x, &ee.vel, &z)?;
    let s2 = snapshot(&*ee.element);
    if !bitwise_equal(&s1, &reference) || !bitwise_equal(&s2, &reference) {
        return Ok(Measured::against(
            max_diff(&s1, &reference)
                .max(max_diff(&s2, &reference))
                .max(f64::MIN_POSITIVE),
            0.0,
            "commit followed by revert (or a second commit) is not idempotent".into(),
        ));
    }
    Ok(Measured::against(0.0, 0.0, String::new()))
}

/// A build context over the sample's nodes: node index `i` has user id `i + 1`.
struct KitCtx {
    positions: Vec<Vector3<f64>>,
}

impl BuildContext for KitCtx {
    fn node_index(&self, id: u64) -> Option<usize> {
        let i = usize::try_from(id).ok()?.checked_sub(1)?;
        (i < self.positions.len()).then_some(i)
    }
    fn node_position(&self, index: usize) -> Vector3<f64> {
        self.positions
            .get(index)
            .copied()
            .unwrap_or_else(Vector3::zeros)
    }
    fn add_internal_node(&mut self, position: Vector3<f64>, _like: Option<usize>) -> usize {
        self.positions.push(position);
        self.positions.len() - 1
    }
    fn resource(&self, _name: &str) -> Option<std::sync::Arc<dyn std::any::Any + Send + Sync>> {
        None
    }
}

/// Check 6: `parameters()` through JSON text and back into the kind's factory gives an
/// element that reports bitwise the same at the same prepared state. The spec's nodes are
/// the element's connectivity nodes (ids = index + 1) — kinds whose factory adds internal
/// nodes or needs model resources cannot be rebuilt by the kit and fail with the reason.
fn check_serde(cx: &Cx) -> Result<Measured, String> {
    let s = cx.prepared()?;
    let params = s.element.parameters();
    let map = match serde_json::from_str::<serde_json::Value>(
        &serde_json::to_string(&params)
            .map_err(|e| format!("parameters() do not serialise: {e}"))?,
    ) {
        Ok(serde_json::Value::Object(m)) => m,
        Ok(other) => {
            return Err(format!(
                "parameters() returned {other} instead of a table of the kind's keys"
            ))
        }
        Err(e) => return Err(format!("parameters() do not parse back: {e}")),
    };
    let mut ids: Vec<u64> = Vec::new();
    for nd in s.element.connectivity() {
        let id = nd.node as u64 + 1;
        if !ids.contains(&id) {
            ids.push(id);
        }
    }
    let spec = ElementSpec {
        id: 1,
        kind: cx.kind.name.to_string(),
        nodes: ids,
        params: map,
        origin: format!("conformance: {} / {}", cx.kind.name, s.name),
    };
    let mut ctx = KitCtx {
        positions: s.nodes.iter().map(|k| k.position).collect(),
    };
    let rebuilt = match s.rebuild {
        Some(f) => f(&serde_json::Value::Object(spec.params.clone())),
        None => (cx.kind.build)(&spec, &mut ctx),
    };
    let mut rebuilt =
        rebuilt.map_err(|e: FemError| format!("cannot rebuild from parameters(): {e}"))?;
    if rebuilt.ndof() != s.element.ndof() {
        return Err(format!(
            "rebuilt element has {} DOFs instead of {}",
            rebuilt.ndof(),
            s.element.ndof()
        ));
    }
    prepare(&mut *rebuilt, s.committed_disp.as_deref(), &s.disp, &s.vel)?;
    let a = snapshot(&*s.element);
    let b = snapshot(&*rebuilt);
    if bitwise_equal(&a, &b) {
        Ok(Measured::against(0.0, 0.0, String::new()))
    } else {
        Ok(Measured::against(
            rel(max_diff(&a, &b), max_abs(&a)).max(f64::MIN_POSITIVE),
            0.0,
            "the element rebuilt from parameters() reports differently".into(),
        ))
    }
}

/// Check 7: force, tangent, mass, damping, outputs and dissipated energy are finite, and
/// there are as many outputs and output units as output names, each unit fit for a CSV
/// header's brackets (not empty, no comma, bracket or line break).
fn check_finite(cx: &Cx) -> Result<Measured, String> {
    let s = cx.prepared()?;
    let e = &*s.element;
    let names = e.output_names();
    let outs = outputs(e);
    if names.len() != outs.len() {
        return Err(format!(
            "{} outputs for {} output names",
            outs.len(),
            names.len()
        ));
    }
    let units = e.output_units();
    if units.len() != names.len() {
        return Err(format!(
            "{} output units for {} output names",
            units.len(),
            names.len()
        ));
    }
    if let Some((n, u)) = names
        .iter()
        .zip(&units)
        .find(|(_, u)| u.is_empty() || u.contains([',', '[', ']', '\n', '\r']))
    {
        return Err(format!(
            "output `{n}` has unit `{u}`: give an SI unit such as N or m/s², `-` for a ratio"
        ));
    }
    let parts: [(&str, Vec<f64>); 6] = [
        ("resisting force", force(e)),
        ("tangent", tangent(e).as_slice().to_vec()),
        ("mass", mass(e).as_slice().to_vec()),
        ("damping", damping(e).as_slice().to_vec()),
        ("outputs", outs),
        ("dissipated energy", vec![e.dissipated_energy()]),
    ];
    let bad: Vec<&str> = parts
        .iter()
        .filter(|(_, v)| v.iter().any(|x| !x.is_finite()))
        .map(|(n, _)| *n)
        .collect();
    if bad.is_empty() {
        Ok(Measured::against(0.0, 0.0, String::new()))
    } else {
        Ok(Measured {
            outcome: Outcome::Fail,
            value: f64::NAN,
            limit: 0.0,
            note: format!("non-finite {}", bad.join(", ")),
        })
    }
}

/// Check 8: the element with a 1 kg-scale mass on each of its DOFs (plus its own mass and
/// damping), released from the prepared sample state with a velocity, stepped
/// [`ENERGY_STEPS`] times by average-acceleration Newmark with Newton iterations; the
/// energy balance `E_kin + W_f + W_c = E_kin,0` must hold, where
/// `W_f = Σ ½(f_n + f_{n+1})·Δu` is the trapezoidal work of the resisting force and
/// `W_c` that of the damping force.
///
/// `W_f` *is* the element's strain energy change plus the energy it dissipated: the kit
/// cannot split the two without the element's free energy, so it checks their sum (adding
/// `dissipated_energy()` on top of `W_f` would count the dissipation twice), and checks
/// separately that `dissipated_energy()` never decreases.
fn check_energy(cx: &Cx) -> Result<Measured, String> {
    let mut s = cx.prepared()?;
    let n = s.element.ndof();
    let props = s.element.properties();
    let e = &mut *s.element;
    e.commit();
    // Finite rotations: the step's rotational increment is the incremental rotation
    // vector and corrections are composed (the driver's scheme); the balance identity below
    // holds with that increment exactly.
    let slots = rotation_slots(e);
    let me = mass(e);
    let m_add = if props.has_mass {
        max_abs(me.as_slice()).max(f64::MIN_POSITIVE)
    } else {
        1.0
    };
    let mmat = &me + DMatrix::identity(n, n) * m_add;
    let kmax = max_abs(tangent(e).as_slice());
    let w_max = (kmax * n as f64 / m_add).sqrt();
    let dt = if w_max > 0.0 {
        2.0 * std::f64::consts::PI / w_max / 20.0
    } else {
        KIT_DT
    };
    let c = scale(&s.disp);
    let d = pattern(n);
    let dn = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    let v0: Vec<f64> = d.iter().map(|x| x / dn * w_max.max(1.0) * c).collect();
    let mut u = DVector::from_vec(s.disp.clone());
    let mut v = DVector::from_vec(v0);
    // Initial acceleration from M a = −f − C v.
    trial(e, u.as_slice(), v.as_slice(), &vec![0.0; n])?;
    let mut f = DVector::from_vec(force(e));
    let mut cv = damping(e) * &v;
    let lu = mmat.clone().lu();
    let mut a = lu
        .solve(&(-(&f + &cv)))
        .ok_or("the mass matrix plus added mass is singular")?;
    let ke = |v: &DVector<f64>| 0.5 * v.dot(&(&mmat * v));
    let e_kin0 = ke(&v);
    let d0 = e.dissipated_energy();
    let mut d_prev = d0;
    let (mut w_f, mut w_c) = (0.0, 0.0);
    let mut e_ref = e_kin0;
    let mut worst = 0.0f64;
    let mut worst_step = 0;
    for step in 1..=ENERGY_STEPS {
        let (u0, v0, a0) = (u.clone(), v.clone(), a.clone());
        let mut un = DVector::from_vec(corrected(u0.as_slice(), (&v0 * dt).as_slice(), &slots));
        let mut converged = false;
        let mut negligible = false;
        for _ in 0..50 {
            let du = DVector::from_vec(increment(u0.as_slice(), un.as_slice(), &slots));
            let vn = &du * (2.0 / dt) - &v0;
            let an = &du * (4.0 / (dt * dt)) - &v0 * (4.0 / dt) - &a0;
            trial(e, un.as_slice(), vn.as_slice(), an.as_slice())?;
            let fn_ = DVector::from_vec(force(e));
            let cmat = damping(e);
            let inertia = &mmat * &an;
            let cvn = &cmat * &vn;
            let r = &inertia + &cvn + &fn_;
            let reference = fn_.amax().max(inertia.amax()).max(cvn.amax());
            // Converged when the residual is at round-off, or when the last correction was
            // negligible (a linear element reaches the exact solution in one solve and its
            // residual is then round-off of whatever size the conditioning gives).
            if r.amax() <= 1e-12 * reference || negligible {
                converged = true;
                u = un.clone();
                v = vn;
                a = an;
                w_f += 0.5 * (&f + &fn_).dot(&du);
                w_c += 0.5 * (&cv + &cvn).dot(&du);
                f = fn_;
                cv = cvn;
                break;
            }
            let keff = tangent(e) + cmat * (2.0 / dt) + &mmat * (4.0 / (dt * dt));
            let delta = keff
                .lu()
                .solve(&(-r))
                .ok_or_else(|| format!("singular effective stiffness at step {step}"))?;
            negligible = delta.amax() <= 1e-13 * un.amax().max(c);
            un = DVector::from_vec(corrected(un.as_slice(), delta.as_slice(), &slots));
        }
        if !converged {
            return Err(format!(
                "Newton did not converge to 1e-12 in 50 iterations at step {step} (dt = {dt:.3e} s)"
            ));
        }
        e.commit();
        let dn = e.dissipated_energy();
        if !dn.is_finite() || dn < d_prev - 1e-12 * e_ref.max(dn.abs()) {
            // Joules, not a relative measure: the note carries them.
            return Ok(Measured {
                outcome: Outcome::Fail,
                value: f64::NAN,
                limit: f64::NAN,
                note: format!(
                    "dissipated_energy() decreased at step {step}: {d_prev:e} J → {dn:e} J (an element's dissipation can only grow)"
                ),
            });
        }
        d_prev = dn;
        let kin = ke(&v);
        e_ref = e_ref.max(kin).max(w_f.abs()).max(w_c.abs());
        let err = (kin + w_f + w_c - e_kin0).abs();
        if err > worst {
            worst = err;
            worst_step = step;
        }
    }
    let value = rel(worst, e_ref);
    Ok(Measured::against(
        value,
        LIMIT_ENERGY,
        format!(
            "dt = {dt:.2e} s, E_kin0 = {e_kin0:.3e} J, work {w_f:.3e} J, dissipated {:.3e} J{}",
            d_prev - d0,
            if value > LIMIT_ENERGY {
                format!(", worst at step {worst_step}")
            } else {
                String::new()
            }
        ),
    ))
}

#[cfg(test)]
mod tests {
    //! Deliberately broken elements, each caught by the matching check, and a correct one
    //! that passes everything.

    use super::*;
    use crate::dof::{Dof, DofSet};
    use crate::element::{ElementError, ElementProperties, NodeDofs};

    #[derive(Clone, Copy, PartialEq, Debug)]
    enum Bug {
        None,
        /// Tangent with the wrong sign.
        WrongSign,
        /// `f = K·u` with an unsymmetric K (rows sum to zero) while declaring symmetric.
        Asymmetric,
    }

    /// A two-node spring on ux between x = 0 and x = 1 m.
    struct Spring {
        nodes: [NodeDofs; 2],
        k: f64,
        bug: Bug,
        u: [f64; 2],
    }

    impl Spring {
        fn kmat(&self) -> [[f64; 2]; 2] {
            let k = self.k;
            match self.bug {
                Bug::Asymmetric => [[k, -k], [-2.0 * k, 2.0 * k]],
                _ => [[k, -k], [-k, k]],
            }
        }
    }

    impl Element for Spring {
        fn kind(&self) -> &str {
            "test_spring"
        }
        fn connectivity(&self) -> &[NodeDofs] {
            &self.nodes
        }
        fn properties(&self) -> ElementProperties {
            ElementProperties::default()
        }
        fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
            self.u = [t.disp[0], t.disp[1]];
            Ok(())
        }
        fn resisting_force(&self, f: &mut [f64]) {
            let k = self.kmat();
            for i in 0..2 {
                f[i] = k[i][0] * self.u[0] + k[i][1] * self.u[1];
            }
        }
        fn tangent_stiffness(&self, km: &mut DMatrix<f64>) {
            let k = self.kmat();
            let s = if self.bug == Bug::WrongSign {
                -1.0
            } else {
                1.0
            };
            for i in 0..2 {
                for j in 0..2 {
                    km[(i, j)] = s * k[i][j];
                }
            }
        }
        fn parameters(&self) -> serde_json::Value {
            serde_json::json!({ "k": self.k, "bug": format!("{:?}", self.bug) })
        }
    }

    fn spring(k: f64, bug: Bug) -> Spring {
        let ux = DofSet::of(&[Dof::Ux]);
        Spring {
            nodes: [
                NodeDofs { node: 0, dofs: ux },
                NodeDofs { node: 1, dofs: ux },
            ],
            k,
            bug,
            u: [0.0; 2],
        }
    }

    fn build_spring(
        spec: &ElementSpec,
        _ctx: &mut dyn BuildContext,
    ) -> Result<Box<dyn Element>, FemError> {
        let k = spec.params["k"].as_f64().unwrap_or(0.0);
        let bug = match spec.params["bug"].as_str() {
            Some("WrongSign") => Bug::WrongSign,
            Some("Asymmetric") => Bug::Asymmetric,
            _ => Bug::None,
        };
        Ok(Box::new(spring(k, bug)))
    }

    fn spring_samples(bug: Bug) -> Vec<Sample> {
        vec![Sample {
            name: "stretched".into(),
            element: Box::new(spring(2.0e5, bug)),
            nodes: vec![
                NodeKinematics::fixed(Vector3::zeros()),
                NodeKinematics::fixed(Vector3::new(1.0, 0.0, 0.0)),
            ],
            disp: vec![1e-3, 3e-3],
            vel: vec![0.0, 0.0],
            fd_step: 1e-6,
            committed_disp: None,
            rebuild: None,
        }]
    }

    /// A grounded elastic–perfectly-plastic spring (k = 1e3 N/m, fy = 1 N) whose dissipation
    /// is `fy·Σ|Δu_p|` (a first version reported `fy·|u_p|`, which decreases on reversed
    /// yielding: the energy check caught it). With `forgetful`
    /// its update writes the plastic displacement straight into the committed history and
    /// revert does nothing.
    struct Plastic {
        nodes: [NodeDofs; 1],
        forgetful: bool,
        up_c: f64,
        up: f64,
        f: f64,
        kt: f64,
        d_c: f64,
        d: f64,
    }

    const PK: f64 = 1.0e3;
    const PFY: f64 = 1.0;

    impl Element for Plastic {
        fn kind(&self) -> &str {
            "test_plastic"
        }
        fn connectivity(&self) -> &[NodeDofs] {
            &self.nodes
        }
        fn properties(&self) -> ElementProperties {
            ElementProperties {
                objective: false,
                ..Default::default()
            }
        }
        fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
            let ft = PK * (t.disp[0] - self.up_c);
            if ft.abs() <= PFY {
                self.f = ft;
                self.up = self.up_c;
                self.kt = PK;
            } else {
                self.f = PFY * ft.signum();
                self.up = t.disp[0] - self.f / PK;
                self.kt = 0.0;
            }
            self.d = self.d_c + PFY * (self.up - self.up_c).abs();
            if self.forgetful {
                self.up_c = self.up;
                self.d_c = self.d;
            }
            Ok(())
        }
        fn resisting_force(&self, f: &mut [f64]) {
            f[0] = self.f;
        }
        fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
            k[(0, 0)] = self.kt;
        }
        fn commit(&mut self) {
            self.up_c = self.up;
            self.d_c = self.d;
        }
        fn revert(&mut self) {
            if !self.forgetful {
                self.up = self.up_c;
                self.d = self.d_c;
            }
        }
        fn parameters(&self) -> serde_json::Value {
            serde_json::json!({ "forgetful": self.forgetful })
        }
        fn dissipated_energy(&self) -> f64 {
            self.d
        }
    }

    fn plastic(forgetful: bool) -> Plastic {
        Plastic {
            nodes: [NodeDofs {
                node: 0,
                dofs: DofSet::of(&[Dof::Ux]),
            }],
            forgetful,
            up_c: 0.0,
            up: 0.0,
            f: 0.0,
            kt: PK,
            d_c: 0.0,
            d: 0.0,
        }
    }

    fn build_plastic(
        spec: &ElementSpec,
        _ctx: &mut dyn BuildContext,
    ) -> Result<Box<dyn Element>, FemError> {
        Ok(Box::new(plastic(
            spec.params["forgetful"].as_bool().unwrap_or(false),
        )))
    }

    fn plastic_samples(forgetful: bool) -> Vec<Sample> {
        vec![Sample {
            name: "elastic".into(),
            element: Box::new(plastic(forgetful)),
            nodes: vec![NodeKinematics::fixed(Vector3::zeros())],
            disp: vec![5e-4],
            vel: vec![0.0],
            fd_step: 1e-6,
            committed_disp: None,
            rebuild: None,
        }]
    }

    fn kind(
        name: &'static str,
        build: registry::Factory,
        samples: registry::SampleGenerator,
    ) -> ElementKind {
        ElementKind {
            name,
            description: "test",
            params: Vec::new,
            build,
            samples,
        }
    }

    fn outcome(results: &[CheckResult], check: &str) -> Outcome {
        results
            .iter()
            .find(|r| r.check == check)
            .map(|r| r.outcome)
            .unwrap_or_else(|| panic!("no result for {check}"))
    }

    fn failed(results: &[CheckResult]) -> Vec<&'static str> {
        results
            .iter()
            .filter(|r| !r.passed())
            .map(|r| r.check.name())
            .collect()
    }

    #[test]
    fn correct_spring_passes_everything() {
        let r = check_kind(&kind("good", build_spring, || spring_samples(Bug::None)));
        assert!(failed(&r).is_empty(), "{r:#?}");
        assert_eq!(outcome(&r, "mass"), Outcome::Skipped);
        assert_eq!(outcome(&r, "tangent"), Outcome::Pass);
        assert_eq!(outcome(&r, "rigid_body"), Outcome::Pass);
        assert_eq!(outcome(&r, "energy"), Outcome::Pass);
        let rep = Report { results: r };
        assert!(rep.passed());
        assert!(rep.table().contains("good / stretched"));
    }

    #[test]
    fn wrong_tangent_sign_is_caught_by_the_tangent_check() {
        let r = check_kind(&kind("wrong_sign", build_spring, || {
            spring_samples(Bug::WrongSign)
        }));
        let t = r.iter().find(|x| x.check == "tangent").unwrap();
        assert_eq!(t.outcome, Outcome::Fail);
        // K = −K_fd: max|K − K_fd| = 2·max|K|.
        assert!((t.value - 2.0).abs() < 1e-6, "{t:?}");
        let rep = Report { results: r };
        assert!(!rep.passed());
        assert!(rep.table().contains("FAIL"));
    }

    #[test]
    fn asymmetric_tangent_is_caught_by_the_symmetry_check() {
        let r = check_kind(&kind("asym", build_spring, || {
            spring_samples(Bug::Asymmetric)
        }));
        // The tangent is consistent and rows sum to zero: only symmetry fails.
        assert_eq!(failed(&r), vec!["symmetry"], "{r:#?}");
        let s = r.iter().find(|x| x.check == "symmetry").unwrap();
        // |K01 − K10| = k against max|K| = 2k.
        assert!((s.value - 0.5).abs() < 1e-12, "{s:?}");
    }

    #[test]
    fn forgetful_revert_is_caught_by_the_revert_check() {
        let good = check_kind(&kind("plastic", build_plastic, || plastic_samples(false)));
        assert!(failed(&good).is_empty(), "{good:#?}");
        assert_eq!(outcome(&good, "rigid_body"), Outcome::Skipped);
        let bad = check_kind(&kind("forgetful", build_plastic, || plastic_samples(true)));
        assert_eq!(outcome(&bad, "revert"), Outcome::Fail, "{bad:#?}");
    }

    #[test]
    fn kinds_without_samples_fail_visibly() {
        let r = check_kind(&kind("empty", build_spring, Vec::new));
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].check, Check::Samples);
        assert!(!r[0].passed());
    }

    #[test]
    fn filter_selects_nothing_for_an_unknown_name() {
        let rep = check_all(Some("no_such_element_kind_anywhere"));
        assert!(rep.results.is_empty() && rep.passed());
    }

    /// A failure reads as the check it is: a relative number is named as what it measures,
    /// and a failure in joules (a dissipation that decreased) is not printed in the column
    /// of relative numbers.
    #[test]
    fn a_failure_names_its_check_and_its_measure() {
        let row = |value: f64, limit: f64, note: &str| CheckResult {
            kind: "k".into(),
            sample: "s".into(),
            check: Check::Energy,
            outcome: Outcome::Fail,
            value,
            limit,
            note: note.into(),
        };
        let relative = Report {
            results: vec![row(2e-2, 1e-6, "")],
        }
        .table();
        assert!(
            relative.contains(
                "FAIL k / s / energy check: relative energy-balance error 2.0e-2 (limit 1.0e-6)"
            ),
            "{relative}"
        );
        let joules = Report {
            results: vec![row(
                f64::NAN,
                f64::NAN,
                "dissipated_energy() decreased at step 3: 1.2e3 J → 9.0e2 J",
            )],
        }
        .table();
        let line = joules.lines().find(|l| l.starts_with("FAIL k")).unwrap();
        assert!(
            line.contains("energy check: dissipated_energy() decreased"),
            "{line}"
        );
        assert!(
            !line.contains("relative") && !line.contains("limit"),
            "{line}"
        );
    }
}
