//! The conformance kit over every registered element kind: a new kind is checked without
//! new test code. Each check's tolerance is justified in `railfem_framework::conformance`.

#[test]
fn every_registered_kind_passes_the_kit() {
    let report = railfem::framework::conformance::check_all(None);
    let kinds: Vec<&str> = railfem::framework::registry::kinds()
        .iter()
        .map(|k| k.name)
        .collect();
    for k in ["beam3d", "spring_damper", "mass", "moving_axle"] {
        assert!(kinds.contains(&k), "{k} is not registered: {kinds:?}");
    }
    assert!(report.passed(), "{}", report.table());
}

/// Every built-in kind declares a unit for each of its outputs (the recorder header
/// `5_Q [N]`): as many units as output names, none left undeclared (`?`), none that would
/// break a CSV header. A mutation check: drop a unit from any kind's list and the count
/// differs; forget `output_units` and the default `?` shows.
#[test]
fn every_built_in_kind_declares_its_output_units() {
    let mut checked = 0;
    for kind in railfem::framework::registry::kinds() {
        for s in (kind.samples)() {
            let names = s.element.output_names();
            let units = s.element.output_units();
            assert_eq!(
                units.len(),
                names.len(),
                "{} ({}): {units:?} for {names:?}",
                kind.name,
                s.name
            );
            for (n, u) in names.iter().zip(&units) {
                assert!(
                    !u.is_empty()
                        && u != railfem::framework::element::UNIT_UNDECLARED
                        && !u.contains([',', '[', ']']),
                    "{}: output `{n}` has unit `{u}`",
                    kind.name
                );
            }
            checked += names.len();
        }
    }
    // beam3d's six resultants alone are 6 per sample; moving_axle has over 40 outputs.
    assert!(checked > 100, "only {checked} outputs checked");
}
