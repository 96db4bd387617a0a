//! The caches the condensed Newton keeps between steps ([`CondensedCache`]: the top
//! equations' constant products, the next predictor's products formed ahead, scratch and
//! the counters [`CondensedStats`]). The condensed Newton owns the caches
//! ([`crate::step_method::CondensedNewton`]); the counters are the driver's record of the
//! run ([`crate::driver::Driver::condensed_stats`]). [`crate::condensed`] reads and fills
//! both.

/// Counters of the condensed Newton.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CondensedStats {
    /// Steps completed by the condensed Newton.
    pub steps: usize,
    /// Iterations on the top system alone (no full residual).
    pub top_iterations: usize,
    /// Full evaluations (the first of each step and each verification).
    pub full_evaluations: usize,
    /// Verifications whose full test did not pass (the screen passed too early).
    pub rejected: usize,
    /// Verified steps whose exact force or displacement tolerance exceeded the screen's
    /// estimate by more than its factor 2 (see the module documentation).
    pub margin_exceeded: usize,
    /// Steps handed back to the full-residual Newton.
    pub fallbacks: usize,
    /// Predictor evaluations whose products the previous step's verification had formed
    /// (no pass over the constant matrices).
    pub predictors_reused: usize,
}

/// Caches kept between steps.
#[derive(Debug, Default)]
pub struct CondensedCache {
    /// The constant matrices between top equations, for the top generation they were built.
    pub(crate) products: Option<TopProducts>,
    /// `|f_int|`, `|M·a_w|` at the last converged step.
    pub(crate) last_norms: Option<(f64, f64)>,
    /// What the last accepted verification formed for the next step's predictor.
    pub(crate) ahead: Ahead,
    /// `false`: the verification forms no products for the next step or the energy
    /// balance (the driver's switch as last applied,
    /// [`crate::driver::Driver::set_products_ahead`]; a comparison switch).
    pub(crate) no_products_ahead: bool,
    /// Scratch for the variable elements' forces, resisting, inertia and damping: zero
    /// between uses (only the variable elements' equations are ever written, and they are
    /// zeroed again after each read).
    pub(crate) var_scratch: [Vec<f64>; 3],
}

/// The next step's predictor products, formed in the verification's pass over the constant
/// matrices (module documentation, *Per step*).
#[derive(Debug, Default)]
pub(crate) struct Ahead {
    /// `Δt` the products were formed for; `None`: nothing valid.
    pub(crate) dt: Option<f64>,
    /// The displacement `q` of the accepted state and `K_const·q`.
    pub(crate) q: Vec<f64>,
    pub(crate) kq: Vec<f64>,
    /// The next predictor's weighted kinematics `a_w`, `v_w` (at `Δu = 0` from the accepted
    /// state) and `M_const·a_w`, `C_const·v_w`.
    pub(crate) a_w: Vec<f64>,
    pub(crate) v_w: Vec<f64>,
    pub(crate) inertia: Vec<f64>,
    pub(crate) damp: Vec<f64>,
}

impl Ahead {
    pub(crate) fn resize(&mut self, n: usize) {
        for x in [
            &mut self.q,
            &mut self.kq,
            &mut self.a_w,
            &mut self.v_w,
            &mut self.inertia,
            &mut self.damp,
        ] {
            x.resize(n, 0.0);
        }
    }
}

/// `K`, `M`, `C` restricted to the top equations (top numbering, column-compressed).
#[derive(Debug)]
pub(crate) struct TopProducts {
    pub(crate) generation: u64,
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) rows: Vec<u32>,
    pub(crate) k: Vec<f64>,
    pub(crate) m: Vec<f64>,
    pub(crate) c: Vec<f64>,
}
