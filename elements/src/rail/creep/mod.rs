//! Rolling contact, first piece of issue 14: the Hertz contact ellipse of wheel and rail
//! ([`hertz`]) and Kalker's linear creep coefficients with the creep forces of the linear
//! theory and their Shen–Hedrick–Elkins saturation ([`kalker`]). Nothing here is wired into an
//! element yet; see docs/creep.md for what remains.

pub mod conicity;
pub mod hertz;
pub mod kalker;
pub mod linear_wheelset;
