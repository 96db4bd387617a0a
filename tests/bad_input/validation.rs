//! Round two of bad input (issue 20): nonsense that used to run, `railfem check` against
//! `railfem run` (one validation, every problem listed), and valid inputs that used to be
//! refused. Included from `tests/bad_input.rs`, whose helpers ([`check`], [`edit`],
//! [`check_train`]) it uses: each bad case asserts exit code 2 and a line naming the file,
//! the key and the fix.

use super::{check, check_train, edit, GOOD};
use crate::common::{railfem, temp_dir, Csv};

/// Runs `railfem check` on `text` written as `name`: exit code and stderr lines.
fn check_lines(name: &str, text: &str) -> (Option<i32>, Vec<String>, String) {
    let dir = temp_dir(name.split('.').next().unwrap_or("case"));
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write model");
    let o = railfem(&["check", path.to_str().expect("utf-8")]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{err}"
    );
    (
        o.status.code(),
        err.lines().map(str::to_string).collect(),
        out,
    )
}

/// `check` lists one line per entry of `expect` (each line containing all its strings and
/// the file name), exits with 2, and `run` prints exactly the first of them (one line,
/// with the count of the others).
fn check_lists_and_run_stops_at_the_first(name: &str, text: &str, expect: &[&[&str]]) {
    let (code, lines, _) = check_lines(name, text);
    assert_eq!(code, Some(2), "{name}: {lines:?}");
    let errors: Vec<&String> = lines.iter().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), expect.len(), "{name}: {lines:#?}");
    for (line, want) in errors.iter().zip(expect) {
        assert!(line.contains(name), "{name}: the file is not named: {line}");
        for w in *want {
            assert!(line.contains(w), "{name}: expected `{w}` in: {line}");
        }
    }
    // The two ran in different temporary directories: compare from the file name on.
    let tail = |l: &str| {
        l.split_once(name)
            .map(|(_, t)| t.to_string())
            .unwrap_or_default()
    };
    let first = tail(errors[0]);
    let run_line = check(name, text, &[]);
    assert!(
        tail(&run_line).starts_with(&first),
        "{name}: run must report check's first problem\n run: {run_line}\ncheck: {first}"
    );
    if expect.len() > 1 {
        assert!(
            run_line.contains(&format!("and {} more problem", expect.len() - 1)),
            "{run_line}"
        );
    }
}

// --- nonsense refused -----------------------------------------------------------------

/// `GOOD` as JSON, with the beam's `E` written twice.
#[test]
fn json_duplicate_key_is_refused() {
    let text = r#"{
  "analysis": {"kind": "static"},
  "node": [
    {"id": 1, "xyz": [0.0, 0.0, 0.0], "fix": "all"},
    {"id": 2, "xyz": [2.0, 0.0, 0.0]}
  ],
  "element": [
    {"type": "beam3d", "id": 7, "nodes": [1, 2], "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3,
     "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6, "E": 2.1e9}
  ]
}"#;
    check(
        "dupkey.json",
        text,
        &[
            "dupkey.json:9:",
            "duplicate key `element[0].E`",
            "remove one",
        ],
    );
}

#[test]
fn spring_from_a_node_to_itself_is_refused() {
    let text = format!(
        "{GOOD}\n[[element]]\ntype = \"spring_damper\"\nid = 8\nnodes = [2, 2]\nk = [1.0e6, 0.0, 0.0, 0.0, 0.0, 0.0]\n"
    );
    check(
        "selfspring.toml",
        &text,
        &[
            "element[1] (id 8, spring_damper)",
            "`nodes` lists node 2 twice",
            "`nodes = [2]`",
        ],
    );
}

/// A fixed slave: the link would silently win over the `fix` (fully, or on some DOFs).
#[test]
fn link_to_a_fixed_slave_is_refused() {
    for (fix, names) in [("\"all\"", "ux, uy, uz, rx, ry, rz"), ("[\"uz\"]", "uz")] {
        let text = format!(
            "{GOOD}\n[[node]]\nid = 3\nxyz = [2.0, 0.0, 0.5]\nfix = {fix}\n\n[[link]]\nmaster = 2\nslave = 3\n"
        );
        check(
            "fixedslave.toml",
            &text,
            &[
                "link[0]",
                &format!("slave node 3 is fixed on {names}"),
                "fix the master node 2 instead",
            ],
        );
    }
}

#[test]
fn negative_rayleigh_coefficients_are_refused() {
    for (table, key) in [
        (
            "rayleigh = {alpha = -0.5, beta = 0.0}",
            "`rayleigh.alpha` = -0.5",
        ),
        (
            "rayleigh = {alpha = 0.0, beta = -1.0e-4}",
            "`rayleigh.beta` = -0.0001",
        ),
    ] {
        let text = edit(
            "kind = \"static\"",
            &format!("kind = \"transient\"\ndt = 0.01\nduration = 0.1\n{table}"),
        );
        check(
            "rayleigh.toml",
            &text,
            &["[analysis]", key, "give a value ≥ 0"],
        );
    }
}

/// `rail_nodes = 0` used to be replaced by 4 without a word; `wheel_points = 3` by 20.
#[test]
fn too_few_profile_points_are_refused_not_replaced() {
    check_train(
        "railnodes",
        "wheel = {mu = 0.3}",
        "wheel = {mu = 0.3, rail_nodes = 0}",
        &[],
        &[
            "[vehicle][0]",
            "`wheel` (element",
            "`rail_nodes` = 0",
            "at least 4",
        ],
    );
    check_train(
        "wheelpoints",
        "wheel = {mu = 0.3}",
        "wheel = {mu = 0.3, wheel_points = 3}",
        &[],
        &["[vehicle][0]", "`wheel_points` = 3", "at least 20"],
    );
}

/// Keys the documentation says a table does not read, given anyway.
#[test]
fn keys_a_table_ignores_are_refused() {
    check_train(
        "wheelside",
        "wheel = {mu = 0.3}",
        "wheel = {mu = 0.3, side = \"left\"}",
        &[],
        &[
            "[vehicle][0]",
            "`wheel.side` would be ignored",
            "remove `side`",
        ],
    );
    // HHT's α with the Newmark integrator; Newmark's β with HHT; load steps in a transient.
    for (analysis, key) in [
        (
            "kind = \"transient\"\nalpha = 0.1",
            "`alpha` would be ignored",
        ),
        (
            "kind = \"transient\"\nintegrator = \"hht\"\nbeta = 0.3",
            "`beta` would be ignored",
        ),
        (
            "kind = \"transient\"\nsteps = 10",
            "`steps` would be ignored",
        ),
        ("kind = \"static\"\ndt = 0.01", "`dt` would be ignored"),
    ] {
        let text = edit("kind = \"static\"", analysis);
        check("ignored.toml", &text, &["[analysis]", key, "remove it"]);
    }
}

/// SDOF (m = 1000 kg, k = 4e6 N/m: ω = 63.246 rad/s) with Newmark β = 0.05, γ = ½: stable
/// only for ω·Δt ≤ 1/√(γ/2 − β) = √5 (Hughes, Table 9.1.1), i.e. Δt ≤ 0.035355 s. Both
/// `check` and `run` accept it with a warning giving that limit.
#[test]
fn a_conditionally_stable_newmark_pair_is_accepted_with_its_limit() {
    let sdof = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/models/sdof.toml"
    ))
    .expect("example");
    let omega = (4.0e6f64 / 1000.0).sqrt();
    let limit = 1.0 / (0.25f64 - 0.05).sqrt() / omega;
    let want = format!("Δt ≤ {limit:.4e} s");
    for (dt, verdict) in [("0.05", "ABOVE it"), ("0.005", "below it")] {
        let text = sdof
            .replace("beta = 0.25", "beta = 0.05")
            .replace("dt = 0.005", &format!("dt = {dt}"));
        let (code, lines, out) = check_lines("cond.toml", &text);
        assert_eq!(code, Some(0), "{lines:?}");
        assert!(out.contains("ok"), "{out}");
        let w = lines
            .iter()
            .find(|l| l.starts_with("warning:"))
            .expect("warning");
        for s in [
            "cond.toml",
            "beta = 0.05",
            "outside the unconditionally stable",
            &want,
            verdict,
        ] {
            assert!(w.contains(s), "expected `{s}` in: {w}");
        }
        let dir = temp_dir("cond");
        let path = dir.join("cond.toml");
        std::fs::write(&path, &text).expect("write");
        let o = railfem(&[
            "run",
            path.to_str().expect("utf-8"),
            "--out",
            dir.join("out").to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&want) && err.contains("warning:"),
            "run: {err}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

// --- check runs what run runs, and lists every problem -------------------------------

/// Node `id` at x = `id` m with only DOF `free` free, carrying a 10 kg mass element (id
/// `id + 5`) with rotary inertia `inertia` (kg·m²) and nothing else.
fn mass_node(id: u64, free: &str, inertia: &str) -> String {
    let fixed: Vec<String> = ["ux", "uy", "uz", "rx", "ry", "rz"]
        .iter()
        .filter(|d| **d != free)
        .map(|d| format!("\"{d}\""))
        .collect();
    format!(
        "\n[[node]]\nid = {id}\nxyz = [{id}.0, 0.0, 0.0]\nfix = [{}]\n[[element]]\ntype = \"mass\"\nid = {}\nnodes = [{id}]\nm = 10.0\ninertia = {inertia}\n",
        fixed.join(", "),
        id + 5
    )
}

/// Two masses free in a static analysis: no stiffness at node 3 ux nor at node 4 uy. Found
/// before any factorization, both by `check`; `run` stops at the first.
#[test]
fn check_finds_every_singular_dof_before_a_factorization() {
    let text = format!(
        "{GOOD}{}{}",
        mass_node(3, "ux", "[0.0, 0.0, 0.0]"),
        mass_node(4, "uy", "[0.0, 0.0, 0.0]")
    );
    check_lists_and_run_stops_at_the_first(
        "twosingular.toml",
        &text,
        &[
            &["no stiffness at node 3 ux", "mass only", "fix that DOF"],
            &["no stiffness at node 4 uy", "mass only", "add a spring"],
        ],
    );
}

/// A free rotation with rotary inertia and no stiffness: fine in a transient without
/// loads at t = 0 (the mass term makes K_eff regular), singular in a static analysis and
/// in a transient whose initial static equilibrium needs K.
#[test]
fn a_free_rotation_with_inertia_is_singular_only_where_k_is_factored() {
    let extra = mass_node(3, "rz", "[0.0, 0.0, 2.0]");
    // Static: singular at node 3 rz.
    let text = format!("{GOOD}{extra}");
    check_lists_and_run_stops_at_the_first(
        "rotstatic.toml",
        &text,
        &[&["no stiffness at node 3 rz", "fix that DOF"]],
    );
    // Transient from rest without the nodal load at t = 0: accepted.
    let transient = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 0.01\nduration = 0.05",
    )
    .replace(
        "value = 1.0e4",
        "value = 1.0e4\nseries = {type = \"ramp\", t0 = 0.01, t1 = 0.02}",
    );
    let (code, lines, out) = check_lines("rottransient.toml", &format!("{transient}{extra}"));
    assert_eq!(code, Some(0), "{lines:?}");
    assert!(out.contains("ok"), "{out}");
    // Transient with the load at t = 0: the initial static solve needs stiffness.
    let loaded = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 0.01\nduration = 0.05",
    );
    check_lists_and_run_stops_at_the_first(
        "rotinitial.toml",
        &format!("{loaded}{extra}"),
        &[&[
            "no stiffness at node 3 rz",
            "initial static equilibrium",
            "`initial_static = false`",
        ]],
    );
}

/// Three independent mistakes in one file: `check` names all three (file, table, key,
/// fix), `run` the first.
#[test]
fn check_lists_every_independent_problem() {
    let text = edit("kind = \"static\"", "kind = \"static\"\nmodes = 3")
        .replace(
            "[[node]]\nid = 2\nxyz = [2.0, 0.0, 0.0]",
            "[[node]]\nid = 2\nxyz = [2.0, 0.0, 0.0]\nfix = [\"uq\"]",
        )
        .replace("dofs = [\"uz\"]", "dofz = [\"uz\"]");
    check_lists_and_run_stops_at_the_first(
        "three.toml",
        &text,
        &[
            &["[analysis]", "`modes` would be ignored", "remove it"],
            &[
                "`node[1].fix[0]`: unknown variant `uq`",
                "expected one of `ux`, `uy`, `uz`",
            ],
            &["recorder[0]", "dofz"],
        ],
    );
    // Once the file reads cleanly, the elements are built: a bad one and a load on a
    // missing node, each named.
    let text = edit("E = 2.1e11", "E = 0.0");
    check_lists_and_run_stops_at_the_first(
        "elem.toml",
        &text,
        &[&["element[0] (id 7, beam3d)", "`E` = 0", "positive"]],
    );
}

/// The `[analysis]` settings and the recorders' file names do not depend on the elements:
/// their problems are listed beside a bad element's instead of hiding it (and behind it).
#[test]
fn check_lists_analysis_and_output_problems_beside_element_ones() {
    let text = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 0.01\nduration = 0.1\nrayleigh = {alpha = -1.0, beta = 0.0}",
    )
    .replace("E = 2.1e11", "E = 0.0")
    .replace("file = \"tip.csv\"", "file = \"../tip.csv\"");
    check_lists_and_run_stops_at_the_first(
        "stages.toml",
        &text,
        &[
            &["[analysis]", "`rayleigh.alpha` = -1", "give a value ≥ 0"],
            &["recorder[0]", "`..`", "relative file name"],
            &["element[0] (id 7, beam3d)", "`E` = 0", "positive"],
        ],
    );
}

/// Problems of the same stage are all listed: two bad elements and a bad link at once.
#[test]
fn check_lists_every_element_and_link_problem() {
    let text = format!(
        "{GOOD}
[[node]]
id = 3
xyz = [4.0, 0.0, 0.0]
fix = \"all\"
[[element]]
type = \"spring_damper\"
id = 8
nodes = [2, 2]
k = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
[[element]]
type = \"mass\"
id = 9
nodes = [2]
m = -4.0
[[link]]
master = 2
slave = 3
"
    );
    check_lists_and_run_stops_at_the_first(
        "stage.toml",
        &text,
        &[
            &["element[1] (id 8, spring_damper)", "lists node 2 twice"],
            &["element[2] (id 9, mass)", "`m`"],
            &[
                "link[0]",
                "slave node 3 is fixed",
                "fix the master node 2 instead",
            ],
        ],
    );
}

/// `check` prints the model's size: nodes, elements, equations, nonzeros, memory, steps.
#[test]
fn check_prints_the_size() {
    let (code, lines, out) = check_lines("size.toml", GOOD);
    assert_eq!(code, Some(0), "{lines:?}");
    // One beam, node 1 fixed: 6 equations, a full 6×6 block.
    for s in [
        "2 nodes",
        "1 elements",
        "6 equations",
        "36 nonzeros",
        "matrices",
        "factor",
        "1 steps",
    ] {
        assert!(out.contains(s), "expected `{s}` in: {out}");
    }
}

// --- valid inputs accepted -----------------------------------------------------------

/// The moving force of `moving_force_beam.toml` with its path listed tip to root (and the
/// force entering at the far end, running back): by symmetry of the simply supported beam
/// the midspan history is the same as the original's, to round-off.
#[test]
fn a_moving_force_path_may_be_listed_in_either_direction() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/models/moving_force_beam.toml"
    ))
    .expect("example");
    let line = src
        .lines()
        .find(|l| l.trim_start().starts_with("elements = ["))
        .expect("a path");
    let ids: Vec<&str> = line
        .split('[')
        .nth(1)
        .and_then(|r| r.split(']').next())
        .expect("ids")
        .split(',')
        .map(str::trim)
        .collect();
    let reversed = format!(
        "elements = [{}]",
        ids.iter().rev().copied().collect::<Vec<_>>().join(", ")
    );
    let dir = temp_dir("reverse");
    let run = |text: &str, name: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        let out = dir.join(format!("out-{name}"));
        let o = railfem(&[
            "run",
            path.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        out
    };
    let a = run(&src, "forward.toml");
    let b = run(&src.replace(line.trim_start(), &reversed), "reversed.toml");
    // Midspan (node 10, uz): the beam, its vertical supports and the force are symmetric
    // about it (the axial and torsional supports differ but are not loaded).
    let (x, y) = (
        Csv::read(&a.join("midspan.csv")),
        Csv::read(&b.join("midspan.csv")),
    );
    let w = x.column("10_uz");
    let scale = w.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 5e-4, "the force crossed the span: {scale}");
    assert_eq!(w.len(), y.rows.len());
    for (u, v) in w.iter().zip(y.column("10_uz")) {
        assert!((u - v).abs() <= 1e-9 * scale, "{u} vs {v}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
