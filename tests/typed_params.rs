//! The typed Rust API builds the model a model file builds (issue 31, item 3): each
//! built-in element family added through `ModelBuilder::add` with its parameter struct
//! (the `new(required…)` constructor and struct update syntax, enums for the choices) gives
//! the same equations and the same stiffness, mass and damping entries, to the bit, as the
//! `[[element]]` tables with the same keys. Both models share their `[analysis]` and nodes
//! (read from the same text), so only the element's route differs.
//!
//! The constructors fill the documented defaults: for every parameter struct, `new` with
//! the required values equals the keys parsed with only those values given (the defaults
//! `railfem elements` documents), and a typed struct survives the builder's serialization.

use railfem::elements::beam3d::{Beam3dParams, BeamGeometry, BeamMass};
use railfem::elements::mass::MassParams;
use railfem::elements::oscillators::moving_mass::MovingMassParams;
use railfem::elements::oscillators::sprung_mass::{Contact, SprungMassParams};
use railfem::elements::rail::contact::creep::law::Tangential;
use railfem::elements::rail::contact::profiles::Inclination;
use railfem::elements::rail::geometry::railline::RailSide;
use railfem::elements::rail::vehicle::comfort::{recorder::ComfortParams, ComfortMethod};
use railfem::elements::rail::wheels::moving_axle::{
    MovingAxleParams, RailProfileSource, WheelProfileSource,
};
use railfem::elements::rail::wheels::point_wheel::{HertzWheelParams, RigidWheelParams};
use railfem::elements::spring_damper::SpringDamperParams;
use railfem::elements::suspension::{SuspensionParams, SuspensionTangent};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::modelfile::{from_value, parse_toml};
use railfem::framework::registry::{parse_params, Params};
use railfem::framework::sparse::CscMatrix;
use railfem::framework::Model;
use railfem::solvers::Driver;
use std::path::Path;

/// The builder of `text` (a model file without its elements, or with them).
fn builder(text: &str) -> ModelBuilder {
    let v = parse_toml(text, "typed.toml").expect("valid TOML");
    from_value(&v, "typed.toml", Path::new(".")).expect("a valid model")
}

/// Equation count and the reference system's `K`, `M`, `C` and load of a model.
fn system(model: Model) -> (usize, [CscMatrix; 3], Vec<f64>) {
    let mut d = Driver::new(model).expect("the model runs");
    let neq = d.neq();
    let s = d.reference_system().expect("the reference system");
    (neq, [s.stiffness, s.mass, s.damping], s.load)
}

/// The two models have the same equations and the same matrix entries, bit for bit.
fn assert_same(file: Model, typed: Model) {
    let (n_file, m_file, l_file) = system(file);
    let (n_typed, m_typed, l_typed) = system(typed);
    assert_eq!(n_file, n_typed, "equation count");
    for (name, (a, b)) in ["K", "M", "C"].iter().zip(m_file.iter().zip(&m_typed)) {
        assert_eq!(a.col_ptr, b.col_ptr, "{name}: column pointers");
        assert_eq!(a.row_idx, b.row_idx, "{name}: row indices");
        let bits = |m: &CscMatrix| m.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b), "{name}: entries");
        assert!(a.values.iter().any(|v| *v != 0.0), "{name} is not empty");
    }
    let bits = |l: &[f64]| l.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&l_file), bits(&l_typed), "load");
}

/// Analysis and nodes shared by the structural family: a beam of two elements clamped at
/// node 1, a grounded spring and a mass at node 3, a suspension from node 3 to node 4.
const STRUCTURE: &str = r#"
[analysis]
kind = "transient"
dt = 0.01
duration = 0.1
rayleigh = { alpha = 0.2, beta = 1.0e-4 }

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [2.0, 0.0, 0.0]

[[node]]
id = 3
xyz = [4.0, 0.0, 0.0]

[[node]]
id = 4
xyz = [4.0, 0.0, 0.5]
"#;

/// `beam3d`, `spring_damper`, `mass` and `suspension`: non-default values of numbers,
/// arrays and choices.
#[test]
fn structural_elements_from_typed_structs_match_the_model_file() {
    let elements = r#"
[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
Asz = 3.0e-3
mass = "lumped"

[[element]]
type = "beam3d"
id = 2
nodes = [2, 3]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
orient = [0.0, 1.0, 0.2]
geometry = "pdelta"

[[element]]
type = "spring_damper"
id = 3
nodes = [3]
k = [1.0e5, 2.0e5, 3.0e5, 4.0e3, 5.0e3, 6.0e3]
c = [1.0e2, 0.0, 3.0e2, 0.0, 0.0, 0.0]

[[element]]
type = "mass"
id = 4
nodes = [4]
m = 350.0
inertia = [10.0, 20.0, 30.0]
Ixy = 1.5

[[element]]
type = "suspension"
id = 5
nodes = [3, 4]
k = [1.0e6, 2.0e6, 3.0e6]
c = [1.0e3, 2.0e3, 3.0e3]
k_rot = [0.0, 0.0, 4.0e4]
tangent = "symmetric"
"#;
    let file = builder(&format!("{STRUCTURE}{elements}")).build().unwrap();
    let section = Beam3dParams {
        rho: 7850.0,
        ..Beam3dParams::new(2.1e11, 8.1e10, 7.686e-3, 3.038e-5, 5.123e-6, 2.0e-6)
    };
    let mut b = builder(STRUCTURE);
    b.add(
        1,
        &[1, 2],
        &Beam3dParams {
            Asz: 3.0e-3,
            mass: BeamMass::Lumped,
            ..section.clone()
        },
    );
    b.add(
        2,
        &[2, 3],
        &Beam3dParams {
            orient: vec![0.0, 1.0, 0.2],
            geometry: BeamGeometry::PDelta,
            ..section
        },
    );
    b.add(
        3,
        &[3],
        &SpringDamperParams {
            c: [1.0e2, 0.0, 3.0e2, 0.0, 0.0, 0.0],
            ..SpringDamperParams::new([1.0e5, 2.0e5, 3.0e5, 4.0e3, 5.0e3, 6.0e3])
        },
    );
    b.add(
        4,
        &[4],
        &MassParams {
            inertia: [10.0, 20.0, 30.0],
            Ixy: 1.5,
            ..MassParams::new(350.0)
        },
    );
    b.add(
        5,
        &[3, 4],
        &SuspensionParams {
            c: [1.0e3, 2.0e3, 3.0e3],
            k_rot: [0.0, 0.0, 4.0e4],
            tangent: SuspensionTangent::Symmetric,
            ..SuspensionParams::new([1.0e6, 2.0e6, 3.0e6])
        },
    );
    assert_same(file, b.build().unwrap());
}

/// `moving_sprung_mass` and `moving_mass` on a simply supported beam of four elements.
#[test]
fn moving_oscillators_from_typed_structs_match_the_model_file() {
    let mut base = String::from(
        "[analysis]\nkind = \"transient\"\ndt = 0.005\nduration = 0.05\ngravity = [0.0, 0.0, -9.81]\nrayleigh = { alpha = 0.1, beta = 1.0e-4 }\n",
    );
    for i in 0..5 {
        let fix = match i {
            0 => "fix = [\"ux\", \"uy\", \"uz\", \"rx\"]\n",
            4 => "fix = [\"uy\", \"uz\"]\n",
            _ => "",
        };
        base.push_str(&format!(
            "[[node]]\nid = {}\nxyz = [{}, 0.0, 0.0]\n{fix}",
            i + 1,
            2.5 * i as f64
        ));
    }
    base.push_str("[[node]]\nid = 10\nxyz = [0.0, 0.0, 1.0]\n");
    for i in 0..4 {
        base.push_str(&format!(
            "[[element]]\ntype = \"beam3d\"\nid = {}\nnodes = [{}, {}]\nE = 2.943e10\nG = 1.2e10\nA = 1.0\nIy = 1.0\nIz = 2.0\nJ = 0.5\nrho = 2303.0\n",
            i + 1,
            i + 1,
            i + 2
        ));
    }
    let elements = r#"
[[element]]
type = "moving_sprung_mass"
id = 20
nodes = [10]
m = 5750.0
k = 1.595e6
c = 2.0e4
contact = "unilateral"
path = [1, 2, 3, 4]
start = 1.0
speed = 27.78

[[element]]
type = "moving_mass"
id = 21
nodes = []
m = 800.0
path = [1, 2, 3, 4]
start = 6.0
speed = 10.0
"#;
    let file = builder(&format!("{base}{elements}")).build().unwrap();
    let mut b = builder(&base);
    b.add(
        20,
        &[10],
        &SprungMassParams {
            c: 2.0e4,
            contact: Contact::Unilateral,
            path: vec![1, 2, 3, 4],
            start: 1.0,
            speed: 27.78,
            ..SprungMassParams::new(5750.0, 1.595e6)
        },
    );
    b.add(
        21,
        &[],
        &MovingMassParams {
            path: vec![1, 2, 3, 4],
            start: 6.0,
            speed: 10.0,
            ..MovingMassParams::new(800.0)
        },
    );
    assert_same(file, b.build().unwrap());
}

/// `P::new(required)` equals the keys parsed with only the required values given, and a
/// typed struct (non-default choices included) reads back from the keys the builder
/// writes for it.
fn check_defaults<P: Params + PartialEq + std::fmt::Debug>(
    typed_new: P,
    required: serde_json::Value,
    changed: P,
) {
    let kind = std::any::type_name::<P>();
    let parsed: P = parse_params(required.as_object().unwrap(), "test", kind).unwrap();
    assert_eq!(
        typed_new, parsed,
        "{kind}: constructor against documented defaults"
    );
    let keys = serde_json::to_value(&changed).unwrap();
    let back: P = parse_params(keys.as_object().unwrap(), "test", kind).unwrap();
    assert_eq!(changed, back, "{kind}: through the builder's keys");
}

/// Every parameter struct's constructor against its documented defaults.
#[test]
fn constructors_fill_the_documented_defaults() {
    use serde_json::json;
    let (e, g, a, iy, iz, j) = (2.1e11, 8.1e10, 1e-2, 1e-5, 2e-5, 3e-5);
    check_defaults(
        Beam3dParams::new(e, g, a, iy, iz, j),
        json!({"E": e, "G": g, "A": a, "Iy": iy, "Iz": iz, "J": j}),
        Beam3dParams {
            geometry: BeamGeometry::Corotational,
            ..Beam3dParams::new(e, g, a, iy, iz, j)
        },
    );
    let k6 = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    check_defaults(
        SpringDamperParams::new(k6),
        json!({ "k": k6 }),
        SpringDamperParams {
            axes: vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            ..SpringDamperParams::new(k6)
        },
    );
    check_defaults(
        MassParams::new(5.0),
        json!({"m": 5.0}),
        MassParams {
            Iyz: 2.0,
            ..MassParams::new(5.0)
        },
    );
    check_defaults(
        SuspensionParams::new([1.0, 2.0, 3.0]),
        json!({"k": [1.0, 2.0, 3.0]}),
        SuspensionParams {
            j_from_i: vec![0.0, 0.0, 1.0],
            ..SuspensionParams::new([1.0, 2.0, 3.0])
        },
    );
    check_defaults(
        SprungMassParams::new(10.0, 20.0),
        json!({"m": 10.0, "k": 20.0}),
        SprungMassParams {
            m_w: 300.0,
            rail: RailSide::Right,
            track: "track".into(),
            ..SprungMassParams::new(10.0, 20.0)
        },
    );
    check_defaults(
        MovingMassParams::new(10.0),
        json!({"m": 10.0}),
        MovingMassParams {
            speed_table: vec![[0.0, 1.0], [1.0, 2.0]],
            ..MovingMassParams::new(10.0)
        },
    );
    check_defaults(
        MovingAxleParams::new(RailSide::Left),
        json!({"side": "left"}),
        MovingAxleParams {
            inclination: Inclination::None,
            tangential: Tangential::Polach,
            wheel_profile: WheelProfileSource::File("profiles/worn.csv".into()),
            rail_profile: RailProfileSource::File("profiles/rail.csv".into()),
            ..MovingAxleParams::new(RailSide::Right)
        },
    );
    // The built-in profiles by any of their names, in any case.
    let named: MovingAxleParams = parse_params(
        json!({"side": "left", "wheel_profile": "S1002", "rail_profile": "UIC60"})
            .as_object()
            .unwrap(),
        "test",
        "moving_axle",
    )
    .unwrap();
    assert_eq!(named, MovingAxleParams::new(RailSide::Left));
    check_defaults(
        HertzWheelParams::new(RailSide::Right),
        json!({"side": "right"}),
        HertzWheelParams {
            G: 5.0e-8,
            ..HertzWheelParams::new(RailSide::Left)
        },
    );
    check_defaults(
        RigidWheelParams::new(RailSide::Left),
        json!({"side": "left"}),
        RigidWheelParams {
            k: 2.0e10,
            ..RigidWheelParams::new(RailSide::Left)
        },
    );
    check_defaults(
        ComfortParams::default(),
        json!({}),
        ComfortParams {
            node: Some(7),
            method: ComfortMethod::En12299,
            ..ComfortParams::default()
        },
    );
    check_defaults(
        ComfortParams::new(&[3], &[railfem::framework::Dof::Uz], &[]),
        json!({"nodes": [3], "vertical": ["uz"]}),
        ComfortParams::new(&[3, 4], &[], &[railfem::framework::Dof::Uy]),
    );
}
