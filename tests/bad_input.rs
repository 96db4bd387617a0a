//! Bad model files: for each kind of mistake, `railfem run` exits with code 2 and prints
//! exactly one line on stderr that names the file, the place in it and what to fix — and
//! never panics.

mod common;
#[cfg(unix)]
#[path = "bad_input/guards.rs"]
mod guards;

use common::{railfem, refused_with, temp_dir};

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

/// Runs `railfem run` on `text` written as `name` and checks the one-line exit-2 error
/// ([`common::check_bad_model`]). Returns the line.
fn check(name: &str, text: &str, expect: &[&str]) -> String {
    common::check_bad_model(name, text, expect)
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
        &[
            "`load[0].dof`: unknown variant `uzz`",
            "expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`",
        ],
    );
    let text = edit("fix = \"all\"", "fix = [\"ux\", \"uq\"]");
    check(
        "fixdof.toml",
        &text,
        &[
            "`node[0].fix[1]`: unknown variant `uq`",
            "expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`, `all`, `translations`, `rotations`",
        ],
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

#[test]
fn non_integer_block_size_is_refused() {
    // Serde alone said "invalid value: integer `-1`, expected usize", without the key.
    for (value, shown) in [("-1", "-1"), ("2.5", "2.5"), ("\"big\"", "\"big\"")] {
        let text = edit(
            "kind = \"static\"",
            &format!("kind = \"static\"\nsolver = \"partitioned\"\nblock_size = {value}"),
        );
        check(
            "blocksize.toml",
            &text,
            &[
                "[analysis]",
                &format!("`block_size` = {shown}"),
                "give a positive integer",
            ],
        );
    }
}

#[test]
fn unknown_newton_predictor_is_refused() {
    let text = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 0.001\n\n[analysis.newton]\npredictor = \"extrapolate\"",
    );
    check(
        "predictor.toml",
        &text,
        &["[analysis]", "extrapolate", "`previous` or `increment`"],
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
        vec!["critical-radius", "--tangential", "contact"],
        vec!["critical-radius", "--sweep", "--tangential", "polach"],
        vec![
            "curve",
            "--quick",
            "--tangential",
            "polach",
            "--polach-spin",
            "on",
        ],
        vec!["curve", "--quick", "--polach-spin", "polach_1999"],
        vec![
            "critical-radius",
            "--tangential",
            "kalker_linear",
            "--polach-spin",
            "off",
        ],
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

// ---------------------------------------------------------------------------------------
// Track, vehicles and profiles. A rigid 30 m straight with one sks700 carriage standing
// in the middle; each case breaks one thing. `railfem check` suffices: every mistake
// below is caught while the model is read or built.
// ---------------------------------------------------------------------------------------

/// A valid track-and-vehicle model (`railfem check` passes on it).
const TRAIN: &str = r#"
[analysis]
kind = "static"

[track]
segments = [{type = "straight", length = 30.0}]
element_length = 0.6
support = {type = "rigid"}

[[vehicle]]
preset = "sks700"
carriages = 1
start = 15.0
speed = 0.0
wheel = {mu = 0.3}
"#;

/// Like [`check`] for `railfem check` on `TRAIN` with `from` replaced by `to`; profile
/// files `(name, text)` are written beside the model and `{dir}` in `to` becomes that
/// directory. Returns the line.
fn check_train(
    case: &str,
    from: &str,
    to: &str,
    files: &[(&str, &str)],
    expect: &[&str],
) -> String {
    assert!(TRAIN.contains(from), "`{from}` not in the model");
    let dir = temp_dir(case);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).expect("write profile");
    }
    let name = format!("{case}.toml");
    let path = dir.join(&name);
    let to = to.replace("{dir}", dir.to_str().expect("utf-8"));
    std::fs::write(&path, TRAIN.replacen(from, &to, 1)).expect("write model");
    let o = railfem(&["check", path.to_str().expect("utf-8")]);
    let err = refused_with(case, &o, expect);
    assert!(
        err.contains(&name),
        "{case}: the model file is not named: {err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    err
}

#[test]
fn the_unbroken_train_checks() {
    let dir = temp_dir("train");
    let path = dir.join("train.toml");
    std::fs::write(&path, TRAIN).expect("write");
    let o = railfem(&["check", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each broken wheel profile file is named with its line and what to fix.
#[test]
fn bad_wheel_profile_files_are_refused() {
    let wheel = |file: &str| format!("wheel = {{wheel_profile = \"{{dir}}/{file}\"}}");
    let cases: [(&str, &str, &[&str]); 8] = [
        // Three points: a not-a-knot spline needs four.
        (
            "few.csv",
            "# units: mm\n-70,-30\n-60,-20\n0,0\n",
            &["few.csv:4:", "only 3 points", "at least 4"],
        ),
        (
            "nan.csv",
            "# units: mm\n-70,-30\nnan,-20\n0,0\n30,0.3\n60,0.5\n",
            &["nan.csv:3:", "not a finite number"],
        ),
        // A point with one column, then one with three.
        (
            "col.csv",
            "# units: mm\n-70,-30\n-60\n0,0\n30,0.3\n60,0.5\n",
            &["col.csv:3:", "two comma-separated numbers"],
        ),
        (
            "three.csv",
            "y_mm,z_mm\n-70,-30,1\n-60,-20,1\n0,0,1\n60,0.5,1\n",
            &["three.csv:2:", "two comma-separated numbers"],
        ),
        (
            "nounit.csv",
            "-70,-30\n-60,-20\n0,0\n30,0.3\n60,0.5\n",
            &["nounit.csv:1:", "unknown units", "# units: mm"],
        ),
        // Millimetre numbers declared as metres: the first point is 70 m from the origin,
        // beyond the ±1 m any cross-section lies in.
        (
            "metres.csv",
            "# units: m\n-70,-30\n-60,-20\n-30,-1\n0,0\n30,0.3\n60,0.5\n",
            &["metres.csv:2:", "column `y` = -70 m", "beyond ±1 m", "unit"],
        ),
        // Within the bound but 1.5 m wide: still a unit slip, by the width.
        (
            "wide.csv",
            "# units: m\n-0.75,-0.3\n-0.6,-0.2\n-0.3,-0.01\n0,0\n0.3,0.003\n0.75,0.005\n",
            &["wide.csv:7:", "spans 1.5 m", "check the units"],
        ),
        // The fourth point goes back across the first segment.
        (
            "loop.csv",
            "# units: mm\n-70,-30\n-60,-20\n0,0\n-65,-10\n30,0.3\n",
            &["loop.csv:", "crosses", "without loops"],
        ),
    ];
    for (file, text, expect) in cases {
        check_train(
            file.trim_end_matches(".csv"),
            "wheel = {mu = 0.3}",
            &wheel(file),
            &[(file, text)],
            expect,
        );
    }
}

#[test]
fn bad_rail_profile_files_are_refused() {
    let rail = |file: &str| format!("wheel = {{rail_profile = \"{{dir}}/{file}\"}}");
    let cases: [(&str, &str, &[&str]); 3] = [
        // y must increase from the gauge side to the field side.
        (
            "unsorted.csv",
            "# units: mm\n-30,-5\n-10,-0.2\n-12,0\n10,-0.2\n30,-5\n",
            &[
                "unsorted.csv:4:",
                "not strictly increasing",
                "sort the points",
            ],
        ),
        (
            "railnan.csv",
            "y_mm,z_mm\n-30,-5\n-10,inf\n0,0\n10,-0.2\n30,-5\n",
            &["railnan.csv:3:", "not a finite number"],
        ),
        // Metre numbers declared as millimetres: a head 0.06 mm wide.
        (
            "tiny.csv",
            "y_mm,z_mm\n-0.03,-0.005\n-0.01,-0.0002\n0,0\n0.01,-0.0002\n0.03,-0.005\n",
            &["tiny.csv:6:", "check the units"],
        ),
    ];
    for (file, text, expect) in cases {
        check_train(
            file.trim_end_matches(".csv"),
            "wheel = {mu = 0.3}",
            &rail(file),
            &[(file, text)],
            expect,
        );
    }
    check_train(
        "nofile",
        "wheel = {mu = 0.3}",
        "wheel = {rail_profile = \"{dir}/absent.csv\"}",
        &[],
        &["absent.csv", "cannot read the profile", "check the path"],
    );
}

#[test]
fn non_physical_track_values_are_refused() {
    let el = "element_length = 0.6";
    for (case, to, expect) in [
        (
            "gauge0",
            "element_length = 0.6\ngauge = 0.0",
            &["[track]", "gauge = 0", "> 0 m"][..],
        ),
        (
            "gaugenan",
            "element_length = 0.6\ngauge = nan",
            &["track.gauge", "not a finite number"][..],
        ),
        (
            "ellen",
            "element_length = -0.6",
            &["[track]", "element_length = -0.6", "> 0 m"][..],
        ),
        (
            "ctneg",
            "element_length = 0.6\nct = -200.0",
            &["[track]", "Ct = -200", "≥ 0 m"][..],
        ),
        (
            "railoff",
            "element_length = 0.6\nrail_offset = 0.0",
            &["[track]", "rail_offset", "> 0 m"][..],
        ),
        (
            "trackkey",
            "element_lenght = 0.6",
            &[
                "[track]",
                "unknown field `element_lenght`",
                "`element_length`",
            ][..],
        ),
        (
            "tracktype",
            "element_length = \"short\"",
            &["[track]", "invalid type: string \"short\""][..],
        ),
    ] {
        check_train(case, el, to, &[], expect);
    }
    check_train(
        "seglen",
        "length = 30.0",
        "length = 0.0",
        &[],
        &["[track]", "segment[0] has length 0", "> 0 m"],
    );
}

#[test]
fn non_physical_vehicle_values_are_refused() {
    let at = "carriages = 1";
    let over = |t: &str| format!("carriages = 1\ncarriage = {t}");
    for (case, to, expect) in [
        (
            "negmass",
            over("{car_body = {mass = -5.0}}"),
            &[
                "vehicle `train`",
                "`carriage.car_body.mass` = -5",
                "positive",
            ][..],
        ),
        // Used to be reported by the generated `mass` element 1002, not by the key.
        (
            "negixx",
            over("{bogie = {ixx = -5.0}}"),
            &["vehicle `train`", "`carriage.bogie.ixx` = -5", "≥ 0"][..],
        ),
        (
            "negk",
            over("{primary = {kz = -1.0}}"),
            &["vehicle `train`", "`carriage.primary.kz` = -1", "≥ 0"][..],
        ),
        (
            "nanc",
            over("{secondary = {cz = nan}}"),
            &["vehicle[0].carriage.secondary.cz", "not a finite number"][..],
        ),
        // Used to be accepted: no roll stiffness, a body below the rails.
        (
            "span0",
            over("{primary_span = 0.0}"),
            &["vehicle `train`", "`carriage.primary_span` = 0", "positive"][..],
        ),
        (
            "lowbody",
            over("{car_body = {height = -1.0}}"),
            &[
                "vehicle `train`",
                "`carriage.car_body.height` = -1",
                "positive",
            ][..],
        ),
        (
            "carr0",
            "carriages = 0".to_string(),
            &["vehicle `train`", "`carriages` must be at least 1"][..],
        ),
        (
            "vkey",
            over("{car_bod = {height = 1.0}}"),
            &["[vehicle][0]", "unknown field `car_bod`", "`car_body`"][..],
        ),
    ] {
        check_train(case, at, &to, &[], expect);
    }
    check_train(
        "nanspeed",
        "speed = 0.0",
        "speed = nan",
        &[],
        &["vehicle[0].speed", "not a finite number"],
    );
    // Used to name no file: the wheel's error at its first step.
    check_train(
        "offtrack",
        "start = 15.0",
        "start = 500.0",
        &[],
        &[
            "vehicle `train`",
            "`start` = 500",
            "rail mesh covers 0.000 to 30.000 m",
        ],
    );
    for (case, to, expect) in [
        (
            "mu",
            "wheel = {mu = -0.3}",
            &["moving_axle", "`mu` = -0.3", "between 0 and 2"][..],
        ),
        // Issue 14: the tangential law and its material, passed through the vehicle's
        // `wheel` table.
        (
            "mu2",
            "wheel = {mu = 2.5, tangential = \"kalker_linear\"}",
            &["moving_axle", "`mu` = 2.5", "between 0 and 2"][..],
        ),
        (
            "law",
            "wheel = {tangential = \"contact\"}",
            &[
                "moving_axle",
                "`tangential`: unknown variant `contact`",
                "expected one of `coulomb`, `kalker_linear`, `polach`, `fastsim`",
            ][..],
        ),
        (
            "fstrips",
            "wheel = {tangential = \"fastsim\", fastsim_strips = 1}",
            &["moving_axle", "`fastsim_strips` = 1", "give 2 to 400"][..],
        ),
        (
            "fignored",
            "wheel = {tangential = \"kalker_linear\", fastsim_elements = 30}",
            &[
                "moving_axle",
                "`fastsim_elements` would be ignored",
                "set `tangential = \"fastsim\"`",
            ][..],
        ),
        (
            "poisson",
            "wheel = {tangential = \"kalker_linear\", poisson = 0.5}",
            &["moving_axle", "`poisson` = 0.5", "0 < ν < 0.5"][..],
        ),
        (
            "shear",
            "wheel = {tangential = \"polach\", shear_modulus = 80.0}",
            &[
                "moving_axle",
                "`shear_modulus` = 80",
                "in Pa between 1e9 and 1e12",
            ][..],
        ),
        (
            "shear0",
            "wheel = {tangential = \"kalker_linear\", shear_modulus = 0.0}",
            &[
                "moving_axle",
                "`shear_modulus` = 0",
                "in Pa between 1e9 and 1e12",
            ][..],
        ),
        (
            "ka",
            "wheel = {tangential = \"polach\", polach_ka = 1.5}",
            &["moving_axle", "`polach_ka` = 1.5", "0 < kA ≤ 1"][..],
        ),
        (
            "ks",
            "wheel = {tangential = \"polach\", polach_ka = 0.3, polach_ks = 0.4}",
            &["moving_axle", "`polach_ks` = 0.4", "0 < kS ≤ kA = 0.3"][..],
        ),
        (
            "pa",
            "wheel = {tangential = \"polach\", polach_a = 0.0}",
            &["moving_axle", "`polach_a` = 0", "0 < A ≤ 1"][..],
        ),
        (
            "pb",
            "wheel = {tangential = \"polach\", polach_b = -1.0}",
            &["moving_axle", "`polach_b` = -1", "0 ≤ B ≤ 100 s/m"][..],
        ),
        (
            "pspin",
            "wheel = {tangential = \"polach\", polach_spin = \"on\"}",
            &[
                "moving_axle",
                "`polach_spin`: unknown variant `on`",
                "expected `off` or `polach_1999`",
            ][..],
        ),
        (
            "pignored",
            "wheel = {tangential = \"kalker_linear\", polach_b = 0.2}",
            &[
                "moving_axle",
                "`polach_b` would be ignored",
                "set `tangential = \"polach\"`",
            ][..],
        ),
        (
            "gignored",
            "wheel = {shear_modulus = 8.0e10}",
            &[
                "moving_axle",
                "`shear_modulus` would be ignored",
                "\"kalker_linear\"",
            ][..],
        ),
        (
            "wheelkey",
            "wheel = {muu = 0.3}",
            &["moving_axle", "unknown key `muu`", "did you mean `mu`?"][..],
        ),
        // Used to hang sampling 1e8 points.
        (
            "points",
            "wheel = {wheel_points = 100000000}",
            &["moving_axle", "`wheel_points` = 100000000", "at most"][..],
        ),
        // Used to be accepted with the wheels 4 m from their rails.
        (
            "offset",
            "wheel = {contact_offset = 5.0}",
            &["moving_axle", "no rail node lies under the wheel profile"][..],
        ),
    ] {
        check_train(case, "wheel = {mu = 0.3}", to, &[], expect);
    }
}

/// Element ids are unique across the file; nodes named by elements, recorders, links and
/// loads must exist, also beside generated vehicle models.
#[test]
fn ids_in_a_train_model_are_checked() {
    let mass = "\n[[node]]\nid = 1\nxyz = [0.0, 0.0, 5.0]\nfix = \"all\"\n[[element]]\ntype = \"mass\"\nid = 5\nnodes = [1]\nm = 1.0\n";
    check_train(
        "dupelem",
        "[track]",
        &format!(
            "{mass}{}\n[track]",
            mass.replace(
                "[[node]]\nid = 1\nxyz = [0.0, 0.0, 5.0]\nfix = \"all\"\n",
                ""
            )
        ),
        &[],
        &[
            "element[1] (id 5, mass)",
            "duplicate element id 5",
            "own id",
        ],
    );
    check_train(
        "wheelnode",
        "[track]",
        "[[element]]\ntype = \"moving_axle\"\nid = 5\nnodes = [999]\nside = \"left\"\n\n[track]",
        &[],
        &[
            "element[0] (id 5, moving_axle)",
            "node 999 does not exist",
            "[[node]]",
        ],
    );
    check_train(
        "recnode",
        "[track]",
        "[[recorder]]\ntype = \"node\"\nnode = 999\ndofs = [\"uz\"]\nfile = \"x.csv\"\n\n[track]",
        &[],
        &["recorder[0]", "node 999 does not exist"],
    );
}

#[test]
fn bad_plugins_are_refused() {
    // A missing library, and a file that is not one; the plugin file is named.
    check_train(
        "noplugin",
        "[analysis]",
        "plugins = [\"absent.so\"]\n[analysis]",
        &[],
        &["absent.so", "cannot open the plugin file"],
    );
}

/// `railfem train-bridge` on a small case with `args` added; asserts the refusal `line`
/// (exact, after the origin): the window's and the far field's option checks.
fn train_bridge_refused(args: &[&str], line: &str) {
    let mut all = vec![
        "train-bridge",
        "--cars",
        "1",
        "--spans",
        "2",
        "--steps",
        "1",
    ];
    all.extend_from_slice(args);
    let err = refused_with(&format!("{args:?}"), &railfem(&all), &[line]);
    assert_eq!(
        err.trim_end(),
        format!("error: command line: {line}"),
        "{args:?}"
    );
}

#[path = "bad_input/far_field.rs"]
mod far_field;
#[path = "bad_input/round_five.rs"]
mod round_five;
#[path = "bad_input/round_four.rs"]
mod round_four;
#[path = "bad_input/round_three.rs"]
mod round_three;
#[path = "bad_input/run_window.rs"]
mod run_window;
#[path = "bad_input/study_window.rs"]
mod study_window;
#[path = "bad_input/validation.rs"]
mod validation;
#[path = "bad_input/window.rs"]
mod window;
