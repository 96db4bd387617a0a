//! `railfem-measure retime --rounds N` and `retime-at H:DT,..`: the wall times behind the
//! train–bridge Pareto study's 1 % and 5 % picks, taken again back to back.
//!
//! The grid of [`railfem::pareto_train`] runs on a shared machine, one run after another
//! over an hour, so two neighbouring runs may have met very different loads. Here the
//! cheapest generalized-α run with the partitioned solver whose every error (Q, ΔQ/Q, w)
//! is within 5 %, the same for 1 %, and their neighbours in the grid (the next coarser
//! and finer mesh at the same step, the next longer step on the same mesh) are run again
//! in turn, `ROUNDS` times, so that each meets the same load on average; the ordering of
//! their medians is what the pick of Δt and mesh rests on.
//!
//! Generalized-α with the partitioned solver: the one block of the grid that has every
//! step, and the pick is of Δt and mesh (at equal Δt and mesh the integrators' and
//! solvers' errors are within a few percent of each other, their wall times within the
//! load's noise). The next shorter step is no neighbour: it doubles the steps, and the
//! grid's wall times never came close to reversing that.

use crate::load_average::loadavg;
use railfem::framework::model::SolverChoice;
use railfem::framework::FemError;
use railfem::pareto::Scheme;
use railfem::pareto_train::{simulate, Settings, TbGrid, TbRun, DURATION, MESH_K, SPACING};
use std::path::Path;

/// The accuracies a user is told which Δt and mesh to pick for.
pub const TARGETS: [f64; 2] = [0.05, 0.01];

/// The cheapest generalized-α, partitioned run (by its grid CPU time) whose errors are
/// all within `target`.
pub fn pick(runs: &[TbRun], target: f64) -> Option<&TbRun> {
    runs.iter()
        .filter(|r| r.settings.scheme == Scheme::GenAlpha)
        .filter(|r| r.settings.solver == SolverChoice::Partitioned)
        .filter(|r| r.errors.iter().all(|e| *e <= target))
        .min_by(|a, b| a.cpu.total_cmp(&b.cpu))
}

/// The neighbours of `s` in `grid`: same integrator and solver; the adjacent meshes of
/// [`MESH_K`] at the same step, and the next longer step on the same mesh.
pub fn neighbours(grid: &TbGrid, s: &Settings) -> Vec<Settings> {
    let same = |r: &&Settings| r.scheme == s.scheme && r.solver == s.solver;
    let k_of = |h: f64| {
        MESH_K
            .iter()
            .position(|&k| (SPACING / k as f64 - h).abs() < 1e-12)
    };
    let mut out = Vec::new();
    if let Some(i) = k_of(s.h) {
        for j in [i.wrapping_sub(1), i + 1] {
            if let Some(&k) = MESH_K.get(j) {
                let h = SPACING / k as f64;
                out.extend(
                    grid.runs
                        .iter()
                        .filter(same)
                        .filter(|r| r.dt == s.dt && r.h == h),
                );
            }
        }
    }
    let mut dts: Vec<f64> = grid
        .runs
        .iter()
        .filter(same)
        .filter(|r| r.h == s.h)
        .map(|r| r.dt)
        .collect();
    dts.sort_by(f64::total_cmp);
    dts.dedup();
    if let Some(i) = dts.iter().position(|&d| d == s.dt) {
        if let Some(&dt) = dts.get(i + 1) {
            out.push(Settings { dt, ..*s });
        }
    }
    out
}

/// One configuration re-timed: why it is there, its grid result and its wall times.
#[derive(Debug, Clone)]
pub struct Retimed {
    /// "pick 5 %", "pick 1 %" or "neighbour of …".
    pub role: String,
    /// Its run in the grid.
    pub run: TbRun,
    /// Wall time of each round (s).
    pub walls: Vec<f64>,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Picks and neighbours of `runs` (the grid's evaluated runs), each simulated again
/// `rounds` times in turn; writes `pareto-train-bridge-retime.md` into `out` and prints it.
pub fn run(grid: &TbGrid, runs: &[TbRun], rounds: usize, out: &Path) -> Result<(), FemError> {
    let mut list: Vec<Retimed> = Vec::new();
    for target in TARGETS {
        let Some(p) = pick(runs, target) else {
            eprintln!(
                "pareto retime: no run within {} %; nothing to re-time for it",
                target * 100.0
            );
            continue;
        };
        let tag = format!("{} %", target * 100.0);
        let mut add = |role: String, s: &Settings| {
            if list.iter().any(|r| r.run.settings == *s) {
                return;
            }
            if let Some(r) = runs.iter().find(|r| r.settings == *s) {
                list.push(Retimed {
                    role,
                    run: r.clone(),
                    walls: Vec::new(),
                });
            }
        };
        add(format!("pick {tag}"), &p.settings);
        for n in neighbours(grid, &p.settings) {
            add(format!("neighbour of the {tag} pick"), &n);
        }
    }
    retime(list, rounds, out)
}

/// Parses `railfem-measure retime-at H:DT,H:DT,…` (element length and time step in m and s; each run
/// generalized-α ρ∞ = 0.8 with the partitioned solver, like the picks).
pub fn parse_at(list: &str) -> Result<Vec<Settings>, FemError> {
    let bad = |item: &str| {
        FemError::input(
            "command line",
            format!("retime-at {list}: `{item}` is not H:DT (e.g. 0.3125:1e-3, both > 0)"),
        )
    };
    list.split(',')
        .map(|item| {
            let (h, dt) = item.trim().split_once(':').ok_or_else(|| bad(item))?;
            let num = |x: &str| {
                x.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| *v > 0.0 && v.is_finite())
            };
            Ok(Settings {
                h: num(h).ok_or_else(|| bad(item))?,
                dt: num(dt).ok_or_else(|| bad(item))?,
                scheme: Scheme::GenAlpha,
                solver: SolverChoice::Partitioned,
            })
        })
        .collect()
}

/// Re-times the runs `at` in turn, `rounds` times, without the grid (their errors are
/// the grid's, not repeated here); writes `pareto-train-bridge-retime.md` into `out`.
pub fn run_at(at: &[Settings], rounds: usize, out: &Path) -> Result<(), FemError> {
    let list = at
        .iter()
        .map(|s| Retimed {
            role: "given".to_string(),
            run: TbRun {
                settings: *s,
                dofs: 0,
                steps: 0,
                wall: f64::NAN,
                cpu: f64::NAN,
                threads: 0,
                errors: [f64::NAN; 3],
                pareto: [false; 3],
            },
            walls: Vec::new(),
        })
        .collect();
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    retime(list, rounds, out)
}

/// Simulates every run of `list` in turn, `rounds` times; writes the table.
fn retime(mut list: Vec<Retimed>, rounds: usize, out: &Path) -> Result<(), FemError> {
    let mut loads = Vec::new();
    for round in 0..rounds {
        let at_start = loadavg();
        for r in &mut list {
            let h = simulate(&r.run.settings, DURATION)?;
            eprintln!(
                "pareto retime, round {}: h {:.4} dt {:e} {} {}: wall {:.2} s, cpu {:.2} s, {} thread(s), load {}",
                round + 1,
                r.run.settings.h,
                r.run.settings.dt,
                r.run.settings.scheme.name(),
                r.run.settings.solver.name(),
                h.wall,
                h.cpu,
                h.threads,
                loadavg()
            );
            r.walls.push(h.wall);
        }
        loads.push((at_start, loadavg()));
    }
    let md = markdown(&list, &loads);
    let p = out.join("pareto-train-bridge-retime.md");
    std::fs::write(&p, &md).map_err(|e| FemError::output(&p, e))?;
    print!("{md}");
    Ok(())
}

/// The re-timing as a markdown table, with the load average (1, 5, 15 min) at the start
/// and end of every round.
fn markdown(list: &[Retimed], loads: &[(String, String)]) -> String {
    let cell = |x: f64, digits: usize| {
        if !x.is_finite() {
            "—".to_string()
        } else if digits == 1 {
            format!("{x:.1}")
        } else {
            format!("{x:.2e}")
        }
    };
    let mut s = String::from(
        "\nRe-timed back to back, in turn (wall times in s; the grid's own in the first \
         time column):\n\n| role | integrator | solver | h (m) | dt (s) | err Q | err w | \
         grid wall |",
    );
    let rounds = list.first().map_or(0, |r| r.walls.len());
    for k in 0..rounds {
        s.push_str(&format!(" round {} |", k + 1));
    }
    s.push_str(" median |\n|---|---|---|---:|---:|---:|---:|---:|");
    for _ in 0..=rounds {
        s.push_str("---:|");
    }
    s.push('\n');
    for r in list {
        let st = &r.run.settings;
        s.push_str(&format!(
            "| {} | {} | {} | {:.4} | {:e} | {} | {} | {} |",
            r.role,
            st.scheme.name(),
            st.solver.name(),
            st.h,
            st.dt,
            cell(r.run.errors[0], 2),
            cell(r.run.errors[2], 2),
            cell(r.run.wall, 1)
        ));
        for w in &r.walls {
            s.push_str(&format!(" {w:.1} |"));
        }
        s.push_str(&format!(" {:.1} |\n", median(&r.walls)));
    }
    s.push_str("\nLoad average (1, 5, 15 min) at the start → end of each round: ");
    let l: Vec<String> = loads.iter().map(|(a, b)| format!("{a} → {b}")).collect();
    s.push_str(&l.join("; "));
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(h: f64, dt: f64, wall: f64, e: f64) -> TbRun {
        TbRun {
            settings: Settings {
                dt,
                h,
                scheme: Scheme::GenAlpha,
                solver: SolverChoice::Partitioned,
            },
            dofs: 0,
            steps: 0,
            wall,
            cpu: wall,
            threads: 1,
            errors: [e, e, e / 10.0],
            pareto: [false; 3],
        }
    }

    /// The pick is the cheapest generalized-α, partitioned run within the target, not the
    /// most accurate one nor the first; none when no run reaches it.
    #[test]
    fn pick_is_the_cheapest_within_target() {
        let newmark = TbRun {
            settings: Settings {
                scheme: Scheme::Newmark,
                ..run(SPACING, 4e-3, 5.0, 0.03).settings
            },
            ..run(SPACING, 4e-3, 5.0, 0.03)
        };
        let runs = [
            newmark,
            run(SPACING, 4e-3, 10.0, 0.03),
            run(SPACING / 2.0, 1e-3, 80.0, 0.008),
            run(SPACING / 2.0, 2e-3, 40.0, 0.015),
            run(SPACING / 9.0, 2.5e-4, 400.0, 0.001),
        ];
        assert_eq!(pick(&runs, 0.05).unwrap().wall, 10.0);
        assert_eq!(pick(&runs, 0.01).unwrap().wall, 80.0);
        assert!(pick(&runs, 1e-4).is_none());
    }

    /// In the default grid the neighbours of 0.3125 m at 1 ms (generalized-α,
    /// partitioned) are 0.625 and 0.125 m at 1 ms and 0.3125 m at 2 ms; those of 0.625 m
    /// at 2 ms with Newmark are 0.3125 m at 2 ms and 0.625 m at 4 ms; 0.625 m at 4 ms, the
    /// grid's cheapest corner, has only 0.3125 m at 4 ms.
    #[test]
    fn neighbours_in_the_default_grid() {
        let g = TbGrid::default();
        let s = run(SPACING / 2.0, 1e-3, 0.0, 0.0).settings;
        let mut n: Vec<(f64, f64)> = neighbours(&g, &s).iter().map(|r| (r.h, r.dt)).collect();
        n.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            n,
            vec![
                (SPACING / 5.0, 1e-3),
                (SPACING / 2.0, 2e-3),
                (SPACING, 1e-3)
            ]
        );
        let s = Settings {
            scheme: Scheme::Newmark,
            ..run(SPACING, 2e-3, 0.0, 0.0).settings
        };
        let n: Vec<Settings> = neighbours(&g, &s);
        assert_eq!(n.len(), 2, "{n:?}");
        assert!(n.iter().all(|r| r.scheme == Scheme::Newmark));
        assert!(n.iter().any(|r| r.h == SPACING / 2.0 && r.dt == 2e-3));
        assert!(n.iter().any(|r| r.h == SPACING && r.dt == 4e-3));
        let s = run(SPACING, 4e-3, 0.0, 0.0).settings;
        let n: Vec<(f64, f64)> = neighbours(&g, &s).iter().map(|r| (r.h, r.dt)).collect();
        assert_eq!(n, vec![(SPACING / 2.0, 4e-3)]);
    }

    /// `retime-at` takes element length and step pairs; anything else is refused with
    /// the option's name and the form it wants.
    #[test]
    fn retime_at_list() {
        let at = parse_at("0.3125:1e-3, 0.625:4e-3").unwrap();
        assert_eq!(at.len(), 2);
        assert_eq!((at[0].h, at[0].dt), (0.3125, 1e-3));
        assert_eq!((at[1].h, at[1].dt), (0.625, 4e-3));
        assert!(at.iter().all(|s| s.scheme == Scheme::GenAlpha));
        for bad in ["0.3125", "0.3125:", "x:1e-3", "0.3125:-1e-3", "0.3:1e-3,"] {
            let e = parse_at(bad).unwrap_err().to_string();
            assert!(e.contains("retime-at") && e.contains(bad), "{bad}: {e}");
        }
    }
}
