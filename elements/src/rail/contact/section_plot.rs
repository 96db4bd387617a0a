//! A cross-section picture of one wheel on its rail: the wheel and rail profiles of a
//! [`MovingAxle`] in their displaced positions at the element's current (trial) state, with
//! the contact points marked by mode, as plain SVG (no dependencies).
//!
//! The picture is drawn in the wheel frame's cross-section plane with axis 1 (to the left
//! of the direction of travel) to the right of the page and axis 2 up, i.e. as seen from
//! ahead of the wheel looking back along the track, in millimetres,
//! relative to B's reference position (the wheel's nominal contact point). The rail is drawn
//! at its reference place and the wheel is moved by its rigid motion relative to the rail
//! ([`MovingAxle::relative_motion`]): only the relative position matters for contact, and
//! it is exact for rigid and flexible rails alike. Penetrations of micrometres do not show
//! at this scale; the markers say where the contact is.
//!
//! Contact points (rail profile nodes inside the wheel) are marked at the rail node: a
//! green circle when sticking, a red square when sliding. Each marker carries
//! `class="contact stick"` or `class="contact slide"`, so a test can count them.

use crate::rail::contact::contact_law::Mode;
use crate::rail::wheels::moving_axle::MovingAxle;
use nalgebra::Vector2;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// Size of the picture (px).
const WIDTH: f64 = 720.0;
const HEIGHT: f64 = 480.0;
const MARGIN: f64 = 60.0;

/// Counts of what a picture shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SectionSummary {
    /// Sticking contact points drawn.
    pub stick: usize,
    /// Sliding contact points drawn.
    pub slide: usize,
}

fn nice_step(span: f64) -> f64 {
    let raw = span / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0] {
        if m * mag >= raw {
            return m * mag;
        }
    }
    10.0 * mag
}

/// The SVG text of the cross-section of `axle` at its current state, and what it shows.
/// `title` is written above the picture.
pub fn section_svg(axle: &MovingAxle, title: &str) -> (String, SectionSummary) {
    let (wheel, rail, c_rel_b) = axle.profiles();
    let (d, roll) = axle.relative_motion();
    // Wheel points moved rigidly relative to the rail, about C.
    let moved = |x: &Vector2<f64>| -> Vector2<f64> {
        let rho = x - c_rel_b;
        x + d + Vector2::new(-rho.y, rho.x) * roll
    };
    let wheel: Vec<Vector2<f64>> = wheel.iter().map(moved).map(|p| p * 1e3).collect();
    let rail: Vec<Vector2<f64>> = rail.iter().map(|p| (p + c_rel_b) * 1e3).collect();
    // Range: the rail head and the part of the wheel above it (clip the wheel to the rail's
    // lateral extent plus a margin so the flange shows).
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in rail.iter().chain(wheel.iter()) {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    // Equal scales on both axes (a true section).
    let (wx, wy) = (WIDTH - 2.0 * MARGIN, HEIGHT - 2.0 * MARGIN);
    // 5 % padding so nothing touches the frame.
    let scale = (wx / (1.05 * (x1 - x0))).min(wy / (1.05 * (y1 - y0)));
    let cx = 0.5 * (x0 + x1);
    let cy = 0.5 * (y0 + y1);
    let px = |x: f64| WIDTH / 2.0 + (x - cx) * scale;
    let py = |y: f64| HEIGHT / 2.0 - (y - cy) * scale;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="20" text-anchor="middle" font-size="14">{}</text>"#,
        WIDTH / 2.0,
        escape(title)
    );
    // Grid and ticks in mm.
    let (gx0, gx1) = ((cx - wx / 2.0 / scale), (cx + wx / 2.0 / scale));
    let (gy0, gy1) = ((cy - wy / 2.0 / scale), (cy + wy / 2.0 / scale));
    let step = nice_step((gx1 - gx0).max(gy1 - gy0));
    let mut t = (gx0 / step).ceil() * step;
    while t <= gx1 {
        let x = px(t);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.2}" y1="{:.2}" x2="{x:.2}" y2="{:.2}" stroke="#e0e0e0"/><text x="{x:.2}" y="{:.2}" text-anchor="middle">{}</text>"##,
            py(gy0),
            py(gy1),
            py(gy0) + 16.0,
            fmt_tick(t)
        );
        t += step;
    }
    let mut t = (gy0 / step).ceil() * step;
    while t <= gy1 {
        let y = py(t);
        let _ = writeln!(
            s,
            r##"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="#e0e0e0"/><text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"##,
            px(gx0),
            px(gx1),
            px(gx0) - 6.0,
            y + 4.0,
            fmt_tick(t)
        );
        t += step;
    }
    let _ = writeln!(
        s,
        r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="#404040"/>"##,
        px(gx0),
        py(gy1),
        px(gx1) - px(gx0),
        py(gy0) - py(gy1)
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">lateral, wheel-frame axis 1 (mm)</text>"#,
        WIDTH / 2.0,
        HEIGHT - 12.0
    );
    let _ = writeln!(
        s,
        r#"<text x="16" y="{}" text-anchor="middle" transform="rotate(-90 16 {})">vertical, axis 2 (mm)</text>"#,
        HEIGHT / 2.0,
        HEIGHT / 2.0
    );
    // Profiles.
    let poly = |pts: &[Vector2<f64>]| -> String {
        pts.iter()
            .map(|p| format!("{:.2},{:.2}", px(p.x), py(p.y)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let _ = writeln!(
        s,
        r##"<polyline class="rail" points="{}" fill="none" stroke="#555555" stroke-width="1.5"/>"##,
        poly(&rail)
    );
    for p in &rail {
        let _ = writeln!(
            s,
            r##"<circle cx="{:.2}" cy="{:.2}" r="1.5" fill="#555555"/>"##,
            px(p.x),
            py(p.y)
        );
    }
    let _ = writeln!(
        s,
        r##"<polyline class="wheel" points="{}" fill="none" stroke="#1f77b4" stroke-width="1.5"/>"##,
        poly(&wheel)
    );
    // Contact points at their rail nodes.
    let mut summary = SectionSummary::default();
    for (k, st, _, _) in axle.contact_points() {
        let p = rail[k];
        let (x, y) = (px(p.x), py(p.y));
        match st.mode {
            Mode::Stick => {
                summary.stick += 1;
                let _ = writeln!(
                    s,
                    r##"<circle class="contact stick" cx="{x:.2}" cy="{y:.2}" r="5" fill="none" stroke="#2ca02c" stroke-width="2"><title>stick, f_n = {:.1} N</title></circle>"##,
                    st.f_n
                );
            }
            Mode::Slide => {
                summary.slide += 1;
                let _ = writeln!(
                    s,
                    r##"<rect class="contact slide" x="{:.2}" y="{:.2}" width="9" height="9" fill="none" stroke="#d62728" stroke-width="2"><title>slide, f_n = {:.1} N</title></rect>"##,
                    x - 4.5,
                    y - 4.5,
                    st.f_n
                );
            }
            Mode::Open => {}
        }
    }
    // Legend.
    let lx = px(gx0) + 10.0;
    let ly = py(gy1) + 16.0;
    let _ = writeln!(
        s,
        r##"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="#1f77b4" stroke-width="1.5"/><text x="{}" y="{}">wheel (displaced)</text>"##,
        lx + 24.0,
        lx + 30.0,
        ly + 4.0
    );
    let ly = ly + 18.0;
    let _ = writeln!(
        s,
        r##"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="#555555" stroke-width="1.5"/><text x="{}" y="{}">rail (profile nodes)</text>"##,
        lx + 24.0,
        lx + 30.0,
        ly + 4.0
    );
    let ly = ly + 18.0;
    let _ = writeln!(
        s,
        r##"<circle cx="{}" cy="{ly}" r="5" fill="none" stroke="#2ca02c" stroke-width="2"/><text x="{}" y="{}">stick ({})</text>"##,
        lx + 12.0,
        lx + 30.0,
        ly + 4.0,
        summary.stick
    );
    let ly = ly + 18.0;
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="9" height="9" fill="none" stroke="#d62728" stroke-width="2"/><text x="{}" y="{}">slide ({})</text>"##,
        lx + 7.5,
        ly - 4.5,
        lx + 30.0,
        ly + 4.0,
        summary.slide
    );
    s.push_str("</svg>\n");
    (s, summary)
}

/// Writes [`section_svg`] to `path`.
pub fn write_section_svg(
    axle: &MovingAxle,
    title: &str,
    path: &Path,
) -> io::Result<SectionSummary> {
    let (s, summary) = section_svg(axle, title);
    std::fs::write(path, s)?;
    Ok(summary)
}

fn fmt_tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        format!("{r}")
    }
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
