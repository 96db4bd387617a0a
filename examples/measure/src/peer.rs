//! `railfem-measure peer FILE`: another code's runs of the moving-force case on the same
//! run-time-against-error plot as railfem's ([`railfem::pareto`]), and the wall-time ratio
//! at equal error.
//!
//! The peer file is a CSV that the peer's own driver writes (`scripts/opensees_compare.py
//! --pareto` for OpenSees), one run per line, with at least the columns
//! [`PEER_COLUMNS`] in any order (more columns are allowed and ignored; no quoting, so a
//! label holds no comma):
//!
//! ```text
//! peer,elements,dt [s],steps,wall [s],error [-]
//! OpenSees ProfileSPD,8,3.478e-4,320,0.84,5.81e-4
//! ```
//!
//! `error [-]` must be the case's own measure (largest midspan deflection difference from
//! Frýba's series over the crossing, relative to its peak; [`railfem::pareto::fryba_midspan`])
//! and `wall [s]` the peer's wall time for the whole run. The points are drawn as squares
//! beside railfem's circles, each code's Pareto front as its own line, and
//! `pareto-peers.md` lists, for every peer point on its front, the cheapest railfem
//! Newmark run that is at least as accurate and the ratio of the two wall times.

use railfem::framework::limits::{check_count, check_file};
use railfem::framework::plot::{Figure, Series, Style};
use railfem::framework::FemError;
use railfem::pareto::{Run, Scheme};
use std::path::Path;

/// The columns a peer CSV must have (header names, units in brackets).
pub const PEER_COLUMNS: [&str; 6] = [
    "peer",
    "elements",
    "dt [s]",
    "steps",
    "wall [s]",
    "error [-]",
];

/// Most runs a peer file may hold (each is a point on a plot; a million is far beyond any grid).
pub const MAX_PEER_RUNS: f64 = 1e6;

/// One run of the peer code.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerRun {
    /// What ran (code and configuration, e.g. `OpenSees ProfileSPD`).
    pub label: String,
    /// Elements on the span.
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the run (s).
    pub wall: f64,
    /// Error against Frýba's series (relative).
    pub error: f64,
    /// On the peer's Pareto front (no other peer run is both faster and more accurate).
    pub pareto: bool,
}

/// Reads a peer CSV; every refusal is one line naming the file, the line and column, and
/// the fix.
pub fn read_peer_csv(path: &Path) -> Result<Vec<PeerRun>, FemError> {
    let origin = format!("peer file {}", path.display());
    check_file(path, "peer file").map_err(|m| FemError::input(&origin, m))?;
    let text = std::fs::read_to_string(path).map_err(|e| {
        FemError::input(
            &origin,
            format!("cannot read the peer runs ({e}); give the CSV that scripts/opensees_compare.py --pareto writes"),
        )
    })?;
    parse_peer_csv(&text, &origin)
}

/// Parses the text of a peer CSV (see the module doc); `origin` names the file in messages.
pub fn parse_peer_csv(text: &str, origin: &str) -> Result<Vec<PeerRun>, FemError> {
    let mut lines = railfem::framework::csv_input::strip_bom(text)
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Err(FemError::input(
            origin,
            format!(
                "the file is empty; it needs a header `{}` and one run per line",
                PEER_COLUMNS.join(",")
            ),
        ));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut col = [0usize; 6];
    for (c, want) in col.iter_mut().zip(PEER_COLUMNS) {
        *c = names.iter().position(|n| *n == want).ok_or_else(|| {
            FemError::input(
                format!("{origin}: line 1 (header)"),
                format!(
                    "no column `{want}`; the header must name {} (units as written)",
                    PEER_COLUMNS.map(|n| format!("`{n}`")).join(", ")
                ),
            )
        })?;
    }
    let rows: Vec<(usize, &str)> = lines.collect();
    check_count(
        origin,
        rows.len() as f64,
        "peer runs",
        MAX_PEER_RUNS,
        "give one line per run of the grid",
    )
    .map_err(|m| FemError::input(origin, m))?;
    if rows.is_empty() {
        return Err(FemError::input(
            origin,
            "no runs below the header; give one line per run (scripts/opensees_compare.py --pareto writes them)",
        ));
    }
    let mut runs = Vec::with_capacity(rows.len());
    for (i, line) in rows {
        let at = |name: &str| format!("{origin}: line {}, column `{name}`", i + 1);
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(FemError::input(
                format!("{origin}: line {}", i + 1),
                format!(
                    "{} fields but the header has {}; give one value per column (no commas inside a value)",
                    fields.len(),
                    names.len()
                ),
            ));
        }
        let field = |k: usize| fields[col[k]];
        let count = |k: usize| -> Result<usize, FemError> {
            let v = field(k);
            match v.parse::<f64>() {
                Ok(x) if x >= 1.0 && x.fract() == 0.0 && x <= 1e12 => Ok(x as usize),
                _ => Err(FemError::input(
                    at(PEER_COLUMNS[k]),
                    format!("`{v}` is not a whole number >= 1; give the count of the run"),
                )),
            }
        };
        let positive = |k: usize, what: &str| -> Result<f64, FemError> {
            let v = field(k);
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
                _ => Err(FemError::input(
                    at(PEER_COLUMNS[k]),
                    format!("`{v}` is not a finite number > 0; give {what}"),
                )),
            }
        };
        let label = field(0);
        if label.is_empty() {
            return Err(FemError::input(
                at("peer"),
                "empty; name the code and its configuration (e.g. OpenSees ProfileSPD)",
            ));
        }
        let error = match field(5).parse::<f64>() {
            Ok(x) if x.is_finite() && x >= 0.0 => x,
            _ => {
                return Err(FemError::input(
                    at("error [-]"),
                    format!(
                        "`{}` is not a finite number >= 0; give the relative error against Frýba's series",
                        field(5)
                    ),
                ))
            }
        };
        runs.push(PeerRun {
            label: label.to_string(),
            elements: count(1)?,
            dt: positive(2, "the time step in s")?,
            steps: count(3)?,
            wall: positive(4, "the run's wall time in s")?,
            error,
            pareto: false,
        });
    }
    mark_front(&mut runs);
    Ok(runs)
}

/// `true` for the points `(wall, error)` that no other point beats in both (at least as
/// good in one, better in the other).
pub fn front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .enumerate()
        .map(|(i, &(w, e))| {
            e.is_finite()
                && !points
                    .iter()
                    .enumerate()
                    .any(|(j, &(wj, ej))| j != i && wj <= w && ej <= e && (wj < w || ej < e))
        })
        .collect()
}

/// Marks the peer runs on the peer's Pareto front (all labels together).
pub fn mark_front(peers: &mut [PeerRun]) {
    let pts: Vec<(f64, f64)> = peers.iter().map(|p| (p.wall, p.error)).collect();
    for (p, on) in peers.iter_mut().zip(front(&pts)) {
        p.pareto = on;
    }
}

/// The cheapest railfem Newmark run of the force case whose error is at most `error`.
pub fn cheapest_at_error(runs: &[Run], error: f64) -> Option<&Run> {
    runs.iter()
        .filter(|r| r.case == "force" && r.scheme == Scheme::Newmark && r.error <= error)
        .min_by(|a, b| a.wall.total_cmp(&b.wall))
}

/// Adds the peer runs to the force figure: squares per label (colours unused by railfem's
/// integrators) and the peer's front as a dashed line.
pub fn add_to_figure(fig: &mut Figure, peers: &[PeerRun]) {
    let Some(panel) = fig.panels.first_mut() else {
        return;
    };
    let colors = [
        "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
    ];
    let mut labels: Vec<&str> = Vec::new();
    for p in peers {
        if !labels.contains(&p.label.as_str()) {
            labels.push(&p.label);
        }
    }
    for (k, label) in labels.iter().enumerate() {
        let pts: Vec<&PeerRun> = peers.iter().filter(|p| p.label == *label).collect();
        panel.series.push(Series::new(
            label,
            pts.iter().map(|p| p.wall).collect(),
            pts.iter().map(|p| p.error).collect(),
            Style::Squares,
            colors[k % colors.len()],
        ));
    }
    let mut on: Vec<&PeerRun> = peers.iter().filter(|p| p.pareto).collect();
    on.sort_by(|a, b| a.wall.total_cmp(&b.wall));
    panel.series.push(Series::new(
        "peer Pareto front",
        on.iter().map(|p| p.wall).collect(),
        on.iter().map(|p| p.error).collect(),
        Style::Dashed,
        "#ff7f0e",
    ));
}

/// The peer's front against railfem at equal error, as a markdown table, and the median
/// ratio of the wall times (peer / railfem) over the peer points railfem matches.
pub fn markdown(runs: &[Run], peers: &[PeerRun]) -> (String, Option<f64>) {
    let mut s = String::from(
        "| peer | elements | dt (s) | steps | peer wall (s) | peer error | railfem elements | railfem dt (s) | railfem wall (s) | railfem error | wall ratio peer / railfem |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut on: Vec<&PeerRun> = peers.iter().filter(|p| p.pareto).collect();
    on.sort_by(|a, b| a.wall.total_cmp(&b.wall));
    let mut ratios = Vec::new();
    for p in on {
        let head = format!(
            "| {} | {} | {:.3e} | {} | {:.4} | {:.3e} |",
            p.label, p.elements, p.dt, p.steps, p.wall, p.error
        );
        match cheapest_at_error(runs, p.error) {
            Some(r) => {
                let ratio = p.wall / r.wall;
                ratios.push(ratio);
                s.push_str(&format!(
                    "{head} {} | {:.3e} | {:.4} | {:.3e} | {:.1} |\n",
                    r.elements, r.dt, r.wall, r.error, ratio
                ));
            }
            None => s.push_str(&format!(
                "{head} — | — | — | — | no railfem run this accurate |\n"
            )),
        }
    }
    ratios.sort_by(f64::total_cmp);
    let median = (!ratios.is_empty()).then(|| {
        let n = ratios.len();
        if n % 2 == 1 {
            ratios[n / 2]
        } else {
            0.5 * (ratios[n / 2 - 1] + ratios[n / 2])
        }
    });
    (s, median)
}

/// Redraws `pareto-force.svg` (and its PNG) in `out` with the peer runs and writes
/// `pareto-peers.md`.
pub fn write(runs: &[Run], peers: &[PeerRun], out: &Path) -> Result<(), FemError> {
    let mut fig = railfem::pareto::figure(runs, "force");
    add_to_figure(&mut fig, peers);
    let p = out.join("pareto-force.svg");
    fig.write_svg_and_png(&p)
        .map_err(|e| FemError::output(&p, e))?;
    let (table, median) = markdown(runs, peers);
    let mut md = String::from(
        "Peer runs on their Pareto front against the cheapest railfem Newmark run of the force case that is at least as accurate.\n\n",
    );
    md.push_str(&table);
    if let Some(m) = median {
        md.push_str(&format!(
            "\nMedian wall-time ratio (peer / railfem) at equal or better error: {m:.1}\n"
        ));
    }
    let p = out.join("pareto-peers.md");
    std::fs::write(&p, &md).map_err(|e| FemError::output(&p, e))?;
    print!("{md}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(wall: f64, error: f64, scheme: Scheme) -> Run {
        Run {
            case: "force",
            scheme,
            elements: 4,
            dt: 1e-3,
            steps: 10,
            wall,
            error,
            pareto: false,
        }
    }

    #[test]
    fn parses_columns_in_any_order_with_extras() {
        let text = "wall [s],peer,extra,error [-],steps,dt [s],elements\n\
                    0.5,OpenSees BandSPD,x,1e-3,100,2e-3,8\n\n\
                    0.25,OpenSees BandSPD,y,2e-3,50,4e-3,8\n";
        let p = parse_peer_csv(text, "t.csv").expect("parses");
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].label, "OpenSees BandSPD");
        assert_eq!((p[0].elements, p[0].steps), (8, 100));
        assert_eq!((p[0].dt, p[0].wall, p[0].error), (2e-3, 0.5, 1e-3));
        // Neither dominates the other: both on the front.
        assert!(p[0].pareto && p[1].pareto);
    }

    #[test]
    fn front_drops_dominated_points() {
        let f = front(&[
            (1.0, 1.0),
            (2.0, 0.5),
            (2.0, 2.0),
            (3.0, 0.5),
            (0.5, f64::NAN),
        ]);
        assert_eq!(f, vec![true, true, false, false, false]);
    }

    /// The ratio is taken against the cheapest Newmark run at least as accurate as the
    /// peer point; other integrators and less accurate runs are not used.
    #[test]
    fn ratio_at_equal_error_uses_cheapest_accurate_enough_newmark_run() {
        let runs = vec![
            run(0.01, 5e-3, Scheme::Newmark),
            run(0.02, 1e-3, Scheme::Newmark),
            run(0.001, 1e-4, Scheme::Hht),
            run(0.05, 5e-4, Scheme::Newmark),
        ];
        let r = cheapest_at_error(&runs, 1e-3).expect("a run");
        assert_eq!(r.wall, 0.02);
        let peers = parse_peer_csv(
            "peer,elements,dt [s],steps,wall [s],error [-]\nP,8,1e-3,10,0.2,1e-3\nP,8,1e-3,10,0.3,1e-6\n",
            "t",
        )
        .unwrap();
        let (table, median) = markdown(&runs, &peers);
        assert_eq!(median, Some(10.0));
        assert!(table.contains("no railfem run this accurate"), "{table}");
    }
}
