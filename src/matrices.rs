//! `railfem matrices MODEL --out DIR`: the model's linear system about its reference state
//! in Matrix Market files, for scipy, MATLAB or Julia.
//!
//! What lives here: the command that builds the model as `run` would, forms the tangent
//! stiffness at zero displacement, the constant mass and damping and the load vector
//! ([`crate::solvers::Driver::reference_system`]), writes them through `sprs`
//! ([`crate::framework::matrix_market`]) as `K.mtx`, `M.mtx`, `C.mtx` and `f.mtx`, and
//! writes the DOF map `dofs.csv`: which node and DOF each equation (row of `K`) is.

use crate::framework::matrix_market::{write_matrix, write_vector};
use crate::framework::FemError;
use std::fmt::Write as _;
use std::path::Path;

/// Names of the files written, in order: stiffness, mass, damping, load, DOF map.
pub const FILES: [&str; 5] = ["K.mtx", "M.mtx", "C.mtx", "f.mtx", "dofs.csv"];

/// Header of `dofs.csv`.
pub const DOF_HEADER: &str =
    "equation [1-based row of K],node [id],dof [ux|uy|uz|rx|ry|rz],unit [m or rad]";

/// Writes the files of model `path` into `out`; returns the number of equations.
pub fn write(path: &Path, out: &Path) -> Result<usize, FemError> {
    let file = path.display().to_string();
    let model = crate::load_model(path).map_err(|e| e.in_file(&file))?;
    let mut d = crate::solvers::Driver::new(model).map_err(|e| e.in_file(&file))?;
    let sys = d.reference_system().map_err(|e| e.in_file(&file))?;
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    write_matrix(&out.join(FILES[0]), &sys.stiffness)?;
    write_matrix(&out.join(FILES[1]), &sys.mass)?;
    write_matrix(&out.join(FILES[2]), &sys.damping)?;
    write_vector(&out.join(FILES[3]), &sys.load)?;
    let n = d.neq();
    let mut csv = String::with_capacity(32 * n + 80);
    csv.push_str(DOF_HEADER);
    csv.push('\n');
    for eq in 0..n {
        let (node, dof) = d.asm.dofmap.dof_of(eq);
        let unit = if dof.index() < 3 { "m" } else { "rad" };
        let _ = writeln!(csv, "{},{},{dof},{unit}", eq + 1, d.model.nodes[node].id);
    }
    let p = out.join(FILES[4]);
    std::fs::write(&p, csv).map_err(|e| FemError::output(&p, e))?;
    Ok(n)
}
