//! What a registered load or recorder may ask of the model while it resolves the ids a
//! model file gives: node and element indices, reference positions and element outputs
//! ([`ModelLookup`], implemented by [`crate::Model`]).
//!
//! It is read-only and knows nothing of loads or recorders, so the load and recorder
//! registries ([`crate::load_kind`], [`crate::recorder_kind`]) can take it without importing
//! the model that imports them.

use crate::analysis::AnalysisSpec;
use nalgebra::Vector3;

/// Read-only questions a load or recorder factory asks of the model.
pub trait ModelLookup {
    /// The model's origin (file name), for messages.
    fn origin(&self) -> &str;
    /// Index of the node with user id `id`.
    fn node_index(&self, id: u64) -> Option<usize>;
    /// Reference position of the node with index `index` (m).
    fn node_position(&self, index: usize) -> Vector3<f64>;
    /// Index of the element with user id `id`.
    fn element_index(&self, id: u64) -> Option<usize> {
        self.element_indices(&[id])[0]
    }
    /// Indices of the elements with user ids `ids`, in one pass over the elements (a path
    /// of a million beams is resolved in linear time).
    fn element_indices(&self, ids: &[u64]) -> Vec<Option<usize>>;
    /// Node indices of the element with index `index`, in connectivity order.
    fn element_nodes(&self, index: usize) -> Vec<usize>;
    /// Registered type name of the element with index `index`.
    fn element_kind(&self, index: usize) -> &str;
    /// Names of the outputs the element with index `index` reports.
    fn element_output_names(&self, index: usize) -> Vec<String>;
    /// Units of those outputs, in the same order (possibly shorter: undeclared).
    fn element_output_units(&self, index: usize) -> Vec<String>;
    /// User ids of every element of registered type `kind`, in model order.
    fn element_ids_of_kind(&self, kind: &str) -> Vec<u64>;
    /// The analysis settings.
    fn analysis(&self) -> &AnalysisSpec;
}
