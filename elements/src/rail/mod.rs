//! The rail toolkit, grouped as a railway engineer looks for it:
//!
//! - [`geometry`]: the track's plan and section — alignment and cant, rail lines and
//!   meshes, the rail's section, slab and bridge under it, irregularities and rail-top
//!   defects;
//! - [`contact`]: wheel and rail profiles, the contact search, the contact laws (the
//!   paper's penalty law, the point wheels' laws, the Hertz spring) and rolling contact
//!   (Hertz patches, creep laws, conicity);
//! - [`wheels`]: the elements that carry a wheel along a rail — the moving wheel-axle
//!   element of Ju & Ro (2021), the point-contact wheels — the rail point under a wheel,
//!   and wheel tread defects;
//! - [`vehicle`]: trains of rigid bodies on suspensions, their quasi-static loads with body
//!   lean, and the simple theory of the paper's Section 3;
//! - [`sections`]: the model-file sections (`[track]`, `[[vehicle]]`, …) built from them.

pub mod contact;
pub mod geometry;
pub mod sections;
pub mod vehicle;
pub mod wheels;
