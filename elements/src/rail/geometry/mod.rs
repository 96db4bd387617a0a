//! The track's geometry and structure: the plan alignment ([`alignment`]), cant and the
//! track frames ([`cant`]), rail lines for meshing and lookup ([`railline`]), member
//! sections ([`rail_section`]), the two-rail track mesh ([`track_model`]), slab and bridge
//! components under the rails ([`bridge`]), track irregularities ([`irregularity`]) and
//! rail-top defects ([`rail_defect`]).

pub mod alignment;
pub mod bridge;
pub mod cant;
pub mod irregularity;
pub mod rail_defect;
pub mod rail_section;
pub mod railline;
pub mod track_model;
