//! Rolling contact (issue 14): the Hertz contact ellipse of wheel and rail ([`hertz`]),
//! Kalker's linear creep coefficients with the creep forces of the linear theory and their
//! Shen–Hedrick–Elkins saturation ([`kalker`]), the tangential laws the `moving_axle`
//! element offers with their exact gradients ([`law`], on the dual numbers of [`dual`];
//! Kalker's FASTSIM in [`fastsim`]); the
//! wheelset contact geometry and equivalent conicity of rigid profiles ([`conicity`]) and
//! the linearised wheelset and bogie with their critical speed ([`linear_wheelset`]).
//! The creepages themselves come from the element's kinematics (`crate::rail::contact::rolling`).

pub mod conicity;
pub mod dual;
pub mod fastsim;
pub mod hertz;
pub mod kalker;
pub mod law;
pub mod linear_wheelset;
