//! Equation numbering: which nodal DOFs are unknowns, and how constrained DOFs follow them.
//!
//! Each nodal DOF is one of: *free* (it has an equation), *fixed* (held at zero), *slave*
//! (a linear combination of other DOFs' equations through a rigid link) or *inactive* (no
//! element uses it; it gets no equation, so a node used only in translations — the wheel
//! node B — does not leave singular rotations behind). The map is stored flat, CSR-like:
//! for nodal DOF `6·node + d` the equations and coefficients `u = Σ c_k·q_{eq_k}`.
//!
//! Rigid links are eliminated by transformation: `u_s = u_m + θ_m × r`, `θ_s = θ_m`, with
//! `r` the offset from master to slave in the nodes' axes (a slave shares its master's
//! frame). A master that is itself a slave is resolved recursively; a cycle is an error.
//!
//! **Finite-rotation nodes.** A node is one when an attached element declares
//! [`crate::ElementProperties::finite_rotations`] or someone asked for it
//! ([`Model::mark_finite_rotation`]); a slave that is one makes its master one too. Its
//! rotational entries hold the total rotation vector ψ ([`crate::rotation`]) and the map
//! lists the equation triples `(rx, ry, rz)` the solvers must update by composition
//! ([`DofMap::add_correction`], [`DofMap::increment`]). Composition mixes the three
//! components, so such a node must have all three rotations free, all three fixed (or
//! unused, or following a master), or exactly one free (rotation about one fixed nodal
//! axis, where composition is addition); two free and one fixed is refused.

use crate::dof::{Dof, DofSet};
use crate::element::NodeKinematics;
use crate::error::FemError;
use crate::model::Model;
use crate::rotation;
use nalgebra::Vector3;

/// Equation numbering with constraints.
#[derive(Debug, Clone)]
pub struct DofMap {
    /// Number of equations (unknowns).
    pub neq: usize,
    start: Vec<u32>,
    eqs: Vec<u32>,
    coefs: Vec<f64>,
    /// For each equation, the nodal DOF (node·6 + d) it belongs to.
    pub eq_dof: Vec<usize>,
    /// DOFs that have an equation or follow one, per node.
    pub active: Vec<DofSet>,
    /// Whether each node is a finite-rotation node.
    finite: Vec<bool>,
    /// Equations `(rx, ry, rz)` of free finite-rotation triples.
    triples: Vec<[u32; 3]>,
}

impl DofMap {
    /// Numbers the equations of `model` given node kinematics at t = 0 (for link offsets).
    pub fn new(model: &Model, kin: &[NodeKinematics]) -> Result<DofMap, FemError> {
        let nn = model.nodes.len();
        // Which DOFs do elements use?
        let mut used = vec![DofSet::NONE; nn];
        for e in &model.elements {
            for nd in e.element.connectivity() {
                used[nd.node] = used[nd.node].union(nd.dofs);
            }
        }
        // Slaves' used DOFs make their masters' DOFs used (translations need rotations).
        let mut slave_of: Vec<Option<(usize, DofSet)>> = vec![None; nn];
        for l in &model.links {
            if let Some((m, _)) = slave_of[l.slave] {
                if m != l.master {
                    return Err(FemError::input(
                        format!("{}: link -> {}", model.origin, model.nodes[l.slave].id),
                        "a node can be the slave of only one master",
                    ));
                }
            }
            slave_of[l.slave] = Some((l.master, l.dofs));
        }
        // Propagate usage along chains (bounded by the number of links).
        for _ in 0..=model.links.len() {
            let mut changed = false;
            for l in &model.links {
                let u = used[l.slave];
                let constrained_used = DofSet::from_bits(u.bits() & l.dofs.bits());
                if constrained_used.is_empty() {
                    continue;
                }
                let mut need = DofSet::NONE;
                for d in constrained_used.iter() {
                    need = need.with(d);
                    if d.index() < 3 {
                        need = need.union(DofSet::ROTATIONS);
                    }
                }
                let nu = used[l.master].union(need);
                if nu != used[l.master] {
                    used[l.master] = nu;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        // Number the free DOFs.
        let mut eq_of = vec![u32::MAX; nn * 6];
        let mut eq_dof = Vec::new();
        for (i, n) in model.nodes.iter().enumerate() {
            let constrained = slave_of[i].map(|(_, d)| d).unwrap_or(DofSet::NONE);
            for d in used[i].iter() {
                if n.fixed.contains(d) || constrained.contains(d) {
                    continue;
                }
                eq_of[i * 6 + d.index()] = eq_dof.len() as u32;
                eq_dof.push(i * 6 + d.index());
            }
        }
        // Terms of every DOF, resolving slaves recursively.
        let mut terms: Vec<Option<Vec<(u32, f64)>>> = vec![None; nn * 6];
        let mut visiting = vec![false; nn];
        fn resolve(
            node: usize,
            model: &Model,
            kin: &[NodeKinematics],
            slave_of: &[Option<(usize, DofSet)>],
            eq_of: &[u32],
            terms: &mut Vec<Option<Vec<(u32, f64)>>>,
            visiting: &mut Vec<bool>,
        ) -> Result<(), FemError> {
            if terms[node * 6].is_some() {
                return Ok(());
            }
            if visiting[node] {
                return Err(FemError::input(
                    format!("{}: node {}", model.origin, model.nodes[node].id),
                    "rigid links form a cycle; a master cannot follow its own slave",
                ));
            }
            visiting[node] = true;
            let mut out: Vec<Vec<(u32, f64)>> = vec![Vec::new(); 6];
            let link = slave_of[node];
            if let Some((m, _)) = link {
                resolve(m, model, kin, slave_of, eq_of, terms, visiting)?;
            }
            for (d, o) in out.iter_mut().enumerate() {
                let k = node * 6 + d;
                let constrained = link.map(|(_, s)| s.bits() & (1 << d) != 0).unwrap_or(false);
                if !constrained {
                    if eq_of[k] != u32::MAX {
                        o.push((eq_of[k], 1.0));
                    }
                    continue;
                }
                let (m, _) = link.expect("constrained implies a link");
                // Offset from master to slave in the (shared) nodal axes.
                let r = kin[m].frame.transpose() * (kin[node].position - kin[m].position);
                let mt = |dd: usize| terms[m * 6 + dd].clone().unwrap_or_default();
                let add = |src: Vec<(u32, f64)>, c: f64, o: &mut Vec<(u32, f64)>| {
                    if c == 0.0 {
                        return;
                    }
                    for (e, v) in src {
                        o.push((e, v * c));
                    }
                };
                add(mt(d), 1.0, o);
                // (θ × r): x = θy·rz − θz·ry, y = θz·rx − θx·rz, z = θx·ry − θy·rx.
                match d {
                    0 => {
                        add(mt(4), r.z, o);
                        add(mt(5), -r.y, o);
                    }
                    1 => {
                        add(mt(5), r.x, o);
                        add(mt(3), -r.z, o);
                    }
                    2 => {
                        add(mt(3), r.y, o);
                        add(mt(4), -r.x, o);
                    }
                    _ => {}
                }
                // Merge duplicate equations.
                o.sort_by_key(|t| t.0);
                let mut merged: Vec<(u32, f64)> = Vec::with_capacity(o.len());
                for &(e, v) in o.iter() {
                    match merged.last_mut() {
                        Some(last) if last.0 == e => last.1 += v,
                        _ => merged.push((e, v)),
                    }
                }
                merged.retain(|t| t.1 != 0.0);
                *o = merged;
            }
            for (d, o) in out.into_iter().enumerate() {
                terms[node * 6 + d] = Some(o);
            }
            visiting[node] = false;
            Ok(())
        }
        for i in 0..nn {
            resolve(i, model, kin, &slave_of, &eq_of, &mut terms, &mut visiting)?;
        }
        let finite = finite_rotation_nodes(model)?;
        let triples = rotation_triples(model, &finite, &eq_of, &terms)?;
        let mut start = Vec::with_capacity(nn * 6 + 1);
        let mut eqs = Vec::new();
        let mut coefs = Vec::new();
        start.push(0);
        for t in terms {
            for (e, c) in t.unwrap_or_default() {
                eqs.push(e);
                coefs.push(c);
            }
            start.push(eqs.len() as u32);
        }
        Ok(DofMap {
            neq: eq_dof.len(),
            start,
            eqs,
            coefs,
            eq_dof,
            active: used,
            finite,
            triples,
        })
    }

    /// Whether node index `node` is a finite-rotation node (see the module documentation).
    pub fn finite_rotation(&self, node: usize) -> bool {
        self.finite.get(node).copied().unwrap_or(false)
    }

    /// Whether any equation triple must be updated by composition.
    pub fn has_finite_rotations(&self) -> bool {
        !self.triples.is_empty()
    }

    /// The equations `(rx, ry, rz)` of every finite-rotation node with three free rotations.
    pub fn rotation_triples(&self) -> impl Iterator<Item = [usize; 3]> + '_ {
        self.triples
            .iter()
            .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
    }

    /// Applies a solver correction: `q ← q + dq`, except that on finite-rotation triples the
    /// correction is a spatial spin composed onto the stored rotation vector,
    /// `ψ ← log(exp([δ]×)·exp([ψ]×))`. Without finite-rotation nodes this is the plain sum.
    pub fn add_correction(&self, q: &mut [f64], dq: &[f64]) {
        let composed: Vec<Vector3<f64>> = self
            .rotation_triples()
            .map(|t| {
                let psi = Vector3::new(q[t[0]], q[t[1]], q[t[2]]);
                let d = Vector3::new(dq[t[0]], dq[t[1]], dq[t[2]]);
                rotation::compose(&psi, &d)
            })
            .collect();
        for (x, d) in q.iter_mut().zip(dq) {
            *x += d;
        }
        for (t, c) in self.rotation_triples().zip(composed) {
            for k in 0..3 {
                q[t[k]] = c[k];
            }
        }
    }

    /// The increment from `old` to `new` into `out`: `new − old`, except on finite-rotation
    /// triples, where it is the incremental rotation vector `log(R_new·R_oldᵀ)` (the spin
    /// that [`DofMap::add_correction`] would compose onto `old` to reach `new`).
    pub fn increment(&self, old: &[f64], new: &[f64], out: &mut [f64]) {
        for ((o, n), d) in old.iter().zip(new).zip(out.iter_mut()) {
            *d = n - o;
        }
        for t in self.rotation_triples() {
            let a = Vector3::new(old[t[0]], old[t[1]], old[t[2]]);
            let b = Vector3::new(new[t[0]], new[t[1]], new[t[2]]);
            let th = rotation::increment(&a, &b);
            for k in 0..3 {
                out[t[k]] = th[k];
            }
        }
    }

    /// The equations and coefficients DOF `dof` of node index `node` depends on: its value
    /// is `Σ c·q[e]` over the pairs `(e, c)` (one pair `(e, 1)` for a free DOF, the
    /// master's terms for a slave, none for a fixed or inactive one).
    pub fn terms(&self, node: usize, dof: Dof) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.terms_at(node, dof.index())
    }

    /// As [`DofMap::terms`], the DOF by its index in [`Dof::ALL`] (the framework's own
    /// loops over the six DOFs of a node).
    pub(crate) fn terms_at(
        &self,
        node: usize,
        d: usize,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        let k = node * 6 + d;
        let (a, b) = (self.start[k] as usize, self.start[k + 1] as usize);
        self.eqs[a..b]
            .iter()
            .zip(&self.coefs[a..b])
            .map(|(e, c)| (*e as usize, *c))
    }

    /// The equation of DOF `dof` of node index `node` if it is free (not fixed, slave or
    /// inactive).
    pub fn equation(&self, node: usize, dof: Dof) -> Option<usize> {
        let k = node * 6 + dof.index();
        let (a, b) = (self.start[k] as usize, self.start[k + 1] as usize);
        if b == a + 1 && self.eq_dof[self.eqs[a] as usize] == k {
            Some(self.eqs[a] as usize)
        } else {
            None
        }
    }

    /// Value of DOF `dof` of node index `node` given the equation vector `q` (m or rad for
    /// displacements, per second for velocities, per second squared for accelerations).
    pub fn value(&self, q: &[f64], node: usize, dof: Dof) -> f64 {
        self.value_at(q, node, dof.index())
    }

    /// As [`DofMap::value`], the DOF by its index in [`Dof::ALL`].
    pub(crate) fn value_at(&self, q: &[f64], node: usize, d: usize) -> f64 {
        self.terms_at(node, d).map(|(e, c)| c * q[e]).sum()
    }

    /// Node index and DOF of equation `eq`.
    pub fn dof_of(&self, eq: usize) -> (usize, crate::dof::Dof) {
        let k = self.eq_dof[eq];
        (k / 6, Dof::ALL[k % 6])
    }
}

/// Finite-rotation flags per node: nodes of elements declaring `finite_rotations`, nodes the
/// model marked, and (transitively) masters of such slaves whose rotations they follow.
fn finite_rotation_nodes(model: &Model) -> Result<Vec<bool>, FemError> {
    let mut finite = vec![false; model.nodes.len()];
    for e in &model.elements {
        if e.element.properties().finite_rotations {
            for nd in e.element.connectivity() {
                finite[nd.node] = true;
            }
        }
    }
    for &n in &model.finite_rotation_nodes {
        match finite.get_mut(n) {
            Some(f) => *f = true,
            None => {
                return Err(FemError::input(
                    &model.origin,
                    format!(
                        "a finite-rotation mark names node index {n} but the model has {} nodes; mark an existing node",
                        model.nodes.len()
                    ),
                ))
            }
        }
    }
    for _ in 0..=model.links.len() {
        let mut changed = false;
        for l in &model.links {
            if finite[l.slave] && !finite[l.master] && l.dofs.bits() & DofSet::ROTATIONS.bits() != 0
            {
                finite[l.master] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    Ok(finite)
}

/// The free rotation triples of the finite-rotation nodes, refusing a node whose rotations
/// are partly free and partly fixed in a way composition cannot respect.
fn rotation_triples(
    model: &Model,
    finite: &[bool],
    eq_of: &[u32],
    terms: &[Option<Vec<(u32, f64)>>],
) -> Result<Vec<[u32; 3]>, FemError> {
    let mut triples = Vec::new();
    for (node, _) in finite.iter().enumerate().filter(|(_, f)| **f) {
        let free: Vec<u32> = (3..6)
            .map(|d| eq_of[node * 6 + d])
            .filter(|&e| e != u32::MAX)
            .collect();
        let follows = (3..6).any(|d| {
            eq_of[node * 6 + d] == u32::MAX
                && terms[node * 6 + d].as_ref().is_some_and(|t| !t.is_empty())
        });
        match (free.len(), follows) {
            (3, _) => triples.push([free[0], free[1], free[2]]),
            (0, _) | (1, false) => {}
            _ => {
                return Err(FemError::input(
                    format!("{}: node {}", model.origin, model.nodes[node].id),
                    "a finite-rotation node (a corotational beam or nonlinear link is attached) must have rx, ry, rz all free, all fixed, or only one of them free: composing rotations mixes the three components; fix or free the rotations together",
                ));
            }
        }
    }
    Ok(triples)
}
