//! Fuzz target: the mutations of the property test `tests/mutations.rs` (the same code,
//! `tests/hostile/mutate.rs`), run for as long as the fuzzer runs. The input's bytes are the
//! seed of the mutation generator: its first byte picks the shipped example model, the
//! next eight seed the generator, so libFuzzer's coverage feedback steers which numbers
//! become extremes and which keys and entries are deleted or duplicated.
//!
//! Each case goes through what `railfem check` does, in process: parse (TOML or JSON),
//! read and build the model, construct the driver, run the preflight checks (singularity,
//! stability, size). Asserts: no panic; a refusal has a non-empty one-line message for
//! each problem, and names the model file.
//!
//! A first byte of 128 or more picks one of the inputs beside the model files instead: a
//! vehicle file (the sks700 preset, mutated as a TOML table, read by the vehicle-file
//! reader), an irregularity CSV (`mutate_csv`, read by the irregularity reader) or a train
//! table (a model with a two-entry `vehicles` list and a speed table, mutated as a model).

#![no_main]

#[path = "../../tests/hostile/mutate.rs"]
mod mutate;

use libfuzzer_sys::fuzz_target;
use railfem::framework::modelfile;
use std::path::Path;

const EXAMPLES: [&str; 5] = [
    include_str!("../../examples/models/cantilever.toml"),
    include_str!("../../examples/models/curve_quick.toml"),
    include_str!("../../examples/models/moving_force_beam.toml"),
    include_str!("../../examples/models/sdof.toml"),
    include_str!("../../examples/models/ss_beam_modal.toml"),
];

/// The sks700 preset written as a vehicle file.
const VEHICLE: &str = include_str!("../../elements/presets/sks700.toml");
/// A measured-style irregularity CSV.
const IRREGULARITY: &str = include_str!("../../examples/models/irregular_straight.csv");
/// A train of two kinds of vehicle on a speed table (the train table of tests/mutations.rs).
const TRAIN: &str = r#"
[analysis]
kind = "static"

[track]
segments = [{type = "straight", length = 80.0}]
element_length = 0.6
support = {type = "rigid"}

[[vehicle]]
start = 50.0
speed_table = [[0.0, 0.0], [1.0, 2.0], [3.0, 2.0]]
wheel = {mu = 0.3}
vehicles = [{preset = "sks700", count = 1}, {preset = "sks700", carriage = {car_length = 20.0}}]
"#;

/// Asserts the one-line contract on every problem of `e`.
fn one_line_each(e: &railfem::framework::FemError) {
    for p in e.problems() {
        let line = p.to_string();
        assert!(!line.trim().is_empty(), "empty error message");
        assert!(!line.contains('\n'), "multi-line error: {line:?}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let mut seed = [0u8; 8];
    for (s, b) in seed.iter_mut().zip(rest) {
        *s = *b;
    }
    let mut rng = mutate::Rng(u64::from_le_bytes(seed));
    if pick >= 128 {
        use railfem::elements::rail::{geometry::irregularity, vehicle};
        match pick % 3 {
            0 => {
                let base: toml::Value = toml::from_str(VEHICLE).expect("the preset is valid");
                let case = mutate::toml_case(&base, &mut rng);
                if let Err(e) = vehicle::section::parse_vehicle(&case.text, "fuzz.toml") {
                    one_line_each(&e);
                }
            }
            1 => {
                let (text, _) = mutate::mutate_csv(IRREGULARITY, &mut rng);
                if let Err(e) = irregularity::csv::read_table(&text, "fuzz.csv") {
                    let line = e.to_string();
                    assert!(!line.contains('\n') && line.starts_with("fuzz.csv:"), "{line:?}");
                }
            }
            _ => check_model(TRAIN, &mut rng),
        }
        return;
    }
    check_model(EXAMPLES[pick as usize % EXAMPLES.len()], &mut rng);
});

/// One mutated case of the model `text` through the path of `railfem check`.
fn check_model(text: &str, rng: &mut mutate::Rng) {
    let base: toml::Value = toml::from_str(text).expect("the examples are valid TOML");
    let case = mutate::case(&base, rng);
    let name = format!("fuzz.{}", case.ext);
    let parsed = if case.ext == "json" {
        modelfile::parse_json(&case.text, &name)
    } else {
        modelfile::parse_toml(&case.text, &name)
    };
    let result = parsed.and_then(|value| {
        let as_toml: Option<toml::Value> = serde_json::from_value(value.clone()).ok();
        if as_toml.as_ref().is_some_and(mutate::too_big) {
            return Ok(());
        }
        let model = modelfile::from_value(&value, &name, Path::new("/nonexistent"))?.build()?;
        let mut driver = railfem::solvers::Driver::new(model)?;
        driver.preflight(false).map(|_| ())
    });
    if let Err(e) = result {
        one_line_each(&e);
    }
}
