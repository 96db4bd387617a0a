//! The partitioned solver: static condensation of the constant structure in blocks, so that
//! a Newton iteration refactors only what the moving and nonlinear elements changed.
//!
//! Write the effective tangent as `K = A + V`: `A = c_K·K + c_M·M + c_C·C` of the constant
//! (linear, fixed) elements, which changes only with `Δt`, and `V` the variable elements'
//! part, non-zero only on the equations `W` they touch (a train's wheels and the rail nodes
//! under them). The equations are split once, from the graph of `A`, into the interiors
//! `I_b` of blocks and a *top* set `T`: the separators between blocks (level sets of a
//! breadth-first search from a pseudo-peripheral equation, so interiors of different blocks
//! are never coupled) and every connected component smaller than a block (a carriage's
//! bodies). Each factorization, the interior equations in `W` are *promoted* to `T`, so
//! that `V` lives in `T × T` only. With `B_b` the top equations coupled to what remains of
//! block `b`'s interior, eliminating the interiors gives the Schur complement
//!
//! ```text
//! S = A_TT + V_TT − Σ_b A_{B_b I_b} A_{I_b I_b}⁻¹ A_{I_b B_b},
//! S·x_T = r_T − Σ_b A_{T I_b} A_{I_b I_b}⁻¹ r_{I_b},
//! x_{I_b} = A_{I_b I_b}⁻¹ (r_{I_b} − A_{I_b B_b} x_{B_b}).
//! ```
//!
//! A promoted equation does not refactor its block. With `P ⊂ I_b` promoted and `I' = I_b∖P`,
//! the block inverse `A_II⁻¹` already knows the condensation onto `P ∪ B`: with
//! `Z = A_II⁻¹·E_P` (`|P|` solves with the block's base factor), `G = Z_P` (the `P × P` part
//! of `A_II⁻¹`, i.e. the inverse of the Schur complement onto `P`) and `W_P = Zᵀ·A_IB`,
//!
//! ```text
//! S_PP = G⁻¹,   S_PB = G⁻¹·W_P,   S_BB = A_BB − A_BI·A_II⁻¹·A_IB + W_Pᵀ·G⁻¹·W_P,
//! r'_P = G⁻¹·y_P,   r'_B = r_B − A_BI·y + W_Pᵀ·G⁻¹·y_P        (y = A_II⁻¹·r_I),
//! x_I = y + Z·G⁻¹·(x_P − y_P)                                 (y = A_II⁻¹·(r_I − A_IB·x_B)),
//! ```
//!
//! which follow from the block form of the inverse. A block's base factor and its base
//! correction `A_BI·A_II⁻¹·A_IB` are made once per `A` (a new `Δt`); a wheel moving onto new
//! rail nodes costs a triangular solve in its block for each newly promoted equation, never
//! a factorization: the columns of `Z` of the equations that stay promoted are kept. A unit
//! column's forward pass starts at its equation's place in the elimination order; in the
//! forward form ([`PromotionForm::Forward`], `partition/forward.rs`) a promotion needs
//! only forward passes, along elimination-tree paths. Each iteration then costs one
//! factorization of the small top system and two triangular solves per block (in
//! parallel).
//!
//! `A` must be symmetric positive definite on every block interior (any transient: the mass
//! term makes it so); `V` may be unsymmetric (the top system then uses LU).
//!
//! **Across ranks** ([`Partitioned::set_exchange`], [`crate::exchange`]). The three sums
//! over `b` above are independent per block, so the blocks can be shared among processes:
//! rank `k` of `P` owns a contiguous range of blocks, those whose middle falls in the `k`-th
//! `P`-th of the interior equations (a rule of the structure alone, so every rank finds the
//! same split without talking). Every rank holds the same pattern of `A` and the same
//! variable triplets (the build is replicated, and so are the variable elements), hence knows the split, the
//! promoted sets and the top set; of `A`'s values a rank needs only the columns it reads
//! ([`Partitioned::columns_read`]: its blocks' interiors, and on rank 0 the base top set),
//! so the matrix it hands to [`Partitioned::factor`] may hold just those. Per factorization each rank factors and promotes its own blocks and
//! sends rank 0 what changed of their condensation (`C` after a new `A`, `G⁻¹` and `W_P`
//! after a new promotion); rank 0 forms `S` from them, in block order, as one process does,
//! factors it and sends the outcome. Per solve each rank condenses its blocks' right-hand
//! sides onto their boundaries and sends those `|B_b| + |P_b|` numbers to rank 0, which
//! sums them in block order, solves the top system and sends `x_T` to every rank; each
//! rank recovers its interiors and every rank receives all of them, so that all ranks end
//! with the whole solution. The operations and their order are those of one process: the
//! answers are the same to the last bit (tests/distributed.rs checks 1e-12).
//!
//! The residual's rows may be shared too (`partition/rows.rs`): each rank forms only the
//! rows it owns (those this solver reads on it) and the norms of the convergence test are
//! summed over the ranks in block order.

use crate::chunks::Shared;
use crate::dense::DenseLu;
use crate::exchange::{decode_status, encode_status, Comm, CommStats, Exchange};
use crate::linear::{solver_for, LinearSolver, SolverError, SparseCholesky};
use crate::top_chain::TopChain;
use railfem_framework::parallel::{map_mut as par_each, threads};
use railfem_framework::sparse::CscMatrix;
use std::ops::Range;
use std::sync::Arc;
use std::time::Instant;

mod forward;
mod frozen;
mod reduced;
mod reduced_cuts;
mod refactor;
mod rows;

pub use forward::PromotionForm;
pub use reduced::ReducedBasis;

const NONE: u32 = u32::MAX;

/// Settings of the partition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartitionOptions {
    /// Target number of interior equations per block.
    pub block_size: usize,
    /// Threads for the block work (`0`: all cores).
    pub threads: usize,
    /// Blocks per group of the top chain's second-level condensation
    /// ([`crate::top_chain`]); `0` or `1`: none, every iteration factors the whole top
    /// system.
    pub top_group_blocks: usize,
    /// How promotions form their condensation (`partition/forward.rs`).
    pub promotion_form: PromotionForm,
}

impl Default for PartitionOptions {
    fn default() -> Self {
        PartitionOptions {
            block_size: 3000,
            threads: 0,
            top_group_blocks: 8,
            promotion_form: PromotionForm::Columns,
        }
    }
}

/// Work counters and times of the partitioned solver.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PartitionStats {
    /// Symbolic analyses: splits of a pattern into blocks, their boundaries and the top
    /// chain's groups ([`Partitioned::prepare`]), once per pattern.
    pub analyses: usize,
    /// Number of blocks.
    pub blocks: usize,
    /// Equations in block interiors (before promotion).
    pub interior_equations: usize,
    /// Separator and small-component equations (the top set before promotion).
    pub base_top_equations: usize,
    /// Top equations at the last factorization (promotions included).
    pub top_equations: usize,
    /// Block factorizations (with their condensed corrections): once per block and `A`.
    pub block_factorizations: usize,
    /// Promotions formed (a block's promoted set changed: `|P|` solves, no factorization).
    pub promotions: usize,
    /// Of the promotions' columns `A_II⁻¹·e_p`: those solved with the block's base factor,
    /// and those kept from the block's previous promotion.
    pub promotion_columns_solved: usize,
    /// See [`PartitionStats::promotion_columns_solved`].
    pub promotion_columns_kept: usize,
    /// Of the columns solved in the forward form ([`PromotionForm::Forward`]): the rows of
    /// their elimination-tree paths, summed, and the longest path.
    pub promotion_reach_rows: usize,
    /// See [`PartitionStats::promotion_reach_rows`].
    pub promotion_reach_max: usize,
    /// Factorizations of the top system.
    pub top_factorizations: usize,
    /// Right-hand sides solved.
    pub solves: usize,
    /// Seconds spent factoring blocks and forming their corrections.
    pub time_blocks: f64,
    /// Seconds spent forming promotions.
    pub time_promote: f64,
    /// Seconds spent forming and factoring the top system.
    pub time_top: f64,
    /// Of `time_top`: seconds spent forming the top system (its constant part when stale,
    /// the triplet layout and pattern when it changed, the variable elements' values).
    pub time_top_form: f64,
    /// Of `time_top`: seconds in the top solver's factorization (symbolic analysis when the
    /// pattern changed, numeric factorization every time).
    pub time_top_factor: f64,
    /// Symbolic analyses (orderings) of the top system.
    pub top_symbolic_analyses: usize,
    /// Times the constant part `S_A` of the top system was formed anew.
    pub top_constant_forms: usize,
    /// Of the formings: those whose triplets changed layout but gave the last pattern again
    /// (its symbolic analysis kept).
    pub top_pattern_repeats: usize,
    /// Stored entries of the top system.
    pub top_nnz: usize,
    /// Stored entries of its last factor (`L` of a Cholesky factorization; 0 for sparse
    /// LU, whose factor size is not exposed).
    pub top_factor_nnz: usize,
    /// Equations of the system factored at the last factorization: the top set less the
    /// inner equations of the condensed groups ([`crate::top_chain`]).
    pub top_reduced_equations: usize,
    /// Groups of the top chain condensed at the last factorization.
    pub top_groups_condensed: usize,
    /// Groups of the top chain in all.
    pub top_groups: usize,
    /// Groups condensed anew (their `M_ii` factored).
    pub top_group_condensations: usize,
    /// Times the variable elements' triplets changed layout but fitted the cached pattern
    /// of the top system (no constant part formed, no symbolic analysis).
    pub top_refits: usize,
    /// Seconds spent in solves.
    pub time_solve: f64,
    /// Ranks the solver runs on (1: one process).
    pub ranks: usize,
    /// Blocks this rank owns (factors, condenses and back-substitutes).
    pub owned_blocks: usize,
    /// Interior equations of the owned blocks.
    pub owned_interior_equations: usize,
    /// Of the owned blocks' current factors: the values faer stored for `L` (diagonal
    /// included) and the off-diagonal non-zeros the solves read
    /// ([`crate::compact_factor`]).
    pub factor_values: usize,
    /// See [`PartitionStats::factor_values`].
    pub factor_nonzeros: usize,
    /// This rank's messages (zero in one process).
    pub comm: CommStats,
}

/// One block's base factor (no promotion) and condensed correction.
struct BlockState {
    /// Equations eliminated inside the block (global, sorted).
    interior: Vec<usize>,
    /// Top equations coupled to the interior (global, sorted).
    boundary: Vec<usize>,
    factor: SparseCholesky,
    /// `A_{I B}` by boundary column: `(local interior row, value)`.
    coupling: Vec<Vec<(u32, f64)>>,
    /// `C = A_{B I} A_{I I}⁻¹ A_{I B}`, column-major `|B| × |B|`.
    correction: Vec<f64>,
    /// `C_B = L⁻¹·P·A_IB` by rows, while the block has promoted equations in the forward
    /// form (`partition/forward.rs`).
    forward_coupling: Option<forward::CouplingRows>,
}

/// A promotion's columns (module documentation; `partition/forward.rs`).
enum Solved {
    /// `Z = A_II⁻¹·E_P`, column-major `|I| × |P|`.
    Columns(Vec<f64>),
    /// `Y = L⁻¹·P·E_P`, each column on its elimination-tree path.
    Forward(Vec<crate::compact_factor::ForwardColumn>),
}

impl Solved {
    fn heap_bytes(&self) -> usize {
        match self {
            Solved::Columns(z) => 8 * z.capacity(),
            Solved::Forward(y) => y
                .iter()
                .map(|c| c.heap_bytes() + std::mem::size_of_val(c))
                .sum(),
        }
    }
}

/// The condensation of a block onto its promoted equations `P` (module documentation).
struct Promotion {
    /// Promoted equations (global, sorted) and their local interior indices.
    promoted: Vec<usize>,
    local: Vec<usize>,
    /// `Z = A_II⁻¹·E_P`, or `Y = L⁻¹·P·E_P` ([`PromotionForm`]).
    z: Solved,
    /// `G⁻¹`, column-major `|P| × |P|`.
    g_inv: Vec<f64>,
    /// `W_P = Zᵀ·A_IB`, column-major `|P| × |B|`.
    w_p: Vec<f64>,
    /// Its terms of the top system, formed with it ([`promoted_products`]) so that a new
    /// top system re-forms only the blocks whose promotion changed.
    products: Products,
    /// Of the columns of `Z`: how many were solved, and how many kept from the last
    /// promotion.
    columns: [usize; 2],
    /// Of the solved columns in the forward form: their paths' rows, summed, and the
    /// longest.
    reach: [usize; 2],
}

struct Block {
    /// The block's interior equations (global, sorted).
    all: Vec<usize>,
    /// Top equations coupled to the interior (global, sorted): known on every rank, from
    /// the pattern alone.
    boundary: Vec<usize>,
    /// The promoted equations of the last factorization (global, sorted), on every rank.
    promoted: Vec<usize>,
    /// Owner only: the base factor and the promotion.
    base: Option<BlockState>,
    promotion: Option<Promotion>,
    /// Owner on a rank other than 0: the base correction, or the promotion, changed since
    /// they were last sent to rank 0.
    base_unsent: bool,
    promotion_unsent: bool,
    /// Its interior is held at its present values: the solves skip its passes
    /// ([`Partitioned::set_frozen_blocks`]).
    frozen: bool,
    /// Its interior is constrained to a reduced basis (`partition/reduced.rs`).
    reduced: Option<reduced::Reduced>,
}

/// Rank 0's copy of a block another rank owns: what the top system needs of it.
#[derive(Default, Clone)]
struct Received {
    /// `C = A_BI·A_II⁻¹·A_IB` (`|B| × |B|`).
    correction: Vec<f64>,
    /// `G⁻¹` (`|P| × |P|`) and `W_P` (`|P| × |B|`); empty without promoted equations.
    g_inv: Vec<f64>,
    w_p: Vec<f64>,
}

impl Block {
    fn state(&self) -> &BlockState {
        self.base.as_ref().expect("block factored")
    }
}

/// The top system of the last factorization and the storage position of each of its
/// triplets, reused while the triplet layout is unchanged.
struct TopCache {
    layout: Vec<(u32, u32)>,
    positions: Vec<usize>,
    matrix: CscMatrix,
    /// How many leading triplets of `layout` are the constant part (`A` and the blocks'
    /// condensation); the rest are the variable elements'.
    constant_len: usize,
    /// The constant part of the (reduced) top matrix alone, on `matrix`'s pattern.
    constant: Vec<f64>,
    /// How many leading triplets of `layout` are `S_A`'s own (the rest of the constant part
    /// is the condensed groups' `M_ee − M_ei·M_ii⁻¹·M_ie`), and their sum on `matrix`'s
    /// pattern: with the condensed groups' `M` it gives `S_A·x`.
    plain_len: usize,
    plain: Vec<f64>,
}

/// The partitioned solver (see the module documentation).
pub struct Partitioned {
    options: PartitionOptions,
    symmetric: bool,
    n: usize,
    /// Pattern id the structure was built for.
    pattern_id: u64,
    /// Coefficients `(c_K, c_M, c_C)` (or any key) the block factors belong to.
    key: Option<[f64; 3]>,
    /// Block of each equation (`NONE`: top).
    block_of: Vec<u32>,
    blocks: Vec<Block>,
    base_top: Vec<usize>,
    /// Current top set and each equation's index in it (`NONE`: not top).
    top: Vec<usize>,
    top_index: Vec<u32>,
    top_solver: Box<dyn LinearSolver>,
    top_factored: bool,
    /// Whether the top solver is the dense one (small top systems).
    top_dense: bool,
    /// The last top system and how its triplets map onto it.
    top_cache: Option<TopCache>,
    /// Whether the constant part of the top system must be formed again at the next
    /// factorization (new structure, new block factors, a promotion changed, a new top set).
    constant_stale: bool,
    /// Counts changes of the top set (a promotion changed which equations are on top).
    top_generation: u64,
    /// The groups of the top chain (`None`: no second-level condensation).
    chain: Option<TopChain>,
    /// The groups condensed in the current reduced system, and the map between top
    /// positions and reduced positions (`NONE`: a condensed inner equation).
    condensed: Vec<usize>,
    red_of_top: Vec<u32>,
    top_of_red: Vec<u32>,
    /// One flag per equation, all `false` between uses (collecting the promoted set).
    marked: Vec<bool>,
    stats: PartitionStats,
    /// The other ranks, when the blocks are shared among processes (module documentation,
    /// *Across ranks*); `None`: one process owns every block.
    comm: Option<Comm>,
    /// Each rank's blocks (contiguous, in block order).
    ranges: Vec<Range<usize>>,
    /// Rank 0 only: the blocks of the other ranks, as last received.
    received: Vec<Received>,
    /// Given blocks: a bin per equation, each bin one block (`partition/reduced_cuts.rs`);
    /// `None`: the breadth-first level sets.
    bins: Option<Vec<u32>>,
}

impl Partitioned {
    /// A solver for tangents whose variable part is symmetric (`true`) or not.
    pub fn new(symmetric: bool, options: PartitionOptions) -> Partitioned {
        Partitioned {
            options,
            symmetric,
            n: 0,
            pattern_id: 0,
            key: None,
            block_of: Vec::new(),
            blocks: Vec::new(),
            base_top: Vec::new(),
            top: Vec::new(),
            top_index: Vec::new(),
            top_solver: top_solver_for(symmetric),
            top_factored: false,
            top_dense: false,
            top_cache: None,
            constant_stale: true,
            top_generation: 0,
            chain: None,
            condensed: Vec::new(),
            red_of_top: Vec::new(),
            top_of_red: Vec::new(),
            marked: Vec::new(),
            stats: PartitionStats::default(),
            comm: None,
            ranges: Vec::new(),
            received: Vec::new(),
            bins: None,
        }
    }

    /// Shares the blocks among the ranks of `exchange` (module documentation, *Across
    /// ranks*): every rank of the job must call the solver's methods in the same order with
    /// the same arguments. Takes effect at the next factorization, which builds the structure
    /// anew.
    pub fn set_exchange(&mut self, exchange: Arc<dyn Exchange>) {
        self.comm = (exchange.size() > 1).then(|| Comm::new(exchange));
        self.pattern_id = 0;
        self.n = 0;
        self.key = None;
        self.top_factored = false;
    }

    /// The blocks this rank owns (all of them in one process).
    pub fn owned_blocks(&self) -> Range<usize> {
        self.owned()
    }

    fn owned(&self) -> Range<usize> {
        let r = self.comm.as_ref().map_or(0, Comm::rank);
        self.ranges.get(r).cloned().unwrap_or(0..self.blocks.len())
    }

    fn is_root(&self) -> bool {
        self.comm.as_ref().is_none_or(Comm::is_root)
    }

    /// The top equations of the last factorization (global, sorted).
    pub fn top_equations(&self) -> &[usize] {
        &self.top
    }

    /// Position of equation `i` in the top numbering, if it is on top.
    pub fn top_position(&self, i: usize) -> Option<usize> {
        self.top_index
            .get(i)
            .filter(|&&t| t != NONE)
            .map(|&t| t as usize)
    }

    /// A counter that changes whenever the top set changes (promotions, a new structure).
    pub fn top_generation(&self) -> u64 {
        self.top_generation
    }

    /// Whether equation `i` lies in a block interior (`false`: in the base top set, or no
    /// structure yet).
    pub fn in_block_interior(&self, i: usize) -> bool {
        self.block_of.get(i).is_some_and(|&b| b != NONE)
    }

    /// Number of equations of the structure (`0` before the first factorization).
    pub fn equations(&self) -> usize {
        self.n
    }

    /// `out = S_A·x` on the top equations: the constant part of the last top system (the
    /// Schur complement of `A` onto the top set, without the variable elements). Across
    /// ranks rank 0, which holds the top system, forms it and sends it to the others.
    pub fn top_constant_times(&mut self, x: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        if self.is_root() {
            if let Some(c) = &self.top_cache {
                // S_A = the reduced system's own part of S_A (`plain`) + each condensed
                // group's M ([`crate::top_chain`]).
                let m = &c.matrix;
                let tr = &self.top_of_red;
                for j in 0..m.n {
                    let xj = x[tr[j] as usize];
                    if xj == 0.0 {
                        continue;
                    }
                    for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                        out[tr[m.row_idx[p]] as usize] += c.plain[p] * xj;
                    }
                }
                if let Some(chain) = &self.chain {
                    let ti = &self.top_index;
                    for &gi in &self.condensed {
                        chain.groups[gi].add_times(x, out, |g| ti[g] as usize);
                    }
                }
            }
        }
        if let Some(comm) = &mut self.comm {
            let mut v = if comm.is_root() {
                out.to_vec()
            } else {
                Vec::new()
            };
            comm.broadcast(&mut v);
            out.copy_from_slice(&v);
        }
    }

    /// Bytes this rank holds, by part (capacities, as allocated; for the memory report of
    /// `railfem bench`): the owned blocks' factors, their couplings `A_IB` and corrections
    /// `C`, their promotions (`Z`, `G⁻¹`, `W_P`), what rank 0 received
    /// of the other ranks' blocks, and the top system with its factor and the structure
    /// (block of each equation, block lists, top numbering).
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        let mut factors = 0;
        let mut coupling = 0;
        let mut promotions = 0;
        let mut structure = 4 * (self.block_of.capacity() + self.top_index.capacity())
            + 8 * (self.base_top.capacity() + self.top.capacity());
        for b in &self.blocks {
            structure += 8 * (b.all.capacity() + b.boundary.capacity() + b.promoted.capacity());
            if let Some(st) = &b.base {
                factors += st.factor.heap_bytes();
                coupling += st.forward_coupling.as_ref().map_or(0, |c| c.heap_bytes())
                    + 8 * (st.interior.capacity()
                        + st.boundary.capacity()
                        + st.correction.capacity())
                    + st.coupling
                        .iter()
                        .map(|c| 16 * c.capacity() + 24)
                        .sum::<usize>();
            }
            if let Some(p) = &b.promotion {
                promotions += 8
                    * (p.promoted.capacity()
                        + p.local.capacity()
                        + p.g_inv.capacity()
                        + p.w_p.capacity()
                        + p.products.h.capacity()
                        + p.products.wth.capacity())
                    + p.z.heap_bytes();
            }
        }
        let received: usize = self
            .received
            .iter()
            .map(|r| 8 * (r.correction.capacity() + r.g_inv.capacity() + r.w_p.capacity()))
            .sum();
        let top = self.top_cache.as_ref().map_or(0, |c| {
            c.matrix.heap_bytes()
                + 8 * (c.layout.capacity()
                    + c.positions.capacity()
                    + c.constant.capacity()
                    + c.plain.capacity())
        }) + self.chain.as_ref().map_or(0, TopChain::heap_bytes)
            + 4 * (self.red_of_top.capacity() + self.top_of_red.capacity());
        vec![
            ("block factors", factors),
            ("block couplings A_IB and corrections C", coupling),
            ("promotions Z, G^-1, W_P", promotions),
            ("received from other ranks", received),
            ("top system (matrix)", top),
            ("partition structure", structure),
        ]
    }

    /// Splits the equations into blocks and the top set from the pattern of `a` (values
    /// unread), unless the split is already that of `a`'s pattern: what the first
    /// factorization would do, done ahead so that [`Partitioned::columns_read`] is known
    /// before the matrix to factor is formed.
    pub fn prepare(&mut self, a: &CscMatrix) {
        if a.pattern_id != self.pattern_id || a.n != self.n {
            self.build_structure(a);
            self.constant_stale = true;
        }
    }

    /// Drops every block factor, correction and promotion (and rank 0's copies of the
    /// other ranks'), as a new key would at the next factorization, which then factors every
    /// block anew. For a caller about to factor another matrix with a second solver: the
    /// two sets of factors are then never held at once.
    pub fn release_factors(&mut self) {
        self.key = None;
        self.top_factored = false;
        for b in &mut self.blocks {
            b.base = None;
            b.promotion = None;
            b.promoted.clear();
            b.base_unsent = false;
            b.promotion_unsent = false;
            if let Some(r) = &mut b.reduced {
                r.cond = None;
            }
        }
        self.received = vec![Received::default(); self.blocks.len()];
        if let Some(chain) = &mut self.chain {
            chain.clear();
        }
        self.condensed.clear();
        self.constant_stale = true;
    }

    /// Across ranks, after [`Partitioned::prepare`]: the columns of `A` this rank's
    /// factorizations read — the interiors of its own blocks (their factors and
    /// couplings), and on rank 0 the base top equations (`A_TT` of the top system); a
    /// promoted equation enters the top system through its block's condensation, never
    /// through its column. The other columns may be left empty in the matrix given to
    /// [`Partitioned::factor`] (with the pattern id of the whole). `None` in one process
    /// or before the split: every column is read.
    pub fn columns_read(&self) -> Option<Vec<bool>> {
        self.comm.as_ref()?;
        if self.n == 0 {
            return None;
        }
        let mut keep = vec![false; self.n];
        for b in &self.blocks[self.owned()] {
            for &i in &b.all {
                keep[i] = true;
            }
        }
        if self.is_root() {
            for &i in &self.base_top {
                keep[i] = true;
            }
        }
        Some(keep)
    }

    /// Work counters and times (of this rank's share of the work).
    pub fn stats(&self) -> PartitionStats {
        let mut s = self.stats;
        s.ranks = self.comm.as_ref().map_or(1, Comm::size);
        let owned = self.owned();
        s.owned_blocks = owned.len();
        s.owned_interior_equations = self.blocks[owned.clone()].iter().map(|b| b.all.len()).sum();
        for b in &self.blocks[owned] {
            if let Some((kept, stored)) = b.base.as_ref().and_then(|st| st.factor.compact_counts())
            {
                s.factor_values += stored;
                s.factor_nonzeros += kept;
            }
        }
        s.comm = self.comm.as_ref().map(|c| c.stats).unwrap_or_default();
        s
    }

    /// Splits the equations of `a` into blocks and the base top set.
    fn build_structure(&mut self, a: &CscMatrix) {
        let n = a.n;
        self.n = n;
        self.pattern_id = a.pattern_id;
        self.key = None;
        self.block_of = vec![NONE; n];
        self.blocks.clear();
        self.base_top.clear();
        let target = self.options.block_size.max(1);
        let mut seen = vec![false; n];
        let mut level_of = vec![u32::MAX; n];
        let neighbours = |j: usize| a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]].iter().copied();
        // Breadth-first levels from `start` over unvisited equations of one component.
        let bfs = |start: usize, level_of: &mut Vec<u32>, stamp: &mut Vec<usize>| {
            let mut levels: Vec<Vec<usize>> = vec![vec![start]];
            level_of[start] = 0;
            stamp.push(start);
            loop {
                let mut next = Vec::new();
                let l = levels.len() as u32;
                for &j in levels.last().expect("non-empty") {
                    for i in neighbours(j) {
                        if level_of[i] == u32::MAX {
                            level_of[i] = l;
                            stamp.push(i);
                            next.push(i);
                        }
                    }
                }
                if next.is_empty() {
                    break;
                }
                levels.push(next);
            }
            levels
        };
        let mut stamp = Vec::new();
        for root in 0..n {
            if seen[root] {
                continue;
            }
            // First sweep: find the component and a far equation.
            let first = bfs(root, &mut level_of, &mut stamp);
            let far = *first.last().and_then(|l| l.last()).expect("non-empty");
            for &i in &stamp {
                level_of[i] = u32::MAX;
                seen[i] = true;
            }
            stamp.clear();
            let size: usize = first.iter().map(Vec::len).sum();
            if size < target {
                for l in &first {
                    self.base_top.extend_from_slice(l);
                }
                continue;
            }
            if self.bins.as_ref().is_some_and(|b| b.len() == n) {
                let component: Vec<usize> = first.concat();
                self.split_by_bins(a, &component);
                continue;
            }
            // Second sweep from the far end: the level structure of an elongated
            // structure (a bridge, a track) runs along it.
            let levels = bfs(far, &mut level_of, &mut stamp);
            for &i in &stamp {
                level_of[i] = u32::MAX;
            }
            stamp.clear();
            let mut acc: Vec<usize> = Vec::new();
            let mut k = 0;
            while k < levels.len() {
                acc.extend_from_slice(&levels[k]);
                k += 1;
                let remaining: usize = levels[k.min(levels.len())..].iter().map(Vec::len).sum();
                // Close the block with the next level as separator, unless what would
                // remain after it is too small to be a block of its own.
                if acc.len() >= target
                    && k < levels.len()
                    && remaining > target / 2 + levels[k].len()
                {
                    self.push_block(std::mem::take(&mut acc));
                    self.base_top.extend_from_slice(&levels[k]);
                    k += 1;
                }
            }
            if !acc.is_empty() {
                self.push_block(acc);
            }
        }
        self.base_top.sort_unstable();
        // Each block's boundary, from the pattern: the rows outside its interior in its
        // interior's columns (separator equations: interiors of two blocks never couple).
        for (b, blk) in self.blocks.iter_mut().enumerate() {
            let mut boundary: Vec<usize> = blk
                .all
                .iter()
                .flat_map(|&g| a.row_idx[a.col_ptr[g]..a.col_ptr[g + 1]].iter().copied())
                .filter(|&r| self.block_of[r] != b as u32)
                .collect();
            boundary.sort_unstable();
            boundary.dedup();
            blk.boundary = boundary;
        }
        let sizes: Vec<usize> = self.blocks.iter().map(|b| b.all.len()).collect();
        let ranks = self.comm.as_ref().map_or(1, Comm::size);
        self.ranges = ownership(&sizes, ranks);
        self.received = vec![Received::default(); self.blocks.len()];
        self.stats.analyses += 1;
        self.stats.blocks = self.blocks.len();
        self.stats.interior_equations = self.blocks.iter().map(|b| b.all.len()).sum();
        self.stats.base_top_equations = self.base_top.len();
        let boundaries: Vec<&[usize]> = self.blocks.iter().map(|b| &b.boundary[..]).collect();
        self.chain = (self.options.top_group_blocks >= 2 && self.blocks.len() >= 2).then(|| {
            TopChain::build(
                &a.col_ptr,
                &a.row_idx,
                &boundaries,
                &self.block_of,
                self.options.top_group_blocks,
            )
        });
        self.condensed.clear();
        self.stats.top_groups = self.chain.as_ref().map_or(0, |c| c.groups.len());
    }

    fn push_block(&mut self, mut all: Vec<usize>) {
        all.sort_unstable();
        let b = self.blocks.len() as u32;
        for &i in &all {
            self.block_of[i] = b;
        }
        self.blocks.push(Block {
            all,
            boundary: Vec::new(),
            promoted: Vec::new(),
            base: None,
            promotion: None,
            base_unsent: false,
            promotion_unsent: false,
            frozen: false,
            reduced: None,
        });
    }

    /// Factors `a + V` where `V` is given by `(row, column, value)` triplets and `key`
    /// identifies `a`'s values (e.g. the integrator coefficients): block factors are kept
    /// while `key` and `a`'s pattern are unchanged. Across ranks each rank factors and
    /// promotes its own blocks, sends what changed of their condensation to rank 0, which
    /// forms and factors the top system; every rank returns the same outcome.
    pub fn factor(
        &mut self,
        a: &CscMatrix,
        key: [f64; 3],
        variable: &[(usize, usize, f64)],
    ) -> Result<(), SolverError> {
        let r = self.factor_inner(a, key, variable);
        if r.is_err() {
            // Some blocks may lack their base factor now (on some rank): start afresh at the
            // next factorization, the same way on every rank.
            self.key = None;
        }
        r
    }

    fn factor_inner(
        &mut self,
        a: &CscMatrix,
        key: [f64; 3],
        variable: &[(usize, usize, f64)],
    ) -> Result<(), SolverError> {
        self.top_factored = false;
        self.prepare(a);
        if self.key != Some(key) {
            self.constant_stale = true;
            self.release_factors();
            self.key = Some(key);
        }
        let n = self.n;
        // Promotions: interior equations the variable part touches, by block.
        // Each equation once (a marker per equation), then only the few distinct ones sorted.
        let mut promoted: Vec<(u32, usize)> = Vec::new();
        self.marked.resize(n, false);
        for &(i, j, _) in variable {
            if i >= n || j >= n {
                for &(_, e) in &promoted {
                    self.marked[e] = false;
                }
                return Err(SolverError::Failed(format!(
                    "variable entry ({i}, {j}) outside the {n} equations"
                )));
            }
            for e in [i, j] {
                let b = self.block_of[e];
                if b != NONE && !self.marked[e] {
                    self.marked[e] = true;
                    promoted.push((b, e));
                }
            }
        }
        for &(_, e) in &promoted {
            self.marked[e] = false;
        }
        promoted.sort_unstable();
        let mut wanted: Vec<Vec<usize>> = vec![Vec::new(); self.blocks.len()];
        for &(b, e) in &promoted {
            wanted[b as usize].push(e);
        }
        let nt = threads(self.options.threads);
        let owned = self.owned();
        let mut local: Result<(), SolverError> = Ok(());
        // Base factors of owned blocks that have none (the first factorization, a new `A`).
        let t0 = Instant::now();
        let mut missing: Vec<(usize, &[usize], &[usize])> = self.blocks[owned.clone()]
            .iter()
            .enumerate()
            .filter(|(_, b)| b.base.is_none())
            .map(|(i, b)| (owned.start + i, &b.all[..], &b.boundary[..]))
            .collect();
        let block_of = &self.block_of;
        let results = par_each(&mut missing, nt, |(_, all, boundary)| {
            block_state(a, all, boundary, block_of)
        });
        let targets: Vec<usize> = missing.iter().map(|m| m.0).collect();
        drop(missing);
        self.stats.block_factorizations += targets.len();
        for (bi, r) in targets.into_iter().zip(results) {
            match r {
                Ok(st) => {
                    self.blocks[bi].base = Some(st);
                    self.blocks[bi].base_unsent = true;
                }
                Err(e) => {
                    if local.is_ok() {
                        local = Err(e);
                    }
                }
            }
        }
        self.stats.time_blocks += t0.elapsed().as_secs_f64();
        // Reduced blocks' condensations for this `A` (`partition/reduced.rs`).
        if local.is_ok() {
            local = self.condense_reduced(a, &wanted);
        }
        // Promotions whose set changed: known on every rank (the promoted sets are), formed
        // by the owner.
        let t0 = Instant::now();
        let mut jobs: Vec<(&mut Block, Vec<usize>)> = Vec::new();
        for (b, (blk, want)) in self.blocks.iter_mut().zip(wanted).enumerate() {
            if blk.promoted == want {
                continue;
            }
            self.constant_stale = true;
            blk.promoted.clone_from(&want);
            if owned.contains(&b) {
                jobs.push((blk, want));
            }
        }
        let changed = jobs.iter().filter(|(_, w)| !w.is_empty()).count();
        let form = self.options.promotion_form;
        if local.is_ok() {
            let results = par_each(&mut jobs, nt, |(blk, want)| {
                let Block {
                    base,
                    promotion: last,
                    ..
                } = &mut **blk;
                let base = base.as_mut().expect("base factored above");
                if want.is_empty() {
                    base.forward_coupling = None;
                    return Ok(None);
                }
                // The last promotion's storage is reused (replaced below in any case).
                promotion(base, std::mem::take(want), last.take(), form).map(Some)
            });
            for ((blk, _), r) in jobs.iter_mut().zip(results) {
                blk.promotion_unsent = true;
                if let Ok(Some(p)) = &r {
                    let [solved, kept] = p.columns;
                    self.stats.promotion_columns_solved += solved;
                    self.stats.promotion_columns_kept += kept;
                    self.stats.promotion_reach_rows += p.reach[0];
                    self.stats.promotion_reach_max = self.stats.promotion_reach_max.max(p.reach[1]);
                }
                match r {
                    Ok(p) => blk.promotion = p,
                    Err(e) => {
                        blk.promotion = None;
                        if local.is_ok() {
                            local = Err(e);
                        }
                    }
                }
            }
        }
        drop(jobs);
        self.stats.promotions += changed;
        self.stats.time_promote += t0.elapsed().as_secs_f64();

        // The top set and system.
        let t1 = Instant::now();
        let mut top: Vec<usize> = Vec::with_capacity(self.base_top.len() + promoted.len());
        top.extend_from_slice(&self.base_top);
        top.extend(promoted.iter().map(|&(_, e)| e));
        top.sort_unstable();
        if top != self.top || self.top_index.len() != n {
            for &i in &self.top {
                if let Some(t) = self.top_index.get_mut(i) {
                    *t = NONE;
                }
            }
            if self.top_index.len() != n {
                self.top_index = vec![NONE; n];
            }
            for (k, &i) in top.iter().enumerate() {
                self.top_index[i] = k as u32;
            }
            self.top = top;
            self.top_generation += 1;
            self.constant_stale = true;
        }
        let nt_top = self.top.len();
        self.stats.top_equations = nt_top;
        // Across ranks: the owners' changed condensations to rank 0 (with their outcome).
        if self.comm.is_some() && self.constant_stale {
            local = self.send_condensations(local);
        }
        let r = if !self.is_root() {
            Ok(())
        } else if local.is_err() {
            local
        } else {
            self.factor_top(a, variable)
        };
        let r = match &mut self.comm {
            Some(comm) => {
                let mut status = if comm.is_root() {
                    encode_status(&r)
                } else {
                    Vec::new()
                };
                comm.broadcast(&mut status);
                decode_status(&status).0
            }
            None => r,
        };
        self.constant_stale = false;
        self.stats.time_top += t1.elapsed().as_secs_f64();
        r?;
        self.stats.top_factorizations += 1;
        self.top_factored = true;
        Ok(())
    }

    /// Across ranks: every rank other than 0 sends its owned blocks' condensations that
    /// changed since it last sent them, `[block, 0, C]` for a new base correction and
    /// `[block, 1, G⁻¹, W_P]` for a new promotion (sizes known on rank 0 from the boundary
    /// and the promoted set), after its outcome; rank 0 keeps them. Returns the job's first
    /// failure in rank order (on rank 0; the others return their own).
    fn send_condensations(&mut self, local: Result<(), SolverError>) -> Result<(), SolverError> {
        let comm = self.comm.as_mut().expect("across ranks");
        let mut msg = encode_status(&local);
        if !comm.is_root() && local.is_ok() {
            let owned = self.ranges[comm.rank()].clone();
            for (b, blk) in self.blocks[owned.clone()].iter_mut().enumerate() {
                let b = (owned.start + b) as f64;
                if std::mem::take(&mut blk.base_unsent) {
                    msg.extend([b, 0.0]);
                    msg.extend_from_slice(&blk.base.as_ref().expect("owned").correction);
                }
                if std::mem::take(&mut blk.promotion_unsent) {
                    msg.extend([b, 1.0]);
                    if let Some(p) = &blk.promotion {
                        msg.extend_from_slice(&p.g_inv);
                        msg.extend_from_slice(&p.w_p);
                    }
                }
            }
        }
        let Some(pieces) = comm.gather(&msg) else {
            return local;
        };
        let mut first = local;
        for piece in pieces.iter().skip(1) {
            let (status, mut at) = decode_status(piece);
            if first.is_ok() {
                first = status;
            }
            while at < piece.len() {
                let b = piece[at] as usize;
                let (nb, np) = (self.blocks[b].boundary.len(), self.blocks[b].promoted.len());
                let rec = &mut self.received[b];
                at += 2;
                if piece[at - 1] == 0.0 {
                    rec.correction = piece[at..at + nb * nb].to_vec();
                    at += nb * nb;
                } else {
                    rec.g_inv = piece[at..at + np * np].to_vec();
                    at += np * np;
                    rec.w_p = piece[at..at + np * nb].to_vec();
                    at += np * nb;
                }
            }
        }
        first
    }

    /// Forms and factors the top system (rank 0 across ranks): the reduced system of the
    /// top chain ([`crate::top_chain`]) when some groups are condensed, else the whole top.
    fn factor_top(
        &mut self,
        a: &CscMatrix,
        variable: &[(usize, usize, f64)],
    ) -> Result<(), SolverError> {
        let t_form = Instant::now();
        let nt_top = self.top.len();
        self.update_condensed(a, variable);
        let nr = self.top_of_red.len();
        let (ti, red) = (&self.top_index, &self.red_of_top);
        let vtrip: Vec<(u32, u32, f64)> = variable
            .iter()
            .map(|&(i, j, v)| (red[ti[i] as usize], red[ti[j] as usize], v))
            .collect();
        // The constant part (A between top equations, the blocks' condensation and the
        // condensed groups' Schur complements) is formed again only when something it
        // depends on changed; otherwise the cached values are reused and only the variable
        // elements' triplets are added.
        let reuse = !self.constant_stale
            && self.top_cache.as_ref().is_some_and(|c| {
                c.matrix.n == nr
                    && c.layout.len() == c.constant_len + vtrip.len()
                    && c.layout[c.constant_len..]
                        .iter()
                        .zip(&vtrip)
                        .all(|(&(i, j), t)| i == t.0 && j == t.1)
            });
        // The constant part is current but the variable elements' triplets changed their
        // layout (a wheel's contact moved to other rail nodes of the same promoted set):
        // when each of them has its place in the cached pattern, only their positions are
        // looked up, and the pattern, with its symbolic analysis, is kept.
        let refit = !reuse
            && !self.constant_stale
            && self.top_cache.as_mut().is_some_and(|c| {
                if c.matrix.n != nr {
                    return false;
                }
                let found: Option<Vec<usize>> = vtrip
                    .iter()
                    .map(|t| c.matrix.position(t.0 as usize, t.1 as usize))
                    .collect();
                let Some(found) = found else {
                    return false;
                };
                c.layout.truncate(c.constant_len);
                c.layout.extend(vtrip.iter().map(|t| (t.0, t.1)));
                c.positions.truncate(c.constant_len);
                c.positions.extend(found);
                true
            });
        if refit {
            self.stats.top_refits += 1;
        }
        if !reuse && !refit {
            let (mut ctrip, plain_len) = self.constant_triplets(a, vtrip.len());
            self.stats.top_constant_forms += 1;
            let constant_len = ctrip.len();
            let same = self.top_cache.as_ref().is_some_and(|c| {
                c.matrix.n == nr
                    && c.constant_len == constant_len
                    && c.plain_len == plain_len
                    && c.layout.len() == constant_len + vtrip.len()
                    && c.layout
                        .iter()
                        .zip(
                            ctrip
                                .iter()
                                .map(|t| (t.0, t.1))
                                .chain(vtrip.iter().map(|t| (t.0, t.1))),
                        )
                        .all(|(&l, t)| l == t)
            });
            // Same triplet layout as last time (the usual case between promotions): refill
            // the cached matrix through the cached positions, keeping its pattern id so the
            // top solver also reuses its symbolic analysis.
            if !same {
                // The variable triplets after the constant ones, in the room left for them.
                ctrip.extend_from_slice(&vtrip);
                let all = &ctrip[..];
                let (m, positions) = pattern_of_triplets(nr, all);
                // Another layout may still give the last pattern (the same couplings
                // between the same top positions): its symbolic analysis then stands, as
                // the same pattern gives the same ordering.
                let mut m = m;
                if let Some(c) = self.top_cache.as_ref().filter(|c| {
                    c.matrix.n == m.n
                        && c.matrix.col_ptr == m.col_ptr
                        && c.matrix.row_idx == m.row_idx
                }) {
                    m.pattern_id = c.matrix.pattern_id;
                    self.stats.top_pattern_repeats += 1;
                }
                let layout = all.iter().map(|&(i, j, _)| (i, j)).collect();
                let nnz = m.values.len();
                self.top_cache = Some(TopCache {
                    layout,
                    positions,
                    matrix: m,
                    constant_len,
                    constant: vec![0.0; nnz],
                    plain_len,
                    plain: vec![0.0; nnz],
                });
            }
            let cache = self.top_cache.as_mut().expect("set above");
            cache.constant.iter_mut().for_each(|v| *v = 0.0);
            for (&p, t) in cache.positions.iter().zip(&ctrip[..plain_len]) {
                cache.constant[p] += t.2;
            }
            cache.plain.copy_from_slice(&cache.constant);
            let tail = &ctrip[plain_len..constant_len];
            for (&p, t) in cache.positions[plain_len..].iter().zip(tail) {
                cache.constant[p] += t.2;
            }
        }
        let cache = self.top_cache.as_mut().expect("set above");
        // Constant part first, then the variable triplets in order: the same sums as
        // scattering every triplet into zeros.
        cache.matrix.values.copy_from_slice(&cache.constant);
        for (&p, t) in cache.positions[cache.constant_len..].iter().zip(&vtrip) {
            cache.matrix.values[p] += t.2;
        }
        let s = &cache.matrix;
        let dense = nr <= crate::thresholds::DENSE_LIMIT;
        if dense != self.top_dense {
            self.top_solver = if dense {
                Box::new(DenseLu::default())
            } else {
                top_solver_for(self.symmetric)
            };
            self.top_dense = dense;
        }
        self.stats.top_nnz = s.values.len();
        self.stats.top_reduced_equations = nr;
        self.stats.top_groups_condensed = self.condensed.len();
        self.stats.time_top_form += t_form.elapsed().as_secs_f64();
        let t_factor = Instant::now();
        let before = self.top_solver.stats().symbolic_analyses;
        let r = self.top_solver.factor(s);
        let after = self.top_solver.stats();
        self.stats.top_symbolic_analyses += after.symbolic_analyses.saturating_sub(before);
        self.stats.top_factor_nnz = after.factor_nnz;
        self.stats.time_top_factor += t_factor.elapsed().as_secs_f64();
        debug_assert_eq!(nt_top, self.red_of_top.len());
        r.map_err(|e| match e {
            SolverError::Singular { equation } => SolverError::Singular {
                equation: self
                    .top_of_red
                    .get(equation)
                    .and_then(|&t| self.top.get(t as usize))
                    .copied()
                    .unwrap_or(equation),
            },
            other => other,
        })
    }

    /// Chooses the groups of the top chain to condense for this factorization — those with
    /// no promoted equation in their blocks and no variable element on their inner
    /// equations — condenses those not condensed yet, and numbers the reduced system. A
    /// change of the chosen set makes the constant part stale.
    fn update_condensed(&mut self, a: &CscMatrix, variable: &[(usize, usize, f64)]) {
        let mut chosen: Vec<usize> = Vec::new();
        let owned = self.owned();
        if let Some(chain) = &mut self.chain {
            let mut touched = vec![false; chain.groups.len()];
            for &(i, j, _) in variable {
                for e in [i, j] {
                    if let Some(&g) = chain.inner_of.get(e).filter(|&&g| g != NONE) {
                        touched[g as usize] = true;
                    }
                }
            }
            for (gi, group) in chain.groups.iter_mut().enumerate() {
                if touched[gi]
                    || group.failed
                    || group.inner.is_empty()
                    || self.blocks[group.blocks.clone()]
                        .iter()
                        .any(|b| !b.promoted.is_empty())
                {
                    continue;
                }
                if group.cond.is_none() {
                    let boundaries: Vec<&[usize]> = self.blocks[group.blocks.clone()]
                        .iter()
                        .map(|b| &b.boundary[..])
                        .collect();
                    // A held block's interior does not follow its boundary: no correction
                    // (`frozen.rs`).
                    let held: Vec<Vec<f64>> = self.blocks[group.blocks.clone()]
                        .iter()
                        .map(|b| match b.frozen {
                            true => vec![0.0; b.boundary.len() * b.boundary.len()],
                            false => Vec::new(),
                        })
                        .collect();
                    let corrections: Vec<&[f64]> = group
                        .blocks
                        .clone()
                        .zip(&held)
                        .map(|(b, zero)| {
                            if self.blocks[b].frozen {
                                &zero[..]
                            } else if let Some(r) = &self.blocks[b].reduced {
                                &r.cond.as_ref().expect("condensed").correction[..]
                            } else if owned.contains(&b) {
                                &self.blocks[b].state().correction[..]
                            } else {
                                &self.received[b].correction[..]
                            }
                        })
                        .collect();
                    self.stats.top_group_condensations += 1;
                    if !group.condense(a, &self.block_of, &boundaries, &corrections) {
                        continue;
                    }
                }
                chosen.push(gi);
            }
        }
        let nt_top = self.top.len();
        if chosen == self.condensed && self.red_of_top.len() == nt_top && !self.constant_stale {
            return;
        }
        self.constant_stale = true;
        self.condensed = chosen;
        self.red_of_top = vec![0; nt_top];
        if let Some(chain) = &self.chain {
            for &gi in &self.condensed {
                for &e in &chain.groups[gi].inner {
                    self.red_of_top[self.top_index[e] as usize] = NONE;
                }
            }
        }
        self.top_of_red.clear();
        for (t, r) in self.red_of_top.iter_mut().enumerate() {
            if *r != NONE {
                *r = self.top_of_red.len() as u32;
                self.top_of_red.push(t as u32);
            }
        }
    }

    /// The constant part of the (reduced) top system as `(row, column, value)` triplets in
    /// reduced numbering, and how many of them lead as `S_A`'s own: `A` between base top
    /// equations and each block's condensation (module documentation), the owned blocks'
    /// from their factors, the others' as received — without what the condensed groups
    /// hold — then each condensed group's `M_ee − M_ei·M_ii⁻¹·M_ie` on its ends. The vector
    /// has room for `extra` more (the variable elements' triplets).
    fn constant_triplets(&self, a: &CscMatrix, extra: usize) -> (Vec<(u32, u32, f64)>, usize) {
        let ti = &self.top_index;
        let red = &self.red_of_top;
        let chain = self.chain.as_ref();
        let mut in_condensed = vec![false; self.blocks.len()];
        if let Some(chain) = chain {
            for &gi in &self.condensed {
                for b in chain.groups[gi].blocks.clone() {
                    in_condensed[b] = true;
                }
            }
        }
        let skipped = |b: usize, blk: &Block| in_condensed[b] || blk.frozen;
        // Room for every triplet at once (and for the caller's `extra`), so that the
        // vector never grows by copying.
        let base_entries: usize = self
            .base_top
            .iter()
            .map(|&j| a.col_ptr[j + 1] - a.col_ptr[j])
            .sum();
        let block_entries: usize = (self.blocks.iter().enumerate())
            .filter(|&(b, blk)| !skipped(b, blk))
            .map(|(_, blk)| block_triplet_count(blk.boundary.len(), blk.promoted.len()))
            .sum();
        let group_entries: usize = chain.map_or(0, |chain| {
            (self.condensed.iter())
                .map(|&gi| chain.groups[gi].ends.len().pow(2))
                .sum()
        });
        let mut trip: Vec<(u32, u32, f64)> =
            Vec::with_capacity(base_entries + block_entries + group_entries + extra);
        // A between base top equations (promoted ones enter through their block's S),
        // except the condensed inner equations' rows and columns.
        for &j in &self.base_top {
            let k = red[ti[j] as usize];
            if k == NONE {
                continue;
            }
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let r = a.row_idx[p];
                if self.block_of[r] == NONE {
                    let kr = red[ti[r] as usize];
                    if kr != NONE {
                        trip.push((kr, k, a.values[p]));
                    }
                }
            }
        }
        let owned = self.owned();
        // Reduced position of a top equation.
        let rti = |g: usize| red[ti[g] as usize];
        let mut formed = Products::default();
        for (b, blk) in self.blocks.iter().enumerate() {
            // A held block's interior is prescribed: its boundary keeps `A_BB` alone
            // (`frozen.rs`).
            if skipped(b, blk) {
                continue;
            }
            let np = blk.promoted.len();
            let (correction, g_inv, products) = if let Some(r) = &blk.reduced {
                let c = &r.cond.as_ref().expect("condensed").correction[..];
                (c, &[][..], &formed)
            } else if owned.contains(&b) {
                let st = blk.state();
                match &blk.promotion {
                    Some(p) => (&st.correction[..], &p.g_inv[..], &p.products),
                    None => (&st.correction[..], &[][..], &formed),
                }
            } else {
                let r = &self.received[b];
                formed = promoted_products(&r.g_inv, &r.w_p, np, blk.boundary.len());
                (&r.correction[..], &r.g_inv[..], &formed)
            };
            debug_assert_eq!(g_inv.len(), np * np, "block {b}'s promotion");
            block_triplets(
                rti,
                &blk.boundary,
                &blk.promoted,
                correction,
                g_inv,
                products,
                &mut trip,
            );
        }
        let plain_len = trip.len();
        if let Some(chain) = chain {
            for &gi in &self.condensed {
                let g = &chain.groups[gi];
                let schur = &g.cond.as_ref().expect("condensed").schur;
                let ne = g.ends.len();
                for (f, &ef) in g.ends.iter().enumerate() {
                    let kf = red[ti[ef] as usize];
                    for (e, &ee) in g.ends.iter().enumerate() {
                        let ke = red[ti[ee] as usize];
                        trip.push((ke, kf, schur[e + f * ne]));
                    }
                }
            }
        }
        (trip, plain_len)
    }
    /// Solves `(A + V)·x = b` in place with the last factorization: the interiors'
    /// right-hand sides condensed onto the top ([`Partitioned::condense_rhs`]), the top
    /// solve ([`Partitioned::solve_top`]), the interiors recovered
    /// ([`Partitioned::back_substitute`]).
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        let mut xt = self.condense_rhs(b)?;
        self.solve_top(&mut xt)?;
        let rhs = b.to_vec();
        // Interiors are overwritten; the top entries are set below.
        self.back_substitute(&[(Some(&rhs), &xt)], &mut [b], false)?;
        for (&i, v) in self.top.iter().zip(&xt) {
            b[i] = *v;
        }
        self.stats.solves += 1;
        Ok(())
    }

    fn check_ready(&self, len: usize) -> Result<(), SolverError> {
        if !self.top_factored {
            return Err(SolverError::Failed(
                "solve called without a valid factorization".into(),
            ));
        }
        if len != self.n {
            return Err(SolverError::Failed(format!(
                "right-hand side has {} entries, the system {}",
                len, self.n
            )));
        }
        Ok(())
    }

    /// The forward half of a solve: `b`'s block interiors condensed onto the top equations,
    /// `g_T = b_T − Σ_b A_{T I_b}·A_{I_b I_b}⁻¹·b_{I_b}` (with the promoted equations' own
    /// form, module documentation), returned in top numbering ([`Partitioned::top_equations`]).
    /// One triangular solve pair per block, in parallel. Across ranks each rank condenses
    /// its blocks and sends the pieces (`|B_b| + |P_b|` numbers a block) to rank 0, which
    /// sums them in block order, as one process does, and sends `g_T` to every rank.
    pub fn condense_rhs(&mut self, b: &[f64]) -> Result<Vec<f64>, SolverError> {
        self.check_ready(b.len())?;
        let t0 = Instant::now();
        let nt = threads(self.options.threads);
        let rhs: &[f64] = b;
        let owned = self.owned();
        // Condense the interiors' right-hand sides onto their boundaries (and promoted
        // equations).
        let parts = par_each(&mut self.blocks[owned], nt, |blk| {
            let Block {
                all,
                base,
                promotion,
                frozen,
                reduced,
                ..
            } = blk;
            if *frozen {
                // A held interior's rows are reactions, not equations: nothing to condense.
                return Ok((Vec::new(), Vec::new()));
            }
            if let Some(red) = reduced {
                return Ok((red.forward(all, rhs), Vec::new()));
            }
            let st = base.as_mut().expect("block factored");
            let mut y: Vec<f64> = st.interior.iter().map(|&i| rhs[i]).collect();
            st.factor.solve_in_place(&mut y)?;
            let mut c: Vec<f64> = st
                .coupling
                .iter()
                .map(|col| col.iter().map(|&(r, v)| v * y[r as usize]).sum())
                .collect();
            let mut u = Vec::new();
            if let Some(pr) = promotion {
                // r'_P = G⁻¹·y_P, and r'_B gains W_Pᵀ·G⁻¹·y_P.
                let np = pr.promoted.len();
                let yp: Vec<f64> = pr.local.iter().map(|&l| y[l]).collect();
                u = (0..np)
                    .map(|k| (0..np).map(|l| pr.g_inv[k + l * np] * yp[l]).sum())
                    .collect();
                for (j, cj) in c.iter_mut().enumerate() {
                    *cj -= (0..np).map(|k| pr.w_p[k + j * np] * u[k]).sum::<f64>();
                }
            }
            Ok::<_, SolverError>((c, u))
        });
        let xt = if let Some(comm) = &mut self.comm {
            let local = first_error(&parts);
            let mut msg = encode_status(&local);
            if local.is_ok() {
                for (c, u) in parts.into_iter().flatten() {
                    msg.extend(c);
                    msg.extend(u);
                }
            }
            let mut reply = match comm.gather(&msg) {
                Some(pieces) => {
                    let mut xt: Vec<f64> = self.top.iter().map(|&i| b[i]).collect();
                    let mut first = Ok(());
                    for (r, piece) in pieces.iter().enumerate() {
                        let (status, mut at) = decode_status(piece);
                        if status.is_err() {
                            first = status;
                            break;
                        }
                        for bi in self.ranges[r].clone() {
                            let blk = &self.blocks[bi];
                            let (nb, np) = (blk.boundary.len(), blk.promoted.len());
                            let (c, u) = piece[at..at + nb + np].split_at(nb);
                            self.add_condensed(&mut xt, bi, c, u);
                            at += nb + np;
                        }
                    }
                    let mut reply = encode_status(&first);
                    if first.is_ok() {
                        reply.extend(xt);
                    }
                    reply
                }
                None => Vec::new(),
            };
            let comm = self.comm.as_mut().expect("across ranks");
            comm.broadcast(&mut reply);
            let (status, at) = decode_status(&reply);
            status?;
            reply.split_off(at)
        } else {
            let mut xt: Vec<f64> = self.top.iter().map(|&i| b[i]).collect();
            for (bi, part) in parts.into_iter().enumerate() {
                let (c, u) = part?;
                self.add_condensed(&mut xt, bi, &c, &u);
            }
            xt
        };
        self.stats.time_solve += t0.elapsed().as_secs_f64();
        Ok(xt)
    }

    /// Block `bi`'s condensed right-hand side into `g_T`: `−c` on its boundary, `u` as
    /// the values of its promoted equations.
    fn add_condensed(&self, xt: &mut [f64], bi: usize, c: &[f64], u: &[f64]) {
        let blk = &self.blocks[bi];
        for (&g, c) in blk.boundary.iter().zip(c) {
            xt[self.top_index[g] as usize] -= c;
        }
        for (&g, &u) in blk.promoted.iter().zip(u) {
            xt[self.top_index[g] as usize] = u;
        }
    }

    /// Solves the factored top system `S·x = g` in place (top numbering). Across ranks
    /// rank 0 solves and sends `x` to every rank.
    pub fn solve_top(&mut self, x: &mut [f64]) -> Result<(), SolverError> {
        if !self.top_factored || x.len() != self.top.len() {
            return Err(SolverError::Failed(format!(
                "top solve: {} entries for {} top equations{}",
                x.len(),
                self.top.len(),
                if self.top_factored {
                    ""
                } else {
                    ", not factored"
                }
            )));
        }
        let t0 = Instant::now();
        let r = if self.is_root() {
            self.solve_reduced(x)
        } else {
            Ok(())
        };
        let r = match &mut self.comm {
            Some(comm) => {
                let mut msg = Vec::new();
                if comm.is_root() {
                    msg = encode_status(&r);
                    if r.is_ok() {
                        msg.extend_from_slice(x);
                    }
                }
                comm.broadcast(&mut msg);
                let (status, at) = decode_status(&msg);
                if status.is_ok() {
                    x.copy_from_slice(&msg[at..]);
                }
                status
            }
            None => r,
        };
        self.stats.time_solve += t0.elapsed().as_secs_f64();
        r
    }

    /// Solves the factored top system in place through the reduced system: the condensed
    /// groups' inner equations eliminated onto their ends, the reduced solve, the inner
    /// equations recovered ([`crate::top_chain`]).
    fn solve_reduced(&mut self, x: &mut [f64]) -> Result<(), SolverError> {
        let Some(chain) = self.chain.as_ref().filter(|_| !self.condensed.is_empty()) else {
            return self.top_solver.solve_in_place(x);
        };
        let ti = &self.top_index;
        let at = |g: usize| ti[g] as usize;
        let ys: Vec<Vec<f64>> = self
            .condensed
            .iter()
            .map(|&gi| chain.groups[gi].forward(x, at))
            .collect();
        let mut xr: Vec<f64> = self.top_of_red.iter().map(|&t| x[t as usize]).collect();
        self.top_solver.solve_in_place(&mut xr)?;
        for (&t, v) in self.top_of_red.iter().zip(&xr) {
            x[t as usize] = *v;
        }
        for (&gi, y) in self.condensed.iter().zip(ys) {
            chain.groups[gi].back(x, y, at);
        }
        Ok(())
    }

    /// The back half of a solve, for several columns at once (one multi-column triangular
    /// solve per block): column `k` has the right-hand side `b_k` (`None`: zero) and the
    /// top values `x_T,k`; its interiors `x_I = A_II⁻¹·(b_I − A_IB·x_B)` (with the promoted
    /// equations' form, module documentation) are written into `outs[k]` (added to it when
    /// `add`). Top entries of `outs`, promoted ones included, are left alone. Across ranks
    /// each rank recovers its blocks' interiors and every rank receives all of them (the
    /// state stays whole on every rank).
    pub fn back_substitute(
        &mut self,
        columns: &[(Option<&[f64]>, &[f64])],
        outs: &mut [&mut [f64]],
        add: bool,
    ) -> Result<(), SolverError> {
        self.check_ready(outs.first().map_or(self.n, |o| o.len()))?;
        if outs.len() != columns.len() {
            return Err(SolverError::Failed(format!(
                "back substitution: {} columns, {} outputs",
                columns.len(),
                outs.len()
            )));
        }
        let t0 = Instant::now();
        let nt = threads(self.options.threads);
        let nc = columns.len();
        let top_index = &self.top_index;
        let owned = self.owned();
        // In one process each block writes its own interiors into `outs` where it recovers
        // them (the blocks' interiors are disjoint), instead of one thread writing them all
        // afterwards; across ranks the pieces are gathered first.
        let lens: Vec<usize> = outs.iter().map(|o| o.len()).collect();
        let direct: Option<Vec<Shared>> = self
            .comm
            .is_none()
            .then(|| outs.iter_mut().map(|o| Shared(o.as_mut_ptr())).collect());
        let parts = par_each(&mut self.blocks[owned.clone()], nt, |blk| {
            let Block {
                all,
                base,
                promotion,
                promoted,
                frozen,
                reduced,
                boundary,
                ..
            } = blk;
            if let Some(red) = reduced {
                // The Galerkin back pass (`partition/reduced.rs`).
                let ni = all.len();
                let mut z = vec![0.0; ni * nc];
                let cols: Vec<(Option<&[f64]>, Vec<f64>)> = columns
                    .iter()
                    .map(|(rhs, xt)| {
                        let x_b = boundary.iter().map(|&g| xt[top_index[g] as usize]);
                        (*rhs, x_b.collect())
                    })
                    .collect();
                red.back(all, &cols, &mut z);
                if let Some(direct) = &direct {
                    for (k, (out, &len)) in direct.iter().zip(&lens).enumerate() {
                        // SAFETY: as below; no other block writes this block's interiors.
                        let out = unsafe { out.range(0, len) };
                        interiors_into(all, &z[k * ni..(k + 1) * ni], out, add, |_| true);
                    }
                    return Ok(Vec::new());
                }
                return Ok(z);
            }
            if *frozen {
                // A held interior does not move: its part of every column is zero.
                if let (Some(direct), false) = (&direct, add) {
                    for (out, &len) in direct.iter().zip(&lens) {
                        // SAFETY: as below; no other block writes this block's interiors.
                        let out = unsafe { out.range(0, len) };
                        for &i in all.iter() {
                            out[i] = 0.0;
                        }
                    }
                }
                return Ok(Vec::new());
            }
            let st = base.as_mut().expect("block factored");
            let ni = st.interior.len();
            let mut z = vec![0.0; ni * nc];
            for (k, (rhs, xt)) in columns.iter().enumerate() {
                let zk = &mut z[k * ni..(k + 1) * ni];
                if let Some(rhs) = rhs {
                    for (zi, &i) in zk.iter_mut().zip(&st.interior) {
                        *zi = rhs[i];
                    }
                }
                for (col, &g) in st.coupling.iter().zip(&st.boundary) {
                    let x = xt[top_index[g] as usize];
                    for &(r, v) in col {
                        zk[r as usize] -= v * x;
                    }
                }
            }
            let forward = match (&*promotion, st.factor.compact_mut()) {
                (
                    Some(Promotion {
                        z: Solved::Forward(y),
                        g_inv,
                        promoted,
                        ..
                    }),
                    Some(c),
                ) => {
                    // The correction between the passes (`partition/forward.rs`).
                    let xp: Vec<Vec<f64>> = columns
                        .iter()
                        .map(|(_, xt)| {
                            promoted
                                .iter()
                                .map(|&g| xt[top_index[g] as usize])
                                .collect()
                        })
                        .collect();
                    forward::back_substitute_forward(c, y, g_inv, &xp, &mut z, nc);
                    true
                }
                _ => false,
            };
            if !forward {
                if nc == 1 {
                    st.factor.solve_in_place(&mut z)?;
                } else {
                    st.factor.solve_columns_in_place(&mut z, nc)?;
                }
            }
            if let (false, Some(pr)) = (forward, promotion.as_ref()) {
                let Solved::Columns(pz) = &pr.z else {
                    unreachable!("a forward-form promotion has a compact factor")
                };
                // x_I = y + Z·G⁻¹·(x_P − y_P).
                let np = pr.promoted.len();
                for (k, (_, xt)) in columns.iter().enumerate() {
                    let zk = &mut z[k * ni..(k + 1) * ni];
                    let d: Vec<f64> = pr
                        .promoted
                        .iter()
                        .zip(&pr.local)
                        .map(|(&g, &l)| xt[top_index[g] as usize] - zk[l])
                        .collect();
                    for kk in 0..np {
                        let e: f64 = (0..np).map(|l| pr.g_inv[kk + l * np] * d[l]).sum();
                        if e != 0.0 {
                            for (zi, zp) in zk.iter_mut().zip(&pz[kk * ni..(kk + 1) * ni]) {
                                *zi += zp * e;
                            }
                        }
                    }
                }
            }
            if let Some(direct) = &direct {
                for (k, (out, &len)) in direct.iter().zip(&lens).enumerate() {
                    // SAFETY: `out` is `outs[k]` (length `len`, in bounds for every
                    // equation); no other block writes this block's interiors.
                    let out = unsafe { out.range(0, len) };
                    let kept = |i: usize| promoted.is_empty() || top_index[i] == NONE;
                    interiors_into(all, &z[k * ni..(k + 1) * ni], out, add, kept);
                }
                return Ok(Vec::new());
            }
            Ok::<_, SolverError>(z)
        });
        if let Some(comm) = &mut self.comm {
            let local = first_error(&parts);
            let mut msg = encode_status(&local);
            if local.is_ok() {
                for z in parts.into_iter().flatten() {
                    msg.extend(z);
                }
            }
            let pieces = comm.all_gather(&msg);
            for piece in &pieces {
                decode_status(piece).0?;
            }
            for (r, piece) in pieces.iter().enumerate() {
                let mut at = decode_status(piece).1;
                for bi in self.ranges[r].clone() {
                    let len = self.blocks[bi].all.len() * nc;
                    self.write_interiors(bi, &piece[at..at + len], outs, add);
                    at += len;
                }
            }
        } else {
            first_error(&parts)?;
        }
        self.stats.time_solve += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// Block `bi`'s recovered interiors `z` (`nc` columns) into `outs`, except its
    /// promoted equations (top equations: their values are the caller's).
    fn write_interiors(&self, bi: usize, z: &[f64], outs: &mut [&mut [f64]], add: bool) {
        let blk = &self.blocks[bi];
        let interior = &blk.all;
        let ni = interior.len();
        let promoted = !blk.promoted.is_empty();
        let kept = |i: usize| !promoted || self.top_index[i] == NONE;
        for (k, out) in outs.iter_mut().enumerate() {
            interiors_into(interior, &z[k * ni..(k + 1) * ni], out, add, kept);
        }
    }
}

/// `out[interior[k]] = z[k]` (or `+=` when `add`) for the equations `kept` accepts.
fn interiors_into(
    interior: &[usize],
    z: &[f64],
    out: &mut [f64],
    add: bool,
    kept: impl Fn(usize) -> bool,
) {
    for (&i, v) in interior.iter().zip(z) {
        if !kept(i) {
            continue;
        }
        if add {
            out[i] += v;
        } else {
            out[i] = *v;
        }
    }
}

/// The matrix of `triplets` (`n × n`, values summed in triplet order) and the storage
/// position of each triplet: the result of [`CscMatrix::from_triplets`] and
/// [`CscMatrix::position`], found by a counting sort over columns and a marker per row
/// instead of a binary search per triplet.
fn pattern_of_triplets(n: usize, triplets: &[(u32, u32, f64)]) -> (CscMatrix, Vec<usize>) {
    let mut count = vec![0usize; n + 1];
    for &(_, j, _) in triplets {
        count[j as usize + 1] += 1;
    }
    for j in 0..n {
        count[j + 1] += count[j];
    }
    let mut order = vec![0usize; triplets.len()];
    let mut next = count.clone();
    for (k, &(_, j, _)) in triplets.iter().enumerate() {
        let j = j as usize;
        order[next[j]] = k;
        next[j] += 1;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx: Vec<usize> = Vec::new();
    let mut positions = vec![0usize; triplets.len()];
    let mut mark = vec![usize::MAX; n];
    let mut slot = vec![0usize; n];
    let mut rows: Vec<usize> = Vec::new();
    for j in 0..n {
        rows.clear();
        let here = &order[count[j]..count[j + 1]];
        for &k in here {
            let r = triplets[k].0 as usize;
            if mark[r] != j {
                mark[r] = j;
                rows.push(r);
            }
        }
        // Every matrix on this path keeps its diagonal (as `from_columns` does).
        if mark[j] != j {
            mark[j] = j;
            rows.push(j);
        }
        rows.sort_unstable();
        let start = row_idx.len();
        for (q, &r) in rows.iter().enumerate() {
            slot[r] = start + q;
        }
        row_idx.extend_from_slice(&rows);
        for &k in here {
            positions[k] = slot[triplets[k].0 as usize];
        }
        col_ptr.push(row_idx.len());
    }
    let mut values = vec![0.0; row_idx.len()];
    for (&p, t) in positions.iter().zip(triplets) {
        values[p] += t.2;
    }
    // A pattern id of its own: that of a fresh (empty) pattern.
    let pattern_id = CscMatrix::from_columns(Vec::new()).pattern_id;
    let m = CscMatrix {
        n,
        col_ptr,
        row_idx,
        values,
        pattern_id,
    };
    (m, positions)
}

/// The sparse solver of the top system: Cholesky in supernodes when the tangent is
/// symmetric (the top system is made of dense blocks — a block's condensation on its
/// boundary and promoted equations, a group's on its ends — which supernodes factor with
/// dense kernels: 1.4–1.7× faster than column by column at 1M DOF, `docs/performance.md`),
/// sparse LU otherwise.
fn top_solver_for(symmetric: bool) -> Box<dyn LinearSolver> {
    if symmetric {
        Box::new(SparseCholesky::new().with_layout(crate::linear::Layout::Supernodal))
    } else {
        solver_for(false)
    }
}

/// The first failure among the blocks' results, in block order.
fn first_error<T>(parts: &[Result<T, SolverError>]) -> Result<(), SolverError> {
    parts
        .iter()
        .find_map(|p| p.as_ref().err().cloned())
        .map_or(Ok(()), Err)
}

/// Contiguous ranges of blocks, one per rank, balanced by interior equations: block `b`
/// goes to the rank whose share `[k·N/P, (k+1)·N/P)` of the `N` interior equations holds
/// the middle of `b`. Deterministic from the sizes, so every rank finds the same split.
fn ownership(sizes: &[usize], ranks: usize) -> Vec<Range<usize>> {
    let total: usize = sizes.iter().sum::<usize>().max(1);
    let mut owner = Vec::with_capacity(sizes.len());
    let mut before = 0usize;
    for &s in sizes {
        let mid = 2 * before + s; // twice the middle, to stay in integers
        owner.push(((mid * ranks) / (2 * total)).min(ranks - 1));
        before += s;
    }
    (0..ranks)
        .map(|k| {
            let lo = owner.partition_point(|&o| o < k);
            let hi = owner.partition_point(|&o| o <= k);
            lo..hi
        })
        .collect()
}

/// The promoted part of a block's condensation on the top system (module documentation),
/// column-major: `H = G⁻¹·W_P` (`|P| × |B|`, on `P × B` and `B × P`) and `W_Pᵀ·H`
/// (`|B| × |B|`, added to `B × B`).
#[derive(Debug, Clone, Default)]
struct Products {
    h: Vec<f64>,
    wth: Vec<f64>,
}

/// [`Products`] of `G⁻¹` (`np × np`) and `W_P` (`np × nb`), each entry one sum over `P`
/// in increasing order.
fn promoted_products(g_inv: &[f64], w_p: &[f64], np: usize, nb: usize) -> Products {
    if np == 0 {
        return Products::default();
    }
    let mut h = vec![0.0; np * nb];
    for j in 0..nb {
        for k in 0..np {
            h[k + j * np] = (0..np).map(|l| g_inv[k + l * np] * w_p[l + j * np]).sum();
        }
    }
    let mut wth = vec![0.0; nb * nb];
    for cj in 0..nb {
        for ci in 0..nb {
            wth[ci + cj * nb] = (0..np).map(|k| w_p[k + ci * np] * h[k + cj * np]).sum();
        }
    }
    Products { h, wth }
}

/// Triplets [`block_triplets`] pushes for a block with boundary `nb` and `np` promoted
/// equations, at most (the correction's zeros are skipped).
fn block_triplet_count(nb: usize, np: usize) -> usize {
    match np {
        0 => nb * nb,
        _ => (nb + np) * (nb + np) + nb * nb,
    }
}

/// Pushes one block's condensation onto the top system as triplets (module
/// documentation): `−C` on `B × B`, and with promoted equations `P`, `G⁻¹` on `P × P`,
/// `H = G⁻¹·W_P` on `P × B` and `B × P`, and `W_Pᵀ·H` on `B × B` ([`Products`]).
fn block_triplets(
    ti: impl Fn(usize) -> u32,
    boundary: &[usize],
    promoted: &[usize],
    correction: &[f64],
    g_inv: &[f64],
    products: &Products,
    trip: &mut Vec<(u32, u32, f64)>,
) {
    let nb = boundary.len();
    // S_BB − A_BB = −C (+ W_Pᵀ·G⁻¹·W_P below).
    for (cj, &gj) in boundary.iter().enumerate() {
        let tj = ti(gj);
        for (ci, &gi) in boundary.iter().enumerate() {
            let v = correction[ci + cj * nb];
            if v != 0.0 {
                trip.push((ti(gi), tj, -v));
            }
        }
    }
    let np = promoted.len();
    if np == 0 {
        return;
    }
    let Products { h, wth } = products;
    for (k, &gk) in promoted.iter().enumerate() {
        let tk = ti(gk);
        for (l, &gl) in promoted.iter().enumerate() {
            trip.push((ti(gl), tk, g_inv[l + k * np]));
        }
        for (j, &gj) in boundary.iter().enumerate() {
            let tj = ti(gj);
            let v = h[k + j * np];
            trip.push((tk, tj, v));
            trip.push((tj, tk, v));
        }
    }
    for (cj, &gj) in boundary.iter().enumerate() {
        let tj = ti(gj);
        for (ci, &gi) in boundary.iter().enumerate() {
            trip.push((ti(gi), tj, wth[ci + cj * nb]));
        }
    }
}

/// Factors one block's interior `all` (with its `boundary`) and forms its condensed
/// correction.
fn block_state(
    a: &CscMatrix,
    all: &[usize],
    boundary: &[usize],
    block_of: &[u32],
) -> Result<BlockState, SolverError> {
    let interior: Vec<usize> = all.to_vec();
    let local = |g: usize| interior.binary_search(&g).ok();
    // Interior pattern (the boundary rows met on the way are the block's boundary).
    let mut cols: Vec<Vec<usize>> = Vec::with_capacity(interior.len());
    for &g in &interior {
        let c = a.row_idx[a.col_ptr[g]..a.col_ptr[g + 1]]
            .iter()
            .filter_map(|&r| local(r))
            .collect();
        cols.push(c);
    }
    let boundary = boundary.to_vec();
    debug_assert!(boundary.iter().all(|&r| block_of[r] == NONE));
    let mut m = CscMatrix::from_columns(cols);
    let nb = boundary.len();
    let mut coupling: Vec<Vec<(u32, f64)>> = vec![Vec::new(); nb];
    for (j, &g) in interior.iter().enumerate() {
        for p in a.col_ptr[g]..a.col_ptr[g + 1] {
            let r = a.row_idx[p];
            match local(r) {
                Some(l) => {
                    let q = m.position(l, j).expect("interior pattern");
                    m.values[q] += a.values[p];
                }
                None => {
                    // A_{B I}(r, j) = A_{I B}(j, r) for a symmetric A.
                    let k = boundary.binary_search(&r).expect("boundary row");
                    coupling[k].push((j as u32, a.values[p]));
                }
            }
        }
    }
    // A block's factor is made once per Δt and solved with twice a step (the condensed
    // right-hand side, the back-substitution) and for every promotion: solve from its
    // non-zeros (`crate::compact_factor`; the same bits as faer's solve).
    let mut factor = SparseCholesky::new().with_compact_solve(true);
    factor.factor(&m).map_err(|e| match e {
        SolverError::Singular { equation } => SolverError::Singular {
            equation: interior.get(equation).copied().unwrap_or(equation),
        },
        other => other,
    })?;
    drop(m);
    // W = A_II⁻¹ A_IB, then C = A_BI W.
    let ni = interior.len();
    let mut w = vec![0.0; ni * nb];
    for (k, col) in coupling.iter().enumerate() {
        for &(r, v) in col {
            w[k * ni + r as usize] = v;
        }
    }
    factor.solve_columns_in_place(&mut w, nb)?;
    let mut correction = vec![0.0; nb * nb];
    for j in 0..nb {
        let wj = &w[j * ni..(j + 1) * ni];
        for (i, col) in coupling.iter().enumerate() {
            correction[i + j * nb] = col.iter().map(|&(r, v)| v * wj[r as usize]).sum();
        }
    }
    Ok(BlockState {
        interior,
        boundary,
        factor,
        coupling,
        correction,
        forward_coupling: None,
    })
}

/// The condensation of block `st` onto its equations `promoted` (module documentation):
/// the columns `Z·e_p = A_II⁻¹·e_p` of the equations promoted in `last` too (the block's
/// previous promotion, on the same base factor) are kept, and those of the other equations
/// solved with the base factor. `G⁻¹` and `W_P` are formed anew from the columns. A column
/// is `A_II⁻¹·e_p` whether kept or solved, to the bit (the solve does each column's
/// operations independently of which others it is solved with: [`crate::compact_factor`]).
/// In the forward form ([`PromotionForm::Forward`]) the columns are those of `Y`
/// (`partition/forward.rs`).
fn promotion(
    st: &mut BlockState,
    promoted: Vec<usize>,
    last: Option<Promotion>,
    form: PromotionForm,
) -> Result<Promotion, SolverError> {
    let ni = st.interior.len();
    let np = promoted.len();
    let local: Vec<usize> = promoted
        .iter()
        .map(|g| {
            st.interior
                .binary_search(g)
                .map_err(|_| SolverError::Failed(format!("equation {g} is not in its block")))
        })
        .collect::<Result<_, _>>()?;
    // Where each column of `Z` was in the last promotion's (`None`: not there); both
    // `local` lists are sorted.
    // A last promotion of the other form keeps nothing.
    let (last_local, last_z, last_w) = match last {
        Some(Promotion { local, z, w_p, .. }) => (local, Some(z), w_p),
        None => (Vec::new(), None, Vec::new()),
    };
    let (last_z, last_y) = match (form, last_z) {
        (PromotionForm::Forward, Some(Solved::Forward(y))) => (None, Some((y, last_w))),
        (PromotionForm::Columns, Some(Solved::Columns(z))) => (Some(z), None),
        _ => (None, None),
    };
    let from: Vec<Option<usize>> = local
        .iter()
        .map(|&l| {
            (last_z.is_some() || last_y.is_some())
                .then(|| last_local.binary_search(&l).ok())
                .flatten()
        })
        .collect();
    if form == PromotionForm::Forward {
        if let Some(r) =
            forward::promotion_forward(st, promoted.clone(), local.clone(), &from, last_y)
        {
            return r;
        }
    }
    // The columns form (asked for, or a factor without its compact copy); a forward-form
    // last promotion's columns are not `Z`'s.
    let from: Vec<Option<usize>> = match &last_z {
        Some(_) => from,
        None => vec![None; np],
    };
    let fresh: Vec<usize> = (0..np).filter(|&k| from[k].is_none()).collect();
    let kept = np - fresh.len();
    let mut z = match last_z {
        Some(last_z) if kept > 0 => kept_columns(last_z, ni, &from),
        _ => vec![0.0; ni * np],
    };
    if fresh.len() == np {
        z = st.factor.solve_unit_columns(&local)?;
    } else if !fresh.is_empty() {
        let ls: Vec<usize> = fresh.iter().map(|&k| local[k]).collect();
        let zf = st.factor.solve_unit_columns(&ls)?;
        for (c, &k) in fresh.iter().enumerate() {
            z[k * ni..(k + 1) * ni].copy_from_slice(&zf[c * ni..(c + 1) * ni]);
        }
    }
    let g = nalgebra::DMatrix::from_fn(np, np, |i, j| z[j * ni + local[i]]);
    // G is a principal block of the inverse of a positive definite matrix.
    let g_inv = g
        .cholesky()
        .ok_or(SolverError::Singular {
            equation: promoted[0],
        })?
        .inverse();
    let nb = st.boundary.len();
    let mut w_p = vec![0.0; np * nb];
    for (j, col) in st.coupling.iter().enumerate() {
        for k in 0..np {
            let zk = &z[k * ni..(k + 1) * ni];
            w_p[k + j * np] = col.iter().map(|&(r, v)| v * zk[r as usize]).sum();
        }
    }
    let g_inv = g_inv.as_slice().to_vec();
    let products = promoted_products(&g_inv, &w_p, np, nb);
    Ok(Promotion {
        promoted,
        local,
        z: Solved::Columns(z),
        g_inv,
        w_p,
        products,
        columns: [fresh.len(), kept],
        reach: [0, 0],
    })
}

/// The last promotion's `Z` (`ni` rows) rearranged in its own storage so that column `k`
/// holds its old column `from[k]`; columns with `from[k] = None` are left with whatever the
/// storage held there (the caller writes them). Both promoted sets are sorted, so the kept
/// columns keep their order (`from` increases over them): the columns moving left are
/// moved first, in increasing order, then those moving right, in decreasing order, and no
/// move overwrites a column still to be read. Columns are copied whole, so every kept
/// value is the old one, bit for bit.
fn kept_columns(mut z: Vec<f64>, ni: usize, from: &[Option<usize>]) -> Vec<f64> {
    let np = from.len();
    z.resize(z.len().max(ni * np), 0.0);
    for (k, m) in from.iter().enumerate() {
        if let Some(m) = *m {
            if m > k {
                z.copy_within(m * ni..(m + 1) * ni, k * ni);
            }
        }
    }
    for (k, m) in from.iter().enumerate().rev() {
        if let Some(m) = *m {
            if m < k {
                z.copy_within(m * ni..(m + 1) * ni, k * ni);
            }
        }
    }
    z.truncate(ni * np);
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns rearranged in place are the old columns where kept, whatever was added
    /// or dropped around them (against a copy into fresh storage).
    #[test]
    fn kept_columns_equal_a_fresh_copy() {
        let ni = 3;
        let old_local = [2usize, 5, 7, 9];
        let old: Vec<f64> = (0..ni * old_local.len()).map(|x| x as f64 + 0.5).collect();
        for new_local in [
            vec![1usize, 2, 5, 7, 9],
            vec![5, 9],
            vec![2, 3, 4, 9, 11, 12],
            vec![0, 7],
            vec![2, 5, 7, 9],
            vec![9, 10],
        ] {
            let from: Vec<Option<usize>> = new_local
                .iter()
                .map(|l| old_local.iter().position(|m| m == l))
                .collect();
            let got = kept_columns(old.clone(), ni, &from);
            assert_eq!(got.len(), ni * new_local.len());
            for (k, m) in from.iter().enumerate() {
                if let Some(m) = *m {
                    assert_eq!(got[k * ni..(k + 1) * ni], old[m * ni..(m + 1) * ni]);
                }
            }
        }
    }

    /// A chain of `nodes` 3-DOF nodes with springs between neighbours and a grounding
    /// spring on each (SPD), plus `extra` free equations coupled only by `V`.
    fn chain(nodes: usize, extra: usize) -> CscMatrix {
        let n = nodes * 3 + extra;
        let mut t = Vec::new();
        for k in 0..nodes {
            for d in 0..3 {
                let i = 3 * k + d;
                t.push((i, i, 4.0 + d as f64));
                if d > 0 {
                    t.push((i, i - 1, -0.5));
                    t.push((i - 1, i, -0.5));
                }
                if k + 1 < nodes {
                    let j = i + 3;
                    t.push((i, i, 1.0));
                    t.push((j, j, 1.0));
                    t.push((i, j, -1.0));
                    t.push((j, i, -1.0));
                }
            }
        }
        for e in nodes * 3..n {
            t.push((e, e, 2.0));
        }
        CscMatrix::from_triplets(n, &t)
    }

    fn dense_solve(a: &CscMatrix, v: &[(usize, usize, f64)], b: &[f64]) -> Vec<f64> {
        let n = a.n;
        let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                m[(a.row_idx[p], j)] += a.values[p];
            }
        }
        for &(i, j, x) in v {
            m[(i, j)] += x;
        }
        m.lu()
            .solve(&nalgebra::DVector::from_column_slice(b))
            .expect("regular")
            .as_slice()
            .to_vec()
    }

    /// A partitioned solver in blocks of `block_size` equations on `threads` threads.
    fn in_blocks(symmetric: bool, block_size: usize, threads: usize) -> Partitioned {
        Partitioned::new(
            symmetric,
            PartitionOptions {
                block_size,
                threads,
                ..Default::default()
            },
        )
    }

    fn rhs(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect()
    }

    fn max_rel(x: &[f64], y: &[f64]) -> f64 {
        let s = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        x.iter()
            .zip(y)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / s
    }

    #[test]
    fn matches_a_dense_solve_with_moving_coupling() {
        // 200 nodes = 600 chain equations in blocks of 50, and a 6-equation "vehicle"
        // coupled to two chain nodes that move along the chain between factorizations.
        let a = chain(200, 6);
        let n = a.n;
        let mut p = in_blocks(false, 50, 2);
        for step in 0..8 {
            // A coupling moving along the chain, unsymmetric on purpose (a consistent
            // sliding tangent).
            let v = moving(step);
            p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let b = rhs(n);
            let mut x = b.clone();
            p.solve_in_place(&mut x).unwrap();
            let reference = dense_solve(&a, &v, &b);
            // Both are backward-stable direct solves of a well-conditioned system
            // (condition ≈ 1e2), so they agree to round-off.
            let e = max_rel(&x, &reference);
            assert!(e < 1e-12, "step {step}: relative difference {e:e}");
        }
        let s = p.stats();
        assert!(s.blocks >= 8, "{s:?}");
        // The base factors are made once; the moving coupling only forms promotions.
        assert_eq!(s.block_factorizations, s.blocks, "{s:?}");
        assert!(s.promotions >= 8, "{s:?}");
    }

    /// The forward form (`partition/forward.rs`) against the columns form and a dense
    /// solve, with the coupling of [`matches_a_dense_solve_with_moving_coupling`] moving
    /// between factorizations, and on the split solve with a two-column back-substitution
    /// of [`run_rank`]. All are backward-stable direct solves of one system whose condition
    /// is about 1e2, differing only in the order of their sums: they agree to round-off,
    /// which 1e-12 of the largest entry bounds with room (1e2 · a few hundred terms · 1.1e-16).
    #[test]
    fn the_forward_form_solves_as_the_columns_form() {
        let a = chain(200, 6);
        let n = a.n;
        let (mut fwd, mut cols) = (
            in_form(PromotionForm::Forward),
            in_form(PromotionForm::Columns),
        );
        let mut differ = false;
        for step in 0..8 {
            let v = moving(step);
            fwd.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            cols.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let b = rhs(n);
            let (mut x, mut y) = (b.clone(), b.clone());
            fwd.solve_in_place(&mut x).unwrap();
            cols.solve_in_place(&mut y).unwrap();
            let e = max_rel(&x, &y);
            assert!(e < 1e-12, "step {step}: forms differ by {e:e}");
            differ |= x.iter().zip(&y).any(|(u, w)| u.to_bits() != w.to_bits());
            let e = max_rel(&x, &dense_solve(&a, &v, &b));
            assert!(e < 1e-12, "step {step}: against the dense solve {e:e}");
        }
        // Different sums (not the columns form under another name), on the paths.
        assert!(differ);
        let s = fwd.stats();
        assert!(
            s.promotion_columns_solved > 0 && s.promotion_reach_rows > 0,
            "{s:?}"
        );
        assert_eq!(cols.stats().promotion_reach_rows, 0);
        let (f, _, _) = run_rank(None, 50, false, PromotionForm::Forward);
        let (c, _, _) = run_rank(None, 50, false, PromotionForm::Columns);
        let e = max_rel(&f, &c);
        assert!(e < 1e-12, "split solves differ by {e:e}");
    }

    /// A chain like [`chain`] with pseudo-random positive spring values (a fixed linear
    /// congruential sequence), so that no two separators' condensations are alike.
    fn random_chain(nodes: usize, extra: usize) -> CscMatrix {
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            0.5 + (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut a = chain(nodes, extra);
        // Symmetric values: scale entry (i, j) and (j, i) alike, keep diagonal dominance.
        let n = a.n;
        let mut scale = std::collections::HashMap::new();
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p];
                let f = *scale.entry((i.min(j), i.max(j))).or_insert_with(&mut next);
                a.values[p] *= if i == j { 1.0 + f } else { f };
            }
        }
        a
    }

    #[test]
    fn the_top_chain_condensation_solves_as_the_whole_top_system() {
        // 400 nodes = 1200 chain equations in blocks of 30 (about 36 blocks, groups of 4),
        // and the unsymmetric coupling moving along the chain: the top system solved
        // through the condensed groups against the whole top system, every factorization,
        // with a new key at step 4 (every block and group condensed again).
        let a = random_chain(400, 6);
        let n = a.n;
        let v_moving = |step: usize| {
            let at = 3 * (53 * step % 390);
            let mut v = Vec::new();
            for (k, &(i, j)) in [(at, n - 6), (at + 4, n - 5), (n - 4, at + 7)]
                .iter()
                .enumerate()
            {
                let s = 3.0 + k as f64;
                v.extend([(i, i, s), (j, j, s), (i, j, -s), (j, i, -0.7 * s)]);
            }
            v
        };
        let options = |groups| PartitionOptions {
            block_size: 30,
            threads: 2,
            top_group_blocks: groups,
            ..Default::default()
        };
        let mut reduced = Partitioned::new(false, options(4));
        let mut whole = Partitioned::new(false, options(0));
        let mut condensed_seen = 0;
        for step in 0..8 {
            let v = v_moving(step);
            let key = if step < 4 {
                [1.0, 0.0, 0.0]
            } else {
                [2.0, 0.0, 0.0]
            };
            let a_step = if step < 4 {
                a.clone()
            } else {
                let mut b = a.clone();
                b.values.iter_mut().for_each(|x| *x *= 1.5);
                b
            };
            reduced.factor(&a_step, key, &v).unwrap();
            whole.factor(&a_step, key, &v).unwrap();
            assert_eq!(reduced.top_equations(), whole.top_equations());
            let s = reduced.stats();
            assert!(s.top_groups >= 8, "{s:?}");
            assert!(
                s.top_reduced_equations < s.top_equations,
                "step {step}: {s:?}"
            );
            condensed_seen += s.top_groups_condensed;
            // The top solve alone, and a whole solve.
            let nt = reduced.top_equations().len();
            let g: Vec<f64> = (0..nt).map(|k| ((k * 29 % 13) as f64) - 6.0).collect();
            let (mut xr, mut xw) = (g.clone(), g.clone());
            reduced.solve_top(&mut xr).unwrap();
            whole.solve_top(&mut xw).unwrap();
            // Two backward-stable eliminations of one well-conditioned system (the chain's
            // condition is about 1e2): they agree to round-off.
            let e = max_rel(&xr, &xw);
            assert!(e < 1e-12, "step {step}: top solves differ by {e:e}");
            let b = rhs(n);
            let (mut x1, mut x2) = (b.clone(), b.clone());
            reduced.solve_in_place(&mut x1).unwrap();
            whole.solve_in_place(&mut x2).unwrap();
            let e = max_rel(&x1, &x2);
            assert!(e < 1e-12, "step {step}: solves differ by {e:e}");
            let e = max_rel(&x1, &dense_solve(&a_step, &v, &b));
            assert!(e < 1e-12, "step {step}: against the dense solve {e:e}");
            // S_A·x through the groups' M and the reduced system's own part.
            let (mut yr, mut yw) = (vec![0.0; nt], vec![0.0; nt]);
            reduced.top_constant_times(&g, &mut yr);
            whole.top_constant_times(&g, &mut yw);
            let e = max_rel(&yr, &yw);
            assert!(e < 1e-12, "step {step}: S_A·x differs by {e:e}");
        }
        let s = reduced.stats();
        assert!(condensed_seen >= 8 * 4, "{s:?}");
        // Each group condensed once per key (the far groups reused between
        // factorizations), at most.
        assert!(s.top_group_condensations <= 2 * s.top_groups, "{s:?}");
        assert!(s.top_group_condensations > 0, "{s:?}");
    }

    /// Two "axles" four nodes apart rolling one node per factorization along `chain(200,
    /// 6)`, each coupling the two chain nodes under it (all three DOFs) to the vehicle's
    /// equations 600..606: the rear axle reaches the nodes the front one left four
    /// factorizations before.
    fn rolling(step: usize) -> Vec<(usize, usize, f64)> {
        let mut v = Vec::new();
        for (axle, node) in [(0usize, 20 + step), (1, 16 + step)] {
            for d in 0..6 {
                let (i, j) = (3 * node + d, 600 + 3 * axle + d % 3);
                let s = 2.0 + d as f64;
                v.extend([(i, i, s), (j, j, s), (i, j, -s), (j, i, -0.9 * s)]);
            }
        }
        v
    }

    /// Promotions that keep their columns of `Z = A_II⁻¹·E_P` give, to the bit, the
    /// solution of a solver that solves every column afresh (a new solver each
    /// factorization: no previous promotion); both are a direct solve's to round-off.
    #[test]
    fn reused_promotion_columns_give_the_fresh_columns_answers_to_the_bit() {
        check_reused_columns(PromotionForm::Columns);
    }

    /// [`reused_promotion_columns_give_the_fresh_columns_answers_to_the_bit`] in the
    /// forward form (the kept columns of `Y = L⁻¹·P·E_P`).
    #[test]
    fn reused_forward_columns_give_the_fresh_columns_answers_to_the_bit() {
        check_reused_columns(PromotionForm::Forward);
    }

    /// The solver of `form` in blocks of 50 equations on two threads.
    fn in_form(form: PromotionForm) -> Partitioned {
        let mut p = in_blocks(false, 50, 2);
        p.set_promotion_form(form);
        p
    }

    fn check_reused_columns(form: PromotionForm) {
        let a = chain(200, 6);
        let n = a.n;
        let mut p = in_form(form);
        let mut fresh_columns = 0;
        for step in 0..24 {
            let v = rolling(step);
            let b = rhs(n);
            p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let mut x = b.clone();
            p.solve_in_place(&mut x).unwrap();
            let mut q = in_form(form);
            q.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let mut y = b.clone();
            q.solve_in_place(&mut y).unwrap();
            let qs = q.stats();
            assert_eq!(qs.promotion_columns_kept, 0);
            fresh_columns += qs.promotion_columns_solved;
            let same = x.iter().zip(&y).all(|(u, w)| u.to_bits() == w.to_bits());
            assert!(same, "step {step}: {:e}", max_rel(&x, &y));
            // Well-conditioned (condition ≈ 1e2): a direct solve agrees to round-off.
            let e = max_rel(&x, &dense_solve(&a, &v, &b));
            assert!(e < 1e-12, "step {step}: relative difference {e:e}");
        }
        let s = p.stats();
        assert!(s.promotion_columns_kept > 0, "{s:?}");
        // Every column of every promotion is counted once, by how it was obtained; the
        // fresh solvers formed the same promotions, plus those the reused solver skipped
        // (an unchanged promoted set forms none).
        let used = s.promotion_columns_solved + s.promotion_columns_kept;
        assert!(used <= fresh_columns, "{used} {fresh_columns}");
        // An axle moving one node keeps the columns of the node it stays on: at most half
        // of its columns are new at each step after the first.
        assert!(
            2 * s.promotion_columns_solved <= fresh_columns + 24,
            "{s:?} {fresh_columns}"
        );
    }

    /// Four axles of a train on the chain of [`chain`]`(nodes, 12)`, `step` nodes on from
    /// node 100: each couples the two chain nodes under it (six equations) to its three
    /// vehicle equations by springs (symmetric: the top system is factored by Cholesky).
    fn train_at(nodes: usize, step: usize) -> Vec<(usize, usize, f64)> {
        let mut v = Vec::new();
        for axle in 0..4 {
            let node = 100 + step + 7 * axle;
            for d in 0..6 {
                let (i, j) = (3 * node + d, 3 * nodes + 3 * axle + d % 3);
                let s = 2.0 + d as f64;
                v.extend([(i, i, s), (j, j, s), (i, j, -s), (j, i, -s)]);
            }
        }
        v
    }

    /// A train moving one node a step keeps the top system's symbolic analysis while each
    /// of its wheels' equations stays in its block and between the same separator
    /// equations: the top system's pattern is then the last one. The count of analyses is
    /// derived from the motion and the split alone (a new one at the first factorization
    /// and whenever a wheel's equation enters another block, meets a separator or passes
    /// one of its equations), and the solutions equal a fresh solver's (a fresh analysis)
    /// to the bit.
    #[test]
    fn a_train_moving_within_its_blocks_keeps_the_top_analysis_to_the_bit() {
        let nodes = 8000;
        let a = chain(nodes, 12);
        let n = a.n;
        let options = PartitionOptions {
            block_size: 200,
            threads: 2,
            top_group_blocks: 0,
            ..Default::default()
        };
        let mut p = Partitioned::new(true, options);
        let mut last: Option<Vec<(u32, usize)>> = None;
        let (mut expected, mut kept) = (0, 0);
        for step in 0..40 {
            let v = train_at(nodes, step);
            p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            // Where each wheel equation is: its block (or none: a base top equation) and
            // how many base top equations come before it. The top system's pattern is the
            // last one while these stay.
            let at: Vec<(u32, usize)> = v
                .iter()
                .flat_map(|&(i, j, _)| [i, j])
                .map(|e| (p.block_of[e], p.base_top.partition_point(|&t| t < e)))
                .collect();
            if last.as_ref() == Some(&at) {
                kept += 1;
            } else {
                expected += 1;
            }
            last = Some(at);
            assert!(p.top.len() > crate::thresholds::DENSE_LIMIT, "a sparse top");
            assert_eq!(p.stats().top_symbolic_analyses, expected, "step {step}");
            let b = rhs(n);
            let mut x = b.clone();
            p.solve_in_place(&mut x).unwrap();
            let mut q = Partitioned::new(true, options);
            q.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let mut y = b.clone();
            q.solve_in_place(&mut y).unwrap();
            assert_eq!(q.stats().top_symbolic_analyses, 1);
            let same = x.iter().zip(&y).all(|(u, w)| u.to_bits() == w.to_bits());
            assert!(same, "step {step}: {:e}", max_rel(&x, &y));
        }
        // The blocks hold about 66 nodes: most moves stay within them.
        assert!(
            kept >= 20 && expected >= 3,
            "kept {kept}, analysed {expected}"
        );
    }

    /// The moving coupling of `matches_a_dense_solve_with_moving_coupling` at `step`.
    fn moving(step: usize) -> Vec<(usize, usize, f64)> {
        let at = 3 * (37 * step % 190);
        let mut v = Vec::new();
        for (k, &(i, j)) in [(at, 600), (at + 4, 601), (602, at + 7), (603, 604)]
            .iter()
            .enumerate()
        {
            let s = 3.0 + k as f64;
            v.push((i, i, s));
            v.push((j, j, s));
            v.push((i, j, -s));
            v.push((j, i, -0.8 * s));
        }
        v
    }

    /// Everything a rank computes over eight factorizations of the moving coupling (a new
    /// key at step 5, so every block is factored again): full solves, and the split solve
    /// of the condensed Newton with a two-column back-substitution.
    /// `a` with only the columns `keep` (the same pattern id: the solver takes it for the
    /// whole matrix's).
    fn only_columns(a: &CscMatrix, keep: &[bool]) -> CscMatrix {
        let mut b = CscMatrix {
            n: a.n,
            col_ptr: vec![0],
            row_idx: Vec::new(),
            values: Vec::new(),
            pattern_id: a.pattern_id,
        };
        for j in 0..a.n {
            if keep[j] {
                let r = a.col_ptr[j]..a.col_ptr[j + 1];
                b.row_idx.extend_from_slice(&a.row_idx[r.clone()]);
                b.values.extend_from_slice(&a.values[r]);
            }
            b.col_ptr.push(b.row_idx.len());
        }
        b
    }

    /// Eight factorizations and solves on one rank of `exchange` (`None`: one process): the
    /// answers, the counters and the columns of `A` the rank kept. With `restrict` (across
    /// ranks) each rank hands the solver only [`Partitioned::columns_read`] of `A`.
    fn run_rank(
        exchange: Option<Arc<dyn Exchange>>,
        block_size: usize,
        restrict: bool,
        form: PromotionForm,
    ) -> (Vec<f64>, PartitionStats, usize) {
        let a = chain(200, 6);
        let n = a.n;
        let mut p = in_blocks(false, block_size, 1);
        p.set_promotion_form(form);
        if let Some(ex) = exchange {
            p.set_exchange(ex);
        }
        p.prepare(&a);
        let keep = p
            .columns_read()
            .filter(|_| restrict)
            .unwrap_or_else(|| vec![true; n]);
        let kept = keep.iter().filter(|&&k| k).count();
        let mut out = Vec::new();
        for step in 0..8 {
            let key = if step < 5 {
                [1.0, 0.0, 0.0]
            } else {
                [1.0, 0.5, 0.0]
            };
            let mut a = only_columns(&a, &keep);
            a.values.iter_mut().for_each(|v| *v *= 1.0 + key[1]);
            p.factor(&a, key, &moving(step)).unwrap();
            let mut x: Vec<f64> = rhs(n).iter().map(|v| v + step as f64).collect();
            p.solve_in_place(&mut x).unwrap();
            out.extend_from_slice(&x);
            let b = rhs(n);
            let mut g = p.condense_rhs(&b).unwrap();
            p.solve_top(&mut g).unwrap();
            let mut sx = vec![0.0; p.top_equations().len()];
            p.top_constant_times(&g, &mut sx);
            let (mut o1, mut o2) = (vec![1.0; n], vec![0.0; n]);
            p.back_substitute(
                &[(Some(&b), &g), (None, &sx)],
                &mut [&mut o1, &mut o2],
                true,
            )
            .unwrap();
            out.extend(g.iter().chain(&sx).chain(&o1).chain(&o2));
        }
        (out, p.stats(), kept)
    }

    #[test]
    fn across_thread_ranks_the_answers_are_one_process_answers() {
        let forms = [PromotionForm::Columns, PromotionForm::Forward];
        for (block_size, restrict, form) in [(50, false), (250, false), (50, true), (250, true)]
            .into_iter()
            .flat_map(|(b, r)| forms.map(|f| (b, r, f)))
        {
            let (serial, s1, _) = run_rank(None, block_size, restrict, form);
            for ranks in [2, 3] {
                let results: Vec<(Vec<f64>, PartitionStats, usize)> = std::thread::scope(|sc| {
                    let hs: Vec<_> = crate::exchange::thread_ranks(ranks)
                        .into_iter()
                        .map(|ex| sc.spawn(move || run_rank(Some(ex), block_size, restrict, form)))
                        .collect();
                    hs.into_iter().map(|h| h.join().unwrap()).collect()
                });
                // With `restrict`, each rank holds only the columns it reads: its blocks'
                // interiors and, on rank 0, the base top set; these split the equations.
                let kept: usize = results.iter().map(|r| r.2).sum();
                let n = chain(200, 6).n;
                let expected = if restrict { n } else { ranks * n };
                assert_eq!(kept, expected, "{ranks} ranks, blocks of {block_size}");
                for (r, (x, st, _)) in results.iter().enumerate() {
                    // The same operations in the same order (rank 0 sums the pieces in block
                    // order): round-off alone could differ, and 1e-12 bounds it.
                    let e = max_rel(x, &serial);
                    assert!(
                        e <= 1e-12,
                        "{ranks} ranks, rank {r}, blocks of {block_size}: {e:e}"
                    );
                    assert_eq!(st.ranks, ranks);
                    assert!(st.comm.bytes_received > 0, "{st:?}");
                }
                // Every block is owned by exactly one rank, and factored only there.
                let owned: usize = results.iter().map(|r| r.1.owned_blocks).sum();
                assert_eq!(owned, s1.blocks, "{ranks} ranks, blocks of {block_size}");
                let factored: usize = results.iter().map(|r| r.1.block_factorizations).sum();
                assert_eq!(factored, s1.block_factorizations);
                let sent: u64 = results.iter().map(|r| r.1.comm.bytes_sent).sum();
                let received: u64 = results.iter().map(|r| r.1.comm.bytes_received).sum();
                assert_eq!(sent, received);
            }
        }
    }

    #[test]
    fn ownership_is_contiguous_complete_and_balanced() {
        let sizes = [10, 10, 10, 10, 40, 10, 10];
        for ranks in 1..=9 {
            let r = ownership(&sizes, ranks);
            assert_eq!(r.len(), ranks);
            assert_eq!(r[0].start, 0);
            assert_eq!(r[ranks - 1].end, sizes.len());
            for w in r.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
        }
        // Two ranks: the 40-equation block's middle (at 60 of 100) falls in the second half.
        assert_eq!(ownership(&sizes, 2), vec![0..4, 4..7]);
        assert_eq!(ownership(&[], 3), vec![0..0, 0..0, 0..0]);
    }

    #[test]
    fn small_models_degenerate_to_one_direct_solve() {
        let a = chain(10, 0);
        let mut p = Partitioned::new(true, PartitionOptions::default());
        p.factor(&a, [1.0, 0.0, 0.0], &[]).unwrap();
        assert_eq!(p.stats().blocks, 0);
        assert_eq!(p.stats().top_equations, 30);
        let b = rhs(30);
        let mut x = b.clone();
        p.solve_in_place(&mut x).unwrap();
        assert!(max_rel(&x, &dense_solve(&a, &[], &b)) < 1e-13);
    }

    #[test]
    fn a_new_key_refactors_every_block_and_a_singular_block_names_its_equation() {
        let mut a = chain(300, 0);
        let mut p = in_blocks(true, 90, 1);
        p.factor(&a, [1.0, 0.0, 0.0], &[]).unwrap();
        let first = p.stats().block_factorizations;
        p.factor(&a, [1.0, 0.0, 0.0], &[]).unwrap();
        assert_eq!(p.stats().block_factorizations, first);
        // Equation 450 (node 150) loses all its stiffness: singular.
        for j in 0..a.n {
            for q in a.col_ptr[j]..a.col_ptr[j + 1] {
                if a.row_idx[q] == 450 || j == 450 {
                    a.values[q] = 0.0;
                }
            }
        }
        match p.factor(&a, [2.0, 0.0, 0.0], &[]) {
            Err(SolverError::Singular { equation }) => assert_eq!(equation, 450),
            other => panic!("expected a singular block, got {other:?}"),
        }
    }

    /// One process's scan (the driver's): the first entry strictly larger in magnitude
    /// than every earlier one, `(0.0, 0)` if none is above zero.
    fn first_largest(x: &[f64]) -> (f64, usize) {
        x.iter().enumerate().fold(
            (0.0, 0),
            |best, (i, v)| {
                if v.abs() > best.0 {
                    (v.abs(), i)
                } else {
                    best
                }
            },
        )
    }

    #[test]
    fn across_thread_ranks_the_largest_entry_is_one_process_first_largest() {
        let a = chain(200, 6);
        let n = a.n;
        // Values in −5..5: |5| occurs at many equations, in every rank's rows, so the tie
        // rule decides; then one clear maximum late in the equations; NaNs and zeros
        // elsewhere; all zeros.
        let ties = rhs(n);
        let mut late = rhs(n);
        late[n - 40] = -9.5;
        let mut nan = vec![0.0; n];
        nan[3] = f64::NAN;
        nan[n / 2] = 1e-300;
        // Equal maxima at a chain equation near the end and at the last free equation (a
        // base top equation, rank 0's): the lower index wins wherever it is held.
        let mut pair = vec![0.0; n];
        pair[n - 1] = 8.0;
        pair[597] = -8.0;
        let cases = [ties, late, nan, vec![0.0; n], pair];
        let expected: Vec<(f64, usize)> = cases.iter().map(|x| first_largest(x)).collect();
        assert_eq!(expected[0], (5.0, first_largest(&cases[0]).1));
        assert_eq!(expected[1], (9.5, n - 40));
        assert_eq!(expected[2], (1e-300, n / 2));
        assert_eq!(expected[3], (0.0, 0));
        assert_eq!(expected[4], (8.0, 597));
        for ranks in [2, 3] {
            let found: Vec<Vec<(f64, usize)>> = std::thread::scope(|sc| {
                let hs: Vec<_> = crate::exchange::thread_ranks(ranks)
                    .into_iter()
                    .map(|ex| {
                        let (a, cases) = (&a, &cases);
                        sc.spawn(move || {
                            let mut p = in_blocks(false, 50, 1);
                            p.set_exchange(ex);
                            p.prepare(a);
                            // A rank holds only its owned rows; whatever the others hold
                            // (here larger than any true entry) must not count.
                            let mut owned = vec![false; n];
                            for b in &p.blocks[p.owned()] {
                                b.all.iter().for_each(|&i| owned[i] = true);
                            }
                            if p.is_root() {
                                p.base_top.iter().for_each(|&i| owned[i] = true);
                            }
                            cases
                                .iter()
                                .map(|x| {
                                    let mine: Vec<f64> = (0..n)
                                        .map(|i| if owned[i] { x[i] } else { 1e9 + i as f64 })
                                        .collect();
                                    p.largest_over_rows(&mine).expect("across ranks")
                                })
                                .collect()
                        })
                    })
                    .collect();
                hs.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for (r, got) in found.iter().enumerate() {
                assert_eq!(got, &expected, "{ranks} ranks, rank {r}");
            }
        }
        // One process: no collective, the caller scans.
        let mut p = Partitioned::new(false, PartitionOptions::default());
        p.prepare(&a);
        assert_eq!(p.largest_over_rows(&cases[0]), None);
    }

    /// The Newton check's element-force reference across ranks: each rank's own
    /// `Σ_e |f_e|²` reduced to the largest (the same on every rank) in the collective that
    /// sums the norms, and those norms unchanged by it: against one process's sums over the
    /// whole vectors (the same squares in another order: 1e-13) and against
    /// [`Partitioned::sums_of_squares`] without the extra value (bit for bit).
    #[test]
    fn across_thread_ranks_the_element_force_reference_is_the_largest_rank_sum() {
        let a = chain(200, 6);
        let n = a.n;
        let x = rhs(n);
        let y: Vec<f64> = x.iter().map(|v| 3.0 * v - 1.0).collect();
        let whole = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>();
        let expected = [whole(&x), whole(&y)];
        for ranks in [2, 3] {
            // Rank k's sum: 100 + k (ranks differing by round-off would differ so little;
            // distinct values show which one wins). Rank 1 holds the largest with 2 ranks.
            let found: Vec<(Vec<f64>, f64, Vec<f64>)> = std::thread::scope(|sc| {
                let hs: Vec<_> = crate::exchange::thread_ranks(ranks)
                    .into_iter()
                    .enumerate()
                    .map(|(k, ex)| {
                        let (a, x, y) = (&a, &x, &y);
                        sc.spawn(move || {
                            let mut p = in_blocks(false, 50, 1);
                            p.set_exchange(ex);
                            p.prepare(a);
                            let local = if k == ranks - 1 {
                                100.0 + 7.0
                            } else {
                                100.0 + k as f64
                            };
                            let (sums, largest) = p
                                .sums_of_squares_and_max(&[x, y], Some(local))
                                .expect("across ranks");
                            let plain = p.sums_of_squares(&[x, y]).expect("across ranks");
                            (sums, largest, plain)
                        })
                    })
                    .collect();
                hs.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for (r, (sums, largest, plain)) in found.iter().enumerate() {
                assert_eq!(*largest, 107.0, "{ranks} ranks, rank {r}");
                assert_eq!(sums, plain, "{ranks} ranks, rank {r}");
                for (s, e) in sums.iter().zip(&expected) {
                    assert!(
                        (s - e).abs() <= 1e-13 * e,
                        "{ranks} ranks, rank {r}: {s} vs {e}"
                    );
                }
            }
        }
        // One process: no collective, the driver forms its own sums.
        let mut p = Partitioned::new(false, PartitionOptions::default());
        p.prepare(&a);
        assert_eq!(p.sums_of_squares_and_max(&[&x], Some(1.0)), None);
    }
}
