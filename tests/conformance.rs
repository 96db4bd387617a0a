//! The conformance kit over every registered element kind: a new kind is checked without
//! new test code. Each check's tolerance is justified in `railfem_framework::conformance`.

#[test]
fn every_registered_kind_passes_the_kit() {
    railfem::elements::link();
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
