//! Matrix Market files of the assembled system, written and read through `sprs`.
//!
//! What lives here: the conversion of the framework's [`CscMatrix`] into an `sprs` matrix
//! (both store compressed columns with sorted row indices, so the arrays carry over
//! unchanged), the writing of a matrix or a vector as a Matrix Market `coordinate real
//! general` file (indices 1-based, values in Rust's shortest round-trip form, so reading a
//! file back gives the very same `f64`s), and the reading of such a file back into an
//! `sprs` matrix. A vector is written as an `n × 1` matrix of its nonzero entries.
//!
//! The solvers keep [`CscMatrix`]: it carries the pattern id the factorizations key their
//! symbolic analysis on, it always stores the diagonal, and its parallel symmetric product
//! ([`crate::sparse::symmetric_products`]) is what the time loop spends its time in;
//! `sprs` serves at the boundary, where files go out and come in (docs/matrices.md).

use crate::error::FemError;
use crate::sparse::CscMatrix;
use std::path::Path;

/// The matrix as an `sprs` compressed-sparse-column matrix (same entries, stored zeros
/// included: the pattern is kept as assembled).
pub fn to_sprs(a: &CscMatrix) -> sprs::CsMat<f64> {
    sprs::CsMat::new_csc(
        (a.n, a.n),
        a.col_ptr.clone(),
        a.row_idx.clone(),
        a.values.clone(),
    )
}

/// Writes `a` to `path` in Matrix Market coordinate format, dropping stored zeros (a
/// pattern entry whose value is exactly zero says nothing a reader needs).
pub fn write_matrix(path: &Path, a: &CscMatrix) -> Result<(), FemError> {
    let mut tri = sprs::TriMat::new((a.n, a.n));
    for j in 0..a.n {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            if a.values[p] != 0.0 {
                tri.add_triplet(a.row_idx[p], j, a.values[p]);
            }
        }
    }
    let m: sprs::CsMat<f64> = tri.to_csc();
    sprs::io::write_matrix_market(path, &m).map_err(|e| FemError::output(path, e))
}

/// Writes the vector `x` to `path` as an `n × 1` Matrix Market coordinate matrix of its
/// nonzero entries (`scipy.io.mmread(path).toarray().ravel()` gives it back dense).
pub fn write_vector(path: &Path, x: &[f64]) -> Result<(), FemError> {
    let mut tri = sprs::TriMat::new((x.len(), 1));
    for (i, &v) in x.iter().enumerate() {
        if v != 0.0 {
            tri.add_triplet(i, 0, v);
        }
    }
    let m: sprs::CsMat<f64> = tri.to_csc();
    sprs::io::write_matrix_market(path, &m).map_err(|e| FemError::output(path, e))
}

/// Reads a Matrix Market file (any symmetry mode `sprs` knows) as a compressed-column
/// matrix, duplicates summed.
pub fn read_matrix(path: &Path) -> Result<sprs::CsMat<f64>, FemError> {
    let tri: sprs::TriMat<f64> = sprs::io::read_matrix_market(path).map_err(|e| {
        FemError::input(
            path.display().to_string(),
            format!("not a readable Matrix Market file: {e}; write it with `railfem matrices`"),
        )
    })?;
    Ok(tri.to_csc())
}

/// Reads a vector written by [`write_vector`] (an `n × 1` matrix) back as a dense vector.
pub fn read_vector(path: &Path) -> Result<Vec<f64>, FemError> {
    let m = read_matrix(path)?;
    if m.cols() != 1 {
        return Err(FemError::input(
            path.display().to_string(),
            format!(
                "a vector file must have one column, this one has {}; give the load vector file",
                m.cols()
            ),
        ));
    }
    let mut x = vec![0.0; m.rows()];
    for (&v, (i, _)) in m.iter() {
        x[i] += v;
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix with stored zeros and awkward values goes out and comes back bit for bit;
    /// the zeros are not written.
    #[test]
    fn matrix_and_vector_round_trip_exactly() {
        let a = CscMatrix::from_triplets(
            3,
            &[
                (0, 0, 2.0),
                (1, 0, -1.0 / 3.0),
                (0, 1, -1.0 / 3.0),
                (1, 1, 1e-300),
                (2, 2, 0.0),
                (0, 2, std::f64::consts::PI * 1e12),
            ],
        );
        let dir = std::env::temp_dir().join(format!("railfem-mm-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.mtx");
        write_matrix(&p, &a).unwrap();
        let b = read_matrix(&p).unwrap();
        assert_eq!(b.nnz(), 5, "the stored zero (2,2) is dropped");
        for j in 0..3 {
            for i in 0..3 {
                let got = b.get(i, j).copied().unwrap_or(0.0);
                assert_eq!(got.to_bits(), a.get(i, j).to_bits(), "({i},{j})");
            }
        }
        assert_eq!(to_sprs(&a).nnz(), a.nnz());
        let x = vec![0.0, -7.25, 1.0 / 7.0, 0.0];
        let pv = dir.join("x.mtx");
        write_vector(&pv, &x).unwrap();
        assert_eq!(read_vector(&pv).unwrap(), x);
        assert!(read_vector(&p).is_err(), "a 3-column file is not a vector");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
