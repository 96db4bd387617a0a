//! Sparse assembly: the global pattern, constant contributions computed once, and the
//! value-only re-assembly of what changes.
//!
//! Elements are split once into *constant* ones (linear, fixed connectivity: their stiffness,
//! mass and damping go into cached global matrices at the start and are never evaluated
//! again — a multi-span bridge's beams) and *variable* ones (nonlinear, or moving: the wheel
//! axles), which are updated every iteration and scattered through precomputed position
//! maps. The pattern is the union over both; it is rebuilt only when a variable element
//! reports a connectivity change, and its `pattern_id` tells the linear solver whether to
//! redo its symbolic analysis. Elements with all their DOFs fixed or inactive are skipped
//! entirely (a rigid rail costs nothing).
//!
//! For large models the assembler can keep variable elements *off the pattern*
//! ([`Assembler::off_pattern`]): the global matrices then hold only the constant elements, a
//! moving element's new connectivity never rebuilds them, and the variable elements' effective
//! matrices are handed to the partitioned solver as triplets
//! ([`Assembler::variable_triplets`]); their mass and damping still enter `M·a` and `C·v`
//! element by element.
//!
//! Loads are formed here too because they need the masses: gravity `M·g`, the rigid-body
//! pseudo-loads of carried masses `−M·a_ref` (Eq. 5, see [`crate::moving`]), uniform ground
//! motion `−M·r·a_g(t)`, nodal loads and moving forces.

use crate::coefficients::Coefficients;
use crate::dofmap::DofMap;
use crate::element::{DissipationKind, ElementError, NodeKinematics, StepContext, TrialState};
use crate::error::FemError;
use crate::loads::{Load, MovingForce};
use crate::model::{Model, SolverResolver};
use crate::row_set::RowSet;
use crate::sparse::CscMatrix;
use nalgebra::{DMatrix, Vector3};

mod damping_diagonal;
mod held_loads;
mod nonzero_products;
mod own_columns;
mod own_elements;

pub use nonzero_products::NonzeroColumns;
pub use own_columns::{ColumnChoice, ColumnChooser};

/// Per-element scatter information.
#[derive(Debug, Clone, Default)]
struct ElementMap {
    /// For each element DOF: (node index, dof index).
    dofs: Vec<(usize, usize)>,
    /// Whether any DOF of the element has an equation.
    active: bool,
    /// Whether any node is carried.
    carried: bool,
    /// Scatter positions for variable elements: (csc position, a·n + b, coefficient).
    scatter: Vec<(u32, u32, f64)>,
}

/// Matrices of one variable element kept off the global pattern.
#[derive(Debug, Clone, Default)]
struct OffPattern {
    /// `(element DOF, equation, coefficient)` of every equation term of the element.
    terms: Vec<(u32, u32, f64)>,
    /// The element's DOF count (its matrices' size; DOFs without equations included).
    ndof: usize,
    /// Tangent stiffness of the current iteration.
    k: DMatrix<f64>,
    /// Mass of the current step, if the element has mass.
    m: Option<DMatrix<f64>>,
    /// Damping of the current step, if the element has damping.
    c: Option<DMatrix<f64>>,
}

/// A variable element's resisting force and (if asked for) tangent.
type Evaluated = (Vec<f64>, Option<DMatrix<f64>>);

/// Counters of the work done, for benchmarks and the performance report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AssemblyStats {
    /// Times the sparsity pattern was built.
    pub patterns: usize,
    /// Element state determinations (`update` calls).
    pub element_updates: usize,
    /// Variable elements at the last build.
    pub variable_elements: usize,
    /// Constant elements at the last build (assembled once).
    pub constant_elements: usize,
    /// Elements skipped because none of their DOFs has an equation.
    pub skipped_elements: usize,
}

/// Wall-clock seconds the assembler spent, by phase (for the performance report).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AssemblyTimes {
    /// Variable elements' state determination: contact detection, forces, tangents.
    pub elements: f64,
    /// Step starts: carriers moved, elements advanced (a wheel's search for the rail
    /// nodes under it), variable masses re-formed, patterns rebuilt.
    pub search: f64,
    /// Products with the constant matrices (`K·q`, `M·a`, `C·v`).
    pub products: f64,
}

/// The assembler of one model.
pub struct Assembler {
    /// Equation numbering.
    pub dofmap: DofMap,
    /// Constant stiffness (linear elements).
    pub k_const: CscMatrix,
    /// Constant mass.
    pub m_const: CscMatrix,
    /// Constant damping, Rayleigh included.
    pub c_const: CscMatrix,
    /// Mass of variable-mass elements, current step.
    pub m_var: CscMatrix,
    /// Tangent stiffness of variable elements, current iteration.
    pub k_var: CscMatrix,
    /// Damping of variable elements, current step.
    pub c_var: CscMatrix,
    maps: Vec<ElementMap>,
    variable: Vec<usize>,
    /// Elements whose mass must be re-formed each step (not constant, or carried loads).
    mass_elems: Vec<usize>,
    /// Cached element mass matrices of elements on carried nodes (for Eq. 5 loads).
    carried_mass: Vec<(usize, DMatrix<f64>)>,
    /// Non-carried moving elements whose mass changes between steps (a mass rolling along a
    /// beam): their gravity `M(t)·g` is formed at every call of [`Assembler::external_force`].
    gravity_variable: Vec<usize>,
    /// Gravity load of elements on fixed (non-carried) nodes, constant.
    gravity_fixed: Vec<f64>,
    /// `−M·r` per ground-motion load, constant part.
    ground_unit: Vec<Vec<f64>>,
    symmetric: bool,
    /// Node kinematics at `kin_time` (fixed nodes never change; carried ones are updated).
    kin: Vec<NodeKinematics>,
    kin_time: f64,
    /// Carried nodes: (carrier, record); `slot_of[node]` indexes it (u32::MAX: not carried).
    carried: Vec<(usize, crate::moving::CarriedNode)>,
    slot_of: Vec<u32>,
    /// Reference motion of each carried node at `kin_time`.
    motions: Vec<crate::moving::ReferenceMotion>,
    /// Work counters.
    pub stats: AssemblyStats,
    /// Time by phase.
    pub times: AssemblyTimes,
    /// Variable elements kept off the pattern (see the module documentation).
    off_pattern: bool,
    /// Off-pattern matrices, parallel to `variable`.
    off: Vec<OffPattern>,
    /// Position of element `ei` in `variable` (`u32::MAX`: constant).
    var_slot: Vec<u32>,
    /// Every constant element is symmetric: products with the constant matrices may use
    /// the parallel gather form ([`crate::sparse::symmetric_products`]).
    const_symmetric: bool,
    /// Whether `m_var` / `c_var` can hold anything (else their products are skipped).
    m_var_used: bool,
    c_var_used: bool,
    /// Threads for the products with the constant matrices.
    threads: usize,
    /// The linear solver the model runs with (`auto` resolved).
    solver: crate::model::SolverChoice,
    /// Every value of `c_const` is zero (no dashpot, no Rayleigh damping): its products
    /// are zero vectors and are not formed.
    c_const_zero: bool,
    /// The diagonal of `m_const` when every stored value off its diagonal is exactly zero
    /// (a lumped mass), else `None`. Then `M·x` is `m_i·x_i` per equation: the same value
    /// as the product over the pattern, whose every other term is `0·x_j` (exactly zero,
    /// so adding it changes nothing but, at most, the sign of a zero), at the cost of one
    /// pass over `n` values instead of over the pattern of K.
    m_diag: Option<Vec<f64>>,
    /// `K`, `M`, `C` hold only some columns (`own_columns`).
    columns_kept: bool,
    /// The diagonals of the whole `K`, `M`, `C` when they were formed on some columns only
    /// ([`Assembler::new_on_columns`]); `None` when the build formed every column.
    diagonals: Option<[Vec<f64>; 3]>,
    /// Stored entries of `K` at the largest build (`M` and `C` the same): what this
    /// process ever held of each constant matrix.
    entries_built: usize,
    /// `K`, `M`, `C` on the patterns of their own non-zero values, which the products read
    /// ([`nonzero_products`]); `None` where the products read the shared pattern (a
    /// matrix not symmetric, Rayleigh damping: `C` then fills the pattern of `K` and `M`).
    nonzero: Option<[NonzeroColumns; 3]>,
    /// `Σ_e |f_e|²` over the variable elements' resisting forces at the last
    /// [`Assembler::update_variable`] ([`Assembler::element_force_norm`]).
    element_force_sq: f64,
}

fn kinematic_vector(kin: &NodeKinematics, d: usize, lin: &Vector3<f64>, ang: &Vector3<f64>) -> f64 {
    // Components of a global vector in the node's axes: Rᵀ·v.
    if d < 3 {
        kin.frame.column(d).dot(lin)
    } else {
        kin.frame.column(d - 3).dot(ang)
    }
}

impl Assembler {
    /// Numbers equations, classifies elements, builds the pattern and the constant parts.
    /// `resolve` picks the linear solver from the model's choice and size
    /// ([`crate::model::SolverResolver`]; the solvers crate's `thresholds::resolve`): any
    /// solver but the direct one keeps the variable elements off the global pattern.
    pub fn new(model: &mut Model, resolve: SolverResolver) -> Result<Assembler, FemError> {
        Self::new_choosing(model, resolve, None)
    }

    /// [`Assembler::new`], and when `choose` is given and the constant part can be kept on
    /// some columns exactly, `K`, `M`, `C` formed on the columns it picks from the pattern
    /// only ([`Assembler::new_on_columns`]).
    pub(crate) fn new_choosing(
        model: &mut Model,
        resolve: SolverResolver,
        choose: Option<&mut ColumnChooser<'_>>,
    ) -> Result<Assembler, FemError> {
        let kin = model.kinematics(0.0);
        // Let every element see its t = 0 state before anything is numbered.
        {
            let ctx = StepContext {
                time: 0.0,
                dt: 0.0,
                nodes: &kin,
            };
            for e in model.elements.iter_mut() {
                e.element
                    .advance(&ctx)
                    .map_err(|err| element_error(&e.origin, err))?;
            }
        }
        let dofmap = DofMap::new(model, &kin)?;
        let n = dofmap.neq;
        let empty = CscMatrix::from_columns(vec![Vec::new(); n]);
        let mut a = Assembler {
            dofmap,
            k_const: empty.clone(),
            m_const: empty.clone(),
            c_const: empty.clone(),
            m_var: empty.clone(),
            k_var: empty.clone(),
            c_var: empty,
            maps: Vec::new(),
            variable: Vec::new(),
            mass_elems: Vec::new(),
            carried_mass: Vec::new(),
            gravity_variable: Vec::new(),
            gravity_fixed: vec![0.0; n],
            ground_unit: Vec::new(),
            symmetric: true,
            kin: kin.clone(),
            kin_time: 0.0,
            carried: Vec::new(),
            slot_of: vec![u32::MAX; model.nodes.len()],
            motions: Vec::new(),
            stats: AssemblyStats::default(),
            times: AssemblyTimes::default(),
            element_force_sq: 0.0,
            off_pattern: false,
            off: Vec::new(),
            var_slot: Vec::new(),
            const_symmetric: true,
            m_var_used: true,
            c_var_used: true,
            threads: crate::parallel::threads(0),
            solver: crate::model::SolverChoice::Direct,
            c_const_zero: false,
            m_diag: None,
            columns_kept: false,
            diagonals: None,
            entries_built: 0,
            nonzero: None,
        };
        let variable_dofs = model
            .elements
            .iter()
            .filter(|e| {
                let p = e.element.properties();
                !p.linear || p.connectivity_may_change
            })
            .map(|e| e.element.ndof())
            .reduce(|a, b| a + b);
        a.solver = resolve(&crate::model::SolverInputs {
            choice: model.analysis.solver,
            equations: n,
            variable_dofs,
            transient: model.analysis.kind == crate::model::AnalysisKind::Transient,
        });
        a.off_pattern = a.solver != crate::model::SolverChoice::Direct;
        for (ci, c) in model.carriers.iter().enumerate() {
            for cn in &c.nodes {
                a.slot_of[cn.node] = a.carried.len() as u32;
                a.carried.push((ci, *cn));
            }
        }
        a.kin_time = f64::NAN;
        a.set_time(model, 0.0);
        a.build(model, &kin, choose)?;
        Ok(a)
    }

    /// Number of equations.
    pub fn neq(&self) -> usize {
        self.dofmap.neq
    }

    /// The linear solver the model runs with: the model's `[analysis] solver` with `auto`
    /// resolved by the [`crate::model::SolverResolver`] it was built with; anything but `Direct` keeps the
    /// variable elements off the global pattern.
    pub fn solver(&self) -> crate::model::SolverChoice {
        self.solver
    }

    /// Whether variable elements are kept off the global pattern (the partitioned solver's
    /// mode): then [`Assembler::effective`] holds only the constant elements and the variable
    /// ones come from [`Assembler::variable_triplets`].
    pub fn off_pattern(&self) -> bool {
        self.off_pattern
    }

    /// Whether the constant part of the effective tangent ([`Assembler::effective`] in the
    /// off-pattern mode) depends only on its coefficients: false when an element on fixed
    /// connectivity has a mass or damping that changes between steps.
    pub fn constant_part_is_constant(&self) -> bool {
        self.mass_elems
            .iter()
            .all(|&ei| self.var_slot.get(ei).is_some_and(|&s| s != u32::MAX))
    }

    /// Equations whose stiffness or mass is not in the constant matrices, from the elements'
    /// declared connectivity: `(variable, variable_mass)` flags per equation — touched by a
    /// variable element (any of its matrices), or by an element whose mass is re-formed
    /// each step. The singularity check counts such an equation as possibly stiff
    /// (possibly massive) without evaluating anything.
    pub fn variable_cover(&self) -> (Vec<bool>, Vec<bool>) {
        let n = self.dofmap.neq;
        let mut var = vec![false; n];
        let mut mass = vec![false; n];
        let mark = |ei: usize, flags: &mut Vec<bool>| {
            for &(node, d) in &self.maps[ei].dofs {
                for (e, _) in self.dofmap.terms_at(node, d) {
                    flags[e] = true;
                }
            }
        };
        for &ei in &self.variable {
            mark(ei, &mut var);
        }
        for &ei in &self.mass_elems {
            mark(ei, &mut mass);
        }
        (var, mass)
    }

    /// Bytes the assembler holds, by part (capacities, as allocated; for the memory report
    /// of `railfem bench`): the constant matrices, the variable ones, the element maps,
    /// the constant load vectors and the node kinematics. Elements themselves live in the
    /// model and are not counted here.
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        let vec_bytes = |v: &Vec<f64>| 8 * v.capacity();
        let maps: usize = self
            .maps
            .iter()
            .map(|m| {
                std::mem::size_of::<ElementMap>()
                    + 16 * m.dofs.capacity()
                    + 16 * m.scatter.capacity()
            })
            .sum();
        let off: usize = self
            .off
            .iter()
            .map(|o| {
                std::mem::size_of::<OffPattern>()
                    + 16 * o.terms.capacity()
                    + 8 * (o.k.len()
                        + o.m.as_ref().map_or(0, |m| m.len())
                        + o.c.as_ref().map_or(0, |m| m.len()))
            })
            .sum();
        vec![
            ("K constant", self.k_const.heap_bytes()),
            ("M constant", self.m_const.heap_bytes()),
            ("C constant", self.c_const.heap_bytes()),
            (
                "K, M, C non-zeros for the products",
                self.nonzero
                    .as_ref()
                    .map_or(0, |nz| nz.iter().map(NonzeroColumns::heap_bytes).sum()),
            ),
            (
                "variable matrices",
                self.k_var.heap_bytes() + self.m_var.heap_bytes() + self.c_var.heap_bytes() + off,
            ),
            ("element maps", maps + 8 * self.var_slot.capacity()),
            (
                "constant loads",
                vec_bytes(&self.gravity_fixed)
                    + self.ground_unit.iter().map(vec_bytes).sum::<usize>()
                    + self.m_diag.as_ref().map_or(0, vec_bytes),
            ),
            (
                "node kinematics",
                std::mem::size_of::<NodeKinematics>() * self.kin.capacity()
                    + 4 * self.slot_of.capacity(),
            ),
        ]
    }

    /// Whether every element declares a symmetric tangent.
    pub fn symmetric(&self) -> bool {
        self.symmetric
    }

    /// (Re)builds maps, pattern, constant matrices and constant loads; with `choose`, the
    /// constant matrices on the columns it picks ([`Assembler::new_on_columns`]).
    fn build(
        &mut self,
        model: &mut Model,
        kin: &[NodeKinematics],
        choose: Option<&mut ColumnChooser<'_>>,
    ) -> Result<(), FemError> {
        let n = self.dofmap.neq;
        let ne = model.elements.len();
        let mut carried_node = vec![false; model.nodes.len()];
        for c in &model.carriers {
            for cn in &c.nodes {
                carried_node[cn.node] = true;
            }
        }
        self.maps = Vec::with_capacity(ne);
        self.variable.clear();
        self.mass_elems.clear();
        self.symmetric = true;
        let mut stats = AssemblyStats {
            patterns: self.stats.patterns + 1,
            element_updates: self.stats.element_updates,
            ..Default::default()
        };
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut eqbuf = Vec::new();
        let mut const_symmetric = true;
        for ei in 0..ne {
            let mut map = {
                let e = &model.elements[ei].element;
                let mut dofs = Vec::with_capacity(e.ndof());
                let mut active = false;
                let mut carried = false;
                for nd in e.connectivity() {
                    carried |= carried_node[nd.node];
                    for d in nd.dofs.iter() {
                        if self.dofmap.terms(nd.node, d).next().is_some() {
                            active = true;
                        }
                        dofs.push((nd.node, d.index()));
                    }
                }
                ElementMap {
                    dofs,
                    active,
                    carried,
                    scatter: Vec::new(),
                }
            };
            let props = model.elements[ei].element.properties();
            if !map.active {
                stats.skipped_elements += 1;
                self.maps.push(map);
                continue;
            }
            self.symmetric &= props.symmetric;
            if props.linear && !props.connectivity_may_change {
                const_symmetric &= props.symmetric;
            }
            eqbuf.clear();
            for &(node, d) in &map.dofs {
                eqbuf.extend(self.dofmap.terms_at(node, d).map(|t| t.0));
            }
            eqbuf.sort_unstable();
            eqbuf.dedup();
            let variable = !props.linear || props.connectivity_may_change;
            if !(variable && self.off_pattern) {
                for &j in &eqbuf {
                    cols[j].extend_from_slice(&eqbuf);
                }
            }
            if variable {
                self.variable.push(ei);
                stats.variable_elements += 1;
            } else {
                stats.constant_elements += 1;
            }
            if props.has_mass && (!props.constant_mass || variable) {
                self.mass_elems.push(ei);
            }
            map.scatter.clear();
            self.maps.push(map);
        }
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
        }
        let mut pattern = CscMatrix::from_columns(cols);
        // Scatter maps of variable elements (or their off-pattern terms).
        self.var_slot = vec![u32::MAX; ne];
        for (slot, &ei) in self.variable.iter().enumerate() {
            self.var_slot[ei] = slot as u32;
        }
        if self.off_pattern {
            self.off_pattern_terms();
        }
        self.const_symmetric = const_symmetric;
        self.m_var_used = self
            .mass_elems
            .iter()
            .any(|&ei| !self.off_pattern || self.var_slot[ei] == u32::MAX);
        self.c_var_used = !self.off_pattern
            && self
                .variable
                .iter()
                .any(|&ei| model.elements[ei].element.properties().has_damping);
        for &ei in self.variable.iter().filter(|_| !self.off_pattern) {
            let map = &self.maps[ei];
            let nd = map.dofs.len();
            let mut sc = Vec::new();
            for (b, &(nb, db)) in map.dofs.iter().enumerate() {
                for (eb, cb) in self.dofmap.terms_at(nb, db) {
                    for (a, &(na, da)) in map.dofs.iter().enumerate() {
                        for (ea, ca) in self.dofmap.terms_at(na, da) {
                            let p = pattern.position(ea, eb).expect("pattern holds the element");
                            sc.push((p as u32, (a * nd + b) as u32, ca * cb));
                        }
                    }
                }
            }
            self.maps[ei].scatter = sc;
        }
        // Across ranks, the columns this rank keeps, chosen on the pattern before any value
        // exists; the whole pattern is dropped once they are taken from it.
        let keep = self.choose_columns(&mut pattern, const_symmetric, choose);
        let pattern = match &keep {
            Some(k) => own_columns::kept_columns(&pattern, k),
            None => pattern,
        };
        let mut diagonals = keep
            .as_ref()
            .map(|_| [vec![0.0; n], vec![0.0; n], vec![0.0; n]]);
        // Constant matrices.
        let mut k_const = pattern.zeros_like();
        let mut m_const = pattern.zeros_like();
        let mut c_const = pattern.zeros_like();
        let mut kbuf = DMatrix::zeros(0, 0);
        let zeros: Vec<f64> = Vec::new();
        let [mut dk, mut dm, mut dc] = match diagonals.as_mut() {
            Some([k, m, c]) => [Some(&mut k[..]), Some(&mut m[..]), Some(&mut c[..])],
            None => [None, None, None],
        };
        for ei in 0..ne {
            if !self.maps[ei].active {
                continue;
            }
            let (map, dofs) = (&self.dofmap, &self.maps[ei].dofs);
            let entry = &mut model.elements[ei];
            let props = entry.element.properties();
            let nd = self.maps[ei].dofs.len();
            let variable = !props.linear || props.connectivity_may_change;
            if !variable {
                // A linear element: its tangent at the zero state is its stiffness.
                let z = if zeros.len() >= nd {
                    &zeros[..nd]
                } else {
                    &vec![0.0; nd][..]
                };
                let z = z.to_vec();
                entry
                    .element
                    .update(&TrialState {
                        time: 0.0,
                        dt: 0.0,
                        disp: &z,
                        vel: &z,
                        acc: &z,
                    })
                    .map_err(|err| element_error(&entry.origin, err))?;
                kbuf = DMatrix::zeros(nd, nd);
                entry.element.tangent_stiffness(&mut kbuf);
                check_finite(&kbuf, &entry.origin, "tangent stiffness")?;
                scatter_dense(map, dofs, &kbuf, &mut k_const, dk.as_deref_mut());
            }
            if props.has_mass && props.constant_mass && !variable {
                kbuf = DMatrix::zeros(nd, nd);
                entry.element.mass(&mut kbuf);
                check_finite(&kbuf, &entry.origin, "mass")?;
                scatter_dense(map, dofs, &kbuf, &mut m_const, dm.as_deref_mut());
            }
            if props.has_damping && props.constant_damping && !variable {
                kbuf = DMatrix::zeros(nd, nd);
                entry.element.damping(&mut kbuf);
                check_finite(&kbuf, &entry.origin, "damping")?;
                scatter_dense(map, dofs, &kbuf, &mut c_const, dc.as_deref_mut());
            }
        }
        let _ = kbuf;
        if let Some(r) = model.analysis.rayleigh {
            for ((c, m), k) in c_const
                .values
                .iter_mut()
                .zip(&m_const.values)
                .zip(&k_const.values)
            {
                *c += r.alpha * m + r.beta * k;
            }
            if let Some([k, m, c]) = diagonals.as_mut() {
                for ((c, m), k) in c.iter_mut().zip(&*m).zip(&*k) {
                    *c += r.alpha * m + r.beta * k;
                }
            }
        }
        // Off the pattern, the variable matrices live with their elements: the global
        // ones stay empty (at a million equations each would cost ~0.7 GB).
        let empty = CscMatrix::from_columns(Vec::new());
        self.k_var = if self.off_pattern {
            empty.clone()
        } else {
            pattern.zeros_like()
        };
        self.m_var = if self.m_var_used {
            pattern.zeros_like()
        } else {
            empty.clone()
        };
        self.c_var = if self.c_var_used {
            pattern.zeros_like()
        } else {
            empty
        };
        self.c_const_zero = c_const.values.iter().all(|&c| c == 0.0);
        self.m_diag = diagonal_of(&m_const);
        self.k_const = k_const;
        self.m_const = m_const;
        self.c_const = c_const;
        self.entries_built = self.entries_built.max(self.k_const.row_idx.len());
        self.columns_kept = keep.is_some();
        if diagonals.is_some() {
            // Whether `M` is diagonal is a property of every column: until the ranks agree
            // on it ([`Assembler::settle_across_ranks`]) the products read the columns.
            self.m_diag = None;
        }
        self.diagonals = diagonals;
        self.nonzero = if model.analysis.rayleigh.is_none() {
            self.nonzero_matrices()
        } else {
            None
        };
        // Constant loads: gravity on non-carried masses, ground-motion influence.
        self.carried_mass.clear();
        self.gravity_variable.clear();
        self.gravity_fixed = vec![0.0; n];
        self.ground_unit = Vec::new();
        let grav = model.analysis.gravity.map(Vector3::from);
        let ground_dirs: Vec<Vector3<f64>> = model
            .loads
            .iter()
            .filter_map(|l| match l {
                Load::GroundMotion { direction, .. } => Some(*direction),
                _ => None,
            })
            .collect();
        self.ground_unit = vec![vec![0.0; n]; ground_dirs.len()];
        for ei in 0..ne {
            let map = &self.maps[ei];
            if !map.active {
                continue;
            }
            let e = &model.elements[ei].element;
            if !e.properties().has_mass {
                continue;
            }
            let nd = map.dofs.len();
            let mut m = DMatrix::zeros(nd, nd);
            e.mass(&mut m);
            if map.carried {
                self.carried_mass.push((ei, m));
                continue;
            }
            // A moving element whose mass follows its position (a mass rolling along a
            // beam): its gravity is formed per step. Other changing masses (the finite-link
            // wrapper's) keep the gravity of the reference state, as before.
            let props = e.properties();
            if !props.constant_mass && props.connectivity_may_change {
                self.gravity_variable.push(ei);
            } else if let Some(g) = grav {
                let gv: Vec<f64> = map
                    .dofs
                    .iter()
                    .map(|&(node, d)| kinematic_vector(&kin[node], d, &g, &Vector3::zeros()))
                    .collect();
                let f = &m * nalgebra::DVector::from_vec(gv);
                scatter_vec(
                    &self.dofmap,
                    &map.dofs,
                    f.as_slice(),
                    &mut self.gravity_fixed,
                );
            }
            for (gi, dir) in ground_dirs.iter().enumerate() {
                let r: Vec<f64> = map
                    .dofs
                    .iter()
                    .map(|&(node, d)| kinematic_vector(&kin[node], d, dir, &Vector3::zeros()))
                    .collect();
                let f = -(&m * nalgebra::DVector::from_vec(r));
                scatter_vec(
                    &self.dofmap,
                    &map.dofs,
                    f.as_slice(),
                    &mut self.ground_unit[gi],
                );
            }
        }
        stats.element_updates = self.stats.element_updates;
        self.stats = stats;
        Ok(())
    }

    /// Equation terms of every variable element, for the off-pattern mode.
    fn off_pattern_terms(&mut self) {
        self.off
            .resize_with(self.variable.len(), OffPattern::default);
        for (slot, &ei) in self.variable.iter().enumerate() {
            let off = &mut self.off[slot];
            off.terms.clear();
            off.ndof = self.maps[ei].dofs.len();
            for (a, &(node, d)) in self.maps[ei].dofs.iter().enumerate() {
                for (e, c) in self.dofmap.terms_at(node, d) {
                    off.terms.push((a as u32, e as u32, c));
                }
            }
        }
    }

    /// Moves the carried nodes' reference positions and frames to time `t` (only the
    /// carried nodes: a track's rail nodes never move).
    fn set_time(&mut self, model: &Model, t: f64) {
        if self.kin_time == t {
            return;
        }
        self.motions.clear();
        for &(ci, cn) in &self.carried {
            let r = model.carriers[ci].reference(&cn, t);
            self.kin[cn.node] = NodeKinematics {
                position: r.position,
                frame: r.point.frame,
                carried: true,
                station: Some(r.point.station),
            };
            self.motions.push(r);
        }
        self.kin_time = t;
    }

    /// Node kinematics at the last time set (positions and frames).
    pub fn kinematics(&self) -> &[NodeKinematics] {
        &self.kin
    }

    /// Starts a step at time `t`: moves carried frames, lets elements advance (re-pick
    /// nodes), rebuilds the pattern if any connectivity changed, re-forms variable masses.
    /// Returns whether the pattern was rebuilt.
    pub fn advance(&mut self, model: &mut Model, t: f64, dt: f64) -> Result<bool, FemError> {
        let t0 = std::time::Instant::now();
        self.set_time(model, t);
        let kin = std::mem::take(&mut self.kin);
        let r = self.advance_with(model, &kin, t, dt);
        self.kin = kin;
        self.times.search += t0.elapsed().as_secs_f64();
        r
    }

    fn advance_with(
        &mut self,
        model: &mut Model,
        kin: &[NodeKinematics],
        t: f64,
        dt: f64,
    ) -> Result<bool, FemError> {
        let ctx = StepContext {
            time: t,
            dt,
            nodes: kin,
        };
        let mut changed = false;
        for &ei in &self.variable {
            let e = &mut model.elements[ei];
            if e.element.properties().connectivity_may_change {
                changed |= e
                    .element
                    .advance(&ctx)
                    .map_err(|err| element_error(&e.origin, err))?;
            } else {
                e.element
                    .advance(&ctx)
                    .map_err(|err| element_error(&e.origin, err))?;
            }
        }
        if changed {
            // Equation numbering is fixed for the run: a moved element must land on DOFs
            // that already have equations (rail nodes always do).
            for &ei in &self.variable {
                let e = &model.elements[ei];
                for nd in e.element.connectivity() {
                    let act = self.dofmap.active[nd.node];
                    let covered = act.bits() | model.nodes[nd.node].fixed.bits();
                    if nd.dofs.bits() & !covered != 0 {
                        return Err(FemError::Element {
                            id: e.id,
                            kind: e.element.kind().to_string(),
                            message: format!(
                                "moved onto {} which has no equation; connect it to another element",
                                model.dof_name(nd.node, crate::dof::Dof::Ux)
                            ),
                        });
                    }
                }
            }
            if self.off_pattern {
                // The global pattern holds only constant elements: nothing to rebuild.
                for &ei in &self.variable {
                    let e = &model.elements[ei].element;
                    let mut dofs = Vec::with_capacity(e.ndof());
                    for nd in e.connectivity() {
                        for d in nd.dofs.iter() {
                            dofs.push((nd.node, d.index()));
                        }
                    }
                    self.maps[ei].dofs = dofs;
                }
                self.off_pattern_terms();
            } else {
                self.build(model, kin, None)?;
            }
        }
        // Variable masses and damping of this step.
        self.m_var.values.iter_mut().for_each(|v| *v = 0.0);
        self.c_var.values.iter_mut().for_each(|v| *v = 0.0);
        for &ei in &self.mass_elems {
            let e = &model.elements[ei];
            let nd = self.maps[ei].dofs.len();
            let mut m = DMatrix::zeros(nd, nd);
            e.element.mass(&mut m);
            check_finite(&m, &e.origin, "mass")?;
            let slot = self.var_slot[ei];
            if self.off_pattern && slot != u32::MAX {
                self.off[slot as usize].m = Some(m);
            } else {
                scatter_dense(&self.dofmap, &self.maps[ei].dofs, &m, &mut self.m_var, None);
            }
        }
        for (slot, &ei) in self.variable.iter().enumerate() {
            let e = &model.elements[ei];
            if e.element.properties().has_damping {
                let nd = self.maps[ei].dofs.len();
                let mut c = DMatrix::zeros(nd, nd);
                e.element.damping(&mut c);
                check_finite(&c, &e.origin, "damping")?;
                if self.off_pattern {
                    self.off[slot].c = Some(c);
                } else {
                    scatter_dense(&self.dofmap, &self.maps[ei].dofs, &c, &mut self.c_var, None);
                }
            }
        }
        Ok(changed)
    }

    /// Element DOF values gathered from an equation vector.
    fn gather(&self, ei: usize, q: &[f64], out: &mut Vec<f64>) {
        out.clear();
        for &(node, d) in &self.maps[ei].dofs {
            out.push(self.dofmap.value_at(q, node, d));
        }
    }

    /// Updates every variable element to the trial state `(q, v, a)` at time `t`, and
    /// forms `f_int` (resisting force of all elements) and `k_var`.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        model: &mut Model,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        t: f64,
        dt: f64,
        f_int: &mut [f64],
        form_tangent: bool,
    ) -> Result<(), FemError> {
        self.constant_internal_force(q, f_int);
        self.update_variable(model, q, v, a, t, dt, f_int, form_tangent)
    }

    /// `f_int = K·q` of the constant elements alone (the value [`Assembler::update`] starts
    /// from): for a model without variable elements, its internal force.
    pub fn constant_internal_force(&mut self, q: &[f64], f_int: &mut [f64]) {
        let t0 = std::time::Instant::now();
        if self.const_symmetric {
            self.products(&[&self.k_const], &[q], &mut [f_int]);
        } else {
            self.k_const.mul_vec(q, f_int);
        }
        self.times.products += t0.elapsed().as_secs_f64();
    }

    /// [`Assembler::update`] for a transient iteration that also forms the inertia and
    /// damping forces `inertia = M·a_w` and `damping = C·v_w` (`a_w`, `v_w` the weighted
    /// acceleration and velocity of the integrator), in one pass over the constant
    /// matrices.
    #[allow(clippy::too_many_arguments)]
    pub fn update_transient(
        &mut self,
        model: &mut Model,
        (q, v, a): (&[f64], &[f64], &[f64]),
        (a_w, v_w): (&[f64], &[f64]),
        t: f64,
        dt: f64,
        (f_int, inertia, damping): (&mut [f64], &mut [f64], &mut [f64]),
        form_tangent: bool,
    ) -> Result<(), FemError> {
        let t0 = std::time::Instant::now();
        self.constant_products(Some((q, &mut *f_int)), (a_w, v_w), (inertia, damping));
        self.times.products += t0.elapsed().as_secs_f64();
        self.update_variable(model, q, v, a, t, dt, f_int, form_tangent)
    }

    /// The constant products of [`Assembler::update_transient`] — `f_int = K·q`,
    /// `inertia = M·a_w`, `damping = C·v_w`, the variable masses' and dashpots' parts
    /// added — without updating any element, and in the same pass over the constant
    /// matrices further products with the constant mass and damping alone:
    /// `y = M_const·x` for each `(x, y)` of `mass_more`, `y = C_const·x` for each of
    /// `damping_more` (zeroed without constant damping). Every product is summed as it is
    /// alone, so each value is the one a separate pass forms, to the bit. The caller adds
    /// the variable elements' forces ([`Assembler::update_variable`]).
    pub fn transient_products_with(
        &mut self,
        (q, f_int): (&[f64], &mut [f64]),
        (a_w, v_w): (&[f64], &[f64]),
        (inertia, damping): (&mut [f64], &mut [f64]),
        mass_more: &mut [(&[f64], &mut [f64])],
        damping_more: &mut [(&[f64], &mut [f64])],
    ) {
        self.transient_products_on(
            None,
            (q, f_int),
            (a_w, v_w),
            (inertia, damping),
            mass_more,
            damping_more,
        );
    }

    /// [`Assembler::transient_products_with`] on the rows of `rows` (every row: `None`):
    /// where the constant matrices' non-zero entries are kept, the other rows of the
    /// products over them are left as they are (a caller that knows them keeps them);
    /// otherwise every row is formed. A formed row has the same value, to the bit.
    pub fn transient_products_on(
        &mut self,
        rows: Option<&RowSet>,
        (q, f_int): (&[f64], &mut [f64]),
        (a_w, v_w): (&[f64], &[f64]),
        (inertia, damping): (&mut [f64], &mut [f64]),
        mass_more: &mut [(&[f64], &mut [f64])],
        damping_more: &mut [(&[f64], &mut [f64])],
    ) {
        let t0 = std::time::Instant::now();
        let mut mats: Vec<&CscMatrix> = vec![&self.k_const];
        let mut xs: Vec<&[f64]> = vec![q];
        let mut ys: Vec<&mut [f64]> = vec![&mut *f_int];
        match &self.m_diag {
            Some(d) => {
                diagonal_times(d, a_w, inertia);
                for (x, y) in mass_more.iter_mut() {
                    diagonal_times(d, x, y);
                }
            }
            None => {
                mats.push(&self.m_const);
                xs.push(a_w);
                ys.push(&mut *inertia);
                for (x, y) in mass_more.iter_mut() {
                    mats.push(&self.m_const);
                    xs.push(x);
                    ys.push(&mut **y);
                }
            }
        }
        if self.c_const_zero {
            damping.iter_mut().for_each(|d| *d = 0.0);
            for (_, y) in damping_more.iter_mut() {
                y.iter_mut().for_each(|d| *d = 0.0);
            }
        } else {
            mats.push(&self.c_const);
            xs.push(v_w);
            ys.push(&mut *damping);
            for (x, y) in damping_more.iter_mut() {
                mats.push(&self.c_const);
                xs.push(x);
                ys.push(&mut **y);
            }
        }
        self.products_on(rows, &mats, &xs, &mut ys);
        drop(ys);
        self.add_variable_mass(a_w, inertia);
        self.add_variable_damping(v_w, damping);
        self.times.products += t0.elapsed().as_secs_f64();
    }

    /// The inertia and damping forces `inertia = M·a_w`, `damping = C·v_w` alone, for a
    /// model without variable elements whose internal force at the iterate is already
    /// known (a linear model's first iteration starts at the last step's displacement, so
    /// `K·q` is the committed internal force): one pass over `M` (and `C` if not zero)
    /// instead of [`Assembler::update_transient`]'s pass over `K`, `M` and `C`.
    pub fn inertia_damping(
        &mut self,
        (a_w, v_w): (&[f64], &[f64]),
        (inertia, damping): (&mut [f64], &mut [f64]),
    ) {
        let t0 = std::time::Instant::now();
        self.constant_products(None, (a_w, v_w), (inertia, damping));
        self.times.products += t0.elapsed().as_secs_f64();
    }

    /// The damping force `damping = C·v_w` alone (zeroed without constant damping), the
    /// same values as [`Assembler::inertia_damping`]'s, for a step whose inertia force is
    /// already known.
    pub fn damping_force(&mut self, v_w: &[f64], damping: &mut [f64]) {
        let t0 = std::time::Instant::now();
        if self.c_const_zero {
            damping.iter_mut().for_each(|d| *d = 0.0);
        } else {
            self.products(&[&self.c_const], &[v_w], &mut [&mut *damping]);
        }
        self.add_variable_damping(v_w, damping);
        self.times.products += t0.elapsed().as_secs_f64();
    }

    /// For a model without variable elements, the products a solved linear step's state
    /// needs, in one pass over the constant matrices: its internal force `f_int = K·q`
    /// (the value [`Assembler::update`] forms), `mv = M·v` (the value
    /// [`Assembler::mass_times`] forms: the energy balance's kinetic energy) and
    /// `inertia = M·a_w`, the next step's first inertia force when its weighted
    /// acceleration is `a_w` (the value [`Assembler::inertia_damping`] forms). Each product
    /// is summed in the same order as alone, so the values are the same to the bit; a
    /// diagonal mass takes both of its products from the diagonal.
    pub fn linear_state_products(
        &mut self,
        (q, v, a_w): (&[f64], &[f64], &[f64]),
        (f_int, mv, inertia): (&mut [f64], &mut [f64], &mut [f64]),
    ) {
        let t0 = std::time::Instant::now();
        let mut mats: Vec<&CscMatrix> = vec![&self.k_const];
        let mut xs: Vec<&[f64]> = vec![q];
        let mut ys: Vec<&mut [f64]> = vec![f_int];
        match &self.m_diag {
            Some(d) => {
                diagonal_times(d, v, mv);
                diagonal_times(d, a_w, inertia);
            }
            None => {
                mats.extend([&self.m_const, &self.m_const]);
                xs.extend([v, a_w]);
                ys.push(&mut *mv);
                ys.push(&mut *inertia);
            }
        }
        self.products(&mats, &xs, &mut ys);
        drop(ys);
        self.add_variable_mass(v, mv);
        self.add_variable_mass(a_w, inertia);
        self.times.products += t0.elapsed().as_secs_f64();
    }

    /// `ys[k] = mats[k]·xs[k]` for constant matrices: in one pass over the non-zero
    /// entries of each when they are kept ([`nonzero_products`]: the same values to the
    /// bit), else over their shared pattern when every constant element is symmetric
    /// ([`crate::sparse::symmetric_products`]), else one scatter product each.
    fn products(&self, mats: &[&CscMatrix], xs: &[&[f64]], ys: &mut [&mut [f64]]) {
        self.products_on(None, mats, xs, ys);
    }

    /// [`Assembler::products`], on the rows of `rows` alone where the non-zero entries
    /// are kept ([`nonzero_products::nonzero_products_on`]), on every row otherwise.
    fn products_on(
        &self,
        rows: Option<&RowSet>,
        mats: &[&CscMatrix],
        xs: &[&[f64]],
        ys: &mut [&mut [f64]],
    ) {
        if let Some(nz) = &self.nonzero {
            let own = [&self.k_const, &self.m_const, &self.c_const];
            let picked: Option<Vec<&NonzeroColumns>> = mats
                .iter()
                .map(|&m| own.iter().position(|&o| std::ptr::eq(o, m)).map(|k| &nz[k]))
                .collect();
            if let Some(picked) = picked {
                match rows {
                    Some(rows) => {
                        nonzero_products::nonzero_products_on(&picked, xs, ys, rows, self.threads)
                    }
                    None => nonzero_products::nonzero_products(&picked, xs, ys, self.threads),
                }
                return;
            }
        }
        if self.const_symmetric {
            crate::sparse::symmetric_products(mats, xs, ys, self.threads);
        } else {
            for ((m, x), y) in mats.iter().zip(xs).zip(ys.iter_mut()) {
                m.mul_vec(x, y);
            }
        }
    }

    /// `f_int = K·q` (when asked for), `inertia = M·a_w`, `damping = C·v_w` in one pass over
    /// the constant matrices (C left out when it is zero: `damping` is then zeroed), plus
    /// the variable masses' and dashpots' parts.
    fn constant_products(
        &self,
        stiffness: Option<(&[f64], &mut [f64])>,
        (a_w, v_w): (&[f64], &[f64]),
        (inertia, damping): (&mut [f64], &mut [f64]),
    ) {
        let mut mats: Vec<&CscMatrix> = Vec::with_capacity(3);
        let mut xs: Vec<&[f64]> = Vec::with_capacity(3);
        let mut ys: Vec<&mut [f64]> = Vec::with_capacity(3);
        if let Some((q, f_int)) = stiffness {
            mats.push(&self.k_const);
            xs.push(q);
            ys.push(f_int);
        }
        match &self.m_diag {
            Some(d) => diagonal_times(d, a_w, inertia),
            None => {
                mats.push(&self.m_const);
                xs.push(a_w);
                ys.push(&mut *inertia);
            }
        }
        if self.c_const_zero {
            damping.iter_mut().for_each(|d| *d = 0.0);
        } else {
            mats.push(&self.c_const);
            xs.push(v_w);
            ys.push(&mut *damping);
        }
        self.products(&mats, &xs, &mut ys);
        self.add_variable_mass(a_w, inertia);
        self.add_variable_damping(v_w, damping);
    }

    /// Updates the variable elements and adds their resisting forces to `f_int` (and their
    /// tangents to `k_var` or the off-pattern store), without the products with the
    /// constant matrices: the whole update of the condensed Newton's iterations
    /// (`solvers/src/condensed.rs`).
    #[allow(clippy::too_many_arguments)]
    pub fn update_variable(
        &mut self,
        model: &mut Model,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        t: f64,
        dt: f64,
        f_int: &mut [f64],
        form_tangent: bool,
    ) -> Result<(), FemError> {
        let t0 = std::time::Instant::now();
        if form_tangent && !self.off_pattern {
            self.k_var.values.iter_mut().for_each(|x| *x = 0.0);
        }
        // State determination of every variable element, in parallel when there are many
        // (a train's wheels): each element only reads the trial vectors and writes itself.
        let (dofmap, maps, slots) = (&self.dofmap, &self.maps, &self.var_slot);
        let eval = |ei: usize,
                    entry: &mut crate::model::ElementEntry|
         -> Result<Evaluated, FemError> {
            let pick = |x: &[f64]| -> Vec<f64> {
                maps[ei]
                    .dofs
                    .iter()
                    .map(|&(n, d)| dofmap.value_at(x, n, d))
                    .collect()
            };
            let (ue, ve, ae) = (pick(q), pick(v), pick(a));
            entry
                .element
                .update(&TrialState {
                    time: t,
                    dt,
                    disp: &ue,
                    vel: &ve,
                    acc: &ae,
                })
                .map_err(|err| element_error(&entry.origin, err))?;
            let nd = ue.len();
            let mut fe = vec![0.0; nd];
            entry.element.resisting_force(&mut fe);
            if let Some(i) = fe.iter().position(|x| !x.is_finite()) {
                return Err(FemError::NonFinite(format!(
                    "element {} ({}) returned a non-finite resisting force at its DOF {i} (t = {t} s)",
                    entry.id,
                    entry.element.kind()
                )));
            }
            let ke = if form_tangent {
                let mut ke = DMatrix::zeros(nd, nd);
                entry.element.tangent_stiffness(&mut ke);
                check_finite(&ke, &entry.origin, "tangent stiffness")?;
                Some(ke)
            } else {
                None
            };
            Ok((fe, ke))
        };
        let mut entries: Vec<(usize, &mut crate::model::ElementEntry)> = model
            .elements
            .iter_mut()
            .enumerate()
            .filter(|(ei, _)| slots.get(*ei).is_some_and(|&s| s != u32::MAX))
            .collect();
        let nt = if entries.len() >= 16 { self.threads } else { 1 };
        let results = crate::parallel::map_mut(&mut entries, nt, |(ei, e)| eval(*ei, e));
        drop(entries);
        self.stats.element_updates += results.len();
        self.element_force_sq = 0.0;
        for (slot, r) in results.into_iter().enumerate() {
            let ei = self.variable[slot];
            let (fe, ke) = r?;
            // The force reference of the Newton check, formed here where each element's
            // force is scattered anyway (no second pass over the elements).
            self.element_force_sq += fe.iter().map(|x| x * x).sum::<f64>();
            scatter_vec(&self.dofmap, &self.maps[ei].dofs, &fe, f_int);
            if let Some(ke) = ke {
                let nd = fe.len();
                for &(p, ab, c) in &self.maps[ei].scatter {
                    self.k_var.values[p as usize] += c * ke.as_slice()[col_major(ab as usize, nd)];
                }
                if self.off_pattern {
                    self.off[slot].k = ke;
                }
            }
        }
        self.times.elements += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// `√(Σ_e |f_e|²)`: the size of the variable elements' own resisting forces `f_e` (each
    /// in its element's DOFs, before they are summed into `f_int`) at the last
    /// [`Assembler::update_variable`] of this process; 0 before any.
    ///
    /// Where elements meet at a free node their forces cancel, so the assembled `|f_int|`
    /// can be far below the forces each element carries; the round-off of the residual is
    /// relative to the latter (each `f_e` is formed from terms of its own size and the sum
    /// over a node's elements loses digits relative to the largest of them). It lies
    /// between `1/√k` and 1 times the norm of the per-node sums `Σ_e |f_e,i|` (k the most
    /// elements at a DOF), so it serves as that reference up to a constant factor.
    /// Constant (linear) elements are not included: their force is one product `K·q`.
    pub fn element_force_norm(&self) -> f64 {
        self.element_force_sq.sqrt()
    }

    /// The variable elements' current resisting forces (as last determined, nothing
    /// re-evaluated) added to `f`.
    pub fn add_variable_resisting(&self, model: &Model, f: &mut [f64]) {
        for &ei in &self.variable {
            let map = &self.maps[ei];
            let mut fe = vec![0.0; map.dofs.len()];
            model.elements[ei].element.resisting_force(&mut fe);
            scatter_vec(&self.dofmap, &map.dofs, &fe, f);
        }
    }

    /// `inertia += M_var·a_w`, `damping += C_var·v_w`: the variable elements' (and re-formed
    /// masses') part of the inertia and damping forces.
    pub fn add_variable_inertia_damping(
        &self,
        a_w: &[f64],
        v_w: &[f64],
        inertia: &mut [f64],
        damping: &mut [f64],
    ) {
        self.add_variable_mass(a_w, inertia);
        self.add_variable_damping(v_w, damping);
    }

    /// The equations the variable elements touch (off-pattern mode; sorted, without
    /// repeats; empty in the direct mode).
    pub fn variable_equations(&self) -> Vec<usize> {
        let mut e: Vec<usize> = self
            .off
            .iter()
            .flat_map(|o| o.terms.iter().map(|t| t.1 as usize))
            .collect();
        e.sort_unstable();
        e.dedup();
        e
    }

    /// `out = M·x` (constant and variable mass).
    pub fn mass_times(&self, x: &[f64], out: &mut [f64]) {
        if let Some(d) = &self.m_diag {
            diagonal_times(d, x, out);
        } else if self.const_symmetric {
            self.products(&[&self.m_const], &[x], &mut [out]);
        } else {
            self.m_const.mul_vec(x, out);
        }
        self.add_variable_mass(x, out);
    }

    /// `out += M_var·x`: masses re-formed each step, on the pattern or off it.
    fn add_variable_mass(&self, x: &[f64], out: &mut [f64]) {
        if self.m_var_used {
            self.m_var.mul_vec_add(1.0, x, out);
        }
        for off in &self.off {
            if let Some(m) = &off.m {
                off_pattern_times(off, m, x, out);
            }
        }
    }

    /// `out += C_var·x`: damping of variable elements, on the pattern or off it.
    fn add_variable_damping(&self, x: &[f64], out: &mut [f64]) {
        if self.c_var_used {
            self.c_var.mul_vec_add(1.0, x, out);
        }
        for off in &self.off {
            if let Some(c) = &off.c {
                off_pattern_times(off, c, x, out);
            }
        }
    }

    /// The constant mass's diagonal when it is diagonal (every stored value off the
    /// diagonal exactly zero: a lumped mass), which every product with `M` then uses.
    pub fn mass_diagonal(&self) -> Option<&[f64]> {
        self.m_diag.as_deref()
    }

    /// Whether every mass is the constant one (`m_const`): no element's mass is re-formed
    /// between steps (time-varying masses and carried masses are, into `m_var` or their
    /// off-pattern store). Then a product `M·x` formed in one step holds in the next.
    pub fn mass_is_constant(&self) -> bool {
        self.mass_elems.is_empty()
    }

    /// Whether any damping can act: a constant damping matrix with a non-zero value, or
    /// variable elements' damping (on the pattern or off it). Without it `C·x` is zero.
    pub fn has_damping(&self) -> bool {
        !self.c_const_zero || self.c_var_used || self.off.iter().any(|o| o.c.is_some())
    }

    /// `out += C·x` (constant and variable damping).
    pub fn damping_times_add(&self, x: &[f64], out: &mut [f64]) {
        if self.c_const_zero {
            // Nothing to add from the constant part.
        } else if self.const_symmetric && (self.c_const.n >= 20_000 || self.columns_kept) {
            let mut cx = vec![0.0; self.c_const.n];
            self.products(&[&self.c_const], &[x], &mut [&mut cx]);
            for (o, c) in out.iter_mut().zip(&cx) {
                *o += c;
            }
        } else {
            self.c_const.mul_vec_add(1.0, x, out);
        }
        self.add_variable_damping(x, out);
    }

    /// Off-pattern mode: the variable elements' effective matrices
    /// `k·K_e + m·M_e + c·C_e` as `(row, column, value)` equation triplets appended to
    /// `out` (duplicates to be summed). Empty in the direct mode, where they are inside
    /// [`Assembler::effective`].
    pub fn variable_triplets(&self, w: Coefficients, out: &mut Vec<(usize, usize, f64)>) {
        if !self.off_pattern {
            return;
        }
        for off in &self.off {
            // The element's own size, not the largest DOF with an equation: a wheel on a
            // rigid rail has its rail DOFs last and fixed.
            let nd = off.ndof;
            let mut e = DMatrix::zeros(nd, nd);
            for (coef, mat) in w.weigh(Some(&off.k), off.m.as_ref(), off.c.as_ref()) {
                if let Some(mat) = mat.filter(|m| m.nrows() == nd && coef != 0.0) {
                    e += mat * coef;
                }
            }
            for &(b, eb, cb) in &off.terms {
                for &(a, ea, ca) in &off.terms {
                    let v = e[(a as usize, b as usize)];
                    if v != 0.0 {
                        out.push((ea as usize, eb as usize, ca * cb * v));
                    }
                }
            }
        }
    }

    /// `out = k·(K_const + K_var) + m·M + c·C` on the common pattern (off-pattern mode:
    /// the constant elements and the non-moving variable masses only).
    pub fn effective(&self, w: Coefficients, out: &mut CscMatrix) {
        if out.pattern_id != self.k_const.pattern_id {
            *out = self.k_const.zeros_like();
        }
        out.set_combination(&self.effective_terms(w));
    }

    /// The matrices of [`Assembler::effective`] with their coefficients.
    fn effective_terms(&self, w: Coefficients) -> Vec<(f64, &CscMatrix)> {
        [
            (w.k, &self.k_const),
            (w.k, &self.k_var),
            (w.m, &self.m_const),
            (w.m, &self.m_var),
            (w.c, &self.c_const),
            (w.c, &self.c_var),
        ]
        .into_iter()
        .filter(|(_, m)| m.n == self.k_const.n) // unused variable matrices are kept empty
        .collect()
    }

    /// `K`, `M`, `C` on the patterns of their own non-zero values, for the products, when
    /// every constant element is symmetric (the gather form) and the equations fit 32-bit
    /// rows; else `None`.
    fn nonzero_matrices(&self) -> Option<[NonzeroColumns; 3]> {
        if !self.const_symmetric {
            return None;
        }
        Some([
            NonzeroColumns::of(&self.k_const)?,
            NonzeroColumns::of(&self.m_const)?,
            NonzeroColumns::of(&self.c_const)?,
        ])
    }

    /// Stored entries of the shared pattern and the non-zero values of `K`, `M` and `C`
    /// in it (the entries the products read when kept apart; for the benchmark's report).
    pub fn constant_nonzeros(&self) -> (usize, [usize; 3]) {
        let count = |m: &CscMatrix| m.values.iter().filter(|&&v| v != 0.0).count();
        (
            self.k_const.nnz(),
            [
                count(&self.k_const),
                count(&self.m_const),
                count(&self.c_const),
            ],
        )
    }

    /// Equations whose column of `M` (constant and variable mass on the pattern, as
    /// [`Assembler::effective`] with [`Coefficients::MASS`] forms it) holds no non-zero value; the
    /// off-pattern elements' masses are not looked at.
    pub fn massless_on_pattern(&self) -> Vec<bool> {
        let a = &self.k_const;
        let terms = self.effective_terms(Coefficients::MASS);
        (0..a.n)
            .map(|j| {
                (a.col_ptr[j]..a.col_ptr[j + 1]).all(|p| {
                    let mut v = 0.0;
                    for (c, m) in &terms {
                        if *c != 0.0 {
                            v += c * m.values[p];
                        }
                    }
                    v == 0.0
                })
            })
            .collect()
    }

    /// [`Assembler::effective`] on the columns `j` with `keep[j]` only: `out` gets the
    /// pattern's id and size, the pattern and the values of those columns (the same values
    /// to the bit: each entry is summed over the same terms in the same order) and no entry
    /// in the other columns. A rank of a model shared by several ones keeps this way only
    /// the columns its share of the partitioned solver reads
    /// (`railfem_solvers::partition::Partitioned::columns_read`), not a copy of the whole
    /// matrix.
    pub fn effective_columns(&self, w: Coefficients, keep: &[bool], out: &mut CscMatrix) {
        let a = &self.k_const;
        let kept = |j: usize| keep.get(j).copied().unwrap_or(false);
        let same = out.pattern_id == a.pattern_id
            && out.n == a.n
            && (0..a.n).all(|j| {
                let len = out.col_ptr[j + 1] - out.col_ptr[j];
                len == if kept(j) {
                    a.col_ptr[j + 1] - a.col_ptr[j]
                } else {
                    0
                }
            });
        if !same {
            let len = (0..a.n)
                .filter(|&j| kept(j))
                .map(|j| a.col_ptr[j + 1] - a.col_ptr[j])
                .sum();
            let mut col_ptr = Vec::with_capacity(a.n + 1);
            let mut row_idx = Vec::with_capacity(len);
            col_ptr.push(0);
            for j in 0..a.n {
                if kept(j) {
                    row_idx.extend_from_slice(&a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]]);
                }
                col_ptr.push(row_idx.len());
            }
            *out = CscMatrix {
                n: a.n,
                values: vec![0.0; row_idx.len()],
                col_ptr,
                row_idx,
                pattern_id: a.pattern_id,
            };
        }
        let terms = self.effective_terms(w);
        for j in (0..a.n).filter(|&j| kept(j)) {
            let (from, to) = (a.col_ptr[j], out.col_ptr[j]);
            for k in 0..a.col_ptr[j + 1] - from {
                let mut v = 0.0;
                for (c, m) in &terms {
                    if *c != 0.0 {
                        v += c * m.values[from + k];
                    }
                }
                out.values[to + k] = v;
            }
        }
    }

    /// External force at time `t` (N, N·m) into `out`: nodal loads, gravity, Eq. 5
    /// pseudo-loads of carried masses, ground motion and moving forces. `load_factor`
    /// scales everything (static load stepping).
    pub fn external_force(
        &mut self,
        model: &Model,
        t: f64,
        load_factor: f64,
        out: &mut [f64],
    ) -> Result<(), FemError> {
        self.external_force_rows(model, t, load_factor, out, None)
    }

    /// [`Assembler::external_force`] (`load_factor` 1) on the rows of `rows` alone, the
    /// others left as they are: `Ok(false)`, with nothing written, where some load could
    /// reach a row outside `rows` (`assembly/held_loads.rs`).
    pub fn external_force_on(
        &mut self,
        model: &Model,
        t: f64,
        out: &mut [f64],
        rows: &RowSet,
    ) -> Result<bool, FemError> {
        if !self.loads_within(model, rows) {
            return Ok(false);
        }
        self.external_force_rows(model, t, 1.0, out, Some(rows))?;
        Ok(true)
    }

    /// [`Assembler::external_force`], its passes over the equations (zero, the constant
    /// gravity, the finiteness check) on the rows of `rows` (every row: `None`); the loads
    /// that reach a few rows are added wherever they act.
    fn external_force_rows(
        &mut self,
        model: &Model,
        t: f64,
        load_factor: f64,
        out: &mut [f64],
        rows: Option<&RowSet>,
    ) -> Result<(), FemError> {
        self.set_time(model, t);
        let parts = held_loads::parts(rows, out.len());
        for p in &parts {
            out[p.clone()].iter_mut().for_each(|x| *x = 0.0);
            for (o, g) in out[p.clone()]
                .iter_mut()
                .zip(&self.gravity_fixed[p.clone()])
            {
                *o += g;
            }
        }
        let grav = model
            .analysis
            .gravity
            .map(Vector3::from)
            .unwrap_or_else(Vector3::zeros);
        // Carried masses: f = M·(g − a_ref) in nodal axes.
        for (ei, m) in &self.carried_mass {
            let map = &self.maps[*ei];
            let mut w = Vec::with_capacity(map.dofs.len());
            for &(node, d) in &map.dofs {
                let slot = self.slot_of[node];
                let (lin, ang) = if slot == u32::MAX {
                    (grav, Vector3::zeros())
                } else {
                    let r = &self.motions[slot as usize];
                    (grav - r.acceleration, -r.angular_acceleration)
                };
                w.push(kinematic_vector(&self.kin[node], d, &lin, &ang));
            }
            let f = m * nalgebra::DVector::from_vec(w);
            scatter_vec(&self.dofmap, &map.dofs, f.as_slice(), out);
        }
        // Masses that change between steps (a mass moving along a beam): M(t)·g now.
        if model.analysis.gravity.is_some() {
            for &ei in &self.gravity_variable {
                let map = &self.maps[ei];
                let nd = map.dofs.len();
                let mut m = DMatrix::zeros(nd, nd);
                model.elements[ei].element.mass(&mut m);
                self.add_mass_times_uniform(ei, &m, &grav, out);
            }
        }
        let mut gi = 0;
        for l in &model.loads {
            match l {
                Load::Nodal {
                    node,
                    dof,
                    value,
                    series,
                } => {
                    let f = value * series.value(t);
                    for (e, c) in self.dofmap.terms(*node, *dof) {
                        out[e] += c * f;
                    }
                }
                Load::GroundMotion {
                    direction,
                    series,
                    scale,
                } => {
                    let ag = scale * series.value(t);
                    for (o, r) in out.iter_mut().zip(&self.ground_unit[gi]) {
                        *o += r * ag;
                    }
                    // Carried masses ride on the moving ground too: their DOFs are
                    // relative to a carrier that travels over the ground, so they feel
                    // `−M·r·a_g` like every other mass, with `r` the ground direction in
                    // their nodal axes at time t (the axes turn as the carrier moves).
                    if ag != 0.0 {
                        let lin = -(direction * ag);
                        for (ei, m) in &self.carried_mass {
                            self.add_mass_times_uniform(*ei, m, &lin, out);
                        }
                    }
                    gi += 1;
                }
                Load::MovingForce(mf) => self.add_moving_force(mf, t, out),
                Load::Registered(r) => r.load.nodal_forces(t, &mut |node, dof, f| {
                    for (e, c) in self.dofmap.terms(node, dof) {
                        out[e] += c * f;
                    }
                })?,
            }
        }
        if load_factor != 1.0 {
            out.iter_mut().for_each(|x| *x *= load_factor);
        }
        let not_finite = parts.iter().find_map(|p| {
            out[p.clone()]
                .iter()
                .position(|x| !x.is_finite())
                .map(|k| p.start + k)
        });
        if let Some(i) = not_finite {
            let (n, d) = self.dofmap.dof_of(i);
            return Err(FemError::NonFinite(format!(
                "external load at {} is not finite at t = {t} s",
                model.dof_name(n, d)
            )));
        }
        Ok(())
    }

    fn add_moving_force(&self, mf: &MovingForce, t: f64, out: &mut [f64]) {
        let Some((k, xi)) = mf.locate(t) else {
            return;
        };
        let (a, b) = mf.segments[k];
        let (xa, xb) = mf.ends[k];
        let f = MovingForce::nodal_forces(mf.force, xa, xb, xi);
        for (node, fv, mv) in [(a, f.force_i, f.moment_i), (b, f.force_j, f.moment_j)] {
            for d in 0..3 {
                for (e, c) in self.dofmap.terms_at(node, d) {
                    out[e] += c * fv[d];
                }
                for (e, c) in self.dofmap.terms_at(node, d + 3) {
                    out[e] += c * mv[d];
                }
            }
        }
    }

    /// Commits every variable element.
    pub fn commit(&self, model: &mut Model) {
        for &ei in &self.variable {
            model.elements[ei].element.commit();
        }
    }

    /// Reverts every variable element.
    pub fn revert(&self, model: &mut Model) {
        for &ei in &self.variable {
            model.elements[ei].element.revert();
        }
    }

    /// Indices of the variable elements.
    pub fn variable_elements(&self) -> &[usize] {
        &self.variable
    }

    /// Brings element `ei` to the state `(q, v, a)` at time `t` if it is a constant
    /// element. Constant elements are never updated while the driver iterates (their
    /// matrices are cached), so their own state — and hence their reported outputs, such
    /// as a beam's end forces — would otherwise stay at the reference state. Recorders call
    /// this before reading an element's outputs; variable elements are left alone (they
    /// already hold the converged state).
    pub fn refresh_constant(
        &self,
        model: &mut Model,
        ei: usize,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<(), FemError> {
        if self.variable.contains(&ei) {
            return Ok(());
        }
        let (ue, ve, ae) = (
            self.element_values(ei, q),
            self.element_values(ei, v),
            self.element_values(ei, a),
        );
        let entry = &mut model.elements[ei];
        entry
            .element
            .update(&TrialState {
                time: t,
                dt: 0.0,
                disp: &ue,
                vel: &ve,
                acc: &ae,
            })
            .map_err(|err| element_error(&entry.origin, err))
    }

    /// Element DOF values of element `ei` from an equation vector (for recorders).
    pub fn element_values(&self, ei: usize, q: &[f64]) -> Vec<f64> {
        let mut v = Vec::new();
        self.gather(ei, q, &mut v);
        v
    }

    /// Total dissipated energy reported by elements (J).
    pub fn dissipated_energy(&self, model: &Model) -> f64 {
        self.variable
            .iter()
            .map(|&ei| model.elements[ei].element.dissipated_energy())
            .sum()
    }

    /// The dissipated energy reported by elements (J), as `[friction, material]`
    /// ([`crate::element::DissipationKind`]).
    pub fn dissipated_by_kind(&self, model: &Model) -> [f64; 2] {
        let mut d = [0.0; 2];
        for &ei in &self.variable {
            let e = &model.elements[ei].element;
            match e.dissipation_kind() {
                DissipationKind::Friction => d[0] += e.dissipated_energy(),
                DissipationKind::Material => d[1] += e.dissipated_energy(),
            }
        }
        d
    }
}

/// `out += A_e·x` for an off-pattern element matrix `a` over its equation terms.
/// `Some(diagonal)` of `m` if every stored value off the diagonal is exactly zero.
fn diagonal_of(m: &CscMatrix) -> Option<Vec<f64>> {
    let mut d = vec![0.0; m.n];
    for (j, dj) in d.iter_mut().enumerate() {
        for p in m.col_ptr[j]..m.col_ptr[j + 1] {
            if m.row_idx[p] == j {
                *dj = m.values[p];
            } else if m.values[p] != 0.0 {
                return None;
            }
        }
    }
    Some(d)
}

/// `out_i = d_i·x_i`.
fn diagonal_times(d: &[f64], x: &[f64], out: &mut [f64]) {
    for ((o, m), v) in out.iter_mut().zip(d).zip(x) {
        *o = m * v;
    }
}

fn off_pattern_times(off: &OffPattern, a: &DMatrix<f64>, x: &[f64], out: &mut [f64]) {
    let nd = a.nrows();
    let mut xe = vec![0.0; nd];
    for &(d, e, c) in &off.terms {
        xe[d as usize] += c * x[e as usize];
    }
    let ye = a * nalgebra::DVector::from_vec(xe);
    for &(d, e, c) in &off.terms {
        out[e as usize] += c * ye[d as usize];
    }
}

#[inline]
fn col_major(ab: usize, n: usize) -> usize {
    // ab = a·n + b  →  column-major index of (a, b) = b·n + a.
    let (a, b) = (ab / n, ab % n);
    b * n + a
}

/// `out += Lᵀ·k·L` for an element matrix `k` over its DOFs' equation terms, into the
/// entries `out`'s pattern holds; with `diagonal`, its diagonal terms also into that vector
/// of every equation, added in the same order as into the matrix (so that each value is
/// the whole matrix's diagonal to the bit, also for a column `out` does not hold).
fn scatter_dense(
    map: &DofMap,
    dofs: &[(usize, usize)],
    k: &DMatrix<f64>,
    out: &mut CscMatrix,
    mut diagonal: Option<&mut [f64]>,
) {
    for (b, &(nb, db)) in dofs.iter().enumerate() {
        for (eb, cb) in map.terms_at(nb, db) {
            for (a, &(na, da)) in dofs.iter().enumerate() {
                let v = k[(a, b)];
                if v == 0.0 {
                    continue;
                }
                for (ea, ca) in map.terms_at(na, da) {
                    if let Some(p) = out.position(ea, eb) {
                        out.values[p] += ca * cb * v;
                    }
                    if let Some(d) = diagonal.as_deref_mut().filter(|_| ea == eb) {
                        d[ea] += ca * cb * v;
                    }
                }
            }
        }
    }
}

impl Assembler {
    /// Adds `M·r` of element `ei` to `out`: `r` the element's DOF values of a uniform
    /// translational acceleration `lin` (global axes) seen in each node's axes, so `M·r` is
    /// the force that acceleration's field puts on the element's mass (gravity: `lin = g`;
    /// ground motion: `lin = −a_g`).
    fn add_mass_times_uniform(
        &self,
        ei: usize,
        m: &DMatrix<f64>,
        lin: &Vector3<f64>,
        out: &mut [f64],
    ) {
        let map = &self.maps[ei];
        let r: Vec<f64> = map
            .dofs
            .iter()
            .map(|&(node, d)| kinematic_vector(&self.kin[node], d, lin, &Vector3::zeros()))
            .collect();
        let f = m * nalgebra::DVector::from_vec(r);
        scatter_vec(&self.dofmap, &map.dofs, f.as_slice(), out);
    }
}

fn scatter_vec(map: &DofMap, dofs: &[(usize, usize)], f: &[f64], out: &mut [f64]) {
    for (a, &(n, d)) in dofs.iter().enumerate() {
        if f[a] == 0.0 {
            continue;
        }
        for (e, c) in map.terms_at(n, d) {
            out[e] += c * f[a];
        }
    }
}

fn check_finite(m: &DMatrix<f64>, origin: &str, what: &str) -> Result<(), FemError> {
    if m.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(FemError::NonFinite(format!(
            "{origin}: returned a non-finite {what}; its inputs are beyond what f64 can hold (check the sizes of its values); the run stops here"
        )))
    }
}

/// An element's failure, named by where the element was defined (file, table, index).
fn element_error(origin: &str, e: ElementError) -> FemError {
    match e {
        ElementError::NonFinite { what } => FemError::NonFinite(format!("{origin}: {what}")),
        ElementError::Invalid(m) => FemError::input(origin, m),
    }
}
