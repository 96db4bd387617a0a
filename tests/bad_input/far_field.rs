//! The reduced far field's options (`railfem train-bridge --far-field …`,
//! docs/reduced-far-field.md): each refused combination exits with code 2 and one stderr
//! line, naming the option and the fix.

use super::train_bridge_refused as refused;

#[test]
fn a_far_field_other_than_full_or_reduced_is_refused() {
    refused(
        &["--far-field", "modal"],
        "--far-field modal: give full or reduced",
    );
}

#[test]
fn far_field_settings_out_of_range_or_without_reduced_are_refused() {
    refused(
        &["--far-field", "reduced", "--far-field-cutoff", "0"],
        "--far-field-cutoff 0: give a positive frequency (Hz)",
    );
    refused(
        &["--far-field", "reduced", "--far-field-reach=-1"],
        "--far-field-reach -1: give a distance ≥ 0 m",
    );
    refused(
        &["--far-field-cutoff", "50"],
        "--far-field-cutoff and --far-field-reach set the reduced far field; add --far-field reduced, or drop them",
    );
}

#[test]
fn the_reduced_far_field_without_the_partitioned_solver_or_with_the_window_is_refused() {
    refused(
        &["--far-field", "reduced", "--solver", "direct"],
        "--far-field reduced runs blocks of the partitioned solver in reduced form, and this model uses another solver; give --solver partitioned",
    );
    refused(
        &[
            "--far-field",
            "reduced",
            "--solver",
            "partitioned",
            "--window",
            "on",
        ],
        "--far-field reduced with the activity window: the window holds the blocks the far field reduces; give --window off",
    );
}
