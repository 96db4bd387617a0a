//! docs/architecture.md names every module of the four library crates in its layer tables
//! (issue 31: "every module in its layer table"). A module added without a row fails here,
//! with the fix: `python3 scripts/module_table.py` prints the rows with each module's first
//! doc sentence.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn architecture_page_names_every_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let page = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let mut files = Vec::new();
    for src in ["framework/src", "elements/src", "solvers/src", "src"] {
        rust_files(&root.join(src), &mut files);
    }
    assert!(files.len() > 100, "found only {} modules", files.len());
    let mut missing: Vec<String> = files
        .iter()
        .map(|p| {
            p.strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .filter(|rel| !page.contains(&format!("`{rel}`")))
        .collect();
    missing.sort();
    assert!(
        missing.is_empty(),
        "docs/architecture.md has no row for {} module(s): {}; add them to its layer tables \
         (python3 scripts/module_table.py prints every row)",
        missing.len(),
        missing.join(", ")
    );
}

/// Every module file the page names exists: a row left behind by a move or a deletion
/// fails too.
#[test]
fn architecture_page_names_no_missing_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let page = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let mut gone = Vec::new();
    for piece in page.split('`').skip(1).step_by(2) {
        // `src/commands/NAME.rs` is a pattern, not a file.
        let is_module = piece.ends_with(".rs")
            && !piece.contains("NAME")
            && ["framework/src/", "elements/src/", "solvers/src/", "src/"]
                .iter()
                .any(|p| piece.starts_with(p));
        if is_module && !root.join(piece).is_file() {
            gone.push(piece.to_string());
        }
    }
    assert!(
        gone.is_empty(),
        "docs/architecture.md names files that do not exist: {}",
        gone.join(", ")
    );
}
