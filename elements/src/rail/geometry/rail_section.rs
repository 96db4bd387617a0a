//! The section and material of a straight member of the track and its structure, in the
//! six constants a 3D beam needs (E, G, A, two second moments, J) and a density: the rail
//! (60E1 here) and, beside the bridge generator, the slab, girder and pier sections.

use serde::{Deserialize, Serialize};

/// Section and material of a rail (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RailSection {
    /// Young's modulus (Pa).
    #[serde(rename = "E")]
    pub e: f64,
    /// Shear modulus (Pa).
    #[serde(rename = "G")]
    pub g: f64,
    /// Area (m²).
    #[serde(rename = "A")]
    pub a: f64,
    /// Second moment for vertical bending (m⁴).
    pub i_vertical: f64,
    /// Second moment for lateral bending (m⁴).
    pub i_lateral: f64,
    /// Torsion constant (m⁴).
    #[serde(rename = "J")]
    pub j: f64,
    /// Density (kg/m³).
    pub rho: f64,
}

impl RailSection {
    /// 60E1 (UIC60): E = 2.1e11 Pa, A = 7.686e-3 m², I_vertical = 3.038e-5 m⁴,
    /// I_lateral = 5.123e-6 m⁴, 60.21 kg/m (ρ = 60.21/A), G = 8.1e10 Pa; J = 2.0e-6 m⁴
    /// is an estimate of the Saint-Venant constant (not in the spec).
    pub fn uic60() -> Self {
        RailSection {
            e: 2.1e11,
            g: 8.1e10,
            a: 7.686e-3,
            i_vertical: 3.038e-5,
            i_lateral: 5.123e-6,
            j: 2.0e-6,
            rho: 60.21 / 7.686e-3,
        }
    }
}
