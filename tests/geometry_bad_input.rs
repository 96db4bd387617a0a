//! Bad geometry input: an unknown `geometry` name, a corotational beam of zero length and a
//! finite-rotation node with only some rotations fixed each give exit code 2 and one line
//! on stderr naming the file, the place (element index and id, key or node) and the fix.

mod common;

use common::{railfem, temp_dir};

/// A corotational cantilever to break in one place at a time.
const GOOD: &str = r#"
[analysis]
kind = "static"

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [2.0, 0.0, 0.0]

[[element]]
type = "beam3d"
id = 7
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
geometry = "corotational"

[[load]]
type = "nodal"
node = 2
dof = "uz"
value = 1.0e4
"#;

fn check(name: &str, text: &str, expect: &[&str]) {
    common::check_bad_model(name, text, expect);
}

fn edit(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "`{from}` not in the model");
    GOOD.replacen(from, to, 1)
}

#[test]
fn the_unbroken_corotational_model_runs() {
    let dir = temp_dir("good-corot");
    let path = dir.join("good.toml");
    std::fs::write(&path, GOOD).expect("write");
    let o = railfem(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_geometry_names_the_key_and_the_choices() {
    let text = edit("geometry = \"corotational\"", "geometry = \"corotatonal\"");
    check(
        "geometry.toml",
        &text,
        &[
            "element[0] (id 7",
            "`geometry`",
            "`corotatonal`",
            "`linear`, `pdelta`, `corotational`",
        ],
    );
}

#[test]
fn zero_length_corotational_beam_is_refused() {
    let text = edit("xyz = [2.0, 0.0, 0.0]", "xyz = [0.0, 0.0, 0.0]");
    check(
        "zero_length.toml",
        &text,
        &[
            "element[0] (id 7",
            "corotational",
            "zero-length",
            "`nodes`",
            "connect two distinct points",
        ],
    );
}

#[test]
fn partly_fixed_rotations_at_a_finite_rotation_node_are_refused() {
    let text = edit(
        "xyz = [2.0, 0.0, 0.0]",
        "xyz = [2.0, 0.0, 0.0]\nfix = [\"rx\"]",
    );
    check(
        "partial_fix.toml",
        &text,
        &[
            "node 2",
            "rx, ry, rz all free, all fixed, or only one of them free",
            "fix or free the rotations together",
        ],
    );
}
