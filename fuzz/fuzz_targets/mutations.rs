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

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let mut seed = [0u8; 8];
    for (s, b) in seed.iter_mut().zip(rest) {
        *s = *b;
    }
    railfem::elements::link();
    let base: toml::Value = toml::from_str(EXAMPLES[pick as usize % EXAMPLES.len()])
        .expect("the examples are valid TOML");
    let mut rng = mutate::Rng(u64::from_le_bytes(seed));
    let case = mutate::case(&base, &mut rng);
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
        for p in e.problems() {
            let line = p.to_string();
            assert!(!line.trim().is_empty(), "empty error message");
            assert!(!line.contains('\n'), "multi-line error: {line:?}");
        }
    }
});
