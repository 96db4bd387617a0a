//! `railfem check` refuses what `railfem run` refuses (issue 36 item 6, docs/robustness.md):
//! a cantilever whose root is free to twist is a mechanism that no diagonal shows (every
//! torsional diagonal is GJ/L > 0); the trial factorization `check` makes finds its zero
//! pivot and names it as the run does, with the word "mechanism".

mod common;

use common::{railfem, refused_with, temp_dir};

/// Two beam3d elements along X, nodes 1–3, a tip force along Z at node 3; node 1 fixed in
/// the DOFs `root_fix`.
fn cantilever(root_fix: &str) -> String {
    format!(
        r#"
[analysis]
kind = "static"
steps = 1

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = {root_fix}

[[node]]
id = 2
xyz = [1.0, 0.0, 0.0]

[[node]]
id = 3
xyz = [2.0, 0.0, 0.0]

[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6

[[element]]
type = "beam3d"
id = 2
nodes = [2, 3]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6

[[load]]
type = "nodal"
node = 3
dof = "uz"
value = 1.0e4
"#
    )
}

#[test]
fn check_finds_the_torsion_mechanism_that_run_stops_on() {
    let dir = temp_dir("mechanism");
    let free = dir.join("free_torsion.toml");
    std::fs::write(&free, cantilever(r#"["ux", "uy", "uz", "ry", "rz"]"#)).unwrap();
    let want = [
        "free_torsion.toml",
        "no stiffness at node 3 rx",
        "mechanism",
        "fix that DOF",
    ];
    let checked = refused_with("check", &railfem(&["check", free.to_str().unwrap()]), &want);
    let ran = refused_with(
        "run",
        &railfem(&[
            "run",
            free.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
            "-q",
        ]),
        &want,
    );
    // The same message, word for word.
    assert_eq!(checked, ran);
    // The clamped cantilever passes both (the check refuses the mechanism, not the model).
    let clamped = dir.join("clamped.toml");
    std::fs::write(&clamped, cantilever(r#""all""#)).unwrap();
    let o = railfem(&["check", clamped.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stdout).contains("ok"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Above the size bound (100 000 equations) `check` skips the factorization and says so,
/// with the option that forces it; `--factor` then finds the mechanism, in the words of
/// `run`. The model: a clamped beam of 16 700 nodes (100 194 equations) and apart from it
/// one element between two nodes held in every DOF but rx: its torsion is free, and the
/// 2×2 block `GJ/L·[1 −1; −1 1]` has an exactly zero second pivot whatever the ordering.
#[test]
fn above_the_bound_check_says_the_mechanism_check_was_skipped() {
    let dir = temp_dir("mechanism-large");
    let n = 16_700;
    let section =
        "E = 2.1e11\nG = 8.1e10\nA = 7.686e-3\nIy = 3.038e-5\nIz = 5.123e-6\nJ = 2.0e-6\n";
    let twist = "fix = [\"ux\", \"uy\", \"uz\", \"ry\", \"rz\"]\n";
    let mut text = String::from("[analysis]\nkind = \"static\"\nsteps = 1\n");
    for k in 1..=n {
        let fix = if k == 1 { "fix = \"all\"\n" } else { "" };
        text.push_str(&format!(
            "[[node]]\nid = {k}\nxyz = [{}, 0.0, 0.0]\n{fix}",
            k as f64 * 0.1
        ));
    }
    for (id, x) in [(n + 1, 0.0), (n + 2, 1.0)] {
        text.push_str(&format!(
            "[[node]]\nid = {id}\nxyz = [{x}, 5.0, 0.0]\n{twist}"
        ));
    }
    for k in 1..n {
        text.push_str(&format!(
            "[[element]]\ntype = \"beam3d\"\nid = {k}\nnodes = [{k}, {}]\n{section}",
            k + 1
        ));
    }
    text.push_str(&format!(
        "[[element]]\ntype = \"beam3d\"\nid = {n}\nnodes = [{}, {}]\n{section}",
        n + 1,
        n + 2
    ));
    text.push_str(&format!(
        "[[load]]\ntype = \"nodal\"\nnode = {n}\ndof = \"uz\"\nvalue = 1.0\n"
    ));
    let path = dir.join("long.toml");
    std::fs::write(&path, text).unwrap();
    let o = railfem(&["check", path.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    assert!(
        out.contains("100196 equations")
            && out.contains("mechanism check")
            && out.contains("skipped")
            && out.contains("--factor"),
        "{out}"
    );
    let want = ["long.toml", "no stiffness at node", "rx", "mechanism"];
    let checked = refused_with(
        "check --factor",
        &railfem(&["check", "--factor", path.to_str().unwrap()]),
        &want,
    );
    let ran = refused_with(
        "run",
        &railfem(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
            "-q",
        ]),
        &want,
    );
    assert_eq!(checked, ran);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A massless cantilever tip (node 2) carrying a 100 kg point mass (node 3) 0.5 m above it
/// through a rigid link, starting a transient from rest. Every translation and rotation
/// of node 2 but rz has mass on its diagonal (m, m, m for u; m·h² for rx, ry), so no
/// diagonal shows a fault; but the mass matrix on (uy, rx) is m·[1 −h; −h h²], whose
/// determinant is 0: eliminating uy leaves rx the pivot m·h² − (m·h)²/m = 0. `run` factors
/// this matrix first (the initial acceleration) and stops there; `check` makes the same
/// factorization and stops with the same line. Rotary inertia of node 2's own (a `mass`
/// element with `inertia`) makes the block regular, and both accept the model.
fn offset_mass(own_inertia: &str) -> String {
    format!(
        r#"
[analysis]
kind = "transient"
dt = 0.01
duration = 0.03

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [2.5, 0.0, 0.0]

[[node]]
id = 3
xyz = [2.5, 0.0, 0.5]

[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6

[[element]]
type = "mass"
id = 2
nodes = [3]
m = 100.0

{own_inertia}

[[link]]
master = 2
slave = 3

[[load]]
type = "nodal"
node = 2
dof = "uz"
value = 1.0e4
series = {{type = "table", points = [[0.0, 0.0], [1.0, 1.0]]}}
"#
    )
}

#[test]
fn check_factors_the_initial_mass_as_run_does() {
    let dir = temp_dir("mass-singular");
    let path = dir.join("offset_mass.toml");
    std::fs::write(&path, offset_mass("")).unwrap();
    let want = [
        "offset_mass.toml",
        "the mass matrix is singular at node 2 rx (equation 3)",
        "rotary inertia",
    ];
    let p = path.to_str().unwrap();
    let checked = refused_with("check", &railfem(&["check", p]), &want);
    let out = dir.join("out");
    let ran = refused_with(
        "run",
        &railfem(&["run", p, "--out", out.to_str().unwrap(), "-q"]),
        &want,
    );
    assert_eq!(checked, ran);
    // Rotary inertia of the master's own: check and run both accept the model.
    std::fs::write(
        &path,
        offset_mass(
            "[[element]]\ntype = \"mass\"\nid = 3\nnodes = [2]\nm = 0.0\ninertia = [1.0, 1.0, 1.0]",
        ),
    )
    .unwrap();
    let o = railfem(&["check", p]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let o = railfem(&["run", p, "--out", out.to_str().unwrap(), "-q"]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
