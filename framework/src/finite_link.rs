//! Rigid links with finite rotations (`geometry = "nonlinear"` on a link or in
//! `[analysis]`): the slave moves with the master's current rotation,
//!
//! `u_s = u_m + (R(ψ_m) − I)·r`,  `ψ_s = ψ_m`,
//!
//! `r` the slave's offset from its master in the master's axes at t = 0 and `ψ_m` the
//! master's total rotation vector ([`crate::rotation`]). Linear links stay in the DOF map
//! (a constant transformation); nonlinear ones are resolved here, at model build, by
//! wrapping every element that touches a nonlinear slave in a [`LinkedElement`].
//!
//! **The adapter.** Its connectivity is the element's nodes with every slave replaced by
//! its root master (chains of nonlinear links are followed to the first node that is not a
//! nonlinear slave, composing offsets; a cycle is refused). At each trial state it maps the
//! masters' states to the slaves' (position above; velocity `v_m + ω_m × R·r`; acceleration
//! `a_m + α_m × R·r + ω_m × (ω_m × R·r)`; rotations, angular velocities and accelerations
//! equal the master's), calls the inner element and returns `Tᵀ·f` and `Tᵀ·K·T + K_σ`.
//! `T` is the current linearisation, `δu_s = δu_m − [R·r]×·δθ_m`, `δθ_s = δθ_m` with `δθ`
//! the master's spatial spin; the inner element's rotational entries are taken as conjugate
//! to that spin (exact for elements that declare finite rotations; for a small-rotation
//! element the difference is of the order of its own small-rotation error). The geometric
//! term comes from the slave's force turning with the arm: the moment `(R·r) × f_s` on the
//! master varies as `[f_s]×·[R·r]×·δθ_m`, added to the master's rotational block.
//!
//! **Limits.** The mass and damping of an element on a slave are transferred as
//! `Tᵀ·M·T` at the current state (not constant); the velocity-dependent inertia of a mass
//! at an offset (`m·ω × (ω × r)`) is left out of the mass matrix, which is what the
//! driver multiplies by the accelerations. Only whole-body links (all six DOFs) can be
//! nonlinear, and elements that re-pick their nodes (the moving axle) cannot sit on a
//! nonlinear slave: both are refused at build with the fix. Nodal loads, supports and
//! recorders act on masters, not on nonlinear slaves (refused likewise).

use crate::dof::DofSet;
use crate::element::{Element, ElementError, ElementProperties, NodeDofs, StepContext, TrialState};
use crate::rotation::{exp, skew};
use nalgebra::{DMatrix, Matrix3, Vector3};

/// How an inner element's node follows the adapter's DOFs.
#[derive(Debug, Clone)]
struct InnerNode {
    /// The DOFs the inner element uses at this node.
    dofs: DofSet,
    /// Offset of this node's first entry in the adapter's vectors (its own node, or the
    /// root master, which has all six DOFs).
    at: usize,
    /// Which DOFs the adapter node has (to find entries).
    adapter_dofs: DofSet,
    /// Offset from the root master in its axes (m), for a slave.
    arm: Option<Vector3<f64>>,
}

/// An element whose nodes include slaves of nonlinear rigid links. See the module docs.
pub struct LinkedElement {
    inner: Box<dyn Element>,
    conn: Vec<NodeDofs>,
    map: Vec<InnerNode>,
    ndof: usize,
    inner_ndof: usize,
    /// `T` at the trial state (inner ndof × adapter ndof).
    t: DMatrix<f64>,
    force: Vec<f64>,
    tangent: DMatrix<f64>,
    /// Forces on the slaves at the trial state (for the geometric term) with their arms.
    scratch: Vec<f64>,
}

/// Position of DOF `d` in a node's entry block with DOF set `set` (None if absent).
fn slot(set: DofSet, d: usize) -> Option<usize> {
    if set.bits() & (1 << d) == 0 {
        return None;
    }
    Some(set.iter().take_while(|x| x.index() < d).count())
}

impl LinkedElement {
    /// Wraps `inner`. `root(node)` gives, for a nonlinear slave, its root master and the
    /// offset from it in the master's axes; `None` for any other node.
    pub fn new(
        inner: Box<dyn Element>,
        root: &dyn Fn(usize) -> Option<(usize, Vector3<f64>)>,
    ) -> LinkedElement {
        // Adapter nodes: each inner node or its root, with the union of the DOFs needed.
        let mut conn: Vec<NodeDofs> = Vec::new();
        let add = |node: usize, dofs: DofSet, conn: &mut Vec<NodeDofs>| {
            if let Some(n) = conn.iter_mut().find(|n| n.node == node) {
                n.dofs = n.dofs.union(dofs);
            } else {
                conn.push(NodeDofs { node, dofs });
            }
        };
        for nd in inner.connectivity() {
            match root(nd.node) {
                Some((m, _)) => add(m, DofSet::ALL, &mut conn),
                None => add(nd.node, nd.dofs, &mut conn),
            }
        }
        let mut starts = Vec::with_capacity(conn.len());
        let mut k = 0;
        for n in &conn {
            starts.push(k);
            k += n.dofs.count();
        }
        let map: Vec<InnerNode> = inner
            .connectivity()
            .iter()
            .map(|nd| {
                let (node, arm) = match root(nd.node) {
                    Some((m, r)) => (m, Some(r)),
                    None => (nd.node, None),
                };
                let i = conn.iter().position(|n| n.node == node).unwrap_or(0);
                InnerNode {
                    dofs: nd.dofs,
                    at: starts[i],
                    adapter_dofs: conn[i].dofs,
                    arm,
                }
            })
            .collect();
        let inner_ndof = inner.ndof();
        let mut e = LinkedElement {
            t: DMatrix::zeros(inner_ndof, k),
            tangent: DMatrix::zeros(k, k),
            force: vec![0.0; k],
            scratch: Vec::new(),
            inner,
            conn,
            map,
            ndof: k,
            inner_ndof,
        };
        e.linearisation(&vec![0.0; k]);
        e
    }

    /// The wrapped element.
    pub fn inner(&self) -> &dyn Element {
        &*self.inner
    }

    /// The six entries (u, θ) of the adapter node block starting at `at` from `x`
    /// (zeros where the node has no DOF).
    fn six(x: &[f64], at: usize, set: DofSet) -> [f64; 6] {
        let mut out = [0.0; 6];
        if x.is_empty() {
            return out;
        }
        for d in 0..6 {
            if let Some(s) = slot(set, d) {
                out[d] = x[at + s];
            }
        }
        out
    }

    /// Maps adapter displacement, velocity and acceleration to the inner element's.
    fn to_inner(&self, disp: &[f64], vel: &[f64], acc: &[f64]) -> [Vec<f64>; 3] {
        let mut out = [
            vec![0.0; self.inner_ndof],
            vec![0.0; if vel.is_empty() { 0 } else { self.inner_ndof }],
            vec![0.0; if acc.is_empty() { 0 } else { self.inner_ndof }],
        ];
        let mut k = 0;
        for n in &self.map {
            let u = Self::six(disp, n.at, n.adapter_dofs);
            let v = Self::six(vel, n.at, n.adapter_dofs);
            let a = Self::six(acc, n.at, n.adapter_dofs);
            let (mut u6, mut v6, mut a6) = (u, v, a);
            if let Some(r) = n.arm {
                let psi = Vector3::new(u[3], u[4], u[5]);
                let rr = exp(&psi) * r;
                let w = Vector3::new(v[3], v[4], v[5]);
                let al = Vector3::new(a[3], a[4], a[5]);
                let du = rr - r;
                let dv = w.cross(&rr);
                let da = al.cross(&rr) + w.cross(&dv);
                for i in 0..3 {
                    u6[i] += du[i];
                    v6[i] += dv[i];
                    a6[i] += da[i];
                }
            }
            for d in n.dofs.iter() {
                let i = d.index();
                out[0][k] = u6[i];
                if !out[1].is_empty() {
                    out[1][k] = v6[i];
                }
                if !out[2].is_empty() {
                    out[2][k] = a6[i];
                }
                k += 1;
            }
        }
        out
    }

    /// `T` at displacement `disp`.
    fn linearisation(&mut self, disp: &[f64]) {
        self.t.fill(0.0);
        let mut k = 0;
        for n in &self.map {
            let arm = n.arm.map(|r| {
                let u = Self::six(disp, n.at, n.adapter_dofs);
                exp(&Vector3::new(u[3], u[4], u[5])) * r
            });
            let sk = arm.map_or(Matrix3::zeros(), |a| skew(&a));
            for d in n.dofs.iter() {
                let i = d.index();
                if let Some(s) = slot(n.adapter_dofs, i) {
                    self.t[(k, n.at + s)] = 1.0;
                }
                if i < 3 && arm.is_some() {
                    // δu_s = δu_m − [R·r]×·δθ_m (the master has all six DOFs).
                    for j in 0..3 {
                        self.t[(k, n.at + 3 + j)] = -sk[(i, j)];
                    }
                }
                k += 1;
            }
        }
    }
}

impl Element for LinkedElement {
    fn kind(&self) -> &str {
        self.inner.kind()
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        let p = self.inner.properties();
        ElementProperties {
            linear: false,
            constant_mass: !p.has_mass,
            constant_damping: !p.has_damping,
            symmetric: false,
            finite_rotations: true,
            ..p
        }
    }

    fn ndof(&self) -> usize {
        self.ndof
    }

    fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
        self.inner.advance(ctx)
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        if trial.disp.len() != self.ndof {
            return Err(ElementError::Invalid(format!(
                "trial displacement has {} entries, the linked element has {} DOFs",
                trial.disp.len(),
                self.ndof
            )));
        }
        let [u, v, a] = self.to_inner(trial.disp, trial.vel, trial.acc);
        self.inner.update(&TrialState {
            time: trial.time,
            dt: trial.dt,
            disp: &u,
            vel: &v,
            acc: &a,
        })?;
        self.linearisation(trial.disp);
        self.scratch.resize(self.inner_ndof, 0.0);
        self.inner.resisting_force(&mut self.scratch);
        let f = self.t.transpose() * nalgebra::DVector::from_column_slice(&self.scratch);
        self.force.copy_from_slice(f.as_slice());
        let mut ki = DMatrix::zeros(self.inner_ndof, self.inner_ndof);
        self.inner.tangent_stiffness(&mut ki);
        self.tangent = self.t.transpose() * ki * &self.t;
        // Geometric term: [f_s]×·[R·r]× in the master's rotational block, per slave.
        let mut k = 0;
        for n in &self.map {
            let count = n.dofs.count();
            if let Some(r) = n.arm {
                let full = Self::six(trial.disp, n.at, n.adapter_dofs);
                let arm = exp(&Vector3::new(full[3], full[4], full[5])) * r;
                let mut fs = Vector3::zeros();
                for (j, d) in n.dofs.iter().enumerate() {
                    if d.index() < 3 {
                        fs[d.index()] = self.scratch[k + j];
                    }
                }
                let g = skew(&fs) * skew(&arm);
                for i in 0..3 {
                    for j in 0..3 {
                        self.tangent[(n.at + 3 + i, n.at + 3 + j)] += g[(i, j)];
                    }
                }
            }
            k += count;
        }
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.copy_from_slice(&self.force);
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from(&self.tangent);
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        let mut mi = DMatrix::zeros(self.inner_ndof, self.inner_ndof);
        self.inner.mass(&mut mi);
        m.copy_from(&(self.t.transpose() * mi * &self.t));
    }

    fn damping(&self, c: &mut DMatrix<f64>) {
        let mut ci = DMatrix::zeros(self.inner_ndof, self.inner_ndof);
        self.inner.damping(&mut ci);
        c.copy_from(&(self.t.transpose() * ci * &self.t));
    }

    fn commit(&mut self) {
        self.inner.commit();
    }

    fn revert(&mut self) {
        self.inner.revert();
    }

    fn output_names(&self) -> Vec<String> {
        self.inner.output_names()
    }

    fn output_units(&self) -> Vec<String> {
        self.inner.output_units()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        self.inner.outputs(out);
    }

    fn parameters(&self) -> serde_json::Value {
        self.inner.parameters()
    }

    fn dissipated_energy(&self) -> f64 {
        self.inner.dissipated_energy()
    }

    fn dissipation_kind(&self) -> crate::element::DissipationKind {
        self.inner.dissipation_kind()
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        self.inner.as_any()
    }
}

/// A nonlinear slave's root master and its offset in the master's axes (m); `None` for
/// any other node.
pub type Root = Option<(usize, Vector3<f64>)>;

/// The root master of every nonlinear slave and its offset in the master's axes: follows
/// chains of nonlinear links. `links` are `(master, slave, origin)` of the nonlinear links,
/// `offset(master, slave)` the slave's offset from the master in the master's axes.
/// A cycle is an error naming the first of its links in `links` order and the nodes of the
/// cycle.
pub fn resolve_roots(
    nodes: usize,
    links: &[(usize, usize, String)],
    offset: &dyn Fn(usize, usize) -> Vector3<f64>,
    id: &dyn Fn(usize) -> u64,
) -> Result<Vec<Root>, crate::FemError> {
    let mut master_of: Vec<Option<usize>> = vec![None; nodes];
    for (m, s, _) in links {
        master_of[*s] = Some(*m);
    }
    let mut roots = vec![None; nodes];
    for (_, s, origin) in links {
        let mut chain = vec![*s];
        let mut at = *s;
        while let Some(m) = master_of[at] {
            if chain.contains(&m) {
                chain.push(m);
                let path: Vec<String> = chain.iter().map(|&n| id(n).to_string()).collect();
                return Err(crate::FemError::input(
                    origin,
                    format!(
                        "geometry = \"nonlinear\" rigid links form a cycle (slave -> master: {}); a master cannot follow its own slave: remove one of these links",
                        path.join(" -> ")
                    ),
                ));
            }
            chain.push(m);
            at = m;
        }
        roots[*s] = Some((at, offset(at, *s)));
    }
    Ok(roots)
}

/// Resolves the nonlinear links `(master, slave, origin)` of `model`: wraps every element
/// that touches a nonlinear slave in a [`LinkedElement`] and refuses what cannot act on
/// such a slave (a support, a nodal load, a node recorder, a moving element, a linear link
/// chained to it). `loads` and `recorders` are the model's specs, for the messages.
pub fn apply(
    model: &mut crate::Model,
    links: &[(usize, usize, String)],
    loads: &[crate::loads::LoadSpec],
    recorders: &[crate::recorder::RecorderSpec],
) -> Result<(), crate::FemError> {
    let kin = model.kinematics(0.0);
    let ids: Vec<u64> = model.nodes.iter().map(|n| n.id).collect();
    let offset =
        |m: usize, s: usize| kin[m].frame.transpose() * (kin[s].position - kin[m].position);
    let roots = resolve_roots(model.nodes.len(), links, &offset, &|n| ids[n])?;
    let fix = "act on its master instead";
    let slave_origin = |n: usize| {
        links
            .iter()
            .find(|l| l.1 == n)
            .map_or(String::new(), |l| l.2.clone())
    };
    for (n, r) in roots.iter().enumerate() {
        if r.is_none() {
            continue;
        }
        if !model.nodes[n].fixed.is_empty() {
            return Err(crate::FemError::input(
                slave_origin(n),
                format!("node {} is the slave of a geometry = \"nonlinear\" link and also has supports; support the master instead", ids[n]),
            ));
        }
        if model.links.iter().any(|l| l.master == n || l.slave == n) {
            return Err(crate::FemError::input(
                slave_origin(n),
                format!("node {} is the slave of a geometry = \"nonlinear\" link and also in a linear link; give the links of one rigid body one geometry", ids[n]),
            ));
        }
    }
    for (i, l) in loads.iter().enumerate() {
        if let crate::loads::LoadSpec::Nodal { node, .. } = l {
            if let Some(&ni) = model.node_index.get(node) {
                if roots[ni].is_some() {
                    return Err(crate::FemError::input(
                        format!("{}: load[{i}]", model.origin),
                        format!("node {node} is the slave of a geometry = \"nonlinear\" link; a nodal load must {fix}"),
                    ));
                }
            }
        }
    }
    for (i, r) in recorders.iter().enumerate() {
        if let crate::recorder::RecorderSpec::Node { node, nodes, .. } = r {
            for id in node.iter().chain(nodes) {
                if model
                    .node_index
                    .get(id)
                    .is_some_and(|&ni| roots[ni].is_some())
                {
                    return Err(crate::FemError::input(
                        format!("{}: recorder[{i}]", model.origin),
                        format!("node {id} is the slave of a geometry = \"nonlinear\" link; a node recorder must {fix}"),
                    ));
                }
            }
        }
    }
    let root = |n: usize| roots[n];
    for entry in model.elements.iter_mut() {
        let touches = entry
            .element
            .connectivity()
            .iter()
            .any(|nd| roots[nd.node].is_some());
        if !touches {
            continue;
        }
        if entry.element.properties().connectivity_may_change {
            return Err(crate::FemError::input(
                &entry.origin,
                "an element that re-picks its nodes (a moving element) cannot sit on the slave of a geometry = \"nonlinear\" link; attach it to the master",
            ));
        }
        let inner = std::mem::replace(&mut entry.element, Box::new(Placeholder));
        entry.element = Box::new(LinkedElement::new(inner, &root));
    }
    Ok(())
}

/// Stands in for an element while it is being moved into its adapter.
struct Placeholder;

impl Element for Placeholder {
    fn kind(&self) -> &str {
        "placeholder"
    }
    fn connectivity(&self) -> &[NodeDofs] {
        &[]
    }
    fn properties(&self) -> ElementProperties {
        ElementProperties::default()
    }
    fn update(&mut self, _trial: &TrialState) -> Result<(), ElementError> {
        Ok(())
    }
    fn resisting_force(&self, _f: &mut [f64]) {}
    fn tangent_stiffness(&self, _k: &mut DMatrix<f64>) {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::compose;

    /// A grounded spring on the three translations of one node, `f = K·u`.
    struct Anchor {
        conn: Vec<NodeDofs>,
        k: Matrix3<f64>,
        u: Vector3<f64>,
    }

    impl Element for Anchor {
        fn kind(&self) -> &str {
            "anchor"
        }
        fn connectivity(&self) -> &[NodeDofs] {
            &self.conn
        }
        fn properties(&self) -> ElementProperties {
            ElementProperties::default()
        }
        fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
            self.u = Vector3::new(t.disp[0], t.disp[1], t.disp[2]);
            Ok(())
        }
        fn resisting_force(&self, f: &mut [f64]) {
            f.copy_from_slice((self.k * self.u).as_slice());
        }
        fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
            k.copy_from_slice(self.k.as_slice());
        }
    }

    fn linked() -> LinkedElement {
        let k = Matrix3::new(3e6, 1e5, 0.0, 1e5, 2e6, -2e5, 0.0, -2e5, 5e6);
        let anchor = Anchor {
            conn: vec![NodeDofs::translations(1)],
            k,
            u: Vector3::zeros(),
        };
        let r = Vector3::new(1.2, -0.4, 0.7);
        LinkedElement::new(Box::new(anchor), &|n| (n == 1).then_some((0, r)))
    }

    fn evaluate(e: &mut LinkedElement, u: &[f64]) -> Vec<f64> {
        e.update(&TrialState {
            time: 0.0,
            dt: 0.0,
            disp: u,
            vel: &[],
            acc: &[],
        })
        .expect("update");
        let mut f = vec![0.0; 6];
        e.resisting_force(&mut f);
        f
    }

    /// The slave sits at `x_m + u_m + R·r`, and the adapter's tangent (material part plus
    /// the geometric term of the slave force turning with the arm) equals central
    /// differences in which the master's rotation is moved by composed spins, at a rotation
    /// of 0.76 rad.
    #[test]
    fn tangent_matches_spin_differences_at_a_finite_rotation() {
        let mut e = linked();
        assert_eq!(e.connectivity()[0].node, 0);
        let u = [0.02, -0.01, 0.03, 0.3, -0.5, 0.4];
        evaluate(&mut e, &u);
        let mut k = DMatrix::zeros(6, 6);
        e.tangent_stiffness(&mut k);
        let h = 1e-6;
        let mut worst = 0.0f64;
        for j in 0..6 {
            let moved = |s: f64| {
                let mut w = u;
                if j < 3 {
                    w[j] += s;
                } else {
                    let psi = Vector3::new(u[3], u[4], u[5]);
                    let c = compose(&psi, &Vector3::ith(j - 3, s));
                    w[3..].copy_from_slice(c.as_slice());
                }
                w
            };
            let fp = evaluate(&mut e, &moved(h));
            let fm = evaluate(&mut e, &moved(-h));
            for i in 0..6 {
                worst = worst.max(((fp[i] - fm[i]) / (2.0 * h) - k[(i, j)]).abs());
            }
        }
        assert!(worst < 1e-6 * k.amax(), "{worst:e} vs {:e}", k.amax());
        // The slave's displacement is (R − I)·r + u_m.
        let r = Vector3::new(1.2, -0.4, 0.7);
        let [us, _, _] = e.to_inner(&u, &[], &[]);
        let want = exp(&Vector3::new(0.3, -0.5, 0.4)) * r - r + Vector3::new(0.02, -0.01, 0.03);
        assert!((Vector3::new(us[0], us[1], us[2]) - want).norm() < 1e-15);
    }

    /// Chains are followed to the root with the offset of the slave from it; a cycle is
    /// refused naming its first link and its nodes.
    #[test]
    fn chains_and_cycles() {
        let pos = [
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 2.0, 0.0),
        ];
        let off = |m: usize, s: usize| pos[s] - pos[m];
        let links = vec![(0, 1, "a".to_string()), (1, 2, "b".to_string())];
        let roots = resolve_roots(3, &links, &off, &|n| n as u64 + 10).expect("chain");
        assert_eq!(roots[2], Some((0, Vector3::new(1.0, 2.0, 0.0))));
        assert_eq!(roots[0], None);
        let mut cyc = links.clone();
        cyc.push((2, 0, "file.toml: link[2]".to_string()));
        let e = resolve_roots(3, &cyc, &off, &|n| n as u64 + 10).unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with("a:") && m.contains("11 -> 10 -> 12 -> 11") && m.contains("remove"),
            "{m}"
        );
    }
}
