//! The activity window's absorbing layer as study keys (`window_layer`,
//! `window_layer_damping`, docs/study.md): each bad setting fails its case with the one-line
//! message `railfem train-bridge` gives for the same setting of `--window-layer` and
//! `--window-layer-damping`, the option's name replaced by the key's (one parser,
//! `railfem::train_window::parse_layer`, names both), and the study goes on.

use super::common::{study, temp_dir};
use super::train_bridge_refused;

/// Each bad setting: the study's keys, the command line's options, and the message with
/// `{t}` and `{d}` for the thickness's and the damping's names.
const BAD: [(&str, &[&str], &str); 5] = [
    (
        "window = \"on\"\nwindow_layer = -10",
        &["--window", "on", "--window-layer", "-10"],
        "{t} -10: give a value ≥ 0",
    ),
    (
        "window = \"on\"\nwindow_layer_damping = 0",
        &["--window", "on", "--window-layer-damping", "0"],
        "{d} 0: give a value > 0 (1/s)",
    ),
    (
        "window = \"auto\"\nwindow_layer_damping = -5",
        &["--window", "auto", "--window-layer-damping", "-5"],
        "{d} -5: give a value > 0 (1/s)",
    ),
    (
        "window = \"on\"\nwindow_layer = 0\nwindow_layer_damping = 100",
        &[
            "--window",
            "on",
            "--window-layer",
            "0",
            "--window-layer-damping",
            "100",
        ],
        "{d} shapes the absorbing layer, which {t} 0 removes; drop {d}, or give {t} > 0",
    ),
    (
        "window = \"off\"\nwindow_layer = 40",
        &["--window", "off", "--window-layer", "40"],
        "{t} and {d} shape the activity window's absorbing layer, which {w} off turns off; drop them, or give {w} on or auto",
    ),
];

/// The message of `template` with the names of `names` (`[window, thickness, damping]`).
fn message(template: &str, names: [&str; 3]) -> String {
    template
        .replace("{w}", names[0])
        .replace("{t}", names[1])
        .replace("{d}", names[2])
}

#[test]
fn bad_layer_keys_fail_the_case_in_the_words_of_the_options() {
    let dir = temp_dir("study-window-layer");
    for (i, (keys, args, template)) in BAD.iter().enumerate() {
        train_bridge_refused(
            args,
            &message(
                template,
                ["--window", "--window-layer", "--window-layer-damping"],
            ),
        );
        let plan = dir.join(format!("plan{i}.toml"));
        std::fs::write(
            &plan,
            format!("case = \"train-bridge\"\n[options]\ncars = 1\nspans = 2\n{keys}\n[[axis]]\nname = \"speed\"\nvalues = [60]\n"),
        )
        .expect("write the plan");
        let out = dir.join(format!("out{i}"));
        let o = study(&plan, &out, &[]);
        assert!(
            o.status.success(),
            "{keys}: the study goes on past a failed case"
        );
        let table = std::fs::read_to_string(out.join("study.csv")).expect("study.csv");
        let row = table.lines().nth(1).expect("the case's row");
        let want = message(
            template,
            ["`window`", "`window_layer`", "`window_layer_damping`"],
        );
        // The row: case id, the speed, the status, then the error (quoted when it holds a
        // comma or a quote).
        let cells: Vec<&str> = row.splitn(4, ',').collect();
        assert_eq!(cells[2], "failed", "{keys}: {row}");
        let error = format!("study case: {want}");
        let quoted = format!("\"{}\"", error.replace('"', "\"\""));
        assert!(
            cells[3].starts_with(&format!("{error},"))
                || cells[3].starts_with(&format!("{quoted},")),
            "{keys}: expected {error:?} in {row}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
