//! The same input gives bitwise identical output across runs: two processes run the same
//! short curved-track case and write byte-identical CSV (every element evaluation, sparse
//! assembly and solve runs in a fixed order on one thread).

use std::process::Command;

#[test]
fn two_runs_write_identical_results() {
    let base = std::env::temp_dir().join(format!("railfem-determinism-{}", std::process::id()));
    let mut outputs = Vec::new();
    for k in 0..2 {
        let out = base.join(format!("run{k}"));
        let st = Command::new(env!("CARGO_BIN_EXE_railfem"))
            .args(["curve", "--quick", "--quiet", "--duration", "3", "--out"])
            .arg(&out)
            .output()
            .expect("runs");
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        outputs.push(std::fs::read(out.join("curve.csv")).expect("curve.csv"));
    }
    assert!(outputs[0].len() > 1000);
    assert!(outputs[0] == outputs[1], "the two runs differ");
}
