//! Recorder rows kept in memory (`Driver::run_keeping`, what the Python bindings return)
//! against the CSV files the same run writes: the same columns, and every kept double,
//! printed as the CSV prints it, is the CSV's text; keeping rows without files changes no
//! bit of them.

mod common;

use railfem::framework::recording::History;
use std::path::Path;

fn run(model: &Path, out: Option<&Path>) -> Vec<History> {
    let m = railfem::load_model(model).expect("model");
    let mut d = railfem::solvers::Driver::new(m).expect("driver");
    d.run_keeping(out, true, &mut |_| {}).expect("run").1
}

#[test]
fn kept_rows_are_the_csv_rows_and_do_not_depend_on_files() {
    for name in ["sdof.toml", "moving_sprung_mass.toml"] {
        let model = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("examples/models")
            .join(name);
        let dir = common::temp_dir("kept");
        let with_files = run(&model, Some(&dir));
        assert!(!with_files.is_empty(), "{name}: no recorder kept");
        for h in &with_files {
            let text = std::fs::read_to_string(dir.join(&h.file)).expect("csv");
            let mut lines = text.lines();
            let header: Vec<&str> = lines.next().expect("header").split(',').collect();
            assert!(header[0].starts_with("time"), "{}", header[0]);
            assert_eq!(
                header[1..],
                h.columns.iter().map(String::as_str).collect::<Vec<_>>()[..]
            );
            let rows: Vec<&str> = lines.collect();
            assert_eq!(rows.len(), h.time.len(), "{name} {}", h.file);
            assert_eq!(h.values.len(), h.time.len() * h.columns.len());
            for (i, row) in rows.iter().enumerate() {
                let mut expect = format!("{:.9e}", h.time[i]);
                for v in &h.values[i * h.columns.len()..(i + 1) * h.columns.len()] {
                    expect.push_str(&format!(",{v:.12e}"));
                }
                assert_eq!(*row, expect, "{name} {} row {i}", h.file);
            }
        }
        let without_files = run(&model, None);
        assert_eq!(with_files.len(), without_files.len());
        for (a, b) in with_files.iter().zip(&without_files) {
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(a.columns, b.columns);
            assert_eq!(bits(&a.time), bits(&b.time), "{name} {}", a.file);
            assert_eq!(bits(&a.values), bits(&b.values), "{name} {}", a.file);
        }
    }
}
