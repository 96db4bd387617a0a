//! `railfem bench --case floor`: the linear beam's time per step against the
//! memory-bandwidth floor of what a step must do, and the machine's bandwidth.
//!
//! A linear step with a kept factor must at least read the matrices' values once (K and M,
//! and C when it is not zero: `nnz × 8` bytes each; a diagonal (lumped) M only its
//! diagonal, `n × 8` bytes, which is all of it a product needs), their shared pattern once (row indices
//! and column pointers, at the width the code stores them) and the factor twice (forward
//! and backward triangular solves: `factor entries × (8 + index width)` bytes each). At the
//! measured streaming bandwidth `B` that traffic takes `floor = bytes / B`; the report
//! gives `time per step / floor` per size.
//!
//! The bandwidth is measured here with two STREAM-like kernels over arrays far larger than
//! the caches (3 × 128 MiB): *copy* `a[i] = b[i]` (16 bytes per element moved) and *triad*
//! `a[i] = b[i] + s·c[i]` (24 bytes), single-threaded like the step's products and solves
//! (a step's passes are single-threaded below 20 000 columns per thread; the factor solves
//! are sequential). Write-allocate traffic is not counted, as in STREAM. The best of five
//! repetitions is the bandwidth.

use crate::bench::{BenchBeam, BenchMass, DT};
use crate::framework::FemError;
use crate::solvers::Driver;
use std::path::Path;
use std::time::Instant;

/// Elements per array of the bandwidth kernels (128 MiB of f64).
const STREAM_LEN: usize = 1 << 24;

/// Measured streaming bandwidth (bytes/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bandwidth {
    /// `a = b`, best of five.
    pub copy: f64,
    /// `a = b + s·c`, best of five.
    pub triad: f64,
}

/// Runs the copy and triad kernels.
pub fn bandwidth() -> Bandwidth {
    let n = STREAM_LEN;
    let mut a = vec![0.0f64; n];
    let b: Vec<f64> = (0..n).map(|i| (i % 13) as f64).collect();
    let c: Vec<f64> = (0..n).map(|i| (i % 7) as f64).collect();
    let (mut copy, mut triad) = (f64::INFINITY, f64::INFINITY);
    for rep in 0..5 {
        let t = Instant::now();
        a.copy_from_slice(&b);
        copy = copy.min(t.elapsed().as_secs_f64());
        std::hint::black_box(&a);
        let s = 1.0 + rep as f64;
        let t = Instant::now();
        for ((x, y), z) in a.iter_mut().zip(&b).zip(&c) {
            *x = y + s * z;
        }
        triad = triad.min(t.elapsed().as_secs_f64());
        std::hint::black_box(&a);
    }
    Bandwidth {
        copy: 16.0 * n as f64 / copy,
        triad: 24.0 * n as f64 / triad,
    }
}

/// One size of the floor table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorRow {
    /// Requested DOF count.
    pub target: usize,
    /// The beam's mass matrix.
    pub mass: BenchMass,
    /// Whether the assembler found M diagonal (and reads only its diagonal).
    pub diagonal_mass: bool,
    /// Equations.
    pub equations: usize,
    /// Stored entries of K (= of M and C: one pattern).
    pub nnz: usize,
    /// Whether C has any non-zero value.
    pub damping: bool,
    /// Entries of the Cholesky factor.
    pub factor_nnz: usize,
    /// Bytes a step must move (see the module documentation).
    pub bytes: f64,
    /// Wall time per step, factor kept (s).
    pub per_step: f64,
    /// Per step: assembly (residual products and element work), solve, loads (s).
    pub assembly: f64,
    /// Per step: triangular solves (s).
    pub solve: f64,
    /// Per step: loads (s).
    pub loads: f64,
}

/// Runs `steps` steps of the benchmark beam after a first step that carries the
/// factorization; the floor's traffic from the model's actual storage.
pub fn measure(target: usize, steps: usize, mass: BenchMass) -> Result<FloorRow, FemError> {
    let geo = BenchBeam {
        mass,
        ..BenchBeam::for_dof(target)
    };
    let mut d = Driver::new(geo.model(steps + 1)?)?;
    d.initialize()?;
    d.step(DT)?;
    let before = d.summary.timings;
    let t0 = Instant::now();
    for _ in 0..steps {
        d.step(DT)?;
    }
    let wall = t0.elapsed().as_secs_f64();
    let after = d.summary.timings;
    let k = &d.asm.k_const;
    let nnz = k.nnz();
    let damping = d.asm.c_const.values.iter().any(|&c| c != 0.0);
    let factor_nnz = d.solver_stats().factor_nnz;
    let index = std::mem::size_of::<usize>() as f64;
    let diagonal_mass = d.asm.mass_diagonal().is_some();
    let pattern_matrices = if damping { 2.0 } else { 1.0 };
    let m_bytes = 8.0 * if diagonal_mass { k.n } else { nnz } as f64;
    let bytes = nnz as f64 * (8.0 * pattern_matrices + index)
        + m_bytes
        + (k.n + 1) as f64 * index
        + 2.0 * factor_nnz as f64 * (8.0 + index);
    let s = steps.max(1) as f64;
    Ok(FloorRow {
        target,
        mass,
        diagonal_mass,
        equations: d.neq(),
        nnz,
        damping,
        factor_nnz,
        bytes,
        per_step: wall / s,
        assembly: (after.assembly - before.assembly) / s,
        solve: (after.solve - before.solve) / s,
        loads: (after.loads - before.loads) / s,
    })
}

/// The bandwidth, then every size; the table on stdout and in `out/floor.md`.
pub fn run(
    sizes: &[usize],
    steps: usize,
    mass: BenchMass,
    out: &Path,
) -> Result<Vec<FloorRow>, FemError> {
    let bw = bandwidth();
    let mut s = format!(
        "bandwidth (one thread, best of 5 over 3 × 128 MiB): copy {:.2} GB/s, triad {:.2} GB/s\n\n",
        bw.copy / 1e9,
        bw.triad / 1e9
    );
    eprint!("{s}");
    let mut rows = Vec::new();
    for &n in sizes {
        let r = measure(n, steps, mass)?;
        eprintln!(
            "floor: {} equations: {:.3} ms/step",
            r.equations,
            r.per_step * 1e3
        );
        rows.push(r);
    }
    s.push_str(&markdown(&rows, bw.triad));
    print!("{s}");
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("floor.md");
    std::fs::write(&p, &s).map_err(|e| FemError::output(&p, e))?;
    Ok(rows)
}

/// The rows as a markdown table against bandwidth `bw` (bytes/s).
pub fn markdown(rows: &[FloorRow], bw: f64) -> String {
    let mut s = String::from(
        "| target DOF | mass | equations | nnz(K) | C ≠ 0 | factor entries | floor traffic (MB) | floor (ms) | step (ms) | step / floor | assembly (ms) | solve (ms) | loads (ms) |\n|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let floor = r.bytes / bw;
        s.push_str(&format!(
            "| {} | {}{} | {} | {} | {} | {} | {:.1} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
            r.target,
            r.mass.name(),
            if r.diagonal_mass { " (diagonal)" } else { "" },
            r.equations,
            r.nnz,
            if r.damping { "yes" } else { "no" },
            r.factor_nnz,
            r.bytes / 1e6,
            floor * 1e3,
            r.per_step * 1e3,
            r.per_step / floor,
            r.assembly * 1e3,
            r.solve * 1e3,
            r.loads * 1e3
        ));
    }
    s
}
