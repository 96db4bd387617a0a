//! Rail lines for meshing and lookup, and the track report (CSV table and SVG diagram).
//!
//! What lives here: the positions of the left and right rail lines of a [`Track`] at ±G/2
//! along wheel axis 1 ([`Track::rail_position`]), the mesh stations of the rail beams
//! ([`Track::rail_stations`], segment ends included so that joints are nodes), the
//! station → (element, ξ) search [`RailLookup`], and the outputs [`Track::write_csv`],
//! [`Track::figure`] and [`write_track_report`].
//!
//! The rail lines are the gauge lines at ±G/2 (G = 1.435 m by default) about the centre
//! line; where the wheels actually touch (about 1.5 m apart) is a matter of the profiles.

use crate::rail::geometry::alignment::AlignmentError;
use crate::rail::geometry::cant::Track;
use nalgebra::Vector3;
use railfem_framework::moving::Path as _;
use railfem_framework::plot::{Corner, Figure, Panel, Series, Style};
use std::io::{self, Write as _};
use std::path::Path;

/// Which rail, seen in the direction of travel (`"left"` or `"right"` in a model file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RailSide {
    /// The left rail (at +G/2 along wheel axis 1).
    Left,
    /// The right rail (at −G/2 along wheel axis 1).
    Right,
}

impl RailSide {
    /// +1 for left, −1 for right: the sign of the offset along axis 1.
    pub fn sign(self) -> f64 {
        match self {
            RailSide::Left => 1.0,
            RailSide::Right => -1.0,
        }
    }

    /// The index of this rail in a track model's `rails` (left 0, right 1).
    pub fn index(self) -> usize {
        match self {
            RailSide::Left => 0,
            RailSide::Right => 1,
        }
    }
}

impl Track {
    /// Global position (m) of the `side` rail line at `station`: centre line ± G/2 along
    /// wheel axis 1 (so the outer rail is (G/2)·sin θ above Z = 0 and the inner one below).
    pub fn rail_position(&self, station: f64, side: RailSide) -> Vector3<f64> {
        let p = self.at(station);
        p.position + p.frame.column(0) * (side.sign() * 0.5 * self.gauge)
    }

    /// Positions of the `side` rail line at each of `stations` (m).
    pub fn rail_line(&self, side: RailSide, stations: &[f64]) -> Vec<Vector3<f64>> {
        stations
            .iter()
            .map(|&s| self.rail_position(s, side))
            .collect()
    }

    /// Node stations (m) of a rail mesh with elements no longer than `element_length` m:
    /// each segment is divided into equal elements and every segment end is a node, so the
    /// joints of the alignment are mesh nodes. Starts at 0, ends at L, strictly increasing.
    ///
    /// # Panics
    /// If `element_length` is not a finite number > 0 (see [`Track::try_rail_stations`]).
    pub fn rail_stations(&self, element_length: f64) -> Vec<f64> {
        self.try_rail_stations(element_length)
            .expect("rail_stations: element length must be > 0 m")
    }

    /// [`Track::rail_stations`] returning an error for a bad `element_length`.
    pub fn try_rail_stations(&self, element_length: f64) -> Result<Vec<f64>, AlignmentError> {
        if !element_length.is_finite() || element_length <= 0.0 {
            return Err(AlignmentError::ElementLength(element_length));
        }
        let joints = self.alignment.joints();
        railfem_framework::limits::check_memory(
            &format!(
                "element length {} m over {} m of track",
                railfem_framework::limits::fmt_num(element_length),
                railfem_framework::limits::fmt_num(self.alignment.length())
            ),
            self.alignment.length() / element_length + joints.len() as f64,
            "rail stations",
            std::mem::size_of::<f64>() as f64,
            "give a larger element length",
        )
        .map_err(AlignmentError::TooLarge)?;
        let mut out = vec![joints[0]];
        for w in joints.windows(2) {
            let len = w[1] - w[0];
            // A tolerance keeps 600.0000000001 / 0.6 from adding a sliver element.
            let n = ((len / element_length) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
            out.extend((1..n).map(|i| w[0] + len * i as f64 / n as f64));
            out.push(w[1]);
        }
        Ok(out)
    }

    /// Writes the track geometry sampled every `step` m (and at L) as CSV with the columns
    /// `station [m],x [m],y [m],z [m],heading [rad],curvature [1/m],radius [m],cant [rad],e1x [-],e1y [-],e1z [-],e2x [-],e2y [-],e2z [-],e3x [-],e3y [-],e3z [-]`:
    /// centre-line position (m), heading (rad), signed curvature (1/m), radius 1/|κ| (m,
    /// `inf` on straights), cant magnitude θ (rad) and the wheel frame axes (unit vectors).
    pub fn write_csv(&self, path: impl AsRef<Path>, step: f64) -> io::Result<()> {
        let mut w = io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(
            w,
            "station [m],x [m],y [m],z [m],heading [rad],curvature [1/m],radius [m],cant [rad],e1x [-],e1y [-],e1z [-],e2x [-],e2y [-],e2z [-],e3x [-],e3y [-],e3z [-]"
        )?;
        for s in self.samples(step) {
            let p = self.at(s);
            let heading = self.alignment.at(s).heading;
            let f = p.frame;
            write!(
                w,
                "{},{},{},{},{},{},{},{}",
                s,
                p.position.x,
                p.position.y,
                p.position.z,
                heading,
                p.curvature,
                1.0 / p.curvature.abs(),
                p.cant
            )?;
            for c in 0..3 {
                for r in 0..3 {
                    write!(w, ",{}", f[(r, c)] + 0.0)?; // + 0.0 turns −0 into 0
                }
            }
            writeln!(w)?;
        }
        w.flush()
    }

    /// Stations from 0 to L every `step` m, with L and the segment joints included.
    fn samples(&self, step: f64) -> Vec<f64> {
        let step = if step.is_finite() && step > 0.0 {
            step
        } else {
            10.0
        };
        let l = self.alignment.length();
        let mut v: Vec<f64> = (0..)
            .map(|i| i as f64 * step)
            .take_while(|&s| s < l)
            .collect();
        v.extend(self.alignment.joints());
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// Plan and cant diagram: the plan (Y against X, with the segment joints marked), the
    /// signed curvature (1/km) and the cant θ (mrad) against station, sampled every `step` m.
    pub fn figure(&self, step: f64) -> Figure {
        let stations = self.samples(step);
        let pts: Vec<_> = stations.iter().map(|&s| self.at(s)).collect();
        let joints = self.alignment.joints();
        let jp: Vec<_> = joints.iter().map(|&s| self.at(s)).collect();
        let col = |f: &dyn Fn(&railfem_framework::moving::PathPoint) -> f64,
                   v: &[railfem_framework::moving::PathPoint]| {
            v.iter().map(f).collect::<Vec<f64>>()
        };
        let mut plan = Panel::new(
            "Plan of the track centre line (axes not to the same scale)",
            "X (m)",
            "Y (m)",
        )
        .with(Series::new(
            "centre line",
            col(&|p| p.position.x, &pts),
            col(&|p| p.position.y, &pts),
            Style::Line,
            "#1f77b4",
        ))
        .with(Series::new(
            "segment joints",
            col(&|p| p.position.x, &jp),
            col(&|p| p.position.y, &jp),
            Style::Markers,
            "#d62728",
        ));
        plan.legend = Corner::TopLeft;
        let mut curv = Panel::new(
            "Signed curvature (positive = left-hand)",
            "station s (m)",
            "curvature κ (1/km)",
        )
        .with(Series::new(
            "κ",
            stations.clone(),
            col(&|p| 1e3 * p.curvature, &pts),
            Style::Line,
            "#2ca02c",
        ))
        .with(Series::new(
            "segment joints",
            joints.clone(),
            col(&|p| 1e3 * p.curvature, &jp),
            Style::Markers,
            "#d62728",
        ));
        // Keep the legend off the curve: a right-hand layout has its plateau at the bottom.
        let (kmin, kmax) = pts.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
            (a.min(p.curvature), b.max(p.curvature))
        });
        if -kmin > kmax {
            curv.legend = Corner::BottomRight;
        }
        let cant = Panel::new(
            "Cant angle (outer rail higher)",
            "station s (m)",
            "cant θ (mrad)",
        )
        .with(Series::new(
            "θ",
            stations,
            col(&|p| 1e3 * p.cant, &pts),
            Style::Line,
            "#9467bd",
        ))
        .with(Series::new(
            "segment joints",
            joints,
            col(&|p| 1e3 * p.cant, &jp),
            Style::Markers,
            "#d62728",
        ));
        Figure::new().with(plan).with(curv).with(cant)
    }
}

/// Writes `track.csv` (every 10 m, see [`Track::write_csv`]) and `track.svg` (the plan and
/// cant diagram, [`Track::figure`]) into the directory `dir`, creating it if needed.
pub fn write_track_report(track: &Track, dir: impl AsRef<Path>) -> io::Result<()> {
    let dir = dir.as_ref();
    std::fs::create_dir_all(dir)?;
    let step = 10.0f64.max(track.alignment.length() / 5000.0);
    track.write_csv(dir.join("track.csv"), step)?;
    track.figure(step).write_svg_and_png(dir.join("track.svg"))
}

/// Station → (element, local coordinate) search over the node stations of a rail mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct RailLookup {
    stations: Vec<f64>,
}

impl RailLookup {
    /// A lookup over node stations (m): at least two, finite and strictly increasing.
    pub fn new(stations: Vec<f64>) -> Result<Self, AlignmentError> {
        let ok = stations.len() >= 2
            && stations.iter().all(|s| s.is_finite())
            && stations.windows(2).all(|w| w[1] > w[0]);
        if !ok {
            return Err(AlignmentError::Mesh(
                "rail lookup: node stations must be at least two, finite and strictly increasing"
                    .into(),
            ));
        }
        Ok(Self { stations })
    }

    /// The node stations (m).
    pub fn stations(&self) -> &[f64] {
        &self.stations
    }

    /// Number of elements (nodes − 1).
    pub fn element_count(&self) -> usize {
        self.stations.len() - 1
    }

    /// The element under `station` and the local coordinate ξ ∈ [0, 1] in it, by binary
    /// search (O(log n)). A station exactly on a node belongs to the element that starts
    /// there (ξ = 0 exactly), except the last node (last element, ξ = 1). `None` outside
    /// `[first, last]` or for NaN.
    pub fn locate(&self, station: f64) -> Option<(usize, f64)> {
        locate_in(&self.stations, station)
    }
}

/// [`RailLookup::locate`] over a slice of node stations already known to be valid (at least
/// two, strictly increasing): binary search, a station on a node belongs to the element that
/// starts there, the last node to the last element with ξ = 1.
pub fn locate_in(stations: &[f64], station: f64) -> Option<(usize, f64)> {
    let (first, last) = (*stations.first()?, *stations.last()?);
    if stations.len() < 2 || !(first..=last).contains(&station) {
        return None;
    }
    let e = (stations.partition_point(|&s| s <= station) - 1).min(stations.len() - 2);
    let (a, b) = (stations[e], stations[e + 1]);
    let xi = if station == b {
        1.0
    } else {
        (station - a) / (b - a)
    };
    Some((e, xi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::geometry::cant::Cant;

    #[test]
    fn stations_include_joints_and_respect_length() {
        let t = Track::paper(6250.0, 200.0);
        let st = t.rail_stations(0.6);
        assert_eq!(st[0], 0.0);
        assert_eq!(*st.last().unwrap(), t.alignment.length());
        for j in t.alignment.joints() {
            assert!(st.contains(&j), "joint {j} is not a node");
        }
        assert!(st
            .windows(2)
            .all(|w| w[1] > w[0] && w[1] - w[0] <= 0.6 + 1e-9));
        // 500/0.6 → 834 elements (ceil), 2000/0.6 → 3334, etc.
        assert_eq!(t.rail_stations(100.0).len(), 1 + 5 + 20 + 110 + 20 + 8);
        assert!(t.try_rail_stations(0.0).is_err());
        assert!(t.try_rail_stations(f64::NAN).is_err());
    }

    #[test]
    fn rail_lines_are_a_gauge_apart_and_canted() {
        let t = Track::paper(6250.0, 900.0);
        for s in [0.0, 1500.0, 7000.0] {
            let (l, r) = (
                t.rail_position(s, RailSide::Left),
                t.rail_position(s, RailSide::Right),
            );
            // Differences of coordinates of up to ~1e4 m: round-off ~1e-12 m.
            assert!(((l - r).norm() - 1.435).abs() < 1e-11);
            let theta = t.at(s).cant;
            // Left-hand curve: the right (outer) rail is higher by G·sin θ.
            assert!((r.z - l.z - 1.435 * theta.sin()).abs() < 1e-15);
            // Both rails are square to the tangent.
            assert!((l - r).dot(&t.at(s).tangent).abs() < 1e-11);
        }
    }

    #[test]
    fn lookup_exact_at_boundaries() {
        let t = Track::new(
            crate::rail::geometry::alignment::Alignment::straight(10.0),
            Cant::none(),
        )
        .unwrap();
        let lk = RailLookup::new(t.rail_stations(3.0)).unwrap();
        assert_eq!(lk.stations(), &[0.0, 2.5, 5.0, 7.5, 10.0]);
        assert_eq!(lk.element_count(), 4);
        assert_eq!(lk.locate(0.0), Some((0, 0.0)));
        assert_eq!(lk.locate(2.5), Some((1, 0.0)));
        assert_eq!(lk.locate(3.75), Some((1, 0.5)));
        assert_eq!(lk.locate(7.5), Some((3, 0.0)));
        assert_eq!(lk.locate(10.0), Some((3, 1.0)));
        assert_eq!(lk.locate(-1e-12), None);
        assert_eq!(lk.locate(10.000001), None);
        assert_eq!(lk.locate(f64::NAN), None);
        assert!(RailLookup::new(vec![0.0, 0.0]).is_err());
        // Every node of a paper mesh maps to itself.
        let st = Track::paper(6250.0, 200.0).rail_stations(25.0);
        let lk = RailLookup::new(st.clone()).unwrap();
        for (i, &s) in st.iter().enumerate().take(st.len() - 1) {
            assert_eq!(lk.locate(s), Some((i, 0.0)));
        }
    }

    #[test]
    fn report_writes_parseable_csv_and_svg() {
        let dir = std::env::temp_dir().join(format!("railfem-track-report-{}", std::process::id()));
        let t = Track::paper(6250.0, 200.0);
        write_track_report(&t, &dir).unwrap();
        let csv = std::fs::read_to_string(dir.join("track.csv")).unwrap();
        let mut lines = csv.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(head.len(), 17);
        assert_eq!(head[6], "radius [m]");
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
            .collect();
        assert!(rows.iter().all(|r| r.len() == 17));
        assert_eq!(rows[0][6], f64::INFINITY);
        let last = rows.last().unwrap();
        assert!((last[0] - 16_208.307_8).abs() < 1e-9);
        let mid = rows.iter().find(|r| r[0] == 7000.0).unwrap();
        assert!((mid[6] - 6250.0).abs() < 1e-9 && (mid[7] - 0.032).abs() < 1e-15);
        // Columns e1..e3 are the frame of Path::at.
        let f = t.at(7000.0).frame;
        assert_eq!(mid[8..11], [f[(0, 0)], f[(1, 0)], f[(2, 0)]]);
        let svg = std::fs::read_to_string(dir.join("track.svg")).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("Plan of the track centre line"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
