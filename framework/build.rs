//! Build script of railfem-framework: stamps the compiler and target into the crate so the
//! plugin loader ([`plugin`](src/plugin.rs)) can refuse a library built differently.
//!
//! It runs `$RUSTC -vV` (the very compiler cargo uses for this crate) and exports its first
//! line (`rustc 1.85.0 (4d91de4e4 2025-02-17)`, which includes the commit hash) as
//! `RAILFEM_RUSTC_VERSION`, and the compilation target (cargo's `TARGET`, which differs from
//! the host when cross-compiling) as `RAILFEM_TARGET`.
//!
//! It also exports `RAILFEM_BOUNDARY_CRATES`, the versions of the crates whose types cross
//! the plugin boundary (`nalgebra 0.35.0;serde 1.0.228;serde_json 1.0.145`), as this build
//! resolved them: read from the `Cargo.lock` of the build (the first one up from `OUT_DIR`,
//! then from the crate's own folder, that holds this very framework version). A build
//! whose lock file is nowhere above (a target folder outside the workspace) stamps
//! `unknown`, which the loader does not compare.

use std::path::PathBuf;
use std::process::Command;

/// The crates whose types cross the plugin boundary: `DMatrix`/`DVector` (nalgebra) in the
/// element contract, `serde_json::Value`/`Map` in element specs, and serde's traits, which
/// the plugin's parameter structs derive and the host's `serde_json` calls.
const BOUNDARY: [&str; 3] = ["nalgebra", "serde", "serde_json"];

/// One `[[package]]` of a lock file: name, version and dependency entries (`name` or
/// `name version`).
struct Package {
    name: String,
    version: String,
    dependencies: Vec<String>,
}

/// The packages of a `Cargo.lock` (the fields used here only).
fn packages(lock: &str) -> Vec<Package> {
    let mut out = Vec::new();
    for block in lock.split("[[package]]").skip(1) {
        let field = |key: &str| {
            block.lines().find_map(|l| {
                l.strip_prefix(key)
                    .and_then(|r| r.trim().strip_prefix('='))
                    .map(|v| v.trim().trim_matches('"').to_string())
            })
        };
        let dependencies = block
            .split_once("dependencies = [")
            .map(|(_, rest)| rest.split(']').next().unwrap_or(""))
            .unwrap_or("")
            .split(',')
            .map(|d| d.trim().trim_matches('"').to_string())
            .filter(|d| !d.is_empty())
            .collect();
        if let (Some(name), Some(version)) = (field("name "), field("version ")) {
            out.push(Package {
                name,
                version,
                dependencies,
            });
        }
    }
    out
}

/// The versions of [`BOUNDARY`] this framework version depends on in `lock`, or `None` if
/// the lock does not hold it.
fn boundary_versions(lock: &str, version: &str) -> Option<String> {
    let pkgs = packages(lock);
    let me = pkgs
        .iter()
        .find(|p| p.name == "railfem-framework" && p.version == version)?;
    let found: Vec<String> = BOUNDARY
        .iter()
        .map(|name| {
            // A dependency entry carries its version when the lock holds several.
            let pinned = me.dependencies.iter().find_map(|d| {
                let mut w = d.split_whitespace();
                (w.next() == Some(name)).then(|| w.next().map(str::to_string))?
            });
            let v = pinned.or_else(|| {
                let all: Vec<&Package> = pkgs.iter().filter(|p| p.name == *name).collect();
                (all.len() == 1).then(|| all[0].version.clone())
            });
            format!("{name} {}", v.unwrap_or_else(|| "unknown".into()))
        })
        .collect();
    Some(found.join(";"))
}

/// The lock file of this build and the boundary versions it names.
fn lock_versions(version: &str) -> Option<(PathBuf, String)> {
    let starts = ["OUT_DIR", "CARGO_MANIFEST_DIR"].map(|k| std::env::var_os(k).map(PathBuf::from));
    for start in starts.iter().flatten() {
        for dir in start.ancestors() {
            let lock = dir.join("Cargo.lock");
            if let Ok(text) = std::fs::read_to_string(&lock) {
                if let Some(v) = boundary_versions(&text, version) {
                    return Some((lock, v));
                }
            }
        }
    }
    None
}

fn unknown() -> String {
    BOUNDARY.map(|n| format!("{n} unknown")).join(";")
}

fn stamp_boundary() {
    let version = std::env::var("CARGO_PKG_VERSION").unwrap_or_default();
    let crates = match lock_versions(&version) {
        Some((lock, v)) => {
            println!("cargo:rerun-if-changed={}", lock.display());
            v
        }
        None => unknown(),
    };
    println!("cargo:rustc-env=RAILFEM_BOUNDARY_CRATES={crates}");
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RUSTC");
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
    let version = Command::new(&rustc)
        .arg("-vV")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.lines().next().map(|l| l.trim().to_string()))
        .unwrap_or_else(|| "rustc unknown".to_string());
    let target = std::env::var("TARGET").unwrap_or_else(|_| "unknown".to_string());
    println!("cargo:rustc-env=RAILFEM_RUSTC_VERSION={version}");
    println!("cargo:rustc-env=RAILFEM_TARGET={target}");
    stamp_boundary();
}
