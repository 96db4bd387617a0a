//! railfem-framework: the generic core of the railfem finite element code.
//!
//! What lives here: DOFs and the model ([`dof`], [`model`]), the element contract
//! ([`element`], with typed per-node views of its vectors and matrices in [`node_view`]),
//! the registry, plugins and conformance kit ([`registry`], [`plugin`], [`conformance`]),
//! equation numbering
//! with constraints ([`dofmap`]), finite rotations ([`rotation`], on the dual numbers of
//! [`dual`]), sparse assembly ([`sparse`], [`assembly`], with the effective matrix's [`coefficients`]), loads and time series ([`loads`]),
//! moving reference frames ([`moving`]), paths along beam chains ([`beam_chain`]), speed
//! histories ([`speed`]), model files ([`modelfile`], [`strict_json`], [`keypath`]),
//! recorders and the names of every output ([`recorder`], [`outputs`]), the size
//! guards of generators ([`limits`]), and what CSV input readers share ([`csv_input`]).
//! What does not: concrete elements (railfem-elements) and solvers (railfem-solvers).
//!
//! Units are SI throughout: m, kg, s, N, rad.
#![deny(missing_docs)]
// Index loops are the clearest way to write small dense matrix algebra.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod assembly;
pub mod beam_chain;
pub mod builder;
pub mod coefficients;
pub mod conformance;
pub mod csv_input;
pub mod dof;
pub mod dofmap;
pub mod dual;
pub mod element;
pub mod elf;
pub mod error;
pub mod fft;
pub mod finite_link;
pub mod interrupt;
pub mod keypath;
pub mod kind_list;
pub mod limits;
pub mod load_kind;
pub mod loads;
pub mod lookup;
pub mod matrix_market;
pub mod model;
pub mod modelfile;
pub mod moving;
pub mod node_view;
pub mod outputs;
pub mod parallel;
pub mod plot;
pub mod plugin;
pub mod recorder;
pub mod recorder_kind;
pub mod recording;
pub mod registry;
pub mod released;
pub mod rotation;
pub mod row_set;
pub mod sparse;
pub mod speed;
pub mod strict_json;
pub mod vtk;

pub use builder::ModelBuilder;
pub use coefficients::Coefficients;
pub use dof::{Dof, DofSet};
pub use element::{
    DissipationKind, Element, ElementError, ElementProperties, NodeDofs, NodeKinematics,
    StepContext, TrialState,
};
pub use error::FemError;
pub use inventory;
pub use model::Model;
pub use node_view::{NodeBlocks, NodeForces, NodeState};
pub use serde_json;
