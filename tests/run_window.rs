//! The activity window of `railfem run` (`[analysis.window]`, docs/model-format.md): a
//! windowed run of a model file against its full run, and the window off or left out
//! against a run without it, byte for byte.
//!
//! The model (`run_window/spans.rs`): a sprung mass crossing 12 spans whose supports are
//! clamped, so that the spans share no equation. A held span is then exactly what it is
//! in the full run as far as the mass is concerned, and the mass's contact force differs
//! between the two runs only by where each run's Newton iterations stop.

mod common;
#[path = "run_window/spans.rs"]
mod spans;

use common::{run_model_in, temp_dir, Csv};
use std::path::{Path, PathBuf};

/// Runs `railfem run` on `text` in a fresh directory; returns the output directory and
/// stdout. Panics when the run fails.
fn run(name: &str, text: &str) -> (PathBuf, String) {
    let (out, o) = run_model_in(&temp_dir(name), &format!("{name}.toml"), text);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    (out, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The largest |a − b| over the samples of column `col`, and the largest |a| (`from_start`:
/// of `a − a(0)`, the part the moving load causes).
fn largest_difference(a: &Csv, b: &Csv, col: &str, from_start: bool) -> (f64, f64) {
    let (x, y) = (a.column(col), b.column(col));
    assert_eq!(x.len(), y.len(), "{col}: sample counts");
    let x0 = if from_start { x[0] } else { 0.0 };
    let diff = x
        .iter()
        .zip(&y)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    let peak = x.iter().map(|p| (p - x0).abs()).fold(0.0, f64::max);
    (diff, peak)
}

/// The counters of the summary line `activity window: H of N block-steps held (…), J
/// blocks joined, L held behind`: `[H, N, J, L]`.
fn window_counters(stdout: &str) -> [usize; 4] {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("activity window: "))
        .unwrap_or_else(|| panic!("no window line in {stdout}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let num = |i: usize| words[i].parse::<usize>().expect("a count");
    [num(2), num(4), num(9), num(12)]
}

/// The window on, 15 m ahead, against the same model without it. Spans ahead of the mass
/// are held at the self-weight state the full run keeps them at; spans behind are held
/// once their interiors' velocity norm is below `tolerance` (1 %) of its peak.
///
/// Bounds. The contact force and the mass's displacement: within 1e-8 of their peaks.
/// Both runs solve the same equations for the span under the mass; each step's Newton
/// stops at a relative residual of `tol` = 1e-10, over all rows in the full run and over
/// the rows not held in the windowed one, so the converged states differ by that
/// tolerance times the conditioning of the span under the mass, which the bound allows
/// a factor 100. Midspan deflections: a span held behind keeps the displacement it had;
/// it is held once the velocity norm of its free, decaying vibration is below 1 % of its
/// largest, and for the vibration of one dominant mode (ω) the amplitude left, |v|/ω, is
/// then below 1 % of the largest dynamic amplitude, which is the bound on `w − w(0)`.
/// Spans never held behind are the full run's to round-off. The window has its default
/// absorbing layer (a third of the reach, 5 m, at 12.5 /s): it damps only spans the mass
/// is not on, which share no equation with the mass's span, so the bounds stay those of
/// the bare window (measured the same: contact force 1.7e-13 of its peak, midspans
/// 0.24 % for the first span and 0.054 % for the others).
#[test]
fn a_windowed_model_file_gives_the_full_runs_contact_force() {
    let window = "mode = \"on\"\nahead = 15.0\ntolerance = 0.01";
    let (full, _) = run("full", &spans::model(None, "partitioned", ""));
    let (on, stdout) = run("on", &spans::model(Some(window), "partitioned", ""));
    let [held, steps, joined, left] = window_counters(&stdout);
    // One block per span (block_size = 14 = the 7 interior nodes' uz, ry): the window
    // held some ahead and some behind.
    assert!(held > steps / 4 && held < steps, "held {held} of {steps}");
    assert_eq!(joined, spans::SPANS, "every span joined as the mass came");
    assert!(left >= spans::SPANS / 2, "{left} spans held behind");
    let read = |d: &Path, f: &str| Csv::read(&d.join(f));
    let (a, b) = (read(&full, "mass.csv"), read(&on, "mass.csv"));
    for col in ["1000_contact_force", "1000_mass_disp"] {
        let (diff, peak) = largest_difference(&a, &b, col, false);
        eprintln!("{col}: {diff:.3e} of {peak:.3e}");
        assert!(diff <= 1e-8 * peak, "{col}: {diff:e} of {peak:e}");
    }
    let (a, b) = (read(&full, "midspans.csv"), read(&on, "midspans.csv"));
    for k in 0..spans::SPANS {
        let col = format!("{}_uz", k * spans::ELEMENTS + spans::ELEMENTS / 2);
        let (diff, peak) = largest_difference(&a, &b, &col, true);
        eprintln!("{col}: {diff:.3e} of {peak:.3e}");
        assert!(diff <= 0.01 * peak, "{col}: {diff:e} of {peak:e}");
    }
}

/// `mode = "off"` runs the code of a model without the table: the same bytes in every
/// output file. So does `auto` where the window does not apply (here the direct solver),
/// which says so once in the summary.
#[test]
fn the_window_off_or_left_out_writes_the_bytes_of_a_run_without_it() {
    let files = ["mass.csv", "midspans.csv"];
    let same = |a: &Path, b: &Path, what: &str| {
        for f in files {
            let (x, y) = (std::fs::read(a.join(f)), std::fs::read(b.join(f)));
            assert_eq!(x.expect("written"), y.expect("written"), "{what}: {f}");
        }
    };
    let (none, _) = run("none", &spans::model(None, "partitioned", ""));
    let (off, stdout) = run(
        "off",
        &spans::model(Some("mode = \"off\""), "partitioned", ""),
    );
    same(&none, &off, "off");
    assert!(!stdout.contains("activity window"), "{stdout}");
    let (direct, _) = run("direct", &spans::model(None, "direct", ""));
    let (auto, stdout) = run("auto", &spans::model(Some("mode = \"auto\""), "direct", ""));
    same(&direct, &auto, "auto on the direct solver");
    let eq = spans::SPANS * (spans::ELEMENTS - 1) * 2 + 1;
    let line = format!("activity window (auto): off here: the window holds blocks of the partitioned solver, and `solver` = \"direct\" does not run it for this model's {eq} equations");
    assert_eq!(
        stdout
            .lines()
            .filter(|l| l.contains("activity window"))
            .collect::<Vec<_>>(),
        [line.as_str()],
        "{stdout}"
    );
}

/// A straight track of 100 m from the origin along +X: station `s` at `(s, 0, 0)`.
fn straight_track() -> railfem::elements::rail::geometry::cant::Track {
    use railfem::elements::rail::geometry::alignment::{Alignment, Segment};
    use railfem::elements::rail::geometry::cant::{Cant, Track};
    let al = Alignment::new(vec![Segment::Straight { length: 100.0 }]).expect("alignment");
    Track::new(al, Cant::none()).expect("track")
}

/// The extent of what moves, by hand. Ten 1 m beams from x = 0; a moving force from 1 m
/// along them at 2 m/s (`x = 1 + 2t`); a sprung mass standing at 0.5 m on them (attached
/// to the nodes at x = 0 and 1), its own node at x = 50 (attached to it alone, so not
/// counted); a carrier from station 10 at 5 m/s carrying nodes 3 m behind and 4 m ahead
/// (`x = 7 + 5t` and `14 + 5t`). At t = 0: [0, 14]; at t = 1.5: the mass at 0–1, the
/// force at 4, the carrier at 14.5–21.5: [0, 21.5]. Without the mass, [4, 21.5].
#[test]
fn the_extent_of_what_moves_by_hand() {
    use railfem::framework::builder::ModelBuilder;
    use railfem::framework::loads::LoadSpec;
    use railfem::framework::moving::Carrier;
    use railfem::framework::DofSet;
    let mut b = ModelBuilder::new("extent");
    for i in 0..=10u64 {
        b.node(i, [i as f64, 0.0, 0.0]);
    }
    let beam =
        serde_json::json!({"E": 2.1e11, "G": 8.1e10, "A": 1e-2, "Iy": 1e-4, "Iz": 1e-4, "J": 1e-4});
    for e in 1..=10u64 {
        b.element("beam3d", e, &[e - 1, e], &beam);
    }
    b.load(LoadSpec::MovingForce {
        elements: (1..=10).collect(),
        force: [0.0, 0.0, -1.0],
        speed: 2.0,
        start: 1.0,
    });
    b.node(100, [50.0, 0.0, 1.0]);
    b.element(
        "moving_sprung_mass",
        100,
        &[100],
        &serde_json::json!({"m": 1.0, "k": 1.0, "path": (1..=10).collect::<Vec<u64>>(), "start": 0.5}),
    );
    b.node_fixed(200, [0.0; 3], DofSet::ALL);
    b.node_fixed(201, [0.0; 3], DofSet::ALL);
    b.carrier(
        Carrier {
            name: "train".into(),
            path: std::sync::Arc::new(straight_track()),
            start: 10.0,
            speed: 5.0,
            accel: 0.0,
            speed_table: None,
            nodes: Vec::new(),
        },
        vec![(200, -3.0, [0.0; 3]), (201, 4.0, [0.0; 3])],
    );
    let model = b.build().expect("the model builds");
    // The track's positions are evaluated from its alignment: round-off of metres.
    let near = |got: Option<[f64; 2]>, want: [f64; 2]| {
        let g = got.expect("something moves");
        assert!(
            (g[0] - want[0]).abs() < 1e-9 && (g[1] - want[1]).abs() < 1e-9,
            "{g:?} against {want:?}"
        );
    };
    let movers = railfem::run_window::MovingExtent::new(&model);
    assert!(!movers.is_empty(&model));
    near(movers.extent(&model, 0.0), [0.0, 14.0]);
    near(movers.extent(&model, 1.5), [0.0, 21.5]);
    let mut model = model;
    model.elements.retain(|e| e.id != 100);
    let movers = railfem::run_window::MovingExtent::new(&model);
    near(movers.extent(&model, 1.5), [4.0, 21.5]);
}

/// `mode = "auto"` where the window applies runs it: the bytes of `mode = "on"`. Where the
/// partitioned solver makes no block (a block size above the model's equations), known
/// only once it has factored, `auto` stays off (the bytes of a run without the table)
/// and says why, once.
#[test]
fn auto_runs_the_window_where_it_applies_and_says_why_not_elsewhere() {
    let files = ["mass.csv", "midspans.csv"];
    let same = |a: &Path, b: &Path, what: &str| {
        for f in files {
            let (x, y) = (std::fs::read(a.join(f)), std::fs::read(b.join(f)));
            assert_eq!(x.expect("written"), y.expect("written"), "{what}: {f}");
        }
    };
    let (on, _) = run(
        "on",
        &spans::model(Some("mode = \"on\"\nahead = 15.0"), "partitioned", ""),
    );
    let (auto, stdout) = run(
        "auto",
        &spans::model(Some("mode = \"auto\"\nahead = 15.0"), "partitioned", ""),
    );
    same(&on, &auto, "auto where the window applies");
    assert!(stdout.contains("activity window: "), "{stdout}");
    let one_block = |t: String| t.replace("block_size = 14", "block_size = 100000");
    let (none, _) = run("none", &one_block(spans::model(None, "partitioned", "")));
    let (auto, stdout) = run(
        "auto",
        &one_block(spans::model(Some("mode = \"auto\""), "partitioned", "")),
    );
    same(&none, &auto, "auto without blocks");
    assert_eq!(
        stdout.lines().filter(|l| l.contains("activity window")).collect::<Vec<_>>(),
        ["activity window (auto): off here: the activity window needs the partitioned solver (solver = \"partitioned\") with at least one block"],
        "{stdout}"
    );
}

/// The last row of a run's energy ledger (`energy.csv`): `[external work, damping work,
/// integrator residual]` (J).
fn energy(out: &Path) -> [f64; 3] {
    let e = Csv::read(&out.join("energy.csv"));
    let last = |c: &str| *e.column(c).last().expect("a row");
    [last("external_work"), last("damping"), last("integrator")]
}

/// The absorbing layer (`layer`, `layer_damping`) in a model file. On a continuous beam
/// (30 spans of 10 m on pinned supports, so that its far end stays more than three times
/// the reach from the mass, where the structure's ends would keep every block active, `E·I` = 2.9e8 N·m²) the bending waves the mass
/// sends ahead run on, and a held span, a fixed wall, sends them back; with a reach of
/// 60 m they come back within the first second (the run's length). The default layer
/// (20 m, `α_max` = 50 /s, as `railfem train-bridge` has it) and no layer (`layer = 0`)
/// are compared with the full run.
///
/// Bounds. The contact force's largest difference to the full run: with the layer at most
/// 0.6 of that without it (measured 1.2e-3 and 3.1e-3 of the peak, a ratio of 0.40; the
/// ratio stays at 0.37–0.60 for reaches of 45–75 m). Energy: the layer's `α·M` is part of
/// `C`, so its work must show as damping work — the layer's run dissipates more in `C`
/// (measured 0.46 J more) — and not in the balance's residual, the integrator's share,
/// which is the window's own error here (Newmark's average acceleration leaves none on
/// this linear beam in the full run, `railfem_solvers::energy`): the layer's residual must
/// be no larger than that of the run without it (measured 6.2e-3 and 1.5e-2 J of 489 J
/// of external work). A layer whose work were lost from the ledger would add its 0.46 J
/// to the residual.
#[test]
fn the_absorbing_layer_takes_out_what_a_held_span_sends_back() {
    let window = |layer: &str| format!("mode = \"on\"\nahead = 60.0\n{layer}");
    let model = |w: Option<&str>| spans::continuous(w, 30, 0.01, 1.0);
    let (full, _) = run("full-continuous", &model(None));
    let (bare, _) = run("bare", &model(Some(&window("layer = 0.0"))));
    let (layer, stdout) = run("layer", &model(Some(&window(""))));
    let [held, steps, ..] = window_counters(&stdout);
    assert!(
        held > steps / 2,
        "held {held} of {steps}: nothing to reflect"
    );
    let f = |d: &Path| Csv::read(&d.join("mass.csv"));
    let col = "1000_contact_force";
    let (d_bare, peak) = largest_difference(&f(&full), &f(&bare), col, false);
    let (d_layer, _) = largest_difference(&f(&full), &f(&layer), col, false);
    eprintln!(
        "contact force: {:.3e} of the peak without the layer, {:.3e} with it (ratio {:.3})",
        d_bare / peak,
        d_layer / peak,
        d_layer / d_bare
    );
    assert!(d_layer <= 0.6 * d_bare, "{d_layer:e} vs {d_bare:e} N");
    let ([w, c_bare, r_bare], [_, c_layer, r_layer]) = (energy(&bare), energy(&layer));
    eprintln!(
        "damping work {c_bare:.6e} / {c_layer:.6e} J, integrator residual {r_bare:.3e} / {r_layer:.3e} J of {w:.3e} J"
    );
    assert!(c_layer > c_bare, "the layer took no energy out");
    assert!(
        r_layer.abs() <= r_bare.abs(),
        "residual {r_layer:e} vs {r_bare:e} J"
    );
}
