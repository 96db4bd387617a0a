//! Issue 36, round three of bad input: the inputs added since round two (trains of many
//! vehicles, vehicle files, irregularity CSVs, moving oscillators). Each case asserts exit
//! code 2 and one stderr line naming the file, the key path (or the CSV's row and column)
//! and the fix; the BOM cases assert that the file now reads.

use super::common::{railfem, refused_with, temp_dir};
use super::{check_train, TRAIN};

/// Writes `files` into a fresh directory and runs `railfem ARGS MODEL` on the first one
/// (`extra` after the model path). Returns the output and the directory.
fn run_in(case: &str, files: &[(&str, &str)], extra: &[&str]) -> (std::process::Output, String) {
    let dir = temp_dir(case);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).expect("write");
    }
    let model = dir.join(files[0].0);
    let mut args = vec!["check", model.to_str().expect("utf-8")];
    args.extend_from_slice(extra);
    let o = railfem(&args);
    (o, dir.display().to_string())
}

// ---------------------------------------------------------------------------------------
// 1. Size before allocation.
// ---------------------------------------------------------------------------------------

/// A train of 1000 entries of 20 000 sks700 carriages each: every entry fits a 4 GiB budget
/// (20 000 × 66 DOFs × 2.9 KiB = 3.7 GiB), the train (2e7 carriages of 90 DOFs) does not.
/// The entries were repeated in memory before the whole train was counted: 2e7 copies of
/// the definition, a failed allocation and SIGABRT. Now the train is counted from its
/// entries first, in milliseconds.
#[test]
fn a_train_of_many_large_entries_is_counted_before_it_is_built() {
    let entries = vec!["{preset = \"sks700\", count = 20000}"; 1000].join(", ");
    let model = TRAIN.replacen(
        "preset = \"sks700\"\ncarriages = 1",
        &format!("vehicles = [{entries}]"),
        1,
    );
    let (o, dir) = run_in(
        "many_entries",
        &[("many.toml", &model)],
        &["--max-memory", "4G"],
    );
    let err = refused_with(
        "many entries",
        &o,
        &[
            "many.toml",
            "`vehicle[0]`",
            // 1000 × 20 000 vehicles; 2e7 × 90 DOFs (7 bodies, 8 wheels' contact nodes).
            "2e7 vehicles in 1000 entries of `vehicles`",
            "1.8e9 vehicle DOFs",
            "give fewer vehicles",
            "--max-memory",
        ],
    );
    assert!(!err.contains("memory allocation"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

/// A track and a train that each fit the budget but not together are refused once, up
/// front, with both parts: 1501 stations on discrete supports (30 m at 0.02 m; 12 DOFs
/// × 2.9 KiB each = 51.0 MiB) and 60 carriages (5400 DOFs, 15.3 MiB) against 64 MiB.
#[test]
fn the_whole_model_is_checked_once_before_any_part_is_built() {
    let model = TRAIN
        .replacen(
            "element_length = 0.6\nsupport = {type = \"rigid\"}",
            "element_length = 0.02\nsupport = {type = \"discrete\", spacing = 0.6, k = [1e7, 1e8, 1e7, 0, 0, 0]}",
            1,
        )
        .replacen("carriages = 1", "carriages = 60", 1);
    let (o, dir) = run_in("whole", &[("whole.toml", &model)], &["--max-memory", "64M"]);
    refused_with(
        "whole model",
        &o,
        &[
            "whole.toml",
            "the model as written needs about 66.3 MiB",
            "[track]: 1501 rail stations: 51.0 MiB",
            "vehicle[0]: 60 vehicles, 5400 DOFs: 15.3 MiB",
            "more than the memory limit 64.0 MiB",
            "--max-memory",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------------------------------
// 3. Every refused value names its key path, in TOML and JSON alike.
// ---------------------------------------------------------------------------------------

#[test]
fn a_speed_table_row_of_three_numbers_names_its_index() {
    check_train(
        "speed_row",
        "speed = 0.0",
        "speed_table = [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0, 5.0]]",
        &[],
        &[
            "`vehicle[0].speed_table[2]`",
            "invalid length 3",
            "give a value of the expected kind",
        ],
    );
}

#[test]
fn the_same_row_in_json_names_the_same_path() {
    let json = r#"{
  "analysis": {"kind": "static"},
  "track": {"segments": [{"type": "straight", "length": 30.0}], "support": {"type": "rigid"}},
  "vehicle": [{"preset": "sks700", "carriages": 1, "start": 15.0, "wheel": {"mu": 0.3},
               "speed_table": [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0, 5.0]]}]
}"#;
    let (o, dir) = run_in("speed_row_json", &[("row.json", json)], &[]);
    refused_with(
        "json row",
        &o,
        &[
            "row.json",
            "`vehicle[0].speed_table[2]`",
            "invalid length 3",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_negative_irregularity_seed_names_its_key() {
    check_train(
        "neg_seed",
        "support = {type = \"rigid\"}",
        "support = {type = \"rigid\"}\nirregularity = {psd = \"fra4\", seed = -1, wavelengths = [1, 50]}",
        &[],
        &["`track.irregularity[0].seed`", "integer `-1`", "expected u64"],
    );
}

/// In a vehicle file the path starts at the file's top level, and the line names the
/// vehicle file.
#[test]
fn a_vehicle_file_value_of_the_wrong_type_names_file_and_path() {
    let sks = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/elements/presets/sks700.toml"
    ))
    .expect("preset");
    // The second body's mass as text.
    let mut seen = 0;
    let broken: Vec<String> = sks
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("mass =") {
                seen += 1;
                if seen == 2 {
                    return "mass = \"heavy\"".to_string();
                }
            }
            l.to_string()
        })
        .collect();
    assert_eq!(seen, 7, "sks700 has seven bodies");
    let model = TRAIN.replacen("preset = \"sks700\"", "file = \"car.toml\"", 1);
    let (o, dir) = run_in(
        "vehicle_file_type",
        &[("vf.toml", &model), ("car.toml", &broken.join("\n"))],
        &[],
    );
    refused_with(
        "vehicle file",
        &o,
        &[
            "car.toml",
            "`body[1].mass`",
            "invalid type: string \"heavy\"",
            "expected f64",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------------------------------
// 4. Bounds with units, and a byte-order mark before a comment.
// ---------------------------------------------------------------------------------------

/// A CSV irregularity of 4 rows; `row3` is the third data row (line 4 of the file).
fn irregularity_csv(header: &str, row3: &str) -> String {
    format!("{header}\n0,0\n10,1\n{row3}\n30,0\n")
}

#[test]
fn an_irregularity_of_1e300_mm_names_file_row_column_and_value() {
    let csv = irregularity_csv("station_m,vertical_mm", "20,1e300");
    check_train(
        "irr_huge",
        "support = {type = \"rigid\"}",
        "support = {type = \"rigid\"}\nirregularity = {file = \"irr.csv\"}",
        &[("irr.csv", &csv)],
        &[
            "irr.csv:4:",
            "column `vertical_mm` = 1e300 mm",
            "beyond ±0.1 m (100 mm)",
            "correct that row, or the column's unit",
        ],
    );
}

#[test]
fn an_irregularity_csv_with_a_mark_before_a_comment_reads() {
    let csv = format!(
        "\u{feff}# measured, vertical profile\n{}",
        irregularity_csv("station_m,vertical_mm", "20,2")
    );
    let model = TRAIN.replacen(
        "support = {type = \"rigid\"}",
        "support = {type = \"rigid\"}\nirregularity = {file = \"irr.csv\"}",
        1,
    );
    let (o, dir) = run_in("irr_bom", &[("bom.toml", &model), ("irr.csv", &csv)], &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

/// A wheel profile point 2000 mm from the origin (a slip of units or a broken line).
#[test]
fn a_profile_point_a_metre_away_names_file_row_and_column() {
    let mut csv = String::from("\u{feff}# units: mm\n");
    for i in 0..30 {
        let y = -60.0 + 4.0 * i as f64;
        let z = if i == 7 { 2000.0 } else { 0.001 * y * y };
        csv.push_str(&format!("{y},{z}\n"));
    }
    check_train(
        "profile_far",
        "wheel = {mu = 0.3}",
        "wheel = {mu = 0.3, wheel_profile = \"{dir}/w.csv\"}",
        &[("w.csv", &csv)],
        &["w.csv:9:", "column `z` = 2000 mm", "beyond ±1 m (1000 mm)"],
    );
}

// ---------------------------------------------------------------------------------------
// 5. Closed choices: an unknown value is refused with the valid ones, and a choice that
// would be ignored is refused as such.
// ---------------------------------------------------------------------------------------

/// Two beams and a moving mass on them: the smallest model with a `path`.
fn oscillator(extra: &str) -> String {
    format!(
        r#"
[analysis]
kind = "transient"
dt = 0.01
duration = 0.05

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [5.0, 0.0, 0.0]

[[node]]
id = 3
xyz = [10.0, 0.0, 0.0]
fix = "all"

[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 1e-2
Iy = 1e-4
Iz = 1e-4
J = 1e-4
rho = 7850

[[element]]
type = "beam3d"
id = 2
nodes = [2, 3]
E = 2.1e11
G = 8.1e10
A = 1e-2
Iy = 1e-4
Iz = 1e-4
J = 1e-4
rho = 7850

[[element]]
type = "moving_mass"
id = 3
nodes = []
m = 100.0
path = [1, 2]
start = 1.0
speed = 1.0
{extra}
"#
    )
}

#[test]
fn an_unknown_rail_is_refused_with_the_valid_ones() {
    super::check(
        "rail_middle.toml",
        &oscillator("rail = \"middle\""),
        &[
            "element[2]",
            "`rail`",
            "unknown variant `middle`, expected `left` or `right`",
        ],
    );
}

#[test]
fn a_rail_beside_a_path_is_refused_as_ignored() {
    super::check(
        "rail_path.toml",
        &oscillator("rail = \"right\""),
        &["element[2]", "`rail` would be ignored", "remove `rail`"],
    );
}

/// The same model without `rail` runs: the refusals above are about `rail` alone.
#[test]
fn the_oscillator_without_rail_runs() {
    let dir = temp_dir("osc_ok");
    let path = dir.join("osc.toml");
    std::fs::write(&path, oscillator("")).expect("write");
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

/// A ground-motion record that begins with a byte-order mark and a comment, with a row of
/// 50 g (a unit slip: the largest recorded peaks are about 4 g): the mark is no longer
/// taken for part of the header, and the row is refused with its column and value.
#[test]
fn a_record_acceleration_of_50_g_names_row_and_column() {
    let dir = temp_dir("quake_50g");
    let f = dir.join("q.csv");
    std::fs::write(
        &f,
        "\u{feff}# a record\ntime_s,ax_g,ay_g,az_g\n0,0,0,0\n0.01,0.1,50,0\n0.02,0,0,0\n",
    )
    .expect("write");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "train-bridge",
            "--cars",
            "1",
            "--spans",
            "1",
            "--build-only",
            "--quake",
        ])
        .arg(&f)
        .output()
        .expect("runs");
    refused_with(
        "quake 50 g",
        &o,
        &[
            "q.csv:4",
            "column `ay_g` = 50 g",
            "beyond ±98.0665 m/s² (10 g)",
        ],
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Found by the `model_file` fuzz target (the input as it found it): a JSON key holding a
/// line feed came back inside the "unknown top-level key" message and
/// broke the one line in two. Every input message writes control characters as escapes.
#[test]
fn a_key_with_a_line_break_stays_on_one_line() {
    const FOUND: &str = "{\n \"car]_,,,,G,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,len]thstraig6(250 raig9(250 m, domed r: a 1000 kass on \\\\\\n \\\\\\\\SU\\\\) 30pe\": 1.0\n \n}";
    super::check(
        "key_break.json",
        FOUND,
        &[
            "unknown top-level key",
            "kass on \\\\n \\\\SU",
            "valid keys: analysis",
        ],
    );
}
