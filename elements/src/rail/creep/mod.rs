//! Rolling contact (issue 14): the Hertz contact ellipse of wheel and rail ([`hertz`]),
//! Kalker's linear creep coefficients with the creep forces of the linear theory and their
//! Shen–Hedrick–Elkins saturation ([`kalker`]), the tangential laws the `moving_axle`
//! element offers with their exact gradients ([`law`], on the dual numbers of [`dual`]).
//! The creepages themselves come from the element's kinematics (`super::rolling`).

pub mod dual;
pub mod hertz;
pub mod kalker;
pub mod law;
