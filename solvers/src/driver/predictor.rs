//! The increment predictor's memory ([`IncrementPredictor`]): the last converged transient
//! step's length and increment, from which [`Predictor::Increment`] starts the next step's
//! Newton iterations at `q_n + (Δt/Δt_prev)·(q_n − q_{n−1})`.

use railfem_framework::dofmap::DofMap;
use railfem_framework::model::Predictor;

/// The last converged step's `Δt` and increment `q_n − q_{n−1}` (on finite-rotation triples
/// the incremental rotation vector, [`DofMap::increment`]); `None` before the first step
/// and always with the default predictor.
#[derive(Debug, Clone, Default)]
pub(crate) struct IncrementPredictor {
    last: Option<(f64, Vec<f64>)>,
}

impl IncrementPredictor {
    /// The last step's length and increment, if one is kept.
    pub(crate) fn last(&self) -> Option<&(f64, Vec<f64>)> {
        self.last.as_ref()
    }

    /// After a step of length `dt` from `q0` to `q1` is committed: its increment, kept in
    /// the last one's vector, when `predictor` is [`Predictor::Increment`]; forgotten
    /// otherwise.
    pub(crate) fn committed(
        &mut self,
        predictor: Predictor,
        dofmap: &DofMap,
        dt: f64,
        q0: &[f64],
        q1: &[f64],
    ) {
        let kept = self.last.take();
        if dt > 0.0 && predictor == Predictor::Increment {
            let mut inc = kept.map(|(_, v)| v).unwrap_or_default();
            inc.resize(q1.len(), 0.0);
            dofmap.increment(q0, q1, &mut inc);
            self.last = Some((dt, inc));
        }
    }

    /// The kept increment, to zero some of its entries (the rows held by the activity
    /// window, [`crate::window`]).
    pub(crate) fn increment_mut(&mut self) -> Option<&mut Vec<f64>> {
        self.last.as_mut().map(|(_, v)| v)
    }

    /// Bytes of the kept increment, as allocated.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.last.as_ref().map_or(0, |(_, v)| 8 * v.capacity())
    }
}
