//! Issue 36, round four of bad input: closed choices read as enums (item 5), the whole
//! model's size estimate with irregularity samples and a bridge's girders and piers
//! (item 1). Each case asserts exit code 2 and one stderr line naming the file, the key and
//! what is valid (the list of values, or the estimate and the limit).

use super::common::{railfem, refused_with, temp_dir};
use super::{check, check_train, edit, TRAIN};

// ---------------------------------------------------------------------------------------
// 5. Closed choices are closed: one case per family of enums, the valid values listed in
//    the order the enum declares them (serde's own wording).
// ---------------------------------------------------------------------------------------

/// `beam3d`'s `mass` and `geometry`.
#[test]
fn a_beam_mass_or_geometry_outside_the_list_is_refused_with_the_list() {
    check(
        "beam_mass.toml",
        &edit("J = 2.0e-6", "J = 2.0e-6\nmass = \"heavy\""),
        &[
            "element[0] (id 7, beam3d)",
            "`mass`: unknown variant `heavy`",
            "expected one of `consistent`, `lumped`, `lumped_translational`",
            "give one of the values listed",
        ],
    );
    check(
        "beam_geometry.toml",
        &edit("J = 2.0e-6", "J = 2.0e-6\ngeometry = \"bent\""),
        &[
            "element[0] (id 7, beam3d)",
            "`geometry`: unknown variant `bent`",
            "expected one of `linear`, `pdelta`, `corotational`",
        ],
    );
}

/// A nodal load's `dof` is the `Dof` enum: "UZ" was read case-insensitively as a string,
/// and is now refused like any other spelling outside the six names.
#[test]
fn a_nodal_load_dof_is_one_of_the_six() {
    check(
        "load_dof.toml",
        &edit("dof = \"uz\"", "dof = \"UZ\""),
        &[
            "`load[0].dof`: unknown variant `UZ`",
            "expected one of `ux`, `uy`, `uz`, `rx`, `ry`, `rz`",
        ],
    );
}

/// The comfort recorder's `method`.
#[test]
fn a_comfort_method_outside_the_list_is_refused_with_the_list() {
    let text = include_str!("../../examples/models/comfort_oscillator.toml");
    assert!(text.contains("method = \"en12299\""));
    check(
        "comfort_method.toml",
        &text.replacen("method = \"en12299\"", "method = \"iso2631\"", 1),
        &[
            "`recorder[3].method`: unknown variant `iso2631`",
            "expected `sperling` or `en12299`",
        ],
    );
}

/// The wheel's string choices (`moving_axle` through a vehicle's `wheel` table), the
/// train's `suspension_tangent`, its `record.comfort_method` and its `preset`.
#[test]
fn the_wheel_and_train_choices_are_refused_with_their_lists() {
    for (case, to, key, list) in [
        (
            "side_tangent",
            "wheel = {mu = 0.3, sliding_tangent = \"exact\"}",
            "`sliding_tangent`: unknown variant `exact`",
            "expected `symmetric` or `consistent`",
        ),
        (
            "incline",
            "wheel = {mu = 0.3, inclination = \"1:30\"}",
            "`inclination`: unknown variant `1:30`",
            "expected one of `none`, `1:40`, `1:20`",
        ),
        (
            "susp_tangent",
            "wheel = {mu = 0.3}\nsuspension_tangent = \"secant\"",
            "`vehicle[0].suspension_tangent`: unknown variant `secant`",
            "expected `consistent` or `symmetric`",
        ),
        (
            "comfort_method",
            "wheel = {mu = 0.3}\nrecord = {comfort = \"c.csv\", comfort_method = \"iso\"}",
            "comfort_method`: unknown variant `iso`",
            "expected `sperling` or `en12299`",
        ),
    ] {
        check_train(case, "wheel = {mu = 0.3}", to, &[], &[key, list]);
    }
    check_train(
        "preset",
        "preset = \"sks700\"",
        "preset = \"ice3\"",
        &[],
        &["`vehicle[0].preset`: unknown variant `ice3`, expected `sks700`"],
    );
}

/// A `suspension` element's `tangent` (the same enum as the train's).
#[test]
fn a_suspension_tangent_outside_the_list_is_refused_with_the_list() {
    let model = r#"
[analysis]
kind = "static"

[[node]]
id = 3
xyz = [10.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 4
xyz = [10.0, 0.0, 1.0]
fix = ["ux", "uy", "rx", "ry", "rz"]

[[element]]
type = "suspension"
id = 3
nodes = [3, 4]
k = [1.0e6, 1.0e6, 1.0e6]
tangent = "secant"
"#;
    check(
        "susp_tangent.toml",
        model,
        &[
            "element[0] (id 3",
            "`tangent`: unknown variant `secant`",
            "expected `consistent` or `symmetric`",
        ],
    );
}

/// Closed choices given on the command line are read into the same enums, with the same
/// list: `--tangential` of `curve` and `critical-radius`, `--polach-spin`.
#[test]
fn a_command_line_choice_is_refused_with_the_list() {
    for args in [
        &["critical-radius", "--tangential", "contact"][..],
        &["curve", "--quick", "--tangential", "contact"][..],
    ] {
        let o = railfem(args);
        refused_with(
            &args.join(" "),
            &o,
            &[
                "command line: --tangential contact",
                "unknown variant `contact`, expected one of `coulomb`, `kalker_linear`, `polach`, `fastsim`",
            ],
        );
    }
    let o = railfem(&[
        "curve",
        "--quick",
        "--tangential",
        "polach",
        "--polach-spin",
        "on",
    ]);
    refused_with(
        "polach-spin",
        &o,
        &["--polach-spin on", "expected `off` or `polach_1999`"],
    );
}

// ---------------------------------------------------------------------------------------
// 1. The whole model's size estimate counts irregularity samples and bridge girders.
// ---------------------------------------------------------------------------------------

/// Writes `model` (and `files`) into a fresh directory and runs `railfem check` on it with
/// `extra` options. Returns the output and the directory.
fn check_in(
    case: &str,
    model: &str,
    files: &[(&str, &str)],
    extra: &[&str],
) -> (std::process::Output, std::path::PathBuf) {
    let dir = temp_dir(case);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).expect("write");
    }
    let path = dir.join(format!("{case}.toml"));
    std::fs::write(&path, model).expect("write model");
    let mut args = vec!["check", path.to_str().expect("utf-8")];
    args.extend_from_slice(extra);
    (railfem(&args), dir)
}

/// A generated irregularity 1e9 m long at a 0.01 m step: 1e11 samples, doubled for the
/// transform and 72 bytes each (1.44e13 B, 13.1 TiB). Refused from the keys, before the
/// profile (or the mesh) is made.
#[test]
fn an_irregularity_a_billion_metres_long_is_refused_before_it_is_sampled() {
    let model = TRAIN.replacen(
        "support = {type = \"rigid\"}",
        "support = {type = \"rigid\"}\nirregularity = {psd = \"german_low\", seed = 1, wavelengths = [1.0, 50.0], step = 0.01, length = 1e9}",
        1,
    );
    let (o, dir) = check_in("irr_long", &model, &[], &["--max-memory", "4G"]);
    refused_with(
        "irregularity 1e9 m",
        &o,
        &[
            "irr_long.toml",
            "irregularity[0]",
            "`length` = 1e9 m at `step` = 0.01 m",
            "2e11 irregularity samples",
            "about 13.1 TiB",
            "more than the memory limit 4.0 GiB",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A billion spans of a micrometre (a bridge 1 km long on a 1.1 km track): 6·(1e9 + 1)·
/// (4 + 3) = 4.2e10 DOFs of girders, bearings and piers, 2.9 KiB each (113 TiB). Refused
/// from the keys before the mesh.
#[test]
fn a_billion_spans_are_refused_before_the_bridge_is_built() {
    let model = TRAIN
        .replacen("length = 30.0", "length = 1100.0", 1)
        .replacen(
            "support = {type = \"rigid\"}",
            "support = {type = \"bridge\", start = 50.0, spans = 1000000000, span = 1e-6}",
            1,
        );
    let (o, dir) = check_in("spans", &model, &[], &["--max-memory", "4G"]);
    refused_with(
        "1e9 spans",
        &o,
        &[
            "spans.toml",
            "`spans` = 1000000000 with `pier_elements` = 4",
            "4.2e10 bridge DOFs",
            "more than the memory limit 4.0 GiB",
            "give fewer `spans` or `pier_elements`",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Parts that fit one by one but not together: the rail stations of a 3000 m track on
/// discrete supports (3000 / 0.6 + 1 = 5001 stations × 12 DOFs × 2.9 KiB = 170.0 MiB), a
/// generated irregularity over it (3000 m / 0.01 m + 1 = 300 001 samples, doubled, 72 B:
/// 41.2 MiB) and an irregularity table of 100 001 rows of two columns (+ a header line:
/// 100 002 × 2 × 48 B = 9.2 MiB) against 200 MiB: refused once, up front, every part
/// named with its size.
#[test]
fn irregularity_samples_count_in_the_whole_model() {
    let mut table = String::from("station_m,vertical_mm\n");
    for i in 0..=100_000 {
        table.push_str(&format!("{},0\n", i as f64 * 0.03));
    }
    let model = TRAIN
        .replacen("length = 30.0", "length = 3000.0", 1)
        .replacen(
            "support = {type = \"rigid\"}",
            "support = {type = \"discrete\", spacing = 0.6, k = [1e7, 1e8, 1e7, 0, 0, 0]}\nirregularity = [{psd = \"german_low\", seed = 1, wavelengths = [1.0, 50.0], step = 0.01}, {file = \"irr.csv\"}]",
            1,
        );
    let (o, dir) = check_in(
        "irr_whole",
        &model,
        &[("irr.csv", &table)],
        &["--max-memory", "200M"],
    );
    refused_with(
        "whole model with irregularity",
        &o,
        &[
            "irr_whole.toml",
            "the model as written needs about",
            "[track]: 5001 rail stations: 170.0 MiB",
            "[track] irregularity[0]: 300001 samples: 41.2 MiB",
            "[track] irregularity[1]: `irr.csv`, 100002 rows: 9.2 MiB",
            "more than the memory limit 200.0 MiB",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A bridge's girders and piers count in the whole model too: 500 spans of 1 m with
/// 10 pier elements, 6·501·13 = 39 078 DOFs × 2.9 KiB = 110.7 MiB, beside 1001 rail
/// stations on the slab of the girders (600 m at 0.6 m, 18 DOFs × 2.9 KiB: 51.0 MiB),
/// against 150 MiB.
#[test]
fn bridge_girders_and_piers_count_in_the_whole_model() {
    let model = TRAIN
        .replacen("length = 30.0", "length = 600.0", 1)
        .replacen(
        "support = {type = \"rigid\"}",
        "support = {type = \"bridge\", start = 50.0, spans = 500, span = 1.0, pier_elements = 10}",
        1,
    );
    let (o, dir) = check_in("bridge_whole", &model, &[], &["--max-memory", "150M"]);
    refused_with(
        "whole model with a bridge",
        &o,
        &[
            "bridge_whole.toml",
            "[track]: 1001 rail stations: 51.0 MiB",
            "[track] bridge: 500 spans, 39078 DOFs of girders and piers: 110.7 MiB",
            "more than the memory limit 150.0 MiB",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}
