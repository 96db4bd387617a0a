//! A tiny, dependency-free SVG line-plot writer for reports and checks.
//!
//! What lives here: a [`Figure`] of one or more vertically stacked [`Panel`]s, each with a
//! title, axis labels (put the units in them), auto-ranged "nice" ticks, a grid, a legend and
//! any number of [`Series`] drawn as lines, dashed lines or markers. Non-finite points are
//! skipped (a line is broken there). The output is plain SVG 1.1 text.

use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A solid polyline.
    Line,
    /// A dashed polyline.
    Dashed,
    /// A small circle at every point, no line.
    Markers,
}

/// One data series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Abscissae (in the panel's x units).
    pub x: Vec<f64>,
    /// Ordinates (in the panel's y units); same length as `x`.
    pub y: Vec<f64>,
    /// Drawing style.
    pub style: Style,
    /// Any SVG colour (`"#1f77b4"`, `"black"`).
    pub color: String,
}

impl Series {
    /// A series from its parts.
    pub fn new(label: &str, x: Vec<f64>, y: Vec<f64>, style: Style, color: &str) -> Self {
        Self {
            label: label.to_string(),
            x,
            y,
            style,
            color: color.to_string(),
        }
    }
}

/// Whether series `r`, drawn through the pixel maps `px`, `py`, puts anything inside the
/// rectangle `(left, top, right, bottom)` (px): a marker whose centre lies in it, or a line
/// segment that crosses it (Liang–Barsky clipping of each segment).
fn covers(
    r: &Series,
    px: &dyn Fn(f64) -> f64,
    py: &dyn Fn(f64) -> f64,
    (l, t, rr, b): (f64, f64, f64, f64),
) -> bool {
    let inside = |x: f64, y: f64| x >= l && x <= rr && y >= t && y <= b;
    let pts: Vec<(f64, f64)> =
        r.x.iter()
            .zip(&r.y)
            .map(|(&x, &y)| (px(x), py(y)))
            .collect();
    if r.style == Style::Markers {
        return pts
            .iter()
            .any(|&(x, y)| x.is_finite() && y.is_finite() && inside(x, y));
    }
    pts.windows(2).any(|w| {
        let ((xa, ya), (xb, yb)) = (w[0], w[1]);
        if ![xa, ya, xb, yb].iter().all(|v| v.is_finite()) {
            return false;
        }
        let (dx, dy) = (xb - xa, yb - ya);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [(-dx, xa - l), (dx, rr - xa), (-dy, ya - t), (dy, b - ya)] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let u = q / p;
                if p < 0.0 {
                    t0 = t0.max(u);
                } else {
                    t1 = t1.min(u);
                }
            }
        }
        t0 <= t1
    })
}

/// Where a panel's legend box goes (inside the plot frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Corner {
    /// Top right (the default).
    #[default]
    TopRight,
    /// Top left.
    TopLeft,
    /// Bottom right.
    BottomRight,
    /// Bottom left.
    BottomLeft,
}

/// One plot area with its axes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Title drawn above the panel.
    pub title: String,
    /// Label of the x axis, with units (`"station s (m)"`).
    pub x_label: String,
    /// Label of the y axis, with units.
    pub y_label: String,
    /// The series drawn, in order (later ones on top).
    pub series: Vec<Series>,
    /// Corner of the legend box.
    pub legend: Corner,
}

impl Panel {
    /// An empty panel with a title and axis labels.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            series: Vec::new(),
            legend: Corner::TopRight,
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
}

/// A picture made of stacked panels.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Width of the picture (px).
    pub width: f64,
    /// Height of each panel including its margins (px).
    pub panel_height: f64,
    /// The panels, top to bottom.
    pub panels: Vec<Panel>,
}

impl Default for Figure {
    fn default() -> Self {
        Self {
            width: 900.0,
            panel_height: 340.0,
            panels: Vec::new(),
        }
    }
}

const MARGIN_LEFT: f64 = 80.0;
const MARGIN_RIGHT: f64 = 20.0;
const MARGIN_TOP: f64 = 34.0;
const MARGIN_BOTTOM: f64 = 50.0;

impl Figure {
    /// An empty figure of the default size (900 px wide, 340 px per panel).
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a panel below the others (builder style).
    pub fn with(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }

    /// The figure as SVG text.
    pub fn to_svg(&self) -> String {
        let height = self.panel_height * self.panels.len().max(1) as f64;
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{height}" viewBox="0 0 {w} {height}" font-family="sans-serif" font-size="12">"#,
            w = self.width
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        for (i, panel) in self.panels.iter().enumerate() {
            self.panel_svg(&mut s, panel, i as f64 * self.panel_height);
        }
        s.push_str("</svg>\n");
        s
    }

    /// Writes the figure as an SVG file.
    pub fn write_svg(&self, path: impl AsRef<Path>) -> io::Result<()> {
        std::fs::write(path, self.to_svg())
    }

    fn panel_svg(&self, s: &mut String, p: &Panel, top: f64) {
        let (x0, x1) = (MARGIN_LEFT, self.width - MARGIN_RIGHT);
        let (y0, y1) = (top + MARGIN_TOP, top + self.panel_height - MARGIN_BOTTOM);
        let finite = |v: &[f64]| {
            v.iter()
                .copied()
                .filter(|v| v.is_finite())
                .collect::<Vec<_>>()
        };
        let xs: Vec<f64> = p.series.iter().flat_map(|r| finite(&r.x)).collect();
        let ys: Vec<f64> = p.series.iter().flat_map(|r| finite(&r.y)).collect();
        let xt = nice_ticks(&xs, 8);
        let mut yt = nice_ticks(&ys, 6);
        let (xlo, xhi) = (xt[0], xt[xt.len() - 1]);
        let px = |x: f64| x0 + (x - xlo) / (xhi - xlo) * (x1 - x0);
        // The legend goes where it covers no data: the preferred corner if it is free, else
        // the first free one; if every corner holds data, the y axis gains a tick of
        // headroom above the data (up to six) until a top corner is free.
        let labelled: Vec<&Series> = p.series.iter().filter(|r| !r.label.is_empty()).collect();
        let longest = labelled
            .iter()
            .map(|r| r.label.chars().count())
            .max()
            .unwrap_or(0);
        let (lw, lh) = (
            40.0 + 7.0 * longest as f64,
            8.0 + 16.0 * labelled.len() as f64,
        );
        let legend_box = |corner: Corner| {
            let lx = match corner {
                Corner::TopRight | Corner::BottomRight => x1 - lw - 8.0,
                Corner::TopLeft | Corner::BottomLeft => x0 + 8.0,
            };
            let ly = match corner {
                Corner::TopRight | Corner::TopLeft => y0 + 8.0,
                Corner::BottomRight | Corner::BottomLeft => y1 - lh - 8.0,
            };
            (lx, ly)
        };
        let mut corner = p.legend;
        for extra in 0..=6 {
            let (ylo, yhi) = (yt[0], yt[yt.len() - 1]);
            let py = |y: f64| y1 - (y - ylo) / (yhi - ylo) * (y1 - y0);
            let free = |c: Corner| {
                let (lx, ly) = legend_box(c);
                !p.series
                    .iter()
                    .any(|r| covers(r, &px, &py, (lx, ly, lx + lw, ly + lh)))
            };
            let order = [
                p.legend,
                Corner::TopRight,
                Corner::TopLeft,
                Corner::BottomRight,
                Corner::BottomLeft,
            ];
            if labelled.is_empty() {
                break;
            }
            if let Some(c) = order.into_iter().find(|&c| free(c)) {
                corner = c;
                break;
            }
            if extra == 6 || yt.len() < 2 {
                break;
            }
            let step = yt[1] - yt[0];
            yt.push(yhi + step);
            corner = match p.legend {
                Corner::BottomLeft | Corner::TopLeft => Corner::TopLeft,
                _ => Corner::TopRight,
            };
        }
        let (ylo, yhi) = (yt[0], yt[yt.len() - 1]);
        let py = |y: f64| y1 - (y - ylo) / (yhi - ylo) * (y1 - y0);
        // Title, frame, grid and tick labels.
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="14" font-weight="bold">{}</text>"#,
            (x0 + x1) / 2.0,
            top + 20.0,
            escape(&p.title)
        );
        for &t in &xt {
            let x = px(t);
            let _ = writeln!(
                s,
                r##"<line x1="{x:.1}" y1="{y0:.1}" x2="{x:.1}" y2="{y1:.1}" stroke="#ddd"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
                y1 + 16.0,
                tick_label(t, &xt)
            );
        }
        for &t in &yt {
            let y = py(t);
            let _ = writeln!(
                s,
                r##"<line x1="{x0:.1}" y1="{y:.1}" x2="{x1:.1}" y2="{y:.1}" stroke="#ddd"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
                x0 - 6.0,
                y + 4.0,
                tick_label(t, &yt)
            );
        }
        let _ = writeln!(
            s,
            r#"<rect x="{x0:.1}" y="{y0:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="black"/>"#,
            x1 - x0,
            y1 - y0
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            (x0 + x1) / 2.0,
            y1 + 36.0,
            escape(&p.x_label)
        );
        let (lx, ly) = (18.0, (y0 + y1) / 2.0);
        let _ = writeln!(
            s,
            r#"<text x="{lx:.1}" y="{ly:.1}" text-anchor="middle" transform="rotate(-90 {lx:.1} {ly:.1})">{}</text>"#,
            escape(&p.y_label)
        );
        // Data.
        for r in &p.series {
            let pts = r.x.iter().zip(&r.y).map(|(&x, &y)| (x, y));
            match r.style {
                Style::Markers => {
                    for (x, y) in pts.filter(|(x, y)| x.is_finite() && y.is_finite()) {
                        let _ = writeln!(
                            s,
                            r#"<circle cx="{:.2}" cy="{:.2}" r="3" fill="none" stroke="{}"/>"#,
                            px(x),
                            py(y),
                            r.color
                        );
                    }
                }
                Style::Line | Style::Dashed => {
                    let dash = if r.style == Style::Dashed {
                        r#" stroke-dasharray="6 4""#
                    } else {
                        ""
                    };
                    // Split into runs of finite points.
                    let mut run: Vec<String> = Vec::new();
                    let flush = |run: &mut Vec<String>, s: &mut String| {
                        if run.len() > 1 {
                            let _ = writeln!(
                                s,
                                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"{dash}/>"#,
                                run.join(" "),
                                r.color
                            );
                        }
                        run.clear();
                    };
                    for (x, y) in pts {
                        if x.is_finite() && y.is_finite() {
                            run.push(format!("{:.2},{:.2}", px(x), py(y)));
                        } else {
                            flush(&mut run, s);
                        }
                    }
                    flush(&mut run, s);
                }
            }
        }
        // Legend, in the corner chosen above (inside the frame, off the data).
        if !labelled.is_empty() {
            let (w, h) = (lw, lh);
            let (lx, ly) = legend_box(corner);
            let _ = writeln!(
                s,
                r#"<rect x="{lx:.1}" y="{ly:.1}" width="{w:.1}" height="{h:.1}" fill="white" fill-opacity="0.85" stroke="gray"/>"#
            );
            for (k, r) in labelled.iter().enumerate() {
                let yy = ly + 14.0 + 16.0 * k as f64;
                let sample = match r.style {
                    Style::Markers => format!(
                        r#"<circle cx="{:.1}" cy="{:.1}" r="3" fill="none" stroke="{}"/>"#,
                        lx + 16.0,
                        yy - 4.0,
                        r.color
                    ),
                    _ => format!(
                        r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="1.5"{}/>"#,
                        lx + 6.0,
                        yy - 4.0,
                        lx + 26.0,
                        yy - 4.0,
                        r.color,
                        if r.style == Style::Dashed {
                            r#" stroke-dasharray="6 4""#
                        } else {
                            ""
                        }
                    ),
                };
                let _ = writeln!(
                    s,
                    r#"{sample}<text x="{:.1}" y="{yy:.1}">{}</text>"#,
                    lx + 32.0,
                    escape(&r.label)
                );
            }
        }
    }
}

/// "Nice" tick values (steps of 1, 2, 2.5 or 5 times a power of ten) covering all `values`,
/// about `target` intervals; the first and last ticks are the axis limits.
pub fn nice_ticks(values: &[f64], target: usize) -> Vec<f64> {
    let (mut lo, mut hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() || !hi.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()) {
        let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        (lo, hi) = (lo - pad, hi + pad);
    }
    let raw = (hi - lo) / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|&st| st >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * mag);
    let first = (lo / step + 1e-9).floor() as i64;
    let last = (hi / step - 1e-9).ceil() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Formats a tick value with as many decimals as the tick step needs.
fn tick_label(v: f64, ticks: &[f64]) -> String {
    let step = if ticks.len() > 1 {
        ticks[1] - ticks[0]
    } else {
        1.0
    };
    let big = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    if !(1e-3..1e6).contains(&big) {
        return format!("{v:.2e}");
    }
    let decimals = (-(step.log10().floor()) + 1.0).max(0.0) as usize;
    let mut s = format!("{v:.decimals$}");
    if s.contains('.') {
        // Trim trailing zeros the step does not need.
        let need = (0..=decimals)
            .find(|&d| {
                ((step * 10f64.powi(d as i32)).round() - step * 10f64.powi(d as i32)).abs() < 1e-6
            })
            .unwrap_or(decimals);
        s = format!("{v:.need$}");
    }
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s.remove(0);
    }
    s
}

/// Escapes the XML special characters of a text.
fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_cover_the_data() {
        let t = nice_ticks(&[0.3, 16208.3], 8);
        assert_eq!(t[0], 0.0);
        assert!(*t.last().unwrap() >= 16208.3);
        let step = t[1] - t[0];
        assert_eq!(step, 2500.0); // 16208/8 = 2026 rounds up to 2.5e3
        let t = nice_ticks(&[-0.0012, 0.0347], 6);
        assert!(t[0] <= -0.0012 && *t.last().unwrap() >= 0.0347);
        assert!((t[1] - t[0] - 0.01).abs() < 1e-15);
        // Degenerate ranges still give an axis.
        assert!(nice_ticks(&[5.0, 5.0], 6).len() >= 2);
        assert!(nice_ticks(&[], 6).len() >= 2);
        assert_eq!(tick_label(0.5, &[0.0, 0.5, 1.0]), "0.5");
        assert_eq!(tick_label(2000.0, &[0.0, 2000.0]), "2000");
    }

    #[test]
    fn svg_has_panels_series_and_legend() {
        let fig = Figure::new()
            .with(
                Panel::new("a <b>", "x (m)", "y (m)")
                    .with(Series::new(
                        "line",
                        vec![0., 1., 2.],
                        vec![0., 1., 4.],
                        Style::Line,
                        "red",
                    ))
                    .with(Series::new(
                        "dots",
                        vec![0., 1., f64::NAN],
                        vec![1., 2., 3.],
                        Style::Markers,
                        "blue",
                    )),
            )
            .with(Panel::new("b", "t (s)", "v").with(Series::new(
                "",
                vec![0., 1., 2., 3.],
                vec![1., f64::INFINITY, 2., 3.],
                Style::Dashed,
                "green",
            )));
        let svg = fig.to_svg();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt;b&gt;"));
        assert_eq!(svg.matches("<circle").count(), 2 + 1); // 2 points + legend sample
        assert_eq!(svg.matches("stroke-dasharray").count(), 1); // one run of 2 points
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    /// Liang–Barsky: a segment that crosses the rectangle with both ends outside covers it;
    /// one that passes beside it, or a marker outside it, does not.
    #[test]
    fn coverage_of_a_rectangle_by_segments_and_markers() {
        let id = |v: f64| v;
        let rect = (10.0, 10.0, 20.0, 20.0);
        let line = |x: Vec<f64>, y: Vec<f64>| Series::new("", x, y, Style::Line, "red");
        assert!(covers(
            &line(vec![0.0, 30.0], vec![15.0, 15.0]),
            &id,
            &id,
            rect
        ));
        assert!(covers(
            &line(vec![0.0, 30.0], vec![0.0, 30.0]),
            &id,
            &id,
            rect
        ));
        assert!(!covers(
            &line(vec![0.0, 30.0], vec![25.0, 25.0]),
            &id,
            &id,
            rect
        ));
        assert!(!covers(
            &line(vec![0.0, 9.0], vec![0.0, 30.0]),
            &id,
            &id,
            rect
        ));
        let dots = |x: Vec<f64>, y: Vec<f64>| Series::new("", x, y, Style::Markers, "blue");
        assert!(covers(&dots(vec![15.0], vec![12.0]), &id, &id, rect));
        assert!(!covers(
            &dots(vec![5.0, 25.0], vec![15.0, 15.0]),
            &id,
            &id,
            rect
        ));
    }

    /// The legend box (the only rect with `fill-opacity`) of the first panel: (x, y, w, h).
    fn legend_rect(svg: &str) -> (f64, f64, f64, f64) {
        let line = svg
            .lines()
            .find(|l| l.contains("fill-opacity"))
            .expect("a legend");
        let attr = |k: &str| -> f64 {
            let a = line.find(&format!(" {k}=\"")).expect(k) + k.len() + 3;
            line[a..a + line[a..].find('"').expect("quote")]
                .parse()
                .expect("number")
        };
        (attr("x"), attr("y"), attr("width"), attr("height"))
    }

    /// A rising line fills the top-right corner: the legend moves to the top left, where
    /// the line is low. Lines in all four corners: the y axis gains headroom instead, and
    /// the legend lies above every point of the data.
    #[test]
    fn legend_never_covers_data() {
        let rising = Panel::new("p", "x (m)", "y (m)").with(Series::new(
            "rising",
            (0..=100).map(|i| i as f64).collect(),
            (0..=100).map(|i| i as f64).collect(),
            Style::Line,
            "red",
        ));
        let fig = Figure::new().with(rising);
        let (x, _, _, _) = legend_rect(&fig.to_svg());
        assert_eq!(x, MARGIN_LEFT + 8.0, "top left expected");
        // Two horizontal lines near the top and the bottom of the range cross every corner's
        // box (a line right on the frame's edge would pass beside it).
        let full = Panel::new("p", "x (m)", "y (m)")
            .with(Series::new(
                "top",
                vec![0.0, 100.0],
                vec![95.0, 95.0],
                Style::Line,
                "red",
            ))
            .with(Series::new(
                "bottom",
                vec![0.0, 100.0],
                vec![5.0, 5.0],
                Style::Line,
                "blue",
            ));
        let fig = Figure::new().with(full);
        let svg = fig.to_svg();
        let (_, y, _, h) = legend_rect(&svg);
        // The y of the data's top line, read back from its polyline.
        let top = svg
            .lines()
            .find(|l| l.contains("<polyline") && l.contains("red"))
            .and_then(|l| l.split("points=\"").nth(1))
            .and_then(|p| p.split(' ').next())
            .and_then(|p| p.split(',').nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .expect("top line");
        assert!(
            y + h < top,
            "legend {y}+{h} must lie above the data at {top}"
        );
    }
}
