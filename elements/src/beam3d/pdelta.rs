//! `beam3d` with `geometry = "pdelta"`: the linear beam plus the P-Δ effect, as OpenSees'
//! `geomTransf PDelta` does it: small rotations, and the axial force `N` of the linear
//! element acting on the chord's transverse drift.
//!
//! In local axes (`u1 v1 w1 … u2 v2 w2 …`, [`super::local_axes`]), with
//! `N = EA/L·(u₂ − u₁)` (tension positive), `Δv = v₂ − v₁`, `Δw = w₂ − w₁`, the resisting
//! force is the linear one plus
//!
//! ```text
//! f_v1 = −N·Δv/L,  f_v2 = +N·Δv/L,   f_w1 = −N·Δw/L,  f_w2 = +N·Δw/L,
//! ```
//!
//! the end shears that keep a chord turned by `Δ/L` in equilibrium under `N` (a compressed
//! column's overturning moment `P·Δ`). Nothing else changes: rotations, torsion and
//! bending are linear and the rotational DOFs add (this geometry does not declare finite
//! rotations); the `P-δ` effect along the member (the curvature's own amplification) is
//! not included, so a column needs several elements per buckling half-wave.
//!
//! Tangent: OpenSees adds the string stiffness `N/L·[[1,−1],[−1,1]]` on `(v₁, v₂)` and
//! `(w₁, w₂)` with `N` frozen. We add it too and, in addition, the term that comes from `N`
//! itself changing, `∂f_v/∂u = ∓(Δv/L)·EA/L`, so the tangent is the exact derivative of the
//! same resisting force (Newton converges quadratically; the converged answer is the same as
//! OpenSees'). That term makes the tangent unsymmetric.

use super::{to_global, to_local_vec, Beam3d, Mat12};
use nalgebra::{DMatrix, SVector};
use railfem_framework::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
use railfem_framework::serde_json;

/// The P-Δ beam. Build it through `beam3d` with `geometry = "pdelta"`.
#[derive(Debug, Clone)]
pub struct Beam3dPDelta {
    linear: Beam3d,
    /// The linear beam's `K` in global axes, kept: [`Self::evaluate`] adds to it at every
    /// iteration and the linear beam forms it on demand.
    k_linear: Mat12,
    ea: f64,
    u: SVector<f64, 12>,
    f: SVector<f64, 12>,
    k: Mat12,
}

impl Beam3dPDelta {
    /// The P-Δ version of a validated linear beam.
    pub(super) fn new(linear: Beam3d) -> Self {
        let ea = linear.params.E * linear.params.A;
        let mut e = Beam3dPDelta {
            k_linear: linear.stiffness_global(),
            linear,
            ea,
            u: SVector::zeros(),
            f: SVector::zeros(),
            k: Mat12::zeros(),
        };
        e.evaluate();
        e
    }

    /// Axial force at the trial state (N, tension positive).
    pub fn axial_force(&self) -> f64 {
        let ul = to_local_vec(&self.u, self.linear.axes());
        self.ea / self.linear.length() * (ul[6] - ul[0])
    }

    fn evaluate(&mut self) {
        let l = self.linear.length();
        let ul = to_local_vec(&self.u, self.linear.axes());
        let n = self.axial_force();
        let mut g = SVector::<f64, 12>::zeros();
        let mut kg = Mat12::zeros();
        // Transverse pairs (v₁, v₂) and (w₁, w₂).
        for (a, b) in [(1, 7), (2, 8)] {
            let drift = ul[b] - ul[a];
            g[a] = -n * drift / l;
            g[b] = n * drift / l;
            let s = n / l;
            kg[(a, a)] += s;
            kg[(b, b)] += s;
            kg[(a, b)] -= s;
            kg[(b, a)] -= s;
            // ∂N/∂u₁ = −EA/L, ∂N/∂u₂ = EA/L.
            let c = drift / l * self.ea / l;
            kg[(a, 0)] += c;
            kg[(a, 6)] -= c;
            kg[(b, 0)] -= c;
            kg[(b, 6)] += c;
        }
        let mut t = Mat12::zeros();
        for blk in 0..4 {
            t.fixed_view_mut::<3, 3>(3 * blk, 3 * blk)
                .copy_from(self.linear.axes());
        }
        self.f = self.k_linear * self.u + t.transpose() * g;
        self.k = self.k_linear + to_global(&kg, self.linear.axes());
    }
}

impl Element for Beam3dPDelta {
    fn kind(&self) -> &str {
        "beam3d"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        self.linear.connectivity()
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: false,
            symmetric: false,
            ..self.linear.properties()
        }
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        self.linear.update(trial)?;
        self.u = SVector::from_column_slice(trial.disp);
        self.evaluate();
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.copy_from_slice(self.f.as_slice());
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from(&self.k);
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        self.linear.mass(m);
    }

    fn output_names(&self) -> Vec<String> {
        self.linear.output_names()
    }

    fn output_units(&self) -> Vec<String> {
        self.linear.output_units()
    }

    /// The linear beam's end-I resultants (the P-Δ shears are not included).
    fn outputs(&self, out: &mut Vec<f64>) {
        self.linear.outputs(out);
    }

    fn parameters(&self) -> serde_json::Value {
        self.linear.parameters()
    }
}
