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
//!
//! CONTACT's positions are those of the contact reference point of an elastic patch
//! (10 kN); ours are the rigid first-touch points; docs/contact-tool.md discusses the
//! differences.

use super::profiles::ProfileSet;
use super::{evaluate, geometry, ContactCase, ShiftResult};
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
}

/// CONTACT's output at one shift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    /// Wheelset shift (mm, CONTACT's sign).
    pub y_mm: f64,
    /// `ROLL_WS` (rad, CONTACT's sign).
    pub roll: f64,
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
        left: Wheel {
            ycp_w: -1.8726,
            ycp_r: 8.66,
            deltcp: 0.029,
            zcp_w: -0.0729,
            fn_: 9997.0,
        },
        right: Wheel {
            ycp_w: 1.8726,
            ycp_r: -8.66,
            deltcp: -0.029,
            zcp_w: -0.0729,
            fn_: 9997.0,
        },
    },
    Reference {
        y_mm: 0.5,
        roll: -2.304000e-05,
        left: Wheel {
            ycp_w: -4.7204,
            ycp_r: 6.3233,
            deltcp: 0.0211,
            zcp_w: -0.1451,
            fn_: 10050.0,
        },
        right: Wheel {
            ycp_w: -6.0075,
            ycp_r: -16.03,
            deltcp: -0.0568,
            zcp_w: 0.2522,
            fn_: 9870.0,
        },
    },
    Reference {
        y_mm: 1.0,
        roll: -5.049000e-05,
        left: Wheel {
            ycp_w: -6.2694,
            ycp_r: 5.2886,
            deltcp: 0.0176,
            zcp_w: -0.1754,
            fn_: 10050.0,
        },
        right: Wheel {
            ycp_w: -9.0305,
            ycp_r: -18.5418,
            deltcp: -0.0696,
            zcp_w: 0.4288,
            fn_: 9827.0,
        },
    },
    Reference {
        y_mm: 1.5,
        roll: -8.103000e-05,
        left: Wheel {
            ycp_w: -7.5089,
            ycp_r: 4.5657,
            deltcp: 0.0152,
            zcp_w: -0.196,
            fn_: 10050.0,
        },
        right: Wheel {
            ycp_w: -10.1558,
            ycp_r: -19.1554,
            deltcp: -0.0753,
            zcp_w: 0.5094,
            fn_: 9811.0,
        },
    },
    Reference {
        y_mm: 2.0,
        roll: -1.128000e-04,
        left: Wheel {
            ycp_w: -8.566,
            ycp_r: 4.027,
            deltcp: 0.0134,
            zcp_w: -0.2114,
            fn_: 10040.0,
        },
        right: Wheel {
            ycp_w: -11.1296,
            ycp_r: -19.6178,
            deltcp: -0.0806,
            zcp_w: 0.5853,
            fn_: 9799.0,
        },
    },
    Reference {
        y_mm: 2.5,
        roll: -1.457000e-04,
        left: Wheel {
            ycp_w: -9.4982,
            ycp_r: 3.6148,
            deltcp: 0.0121,
            zcp_w: -0.2235,
            fn_: 10040.0,
        },
        right: Wheel {
            ycp_w: -12.0933,
            ycp_r: -20.0706,
            deltcp: -0.0862,
            zcp_w: 0.6657,
            fn_: 9787.0,
        },
    },
    Reference {
        y_mm: 3.0,
        roll: -1.803000e-04,
        left: Wheel {
            ycp_w: -10.3382,
            ycp_r: 3.2967,
            deltcp: 0.011,
            zcp_w: -0.2334,
            fn_: 10030.0,
        },
        right: Wheel {
            ycp_w: -13.0963,
            ycp_r: -20.5627,
            deltcp: -0.0923,
            zcp_w: 0.7553,
            fn_: 9774.0,
        },
    },
    Reference {
        y_mm: 3.5,
        roll: -2.168000e-04,
        left: Wheel {
            ycp_w: -11.1063,
            ycp_r: 3.0525,
            deltcp: 0.0102,
            zcp_w: -0.2418,
            fn_: 10030.0,
        },
        right: Wheel {
            ycp_w: -14.17,
            ycp_r: -21.1254,
            deltcp: -0.0994,
            zcp_w: 0.8583,
            fn_: 9760.0,
        },
    },
    Reference {
        y_mm: 4.0,
        roll: -2.557000e-04,
        left: Wheel {
            ycp_w: -11.8167,
            ycp_r: 2.8681,
            deltcp: 0.0096,
            zcp_w: -0.249,
            fn_: 10030.0,
        },
        right: Wheel {
            ycp_w: -15.3505,
            ycp_r: -21.7944,
            deltcp: -0.1078,
            zcp_w: 0.9806,
            fn_: 9745.0,
        },
    },
    Reference {
        y_mm: 4.5,
        roll: -2.977000e-04,
        left: Wheel {
            ycp_w: -12.4799,
            ycp_r: 2.7335,
            deltcp: 0.0091,
            zcp_w: -0.2554,
            fn_: 10030.0,
        },
        right: Wheel {
            ycp_w: -16.7104,
            ycp_r: -22.6421,
            deltcp: -0.1185,
            zcp_w: 1.1346,
            fn_: 9726.0,
        },
    },
    Reference {
        y_mm: 5.0,
        roll: -3.554000e-04,
        left: Wheel {
            ycp_w: -13.1136,
            ycp_r: 2.6368,
            deltcp: 0.0088,
            zcp_w: -0.2614,
            fn_: 10030.0,
        },
        right: Wheel {
            ycp_w: -28.0471,
            ycp_r: -33.447,
            deltcp: -0.2905,
            zcp_w: 3.2592,
            fn_: 9619.0,
        },
    },
    Reference {
        y_mm: 5.5,
        roll: -4.777000e-04,
        left: Wheel {
            ycp_w: -13.7601,
            ycp_r: 2.558,
            deltcp: 0.0085,
            zcp_w: -0.2673,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -29.5701,
            ycp_r: -34.4157,
            deltcp: -0.3363,
            zcp_w: 3.7315,
            fn_: 9629.0,
        },
    },
    Reference {
        y_mm: 6.0,
        roll: -6.272000e-04,
        left: Wheel {
            ycp_w: -14.3878,
            ycp_r: 2.5116,
            deltcp: 0.0084,
            zcp_w: -0.273,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -31.1222,
            ycp_r: -35.3954,
            deltcp: -0.4176,
            zcp_w: 4.3352,
            fn_: 9709.0,
        },
    },
    Reference {
        y_mm: 6.5,
        roll: -4.376000e-03,
        left: Wheel {
            ycp_w: -17.2354,
            ycp_r: 1.9083,
            deltcp: 0.0064,
            zcp_w: -0.3006,
            fn_: 10010.0,
        },
        right: Wheel {
            ycp_w: -40.2622,
            ycp_r: -42.0394,
            deltcp: -1.1591,
            zcp_w: 16.5234,
            fn_: 15440.0,
        },
    },
    Reference {
        y_mm: 7.0,
        roll: -6.393000e-03,
        left: Wheel {
            ycp_w: -18.6704,
            ycp_r: 1.9234,
            deltcp: 0.0064,
            zcp_w: -0.3175,
            fn_: 10010.0,
        },
        right: Wheel {
            ycp_w: -41.1389,
            ycp_r: -41.4881,
            deltcp: -1.0634,
            zcp_w: 18.3758,
            fn_: 14030.0,
        },
    },
    Reference {
        y_mm: 7.5,
        roll: -7.642000e-03,
        left: Wheel {
            ycp_w: -19.6018,
            ycp_r: 2.0885,
            deltcp: 0.007,
            zcp_w: -0.3303,
            fn_: 10010.0,
        },
        right: Wheel {
            ycp_w: -41.8043,
            ycp_r: -41.0693,
            deltcp: -1.0006,
            zcp_w: 19.5093,
            fn_: 13260.0,
        },
    },
    Reference {
        y_mm: 8.0,
        roll: -8.606000e-03,
        left: Wheel {
            ycp_w: -20.3458,
            ycp_r: 2.3103,
            deltcp: 0.0077,
            zcp_w: -0.3418,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -42.3894,
            ycp_r: -40.701,
            deltcp: -0.9501,
            zcp_w: 20.3791,
            fn_: 12720.0,
        },
    },
    Reference {
        y_mm: 8.5,
        roll: -9.408000e-03,
        left: Wheel {
            ycp_w: -20.9835,
            ycp_r: 2.5645,
            deltcp: 0.0086,
            zcp_w: -0.3527,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -42.9279,
            ycp_r: -40.3617,
            deltcp: -0.9065,
            zcp_w: 21.0991,
            fn_: 12310.0,
        },
    },
    Reference {
        y_mm: 9.0,
        roll: -1.010000e-02,
        left: Wheel {
            ycp_w: -21.5501,
            ycp_r: 2.8403,
            deltcp: 0.0095,
            zcp_w: -0.3634,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -43.4346,
            ycp_r: -40.0422,
            deltcp: -0.8676,
            zcp_w: 21.7187,
            fn_: 11970.0,
        },
    },
    Reference {
        y_mm: 9.5,
        roll: -1.071000e-02,
        left: Wheel {
            ycp_w: -22.065,
            ycp_r: 3.1318,
            deltcp: 0.0105,
            zcp_w: -0.3739,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -43.9174,
            ycp_r: -39.7376,
            deltcp: -0.8321,
            zcp_w: 22.2644,
            fn_: 11680.0,
        },
    },
    Reference {
        y_mm: 10.0,
        roll: -1.126000e-02,
        left: Wheel {
            ycp_w: -22.5401,
            ycp_r: 3.4351,
            deltcp: 0.0115,
            zcp_w: -0.3844,
            fn_: 10020.0,
        },
        right: Wheel {
            ycp_w: -44.3815,
            ycp_r: -39.4446,
            deltcp: -0.7992,
            zcp_w: 22.753,
            fn_: 11440.0,
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
    /// Left (flange-side) and right wheel: `wheel_y`, `rail_y` (mm), `δ` (mrad), N (N).
    pub wheels: [[Pair; 4]; 2],
}

fn mapped(ours: &ShiftResult, r: &Reference) -> Comparison {
    let p = |a: f64, b: f64| Pair {
        ours: a,
        contact: b,
    };
    let side = |s: &super::Patch, w: &Wheel, m: f64| {
        [
            p(s.geometry.wheel_y * 1e3, m * w.ycp_w),
            p(s.geometry.rail_y * 1e3, m * w.ycp_r),
            p(s.geometry.contact_angle * 1e3, -m * w.deltcp * 1e3),
            p(s.normal, w.fn_),
        ]
    };
    Comparison {
        y_mm: r.y_mm,
        roll: p(ours.contact.roll * 1e3, -r.roll * 1e3),
        delta_r: p(ours.contact.delta_r() * 1e3, r.right.zcp_w - r.left.zcp_w),
        wheels: [
            side(&ours.left, &r.right, 1.0),
            side(&ours.right, &r.left, -1.0),
        ],
    }
}

/// Our results at CONTACT's shifts, side by side with its numbers.
pub fn compare() -> Result<Vec<Comparison>, FemError> {
    let case = benchmark_case();
    let (geom, _) = geometry(&case)?;
    CONTACT_A22
        .iter()
        .map(|r| Ok(mapped(&evaluate(&case, &geom, r.y_mm * 1e-3)?, r)))
        .collect()
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
