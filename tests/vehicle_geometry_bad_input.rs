//! Bad geometry input of rigid links and vehicles: an unknown geometry name in
//! `[analysis]`, on a `[[link]]` or on the command line, a nonlinear-geometry link that
//! closes a cycle, and a partial nonlinear link. Each exits with code 2 and one line that
//! names the file (or the command line), the place and the fix — never a panic.

mod common;

use common::{railfem, refused_with, temp_dir};

/// A lever: node 1 turns about z (translations and rx, ry fixed), node 2 is its rigid
/// arm, node 3 a second arm on node 2; a grounded spring holds node 3.
const GOOD: &str = r#"
[analysis]
kind = "static"
geometry = "nonlinear"

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "uy", "uz", "rx", "ry"]

[[node]]
id = 2
xyz = [1.0, 0.0, 0.0]

[[node]]
id = 3
xyz = [2.0, 0.0, 0.0]

[[link]]
master = 1
slave = 2

[[link]]
master = 2
slave = 3

[[element]]
type = "spring_damper"
id = 1
nodes = [3]
k = [0.0, 1.0e6, 0.0, 0.0, 0.0, 0.0]

[[load]]
type = "nodal"
node = 1
dof = "rz"
value = 1.0e5
"#;

/// Runs `railfem check` on `text` saved as `name`; asserts exit 2, one line, the file
/// named and every string of `expect` present. Returns the line.
fn check(name: &str, text: &str, expect: &[&str]) -> String {
    let dir = temp_dir(name.split('.').next().unwrap_or("case"));
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write model");
    let o = railfem(&["check", path.to_str().expect("utf-8")]);
    let err = refused_with(name, &o, expect);
    assert!(err.contains(name), "{name}: the file is not named: {err}");
    let _ = std::fs::remove_dir_all(&dir);
    err
}

#[test]
fn the_unbroken_lever_checks() {
    let dir = temp_dir("lever");
    let path = dir.join("lever.toml");
    std::fs::write(&path, GOOD).expect("write");
    let o = railfem(&["check", path.to_str().expect("utf-8")]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn unknown_geometry_in_analysis() {
    let text = GOOD.replacen("geometry = \"nonlinear\"", "geometry = \"large\"", 1);
    check(
        "analysis_geometry.toml",
        &text,
        &[
            "[analysis]",
            "`geometry` = \"large\"",
            "\"linear\"",
            "\"nonlinear\"",
        ],
    );
}

#[test]
fn unknown_geometry_on_a_link() {
    let text = GOOD.replacen("slave = 3\n", "slave = 3\ngeometry = \"corotational\"\n", 1);
    check(
        "link_geometry.toml",
        &text,
        &["link[1]", "\"corotational\"", "\"nonlinear\""],
    );
}

#[test]
fn a_nonlinear_cycle_is_refused() {
    // Node 1 is unfixed here: a fixed slave is refused on its own, before any cycle is sought.
    let unfixed = GOOD.replacen("fix = [\"ux\", \"uy\", \"uz\", \"rx\", \"ry\"]\n", "", 1);
    let text = format!("{unfixed}\n[[link]]\nmaster = 3\nslave = 1\n");
    let line = check(
        "cycle.toml",
        &text,
        &["link[", "cycle", "remove one of these links"],
    );
    // The path of the cycle names the nodes.
    assert!(line.contains("1") && line.contains("3"), "{line}");
}

#[test]
fn a_partial_nonlinear_link_is_refused() {
    let text = GOOD.replacen(
        "master = 1\nslave = 2\n",
        "master = 1\nslave = 2\ndofs = [\"ux\", \"uy\"]\n",
        1,
    );
    check(
        "partial.toml",
        &text,
        &["link[0]", "all six DOFs", "geometry = \"linear\""],
    );
}

#[test]
fn unknown_geometry_on_the_command_line() {
    let o = railfem(&["curve", "--quick", "--geometry", "bent"]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("command line")
            && err.contains("--geometry bent")
            && err.contains("nonlinear"),
        "{err}"
    );
}
