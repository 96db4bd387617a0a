//! Issue 20, round two of bad input: size guards, crash-proof entry (non-UTF-8 paths,
//! damaged plugins), safe output names, messages that name the file and show the size of
//! their numbers, and mistyped command-line options. Every case asserts exit code 2 and
//! one stderr line naming the file (or the command line), the key and the fix.

use super::common::{plugin_lib, temp_dir};
use super::{check, check_train, edit, refused_with, GOOD};
use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::process::{Command, Output};

fn railfem_os(args: &[&OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .output()
        .expect("run railfem")
}

/// Runs `railfem args`; asserts exit code 2, one stderr line, no panic, and every string
/// of `expect` in it. Returns the line.
fn refused(args: &[&OsStr], expect: &[&str]) -> String {
    refused_with(&format!("{args:?}"), &railfem_os(args), expect)
}

/// The tip deflection `uz` (m) in the first row of `tip.csv` in `out`, written by GOOD.
fn tip_uz(out: &Path) -> f64 {
    let csv = std::fs::read_to_string(out.join("tip.csv")).expect("tip.csv");
    let row = csv.lines().nth(1).expect("a row");
    row.split(',')
        .nth(1)
        .and_then(|x| x.parse().ok())
        .expect("uz")
}

/// GOOD's tip deflection P·L³/(3·E·I): L = 2 m, P = 1e4 N, E = 2.1e11 Pa,
/// I = Iy = 3.038e-5 m⁴ (one cubic Hermite element is exact).
const GOOD_TIP_UZ: f64 = 1e4 * 8.0 / (3.0 * 2.1e11 * 3.038e-5);

fn os(s: &str) -> &OsStr {
    OsStr::new(s)
}

// ---------------------------------------------------------------------------------------
// 1. Sizes: refused before the work, with the estimate, the key and the limit's flag. Each
// of these used to abort on a failed allocation or compute for minutes; the guard answers
// in milliseconds because it runs before anything is allocated.
// ---------------------------------------------------------------------------------------

#[test]
fn a_rail_element_length_implying_billions_of_nodes_is_refused() {
    let line = check_train(
        "tinyel",
        "element_length = 0.6",
        "element_length = 1e-9",
        &[],
        &[
            "[track]",
            "`element_length` = 1e-9 m over 30 m of track",
            // 30 m / 1e-9 m = 3e10 stations.
            "3e10 rail nodes",
            "give a larger `element_length`",
            "`[limits] max_memory` or `--max-memory`",
        ],
    );
    assert!(line.contains("TiB"), "{line}");
}

#[test]
fn a_huge_track_length_is_refused_at_the_alignment() {
    // 1e12 m of straight in knots of 20 m: 5e10 knots.
    check_train(
        "longtrack",
        "length = 30.0",
        "length = 1e12",
        &[],
        &[
            "[track]",
            "segment[0] (straight, `length` = 1e12 m)",
            "5e10 alignment knots",
            "give shorter segments",
            "--max-memory",
        ],
    );
}

#[test]
fn a_meshing_window_far_beyond_the_track_is_refused() {
    // 1e13 m at 0.6 m: 1.67e13 stations.
    check_train(
        "window",
        "element_length = 0.6",
        "element_length = 0.6\nwindow = [0.0, 1e13]",
        &[],
        &[
            "`window` [0, 1e13] m",
            "1.67e13 rail nodes",
            "shorter `window`",
        ],
    );
}

#[test]
fn a_curve_too_tight_for_a_wheelset_is_refused() {
    // A clothoid to 1/R = 1000 1/m (R = 1 mm: a radius given in km read as m … or mm).
    check_train(
        "tight",
        "segments = [{type = \"straight\", length = 30.0}]",
        "segments = [{type = \"straight\", length = 10.0}, {type = \"clothoid\", length = 20.0, from_curvature = 0.0, to_curvature = 1000.0}]",
        &[],
        &[
            "segment[1]",
            "radius of curvature of 0.001 m",
            "below the 5 m",
            "check the units",
        ],
    );
    check_train(
        "tightarc",
        "segments = [{type = \"straight\", length = 30.0}]",
        "segments = [{type = \"arc\", length = 30.0, radius = 2.0, hand = \"left\"}]",
        &[],
        &["segment[0]", "radius of curvature of 2 m", "below the 5 m"],
    );
}

#[test]
fn a_step_count_past_the_limit_is_refused_and_the_flag_raises_it() {
    let model = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 1e-300\nduration = 1.0",
    );
    check(
        "tinydt.toml",
        &model,
        &[
            "[analysis]",
            "`duration` = 1 s at `dt` = 1e-300 s is 1e300 steps",
            "give a larger `dt`",
            "`[limits] max_steps` or `--max-steps`",
        ],
    );
    // 2e7 steps: over the default 1e7, under a raised limit (`check` runs no step).
    let model = edit(
        "kind = \"static\"",
        "kind = \"transient\"\ndt = 1e-7\nduration = 2.0",
    );
    let dir = temp_dir("steps");
    let path = dir.join("steps.toml");
    std::fs::write(&path, &model).expect("write");
    refused(
        &[os("check"), path.as_os_str()],
        &["steps.toml", "20000000 steps", "10000000"],
    );
    let o = railfem_os(&[os("check"), path.as_os_str(), os("--max-steps"), os("1e8")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::write(&path, format!("{model}\n[limits]\nmax_steps = 1e8\n")).expect("write");
    let o = railfem_os(&[os("check"), path.as_os_str()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_lowered_memory_limit_refuses_a_normal_track() {
    // 30 m at 0.6 m: 51 stations of 2 fixed nodes, 256 B each (~26 KiB) > 1 KiB.
    check_train(
        "lowmem",
        "[analysis]",
        "[limits]\nmax_memory = \"1K\"\n\n[analysis]",
        &[],
        &[
            "rail nodes",
            "more than the memory limit 1.0 KiB",
            "max_memory",
        ],
    );
    check_train(
        "badlimit",
        "[analysis]",
        "[limits]\nmax_memroy = \"1K\"\n\n[analysis]",
        &[],
        &["[limits]", "unknown key `max_memroy`", "`max_memory`"],
    );
}

#[test]
fn a_model_whose_parts_fit_but_whole_does_not_is_refused_before_assembly() {
    // 30 m of rigid rails and one carriage under a 400 KiB budget: the track (102 fixed
    // nodes of 256 B, ~26 KiB) and the carriage (66 DOFs × 2.9 KiB, ~191 KiB) each pass
    // their generator's guard; the whole model (39 free nodes × 6 DOFs × 2.9 KiB,
    // ~679 KiB) does not.
    let line = check_train(
        "whole",
        "[analysis]",
        "[limits]\nmax_memory = \"400K\"\n\n[analysis]",
        &[],
        &[
            "the model (39 nodes not fully fixed) implies 234 DOFs",
            "more than the memory limit 400.0 KiB",
            "--max-memory",
        ],
    );
    assert!(!line.contains("rail nodes"), "{line}");
}

#[test]
fn a_billion_carriages_or_bridge_spans_are_refused() {
    // 66 DOFs per carriage.
    check_train(
        "carrbig",
        "carriages = 1",
        "carriages = 1000000000",
        &[],
        &[
            "vehicle `train`",
            "`carriages` = 1000000000",
            "6.6e10 vehicle DOFs",
            "give fewer `carriages`",
        ],
    );
    // 1e9 spans of 1e-8 m fit the 30 m track; 6 DOFs × (1e9 + 1) × (4 + 3) nodes.
    check_train(
        "spansbig",
        "support = {type = \"rigid\"}",
        "support = {type = \"bridge\", start = 5.0, spans = 1000000000, span = 1e-8}",
        &[],
        &[
            "[track]",
            "`spans` = 1000000000 with `pier_elements` = 4",
            "4.2e10 bridge DOFs",
            "give fewer `spans`",
        ],
    );
}

#[test]
fn a_profile_with_a_million_points_is_refused_before_its_checks() {
    let mut text = String::from("# units: mm\n");
    for i in 0..1_000_000 {
        let y = -70.0 + 130.0 * i as f64 / 1e6;
        text.push_str(&format!("{y},{}\n", 0.001 * y));
    }
    check_train(
        "million",
        "wheel = {mu = 0.3}",
        "wheel = {wheel_profile = \"{dir}/million.csv\"}",
        &[("million.csv", &text)],
        &[
            "`wheel_profile`",
            "million.csv:5002:",
            "1000000 points, more than 5000",
            "resample the profile",
        ],
    );
}

#[test]
fn a_synthetic_quake_too_long_to_hold_is_refused() {
    refused(
        &[
            os("train-bridge"),
            os("--quake"),
            os("synthetic"),
            os("--quake-duration"),
            os("1e15"),
            os("--build-only"),
        ],
        &[
            "command line",
            "--quake-duration 1e15 s",
            "1e17 ground-motion samples",
            "--max-memory",
        ],
    );
}

// ---------------------------------------------------------------------------------------
// 2. Crashes: a non-UTF-8 path, a damaged plugin.
// ---------------------------------------------------------------------------------------

#[test]
fn a_non_utf8_model_path_runs_and_a_non_utf8_value_is_refused() {
    let dir = temp_dir("nonutf8");
    let name = OsStr::from_bytes(b"m\xff.toml");
    let path = dir.join(name);
    std::fs::write(&path, GOOD).expect("write");
    let out = dir.join(OsStr::from_bytes(b"out\xfe"));
    let o = railfem_os(&[os("run"), path.as_os_str(), os("--out"), out.as_os_str()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The recorder wrote into the non-UTF-8 directory, GOOD's answer.
    let uz = tip_uz(&out);
    assert!((uz - GOOD_TIP_UZ).abs() < 1e-9 * GOOD_TIP_UZ, "{uz}");
    // A non-UTF-8 model that is broken is named (lossily) in one line.
    std::fs::write(&path, "[[node]]\nid = 1\n").expect("write");
    refused(
        &[os("check"), path.as_os_str()],
        &["m\u{fffd}.toml", "node[0]", "xyz"],
    );
    // A number that is not text.
    refused(
        &[os("curve"), os("--speed"), OsStr::from_bytes(b"8\xff0")],
        &["command line", "--speed", "not valid UTF-8"],
    );
    refused(
        &[OsStr::from_bytes(b"ru\xffn")],
        &["command line", "the command", "not valid UTF-8"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A copy of the example plugin's bytes, edited by `f`, as a library file; `elements
/// --plugin` must refuse it with its path and the fix.
fn damaged_plugin(case: &str, f: impl FnOnce(&mut Vec<u8>), expect: &[&str]) {
    let mut bytes = std::fs::read(plugin_lib()).expect("plugin");
    f(&mut bytes);
    let dir = temp_dir(case);
    let lib = dir.join(format!("lib{case}.so"));
    std::fs::write(&lib, &bytes).expect("write");
    let line = refused(&[os("elements"), os("--plugin"), lib.as_os_str()], expect);
    assert!(line.contains(&format!("lib{case}.so")), "{line}");
    assert!(line.contains("rebuild the plugin"), "{line}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_truncated_plugin_is_refused_never_a_signal() {
    let len = std::fs::metadata(plugin_lib()).expect("plugin").len() as usize;
    // Inside the ELF header, inside the program headers, inside the first loadable
    // segment, half way, and short of the section headers at the end by one byte.
    for (k, cut) in [10, 100, 5000, len / 2, len - 1].into_iter().enumerate() {
        damaged_plugin(
            &format!("cut{k}"),
            |b| b.truncate(cut),
            &["damaged or foreign library", &format!("{cut} bytes")],
        );
    }
}

#[test]
fn corrupt_plugin_headers_are_refused() {
    // EI_CLASS = 1 (32-bit).
    damaged_plugin("class", |b| b[4] = 1, &["not 64-bit"]);
    // EI_DATA = 2 (big-endian).
    damaged_plugin("endian", |b| b[5] = 2, &["not little-endian"]);
    // e_machine = 40 (ARM, 32-bit).
    damaged_plugin(
        "machine",
        |b| b[18..20].copy_from_slice(&40u16.to_le_bytes()),
        &["ELF machine 40"],
    );
    // e_phoff far past the end.
    damaged_plugin(
        "phoff",
        |b| b[0x20..0x28].copy_from_slice(&(1u64 << 40).to_le_bytes()),
        &["program header table", "truncated or damaged"],
    );
    // e_shnum = 65535: the section header table runs past the end.
    damaged_plugin(
        "shnum",
        |b| b[0x3c..0x3e].copy_from_slice(&u16::MAX.to_le_bytes()),
        &["section header table"],
    );
}

#[test]
fn a_file_that_is_not_a_library_is_refused_through_the_model_file() {
    let dir = temp_dir("notelf");
    std::fs::write(dir.join("libnot.so"), "#!/bin/sh\necho not a library\n").expect("write");
    let path = dir.join("notelf.toml");
    std::fs::write(&path, format!("plugins = [\"libnot.so\"]\n{GOOD}")).expect("write");
    refused(
        &[os("check"), path.as_os_str()],
        &[
            "notelf.toml: plugins",
            "libnot.so",
            "not an ELF file",
            "rebuild the plugin",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------
// 3. Outputs: every name checked before anything is written.
// ---------------------------------------------------------------------------------------

/// GOOD with a second recorder writing `file`.
fn two_recorders(file: &str) -> String {
    format!("{GOOD}\n[[recorder]]\ntype = \"node\"\nnode = 2\ndofs = [\"ry\"]\nfile = \"{file}\"\n")
}

#[test]
fn two_recorders_on_one_file_are_refused_naming_both() {
    check(
        "samefile.toml",
        &two_recorders("tip.csv"),
        &[
            "recorder[1]",
            "file \"tip.csv\" is also written by recorder[0]",
            "its own file",
        ],
    );
    // The same file after normalisation.
    check(
        "dotfile.toml",
        &two_recorders("./tip.csv"),
        &[
            "recorder[1]",
            "\"./tip.csv\" is also written by recorder[0] (\"tip.csv\")",
        ],
    );
}

#[test]
fn a_recorder_may_write_into_a_subdirectory_of_out() {
    let dir = temp_dir("subdir");
    let path = dir.join("subdir.toml");
    std::fs::write(
        &path,
        edit("file = \"tip.csv\"", "file = \"deep/er/tip.csv\""),
    )
    .expect("write");
    let out = dir.join("out");
    let o = railfem_os(&[os("run"), path.as_os_str(), os("--out"), out.as_os_str()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let uz = tip_uz(&out.join("deep/er"));
    assert!((uz - GOOD_TIP_UZ).abs() < 1e-9 * GOOD_TIP_UZ, "{uz}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_recorder_named_like_railfems_own_files_is_refused() {
    for own in ["energy.csv", "last_converged_state.csv", "modes.csv"] {
        check(
            "ownfile.toml",
            &two_recorders(own),
            &[
                "recorder[1]",
                &format!("\"{own}\" is also written by railfem itself"),
                "rename",
            ],
        );
    }
}

#[test]
fn recorders_outside_the_output_directory_are_refused_before_writing() {
    let dir = temp_dir("escape");
    let outside = dir.join("outside.csv");
    for (file, why) in [
        (outside.to_str().unwrap(), "absolute path"),
        ("../up.csv", "`..`"),
        ("sub/../../up.csv", "`..`"),
        ("", "is empty"),
    ] {
        let path = dir.join("escape.toml");
        std::fs::write(&path, two_recorders(file)).expect("write");
        let out = dir.join("out");
        refused(
            &[os("run"), path.as_os_str(), os("--out"), out.as_os_str()],
            &["escape.toml: recorder[1]", why, "relative file name"],
        );
        // Nothing was written: not even the output directory.
        assert!(!out.exists() && !outside.exists() && !dir.join("up.csv").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------
// 6. Messages: the file, the table, index and key, numbers that show their size.
// ---------------------------------------------------------------------------------------

#[test]
fn a_beam_to_1e200_is_reported_as_such_not_as_zero_length() {
    check(
        "far.toml",
        &edit("xyz = [2.0, 0.0, 0.0]", "xyz = [1e200, 0.0, 0.0]"),
        &[
            "node[1]",
            "`xyz` = [1e200, 0, 0]",
            "1e200 m from the origin",
            "check the units",
        ],
    );
    // A truly zero-length beam names both positions as they are.
    check(
        "near.toml",
        &edit("xyz = [2.0, 0.0, 0.0]", "xyz = [1e-200, 0.0, 0.0]"),
        &[
            "element[0] (id 7, beam3d)",
            "I at [0, 0, 0] and J at [1e-200, 0, 0]",
            "connect two distinct points",
        ],
    );
    check(
        "hugeE.toml",
        &edit("E = 2.1e11", "E = -1e200"),
        &["element[0] (id 7, beam3d)", "`E` = -1e200", "positive"],
    );
}

#[test]
fn a_moving_axle_on_a_node_no_vehicle_carries_is_named() {
    check_train(
        "uncarried",
        "[track]",
        "[[node]]\nid = 1\nxyz = [15.0, 0.0, 0.5]\n\n[[element]]\ntype = \"moving_axle\"\nid = 5\nnodes = [1]\nside = \"left\"\n\n[track]",
        &[],
        &[
            "element[0] (id 5, moving_axle)",
            "`nodes` = [1]",
            "not carried by any vehicle",
            "[[vehicle]]",
        ],
    );
}

#[test]
fn a_json_model_with_a_byte_order_mark_reads_like_toml() {
    let json = r#"{"analysis": {"kind": "static"},
        "node": [{"id": 1, "xyz": [0, 0, 0], "fix": "all"}, {"id": 2, "xyz": [2, 0, 0]}],
        "element": [{"type": "beam3d", "id": 7, "nodes": [1, 2], "E": 2.1e11, "G": 8.1e10,
                     "A": 7.686e-3, "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6}],
        "load": [{"type": "nodal", "node": 2, "dof": "uz", "value": 1.0e4}],
        "recorder": [{"type": "node", "node": 2, "dofs": ["uz"], "file": "tip.csv"}]}"#;
    let dir = temp_dir("bom");
    let tip = |name: &str, text: String| -> f64 {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write");
        let out = dir.join(format!("out-{name}"));
        let o = railfem_os(&[os("run"), path.as_os_str(), os("--out"), out.as_os_str()]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        tip_uz(&out)
    };
    let from_json = tip("bom.json", format!("\u{feff}{json}"));
    let from_toml = tip("bom.toml", format!("\u{feff}{GOOD}"));
    // Same model, same solution, both against P·L³/(3·E·I).
    assert!(
        (from_json - GOOD_TIP_UZ).abs() < 1e-9 * GOOD_TIP_UZ,
        "{from_json}"
    );
    assert_eq!(from_json, from_toml);
    // A broken JSON model with a BOM still gets line and column.
    let path = dir.join("bombad.json");
    std::fs::write(&path, "\u{feff}{\n \"node\": [\n}").expect("write");
    refused(
        &[os("check"), path.as_os_str()],
        &["bombad.json:3:", "JSON syntax error"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------
// CLI options: each command knows its own.
// ---------------------------------------------------------------------------------------

#[test]
fn a_mistyped_option_is_refused_with_the_nearest_before_anything_runs() {
    let dir = temp_dir("otu");
    let path = dir.join("otu.toml");
    std::fs::write(&path, GOOD).expect("write");
    let elsewhere = dir.join("elsewhere");
    refused(
        &[
            os("run"),
            path.as_os_str(),
            os("--otu"),
            elsewhere.as_os_str(),
        ],
        &[
            "command line",
            "`railfem run` has no option `--otu`",
            "did you mean `--out`?",
        ],
    );
    assert!(!elsewhere.exists());
    refused(
        &[os("curve"), os("--radious"), os("300")],
        &["`railfem curve` has no option `--radious`", "`--radius`"],
    );
    refused(
        &[os("train-bridge"), os("--car"), os("3")],
        &["`railfem train-bridge` has no option `--car`", "`--cars`"],
    );
    // `check` writes nothing, so it takes no --out.
    refused(
        &[os("check"), path.as_os_str(), os("--out"), os("x")],
        &[
            "`railfem check` has no option `--out`",
            "its options are --factor, --plugin",
        ],
    );
    refused(
        &[os("run"), path.as_os_str(), os("--max-memory"), os("lots")],
        &["--max-memory lots", "8G"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}
