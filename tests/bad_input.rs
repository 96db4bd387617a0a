//! Bad model files: for each kind of mistake, `railfem run` exits with code 2 and prints
//! exactly one line on stderr that names the file, the place in it and what to fix — and
//! never panics.

mod common;

use common::{railfem, temp_dir};

/// A valid cantilever to break in one place at a time (one-line edits below).
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

[[load]]
type = "nodal"
node = 2
dof = "uz"
value = 1.0e4

[[recorder]]
type = "node"
node = 2
dofs = ["uz"]
file = "tip.csv"
"#;

/// Writes `text` as `name` into a fresh directory, runs `railfem run` on it and checks
/// the exit code (2), that stderr is one line, that it names the file, and that it contains
/// every string of `expect` (the place and the fix). Returns the line.
fn check(name: &str, text: &str, expect: &[&str]) -> String {
    let dir = temp_dir(name.split('.').next().unwrap_or("case"));
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write model");
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        path.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(2), "{name}: exit code; stderr: {err}");
    assert!(
        err.ends_with('\n') && err.lines().count() == 1,
        "{name}: stderr must be exactly one line, got {err:?}"
    );
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{name}: {err}"
    );
    assert!(err.contains(name), "{name}: the file is not named: {err}");
    for e in expect {
        assert!(err.contains(e), "{name}: expected `{e}` in: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    err
}

/// `GOOD` with the first occurrence of `from` replaced by `to` (which must exist).
fn edit(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "`{from}` not in the model");
    GOOD.replacen(from, to, 1)
}

#[test]
fn the_unbroken_model_runs() {
    let dir = temp_dir("good");
    let path = dir.join("good.toml");
    std::fs::write(&path, GOOD).expect("write");
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn malformed_toml_names_line_and_column() {
    // Line 6 of GOOD is `id = 1` of the first node (line 1 is empty).
    let text = edit("id = 1\n", "id = = 1\n");
    let e = check(
        "syntax.toml",
        &text,
        &["syntax.toml:6:", "TOML syntax error"],
    );
    // line:column then a message: `file:6:6: TOML syntax error: …`
    let col = e
        .split("syntax.toml:6:")
        .nth(1)
        .and_then(|r| r.split(':').next())
        .unwrap_or("");
    assert!(col.parse::<usize>().is_ok(), "no column in {e}");
}

#[test]
fn malformed_json_names_line_and_column() {
    let text = "{\n  \"node\": [\n    {\"id\": 1,, \"xyz\": [0, 0, 0]}\n  ]\n}\n";
    check(
        "syntax.json",
        text,
        &["syntax.json:3:", "JSON syntax error"],
    );
}

#[test]
fn unknown_top_level_key_suggests_the_nearest() {
    let text = GOOD.replace("[[recorder]]", "[[recorders]]");
    check(
        "toplevel.toml",
        &text,
        &[
            "unknown top-level key `recorders`",
            "did you mean `recorder`?",
        ],
    );
}

#[test]
fn unknown_element_type_lists_the_nearest_registered() {
    let text = edit("type = \"beam3d\"", "type = \"beam3\"");
    check(
        "eltype.toml",
        &text,
        &[
            "element[0] (id 7, beam3)",
            "unknown element type `beam3`",
            "beam3d",
        ],
    );
}

#[test]
fn unknown_element_key_suggests_the_nearest() {
    let text = edit("Iy = 3.038e-5", "Iyy = 3.038e-5");
    check(
        "elkey.toml",
        &text,
        &[
            "element[0] (id 7, beam3d)",
            "unknown key `Iyy`",
            "did you mean `Iy`?",
        ],
    );
}

#[test]
fn missing_required_element_key_is_named() {
    let text = edit("E = 2.1e11\n", "");
    check(
        "missing.toml",
        &text,
        &["element[0] (id 7, beam3d)", "missing key `E`", "add it"],
    );
}

#[test]
fn missing_node_coordinates_are_named() {
    let text = edit("xyz = [2.0, 0.0, 0.0]\n", "");
    check("noxyz.toml", &text, &["node[1]", "xyz"]);
}

#[test]
fn duplicate_node_id_is_refused() {
    let text = edit("id = 2\n", "id = 1\n");
    check(
        "dupnode.toml",
        &text,
        &["node[1]", "duplicate node id 1", "node[0]"],
    );
}

#[test]
fn element_on_a_missing_node_is_refused() {
    let text = edit("nodes = [1, 2]", "nodes = [1, 9]");
    check(
        "nonode.toml",
        &text,
        &[
            "element[0] (id 7, beam3d)",
            "node 9 does not exist",
            "[[node]]",
        ],
    );
}

#[test]
fn nan_coordinate_is_refused() {
    let text = edit("xyz = [2.0, 0.0, 0.0]", "xyz = [2.0, nan, 0.0]");
    check(
        "nan.toml",
        &text,
        &["node[1].xyz[1]", "not a finite number", "finite value"],
    );
}

#[test]
fn negative_mass_is_refused() {
    let text = format!("{GOOD}\n[[element]]\ntype = \"mass\"\nid = 8\nnodes = [2]\nm = -5.0\n");
    check(
        "negmass.toml",
        &text,
        &["element[1] (id 8, mass)", "`m` = -5", "≥ 0"],
    );
}

#[test]
fn zero_length_beam_is_refused() {
    let text = edit("xyz = [2.0, 0.0, 0.0]", "xyz = [0.0, 0.0, 0.0]");
    check(
        "zerolen.toml",
        &text,
        &[
            "element[0] (id 7, beam3d)",
            "zero-length",
            "distinct points",
        ],
    );
}

#[test]
fn non_positive_modulus_is_refused() {
    let text = edit("E = 2.1e11", "E = 0.0");
    check(
        "zeroe.toml",
        &text,
        &["element[0] (id 7, beam3d)", "`E` = 0", "positive"],
    );
}

/// Node 3 carries a mass and may move along ux, but nothing is stiff there: the static
/// solve must name that DOF.
#[test]
fn unconstrained_dof_is_named() {
    let text = format!(
        "{GOOD}\n[[node]]\nid = 3\nxyz = [4.0, 0.0, 0.0]\nfix = [\"uy\", \"uz\", \"rx\", \"ry\", \"rz\"]\n\n[[element]]\ntype = \"mass\"\nid = 8\nnodes = [3]\nm = 10.0\n"
    );
    check("singular.toml", &text, &["node 3 ux", "fix that DOF"]);
}

#[test]
fn load_on_a_missing_node_is_refused() {
    let text = edit("node = 2\ndof", "node = 9\ndof");
    check(
        "loadnode.toml",
        &text,
        &["load[0]", "node 9 does not exist"],
    );
}

#[test]
fn bad_dof_names_are_refused() {
    let text = edit("dof = \"uz\"", "dof = \"uzz\"");
    check(
        "loaddof.toml",
        &text,
        &["load[0]", "\"uzz\" is not a DOF", "ux, uy, uz, rx, ry, rz"],
    );
    let text = edit("fix = \"all\"", "fix = [\"ux\", \"uq\"]");
    check(
        "fixdof.toml",
        &text,
        &["node[0]", "`uq` is not a DOF", "ux, uy, uz, rx, ry, rz"],
    );
}

#[test]
fn recorder_on_a_missing_node_is_refused() {
    let text = edit("node = 2\ndofs", "node = 9\ndofs");
    check(
        "recnode.toml",
        &text,
        &["recorder[0]", "tip.csv", "node 9 does not exist"],
    );
}

#[test]
fn negative_time_step_is_refused() {
    let text = edit("kind = \"static\"", "kind = \"transient\"\ndt = -0.001");
    check(
        "negdt.toml",
        &text,
        &["[analysis]", "`dt` must be a positive number", "-0.001"],
    );
}

/// Bad options of the validation commands: one line, exit code 2, never a hang or a panic.
#[test]
fn curve_command_refuses_bad_options() {
    for args in [
        vec!["curve", "--speed", "0", "--quiet"],
        vec!["curve", "--radius", "-5", "--quiet"],
        vec!["curve", "--dt", "0", "--quick", "--quiet"],
        vec!["curve", "--speed", "abc"],
        vec!["critical-radius", "--criterion", "tipping"],
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .args(&args)
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    }
}
