//! Wheels on rails: the moving wheel-axle contact element of Ju & Ro (2021)
//! ([`moving_axle`]), the point-contact wheels `hertz_wheel` and `rigid_wheel`
//! ([`point_wheel`]), the rail point under a wheel ([`rail_point`]) and wheel tread defects
//! ([`wheel_defect`]).

pub mod moving_axle;
pub mod point_wheel;
pub mod rail_point;
pub mod wheel_defect;
