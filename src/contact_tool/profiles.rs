//! The profile pairs of `railfem contact`: the built-in S1002 on 60E1, the Manchester
//! contact benchmark's S1002 and UIC60 (the SIMPACK point lists in `examples/profiles/`,
//! embedded at build time), or CSV files; and where each pair sits on the track, from the
//! gauge and the back-to-back distance.
//!
//! # Placement
//!
//! The **gauge point** of a rail is, by EN 13848-1 (its definition of track gauge), the point of its
//! gauge face [`GAUGE_DEPTH`] = 14 mm below the top of the rail; walking from the rail's
//! highest node towards the gauge side, it is the first crossing of that depth
//! (linear between nodes). With `y_g < 0` its profile coordinate, the rails' profile
//! origins stand at `±(gauge/2 − y_g)` from the track centre line. The wheels' tape-circle
//! points stand at `±(back_to_back/2 + d_fb)` from the wheelset centre, `d_fb` the distance
//! of the flange back from the tape circle (70 mm for S1002, EN 13715; for a CSV wheel the
//! distance to its gauge-side end).
//!
//! # The benchmark's files
//!
//! SIMPACK's `.prw`/`.prr` lists `y z` in mm between `point.begin` and `point.end`, `!`
//! starting a comment, `z` pointing **down**. The benchmark rail is given already inclined
//! (1:40) with its origin at the top, field side at `+y`: in the profile coordinates of
//! `railfem_elements::rail::contact::profiles` it is `(y, −z)/1000`. The wheel is given with the
//! flange at `+y`: it is `(−y, −z)/1000`. The search needs the rail as a function `z(y)`, so
//! the rail keeps its head down to [`RAIL_DEPTH`] below the top (the flange contact of the
//! benchmark lies above 11 mm), thinned to nodes at least [`RAIL_SPACING`] apart in `y`
//! (the file repeats nodes on the nearly vertical flanks within micrometres, which a cubic
//! `z(y)` cannot follow).

use crate::elements::rail::contact::profiles::{Inclination, RailProfile, WheelProfile};
use crate::framework::FemError;
use nalgebra::Vector2;
use std::path::PathBuf;

/// Depth of the gauge point below the top of the rail (m), EN 13848-1.
pub const GAUGE_DEPTH: f64 = 0.014;
/// Depth below the top down to which the benchmark rail is kept (m).
pub const RAIL_DEPTH: f64 = 0.013;
/// Smallest lateral spacing of the benchmark rail's nodes (m).
pub const RAIL_SPACING: f64 = 1e-4;
/// Flange back to tape circle of S1002 (m), EN 13715.
pub const S1002_FLANGE_BACK: f64 = 0.070;

/// The benchmark's wheel file (Apache-2.0, source in its header).
const MBENCH_WHEEL: &str = include_str!("../../examples/profiles/MBench_S1002_v3.prw");
/// The benchmark's rail file (Apache-2.0, source in its header).
const MBENCH_RAIL: &str = include_str!("../../examples/profiles/MBench_UIC60_v3.prr");

/// The built-in profile pairs `railfem contact --profiles` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
pub enum BuiltInProfiles {
    /// `s1002-60e1`: [`ProfileSet::S1002On60E1`].
    #[serde(rename = "s1002-60e1")]
    S1002On60E1,
    /// `mbench`: [`ProfileSet::ManchesterBenchmark`].
    #[serde(rename = "mbench")]
    ManchesterBenchmark,
}

/// Which profiles a wheelset runs on.
#[derive(Debug, Clone, PartialEq)]
pub enum ProfileSet {
    /// The built-in S1002 (201 points) on the built-in 60E1 at an inclination.
    S1002On60E1(Inclination),
    /// The Manchester contact benchmark's S1002 and UIC60 (rail inclined 1:40 in the file).
    ManchesterBenchmark,
    /// CSV files (format of `railfem_elements::rail::contact::profiles::read_points_csv`).
    Files {
        /// Wheel profile.
        wheel: PathBuf,
        /// Rail profile (upright).
        rail: PathBuf,
        /// Inclination of the rail.
        inclination: Inclination,
    },
}

/// A profile pair with the placement data of the module doc.
#[derive(Debug, Clone)]
pub struct PlacedProfiles {
    /// Wheel (left, as stored).
    pub wheel: WheelProfile,
    /// Rail (left, inclined).
    pub rail: RailProfile,
    /// Gauge point's lateral profile coordinate on the rail (m, negative).
    pub gauge_y: f64,
    /// Flange back to tape circle (m).
    pub flange_back: f64,
}

/// The gauge point (module doc) of rail nodes `[y, z]` sorted by `y`, if the gauge face
/// reaches [`GAUGE_DEPTH`].
pub fn gauge_point(nodes: &[Vector2<f64>]) -> Option<f64> {
    let top = (0..nodes.len()).max_by(|&i, &j| nodes[i].y.total_cmp(&nodes[j].y))?;
    let z = nodes[top].y - GAUGE_DEPTH;
    (1..=top).rev().find_map(|i| {
        let (p, q) = (nodes[i - 1], nodes[i]);
        (p.y <= z && z <= q.y).then(|| p.x + (z - p.y) / (q.y - p.y) * (q.x - p.x))
    })
}

/// The `y z` pairs (mm) of a SIMPACK profile file's point list.
pub fn simpack_points(text: &str, file: &str) -> Result<Vec<Vector2<f64>>, FemError> {
    let mut inside = false;
    let mut pts = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let l = line.split('!').next().unwrap_or("").trim();
        if l == "point.begin" {
            inside = true;
        } else if l == "point.end" {
            inside = false;
        } else if inside && !l.is_empty() {
            let v: Vec<f64> = l
                .split_whitespace()
                .take(2)
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| {
                    FemError::input(
                        format!("{file}:{}", k + 1),
                        "expected two numbers `y z` in mm inside point.begin … point.end",
                    )
                })?;
            if v.len() < 2 {
                return Err(FemError::input(
                    format!("{file}:{}", k + 1),
                    "expected two numbers `y z` in mm inside point.begin … point.end",
                ));
            }
            pts.push(Vector2::new(v[0], v[1]));
        }
    }
    Ok(pts)
}

fn profile_error(file: &str, e: impl std::fmt::Display) -> FemError {
    FemError::input(file, e.to_string())
}

/// The benchmark's wheel and rail, converted and trimmed as the module doc says.
pub fn manchester() -> Result<PlacedProfiles, FemError> {
    let (wf, rf) = ("MBench_S1002_v3.prw", "MBench_UIC60_v3.prr");
    let wheel: Vec<Vector2<f64>> = simpack_points(MBENCH_WHEEL, wf)?
        .iter()
        .map(|p| Vector2::new(-p.x, -p.y) * 1e-3)
        .collect();
    let wheel = WheelProfile::from_points(&wheel).map_err(|e| profile_error(wf, e))?;
    let all: Vec<Vector2<f64>> = simpack_points(MBENCH_RAIL, rf)?
        .iter()
        .map(|p| Vector2::new(p.x, -p.y) * 1e-3)
        .collect();
    let gauge_y =
        gauge_point(&all).ok_or_else(|| profile_error(rf, "no gauge point 14 mm below the top"))?;
    let top = all.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    let mut kept: Vec<Vector2<f64>> = Vec::new();
    for p in all.iter().filter(|p| p.y >= top - RAIL_DEPTH) {
        if kept.last().is_none_or(|q| p.x - q.x >= RAIL_SPACING) {
            kept.push(*p);
        }
    }
    let rail =
        RailProfile::from_nodes(&kept, Inclination::None).map_err(|e| profile_error(rf, e))?;
    Ok(PlacedProfiles {
        wheel,
        rail,
        gauge_y,
        flange_back: S1002_FLANGE_BACK,
    })
}

impl ProfileSet {
    /// Builds the profiles and their placement data.
    pub fn load(&self) -> Result<PlacedProfiles, FemError> {
        let (wheel, rail, flange_back, origin) = match self {
            ProfileSet::ManchesterBenchmark => return manchester(),
            ProfileSet::S1002On60E1(incl) => (
                WheelProfile::s1002(crate::elements::rail::contact::profiles::DEFAULT_WHEEL_POINTS),
                RailProfile::uic60(
                    crate::elements::rail::contact::creep::conicity::RAIL_NODES,
                    *incl,
                ),
                S1002_FLANGE_BACK,
                "the built-in 60E1".to_string(),
            ),
            ProfileSet::Files {
                wheel,
                rail,
                inclination,
            } => {
                let (wn, rn) = (wheel.display().to_string(), rail.display().to_string());
                let w = WheelProfile::from_csv_file(wheel).map_err(|e| profile_error(&wn, e))?;
                let r = RailProfile::from_csv_file(rail, *inclination)
                    .map_err(|e| profile_error(&rn, e))?;
                let fb = -w.points().iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
                if fb <= 0.0 {
                    return Err(FemError::input(
                        wn,
                        "the wheel profile has no point on the flange side (y < 0); fix: put \
                         the tape circle at y = 0 and the flange at negative y",
                    ));
                }
                (w, r, fb, rn)
            }
        };
        let gauge_y = gauge_point(rail.nodes()).ok_or_else(|| {
            FemError::input(
                origin,
                "the rail's gauge face does not reach 14 mm below its top (EN 13848-1 gauge \
                 point); fix: give the head down to at least 14 mm",
            )
        })?;
        Ok(PlacedProfiles {
            wheel,
            rail,
            gauge_y,
            flange_back,
        })
    }
}
