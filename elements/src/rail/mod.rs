//! The rail toolkit: alignment and cant, track meshes, profiles, contact geometry, the
//! moving wheel-axle element, vehicles and the simple theory of the paper's Section 3.

pub mod alignment;
pub mod cant;
pub mod profiles;
pub mod railline;
pub mod theory;
