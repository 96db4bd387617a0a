//! Running the cases of a study: one case ([`compute`]: the base case with the case's
//! values, its results as table cells, an error or a panic turned into a failed row) and
//! the local pool (`Pool`): worker threads take case indices from one queue, longest
//! first, and send their rows back to the thread that records them. The MPI master
//! (`super::mpi`) serves remote workers from the same queue.

use super::cases::{self, Case};
use super::plan::{Base, Plan};
use super::table::{self, num, wheel_name};
use crate::framework::FemError;
use std::collections::VecDeque;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex};

/// Environment variable naming a case id whose run panics on purpose: the test of the
/// panic path (a panicking case is recorded as failed and the study goes on).
pub const PANIC_HOOK: &str = "RAILFEM_STUDY_PANIC_CASE";

/// Environment variable naming a case id whose process dies on the spot (`abort`, no
/// unwinding, as a crash or a kill would): the test of a rank that dies under MPI
/// (`scripts/mpi.sh`: the launcher ends the job with a message naming the rank, the
/// checkpoint keeps the finished cases, and rerunning resumes).
pub const ABORT_HOOK: &str = "RAILFEM_STUDY_ABORT_CASE";

/// Where a case writes its histories (`DIR/cases/<id>/`) when the plan asks for them.
pub fn history_dir(plan: &Plan, out: &Path, case: &Case) -> Option<PathBuf> {
    plan.histories.then(|| out.join("cases").join(&case.id))
}

/// Runs one case; its result cells (see [`table::result_columns`]).
fn run_case(plan: &Plan, case: &Case, out: &Path) -> Result<Vec<String>, FemError> {
    if std::env::var(PANIC_HOOK).is_ok_and(|id| id == case.id) {
        panic!("{PANIC_HOOK} asked case {} to panic", case.id);
    }
    if std::env::var(ABORT_HOOK).is_ok_and(|id| id == case.id) {
        eprintln!("{ABORT_HOOK} asked case {} to end its process", case.id);
        std::process::abort();
    }
    let hist = history_dir(plan, out, case);
    match &plan.base {
        Base::TrainBridge => {
            let c = cases::train_bridge(plan, case)?;
            let mut m = crate::train_bridge::build(&c)?;
            let r = crate::train_bridge::run(&mut m, &c, None, hist.as_deref())?;
            Ok(train_bridge_cells(plan, &r))
        }
        Base::Curve => {
            let c = cases::curve(plan, case)?;
            let r = crate::curve::run(&c, None, &mut |_| {})?;
            if let Some(dir) = &hist {
                std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
                crate::curve::write_outputs(&c, &r, dir)?;
            }
            Ok(curve_cells(&r))
        }
        Base::Model { path, value } => {
            let v = cases::model_value(value, plan, case);
            let name = format!("{} (case {})", path.display(), case.id);
            let folder = path.parent().unwrap_or(Path::new(""));
            let model = crate::model_from_value(&v, &name, folder);
            let (mut driver, _) = crate::prepare(model, &name, false)?;
            let mut wheels = WheelExtremes::of(&driver.model);
            // The model's activity window (`[analysis.window]`), as `railfem run` has it.
            let spec = driver.model.analysis.window;
            let mut window = crate::run_window::plan(&driver, &spec, &name)?;
            let (s, _) = driver
                .run_preparing(
                    hist.as_deref(),
                    false,
                    &mut |_| {},
                    &mut |m, t| wheels.observe(m, t),
                    &mut |d| window.before_step(d),
                )
                .map_err(|e| e.in_file(&name))?;
            let peak = driver.state.q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let mut c = vec![
                s.steps.to_string(),
                s.iterations.to_string(),
                s.cuts.to_string(),
                num(peak),
            ];
            c.extend(wheels.cells());
            Ok(c)
        }
    }
}

/// The wheel extremes of a model-file case: every element that reports `Q`, `YQ` and `dQQ`
/// (`moving_axle`, `hertz_wheel`, `rigid_wheel`: Y/Q as |Y|/Q, ΔQ/Q against the wheel's
/// own static load, 0 while a wheel carries no load), named `e<id>` by its model id, read
/// after every transient step.
struct WheelExtremes {
    /// (element index, its id, positions of Q, YQ and dQQ among its outputs).
    wheels: Vec<(usize, u64, [usize; 3])>,
    /// Per wheel: (max Y/Q, t), (max ΔQ/Q, t), (min Q, t).
    ext: Vec<[(f64, f64); 3]>,
    buf: Vec<f64>,
}

impl WheelExtremes {
    fn of(model: &crate::framework::model::Model) -> WheelExtremes {
        let wheels: Vec<_> = model
            .elements
            .iter()
            .enumerate()
            .filter_map(|(i, e)| {
                let names = e.element.output_names();
                let at = |k: &str| names.iter().position(|n| n == k);
                Some((i, e.id, [at("Q")?, at("YQ")?, at("dQQ")?]))
            })
            .collect();
        let start = [
            (f64::NEG_INFINITY, 0.0),
            (f64::NEG_INFINITY, 0.0),
            (f64::INFINITY, 0.0),
        ];
        WheelExtremes {
            ext: vec![start; wheels.len()],
            wheels,
            buf: Vec::new(),
        }
    }

    fn observe(&mut self, model: &crate::framework::model::Model, t: f64) {
        for (w, &(i, _, [iq, iyq, idqq])) in self.wheels.iter().enumerate() {
            self.buf.clear();
            model.elements[i].element.outputs(&mut self.buf);
            let e = &mut self.ext[w];
            let (q, yq, dqq) = (self.buf[iq], self.buf[iyq], self.buf[idqq]);
            if yq > e[0].0 {
                e[0] = (yq, t);
            }
            if dqq > e[1].0 {
                e[1] = (dqq, t);
            }
            if q < e[2].0 {
                e[2] = (q, t);
            }
        }
    }

    /// The nine overall cells: value, wheel and time of max Y/Q, max ΔQ/Q and min Q
    /// (empty without wheels or steps).
    fn cells(&self) -> Vec<String> {
        let mut c = Vec::new();
        for (k, sign) in [(0usize, 1.0), (1, 1.0), (2, -1.0)] {
            match argmax(self.ext.iter().map(|e| sign * e[k].0)) {
                Some((w, _)) => c.extend([
                    num(self.ext[w][k].0),
                    format!("e{}", self.wheels[w].1),
                    num(self.ext[w][k].1),
                ]),
                None => c.extend([String::new(), String::new(), String::new()]),
            }
        }
        c
    }
}

/// The largest of `values` (first on ties) with its index.
fn argmax(values: impl Iterator<Item = f64>) -> Option<(usize, f64)> {
    values.enumerate().fold(None, |best, (i, v)| match best {
        Some((_, b)) if b >= v => best,
        _ if v.is_finite() => Some((i, v)),
        _ => best,
    })
}

fn train_bridge_cells(plan: &Plan, r: &crate::train_bridge::TrainBridgeReport) -> Vec<String> {
    let w = &r.wheels;
    let mut c = Vec::new();
    let mut extreme = |pick: &dyn Fn(usize) -> (f64, f64), sign: f64| match argmax(
        (0..w.len()).map(|i| sign * pick(i).0),
    ) {
        Some((i, _)) => {
            let (v, t) = pick(i);
            c.extend([num(v), r.wheel_names[i].clone(), num(t)]);
        }
        None => c.extend([String::new(), String::new(), String::new()]),
    };
    extreme(&|i| w[i].max_yq, 1.0);
    extreme(&|i| w[i].max_dqq, 1.0);
    extreme(&|i| w[i].min_q, -1.0);
    // Deck: the largest midspan deflection (positive down) and acceleration over spans.
    let defl: Vec<(usize, f64, f64)> = r
        .midspan
        .iter()
        .map(|(k, h)| {
            h.iter().fold((*k, f64::NEG_INFINITY, 0.0), |a, &(t, v)| {
                if v > a.1 {
                    (*k, v, t)
                } else {
                    a
                }
            })
        })
        .collect();
    for list in [&defl, &r.deck_acc] {
        match argmax(list.iter().map(|x| x.1)) {
            Some((i, _)) => c.extend([num(list[i].1), list[i].0.to_string(), num(list[i].2)]),
            None => c.extend([String::new(), String::new(), String::new()]),
        }
    }
    let nwheels = table::result_columns(plan).len() - c.len();
    for (i, e) in w.iter().enumerate().take(nwheels / 6) {
        debug_assert_eq!(r.wheel_names[i], wheel_name(i));
        c.extend([
            num(e.max_yq.0),
            num(e.max_yq.1),
            num(e.max_dqq.0),
            num(e.max_dqq.1),
            num(e.min_q.0),
            num(e.min_q.1),
        ]);
    }
    c
}

fn curve_cells(r: &crate::curve::CurveReport) -> Vec<String> {
    let nw = r.samples.first().map_or(0, |s| s.wheels.len());
    let q0: Vec<f64> = (0..nw).map(|i| r.samples[0].wheels[i].q).collect();
    // Per wheel: (max |Y|/Q, t), (max ΔQ/Q against the first sample, t), (min Q, t).
    let mut ext = vec![
        [
            (f64::NEG_INFINITY, 0.0),
            (f64::NEG_INFINITY, 0.0),
            (f64::INFINITY, 0.0)
        ];
        nw
    ];
    for s in &r.samples {
        for (i, w) in s.wheels.iter().enumerate() {
            let yq = if w.q > 0.0 { w.y.abs() / w.q } else { f64::NAN };
            let dqq = (q0[i] - w.q) / q0[i];
            if yq > ext[i][0].0 {
                ext[i][0] = (yq, s.t);
            }
            if dqq > ext[i][1].0 {
                ext[i][1] = (dqq, s.t);
            }
            if w.q < ext[i][2].0 {
                ext[i][2] = (w.q, s.t);
            }
        }
    }
    let mut c = Vec::new();
    for (k, sign) in [(0usize, 1.0), (1, 1.0), (2, -1.0)] {
        match argmax(ext.iter().map(|e| sign * e[k].0)) {
            Some((i, _)) => c.extend([num(ext[i][k].0), wheel_name(i), num(ext[i][k].1)]),
            None => c.extend([String::new(), String::new(), String::new()]),
        }
    }
    let flag = |t: Option<f64>| {
        [
            u8::from(t.is_some()).to_string(),
            t.map_or(String::new(), num),
        ]
    };
    c.extend(flag(r.first_slide));
    c.extend(flag(r.first_separation));
    c.push(num(r.max_rel_normal_statics));
    c
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "a panic without a message".into())
}

/// Runs a case and makes its row: `ok` with the results, or `failed` with the error or the
/// panic's message. `None` when a stop request (Ctrl-C) cut the case: it is not finished
/// and runs again when the study resumes.
pub fn compute(plan: &Plan, case: &Case, out: &Path) -> Option<String> {
    let r = std::panic::catch_unwind(AssertUnwindSafe(|| run_case(plan, case, out)));
    let outcome = match r {
        Ok(Ok(cells)) => Ok(cells),
        Ok(Err(FemError::Interrupted { .. })) => return None,
        Ok(Err(e)) => Err(e.to_string()),
        Err(p) => Err(format!("panic: {}", panic_text(p.as_ref()))),
    };
    if crate::framework::interrupt::requested() && outcome.is_err() {
        // A case that failed while a stop was asked for may have failed because of it.
        return None;
    }
    Some(table::row(plan, case, &outcome))
}

/// The queue of cases still to hand out (indices into the case list, longest first) and
/// how many more may be handed out in this run (`--stop-after`).
pub struct Queue {
    todo: Mutex<VecDeque<usize>>,
    left: AtomicUsize,
}

impl Queue {
    /// A queue of `todo` (in hand-out order), at most `limit` of them handed out.
    pub fn new(todo: Vec<usize>, limit: usize) -> Queue {
        Queue {
            todo: Mutex::new(todo.into()),
            left: AtomicUsize::new(limit),
        }
    }

    /// The next case to run, unless the queue is empty, the limit reached or a stop asked.
    pub fn next(&self) -> Option<usize> {
        if crate::framework::interrupt::requested() {
            return None;
        }
        let mut q = self.todo.lock().ok()?;
        if self.left.load(Ordering::SeqCst) == 0 {
            return None;
        }
        let i = q.pop_front()?;
        self.left.fetch_sub(1, Ordering::SeqCst);
        Some(i)
    }
}

/// A message from a computing thread: the case index and its row (`None`: cut by a stop).
pub type Done = (usize, Option<String>);

/// Starts `threads` computing threads in `scope` taking cases from `queue`; each sends its
/// rows on `tx`.
pub fn spawn_workers<'s, 'e: 's>(
    scope: &'s std::thread::Scope<'s, 'e>,
    threads: usize,
    plan: &'e Plan,
    cases: &'e [Case],
    queue: &'e Queue,
    out: &'e Path,
    tx: &mpsc::Sender<Done>,
) {
    for _ in 0..threads {
        let tx = tx.clone();
        scope.spawn(move || {
            while let Some(i) = queue.next() {
                let row = compute(plan, &cases[i], out);
                if tx.send((i, row)).is_err() {
                    break;
                }
            }
        });
    }
}
