//! Build script of railfem-framework: stamps the compiler and target into the crate so the
//! plugin loader ([`plugin`](src/plugin.rs)) can refuse a library built differently.
//!
//! It runs `$RUSTC -vV` (the very compiler cargo uses for this crate) and exports its first
//! line (`rustc 1.85.0 (4d91de4e4 2025-02-17)`, which includes the commit hash) as
//! `RAILFEM_RUSTC_VERSION`, and the compilation target (cargo's `TARGET`, which differs from
//! the host when cross-compiling) as `RAILFEM_TARGET`.

use std::process::Command;

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
}
