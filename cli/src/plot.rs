//! SVG figures (plotters' SVG backend, rendered to a string).
//!
//! Fonts: plotters is built without its `ttf` feature, so it uses its
//! built-in "naive" font, which only *estimates* text extents for layout;
//! the SVG backend writes text as `<text>` elements that the viewer
//! renders with its own fonts. No system font is needed at build or run
//! time, and labels, titles and legends work.
//!
//! A figure is a grid of [`Panel`]s, each with line or marker [`Series`].
//! Lines are thinned before drawing (points closer than about a pixel to
//! the last kept one are dropped; a few pixels for wide lines), which keeps
//! files small and avoids pixel-rounding zig-zags.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt;

/// An error while drawing a figure.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("drawing failed: {0}")]
pub struct PlotError(pub String);

fn err<E: fmt::Debug>(e: E) -> PlotError {
    PlotError(crate::csvio::one_line(&format!("{e:?}")))
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A polyline through the points.
    Line,
    /// A thick polyline (for emphasis).
    ThickLine,
    /// A wide translucent polyline, for a reference curve that thinner
    /// lines are drawn over.
    Band,
    /// A circle at every point.
    Markers,
}

/// One data series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// The points `(x, y)`; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Index into the figure palette.
    pub color: usize,
    /// How to draw it.
    pub style: Style,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            style: Style::Line,
        }
    }

    /// The same series drawn with `style`.
    pub fn with_style(mut self, style: Style) -> Self {
        self.style = style;
        self
    }
}

/// Where a panel's legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    /// Upper left corner.
    #[default]
    UpperLeft,
    /// Lower right corner.
    LowerRight,
    /// Middle of the lower edge.
    LowerMiddle,
}

/// One panel (a chart with axes) of a figure.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// The series, drawn in order.
    pub series: Vec<Series>,
    /// Axis ranges; `None` fits the data (with a 5 % margin).
    pub x_range: Option<(f64, f64)>,
    /// Axis ranges; `None` fits the data (with a 5 % margin).
    pub y_range: Option<(f64, f64)>,
    /// Legend position (shown when a series has a label).
    pub legend: Legend,
}

impl Panel {
    /// A panel with a title and axis labels, no series yet.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// The range of the data, `(x_min, x_max, y_min, y_max)`.
    pub fn data_bounds(&self) -> Option<(f64, f64, f64, f64)> {
        let mut it = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite() && p.1.is_finite());
        let first = it.next()?;
        Some(it.fold((first.0, first.0, first.1, first.1), |b, p| {
            (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1))
        }))
    }
}

/// The palette: colour-blind-friendly, distinct in print.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // green
    RGBColor(204, 121, 167), // purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(0, 0, 0),       // black
    RGBColor(120, 120, 120), // grey
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The largest axis value a figure accepts (far below `f64::MAX`, so spans
/// and tick arithmetic cannot overflow).
pub const MAX_AXIS: f64 = 1e300;

/// Pads a range by 5 % on each side; a degenerate range becomes ±1 (or
/// ±10 % of its value) around it.
pub fn padded(lo: f64, hi: f64) -> (f64, f64) {
    // half-values first: hi − lo itself may overflow
    let span = 2.0 * (0.5 * hi - 0.5 * lo);
    if span > f64::EPSILON * hi.abs().max(lo.abs()).max(1e-300) {
        (lo - 0.05 * span, hi + 0.05 * span)
    } else {
        let d = if lo.abs() > 0.0 { 0.1 * lo.abs() } else { 1.0 };
        (lo - d, hi + d)
    }
}

/// Drops points closer than `tol` (as a fraction of the axis spans) in
/// both coordinates to the last kept point; keeps the first and last
/// points and every non-finite-free point that moves visibly.
pub fn thin(points: &[(f64, f64)], x_span: f64, y_span: f64, tol: f64) -> Vec<(f64, f64)> {
    let (tx, ty) = (tol * x_span.abs(), tol * y_span.abs());
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(points.len().min(8192));
    for &p in points.iter().filter(|p| p.0.is_finite() && p.1.is_finite()) {
        match out.last() {
            Some(&q) if (p.0 - q.0).abs() <= tx && (p.1 - q.1).abs() <= ty => {}
            _ => out.push(p),
        }
    }
    if let Some(&last) = points
        .iter()
        .rev()
        .find(|p| p.0.is_finite() && p.1.is_finite())
    {
        if out.last() != Some(&last) {
            out.push(last);
        }
    }
    out
}

/// Renders `panels` in a `rows × cols` grid (row-major) into an SVG
/// document of `size` pixels.
pub fn render(
    panels: &[Panel],
    rows: usize,
    cols: usize,
    size: (u32, u32),
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let areas = root.split_evenly((rows.max(1), cols.max(1)));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            draw_panel(panel, area)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

fn draw_panel(panel: &Panel, area: &DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), PlotError> {
    let bounds = panel.data_bounds().unwrap_or((-1.0, 1.0, -1.0, 1.0));
    let (x0, x1) = panel.x_range.unwrap_or_else(|| padded(bounds.0, bounds.1));
    let (y0, y1) = panel.y_range.unwrap_or_else(|| padded(bounds.2, bounds.3));
    // Axis arithmetic (spans, ticks) must stay finite: refuse ranges whose
    // span would overflow instead of handing them to the plotting library.
    if ![x0, x1, y0, y1].iter().all(|v| v.abs() <= MAX_AXIS) {
        return Err(PlotError(format!(
            "values beyond ±{MAX_AXIS:e} cannot be plotted (axis range x [{x0:e}, {x1:e}], y [{y0:e}, {y1:e}])"
        )));
    }
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let mut legend = false;
    for s in &panel.series {
        let c = color(s.color);
        let anno = match s.style {
            Style::Line | Style::ThickLine | Style::Band => {
                // plotters rounds to whole pixels: points much closer than a
                // pixel only add zig-zags (and miter spikes on wide lines).
                let (stroke, tol) = match s.style {
                    Style::Line => (c.stroke_width(1), 1.0 / 400.0),
                    Style::ThickLine => (c.stroke_width(3), 1.0 / 300.0),
                    _ => (c.mix(0.35).stroke_width(7), 1.0 / 150.0),
                };
                let pts = thin(&s.points, x1 - x0, y1 - y0, tol);
                chart
                    .draw_series(LineSeries::new(pts, stroke))
                    .map_err(err)?
            }
            Style::Markers => chart
                .draw_series(
                    s.points
                        .iter()
                        .filter(|p| p.0.is_finite() && p.1.is_finite())
                        .map(|&p| Circle::new(p, 4, c.filled())),
                )
                .map_err(err)?,
        };
        if !s.label.is_empty() {
            legend = true;
            let style = s.style;
            anno.label(s.label.as_str())
                .legend(move |(x, y)| match style {
                    Style::Markers => Circle::new((x + 8, y), 4, c.filled()).into_dyn(),
                    Style::Band => {
                        PathElement::new(vec![(x, y), (x + 16, y)], c.mix(0.35).stroke_width(7))
                            .into_dyn()
                    }
                    _ => PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)).into_dyn(),
                });
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .position(match panel.legend {
                Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
                Legend::LowerRight => SeriesLabelPosition::LowerRight,
                Legend::LowerMiddle => SeriesLabelPosition::LowerMiddle,
            })
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// A panel of `y` over `x` (a hysteresis loop), one unlabelled line.
pub fn loop_panel(title: &str, x_label: &str, y_label: &str, x: &[f64], y: &[f64]) -> Panel {
    let mut p = Panel::new(title, x_label, y_label);
    p.series.push(Series::line(
        "",
        x.iter().copied().zip(y.iter().copied()).collect(),
        0,
    ));
    p
}

/// For values up to `largest` in magnitude: the power of ten to divide
/// them by so that axis labels stay short (1 when they already are), and
/// the axis label naming it (`sample / 1e3`).
pub fn power_of_ten(largest: f64, label: &str) -> (f64, String) {
    if !(largest.is_finite() && largest > 0.0) {
        return (1.0, label.to_string());
    }
    let exp = largest.log10().floor() as i32;
    if (-2..3).contains(&exp) {
        (1.0, label.to_string())
    } else {
        (10f64.powi(exp), format!("{label} / 1e{exp}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_scales_are_powers_of_ten() {
        assert_eq!(
            power_of_ten(19999.0, "sample"),
            (1e4, "sample / 1e4".into())
        );
        assert_eq!(power_of_ten(999.0, "sample"), (1.0, "sample".into()));
        assert_eq!(power_of_ten(3.2e-15, "r"), (1e-15, "r / 1e-15".into()));
        assert_eq!(power_of_ten(0.0, "r"), (1.0, "r".into()));
    }

    #[test]
    fn huge_values_are_an_error_not_a_hang() {
        // A span that overflows f64 once hung the plotting library.
        let p = loop_panel("t", "x", "y", &[-1.0, 1.0], &[-1.7e308, 1.7e308]);
        assert!(render(&[p], 1, 1, (200, 200)).is_err());
        let p = loop_panel("t", "x", "y", &[-1.7e308, 1.7e308], &[0.0, 1.0]);
        assert!(render(&[p], 1, 1, (200, 200)).is_err());
        let p = loop_panel("t", "x", "y", &[-1.0, 1.0], &[-1e6, 1e6]);
        assert!(render(&[p], 1, 1, (200, 200)).is_ok());
    }

    #[test]
    fn renders_text_without_system_fonts() {
        let mut p = Panel::new("a & b < c", "x [deg]", "F [Nm]");
        p.series
            .push(Series::line("line", vec![(0.0, 0.0), (1.0, 2.0)], 0));
        p.series
            .push(Series::line("knots", vec![(0.5, 1.0)], 1).with_style(Style::Markers));
        let svg = render(&[p], 1, 1, (400, 300)).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &amp; b &lt; c"));
        assert!(svg.contains("F [Nm]"));
        assert!(svg.contains("<polyline"));
        assert!(svg.contains("<circle"));
    }

    #[test]
    fn thinning_keeps_ends_and_shape() {
        let pts: Vec<(f64, f64)> = (0..=1000).map(|i| (i as f64 / 1000.0, 0.0)).collect();
        let t = thin(&pts, 1.0, 1.0, 0.01);
        assert_eq!(t.first(), Some(&(0.0, 0.0)));
        assert_eq!(t.last(), Some(&(1.0, 0.0)));
        assert!(t.len() < 110, "{}", t.len());
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(padded(0.0, 0.0), (-1.0, 1.0));
        let (a, b) = padded(2.0, 2.0);
        assert!(a < 2.0 && b > 2.0);
    }
}
