//! A model file for the activity window of `railfem run` (`[analysis.window]`): a sprung
//! mass crossing a row of spans whose supports are clamped (`fix = "all"`), so that the
//! spans share no equation. A span the mass is not on then feels nothing of it, and the
//! mass feels nothing of such a span: holding it changes nothing the mass sees, and a
//! windowed run solves the same equations for the span under the mass as the full run.
//!
//! [`continuous`] makes the other kind of row: the supports pinned (the beam's rotation
//! free), so that the spans make one continuous beam along which the bending waves the
//! mass sends run on, and a held span ahead sends them back (the absorbing layer's case).

/// Spans of the row.
pub const SPANS: usize = 12;
/// Span length (m).
pub const SPAN: f64 = 10.0;
/// Beam elements per span.
pub const ELEMENTS: usize = 8;
/// Speed of the sprung mass (m/s).
pub const SPEED: f64 = 25.0;

/// The model file's text: `window` is the `[analysis.window]` table's body (`None`: no
/// table), `solver` the `[analysis] solver`, `extra` appended at the end (a load, say).
pub fn model(window: Option<&str>, solver: &str, extra: &str) -> String {
    // The mass enters at 1 m and stops 1 m before the end of the path (leaving it is an
    // error).
    let duration = (SPANS as f64 * SPAN - 2.0) / SPEED;
    let row = Row {
        spans: SPANS,
        pinned: false,
        iy: 0.1,
        duration,
    };
    text(&row, window, solver, extra)
}

/// A continuous beam of `spans` spans on pinned supports, bending stiffness `E·iy`, on the
/// partitioned solver, run for `duration` s (the mass must stay on the path,
/// `duration < (10·spans − 2)/25`): the module documentation's other row.
#[allow(dead_code)]
pub fn continuous(window: Option<&str>, spans: usize, iy: f64, duration: f64) -> String {
    let row = Row {
        spans,
        pinned: true,
        iy,
        duration,
    };
    text(&row, window, "partitioned", "")
}

/// The row's layout: how many spans, the supports, the girders' second moment of area
/// about the bending axis (m⁴) and the run's length (s).
struct Row {
    spans: usize,
    pinned: bool,
    iy: f64,
    duration: f64,
}

/// The model file of `row` (see [`model`] for the rest); 2 ms steps.
fn text(row: &Row, window: Option<&str>, solver: &str, extra: &str) -> String {
    let n = row.spans * ELEMENTS;
    let h = SPAN / ELEMENTS as f64;
    let mut s = String::new();
    let duration = row.duration;
    let block = if solver == "partitioned" {
        "block_size = 14\n"
    } else {
        ""
    };
    s.push_str(&format!(
        "[analysis]\nkind = \"transient\"\ndt = 0.002\nduration = {duration}\ngravity = [0.0, 0.0, -9.81]\nsolver = \"{solver}\"\n{block}rayleigh = {{alpha = 0.5, beta = 1e-4}}\n\n[analysis.newton]\ntol = 1e-10\nabs_tol = 1e-9\n\n"
    ));
    if let Some(w) = window {
        s.push_str(&format!("[analysis.window]\n{w}\n\n"));
    }
    for i in 0..=n {
        // Every ELEMENTS-th node is a support, clamped (or pinned: the rotation ry free);
        // the others bend in the X-Z plane.
        let fix = if i % ELEMENTS == 0 && row.pinned {
            "[\"ux\", \"uy\", \"uz\", \"rx\", \"rz\"]".to_string()
        } else if i % ELEMENTS == 0 {
            "\"all\"".to_string()
        } else {
            "[\"ux\", \"uy\", \"rx\", \"rz\"]".to_string()
        };
        s.push_str(&format!(
            "[[node]]\nid = {i}\nxyz = [{}, 0.0, 0.0]\nfix = {fix}\n\n",
            i as f64 * h
        ));
    }
    s.push_str("[[node]]\nid = 1000\nxyz = [1.0, 0.0, 1.0]\nfix = [\"ux\", \"uy\", \"rx\", \"ry\", \"rz\"]\n\n");
    for e in 1..=n {
        s.push_str(&format!(
            "[[element]]\ntype = \"beam3d\"\nid = {e}\nnodes = [{}, {e}]\nE = 2.943e10\nG = 1.2e10\nA = 1.0\nIy = {}\nIz = 2.0\nJ = 0.5\nrho = 2303.0\nmass = \"consistent\"\n\n",
            e - 1,
            row.iy
        ));
    }
    let path: Vec<String> = (1..=n).map(|e| e.to_string()).collect();
    s.push_str(&format!(
        "[[element]]\ntype = \"moving_sprung_mass\"\nid = 1000\nnodes = [1000]\nm = 5750.0\nk = 1.595e6\nc = 2.0e4\npath = [{}]\nstart = 1.0\nspeed = {SPEED}\n\n",
        path.join(", ")
    ));
    s.push_str("[[recorder]]\ntype = \"element\"\nelement = 1000\noutputs = [\"station\", \"contact_force\", \"mass_disp\"]\nfile = \"mass.csv\"\n\n");
    let mids: Vec<String> = (0..row.spans)
        .map(|k| (k * ELEMENTS + ELEMENTS / 2).to_string())
        .collect();
    s.push_str(&format!(
        "[[recorder]]\ntype = \"node\"\nnodes = [{}]\ndofs = [\"uz\"]\nfile = \"midspans.csv\"\n\n",
        mids.join(", ")
    ));
    s.push_str(extra);
    s
}
