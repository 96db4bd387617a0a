//! A modal analysis from a model file through the CLI: the simply supported beam of
//! `examples/models/ss_beam_modal.toml` (20 consistent-mass beam3d elements, only vertical
//! bending free). Closed form: ω_n = (nπ/L)²·√(EI/m); with 20 cubic elements the first
//! three frequencies are within 0.1 % (the discretisation error of mode 3 is ≈ 3e-5).

use std::process::Command;

#[test]
fn modal_model_file_gives_the_bending_frequencies() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::env::temp_dir().join(format!("railfem-modal-{}", std::process::id()));
    let st = Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "run",
            &format!("{root}/examples/models/ss_beam_modal.toml"),
            "--out",
        ])
        .arg(&out)
        .status()
        .expect("runs");
    assert!(st.success());
    let text = std::fs::read_to_string(out.join("modes.csv")).expect("modes.csv");
    let header = text.lines().next().expect("header");
    let freqs: Vec<f64> = header
        .split(',')
        .skip(2)
        .map(|c| {
            c.split(" [")
                .next()
                .unwrap_or(c)
                .split('_')
                .nth(1)
                .and_then(|f| f.trim_end_matches("Hz").parse().ok())
                .expect("frequency")
        })
        .collect();
    let (ei, m, l) = (2.943e10f64, 2303.0f64, 25.0f64);
    for n in 1..=3 {
        let nf = n as f64;
        let exact = (nf * std::f64::consts::PI / l).powi(2) * (ei / m).sqrt()
            / (2.0 * std::f64::consts::PI);
        let f = freqs[n - 1];
        assert!(
            (f - exact).abs() / exact < 1e-3,
            "mode {n}: {f} Hz vs {exact} Hz"
        );
    }
    // One row per DOF the beams use (6 at each of the 21 nodes; held DOFs read 0).
    assert_eq!(text.lines().count() - 1, 126);
}
