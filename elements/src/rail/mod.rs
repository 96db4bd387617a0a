//! The rail toolkit: alignment and cant, track meshes, profiles, contact geometry, the
//! moving wheel-axle element and the point-contact wheels, vehicles and the simple theory
//! of the paper's Section 3.

pub mod alignment;
pub mod bridge;
pub mod cant;
pub mod contact_geometry;
pub mod contact_law;
pub mod creep;
pub mod hertz_spring;
pub mod irregularity;
pub mod lean;
pub mod moving_axle;
pub mod point_contact_law;
pub mod point_wheel;
pub mod profiles;
pub mod rail_defect;
pub mod rail_point;
pub mod rail_section;
pub mod railline;
pub mod rolling;
pub mod section_plot;
pub mod sections;
pub mod theory;
pub mod track_model;
pub mod vehicle;
pub mod wheel_defect;
