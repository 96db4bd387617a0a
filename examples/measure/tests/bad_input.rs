//! `railfem-measure` refuses bad input as `railfem` does: one line on stderr naming the
//! file (with the line and column where it applies) or the option, and the fix; exit code
//! 2; nothing run or written before the refusal.

#[path = "../../../tests/common/refusal.rs"]
mod refusal;

use refusal::refused_with;
use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `railfem-measure` binary with `args`.
fn measure(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_railfem-measure"))
        .args(args)
        .output()
        .expect("run railfem-measure")
}

/// A fresh, empty directory for one test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("railfem-measure-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create temp dir");
    d
}

/// Every refusal of a peer CSV: one line naming the file, the line and the column where
/// it applies, and the fix; exit 2 before the grid runs.
#[test]
fn peer_file_bad_input_is_refused_in_one_line() {
    let dir = temp_dir("peer");
    let out = dir.join("out");
    let head = "peer,elements,dt [s],steps,wall [s],error [-]\n";
    let cases: [(&str, String, &[&str]); 8] = [
        (
            "empty.csv",
            String::new(),
            &["empty.csv", "empty", "header"],
        ),
        (
            "nocol.csv",
            "peer,elements,dt [s],steps,error [-]\nP,8,1e-3,10,1e-3\n".into(),
            &["nocol.csv", "line 1", "`wall [s]`", "header must name"],
        ),
        ("norows.csv", head.into(), &["norows.csv", "no runs"]),
        (
            "fields.csv",
            format!("{head}P,8,1e-3,10,0.5\n"),
            &["fields.csv", "line 2", "5 fields", "6"],
        ),
        (
            "dt.csv",
            format!("{head}P,8,1e-3,10,0.5,1e-3\nP,8,-1,10,0.5,1e-3\n"),
            &["dt.csv", "line 3", "`dt [s]`", "`-1`", "> 0"],
        ),
        (
            "elements.csv",
            format!("{head}P,2.5,1e-3,10,0.5,1e-3\n"),
            &["elements.csv", "line 2", "`elements`", "whole number"],
        ),
        (
            "error.csv",
            format!("{head}P,8,1e-3,10,0.5,NaN\n"),
            &["error.csv", "line 2", "`error [-]`", "Frýba"],
        ),
        (
            "label.csv",
            format!("{head},8,1e-3,10,0.5,1e-3\n"),
            &["label.csv", "line 2", "`peer`", "name the code"],
        ),
    ];
    for (name, text, expect) in cases {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let o = measure(&[
            "peer",
            p.to_str().unwrap(),
            "--cases",
            "force",
            "--out",
            out.to_str().unwrap(),
        ]);
        refused_with(name, &o, expect);
    }
    let o = measure(&[
        "peer",
        dir.join("missing.csv").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    refused_with("missing", &o, &["missing.csv", "cannot read"]);
    let p = dir.join("ok.csv");
    std::fs::write(&p, format!("{head}P,8,1e-3,10,0.5,1e-3\n")).unwrap();
    let o = measure(&["peer", p.to_str().unwrap(), "--cases", "sprung"]);
    refused_with(
        "peer without force",
        &o,
        &["--cases", "add force to --cases"],
    );
    let o = measure(&["peer", p.to_str().unwrap(), "--cases", "force,bridge"]);
    refused_with(
        "unknown case",
        &o,
        &["--cases", "`bridge`", "force,sprung,curve"],
    );
    assert!(!out.exists(), "nothing may run before the refusal");
}

/// `retime-at` and `--rounds` are checked before anything runs: the option or argument,
/// the bad value and the form wanted.
#[test]
fn retime_options_are_refused_in_one_line() {
    let dir = temp_dir("retime");
    let out = dir.join("out");
    let o = measure(&["retime-at", "0.3125:-1e-3", "--out", out.to_str().unwrap()]);
    refused_with("retime-at", &o, &["retime-at", "`0.3125:-1e-3`", "H:DT"]);
    for bad in ["0", "2.5", "101", "x"] {
        let o = measure(&[
            "retime-at",
            "0.3125:1e-3",
            "--rounds",
            bad,
            "--out",
            out.to_str().unwrap(),
        ]);
        refused_with(bad, &o, &["--rounds", bad, "1 to 100"]);
        let o = measure(&["retime", "--rounds", bad, "--out", out.to_str().unwrap()]);
        refused_with(bad, &o, &["--rounds", bad, "1 to 100"]);
    }
    // An option no measurement has is clap's refusal, still one line and exit 2.
    let o = measure(&["retime", "--retime", "3"]);
    refused_with("unknown option", &o, &["--retime"]);
    assert!(!out.exists(), "nothing may run before the refusal");
}
