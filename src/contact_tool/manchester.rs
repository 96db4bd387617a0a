//! The Manchester contact benchmark (Shackleton & Iwnicki, "Comparison of wheel–rail
//! contact codes for railway vehicle simulation: an introduction to the Manchester Contact
//! Benchmark and initial results", Vehicle System Dynamics 46 (2008) 3–41): S1002 on UIC60
//! at 1:40, gauge 1435 mm, back to back 1360 mm, r0 = 460 mm, 10 kN per wheel, lateral
//! shift 0 … 10 mm; and the reference numbers of one code for it.
//!
//! # Reference
//!
//! [`CONTACT_A22`] holds E. Vollebregt's CONTACT results for the benchmark's case
//! (shift 0 … 10 mm with yaw 2.4·y rad/m, the wheelset roll prescribed from the benchmark),
//! as printed in the reference output files `examples/mbench_a22_left.ref_out` and
//! `examples/mbench_a22_right.ref_out` of <https://github.com/eve70a/CONTACT> (revision 2707,
//! 2025-07-23, Apache-2.0); the numbers are typed from there, no code is used. CONTACT's
//! track frame has `y` to the right and `z` down, so a positive shift brings its **right**
//! wheel to the flange; ours has `y` to the left. With `Y` the wheelset shift:
//!
//! | ours, shift `Y`             | CONTACT, shift `Y`                              |
//! |-----------------------------|-------------------------------------------------|
//! | left wheel `wheel_y`        | right wheel `YCP(W)`                            |
//! | left rail `rail_y`          | right wheel `YCP(R)`                            |
//! | left contact angle `δ`      | right wheel `−DELTCP(TR)`                       |
//! | left rolling radius − r0    | right wheel `ZCP(W)` (wheel profile `z`, down)  |
//! | right wheel `wheel_y`       | left wheel `−YCP(W)`                            |
//! | right rail `rail_y`         | left wheel `−YCP(R)`                            |
//! | right contact angle `δ`     | left wheel `DELTCP(TR)`                         |
//! | right rolling radius − r0   | left wheel `ZCP(W)`                             |
//! | roll `φ`                    | `−ROLL_WS`                                      |
//! | yaw `ψ`                     | `YAW` (the mirror image of a yaw to the flange) |
//! | pitch rate `Ω`              | `−VPITCH`                                       |
//! | `ξx`, `ξy`, `φ` (1/m)       | `−CKSI`, `−CETA`, `−1000·CPHI` (same wheel map) |
//! | `Fx`, `Fy` on the wheel     | `−FX`, `−FS` (CONTACT's act on the rail)        |
//!
//! CONTACT's creepages are the rail's velocity relative to the wheel over its rolling speed
//! `VELOC = (V + Ω·r)/2`, ours the wheel's relative to the rail over the same speed; both
//! codes give the lateral quantities in the contact plane. The spin moment `MN` is typed in
//! but not compared: none of our laws gives one.
//!
//! CONTACT's positions are those of the contact reference point of an elastic patch
//! (10 kN); ours are the rigid first-touch points; docs/contact-tool.md discusses the
//! differences.

use super::profiles::ProfileSet;
use super::{evaluate, geometry, Balance, ContactCase, CreepLaw, ShiftResult};
use crate::framework::FemError;
use std::fmt::Write as _;

/// CONTACT's output for one wheel (mm, rad, N; its own frame, see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wheel {
    /// `YCP(W)`: lateral position of the contact on the wheel profile (mm).
    pub ycp_w: f64,
    /// `YCP(R)`: lateral position on the rail profile (mm).
    pub ycp_r: f64,
    /// `DELTCP(TR)`: contact angle in the track frame (rad).
    pub deltcp: f64,
    /// `ZCP(W)`: wheel profile height at the contact, down positive (mm).
    pub zcp_w: f64,
    /// `FN`: normal force (N).
    pub fn_: f64,
    /// `CKSI`: longitudinal creepage (−).
    pub cksi: f64,
    /// `CETA`: lateral creepage (−).
    pub ceta: f64,
    /// `CPHI`: spin creepage (1/mm).
    pub cphi: f64,
    /// `FX`: longitudinal creep force on the rail (N).
    pub fx: f64,
    /// `FS`: lateral creep force on the rail, in the contact plane (N).
    pub fs: f64,
    /// `MN`: spin moment about the contact normal (N·mm).
    pub mn: f64,
}

/// CONTACT's input and output at one shift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    /// Wheelset shift (mm, CONTACT's sign).
    pub y_mm: f64,
    /// `ROLL_WS` (rad, CONTACT's sign).
    pub roll: f64,
    /// `YAW`: the prescribed yaw, 2.4·y rad/m (rad, CONTACT's sign).
    pub yaw: f64,
    /// `VPITCH`: the prescribed pitch rate of the wheelset (rad/s) at `VS` = 2000 mm/s.
    pub vpitch: f64,
    /// CONTACT's left wheel (our right).
    pub left: Wheel,
    /// CONTACT's right wheel (our left).
    pub right: Wheel,
}

/// CONTACT, Manchester benchmark case A-2.2 (module doc).
pub const CONTACT_A22: [Reference; 21] = [
    Reference {
        y_mm: 0.0,
        roll: 0.000000e+00,
        yaw: 0.0,
        vpitch: -4.3481181,
        left: Wheel {
            ycp_w: -1.8726,
            ycp_r: 8.66,
            deltcp: 0.029,
            zcp_w: -0.0729,
            fn_: 9997.0,
            cksi: -5.665000e-05,
            ceta: 0.000000e+00,
            cphi: -6.302000e-05,
            fx: 0.2783,
            fs: 253.6,
            mn: 4605.0,
        },
        right: Wheel {
            ycp_w: 1.8726,
            ycp_r: -8.66,
            deltcp: -0.029,
            zcp_w: -0.0729,
            fn_: 9997.0,
            cksi: -5.665000e-05,
            ceta: 0.000000e+00,
            cphi: 6.302000e-05,
            fx: 0.2783,
            fs: -253.6,
            mn: -4605.0,
        },
    },
    Reference {
        y_mm: 0.5,
        roll: -2.304000e-05,
        yaw: 0.0012,
        vpitch: -4.3474134,
        left: Wheel {
            ycp_w: -4.7204,
            ycp_r: 6.3233,
            deltcp: 0.0211,
            zcp_w: -0.1451,
            fn_: 10050.0,
            cksi: -3.708000e-04,
            ceta: 1.200000e-03,
            cphi: -4.592000e-05,
            fx: 887.1,
            fs: -2370.0,
            mn: 1340.0,
        },
        right: Wheel {
            ycp_w: -6.0075,
            ycp_r: -16.03,
            deltcp: -0.0568,
            zcp_w: 0.2522,
            fn_: 9870.0,
            cksi: 4.948000e-04,
            ceta: 1.202000e-03,
            cphi: 1.233000e-04,
            fx: -880.0,
            fs: -2579.0,
            mn: -3202.0,
        },
    },
    Reference {
        y_mm: 1.0,
        roll: -5.049000e-05,
        yaw: 0.0024,
        vpitch: -4.3465752,
        left: Wheel {
            ycp_w: -6.2694,
            ycp_r: 5.2886,
            deltcp: 0.0176,
            zcp_w: -0.1754,
            fn_: 10050.0,
            cksi: -6.297000e-04,
            ceta: 2.400000e-03,
            cphi: -3.848000e-05,
            fx: 829.2,
            fs: -2893.0,
            mn: 376.0,
        },
        right: Wheel {
            ycp_w: -9.0305,
            ycp_r: -18.5418,
            deltcp: -0.0696,
            zcp_w: 0.4288,
            fn_: 9827.0,
            cksi: 6.943000e-04,
            ceta: 2.407000e-03,
            cphi: 1.510000e-04,
            fx: -814.3,
            fs: -2832.0,
            mn: -227.9,
        },
    },
    Reference {
        y_mm: 1.5,
        roll: -8.103000e-05,
        yaw: 0.0036,
        vpitch: -4.346244,
        left: Wheel {
            ycp_w: -7.5089,
            ycp_r: 4.5657,
            deltcp: 0.0152,
            zcp_w: -0.196,
            fn_: 10050.0,
            cksi: -7.530000e-04,
            ceta: 3.599000e-03,
            cphi: -3.330000e-05,
            fx: 641.1,
            fs: -2942.0,
            mn: 215.2,
        },
        right: Wheel {
            ycp_w: -10.1558,
            ycp_r: -19.1554,
            deltcp: -0.0753,
            zcp_w: 0.5094,
            fn_: 9811.0,
            cksi: 7.903000e-04,
            ceta: 3.612000e-03,
            cphi: 1.633000e-04,
            fx: -619.8,
            fs: -2877.0,
            mn: -81.42,
        },
    },
    Reference {
        y_mm: 2.0,
        roll: -1.128000e-04,
        yaw: 0.0048,
        vpitch: -4.3459197,
        left: Wheel {
            ycp_w: -8.566,
            ycp_r: 4.027,
            deltcp: 0.0134,
            zcp_w: -0.2114,
            fn_: 10040.0,
            cksi: -8.651000e-04,
            ceta: 4.798000e-03,
            cphi: -2.947000e-05,
            fx: 546.3,
            fs: -2961.0,
            mn: 143.4,
        },
        right: Wheel {
            ycp_w: -11.1296,
            ycp_r: -19.6178,
            deltcp: -0.0806,
            zcp_w: 0.5853,
            fn_: 9799.0,
            cksi: 8.752000e-04,
            ceta: 4.818000e-03,
            cphi: 1.746000e-04,
            fx: -517.3,
            fs: -2893.0,
            mn: -37.57,
        },
    },
    Reference {
        y_mm: 2.5,
        roll: -1.457000e-04,
        yaw: 0.006,
        vpitch: -4.3455627,
        left: Wheel {
            ycp_w: -9.4982,
            ycp_r: 3.6148,
            deltcp: 0.0121,
            zcp_w: -0.2235,
            fn_: 10040.0,
            cksi: -9.792000e-04,
            ceta: 5.998000e-03,
            cphi: -2.655000e-05,
            fx: 492.1,
            fs: -2970.0,
            mn: 105.0,
        },
        right: Wheel {
            ycp_w: -12.0933,
            ycp_r: -20.0706,
            deltcp: -0.0862,
            zcp_w: 0.6657,
            fn_: 9787.0,
            cksi: 9.607000e-04,
            ceta: 6.025000e-03,
            cphi: 1.866000e-04,
            fx: -456.2,
            fs: -2900.0,
            mn: -25.37,
        },
    },
    Reference {
        y_mm: 3.0,
        roll: -1.803000e-04,
        yaw: 0.0072,
        vpitch: -4.3451503,
        left: Wheel {
            ycp_w: -10.3382,
            ycp_r: 3.2967,
            deltcp: 0.011,
            zcp_w: -0.2334,
            fn_: 10030.0,
            cksi: -1.103000e-03,
            ceta: 7.197000e-03,
            cphi: -2.432000e-05,
            fx: 460.5,
            fs: -2974.0,
            mn: 80.74,
        },
        right: Wheel {
            ycp_w: -13.0963,
            ycp_r: -20.5627,
            deltcp: -0.0923,
            zcp_w: 0.7553,
            fn_: 9774.0,
            cksi: 1.052000e-03,
            ceta: 7.235000e-03,
            cphi: 1.998000e-04,
            fx: -417.5,
            fs: -2902.0,
            mn: -23.9,
        },
    },
    Reference {
        y_mm: 3.5,
        roll: -2.168000e-04,
        yaw: 0.0084,
        vpitch: -4.3446688,
        left: Wheel {
            ycp_w: -11.1063,
            ycp_r: 3.0525,
            deltcp: 0.0102,
            zcp_w: -0.2418,
            fn_: 10030.0,
            cksi: -1.241000e-03,
            ceta: 8.395000e-03,
            cphi: -2.263000e-05,
            fx: 443.1,
            fs: -2976.0,
            mn: 65.56,
        },
        right: Wheel {
            ycp_w: -14.17,
            ycp_r: -21.1254,
            deltcp: -0.0994,
            zcp_w: 0.8583,
            fn_: 9760.0,
            cksi: 1.154000e-03,
            ceta: 8.447000e-03,
            cphi: 2.150000e-04,
            fx: -393.1,
            fs: -2901.0,
            mn: -23.33,
        },
    },
    Reference {
        y_mm: 4.0,
        roll: -2.557000e-04,
        yaw: 0.0096,
        vpitch: -4.344093,
        left: Wheel {
            ycp_w: -11.8167,
            ycp_r: 2.8681,
            deltcp: 0.0096,
            zcp_w: -0.249,
            fn_: 10030.0,
            cksi: -1.399000e-03,
            ceta: 9.594000e-03,
            cphi: -2.138000e-05,
            fx: 436.6,
            fs: -2977.0,
            mn: 54.89,
        },
        right: Wheel {
            ycp_w: -15.3505,
            ycp_r: -21.7944,
            deltcp: -0.1078,
            zcp_w: 0.9806,
            fn_: 9745.0,
            cksi: 1.276000e-03,
            ceta: 9.662000e-03,
            cphi: 2.330000e-04,
            fx: -379.6,
            fs: -2898.0,
            mn: -24.06,
        },
    },
    Reference {
        y_mm: 4.5,
        roll: -2.977000e-04,
        yaw: 0.0108,
        vpitch: -4.3433715,
        left: Wheel {
            ycp_w: -12.4799,
            ycp_r: 2.7335,
            deltcp: 0.0091,
            zcp_w: -0.2554,
            fn_: 10030.0,
            cksi: -1.591000e-03,
            ceta: 1.079000e-02,
            cphi: -2.049000e-05,
            fx: 440.6,
            fs: -2976.0,
            mn: 47.29,
        },
        right: Wheel {
            ycp_w: -16.7104,
            ycp_r: -22.6421,
            deltcp: -0.1185,
            zcp_w: 1.1346,
            fn_: 9726.0,
            cksi: 1.430000e-03,
            ceta: 1.088000e-02,
            cphi: 2.559000e-04,
            fx: -376.8,
            fs: -2893.0,
            mn: -25.19,
        },
    },
    Reference {
        y_mm: 5.0,
        roll: -3.554000e-04,
        yaw: 0.012,
        vpitch: -4.3353637,
        left: Wheel {
            ycp_w: -13.1136,
            ycp_r: 2.6368,
            deltcp: 0.0088,
            zcp_w: -0.2614,
            fn_: 10030.0,
            cksi: -3.462000e-03,
            ceta: 1.198000e-02,
            cphi: -1.990000e-05,
            fx: 837.8,
            fs: -2889.0,
            mn: 48.32,
        },
        right: Wheel {
            ycp_w: -28.0471,
            ycp_r: -33.447,
            deltcp: -0.2905,
            zcp_w: 3.2592,
            fn_: 9619.0,
            cksi: 4.174000e-03,
            ceta: 1.255000e-02,
            cphi: 6.188000e-04,
            fx: -763.3,
            fs: -2738.0,
            mn: -826.6,
        },
    },
    Reference {
        y_mm: 5.5,
        roll: -4.777000e-04,
        yaw: 0.0132,
        vpitch: -4.3318864,
        left: Wheel {
            ycp_w: -13.7601,
            ycp_r: 2.558,
            deltcp: 0.0085,
            zcp_w: -0.2673,
            fn_: 10020.0,
            cksi: -4.292000e-03,
            ceta: 1.317000e-02,
            cphi: -1.959000e-05,
            fx: 934.1,
            fs: -2859.0,
            mn: 45.16,
        },
        right: Wheel {
            ycp_w: -29.5701,
            ycp_r: -34.4157,
            deltcp: -0.3363,
            zcp_w: 3.7315,
            fn_: 9629.0,
            cksi: 4.379000e-03,
            ceta: 1.401000e-02,
            cphi: 7.122000e-04,
            fx: -850.2,
            fs: -2759.0,
            mn: -17.75,
        },
    },
    Reference {
        y_mm: 6.0,
        roll: -6.272000e-04,
        yaw: 0.0144,
        vpitch: -4.3293718,
        left: Wheel {
            ycp_w: -14.3878,
            ycp_r: 2.5116,
            deltcp: 0.0084,
            zcp_w: -0.273,
            fn_: 10020.0,
            cksi: -4.901000e-03,
            ceta: 1.437000e-02,
            cphi: -1.957000e-05,
            fx: 973.1,
            fs: -2845.0,
            mn: 41.57,
        },
        right: Wheel {
            ycp_w: -31.1222,
            ycp_r: -35.3954,
            deltcp: -0.4176,
            zcp_w: 4.3352,
            fn_: 9709.0,
            cksi: 5.077000e-03,
            ceta: 1.580000e-02,
            cphi: 8.744000e-04,
            fx: -880.0,
            fs: -2775.0,
            mn: 59.67,
        },
    },
    Reference {
        y_mm: 6.5,
        roll: -4.376000e-03,
        yaw: 0.0156,
        vpitch: -4.2748834,
        left: Wheel {
            ycp_w: -17.2354,
            ycp_r: 1.9083,
            deltcp: 0.0064,
            zcp_w: -0.3006,
            fn_: 10010.0,
            cksi: -1.764000e-02,
            ceta: 1.546000e-02,
            cphi: -2.319000e-05,
            fx: 2260.0,
            fs: -1979.0,
            mn: 51.61,
        },
        right: Wheel {
            ycp_w: -40.2622,
            ycp_r: -42.0394,
            deltcp: -1.1591,
            zcp_w: 16.5234,
            fn_: 15440.0,
            cksi: 1.828000e-02,
            ceta: 3.905000e-02,
            cphi: 1.937000e-03,
            fx: -1987.0,
            fs: -4170.0,
            mn: -728.2,
        },
    },
    Reference {
        y_mm: 7.0,
        roll: -6.393000e-03,
        yaw: 0.0168,
        vpitch: -4.2635629,
        left: Wheel {
            ycp_w: -18.6704,
            ycp_r: 1.9234,
            deltcp: 0.0064,
            zcp_w: -0.3175,
            fn_: 10010.0,
            cksi: -2.035000e-02,
            ceta: 1.663000e-02,
            cphi: -2.761000e-05,
            fx: 2327.0,
            fs: -1900.0,
            mn: 45.23,
        },
        right: Wheel {
            ycp_w: -41.1389,
            ycp_r: -41.4881,
            deltcp: -1.0634,
            zcp_w: 18.3758,
            fn_: 14030.0,
            cksi: 1.949000e-02,
            ceta: 3.457000e-02,
            cphi: 1.838000e-03,
            fx: -2079.0,
            fs: -3644.0,
            mn: -654.2,
        },
    },
    Reference {
        y_mm: 7.5,
        roll: -7.642000e-03,
        yaw: 0.018,
        vpitch: -4.2575747,
        left: Wheel {
            ycp_w: -19.6018,
            ycp_r: 2.0885,
            deltcp: 0.007,
            zcp_w: -0.3303,
            fn_: 10010.0,
            cksi: -2.180000e-02,
            ceta: 1.781000e-02,
            cphi: -3.146000e-05,
            fx: 2327.0,
            fs: -1899.0,
            mn: 43.85,
        },
        right: Wheel {
            ycp_w: -41.8043,
            ycp_r: -41.0693,
            deltcp: -1.0006,
            zcp_w: 19.5093,
            fn_: 13260.0,
            cksi: 2.044000e-02,
            ceta: 3.333000e-02,
            cphi: 1.765000e-03,
            fx: -2086.0,
            fs: -3375.0,
            mn: -578.2,
        },
    },
    Reference {
        y_mm: 8.0,
        roll: -8.606000e-03,
        yaw: 0.0192,
        vpitch: -4.2534857,
        left: Wheel {
            ycp_w: -20.3458,
            ycp_r: 2.3103,
            deltcp: 0.0077,
            zcp_w: -0.3418,
            fn_: 10020.0,
            cksi: -2.281000e-02,
            ceta: 1.899000e-02,
            cphi: -3.511000e-05,
            fx: 2310.0,
            fs: -1921.0,
            mn: 40.02,
        },
        right: Wheel {
            ycp_w: -42.3894,
            ycp_r: -40.701,
            deltcp: -0.9501,
            zcp_w: 20.3791,
            fn_: 12720.0,
            cksi: 2.127000e-02,
            ceta: 3.300000e-02,
            cphi: 1.701000e-03,
            fx: -2070.0,
            fs: -3195.0,
            mn: -516.1,
        },
    },
    Reference {
        y_mm: 8.5,
        roll: -9.408000e-03,
        yaw: 0.0204,
        vpitch: -4.2503245,
        left: Wheel {
            ycp_w: -20.9835,
            ycp_r: 2.5645,
            deltcp: 0.0086,
            zcp_w: -0.3527,
            fn_: 10020.0,
            cksi: -2.360000e-02,
            ceta: 2.017000e-02,
            cphi: -3.864000e-05,
            fx: 2285.0,
            fs: -1951.0,
            mn: 36.85,
        },
        right: Wheel {
            ycp_w: -42.9279,
            ycp_r: -40.3617,
            deltcp: -0.9065,
            zcp_w: 21.0991,
            fn_: 12310.0,
            cksi: 2.200000e-02,
            ceta: 3.309000e-02,
            cphi: 1.642000e-03,
            fx: -2044.0,
            fs: -3064.0,
            mn: -459.9,
        },
    },
    Reference {
        y_mm: 9.0,
        roll: -1.010113e-02,
        yaw: 0.0216,
        vpitch: -4.2477561,
        left: Wheel {
            ycp_w: -21.5501,
            ycp_r: 2.8403,
            deltcp: 0.0095,
            zcp_w: -0.3634,
            fn_: 10020.0,
            cksi: -2.425000e-02,
            ceta: 2.135000e-02,
            cphi: -4.210000e-05,
            fx: 2257.0,
            fs: -1985.0,
            mn: 34.39,
        },
        right: Wheel {
            ycp_w: -43.4346,
            ycp_r: -40.0422,
            deltcp: -0.8676,
            zcp_w: 21.7187,
            fn_: 11970.0,
            cksi: 2.266000e-02,
            ceta: 3.341000e-02,
            cphi: 1.588000e-03,
            fx: -2014.0,
            fs: -2963.0,
            mn: -411.9,
        },
    },
    Reference {
        y_mm: 9.5,
        roll: -1.071386e-02,
        yaw: 0.0228,
        vpitch: -4.2455665,
        left: Wheel {
            ycp_w: -22.065,
            ycp_r: 3.1318,
            deltcp: 0.0105,
            zcp_w: -0.3739,
            fn_: 10020.0,
            cksi: -2.482000e-02,
            ceta: 2.253000e-02,
            cphi: -4.549000e-05,
            fx: 2227.0,
            fs: -2020.0,
            mn: 33.43,
        },
        right: Wheel {
            ycp_w: -43.9174,
            ycp_r: -39.7376,
            deltcp: -0.8321,
            zcp_w: 22.2644,
            fn_: 11680.0,
            cksi: 2.325000e-02,
            ceta: 3.388000e-02,
            cphi: 1.536000e-03,
            fx: -1981.0,
            fs: -2884.0,
            mn: -368.0,
        },
    },
    Reference {
        y_mm: 10.0,
        roll: -1.126431e-02,
        yaw: 0.024,
        vpitch: -4.2436375,
        left: Wheel {
            ycp_w: -22.5401,
            ycp_r: 3.4351,
            deltcp: 0.0115,
            zcp_w: -0.3844,
            fn_: 10020.0,
            cksi: -2.532000e-02,
            ceta: 2.371000e-02,
            cphi: -4.883000e-05,
            fx: 2196.0,
            fs: -2054.0,
            mn: 32.16,
        },
        right: Wheel {
            ycp_w: -44.3815,
            ycp_r: -39.4446,
            deltcp: -0.7992,
            zcp_w: 22.753,
            fn_: 11440.0,
            cksi: 2.378000e-02,
            ceta: 3.445000e-02,
            cphi: 1.486000e-03,
            fx: -1947.0,
            fs: -2820.0,
            mn: -333.7,
        },
    },
];

/// The benchmark's case in `railfem contact` terms.
pub fn benchmark_case() -> ContactCase {
    ContactCase {
        profiles: ProfileSet::ManchesterBenchmark,
        gauge: 1.435,
        back_to_back: 1.360,
        radius: 0.46,
        yaw: 0.0,
        yaw_per_shift: 2.4,
        pitch_rate: None,
        balance: Balance::Creep(CreepLaw::Fastsim),
        load: 10e3,
        speed: 2.0,
        mu: 0.3,
        young: 2.0 * 82e9 * 1.28,
        poisson: 0.28,
    }
}

/// One quantity compared: ours and CONTACT's, both in our frame (mm, mrad or N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    /// Ours.
    pub ours: f64,
    /// CONTACT's.
    pub contact: f64,
}

/// The comparison at one shift (mm, mrad, N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    /// Shift (mm).
    pub y_mm: f64,
    /// Roll (mrad).
    pub roll: Pair,
    /// Δr (mm).
    pub delta_r: Pair,
    /// Left (flange-side) and right wheel: `wheel_y`, `rail_y` (mm), `δ` (mrad) of our
    /// first patch, N (N) summed over our patches.
    pub wheels: [[Pair; 4]; 2],
    /// Left and right wheel: creepages `ξx`, `ξy` (−), spin `φ` (1/m), creep forces `Fx`,
    /// `Fy` on the wheel (N; ours: FASTSIM, the law of the balance; summed over our
    /// patches).
    pub creep: [[Pair; 5]; 2],
    /// Our number of patches on the left and right wheel (CONTACT: one each).
    pub patches: [usize; 2],
}

fn mapped(ours: &ShiftResult, r: &Reference) -> Comparison {
    let p = |a: f64, b: f64| Pair {
        ours: a,
        contact: b,
    };
    // Where we find two patches and CONTACT one (it merges patches less than 4 mm apart,
    // D_COMB, and reports one reference point), the normal and creep forces are the sums
    // over our patches, the position and creepages those of our first patch.
    let sum = |s: &super::Patch, t: Option<&super::Patch>, f: &dyn Fn(&super::Patch) -> f64| {
        f(s) + t.map_or(0.0, f)
    };
    let side = |s: &super::Patch, t: Option<&super::Patch>, w: &Wheel, m: f64| {
        [
            p(s.geometry.wheel_y * 1e3, m * w.ycp_w),
            p(s.geometry.rail_y * 1e3, m * w.ycp_r),
            p(s.geometry.contact_angle * 1e3, -m * w.deltcp * 1e3),
            p(sum(s, t, &|q| q.normal), w.fn_),
        ]
    };
    // CONTACT's creepages are those of the rail relative to the wheel and its forces act on
    // the rail: all five change sign (module doc).
    let creep = |s: &super::Patch, t: Option<&super::Patch>, w: &Wheel| {
        let f = |q: &super::Patch| q.forces.map_or((f64::NAN, f64::NAN), |f| f.fastsim);
        [
            p(s.creepage[0], -w.cksi),
            p(s.creepage[1], -w.ceta),
            p(s.creepage[2], -w.cphi * 1e3),
            p(sum(s, t, &|q| f(q).0), -w.fx),
            p(sum(s, t, &|q| f(q).1), -w.fs),
        ]
    };
    let [l2, r2] = [ours.second[0].as_ref(), ours.second[1].as_ref()];
    Comparison {
        y_mm: r.y_mm,
        creep: [
            creep(&ours.left, l2, &r.right),
            creep(&ours.right, r2, &r.left),
        ],
        roll: p(ours.contact.roll * 1e3, -r.roll * 1e3),
        delta_r: p(ours.contact.delta_r() * 1e3, r.right.zcp_w - r.left.zcp_w),
        wheels: [
            side(&ours.left, l2, &r.right, 1.0),
            side(&ours.right, r2, &r.left, -1.0),
        ],
        patches: [1 + usize::from(l2.is_some()), 1 + usize::from(r2.is_some())],
    }
}

/// Our results at CONTACT's shifts and pitch rates, side by side with its numbers.
pub fn compare() -> Result<Vec<Comparison>, FemError> {
    let mut case = benchmark_case();
    let (geom, _) = geometry(&case)?;
    CONTACT_A22
        .iter()
        .map(|r| {
            case.pitch_rate = Some(-r.vpitch);
            Ok(mapped(&evaluate(&case, &geom, r.y_mm * 1e-3)?, r))
        })
        .collect()
}

/// The creepages and creep forces as a markdown table (`ours / CONTACT`).
pub fn creep_markdown(rows: &[Comparison]) -> String {
    let mut s = String::from(
        "| y [mm] | L ξx [‰] | L ξy [‰] | L φ [1/m] | L Fx [kN] | L Fy [kN] | \
         R ξx [‰] | R ξy [‰] | R φ [1/m] | R Fx [kN] | R Fy [kN] |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let f = |p: Pair, k: f64, d: usize| format!("{:.d$} / {:.d$}", p.ours * k, p.contact * k);
    for c in rows {
        let _ = write!(s, "| {} |", c.y_mm);
        for w in &c.creep {
            let _ = write!(
                s,
                " {} | {} | {} | {} | {} |",
                f(w[0], 1e3, 3),
                f(w[1], 1e3, 3),
                f(w[2], 1.0, 4),
                f(w[3], 1e-3, 3),
                f(w[4], 1e-3, 3)
            );
        }
        s.push('\n');
    }
    s
}

/// The comparison as a markdown table (`ours / CONTACT`).
pub fn markdown(rows: &[Comparison]) -> String {
    let mut s = String::from(
        "| y [mm] | roll [mrad] | Δr [mm] | L wheel_y [mm] | L rail_y [mm] | L δ [mrad] | \
         L N [kN] | R wheel_y [mm] | R rail_y [mm] | R δ [mrad] | R N [kN] |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let f = |p: Pair, k: f64| format!("{:.2} / {:.2}", p.ours * k, p.contact * k);
    for c in rows {
        let _ = write!(
            s,
            "| {} | {} | {} |",
            c.y_mm,
            f(c.roll, 1.0),
            f(c.delta_r, 1.0)
        );
        for w in &c.wheels {
            let _ = write!(
                s,
                " {} | {} | {} | {} |",
                f(w[0], 1.0),
                f(w[1], 1.0),
                f(w[2], 1.0),
                f(w[3], 1e-3)
            );
        }
        s.push('\n');
    }
    s
}
