//! `railfem-measure threshold`: where the dense solver stops paying — dense LU
//! against the sparse direct solver per factorization + solve and per solve, on the
//! effective tangents of two representative model families, for n ≈ 20 … 2000 equations.
//!
//! * `beam`: one span of `beam3d` elements (six DOF per node, consistent mass; the
//!   benchmark beam of [`railfem::bench`] with `n/6` elements), banded;
//! * `vehicle`: trains of 1 … 30 `sks700` carriages on a rigid track (66 equations each;
//!   bodies, suspensions and wheels), block diagonal with small dense blocks; frictionless
//!   wheels (symmetric: sparse Cholesky) and with μ = 0.3 (the curve case's wheels,
//!   unsymmetric: sparse LU).
//!
//! Each time is the median of repeated runs (at least 5, and at least 0.2 s in all), the
//! factorization on a solver that has already seen the pattern (what a run repeats every
//! Newton iteration). The driver's [`railfem::solvers::driver::DENSE_LIMIT`] is chosen from
//! this table (docs/performance.md, "Small models and the bandwidth floor").

use railfem::framework::{FemError, Model};
use railfem::solvers::dense::DenseLu;
use railfem::solvers::linear::{solver_for, LinearSolver};
use railfem::solvers::Driver;
use std::path::Path;
use std::time::Instant;

/// One pattern at one size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThresholdRow {
    /// `beam` or `vehicle`.
    pub family: &'static str,
    /// Equations.
    pub n: usize,
    /// Stored entries of the effective tangent.
    pub nnz: usize,
    /// The sparse solver the driver would use: `Cholesky` (symmetric) or `LU`.
    pub sparse: &'static str,
    /// Dense LU: factorization + one solve (s).
    pub dense_factor_solve: f64,
    /// Dense: one solve (s).
    pub dense_solve: f64,
    /// Sparse: numeric refactorization + one solve (s).
    pub sparse_factor_solve: f64,
    /// Sparse: one solve (s).
    pub sparse_solve: f64,
}

fn median_time(mut f: impl FnMut()) -> f64 {
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 5 || (start.elapsed().as_secs_f64() < 0.2 && times.len() < 10_000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn beam(n: usize) -> Result<Model, FemError> {
    let geo = railfem::bench::BenchBeam {
        spans: 1,
        elements_per_span: (n / 6).max(1),
        mass: railfem::bench::BenchMass::Consistent,
    };
    geo.model(1)
}

fn vehicle(carriages: usize, wheel: &str) -> Result<Model, FemError> {
    let text = format!(
        r#"
[analysis]
kind = "transient"
dt = 0.002
duration = 0.002

[track]
segments = [{{type = "straight", length = {}}}]
element_length = 0.6
support = {{type = "rigid"}}

[[vehicle]]
preset = "sks700"
carriages = {carriages}
start = {}
speed = 20.0
{wheel}
"#,
        60.0 + 40.0 * carriages as f64,
        30.0 + 30.0 * carriages as f64
    );
    let value = railfem::framework::modelfile::parse_toml(&text, "threshold vehicle")?;
    railfem::model_from_value(&value, "threshold vehicle", Path::new("."))
}

/// Times one model's effective tangent with both solvers.
pub fn measure(family: &'static str, model: Model) -> Result<ThresholdRow, FemError> {
    let d = Driver::new(model)?;
    let coef = d.integrator.coefficients(railfem::bench::DT);
    let mut k = d.asm.k_const.zeros_like();
    d.asm.effective(coef, &mut k);
    // The variable elements' tangents are not formed before a step, and a wheel's DOFs
    // may have neither mass nor constant stiffness: a diagonal shift of 1e-3 of the
    // largest diagonal makes every pattern definite. The work of both solvers depends on
    // the pattern and the size, not on these values.
    let n = k.n;
    let big = (0..n).map(|j| k.get(j, j).abs()).fold(0.0f64, f64::max);
    for j in 0..n {
        let p = k.position(j, j).expect("every diagonal is stored");
        k.values[p] += 1e-3 * big.max(1.0);
    }
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    let fail = |e| FemError::Singular(format!("threshold bench: {e}"));
    let mut dense = DenseLu::default();
    let mut sparse = solver_for(d.asm.symmetric());
    dense.factor(&k).map_err(fail)?;
    sparse.factor(&k).map_err(fail)?;
    let mut x = b.clone();
    let dense_factor_solve = median_time(|| {
        dense.factor(&k).expect("factored before");
        x.copy_from_slice(&b);
        dense.solve_in_place(&mut x).expect("solve");
    });
    let dense_solve = median_time(|| {
        x.copy_from_slice(&b);
        dense.solve_in_place(&mut x).expect("solve");
    });
    let sparse_factor_solve = median_time(|| {
        sparse.factor(&k).expect("factored before");
        x.copy_from_slice(&b);
        sparse.solve_in_place(&mut x).expect("solve");
    });
    let sparse_solve = median_time(|| {
        x.copy_from_slice(&b);
        sparse.solve_in_place(&mut x).expect("solve");
    });
    Ok(ThresholdRow {
        family,
        n,
        nnz: k.nnz(),
        sparse: if d.asm.symmetric() { "Cholesky" } else { "LU" },
        dense_factor_solve,
        dense_solve,
        sparse_factor_solve,
        sparse_solve,
    })
}

/// Both families over the sizes; the table on stdout and in `out/threshold.md`.
pub fn run(out: &Path) -> Result<Vec<ThresholdRow>, FemError> {
    let mut rows = Vec::new();
    for n in [
        6, 12, 18, 24, 30, 36, 48, 72, 96, 120, 150, 198, 246, 300, 402, 498, 750, 1002, 1500, 1998,
    ] {
        let r = measure("beam", beam(n)?)?;
        eprintln!("{}", line(&r));
        rows.push(r);
    }
    for (family, wheel) in [("vehicle", ""), ("vehicle μ = 0.3", "wheel = {mu = 0.3}")] {
        for c in [1, 2, 3, 4, 6, 8, 12, 16, 23, 30] {
            let r = measure(family, vehicle(c, wheel)?)?;
            eprintln!("{}", line(&r));
            rows.push(r);
        }
    }
    let table = markdown(&rows);
    print!("{table}");
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("threshold.md");
    std::fs::write(&p, &table).map_err(|e| FemError::output(&p, e))?;
    Ok(rows)
}

fn line(r: &ThresholdRow) -> String {
    format!(
        "threshold: {} n = {}: dense {:.1} µs, sparse {:.1} µs (factor + solve)",
        r.family,
        r.n,
        r.dense_factor_solve * 1e6,
        r.sparse_factor_solve * 1e6
    )
}

/// The rows as a markdown table (times in µs; ratios dense/sparse).
pub fn markdown(rows: &[ThresholdRow]) -> String {
    let mut s = String::from(
        "| pattern | n | nnz | sparse solver | dense factor+solve (µs) | sparse factor+solve (µs) | dense/sparse | dense solve (µs) | sparse solve (µs) | dense/sparse |\n|---|---:|---:|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.1} | {:.1} | {:.2} | {:.1} | {:.1} | {:.2} |\n",
            r.family,
            r.n,
            r.nnz,
            r.sparse,
            r.dense_factor_solve * 1e6,
            r.sparse_factor_solve * 1e6,
            r.dense_factor_solve / r.sparse_factor_solve,
            r.dense_solve * 1e6,
            r.sparse_solve * 1e6,
            r.dense_solve / r.sparse_solve
        ));
    }
    s
}
