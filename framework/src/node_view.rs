//! Typed per-node views of an element's vectors and matrices: a node's translation and
//! rotation as [`Vector3`]s out of a [`TrialState`], and a node's force or a pair of nodes'
//! 3×3 or 6×6 block added into an element vector or matrix — instead of flat indices
//! (`t.disp[3] - t.disp[0]`) and blocks filled entry by entry.
//!
//! An element's vectors list its nodes in the order of [`Element::connectivity`] and, within
//! a node, the DOFs it uses there in the order ux, uy, uz, rx, ry, rz (the module
//! documentation of [`crate::element`]). A view is made from that connectivity, so it finds
//! a node's entries whichever DOFs the element uses: a DOF the node does not use reads as
//! zero, and a block entry on it is not written (the element declared it has none there).
//!
//! ```
//! use nalgebra::{DMatrix, Matrix3, Vector3};
//! use railfem_framework::element::{NodeDofs, TrialState};
//! use railfem_framework::node_view::{NodeBlocks, NodeForces};
//!
//! // A bar between two nodes that uses their translations only: 6 element DOFs.
//! let conn = [NodeDofs::translations(4), NodeDofs::translations(9)];
//! let disp = [0.0, 0.0, 0.0, 1e-3, 2e-3, 0.0];
//! let t = TrialState { time: 0.0, dt: 0.0, disp: &disp, vel: &[], acc: &[] };
//! let du = t.node(&conn, 1).translation() - t.node(&conn, 0).translation();
//! assert_eq!(du, Vector3::new(1e-3, 2e-3, 0.0));
//! assert_eq!(t.node(&conn, 1).velocity(), Vector3::zeros()); // a static state has none
//!
//! // Its tangent k·[[n nᵀ, −n nᵀ], [−n nᵀ, n nᵀ]] along n = x, by blocks.
//! let n = Vector3::x();
//! let nn: Matrix3<f64> = n * n.transpose() * 2e6;
//! let mut k = DMatrix::zeros(6, 6);
//! let mut blocks = NodeBlocks::new(&mut k, &conn);
//! blocks.add_translations(0, 0, &nn);
//! blocks.add_translations(1, 1, &nn);
//! blocks.add_translations(0, 1, &-nn);
//! blocks.add_translations(1, 0, &-nn);
//! assert_eq!((k[(0, 0)], k[(0, 3)], k[(3, 0)], k[(4, 4)]), (2e6, -2e6, -2e6, 0.0));
//!
//! // Its resisting force: −N·n at I, +N·n at J.
//! let mut f = [0.0; 6];
//! let mut forces = NodeForces::new(&mut f, &conn);
//! forces.add_force(0, &(-5.0 * n));
//! forces.add_force(1, &(5.0 * n));
//! assert_eq!(f, [-5.0, 0.0, 0.0, 5.0, 0.0, 0.0]);
//! ```
//!
//! [`Element::connectivity`]: crate::element::Element::connectivity

use crate::dof::Dof;
use crate::element::{NodeDofs, TrialState};
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};

/// Where each of a node's six DOFs sits in an element vector (`None`: the node does not
/// use it), from the element's connectivity.
fn positions(conn: &[NodeDofs], i: usize) -> [Option<usize>; 6] {
    let start: usize = conn[..i].iter().map(|n| n.dofs.count()).sum();
    let mut out = [None; 6];
    for (at, d) in (start..).zip(conn[i].dofs.iter()) {
        out[d.index()] = Some(at);
    }
    out
}

/// One node's part of a trial state ([`TrialState::node`]): its displacements,
/// velocities and accelerations by DOF, in the node's axes. A DOF the element does not use
/// at the node reads 0, and so does every velocity and acceleration of a state that has
/// none (a static analysis may pass empty slices).
#[derive(Debug, Clone, Copy)]
pub struct NodeState<'a> {
    at: [Option<usize>; 6],
    disp: &'a [f64],
    vel: &'a [f64],
    acc: &'a [f64],
}

impl<'a> NodeState<'a> {
    fn read(&self, x: &[f64], d: Dof) -> f64 {
        self.at[d.index()]
            .and_then(|k| x.get(k).copied())
            .unwrap_or(0.0)
    }

    fn three(&self, x: &[f64], first: Dof) -> Vector3<f64> {
        let i = first.index();
        Vector3::from_fn(|r, _| self.read(x, Dof::ALL[i + r]))
    }

    /// The displacement of DOF `d` (m or rad).
    pub fn displacement(&self, d: Dof) -> f64 {
        self.read(self.disp, d)
    }

    /// The velocity of DOF `d` (m/s or rad/s).
    pub fn velocity_of(&self, d: Dof) -> f64 {
        self.read(self.vel, d)
    }

    /// The acceleration of DOF `d` (m/s² or rad/s²).
    pub fn acceleration_of(&self, d: Dof) -> f64 {
        self.read(self.acc, d)
    }

    /// The translation `(ux, uy, uz)` (m).
    pub fn translation(&self) -> Vector3<f64> {
        self.three(self.disp, Dof::Ux)
    }

    /// The rotation `(rx, ry, rz)` (rad): small rotations, or the total rotation vector of
    /// a finite-rotation node ([`crate::element::ElementProperties::finite_rotations`]).
    pub fn rotation(&self) -> Vector3<f64> {
        self.three(self.disp, Dof::Rx)
    }

    /// The velocity `(u̇x, u̇y, u̇z)` (m/s).
    pub fn velocity(&self) -> Vector3<f64> {
        self.three(self.vel, Dof::Ux)
    }

    /// The angular velocity `(ṙx, ṙy, ṙz)` (rad/s).
    pub fn angular_velocity(&self) -> Vector3<f64> {
        self.three(self.vel, Dof::Rx)
    }

    /// The acceleration `(üx, üy, üz)` (m/s²).
    pub fn acceleration(&self) -> Vector3<f64> {
        self.three(self.acc, Dof::Ux)
    }

    /// The angular acceleration `(r̈x, r̈y, r̈z)` (rad/s²).
    pub fn angular_acceleration(&self) -> Vector3<f64> {
        self.three(self.acc, Dof::Rx)
    }

    /// All six displacements, translation then rotation (m, rad).
    pub fn displacement6(&self) -> Vector6<f64> {
        Vector6::from_fn(|r, _| self.read(self.disp, Dof::ALL[r]))
    }

    /// All six velocities, translation then rotation (m/s, rad/s).
    pub fn velocity6(&self) -> Vector6<f64> {
        Vector6::from_fn(|r, _| self.read(self.vel, Dof::ALL[r]))
    }
}

impl<'a> TrialState<'a> {
    /// The state of the element's node `i` (its position in `conn`, the element's
    /// [`crate::element::Element::connectivity`]). Panics if `i` is not a node of `conn`.
    pub fn node(&self, conn: &[NodeDofs], i: usize) -> NodeState<'a> {
        NodeState {
            at: positions(conn, i),
            disp: self.disp,
            vel: self.vel,
            acc: self.acc,
        }
    }
}

/// An element matrix (stiffness, mass, damping) written by node blocks: the block of node
/// `i`'s DOFs (rows) against node `j`'s (columns), `i` and `j` positions in the element's
/// connectivity. Entries on a DOF a node does not use are not written.
pub struct NodeBlocks<'m> {
    m: &'m mut DMatrix<f64>,
    at: Vec<[Option<usize>; 6]>,
}

impl<'m> NodeBlocks<'m> {
    /// Blocks of `m`, an element matrix of the connectivity `conn`.
    pub fn new(m: &'m mut DMatrix<f64>, conn: &[NodeDofs]) -> NodeBlocks<'m> {
        let at = (0..conn.len()).map(|i| positions(conn, i)).collect();
        NodeBlocks { m, at }
    }

    /// Adds the `R×C` block `b` at DOFs `rows` of node `i` and `cols` of node `j`.
    fn add<const R: usize, const C: usize>(
        &mut self,
        (i, rows): (usize, &[Dof; R]),
        (j, cols): (usize, &[Dof; C]),
        b: &nalgebra::SMatrix<f64, R, C>,
    ) {
        for (r, dr) in rows.iter().enumerate() {
            let Some(p) = self.at[i][dr.index()] else {
                continue;
            };
            for (c, dc) in cols.iter().enumerate() {
                if let Some(q) = self.at[j][dc.index()] {
                    self.m[(p, q)] += b[(r, c)];
                }
            }
        }
    }

    /// Adds `b` to the block of node `i`'s translations against node `j`'s.
    pub fn add_translations(&mut self, i: usize, j: usize, b: &Matrix3<f64>) {
        const T: [Dof; 3] = [Dof::Ux, Dof::Uy, Dof::Uz];
        self.add((i, &T), (j, &T), b);
    }

    /// Adds `b` to the block of node `i`'s rotations against node `j`'s.
    pub fn add_rotations(&mut self, i: usize, j: usize, b: &Matrix3<f64>) {
        const R: [Dof; 3] = [Dof::Rx, Dof::Ry, Dof::Rz];
        self.add((i, &R), (j, &R), b);
    }

    /// Adds `b` to the block of node `i`'s six DOFs against node `j`'s (translations then
    /// rotations in both).
    pub fn add_block6(&mut self, i: usize, j: usize, b: &Matrix6<f64>) {
        self.add((i, &Dof::ALL), (j, &Dof::ALL), b);
    }

    /// Adds the two-node pattern `[[b, −b], [−b, b]]` of nodes `i` and `j`'s six DOFs: the
    /// matrix of anything that acts on the relative motion of two nodes (a spring, a
    /// dashpot).
    pub fn add_between6(&mut self, i: usize, j: usize, b: &Matrix6<f64>) {
        let minus = -b;
        self.add_block6(i, i, b);
        self.add_block6(j, j, b);
        self.add_block6(i, j, &minus);
        self.add_block6(j, i, &minus);
    }
}

/// An element vector (a resisting force) written by node: a force or moment added at node
/// `i` (its position in the element's connectivity). Entries on a DOF the node does not use
/// are not written.
pub struct NodeForces<'f> {
    f: &'f mut [f64],
    at: Vec<[Option<usize>; 6]>,
}

impl<'f> NodeForces<'f> {
    /// Nodes of `f`, an element vector of the connectivity `conn`.
    pub fn new(f: &'f mut [f64], conn: &[NodeDofs]) -> NodeForces<'f> {
        let at = (0..conn.len()).map(|i| positions(conn, i)).collect();
        NodeForces { f, at }
    }

    fn add(&mut self, i: usize, dofs: &[Dof], v: &[f64]) {
        for (d, x) in dofs.iter().zip(v) {
            if let Some(p) = self.at[i][d.index()] {
                self.f[p] += x;
            }
        }
    }

    /// Adds the force `v` (N) at node `i`'s translations.
    pub fn add_force(&mut self, i: usize, v: &Vector3<f64>) {
        self.add(i, &[Dof::Ux, Dof::Uy, Dof::Uz], v.as_slice());
    }

    /// Adds the moment `v` (N·m) at node `i`'s rotations.
    pub fn add_moment(&mut self, i: usize, v: &Vector3<f64>) {
        self.add(i, &[Dof::Rx, Dof::Ry, Dof::Rz], v.as_slice());
    }

    /// Adds `v`, force then moment (N, N·m), at node `i`'s six DOFs.
    pub fn add6(&mut self, i: usize, v: &Vector6<f64>) {
        self.add(i, &Dof::ALL, v.as_slice());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dof::DofSet;

    /// A node using some DOFs only: each value lands at its compacted position, unused DOFs
    /// read 0 and are not written; against the positions counted by hand.
    #[test]
    fn a_partial_node_reads_and_writes_its_own_dofs_only() {
        // Node 0: uz, ry (2 DOFs, positions 0, 1); node 1: all six (positions 2..8).
        let conn = [
            NodeDofs {
                node: 7,
                dofs: DofSet::of(&[Dof::Uz, Dof::Ry]),
            },
            NodeDofs::all(3),
        ];
        let disp: Vec<f64> = (0..8).map(|k| 10.0 + k as f64).collect();
        let vel: Vec<f64> = (0..8).map(|k| -(k as f64)).collect();
        let t = TrialState {
            time: 0.0,
            dt: 0.1,
            disp: &disp,
            vel: &vel,
            acc: &[],
        };
        let a = t.node(&conn, 0);
        assert_eq!(a.translation(), Vector3::new(0.0, 0.0, 10.0));
        assert_eq!(a.rotation(), Vector3::new(0.0, 11.0, 0.0));
        assert_eq!(a.velocity_of(Dof::Ry), -1.0);
        let b = t.node(&conn, 1);
        assert_eq!(b.translation(), Vector3::new(12.0, 13.0, 14.0));
        assert_eq!(b.rotation(), Vector3::new(15.0, 16.0, 17.0));
        assert_eq!(b.angular_velocity(), Vector3::new(-5.0, -6.0, -7.0));
        assert_eq!(b.acceleration(), Vector3::zeros());
        assert_eq!(
            b.displacement6(),
            Vector6::new(12.0, 13.0, 14.0, 15.0, 16.0, 17.0)
        );

        let mut k = DMatrix::zeros(8, 8);
        let m = Matrix3::from_fn(|r, c| (3 * r + c + 1) as f64);
        let mut blocks = NodeBlocks::new(&mut k, &conn);
        blocks.add_translations(0, 1, &m);
        blocks.add_rotations(1, 0, &m);
        // Row uz of node 0 (position 0) against node 1's ux uy uz (2, 3, 4): m's row 2.
        assert_eq!((k[(0, 2)], k[(0, 3)], k[(0, 4)]), (7.0, 8.0, 9.0));
        // Node 1's rx ry rz (5, 6, 7) against node 0's ry (position 1): m's column 1.
        assert_eq!((k[(5, 1)], k[(6, 1)], k[(7, 1)]), (2.0, 5.0, 8.0));
        assert_eq!(k.iter().filter(|x| **x != 0.0).count(), 6);

        let mut f = [0.0; 8];
        let mut forces = NodeForces::new(&mut f, &conn);
        forces.add_force(0, &Vector3::new(1.0, 2.0, 3.0));
        forces.add_moment(1, &Vector3::new(4.0, 5.0, 6.0));
        assert_eq!(f, [3.0, 0.0, 0.0, 0.0, 0.0, 4.0, 5.0, 6.0]);
    }

    /// `add_between6` is `[[b, −b], [−b, b]]`, entry for entry.
    #[test]
    fn the_two_node_pattern_is_b_minus_b() {
        let conn = [NodeDofs::all(0), NodeDofs::all(1)];
        let b = Matrix6::from_fn(|r, c| (6 * r + c) as f64 - 17.0);
        let mut k = DMatrix::zeros(12, 12);
        NodeBlocks::new(&mut k, &conn).add_between6(0, 1, &b);
        for r in 0..12 {
            for c in 0..12 {
                let s = if (r < 6) == (c < 6) { 1.0 } else { -1.0 };
                assert_eq!(k[(r, c)], s * b[(r % 6, c % 6)]);
            }
        }
    }
}
