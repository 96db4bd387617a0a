//! Build script of the `railfem` binary: records the git revision for `railfem --version`
//! and the run sidecars (`run.json`). Outside a git checkout (a crates.io package build,
//! a tarball) the revision is "unknown"; the build never fails for want of git.

use std::process::Command;

/// Whether this package's directory is the top of a git work tree (not a crates.io
/// source unpacked somewhere inside another project's repository).
fn is_checkout() -> bool {
    let Ok(manifest) = std::env::var("CARGO_MANIFEST_DIR") else {
        return false;
    };
    Command::new("git")
        .args(["rev-parse", "--show-toplevel"])
        .current_dir(&manifest)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|top| std::fs::canonicalize(top.trim()).ok())
        .zip(std::fs::canonicalize(&manifest).ok())
        .is_some_and(|(top, here)| top == here)
}

fn main() {
    let rev = is_checkout()
        .then(|| {
            Command::new("git")
                .args(["rev-parse", "--short", "HEAD"])
                .output()
                .ok()
        })
        .flatten()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=RAILFEM_GIT_REVISION={rev}");
    // Rebuild when HEAD moves (a commit or a checkout); harmless when there is no .git.
    // In a worktree HEAD lives in its own git dir and the branches in the common one.
    for (flag, sub) in [("--git-dir", "HEAD"), ("--git-common-dir", "refs/heads")] {
        if let Ok(out) = Command::new("git").args(["rev-parse", flag]).output() {
            if out.status.success() {
                let dir = String::from_utf8_lossy(&out.stdout).trim().to_string();
                println!("cargo:rerun-if-changed={dir}/{sub}");
            }
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
