//! `railfem study PLAN.toml`: many runs of one case over parameter axes (docs/study.md).
//!
//! The plan ([`plan`]) names a base case and axes; [`cases`] expands them into cases with
//! stable ids; [`run`] computes a case and runs local worker threads; under `mpirun` with
//! the `mpi` feature, `mpi` makes rank 0 the master that hands cases to the other ranks.
//! Every finished case is appended to the checkpoint ([`checkpoint`]) by the one recording
//! thread of rank 0; at the end (or at a stop) the table, the sidecar and the figure
//! ([`table`]) are written from the checkpoint's rows, sorted by case id, so the table is
//! the same bytes whatever the threads, the ranks or the number of resumptions.

pub mod cases;
pub mod checkpoint;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod plan;
pub mod run;
pub mod table;

use crate::framework::FemError;
use std::path::PathBuf;
use std::sync::mpsc;

/// Default output folder.
pub const DEFAULT_OUT: &str = "out/study";

/// What the command line asks of a study.
#[derive(Debug, Clone)]
pub struct Options {
    /// The plan file.
    pub plan: PathBuf,
    /// Output folder.
    pub out: PathBuf,
    /// Computing threads of this process.
    pub threads: usize,
    /// Hand out at most this many cases in this run, then stop (resumable).
    pub stop_after: Option<usize>,
    /// Start afresh: the checkpoint's rows are discarded, not verified.
    pub restart: bool,
}

/// What a study run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Cases in the plan.
    pub cases: usize,
    /// Finished with results.
    pub ok: usize,
    /// Finished with an error.
    pub failed: usize,
    /// Computed in this run.
    pub this_run: usize,
}

/// Refuses a process that a launcher started as one of `launched` ranks but that runs in a
/// world of `size`: each such process would run the whole study alone, all of them into
/// one checkpoint. `size` is 1 in a build without the `mpi` feature, and in an MPI build
/// whose MPI library is not the launcher's (each rank then starts as a singleton).
fn check_launch(size: usize, launched: Option<usize>) -> Result<(), FemError> {
    match launched {
        Some(n) if n != size => {
            let fix = if cfg!(feature = "mpi") {
                "rebuild with `--features mpi` against the MPI library of the mpirun on PATH"
            } else {
                "this railfem is built without MPI: build it with `--features mpi` \
                 (docs/scale-out.md), or run the study without mpirun"
            };
            Err(FemError::input(
                "mpirun",
                format!(
                    "the launcher started {n} ranks but this one is in a world of {size}; {fix}"
                ),
            ))
        }
        _ => Ok(()),
    }
}

/// `railfem study`: the exit code (0 done, 130 stopped by a signal, resumable).
pub fn command(o: Options) -> Result<i32, FemError> {
    let plan = plan::read(&o.plan)?;
    let cases = cases::expand(&plan);
    #[cfg(feature = "mpi")]
    let world = mpi::World::init();
    #[cfg(feature = "mpi")]
    let size = world.as_ref().map_or(1, |w| w.size());
    #[cfg(not(feature = "mpi"))]
    let size = 1;
    check_launch(size, crate::sidecar::launcher_size().map(|n| n as usize))?;
    #[cfg(feature = "mpi")]
    if let Some(w) = world.as_ref().filter(|w| !w.is_master()) {
        w.serve(&plan, &cases, &o.out);
        return Ok(0);
    }
    let fingerprint = cases::fingerprint(&plan, &cases)?;
    let mut ck = checkpoint::Checkpoint::open(&o.out, &plan, &cases, fingerprint, o.restart)?;
    let skipped = cases.iter().filter(|c| ck.rows.contains_key(&c.id)).count();
    let mut todo: Vec<(f64, usize)> = cases
        .iter()
        .filter(|c| !ck.rows.contains_key(&c.id))
        .map(|c| (cases::cost(&plan, c), c.index))
        .collect();
    // Longest first; equal costs in id order, so the order is the same on every run.
    todo.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let todo: Vec<usize> = todo.into_iter().map(|t| t.1).collect();
    let left = todo.len();
    let planned = o.stop_after.unwrap_or(left).min(left);
    let queue = run::Queue::new(todo, planned);
    #[cfg(feature = "mpi")]
    let ranks = world.as_ref().map_or(1, |w| w.size());
    #[cfg(not(feature = "mpi"))]
    let ranks = 1usize;
    if skipped > 0 {
        eprintln!(
            "study: {skipped} of {} cases already in {}; running the other {}",
            cases.len(),
            o.out.join(checkpoint::FILE).display(),
            left
        );
    }
    let mut bar = crate::progress::Progress::new("study", planned as u64, "cases");
    // The cases' own progress displays stay silent; the study's bar is made already.
    let was_quiet = crate::progress::quiet();
    crate::progress::set_quiet(true);
    let mut this_run = 0usize;
    let mut first_error: Option<FemError> = None;
    let mut record = |ck: &mut checkpoint::Checkpoint, i: usize, row: Option<String>| {
        if let Some(row) = row {
            if let Err(e) = ck.record(&cases[i].id, row) {
                first_error.get_or_insert(e);
            }
            this_run += 1;
            bar.set(this_run as u64);
        }
    };
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel::<run::Done>();
        // Under MPI the master rank computes with its threads too; --threads 0 is not
        // allowed, so it always takes part.
        run::spawn_workers(s, o.threads, &plan, &cases, &queue, &o.out, &tx);
        drop(tx);
        #[cfg(feature = "mpi")]
        if let Some(w) = world.as_ref().filter(|w| w.size() > 1) {
            w.master(&queue, &rx, &mut |i, row| record(&mut ck, i, row));
            return;
        }
        for (i, row) in rx {
            record(&mut ck, i, row);
        }
    });
    bar.finish();
    crate::progress::set_quiet(was_quiet);
    if let Some(e) = first_error {
        return Err(e);
    }
    let interrupted = crate::framework::interrupt::requested();
    let rows = &ck.rows;
    // Counted over the plan's cases (every row the checkpoint kept is one of them).
    let status_of = |c: &cases::Case| rows.get(&c.id).map(|r| status(r, plan.axes.len()));
    let counts = Counts {
        cases: cases.len(),
        ok: cases
            .iter()
            .filter(|c| status_of(c).as_deref() == Some("ok"))
            .count(),
        failed: cases
            .iter()
            .filter(|c| status_of(c).as_deref() == Some("failed"))
            .count(),
        this_run,
    };
    table::write_csv(&plan, rows, &o.out)?;
    let figure = table::write_figure(&plan, &cases, rows, &o.out)?;
    write_sidecar(&plan, &o, counts, fingerprint, ranks, interrupted)?;
    let done = counts.ok + counts.failed;
    let not_run = cases.iter().filter(|c| !rows.contains_key(&c.id)).count();
    println!(
        "study: {} cases, {} ok, {} failed, {} not yet run; {} computed now on {} rank(s) × {} thread(s); table {}{}",
        counts.cases,
        counts.ok,
        counts.failed,
        not_run,
        counts.this_run,
        ranks,
        o.threads,
        o.out.join("study.csv").display(),
        figure.map_or(String::new(), |f| format!(", figure {}", f.display()))
    );
    if interrupted {
        eprintln!(
            "study: stopped by a signal at a case boundary; the {done} finished cases are in {}, the cases in progress were not kept; run the same command again to go on",
            o.out.join(checkpoint::FILE).display()
        );
        return Err(FemError::Interrupted { t: 0.0 });
    }
    if not_run > 0 {
        println!(
            "study: stopped after {} cases as asked (--stop-after); run the same command again to go on",
            counts.this_run
        );
    }
    Ok(0)
}

/// The status cell of a row (after the id and the axis values).
fn status(row: &str, axes: usize) -> String {
    table::split_csv(row)
        .into_iter()
        .nth(1 + axes)
        .unwrap_or_default()
}

/// `study.json`: the plan, railfem's version and git revision, the counts and how this
/// run ran (ranks, threads).
fn write_sidecar(
    plan: &plan::Plan,
    o: &Options,
    c: Counts,
    fingerprint: u64,
    ranks: usize,
    interrupted: bool,
) -> Result<(), FemError> {
    let v = serde_json::json!({
        "railfem": {
            "version": env!("CARGO_PKG_VERSION"),
            "git_revision": env!("RAILFEM_GIT_REVISION"),
            "mpi_feature": cfg!(feature = "mpi"),
        },
        "plan_file": o.plan.display().to_string(),
        "plan": plan.json,
        "base": plan.base.name(),
        "axes": plan.axes.iter().map(|a| serde_json::json!({
            "name": a.name,
            "values": a.values.iter().map(|v| v.label()).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "fingerprint": format!("{fingerprint:016x}"),
        "cases": c.cases,
        "ok": c.ok,
        "failed": c.failed,
        "not_run": c.cases.saturating_sub(c.ok + c.failed),
        "computed_this_run": c.this_run,
        "ranks": ranks,
        "threads_per_rank": o.threads,
        "status": if interrupted { "interrupted" } else if c.ok + c.failed == c.cases { "completed" } else { "partial" },
    });
    let p = o.out.join("study.json");
    let text = serde_json::to_string_pretty(&v).unwrap_or_default() + "\n";
    crate::atomic_file::write(&p, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A launch of `n` ranks is accepted only by a world of `n`; no launcher, any world.
    #[test]
    fn a_rank_outside_the_launchers_world_is_refused() {
        assert!(check_launch(1, None).is_ok());
        assert!(check_launch(1, Some(1)).is_ok());
        assert!(check_launch(2, Some(2)).is_ok());
        let e = check_launch(1, Some(2)).unwrap_err();
        assert!(matches!(e, FemError::Input { .. }));
        let text = e.to_string();
        assert!(
            text.contains("started 2 ranks") && text.contains("world of 1"),
            "{text}"
        );
    }
}
