//! The check of a refusal of bad input: exit code 2 and one line naming the place and the
//! fix (docs/robustness.md). Shared by the root package's tests (`tests/common`) and the
//! `railfem-measure` member's (`examples/measure/tests`), which include this file by path.

/// Asserts that the run `o` (called `label` in failures) exited with code 2 and printed
/// exactly one line on stderr, with no panic, containing every string of `expect`.
/// Returns the line.
pub fn refused_with(label: &str, o: &std::process::Output, expect: &[&str]) -> String {
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(
        o.status.code(),
        Some(2),
        "{label}: exit code; stderr: {err}"
    );
    assert!(
        err.ends_with('\n') && err.lines().count() == 1,
        "{label}: stderr must be exactly one line, got {err:?}"
    );
    assert!(
        !err.contains("internal error") && !err.contains("panicked"),
        "{label}: {err}"
    );
    for e in expect {
        assert!(err.contains(e), "{label}: expected `{e}` in: {err}");
    }
    err
}
