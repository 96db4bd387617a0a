//! Wheel–rail contact: the profiles ([`profiles`]), the contact search of the moving-axle
//! element ([`contact_geometry`]), its frictional penalty law ([`contact_law`]), the point
//! wheels' laws ([`point_contact_law`]), the paper's vertical Hertz spring
//! ([`hertz_spring`]), rolling contact — Hertz patches, creep laws, conicity ([`creep`]) —
//! and creep at a contact point of the moving axle ([`rolling`]); a cross-section picture
//! of a wheel on its rail ([`section_plot`]).

pub mod contact_geometry;
pub mod contact_law;
pub mod creep;
pub mod hertz_spring;
pub mod point_contact_law;
pub mod profiles;
pub mod rolling;
pub mod section_plot;
