//! `beam3d`: the two-node 3-D beam (Euler–Bernoulli, optionally Timoshenko), and the beam
//! helpers other elements reuse: local axes, cubic Hermite shape functions, the local 12×12
//! stiffness and mass matrices and their rotation to the nodal axes.
//!
//! The key `geometry` picks the kinematics: `"linear"` (the default; the small-displacement
//! element of this file, assembled once), `"pdelta"` (the linear element plus the P-Δ
//! effect of its axial force, [`pdelta`]) and `"corotational"` (finite 3-D rotations,
//! [`corotational`], on the forward-mode derivatives of `railfem_framework::dual`).
//!
//! What does not live here: warping torsion, and beams on carried nodes (the element
//! assumes both nodes have the global axes X-Y-Z).
//!
//! # Conventions
//!
//! * Local DOF order (12): `u1 v1 w1 θx1 θy1 θz1 u2 v2 w2 θx2 θy2 θz2`, node I first;
//!   `u, v, w` along local `x, y, z` (m), `θ` about them (rad).
//! * Local axes: `x` from node I to node J; `z = x × orient / |x × orient|`,
//!   `y = z × x`, so `orient` lies in the local x-y plane and fixes local `y`.
//!   Default `orient` (key `orient = []`): the horizontal vector `Z × x`, which makes local
//!   `z` the projection of global `Z` (up) normal to the axis and local `y` horizontal —
//!   so `Iy` is the vertical-bending inertia of a horizontal beam, as for rails (60E1:
//!   `Iy = 3.038e-5 m⁴` vertical). For a vertical beam (`|x × Z| < 1e-6`) the default is
//!   global `Y`, which then is local `y`.
//! * Bending in the local x-y plane (`v`, `θz = dv/dx`) uses `Iz` and `Asy`; bending in the
//!   x-z plane (`w`, `θy = −dw/dx`) uses `Iy` and `Asz`. The sign of `θy` is what a
//!   right-handed rotation about `y` does to a fibre along `x`.

use nalgebra::{DMatrix, Matrix3, SMatrix, SVector, Vector3};
use railfem_framework::element::{
    Element, ElementError, ElementProperties, NodeDofs, NodeKinematics, TrialState,
};
use railfem_framework::limits::{fmt_num, fmt_vec};
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::{serde_json, FemError};

pub mod corotational;
pub mod pdelta;

pub use corotational::Beam3dCorotational;
pub use pdelta::Beam3dPDelta;

/// A 12×12 matrix of a two-node, six-DOF-per-node element.
pub type Mat12 = SMatrix<f64, 12, 12>;

railfem_framework::element_params! {
    /// Model-file keys of `beam3d` (SI units).
    pub struct Beam3dParams {
        /// Young's modulus E (Pa), > 0.
        E: f64 ["Pa"],
        /// Shear modulus G (Pa), > 0; used by torsion and by the Timoshenko shear terms.
        G: f64 ["Pa"],
        /// Cross-section area A (m²), > 0.
        A: f64 ["m^2"],
        /// Second moment of area about local y (m⁴), > 0: bending in the local x-z plane.
        Iy: f64 ["m^4"],
        /// Second moment of area about local z (m⁴), > 0: bending in the local x-y plane.
        Iz: f64 ["m^4"],
        /// Saint-Venant torsion constant J (m⁴), > 0.
        J: f64 ["m^4"],
        /// Mass density ρ (kg/m³), ≥ 0; 0 gives a massless beam.
        rho: f64 ["kg/m^3"] = 0.0,
        /// Orientation vector [x, y, z] in global axes lying in the local x-y plane; [] = automatic (local z as close to global Z as possible).
        orient: Vec<f64> ["-"] = Vec::<f64>::new(),
        /// Shear area for shear along local y (m²), ≥ 0; 0 = no shear deformation (Euler–Bernoulli).
        Asy: f64 ["m^2"] = 0.0,
        /// Shear area for shear along local z (m²), ≥ 0; 0 = no shear deformation (Euler–Bernoulli).
        Asz: f64 ["m^2"] = 0.0,
        /// Mass matrix: "consistent" (cubic Hermite), "lumped" (diagonal, ρAL/2 per node and translation plus the section's rotary inertia) or "lumped_translational" (ρAL/2 per node and translation only, no rotary inertia: OpenSees' elasticBeamColumn default).
        mass: BeamMass [""] = "consistent",
        /// Kinematics: "linear" (small displacements), "pdelta" (linear plus the P-Δ effect of the axial force, as OpenSees geomTransf PDelta) or "corotational" (finite 3-D rotations; translational mass only).
        geometry: BeamGeometry [""] = "linear",
    }
}

impl railfem_framework::registry::ElementParams for Beam3dParams {
    const KIND: &'static str = "beam3d";
}

impl Beam3dParams {
    /// A massless, linear, Euler–Bernoulli beam of the given section (the required keys:
    /// E, G in Pa; A in m²; Iy, Iz, J in m⁴) with every other key at its documented
    /// default; set the rest with struct update syntax,
    /// `Beam3dParams { rho: 7850.0, ..Beam3dParams::new(e, g, a, iy, iz, j) }`.
    #[allow(non_snake_case)]
    pub fn new(E: f64, G: f64, A: f64, Iy: f64, Iz: f64, J: f64) -> Beam3dParams {
        Beam3dParams {
            E,
            G,
            A,
            Iy,
            Iz,
            J,
            rho: 0.0,
            orient: Vec::new(),
            Asy: 0.0,
            Asz: 0.0,
            mass: BeamMass::Consistent,
            geometry: BeamGeometry::Linear,
        }
    }
}

/// The kinematics a beam uses (key `geometry`: `"linear"`, `"pdelta"`, `"corotational"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BeamGeometry {
    /// Small displacements and rotations: [`Beam3d`].
    Linear,
    /// Linear plus the P-Δ effect: [`Beam3dPDelta`].
    PDelta,
    /// Finite rotations: [`Beam3dCorotational`].
    Corotational,
}

impl BeamGeometry {
    /// The name as a model file writes it.
    pub fn name(self) -> &'static str {
        match self {
            BeamGeometry::Linear => "linear",
            BeamGeometry::PDelta => "pdelta",
            BeamGeometry::Corotational => "corotational",
        }
    }
}

/// Section and material constants of a beam (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSection {
    /// Young's modulus (Pa).
    pub e: f64,
    /// Shear modulus (Pa).
    pub g: f64,
    /// Area (m²).
    pub a: f64,
    /// Second moment of area about local y (m⁴).
    pub iy: f64,
    /// Second moment of area about local z (m⁴).
    pub iz: f64,
    /// Saint-Venant torsion constant (m⁴).
    pub j: f64,
    /// Shear area for shear along local y (m²); 0 = rigid in shear.
    pub asy: f64,
    /// Shear area for shear along local z (m²); 0 = rigid in shear.
    pub asz: f64,
}

impl BeamSection {
    /// The section of a parameter set.
    pub fn from_params(p: &Beam3dParams) -> Self {
        BeamSection {
            e: p.E,
            g: p.G,
            a: p.A,
            iy: p.Iy,
            iz: p.Iz,
            j: p.J,
            asy: p.Asy,
            asz: p.Asz,
        }
    }

    /// Timoshenko shear parameter of bending in the local x-y plane,
    /// `Φ = 12·E·Iz / (G·Asy·L²)` (dimensionless) for length `l` (m); 0 when `Asy = 0`.
    pub fn phi_xy(&self, l: f64) -> f64 {
        shear_parameter(self.e * self.iz, self.g * self.asy, l)
    }

    /// Timoshenko shear parameter of bending in the local x-z plane,
    /// `Φ = 12·E·Iy / (G·Asz·L²)` (dimensionless) for length `l` (m); 0 when `Asz = 0`.
    pub fn phi_xz(&self, l: f64) -> f64 {
        shear_parameter(self.e * self.iy, self.g * self.asz, l)
    }
}

fn shear_parameter(ei: f64, gas: f64, l: f64) -> f64 {
    if gas > 0.0 {
        12.0 * ei / (gas * l * l)
    } else {
        0.0
    }
}

/// Which mass matrix a beam uses (key `mass`: `"consistent"`, `"lumped"`,
/// `"lumped_translational"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BeamMass {
    /// Consistent: cubic Hermite interpolation of `v, w`, linear of `u, θx`.
    Consistent,
    /// Lumped: diagonal; `ρAL/2` per node and translation, section rotary inertia
    /// `ρ·(Iy+Iz)·L/2`, `ρ·Iy·L/2`, `ρ·Iz·L/2` about local x, y, z per node.
    Lumped,
    /// Lumped, translations only: `ρAL/2` per node and translation, no rotary inertia
    /// (the rotations are massless). This is OpenSees' `elasticBeamColumn` mass without
    /// `-cMass`, kept for side-by-side comparisons (`railfem bench --mass lumped`).
    LumpedTranslational,
}

/// Local axes of a beam from node I at `xi` to node J at `xj` (m, global).
///
/// Returns `R` whose **rows** are the unit vectors of local x, y, z in global axes, so a
/// vector transforms as `v_local = R·v_global`. Local `x = (xj − xi)/|xj − xi|`,
/// `z = x × orient / |x × orient|`, `y = z × x` (right-handed, orthonormal).
///
/// Preconditions (checked by the `beam3d` factory, not here): `xi ≠ xj` and `orient` not
/// parallel to the axis; otherwise the result holds NaN. See [`default_orient`].
pub fn local_axes(xi: &Vector3<f64>, xj: &Vector3<f64>, orient: &Vector3<f64>) -> Matrix3<f64> {
    let x = (xj - xi).normalize();
    let z = x.cross(orient).normalize();
    let y = z.cross(&x);
    Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()])
}

/// The default orientation vector of a beam with unit axis `x` (global): the horizontal
/// `Z × x` (local z then is global Z projected normal to the axis), or global `Y` when the
/// beam is vertical (`|x × Z| < 1e-6`).
pub fn default_orient(x: &Vector3<f64>) -> Vector3<f64> {
    let zx = Vector3::z().cross(x);
    if zx.norm() < 1e-6 {
        Vector3::y()
    } else {
        zx
    }
}

/// Cubic Hermite shape functions at `xi ∈ [0, 1]` (dimensionless) on a beam of length `l`
/// (m): `w(x) = N1·w1 + N2·θ1 + N3·w2 + N4·θ2` with `θ = dw/dx` at the ends and `x = ξ·l`.
///
/// `N1 = 1 − 3ξ² + 2ξ³`, `N2 = l·(ξ − 2ξ² + ξ³)`, `N3 = 3ξ² − 2ξ³`, `N4 = l·(ξ³ − ξ²)`:
/// the cubic that matches the two end values and end slopes (the exact deflection of an
/// unloaded Euler–Bernoulli span). `N1, N3` are dimensionless, `N2, N4` in m.
/// For bending in the local x-z plane, where `θy = −dw/dx`, negate `θ` before use.
pub fn hermite(xi: f64, l: f64) -> [f64; 4] {
    let x2 = xi * xi;
    let x3 = x2 * xi;
    [
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        l * (x3 - x2),
    ]
}

/// First derivatives `dN/dx = (1/l)·dN/dξ` of [`hermite`] at `xi` (1/m for `N1, N3`,
/// dimensionless for `N2, N4`): the slope `dw/dx` of the interpolated deflection.
pub fn hermite_d(xi: f64, l: f64) -> [f64; 4] {
    let x2 = xi * xi;
    [
        (-6.0 * xi + 6.0 * x2) / l,
        1.0 - 4.0 * xi + 3.0 * x2,
        (6.0 * xi - 6.0 * x2) / l,
        3.0 * x2 - 2.0 * xi,
    ]
}

/// Second derivatives `d²N/dx² = (1/l²)·d²N/dξ²` of [`hermite`] at `xi` (1/m² for `N1, N3`,
/// 1/m for `N2, N4`): the curvature `d²w/dx²` of the interpolated deflection.
pub fn hermite_dd(xi: f64, l: f64) -> [f64; 4] {
    [
        (-6.0 + 12.0 * xi) / (l * l),
        (-4.0 + 6.0 * xi) / l,
        (6.0 - 12.0 * xi) / (l * l),
        (6.0 * xi - 2.0) / l,
    ]
}

/// Indices of the bending DOFs `(w1, θ1, w2, θ2)` of the local x-y plane (`v`, `θz`).
const XY: [usize; 4] = [1, 5, 7, 11];
/// Indices of the bending DOFs `(w1, θ1, w2, θ2)` of the local x-z plane (`w`, `θy`).
const XZ: [usize; 4] = [2, 4, 8, 10];

/// Adds `s·b` at rows/columns `idx` of `m`; `sign` flips the rotational entries
/// (positions 1 and 3) for the x-z plane, where `θy = −dw/dx`.
fn add_bending(m: &mut Mat12, idx: [usize; 4], b: &[[f64; 4]; 4], s: f64, flip: bool) {
    let sg = if flip {
        [1.0, -1.0, 1.0, -1.0]
    } else {
        [1.0; 4]
    };
    for r in 0..4 {
        for c in 0..4 {
            m[(idx[r], idx[c])] += s * sg[r] * sg[c] * b[r][c];
        }
    }
}

/// Adds `s·[[2,1],[1,2]]` (`linear`=false: `s·[[1,−1],[−1,1]]`) at DOFs `i`, `j`.
fn add_bar(m: &mut Mat12, i: usize, j: usize, s: f64, mass_like: bool) {
    let (d, o) = if mass_like { (2.0, 1.0) } else { (1.0, -1.0) };
    m[(i, i)] += s * d;
    m[(j, j)] += s * d;
    m[(i, j)] += s * o;
    m[(j, i)] += s * o;
}

/// Local 12×12 stiffness (N/m, N, N·m/rad) of a straight beam of length `l` (m).
///
/// Axial `EA/L·[[1,−1],[−1,1]]` on `(u1, u2)`, torsion `GJ/L·[[1,−1],[−1,1]]` on
/// `(θx1, θx2)`. Bending in each plane, DOFs `(w1, θ1, w2, θ2)` with `θ = dw/dx`:
///
/// ```text
///             E·I        ⎡ 12    6L        −12   6L       ⎤
/// k = ─────────────────  ⎢ 6L   (4+Φ)L²    −6L  (2−Φ)L²   ⎥
///      L³·(1+Φ)          ⎢−12   −6L         12  −6L       ⎥
///                        ⎣ 6L   (2−Φ)L²    −6L  (4+Φ)L²   ⎦
/// ```
///
/// With `Φ = 0` this is `∫ E·I·N_i''·N_j'' dx` over the [`hermite`] functions. With
/// `Φ = 12EI/(G·As·L²)` it is the exact flexibility-based Timoshenko matrix: clamping
/// node 1 and inverting the node-2 block gives the tip flexibility
/// `(4+Φ)L³/(12EI) = L³/(3EI) + L/(G·As)` — bending plus shear deflection of a cantilever.
/// The x-z plane (`θy = −dw/dx`) uses the same matrix with the signs of the `θ` rows and
/// columns flipped.
pub fn local_stiffness(s: &BeamSection, l: f64) -> Mat12 {
    let mut k = Mat12::zeros();
    add_bar(&mut k, 0, 6, s.e * s.a / l, false);
    add_bar(&mut k, 3, 9, s.g * s.j / l, false);
    for (idx, ei, phi, flip) in [
        (XY, s.e * s.iz, s.phi_xy(l), false),
        (XZ, s.e * s.iy, s.phi_xz(l), true),
    ] {
        let l2 = l * l;
        let b = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, (4.0 + phi) * l2, -6.0 * l, (2.0 - phi) * l2],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, (2.0 - phi) * l2, -6.0 * l, (4.0 + phi) * l2],
        ];
        add_bending(&mut k, idx, &b, ei / (l2 * l * (1.0 + phi)), flip);
    }
    k
}

/// Local 12×12 mass matrix (kg, kg·m, kg·m²) of a beam of length `l` (m) and density
/// `rho` (kg/m³).
///
/// [`BeamMass::Consistent`]: axial `ρAL/6·[[2,1],[1,2]]` (linear `u`), torsion
/// `ρ·Ip·L/6·[[2,1],[1,2]]` with the polar moment `Ip = Iy + Iz` (not `J`), and in each
/// bending plane `∫ ρA·N_i·N_j dx` over the [`hermite`] functions:
/// `ρAL/420·[[156, 22L, 54, −13L], [22L, 4L², 13L, −3L²], [54, 13L, 156, −22L],
/// [−13L, −3L², −22L, 4L²]]` (signs of `θ` flipped for the x-z plane). The rotary inertia
/// of bending and the shear correction of the mass are neglected (slender beams).
///
/// [`BeamMass::Lumped`]: diagonal, see the variant. Both give the total translational
/// mass `ρAL` in every direction.
pub fn local_mass(s: &BeamSection, rho: f64, l: f64, kind: BeamMass) -> Mat12 {
    let mut m = Mat12::zeros();
    let ip = s.iy + s.iz;
    match kind {
        BeamMass::Consistent => {
            add_bar(&mut m, 0, 6, rho * s.a * l / 6.0, true);
            add_bar(&mut m, 3, 9, rho * ip * l / 6.0, true);
            let l2 = l * l;
            let b = [
                [156.0, 22.0 * l, 54.0, -13.0 * l],
                [22.0 * l, 4.0 * l2, 13.0 * l, -3.0 * l2],
                [54.0, 13.0 * l, 156.0, -22.0 * l],
                [-13.0 * l, -3.0 * l2, -22.0 * l, 4.0 * l2],
            ];
            let sc = rho * s.a * l / 420.0;
            add_bending(&mut m, XY, &b, sc, false);
            add_bending(&mut m, XZ, &b, sc, true);
        }
        BeamMass::Lumped | BeamMass::LumpedTranslational => {
            let half = 0.5 * rho * l;
            let rotary = kind == BeamMass::Lumped;
            for n in [0, 6] {
                for t in 0..3 {
                    m[(n + t, n + t)] = half * s.a;
                }
                if rotary {
                    m[(n + 3, n + 3)] = half * ip;
                    m[(n + 4, n + 4)] = half * s.iy;
                    m[(n + 5, n + 5)] = half * s.iz;
                }
            }
        }
    }
    m
}

/// Rotates a local 12×12 matrix to the nodal (global) axes: `Tᵀ·m·T` with
/// `T = diag(R, R, R, R)` and `R` from [`local_axes`] (rows = local axes).
pub fn to_global(m_local: &Mat12, r: &Matrix3<f64>) -> Mat12 {
    let mut t = Mat12::zeros();
    for b in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * b, 3 * b).copy_from(r);
    }
    t.transpose() * m_local * t
}

/// Rotates a global 12-vector of a two-node element to local axes (`T·v`).
pub fn to_local_vec(v: &SVector<f64, 12>, r: &Matrix3<f64>) -> SVector<f64, 12> {
    let mut out = SVector::<f64, 12>::zeros();
    for b in 0..4 {
        let part = r * v.fixed_rows::<3>(3 * b);
        out.fixed_rows_mut::<3>(3 * b).copy_from(&part);
    }
    out
}

/// The linear two-node 3-D beam element `beam3d`. See the module documentation.
///
/// It holds what defines it (parameters, nodes, length, axes, mass type) and its trial
/// displacement, not its matrices: `K_local`, `K = Tᵀ·K_local·T` and `M` are formed when
/// asked ([`Beam3d::local_stiffness`], [`Beam3d::stiffness_global`],
/// [`Beam3d::mass_global`]) by the same functions in the same order as at construction
/// before, so every number is unchanged to the bit. The framework asks for `K` and `M`
/// once (the constant matrices' assembly); the recorders' end forces form `K_local`
/// (12×12, about 300 flops) per recorded step. Three stored matrices were 3.4 KB of the
/// 3.8 KB an element took, 730 MiB of the model at 1e6 DOF on every rank.
#[derive(Debug, Clone)]
pub struct Beam3d {
    params: Beam3dParams,
    conn: [NodeDofs; 2],
    length: f64,
    axes: Matrix3<f64>,
    mass_kind: BeamMass,
    u: SVector<f64, 12>,
}

impl Beam3d {
    /// Builds a beam between node indices `nodes` at reference positions `xi`, `xj`
    /// (m, global). Validates the parameters; errors are [`FemError::Input`] at `origin`
    /// naming the offending key and the fix.
    pub fn new(
        params: Beam3dParams,
        nodes: [usize; 2],
        xi: Vector3<f64>,
        xj: Vector3<f64>,
        origin: &str,
    ) -> Result<Beam3d, FemError> {
        let bad = |msg: String| Err(FemError::input(origin, msg));
        for (key, v) in [
            ("E", params.E),
            ("G", params.G),
            ("A", params.A),
            ("Iy", params.Iy),
            ("Iz", params.Iz),
            ("J", params.J),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!(
                    "beam3d: `{key}` = {} must be a positive finite number in SI units; give the section's actual value",
                    fmt_num(v)
                ));
            }
        }
        for (key, v) in [
            ("rho", params.rho),
            ("Asy", params.Asy),
            ("Asz", params.Asz),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(format!(
                    "beam3d: `{key}` = {} must be ≥ 0 and finite (0 switches it off)",
                    fmt_num(v)
                ));
            }
        }
        let kind = params.mass;
        let d = xj - xi;
        // Scaled norms: |d| of a beam 1e200 m long is finite although |d|² is not.
        let scaled_norm = |v: &Vector3<f64>| match v.amax() {
            m if m > 0.0 && m.is_finite() => m * (v / m).norm(),
            m => m,
        };
        let length = scaled_norm(&d);
        let scale = scaled_norm(&xi).max(scaled_norm(&xj)).max(1.0);
        if !length.is_finite() {
            return bad(format!(
                "beam3d: the beam from {} to {} is longer than a number can hold; check the node coordinates (m)",
                fmt_vec(xi.as_slice()),
                fmt_vec(xj.as_slice())
            ));
        }
        if length <= 1e-12 * scale {
            return bad(format!(
                "beam3d{}: zero-length beam (`nodes` I at {} and J at {}, {} m apart); connect two distinct points",
                if params.geometry == BeamGeometry::Linear {
                    String::new()
                } else {
                    format!(" (geometry = \"{}\")", params.geometry.name())
                },
                fmt_vec(xi.as_slice()),
                fmt_vec(xj.as_slice()),
                fmt_num(length)
            ));
        }
        let x = d / length;
        let orient = match params.orient.as_slice() {
            [] => default_orient(&x),
            [a, b, c] => {
                let o = Vector3::new(*a, *b, *c);
                let on = o.norm();
                if on <= 0.0 || x.cross(&(o / on)).norm() < 1e-6 {
                    return bad(format!(
                        "beam3d: `orient` = {:?} is zero or parallel to the beam axis {:?}; give a vector across the beam lying in its local x-y plane",
                        params.orient,
                        [x.x, x.y, x.z]
                    ));
                }
                o
            }
            _ => {
                return bad(format!(
                    "beam3d: `orient` has {} components; give [x, y, z] or [] for the default",
                    params.orient.len()
                ))
            }
        };
        let axes = local_axes(&xi, &xj, &orient);
        Ok(Beam3d {
            params,
            conn: [NodeDofs::all(nodes[0]), NodeDofs::all(nodes[1])],
            length,
            axes,
            mass_kind: kind,
            u: SVector::zeros(),
        })
    }

    /// Length L (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Local axes `R` (rows = local x, y, z in global axes), see [`local_axes`].
    pub fn axes(&self) -> &Matrix3<f64> {
        &self.axes
    }

    /// Local stiffness `K_local` (N/m, N, N·m/rad), formed now by [`local_stiffness`].
    pub fn local_stiffness(&self) -> Mat12 {
        local_stiffness(&BeamSection::from_params(&self.params), self.length)
    }

    /// Stiffness in global axes `Tᵀ·K_local·T` (N/m, N, N·m/rad), formed now by
    /// [`to_global`].
    pub fn stiffness_global(&self) -> Mat12 {
        to_global(&self.local_stiffness(), &self.axes)
    }

    /// Mass matrix in global axes (kg, kg·m, kg·m²), formed now by [`local_mass`] and
    /// [`to_global`].
    pub fn mass_global(&self) -> Mat12 {
        let sec = BeamSection::from_params(&self.params);
        let m = local_mass(&sec, self.params.rho, self.length, self.mass_kind);
        to_global(&m, &self.axes)
    }

    /// Stress resultants at end I in local axes at the trial state:
    /// `[N, Vy, Vz, T, My, Mz]` (N, N·m), the forces and moments on the positive
    /// (+x-facing) face of a cut just inside end I, i.e. minus the local end forces
    /// `K_local·T·u` at node I. Tension is positive `N`; a cantilever clamped at I with a
    /// tip force `P` along local y has `Vy = P`, `Mz = P·L`.
    pub fn end_forces_i(&self) -> [f64; 6] {
        let f = self.local_stiffness() * to_local_vec(&self.u, &self.axes);
        [-f[0], -f[1], -f[2], -f[3], -f[4], -f[5]]
    }
}

impl Element for Beam3d {
    fn kind(&self) -> &str {
        "beam3d"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        let has_mass = self.params.rho > 0.0;
        ElementProperties {
            linear: true,
            constant_mass: true,
            constant_damping: true,
            has_mass,
            has_damping: false,
            symmetric: true,
            connectivity_may_change: false,
            objective: true,
            declared_mass: has_mass.then_some(self.params.rho * self.params.A * self.length),
            finite_rotations: false,
        }
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        support::check_trial(trial, 12)?;
        self.u = SVector::from_column_slice(trial.disp);
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        let r = self.stiffness_global() * self.u;
        f.copy_from_slice(r.as_slice());
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from(&self.stiffness_global());
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        m.copy_from(&self.mass_global());
    }

    fn output_names(&self) -> Vec<String> {
        ["N", "Vy", "Vz", "T", "My", "Mz"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["N", "N", "N", "N·m", "N·m", "N·m"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&self.end_forces_i());
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }
}

/// Factory of `beam3d`: two nodes I, J; see [`Beam3d::new`] for the checks.
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: Beam3dParams = spec.parse()?;
    let geometry = p.geometry;
    let n = support::resolve_nodes(spec, ctx, &[2], "beam3d", "node I, node J")?;
    let (xi, xj) = (ctx.node_position(n[0]), ctx.node_position(n[1]));
    let linear = Beam3d::new(p, [n[0], n[1]], xi, xj, &spec.origin)?;
    Ok(match geometry {
        BeamGeometry::Linear => Box::new(linear),
        BeamGeometry::PDelta => Box::new(Beam3dPDelta::new(linear)),
        BeamGeometry::Corotational => Box::new(Beam3dCorotational::new(
            linear.params.clone(),
            [n[0], n[1]],
            xi,
            xj,
            &linear.axes,
            linear.params.mass != BeamMass::Consistent,
        )),
    })
}

/// Conformance samples: a horizontal consistent-mass beam, a skew Timoshenko beam with
/// lumped mass and an explicit `orient`, a vertical massless beam; a skew P-Δ beam; and
/// corotational beams at strongly deformed states (rotations of order 1 rad, translations of
/// a tenth of the length), one Timoshenko with lumped mass.
fn samples() -> Vec<Sample> {
    let cases: [(&str, [f64; 3], [f64; 3], serde_json::Value); 6] = [
        (
            "horizontal, consistent mass",
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            serde_json::json!({"E": 2.1e11, "G": 8.1e10, "A": 7.686e-3, "Iy": 3.038e-5,
                               "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0}),
        ),
        (
            "skew Timoshenko, lumped mass",
            [1.0, -0.5, 0.3],
            [2.2, 0.7, 1.4],
            serde_json::json!({"E": 3.0e10, "G": 1.25e10, "A": 0.12, "Iy": 1.6e-3,
                               "Iz": 9.0e-4, "J": 1.2e-3, "rho": 2500.0, "Asy": 0.1,
                               "Asz": 0.1, "orient": [0.0, 1.0, 1.0], "mass": "lumped"}),
        ),
        (
            "vertical, massless",
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 3.0],
            serde_json::json!({"E": 2.0e11, "G": 7.7e10, "A": 1.0e-2, "Iy": 8.0e-5,
                               "Iz": 2.0e-5, "J": 1.0e-5}),
        ),
        (
            "skew P-Delta",
            [0.5, 0.2, -0.1],
            [1.9, -0.8, 2.3],
            serde_json::json!({"E": 2.0e11, "G": 7.7e10, "A": 1.0e-2, "Iy": 8.0e-5,
                               "Iz": 2.0e-5, "J": 1.0e-5, "rho": 7850.0,
                               "geometry": "pdelta"}),
        ),
        (
            "corotational, large rotation",
            [0.0, 0.0, 0.0],
            [2.0, 0.5, -0.3],
            serde_json::json!({"E": 2.1e11, "G": 8.1e10, "A": 7.686e-3, "Iy": 3.038e-5,
                               "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0,
                               "geometry": "corotational"}),
        ),
        (
            "corotational Timoshenko, lumped, large rotation",
            [1.0, -0.5, 0.3],
            [2.2, 0.7, 1.4],
            serde_json::json!({"E": 3.0e10, "G": 1.25e10, "A": 0.12, "Iy": 1.6e-3,
                               "Iz": 9.0e-4, "J": 1.2e-3, "rho": 2500.0, "Asy": 0.1,
                               "Asz": 0.1, "orient": [0.0, 1.0, 1.0], "mass": "lumped",
                               "geometry": "corotational"}),
        ),
    ];
    cases
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, a, b, params))| {
            let pos = [Vector3::from(a), Vector3::from(b)];
            let mut ctx = support::PointContext::new(&pos);
            let spec = support::spec("beam3d", &[1, 2], params);
            let element = build(&spec, &mut ctx).ok()?;
            // Samples 4 on are strongly deformed (finite rotations for the corotational beam).
            let scale = if i >= 4 { (0.2, 1.2) } else { (1e-3, 1e-3) };
            Some(support::sample_on_points(
                name,
                element,
                &pos,
                100 + i as u64,
                scale,
            ))
        })
        .collect()
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "beam3d",
        description: "2-node 3-D Euler–Bernoulli/Timoshenko beam, 6 DOF per node; geometry linear, pdelta or corotational",
        params: <Beam3dParams as Params>::docs,
        build,
        samples,
    }
}

/// Helpers shared by the element factories and sample generators of this crate: node
/// resolution, a minimal [`BuildContext`] over a list of points, and deterministic
/// pseudo-random states.
pub(crate) mod support {
    use super::*;

    /// Resolves `spec.nodes` to node indices; the count must be one of `counts`.
    /// `what` names the nodes expected, for the message.
    pub(crate) fn resolve_nodes(
        spec: &ElementSpec,
        ctx: &dyn BuildContext,
        counts: &[usize],
        kind: &str,
        what: &str,
    ) -> Result<Vec<usize>, FemError> {
        if !counts.contains(&spec.nodes.len()) {
            let want: Vec<String> = counts.iter().map(|c| c.to_string()).collect();
            return Err(FemError::input(
                &spec.origin,
                format!(
                    "{kind}: `nodes` has {} ids but {kind} takes {} ({what}); fix the `nodes` list",
                    spec.nodes.len(),
                    want.join(" or ")
                ),
            ));
        }
        spec.nodes
            .iter()
            .map(|&id| {
                ctx.node_index(id).ok_or_else(|| {
                    FemError::input(
                        &spec.origin,
                        format!("{kind}: `nodes` names node id {id}, which is not defined; define the node or fix the id"),
                    )
                })
            })
            .collect()
    }

    /// Checks that a trial state has `n` finite displacements.
    pub(crate) fn check_trial(trial: &TrialState, n: usize) -> Result<(), ElementError> {
        if trial.disp.len() != n {
            return Err(ElementError::Invalid(format!(
                "trial displacement has {} entries, the element has {n} DOFs",
                trial.disp.len()
            )));
        }
        if trial.disp.iter().any(|v| !v.is_finite()) {
            return Err(ElementError::NonFinite {
                what: "trial displacement".into(),
            });
        }
        Ok(())
    }

    /// A [`BuildContext`] over a list of points; node `i` has user id `i + 1`.
    pub(crate) struct PointContext {
        pos: Vec<Vector3<f64>>,
    }

    impl PointContext {
        /// Nodes with ids 1, 2, … at `pos` (m).
        pub(crate) fn new(pos: &[Vector3<f64>]) -> Self {
            PointContext { pos: pos.to_vec() }
        }
    }

    impl BuildContext for PointContext {
        fn node_index(&self, id: u64) -> Option<usize> {
            let i = usize::try_from(id).ok()?.checked_sub(1)?;
            (i < self.pos.len()).then_some(i)
        }
        fn node_position(&self, index: usize) -> Vector3<f64> {
            self.pos[index]
        }
        fn add_internal_node(&mut self, position: Vector3<f64>, _like: Option<usize>) -> usize {
            self.pos.push(position);
            self.pos.len() - 1
        }
        fn resource(&self, _name: &str) -> Option<std::sync::Arc<dyn std::any::Any + Send + Sync>> {
            None
        }
    }

    /// An element spec of `kind` on node ids `nodes` with keys `params` (a JSON object).
    pub(crate) fn spec(kind: &str, nodes: &[u64], params: serde_json::Value) -> ElementSpec {
        ElementSpec {
            id: 1,
            kind: kind.to_string(),
            nodes: nodes.to_vec(),
            params: match params {
                serde_json::Value::Object(m) => m,
                _ => serde_json::Map::new(),
            },
            origin: format!("test: {kind}"),
        }
    }

    /// `n` deterministic pseudo-random numbers in [−1, 1) (SplitMix64 of `seed`).
    pub(crate) fn pseudo_random(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = s;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^= z >> 31;
                (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            })
            .collect()
    }

    /// A pseudo-random state of `nodes` six-DOF nodes: translations up to `trans` (m or
    /// m/s), rotations up to `rot` (rad or rad/s).
    pub(crate) fn pseudo_random_state(seed: u64, nodes: usize, trans: f64, rot: f64) -> Vec<f64> {
        pseudo_random(seed, 6 * nodes)
            .into_iter()
            .enumerate()
            .map(|(i, r)| r * if i % 6 < 3 { trans } else { rot })
            .collect()
    }

    /// A conformance sample of `element` on fixed nodes at `pos`: displacements up to
    /// `(trans, rot)` drawn from `seed`, velocities up to 1e-2 from `seed + 100`, the kit's
    /// default difference step, no committed history.
    pub(crate) fn sample_on_points(
        name: &str,
        element: Box<dyn Element>,
        pos: &[Vector3<f64>],
        seed: u64,
        (trans, rot): (f64, f64),
    ) -> Sample {
        Sample {
            name: name.to_string(),
            element,
            nodes: pos.iter().map(|p| NodeKinematics::fixed(*p)).collect(),
            disp: pseudo_random_state(seed, pos.len(), trans, rot),
            vel: pseudo_random_state(seed + 100, pos.len(), 1e-2, 1e-2),
            fd_step: 1e-6,
            committed_disp: None,
            rebuild: None,
        }
    }
}

#[cfg(test)]
mod params_tests {
    use super::Beam3dParams;
    use railfem_framework::registry::{parse_params, Params};

    /// `Beam3dParams::new` fills exactly the documented defaults: it equals the struct the
    /// registry parses from the required keys alone.
    #[test]
    fn new_equals_the_documented_defaults() {
        let required = serde_json::json!({"E": 2.1e11, "G": 8.1e10, "A": 0.01, "Iy": 1e-4, "Iz": 2e-4, "J": 3e-4});
        let parsed: Beam3dParams = parse_params(
            required.as_object().unwrap(),
            "test",
            "element type `beam3d`",
        )
        .unwrap();
        assert_eq!(
            parsed,
            Beam3dParams::new(2.1e11, 8.1e10, 0.01, 1e-4, 2e-4, 3e-4)
        );
        assert_eq!(Beam3dParams::docs().len(), 12);
    }
}

#[cfg(test)]
mod tests {
    use super::support::{spec, PointContext};
    use super::*;
    use nalgebra::{SMatrix, Vector6};

    const E: f64 = 2.1e11;
    const G: f64 = 8.1e10;
    const A: f64 = 7.686e-3;
    const IY: f64 = 3.038e-5;
    const IZ: f64 = 5.123e-6;
    const J: f64 = 2.0e-6;

    fn params(extra: serde_json::Value) -> serde_json::Value {
        let mut p = serde_json::json!({"E": E, "G": G, "A": A, "Iy": IY, "Iz": IZ, "J": J});
        if let (Some(m), serde_json::Value::Object(x)) = (p.as_object_mut(), extra) {
            m.extend(x);
        }
        p
    }

    fn beam(xi: [f64; 3], xj: [f64; 3], extra: serde_json::Value) -> Beam3d {
        let p: Beam3dParams = spec("beam3d", &[1, 2], params(extra)).parse().unwrap();
        Beam3d::new(p, [0, 1], xi.into(), xj.into(), "test").unwrap()
    }

    fn build_err(nodes: &[u64], pos: &[[f64; 3]], p: serde_json::Value) -> String {
        let pos: Vec<Vector3<f64>> = pos.iter().map(|&x| x.into()).collect();
        let mut ctx = PointContext::new(&pos);
        match build(&spec("beam3d", nodes, p), &mut ctx) {
            Ok(_) => panic!("expected an error"),
            Err(e) => e.to_string(),
        }
    }

    /// Clamps node I (deletes its rows and columns) and solves the 6×6 free-end system
    /// `K_JJ·u_J = f_J` (global axes) by dense LU.
    fn cantilever(b: &Beam3d, f_global: Vector6<f64>) -> Vector6<f64> {
        let kjj: SMatrix<f64, 6, 6> = b.stiffness_global().fixed_view::<6, 6>(6, 6).into();
        kjj.lu()
            .solve(&f_global)
            .expect("free-end block is regular")
    }

    fn rot6(r: &Matrix3<f64>) -> SMatrix<f64, 6, 6> {
        let mut t = SMatrix::<f64, 6, 6>::zeros();
        t.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
        t.fixed_view_mut::<3, 3>(3, 3).copy_from(r);
        t
    }

    /// The matrices formed on demand are those the element stored before it dropped them:
    /// `K_local` against the closed-form entries of the Timoshenko beam written out here
    /// (to 4 ulps of each entry: the closed form multiplies the factors in another order,
    /// each of the ≤ 4 roundings costing at most one ulp), and `K`, `M` against
    /// `Tᵀ·X·T` with `T = diag(R, R, R, R)` built here — the same products in the same
    /// order as the construction formed, so equal to the bit. The element without its
    /// matrices takes less than one 12×12 matrix (1 152 B); it took 3 808 B with three.
    #[test]
    fn matrices_formed_on_demand_equal_the_stored_ones() {
        let (asy, asz) = (5e-3, 4e-3);
        let b = beam(
            [1.0, -0.5, 0.3],
            [2.2, 0.7, 1.4],
            serde_json::json!({"rho": 7850.0, "Asy": asy, "Asz": asz, "orient": [0.0, 1.0, 1.0]}),
        );
        let l = b.length();
        let kl = b.local_stiffness();
        let mut want = Mat12::zeros();
        let mut bar = |i: usize, j: usize, s: f64| {
            want[(i, i)] = s;
            want[(j, j)] = s;
            want[(i, j)] = -s;
            want[(j, i)] = -s;
        };
        bar(0, 6, E * A / l);
        bar(3, 9, G * J / l);
        // (v1, θz1, v2, θz2) with EIz, Asy; (w1, θy1, w2, θy2) with EIy, Asz and θ signs flipped.
        for (idx, ei, gas, sg) in [(XY, E * IZ, G * asy, 1.0), (XZ, E * IY, G * asz, -1.0)] {
            let phi = 12.0 * ei / (gas * l * l);
            let d = 1.0 + phi;
            let (a, c) = (12.0 * ei / (l * l * l * d), 6.0 * ei / (l * l * d));
            let (p, q) = ((4.0 + phi) * ei / (l * d), (2.0 - phi) * ei / (l * d));
            let block = [
                [a, sg * c, -a, sg * c],
                [sg * c, p, -sg * c, q],
                [-a, -sg * c, a, -sg * c],
                [sg * c, q, -sg * c, p],
            ];
            for r in 0..4 {
                for col in 0..4 {
                    want[(idx[r], idx[col])] = block[r][col];
                }
            }
        }
        for i in 0..12 {
            for j in 0..12 {
                let tol = 4.0 * f64::EPSILON * want[(i, j)].abs();
                assert!(
                    (kl[(i, j)] - want[(i, j)]).abs() <= tol,
                    "K_local ({i},{j})"
                );
            }
        }
        let mut t = Mat12::zeros();
        for blk in 0..4 {
            t.fixed_view_mut::<3, 3>(3 * blk, 3 * blk)
                .copy_from(b.axes());
        }
        let sec = BeamSection::from_params(&b.params);
        let ml = local_mass(&sec, 7850.0, l, BeamMass::Consistent);
        assert_eq!(b.stiffness_global(), t.transpose() * kl * t);
        assert_eq!(b.mass_global(), t.transpose() * ml * t);
        let mut k = DMatrix::zeros(12, 12);
        b.tangent_stiffness(&mut k);
        assert_eq!(
            k,
            DMatrix::from_column_slice(12, 12, b.stiffness_global().as_slice())
        );
        assert!(
            std::mem::size_of::<Beam3d>() < 1152,
            "{}",
            std::mem::size_of::<Beam3d>()
        );
    }

    /// Checks the six tip load cases of a cantilever clamped at I against beam theory.
    ///
    /// Closed forms, local axes, `x` along the beam, tip at `x = L`: the Euler–Bernoulli
    /// equation `EI·w'''' = 0` with `w(0) = w'(0) = 0` and a tip force `P`
    /// (`EI·w''(L) = 0`, `−EI·w'''(L) = −P`…) gives `w = P·x²(3L − x)/(6EI)`, so the tip
    /// deflection is `PL³/(3EI)` and the tip slope `PL²/(2EI)`; a tip moment `M` gives
    /// `EI·w'' = M`, `w = M·x²/(2EI)`: `ML²/(2EI)` and slope `ML/(EI)`. Shear deformation
    /// adds `P·x/(G·As)` to the deflection under a constant shear force `P` (Timoshenko,
    /// slope of the section unchanged). A bar: `PL/(EA)`; a shaft: `TL/(GJ)`. In the x-z
    /// plane `θy = −w'`, which flips the signs of the coupled terms. The load is applied
    /// in global axes (`F = Tᵀ·F_local`) and the solution rotated back (`u_local = T·u`),
    /// so an arbitrary orientation checks that the results rotate with the geometry.
    ///
    /// Tolerance 1e-9 relative: a 6×6 LU with condition number ~ (L²·A/I)² ≈ 1e6 loses at
    /// most ~1e-10 of double precision; the closed forms are exact for this element.
    fn check_cantilever(b: &Beam3d, asy: f64, asz: f64) {
        let l = b.length();
        let t = rot6(b.axes());
        let (p, m, tq) = (1.0e4, 2.0e3, 5.0e2);
        let sy = if asy > 0.0 { p * l / (G * asy) } else { 0.0 };
        let sz = if asz > 0.0 { p * l / (G * asz) } else { 0.0 };
        let l2 = l * l;
        let l3 = l2 * l;
        let cases: [(usize, f64, [f64; 6]); 6] = [
            (0, p, [p * l / (E * A), 0.0, 0.0, 0.0, 0.0, 0.0]),
            (
                1,
                p,
                [
                    0.0,
                    p * l3 / (3.0 * E * IZ) + sy,
                    0.0,
                    0.0,
                    0.0,
                    p * l2 / (2.0 * E * IZ),
                ],
            ),
            (
                2,
                p,
                [
                    0.0,
                    0.0,
                    p * l3 / (3.0 * E * IY) + sz,
                    0.0,
                    -p * l2 / (2.0 * E * IY),
                    0.0,
                ],
            ),
            (3, tq, [0.0, 0.0, 0.0, tq * l / (G * J), 0.0, 0.0]),
            (
                4,
                m,
                [
                    0.0,
                    0.0,
                    -m * l2 / (2.0 * E * IY),
                    0.0,
                    m * l / (E * IY),
                    0.0,
                ],
            ),
            (
                5,
                m,
                [
                    0.0,
                    m * l2 / (2.0 * E * IZ),
                    0.0,
                    0.0,
                    0.0,
                    m * l / (E * IZ),
                ],
            ),
        ];
        for (dof, load, expect) in cases {
            let mut f_local = Vector6::zeros();
            f_local[dof] = load;
            let u = t * cantilever(b, t.transpose() * f_local);
            let et = expect[..3].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let er = expect[3..].iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..6 {
                let scale = if i < 3 {
                    et.max(er * l)
                } else {
                    er.max(et / l)
                };
                assert!(
                    (u[i] - expect[i]).abs() <= 1e-9 * scale,
                    "load on local DOF {dof}: u[{i}] = {:e}, closed form {:e}",
                    u[i],
                    expect[i]
                );
            }
        }
    }

    #[test]
    fn cantilever_along_x_matches_beam_theory() {
        check_cantilever(
            &beam([0.0; 3], [3.0, 0.0, 0.0], serde_json::json!({})),
            0.0,
            0.0,
        );
    }

    #[test]
    fn cantilever_arbitrarily_oriented_matches_beam_theory() {
        let b = beam(
            [1.0, -2.0, 0.5],
            [2.3, 0.4, 2.9],
            serde_json::json!({"orient": [0.3, -1.0, 0.7]}),
        );
        check_cantilever(&b, 0.0, 0.0);
        // Vertical beam with the default orientation.
        check_cantilever(
            &beam([0.0; 3], [0.0, 0.0, -2.5], serde_json::json!({})),
            0.0,
            0.0,
        );
    }

    #[test]
    fn timoshenko_cantilever_adds_shear_deflection() {
        // κ = 5/6 for a rectangle: As = κ·A. Short beam (L = 0.4 m) so shear matters.
        let (asy, asz) = (5.0 / 6.0 * A, 0.6 * A);
        let b = beam(
            [0.0, 0.0, 0.0],
            [0.2, 0.3, -0.1],
            serde_json::json!({"Asy": asy, "Asz": asz, "orient": [0.0, 0.0, 1.0]}),
        );
        check_cantilever(&b, asy, asz);
    }

    #[test]
    fn end_forces_of_a_cantilever() {
        // Statics of a cantilever clamped at I with tip force P along local y: the section
        // at the root carries Vy = P and Mz = P·L; an axial tip pull P gives N = P.
        let b = beam([0.5, 0.5, 0.0], [0.5, 3.5, 4.0], serde_json::json!({}));
        let t = rot6(b.axes());
        let (p, l) = (1.0e4, b.length());
        for (dof, want) in [
            (1usize, [0.0, p, 0.0, 0.0, 0.0, p * l]),
            (0, [p, 0.0, 0.0, 0.0, 0.0, 0.0]),
        ] {
            let mut fl = Vector6::zeros();
            fl[dof] = p;
            let uj = cantilever(&b, t.transpose() * fl);
            let mut disp = [0.0; 12];
            disp[6..].copy_from_slice(uj.as_slice());
            let mut e = b.clone();
            e.update(&TrialState {
                time: 0.0,
                dt: 0.0,
                disp: &disp,
                vel: &[0.0; 12],
                acc: &[0.0; 12],
            })
            .unwrap();
            let mut out = Vec::new();
            e.outputs(&mut out);
            assert_eq!(out.len(), e.output_names().len());
            for i in 0..6 {
                assert!(
                    (out[i] - want[i]).abs() <= 1e-8 * p * l,
                    "{i}: {} vs {}",
                    out[i],
                    want[i]
                );
            }
        }
    }

    fn skew_beams() -> Vec<Beam3d> {
        vec![
            beam(
                [1.0, -0.5, 0.3],
                [2.2, 0.7, 1.4],
                serde_json::json!({"rho": 7850.0, "Asy": 5e-3, "Asz": 4e-3, "orient": [0.0, 1.0, 1.0]}),
            ),
            beam(
                [1.0, -0.5, 0.3],
                [-0.2, 0.7, 1.4],
                serde_json::json!({"rho": 7850.0, "mass": "lumped"}),
            ),
        ]
    }

    /// Rigid translations and infinitesimal rigid rotations about any point,
    /// `u_n = t + θ × x_n`, `θ_n = θ`, leave every member unstrained, so `K·u = 0` up to
    /// rounding: the tolerance is 1e-12 of `max|K_ij|·max|u|` times the 12 terms summed.
    #[test]
    fn rigid_body_modes_give_no_force() {
        for b in skew_beams() {
            let k = b.stiffness_global();
            let kmax = k.amax();
            let x = [
                Vector3::new(1.0, -0.5, 0.3),
                b.axes().row(0).transpose() * b.length() + Vector3::new(1.0, -0.5, 0.3),
            ];
            for mode in 0..6 {
                let mut u = SVector::<f64, 12>::zeros();
                let mut v = Vector3::zeros();
                v[mode % 3] = 1.0;
                for n in 0..2 {
                    if mode < 3 {
                        u.fixed_rows_mut::<3>(6 * n).copy_from(&v);
                    } else {
                        let c = Vector3::new(0.7, 2.0, -1.0); // centre of rotation
                        u.fixed_rows_mut::<3>(6 * n)
                            .copy_from(&v.cross(&(x[n] - c)));
                        u.fixed_rows_mut::<3>(6 * n + 3).copy_from(&v);
                    }
                }
                let f = k * u;
                assert!(
                    f.amax() <= 12.0 * 1e-12 * kmax * u.amax(),
                    "mode {mode}: {f}"
                );
            }
        }
    }

    #[test]
    fn stiffness_and_mass_are_symmetric() {
        for b in skew_beams() {
            for m in [b.stiffness_global(), b.mass_global()] {
                assert!((m - m.transpose()).amax() <= 1e-14 * m.amax());
            }
        }
    }

    /// `tᵀ·M·t` for a unit rigid translation `t` is the kinetic-energy mass `ρAL` in every
    /// direction; for a unit rigid rotation about the beam axis it is `ρ·(Iy+Iz)·L`.
    /// Eigenvalues are ≥ 0 (to 1e-12 of the largest). Both mass types.
    #[test]
    fn mass_is_total_and_positive_semidefinite() {
        for b in skew_beams() {
            let m = b.mass_global();
            let total = 7850.0 * A * b.length();
            for d in [
                Vector3::x(),
                Vector3::y(),
                Vector3::z(),
                Vector3::new(0.3, -0.8, 0.52).normalize(),
            ] {
                let mut t = SVector::<f64, 12>::zeros();
                t.fixed_rows_mut::<3>(0).copy_from(&d);
                t.fixed_rows_mut::<3>(6).copy_from(&d);
                let q = (t.transpose() * m * t)[0];
                assert!((q - total).abs() <= 1e-12 * total, "{q} vs {total}");
            }
            let ax = b.axes().row(0).transpose();
            let mut t = SVector::<f64, 12>::zeros();
            t.fixed_rows_mut::<3>(3).copy_from(&ax);
            t.fixed_rows_mut::<3>(9).copy_from(&ax);
            let q = (t.transpose() * m * t)[0];
            let want = 7850.0 * (IY + IZ) * b.length();
            assert!((q - want).abs() <= 1e-12 * want);
            let eig = m.symmetric_eigenvalues();
            assert!(eig.min() >= -1e-12 * eig.max(), "{eig}");
            assert_eq!(b.properties().declared_mass, Some(total));
        }
    }

    /// `mass = "lumped_translational"` (OpenSees' `elasticBeamColumn` without `-cMass`):
    /// in global axes, for a skew beam, each node carries `ρAL/2·I₃` on its translations
    /// and nothing on its rotations, with no coupling between nodes or DOF kinds; the
    /// translational block equals that of `"lumped"`.
    #[test]
    fn lumped_translational_mass_has_no_rotary_inertia() {
        let (xi, xj) = ([1.0, -0.5, 0.3], [-0.2, 0.7, 1.4]);
        let t = beam(
            xi,
            xj,
            serde_json::json!({"rho": 7850.0, "mass": "lumped_translational"}),
        );
        let r = beam(xi, xj, serde_json::json!({"rho": 7850.0, "mass": "lumped"}));
        let half = 0.5 * 7850.0 * A * t.length();
        let (mt, mr) = (t.mass_global(), r.mass_global());
        for i in 0..12 {
            for j in 0..12 {
                let translation = i % 6 < 3;
                let want = if i == j && translation { half } else { 0.0 };
                assert!((mt[(i, j)] - want).abs() <= 1e-12 * half, "({i},{j})");
                if translation && j % 6 < 3 {
                    assert!((mt[(i, j)] - mr[(i, j)]).abs() <= 1e-12 * half);
                }
            }
        }
        // The lumped mass with rotary inertia does carry rotational mass: the two differ.
        assert!(mr[(4, 4)] + mr[(5, 5)] > 0.0);
    }

    /// 4-point Gauss–Legendre nodes and weights on [0, 1]: exact for polynomials of
    /// degree ≤ 7, hence for products of two cubics.
    fn gauss4() -> [(f64, f64); 4] {
        let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
        let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
        let wa = (18.0 + 30.0f64.sqrt()) / 36.0;
        let wb = (18.0 - 30.0f64.sqrt()) / 36.0;
        [(-b, wb), (-a, wa), (a, wa), (b, wb)].map(|(x, w)| (0.5 * (1.0 + x), 0.5 * w))
    }

    /// The closed-form bending blocks equal the integrals they are derived from:
    /// `∫ρA·N_i·N_j dx` (mass) and `∫EI·N_i''·N_j'' dx` (Euler–Bernoulli stiffness),
    /// evaluated by exact Gauss quadrature of [`hermite`] and [`hermite_dd`].
    #[test]
    fn bending_blocks_are_hermite_integrals() {
        let (rho, l) = (7850.0, 1.7);
        let sec = BeamSection {
            e: E,
            g: G,
            a: A,
            iy: IY,
            iz: IZ,
            j: J,
            asy: 0.0,
            asz: 0.0,
        };
        let m = local_mass(&sec, rho, l, BeamMass::Consistent);
        let k = local_stiffness(&sec, l);
        for r in 0..4 {
            for c in 0..4 {
                let (mut mi, mut ki) = (0.0, 0.0);
                for (xi, w) in gauss4() {
                    let (n, b) = (hermite(xi, l), hermite_dd(xi, l));
                    mi += w * l * rho * A * n[r] * n[c];
                    ki += w * l * E * IZ * b[r] * b[c];
                }
                assert!((m[(XY[r], XY[c])] - mi).abs() <= 1e-12 * m.amax());
                assert!((k[(XY[r], XY[c])] - ki).abs() <= 1e-12 * k.amax());
            }
        }
    }

    /// Hermite interpolation reproduces any cubic `w = a + bx + cx² + dx³` exactly from
    /// its end values and slopes, together with its first and second derivatives.
    #[test]
    fn hermite_reproduces_cubics() {
        let (a, b, c, d, l) = (0.3, -1.2, 0.8, 2.1, 1.5);
        let w = |x: f64| a + b * x + c * x * x + d * x * x * x;
        let w1 = |x: f64| b + 2.0 * c * x + 3.0 * d * x * x;
        let w2 = |x: f64| 2.0 * c + 6.0 * d * x;
        let q = [w(0.0), w1(0.0), w(l), w1(l)];
        for xi in [0.0, 0.13, 0.5, 0.77, 1.0] {
            let x = xi * l;
            let dot = |n: [f64; 4]| n.iter().zip(q).map(|(n, q)| n * q).sum::<f64>();
            assert!((dot(hermite(xi, l)) - w(x)).abs() < 1e-13);
            assert!((dot(hermite_d(xi, l)) - w1(x)).abs() < 1e-13);
            assert!((dot(hermite_dd(xi, l)) - w2(x)).abs() < 1e-12);
        }
    }

    #[test]
    fn local_axes_follow_the_conventions() {
        let (xi, xj) = (Vector3::new(1.0, 2.0, 3.0), Vector3::new(2.0, 4.0, 3.5));
        let o = Vector3::new(0.2, -0.3, 1.0);
        let r = local_axes(&xi, &xj, &o);
        assert!((r * r.transpose() - Matrix3::identity()).amax() < 1e-14);
        assert!((r.determinant() - 1.0).abs() < 1e-14);
        assert!((r.row(0).transpose() - (xj - xi).normalize()).amax() < 1e-15);
        assert!(
            r.row(2).transpose().dot(&o).abs() < 1e-14,
            "orient lies in local x-y"
        );
        assert!(
            r.row(1).transpose().dot(&o) > 0.0,
            "local y on the side of orient"
        );
        // Default: horizontal beam → local z = global Z, local y horizontal.
        let xh = Vector3::new(3.0, -1.0, 0.0);
        let rh = local_axes(&Vector3::zeros(), &xh, &default_orient(&xh.normalize()));
        assert!((rh.row(2).transpose() - Vector3::z()).amax() < 1e-15);
        // Vertical beam → local y = global Y.
        let rv = local_axes(
            &Vector3::zeros(),
            &Vector3::z(),
            &default_orient(&Vector3::z()),
        );
        assert!((rv.row(1).transpose() - Vector3::y()).amax() < 1e-15);
    }

    #[test]
    fn bad_input_is_refused_with_the_key_named() {
        let two = [[0.0; 3], [1.0, 0.0, 0.0]];
        let with = |k: &str, v: serde_json::Value| {
            let mut p = params(serde_json::json!({}));
            p.as_object_mut().unwrap().insert(k.into(), v);
            p
        };
        for key in ["E", "G", "A", "Iy", "Iz", "J"] {
            for v in [0.0, -1.0] {
                let e = build_err(&[1, 2], &two, with(key, v.into()));
                assert!(e.contains(&format!("`{key}`")), "{e}");
            }
        }
        for key in ["rho", "Asy", "Asz"] {
            let e = build_err(&[1, 2], &two, with(key, (-1.0).into()));
            assert!(e.contains(&format!("`{key}`")), "{e}");
        }
        let e = build_err(&[1, 2], &two, with("mass", "diagonal".into()));
        assert!(e.contains("`mass`"), "{e}");
        let e = build_err(
            &[1, 2, 3],
            &[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            params(serde_json::json!({})),
        );
        assert!(e.contains("`nodes`") && e.contains("3 ids"), "{e}");
        let e = build_err(&[1, 9], &two, params(serde_json::json!({})));
        assert!(e.contains("`nodes`") && e.contains("9"), "{e}");
        let e = build_err(
            &[1, 2],
            &[[1.0; 3], [1.0; 3]],
            params(serde_json::json!({})),
        );
        assert!(e.contains("zero-length"), "{e}");
        let e = build_err(
            &[1, 2],
            &two,
            with("orient", serde_json::json!([-2.0, 0.0, 0.0])),
        );
        assert!(e.contains("`orient`") && e.contains("parallel"), "{e}");
        let e = build_err(&[1, 2], &two, with("orient", serde_json::json!([0.0, 1.0])));
        assert!(e.contains("`orient`"), "{e}");
        let e = build_err(&[1, 2], &two, with("Ix", 1.0.into()));
        assert!(e.contains("`Ix`"), "{e}");
    }

    #[test]
    fn registered_with_samples() {
        let k = railfem_framework::registry::find("beam3d").expect("beam3d registered");
        assert!((k.params)().iter().any(|d| d.key == "orient"));
        let s = (k.samples)();
        assert_eq!(s.len(), 6);
        for x in &s {
            assert_eq!(x.element.ndof(), 12);
            assert_eq!(x.disp.len(), 12);
        }
    }
}

/// The conformance kit on the `beam3d` samples of every geometry (the large-rotation ones
/// included): tangent against finite differences with spins composed, finite rigid motion,
/// mass, energy.
#[cfg(test)]
mod conformance_tests {
    #[test]
    fn every_geometry_passes_the_kit() {
        let k = railfem_framework::registry::find("beam3d").expect("beam3d registered");
        let r = railfem_framework::conformance::check_kind(&k);
        let report = railfem_framework::conformance::Report { results: r };
        println!("{}", report.table());
        assert!(report.passed(), "{}", report.table());
    }
}
