//! Line plots for reports and checks, drawn with `plotters`: SVG, and PNG through its
//! bitmap backend.
//!
//! What lives here: a [`Figure`] of one or more vertically stacked [`Panel`]s, each with a
//! title, axis labels (put the units in them), linear or logarithmic axes, a grid and any
//! number of [`Series`] drawn as lines, dashed lines or markers. Non-finite points (and, on
//! a log axis, points ≤ 0) are skipped: a line is broken there. The legend stands in its
//! own column to the right of the plot frame, so it never covers data. PNG text is drawn
//! with the DejaVu Sans font bundled in `framework/assets` (its licence beside it), so
//! rendering needs no system font library.

use plotters::coord::Shift;
use plotters::prelude::*;
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
    /// A small filled square at every point, no line (a second marker shape, e.g. for a
    /// peer code's points beside one's own circles).
    Squares,
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

/// Where the legend sits in its column beside the plot frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Corner {
    /// Level with the top of the frame (the default).
    #[default]
    TopRight,
    /// Level with the top of the frame (the column is always on the right).
    TopLeft,
    /// Level with the bottom of the frame.
    BottomRight,
    /// Level with the bottom of the frame.
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
    /// Vertical placement of the legend beside the frame.
    pub legend: Corner,
    /// Logarithmic x axis (decades; values ≤ 0 are not drawn).
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
}

impl Panel {
    /// An empty panel with a title and axis labels, linear axes.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            ..Default::default()
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Makes both axes logarithmic (builder style).
    pub fn log_log(mut self) -> Self {
        self.x_log = true;
        self.y_log = true;
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

/// Font family every text is drawn in (registered from the bundled file for PNG).
const FONT: &str = "sans-serif";

/// Registers the bundled DejaVu Sans under [`FONT`] for the text layout of both backends.
fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../assets/DejaVuSans.ttf");
        // The file is bundled and valid; a failure would show as missing text.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, bytes);
    });
}

/// An SVG colour (`"#1f77b4"` or one of a few names) as RGB; unknown names are black.
fn rgb(color: &str) -> RGBColor {
    let hex = |s: &str| u8::from_str_radix(s, 16).ok();
    if let Some(h) = color.strip_prefix('#').filter(|h| h.len() == 6) {
        if let (Some(r), Some(g), Some(b)) = (hex(&h[0..2]), hex(&h[2..4]), hex(&h[4..6])) {
            return RGBColor(r, g, b);
        }
    }
    match color {
        "red" => RGBColor(214, 39, 40),
        "blue" => RGBColor(31, 119, 180),
        "green" => RGBColor(44, 160, 44),
        "gray" | "grey" => RGBColor(127, 127, 127),
        "orange" => RGBColor(255, 127, 14),
        "white" => RGBColor(255, 255, 255),
        _ => RGBColor(0, 0, 0),
    }
}

/// Width of the legend column for `labels` (px): sample, gap, text at ~7 px a character.
fn legend_width(p: &Panel) -> u32 {
    let longest = p
        .series
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0);
    if longest == 0 {
        0
    } else {
        (48 + 7 * longest) as u32
    }
}

/// Fraction of the data's extent left free above and below the data on a linear y axis,
/// so that no line runs along the frame (a maximum that falls on a nice tick would).
const Y_HEADROOM: f64 = 0.03;

/// The data extent `values` widened by `fraction` of it at both ends (none for fewer than
/// two distinct finite values), never across zero: data that are all ≥ 0 (a radius, a
/// force magnitude) keep an axis starting at 0 at the latest, data all ≤ 0 one ending there.
fn with_headroom(values: &[f64], fraction: f64) -> Vec<f64> {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return values.to_vec();
    }
    let pad = fraction * (hi - lo);
    let (mut a, mut b) = (lo - pad, hi + pad);
    if lo >= 0.0 {
        a = a.max(0.0);
    }
    if hi <= 0.0 {
        b = b.min(0.0);
    }
    vec![a, b]
}

/// The decades `10^a ..= 10^b` of a log axis from `lo` to `hi` (themselves decades, from
/// [`axis_range`]), each parsed from its decimal text so that it is the double nearest the
/// power of ten; and the minor points `2·10^k … 9·10^k` between them. Plotters' own key
/// points start from `ceil(ln(lo)/ln 10)`, which round-off turns into the next decade
/// (`ln(1e-4)/ln(10) = −3.9999999999999996`), dropping the left-most label.
fn log_key_points(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let (a, b) = (lo.log10().round() as i32, hi.log10().round() as i32);
    let decade = |k: i32| format!("1e{k}").parse::<f64>().unwrap_or(f64::NAN);
    let bold: Vec<f64> = (a..=b).map(decade).collect();
    let light = (a..b)
        .flat_map(|k| (2..10).map(move |m| format!("{m}e{k}").parse::<f64>().unwrap_or(f64::NAN)))
        .collect();
    (bold, light)
}

/// Axis range of `values`: for a linear axis the outer "nice" ticks ([`nice_ticks`]), for
/// a log axis the enclosing decades of the positive values.
fn axis_range(values: &[f64], log: bool) -> (f64, f64) {
    if log {
        let pos: Vec<f64> = values.iter().copied().filter(|v| *v > 0.0).collect();
        let (lo, hi) = pos
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
        if !lo.is_finite() || hi <= 0.0 {
            return (0.1, 10.0);
        }
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        let b = if b <= a { a + 1.0 } else { b };
        (10f64.powf(a), 10f64.powf(b))
    } else {
        let t = nice_ticks(values, 8);
        (t[0], t[t.len() - 1])
    }
}

/// A tick label: up to six decimals with trailing zeros trimmed; scientific notation with
/// three significant digits outside 1e-3 ≤ |v| < 1e6.
fn tick_text(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e6).contains(&v.abs()) {
        // Three significant digits, trailing zeros of the mantissa trimmed: 1e-4, 2.5e7.
        let s = format!("{v:.2e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.')
        } else {
            m
        };
        return format!("{m}e{e}");
    }
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

type PlotResult<T> = Result<T, Box<dyn std::error::Error>>;

/// Draws one panel's frame, grid, labels and series in `area`, on the coordinate ranges
/// `xr`, `yr` (linear or log).
fn draw_chart<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    (xr, x_span): (X, f64),
    (yr, y_span): (Y, f64),
) -> PlotResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
    Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, (FONT, 16).into_font().style(FontStyle::Normal))
        .margin_right(12)
        .margin_left(6)
        .margin_top(6)
        .x_label_area_size(44)
        .y_label_area_size(78)
        .build_cartesian_2d(xr, yr)?;
    // Tick values come with round-off (−1.1e-16 for a zero tick): snap what is below a
    // billionth of the axis span to zero.
    let snap = |v: f64, span: f64| if v.abs() < 1e-9 * span { 0.0 } else { v };
    let fmt_x = |v: &f64| tick_text(snap(*v, x_span));
    let fmt_y = |v: &f64| tick_text(snap(*v, y_span));
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .max_light_lines(4)
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .x_label_formatter(&fmt_x)
        .y_label_formatter(&fmt_y)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 14))
        .x_labels(9)
        .y_labels(7)
        .draw()?;
    let (xlog, ylog) = (p.x_log, p.y_log);
    let ok =
        |x: f64, y: f64| x.is_finite() && y.is_finite() && (!xlog || x > 0.0) && (!ylog || y > 0.0);
    for r in &p.series {
        let c = rgb(&r.color);
        let pts = r.x.iter().zip(&r.y).map(|(&x, &y)| (x, y));
        match r.style {
            Style::Markers => {
                chart.draw_series(
                    pts.filter(|&(x, y)| ok(x, y))
                        .map(|xy| Circle::new(xy, 3, c.stroke_width(1))),
                )?;
            }
            Style::Squares => {
                chart.draw_series(pts.filter(|&(x, y)| ok(x, y)).map(|xy| {
                    EmptyElement::at(xy) + Rectangle::new([(-3, -3), (3, 3)], c.filled())
                }))?;
            }
            Style::Line | Style::Dashed => {
                // Runs of drawable points, each its own polyline.
                let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
                for (x, y) in pts {
                    if ok(x, y) {
                        runs.last_mut().expect("a run").push((x, y));
                    } else if !runs.last().expect("a run").is_empty() {
                        runs.push(Vec::new());
                    }
                }
                for run in runs.into_iter().filter(|r| r.len() > 1) {
                    if r.style == Style::Dashed {
                        chart.draw_series(DashedLineSeries::new(run, 6, 4, c.stroke_width(2)))?;
                    } else {
                        chart.draw_series(LineSeries::new(run, c.stroke_width(2)))?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Height (px) a panel needs for its legend: the box ([`draw_legend`]: 10 px plus 18 px a
/// labelled series) below the caption (30 px) and above the x labels (50 px).
fn legend_height(p: &Panel) -> u32 {
    let n = p.series.iter().filter(|r| !r.label.is_empty()).count() as u32;
    if n == 0 {
        0
    } else {
        30 + 10 + 18 * n + 50
    }
}

/// Draws the legend of `p` in its column `area` (pixel coordinates).
fn draw_legend<DB>(area: &DrawingArea<DB, Shift>, p: &Panel) -> PlotResult<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
{
    let labelled: Vec<&Series> = p.series.iter().filter(|r| !r.label.is_empty()).collect();
    if labelled.is_empty() {
        return Ok(());
    }
    let (w, h) = area.dim_in_pixel();
    let box_h = 10 + 18 * labelled.len() as i32;
    // Level with the top of the frame (below the caption) or with its bottom (above the
    // x labels).
    let top = match p.legend {
        Corner::TopRight | Corner::TopLeft => 30,
        Corner::BottomRight | Corner::BottomLeft => (h as i32 - 50 - box_h).max(30),
    };
    area.draw(&Rectangle::new(
        [(2, top), (w as i32 - 4, top + box_h)],
        RGBColor(160, 160, 160).stroke_width(1),
    ))?;
    for (k, r) in labelled.iter().enumerate() {
        let y = top + 14 + 18 * k as i32;
        let c = rgb(&r.color);
        match r.style {
            Style::Markers => area.draw(&Circle::new((20, y), 3, c.stroke_width(1)))?,
            Style::Squares => area.draw(&Rectangle::new([(17, y - 3), (23, y + 3)], c.filled()))?,
            Style::Line => {
                area.draw(&PathElement::new(vec![(8, y), (32, y)], c.stroke_width(2)))?
            }
            Style::Dashed => {
                area.draw(&PathElement::new(vec![(8, y), (16, y)], c.stroke_width(2)))?;
                area.draw(&PathElement::new(vec![(22, y), (32, y)], c.stroke_width(2)))?;
            }
        }
        area.draw(&Text::new(
            r.label.clone(),
            (38, y - 7),
            (FONT, 13).into_font(),
        ))?;
    }
    Ok(())
}

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

    /// Width and height (px): every panel as tall as `panel_height`, or as its legend
    /// needs ([`legend_height`]) when that is more, so a long legend is never cut.
    fn size(&self) -> (u32, u32) {
        let tallest = self
            .panels
            .iter()
            .map(|p| legend_height(p) as f64)
            .fold(self.panel_height, f64::max);
        (
            self.width.round() as u32,
            (tallest * self.panels.len().max(1) as f64).round() as u32,
        )
    }

    /// Draws every panel on `root`.
    fn draw<DB>(&self, root: DrawingArea<DB, Shift>) -> PlotResult<()>
    where
        DB: DrawingBackend,
        DB::ErrorType: 'static,
    {
        register_font();
        root.fill(&WHITE)?;
        let areas = root.split_evenly((self.panels.len().max(1), 1));
        // One legend column width for every panel, so the plot frames line up.
        let lw = self.panels.iter().map(legend_width).max().unwrap_or(0);
        for (p, area) in self.panels.iter().zip(areas) {
            let (w, _) = area.dim_in_pixel();
            let (chart, legend) = area.split_horizontally(w.saturating_sub(lw));
            let xs: Vec<f64> = p.series.iter().flat_map(|r| r.x.iter().copied()).collect();
            let ys: Vec<f64> = p.series.iter().flat_map(|r| r.y.iter().copied()).collect();
            let finite = |v: &[f64]| {
                v.iter()
                    .copied()
                    .filter(|v| v.is_finite())
                    .collect::<Vec<_>>()
            };
            let (x0, x1) = axis_range(&finite(&xs), p.x_log);
            let ys = finite(&ys);
            let (y0, y1) = if p.y_log {
                axis_range(&ys, true)
            } else {
                axis_range(&with_headroom(&ys, Y_HEADROOM), false)
            };
            let (sx, sy) = (x1 - x0, y1 - y0);
            let log = |lo: f64, hi: f64| {
                let (bold, light) = log_key_points(lo, hi);
                (lo..hi)
                    .log_scale()
                    .with_key_points(bold)
                    .with_light_points(light)
            };
            match (p.x_log, p.y_log) {
                (false, false) => draw_chart(&chart, p, (x0..x1, sx), (y0..y1, sy))?,
                (true, false) => draw_chart(&chart, p, (log(x0, x1), sx), (y0..y1, sy))?,
                (false, true) => draw_chart(&chart, p, (x0..x1, sx), (log(y0, y1), sy))?,
                (true, true) => draw_chart(&chart, p, (log(x0, x1), sx), (log(y0, y1), sy))?,
            }
            draw_legend(&legend, p)?;
        }
        root.present()?;
        Ok(())
    }

    /// The figure as SVG text.
    pub fn to_svg(&self) -> String {
        let mut s = String::new();
        {
            let root = SVGBackend::with_string(&mut s, self.size()).into_drawing_area();
            if let Err(e) = self.draw(root) {
                // Drawing into a string cannot fail on I/O; say what went wrong in the file.
                return format!("<svg xmlns=\"http://www.w3.org/2000/svg\"><!-- {e} --></svg>\n");
            }
        }
        s
    }

    /// Writes the figure as an SVG file.
    pub fn write_svg(&self, path: impl AsRef<Path>) -> io::Result<()> {
        std::fs::write(path, self.to_svg())
    }

    /// Writes the figure as SVG at `svg` and as PNG beside it (same name, `.png`): the
    /// vector file for documents, the raster one for viewers and slides.
    pub fn write_svg_and_png(&self, svg: impl AsRef<Path>) -> io::Result<()> {
        let svg = svg.as_ref();
        self.write_svg(svg)?;
        self.write_png(svg.with_extension("png"))
    }

    /// Writes the figure as a PNG file (the same drawing, rasterized with the bundled font).
    pub fn write_png(&self, path: impl AsRef<Path>) -> io::Result<()> {
        let root = BitMapBackend::new(path.as_ref(), self.size()).into_drawing_area();
        self.draw(root).map_err(|e| io::Error::other(e.to_string()))
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
        assert_eq!(tick_text(0.5), "0.5");
        assert_eq!(tick_text(2000.0), "2000");
        assert_eq!(tick_text(0.30000000000000004), "0.3");
        assert_eq!(tick_text(1e-5), "1e-5");
        assert_eq!(tick_text(2.5e7), "2.5e7");
    }

    #[test]
    fn log_axes_span_whole_decades_of_the_positive_data() {
        assert_eq!(axis_range(&[0.02, 3.0, -1.0, 0.0], true), (0.01, 10.0));
        assert_eq!(axis_range(&[1.0, 1.0], true), (1.0, 10.0));
        assert_eq!(axis_range(&[-1.0], true), (0.1, 10.0));
    }

    /// Every decade of a log axis is labelled, the left-most too: an x axis from 1e-4
    /// (where `ln(1e-4)/ln 10` rounds below −4) to 0.1 shows 1e-4, 0.001, 0.01 and 0.1.
    #[test]
    fn log_axes_label_their_first_decade() {
        let (bold, light) = log_key_points(1e-4, 0.1);
        assert_eq!(bold, vec![1e-4, 1e-3, 1e-2, 0.1]);
        assert_eq!(light.len(), 3 * 8);
        assert_eq!(light[0], 2e-4);
        let svg = Figure::new()
            .with(
                Panel::new("t", "error (-)", "time (s)")
                    .with(Series::new(
                        "a",
                        vec![2e-4, 5e-2],
                        vec![3.0, 40.0],
                        Style::Markers,
                        "red",
                    ))
                    .log_log(),
            )
            .to_svg();
        for label in ["1e-4", "0.001", "0.01", "0.1", "1", "10", "100"] {
            assert!(
                svg.contains(&format!("\n{label}\n</text>")),
                "tick {label} missing"
            );
        }
    }

    /// A linear y axis leaves room above and below the data: extremes on nice ticks
    /// (±10) are not the axis ends.
    #[test]
    fn linear_y_axes_leave_headroom() {
        let (lo, hi) = axis_range(&with_headroom(&[-10.0, 10.0], Y_HEADROOM), false);
        assert!(lo < -10.0 && hi > 10.0, "{lo} .. {hi}");
        // At most one tick step (5 for this range) beyond the data.
        assert!(hi <= 15.0 && lo >= -15.0, "{lo} .. {hi}");
        // One value (or none) stays as it is.
        assert_eq!(with_headroom(&[5.0, 5.0], Y_HEADROOM), vec![5.0, 5.0]);
        // Not across zero: positive data keep the axis at 0 and above.
        assert_eq!(
            axis_range(&with_headroom(&[0.0, 6e4], Y_HEADROOM), false).0,
            0.0
        );
        assert_eq!(
            axis_range(&with_headroom(&[-6e4, -10.0], Y_HEADROOM), false).1,
            0.0
        );
    }

    /// A panel with more legend entries than its height holds grows to hold them all.
    #[test]
    fn a_long_legend_makes_its_panel_taller() {
        let mut p = Panel::new("t", "x (m)", "y (m)");
        for k in 0..30 {
            p = p.with(Series::new(
                &format!("s{k}"),
                vec![0.0, 1.0],
                vec![0.0, 1.0],
                Style::Line,
                "red",
            ));
        }
        let f = Figure::new().with(p);
        let (_, h) = f.size();
        assert_eq!(h, 30 + 10 + 18 * 30 + 50);
        assert!(h as f64 > f.panel_height);
        // Short legends leave the default height.
        assert_eq!(sample().size(), (900, 680));
    }

    fn sample() -> Figure {
        Figure::new()
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
                        "#1f77b4",
                    )),
            )
            .with(
                Panel::new("b", "t (s)", "v (m/s)")
                    .with(Series::new(
                        "",
                        vec![0.1, 1., 2., 3.],
                        vec![1., f64::INFINITY, 2., 300.],
                        Style::Dashed,
                        "green",
                    ))
                    .log_log(),
            )
    }

    /// The SVG holds both titles (escaped), one circle per finite marker plus the legend's,
    /// no non-finite number, and log-axis tick labels at decades.
    #[test]
    fn svg_has_panels_series_legend_and_log_ticks() {
        let svg = sample().to_svg();
        assert!(
            svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
            "{svg}"
        );
        assert!(svg.contains("a &lt;b&gt;"));
        assert_eq!(svg.matches("<circle").count(), 2 + 1);
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        for decade in ["1", "10", "100", "1000"] {
            let label = format!("\n{decade}\n</text>");
            assert!(svg.contains(&label), "log tick {decade} missing");
        }
    }

    /// The legend column lies right of every data point: the legend's circle sample is
    /// further right than any marker of the data, and the legend's frame starts right of
    /// the plot frame.
    #[test]
    fn legend_stands_beside_the_data() {
        let svg = sample().to_svg();
        let cx: Vec<f64> = svg
            .split("<circle cx=\"")
            .skip(1)
            .map(|s| s[..s.find('"').unwrap()].parse().unwrap())
            .collect();
        assert_eq!(cx.len(), 3);
        let legend = cx.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let width = 900.0 - legend_width(&sample().panels[0]) as f64;
        assert!(
            legend > width,
            "legend sample at {legend} px, column from {width} px"
        );
        assert!(
            cx.iter().filter(|&&x| x < width).count() == 2,
            "data markers left of it"
        );
    }

    /// PNG through the bitmap backend and the bundled font: a valid PNG of the figure's
    /// size with more than background in it.
    #[test]
    fn png_is_written_with_the_bundled_font() {
        let dir = std::env::temp_dir().join(format!("railfem-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("f.png");
        sample().write_png(&p).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        assert_eq!((w, h), (900, 680));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
