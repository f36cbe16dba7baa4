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
//! files small and avoids pixel-rounding zig-zags. A line that still has
//! more than [`MAX_LINE_POINTS`] points (a long record whose curve keeps
//! retracing itself: 10⁷ samples of a loop) is reduced to what the figure
//! can show ([`decimate`]): it is drawn through the cells of a grid of
//! about a pixel, a stretch that only revisits cells already drawn is left
//! out, and the first and last points and the extremes in `x` and `y` are
//! always kept, so the figure's extent is exact.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::fmt;
use std::path::Path;

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
    /// The points `(x, y)`; a non-finite point is not drawn, and breaks a
    /// line in two.
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
        bounds_of(self.series.iter().flat_map(|s| s.points.iter().copied()))
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

impl Style {
    /// How close (as a fraction of the axis spans) two points of a line
    /// drawn in this style may be before the second is dropped.
    pub fn tolerance(self) -> f64 {
        match self {
            Style::Line | Style::Markers => 1.0 / 400.0,
            Style::ThickLine => 1.0 / 300.0,
            Style::Band => 1.0 / 150.0,
        }
    }
}

/// The most points a line series is drawn with (see [`decimate`]); a
/// polyline of 50 000 points is about 500 kB of SVG.
pub const MAX_LINE_POINTS: usize = 50_000;

/// The points of a line drawn over axis ranges `x_range`, `y_range`: at
/// most [`MAX_LINE_POINTS`] (plus a handful), with `(NaN, NaN)` where the
/// line is broken. `points` is walked a few times (hence `Clone`; a slice
/// iterator or [`PointStore::iter`]), so a long record need not be copied.
///
/// First the plain thinning of [`thin`] (points closer than `tol` of the
/// spans to the last kept one are dropped), run by run between non-finite
/// points; that is the result when it is small enough. Otherwise the
/// ranges are divided into a grid of `⌈1/tol⌉²` cells and a point is kept
/// when it enters a cell no kept point is in yet, when it jumps farther
/// than to a neighbouring cell (the first time between those two cells),
/// or when it is one of the *extremes*: the
/// first and last finite points and the first points of least and greatest
/// `x` and `y`. A stretch of dropped points stays inside cells already
/// drawn; when it leaves the cell of the last kept point the line is
/// broken and resumes at the stretch's last point, so no chord is drawn
/// across the figure. If that is still too many points (a curve that
/// covers the whole figure), the grid is made coarser until it is not.
pub fn decimate<I>(
    points: I,
    x_range: (f64, f64),
    y_range: (f64, f64),
    tol: f64,
    max_points: usize,
) -> Vec<(f64, f64)>
where
    I: Iterator<Item = (f64, f64)> + Clone,
{
    let spans = (x_range.1 - x_range.0, y_range.1 - y_range.0);
    if let Some(out) = thin_runs(points.clone(), spans, tol, max_points) {
        return out;
    }
    let extremes = Extremes::of(points.clone());
    let mut cells = (1.0 / tol).ceil().clamp(1.0, 4096.0) as usize;
    loop {
        let grid = Grid::new(x_range, y_range, cells);
        // Line breaks in the data are kept while the grid allows; a data
        // set made of tiny runs falls back to skipping non-finite points.
        for breaks in [true, false] {
            if let Some(out) = grid.walk(points.clone(), &extremes, breaks, max_points) {
                return out;
            }
            if cells > 1 {
                break;
            }
        }
        if cells == 1 {
            // cannot happen (one cell and no breaks keeps ≤ 3 points per
            // extreme), but never loop forever
            return Vec::new();
        }
        cells = cells.div_ceil(2);
    }
}

/// A point `(x, y)`.
type Point = (f64, f64);

/// The line break marker of [`decimate`]'s output.
const BREAK: (f64, f64) = (f64::NAN, f64::NAN);

fn finite(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// [`thin`] run by run (non-finite points break the line), or `None` once
/// more than `max` points are kept.
fn thin_runs<I>(points: I, spans: (f64, f64), tol: f64, max: usize) -> Option<Vec<(f64, f64)>>
where
    I: Iterator<Item = (f64, f64)>,
{
    let (tx, ty) = (tol * spans.0.abs(), tol * spans.1.abs());
    let mut out: Vec<(f64, f64)> = Vec::new();
    // the last kept point of the current run, and its last point if not kept
    let mut kept: Option<Point> = None;
    let mut pending: Option<Point> = None;
    for p in points {
        if !finite(&p) {
            if let Some(q) = pending.take() {
                out.push(q);
            }
            if kept.take().is_some() {
                out.push(BREAK);
            }
            continue;
        }
        match kept {
            Some(q) if (p.0 - q.0).abs() <= tx && (p.1 - q.1).abs() <= ty => pending = Some(p),
            _ => {
                out.push(p);
                kept = Some(p);
                pending = None;
            }
        }
        if out.len() > max {
            return None;
        }
    }
    if let Some(q) = pending {
        out.push(q);
    }
    if out.last().is_some_and(|p| !finite(p)) {
        out.pop();
    }
    Some(out)
}

/// Indices of the points [`decimate`] always keeps: first and last finite
/// point, and the first of least and greatest `x` and `y`.
#[derive(Debug, Clone, Default)]
struct Extremes([usize; 6]);

impl Extremes {
    fn of<I: Iterator<Item = (f64, f64)>>(points: I) -> Self {
        let mut idx = [usize::MAX; 6];
        let mut val = [0.0_f64; 4];
        for (i, p) in points.enumerate().filter(|(_, p)| finite(p)) {
            if idx[0] == usize::MAX {
                idx = [i; 6];
                val = [p.0, p.0, p.1, p.1];
            }
            idx[1] = i;
            for (k, (v, less)) in [(p.0, true), (p.0, false), (p.1, true), (p.1, false)]
                .into_iter()
                .enumerate()
            {
                if (less && v < val[k]) || (!less && v > val[k]) {
                    val[k] = v;
                    idx[k + 2] = i;
                }
            }
        }
        Extremes(idx)
    }

    fn contains(&self, i: usize) -> bool {
        self.0.contains(&i)
    }
}

/// A grid of `cells × cells` over the axis ranges, with the cells a kept
/// point is in.
struct Grid {
    x0: f64,
    y0: f64,
    /// cells per unit of x and y
    sx: f64,
    sy: f64,
    cells: usize,
}

impl Grid {
    fn new(x_range: (f64, f64), y_range: (f64, f64), cells: usize) -> Self {
        let scale = |r: (f64, f64)| {
            let span = r.1 - r.0;
            if span > 0.0 && span.is_finite() {
                cells as f64 / span
            } else {
                0.0
            }
        };
        Grid {
            x0: x_range.0,
            y0: y_range.0,
            sx: scale(x_range),
            sy: scale(y_range),
            cells,
        }
    }

    fn cell(&self, p: (f64, f64)) -> (usize, usize) {
        let last = (self.cells - 1) as f64;
        let c = |v: f64, v0: f64, s: f64| ((v - v0) * s).floor().clamp(0.0, last) as usize;
        (c(p.0, self.x0, self.sx), c(p.1, self.y0, self.sy))
    }

    /// One pass of [`decimate`] on this grid, or `None` once more than
    /// `max` points are kept.
    fn walk<I>(
        &self,
        points: I,
        extremes: &Extremes,
        breaks: bool,
        max: usize,
    ) -> Option<Vec<(f64, f64)>>
    where
        I: Iterator<Item = (f64, f64)>,
    {
        let mut visited = vec![false; self.cells * self.cells];
        let mut jumps = std::collections::HashSet::new();
        let mut out: Vec<(f64, f64)> = Vec::new();
        // the previous finite point of the run, its cell, whether it was kept
        let mut prev: Option<(Point, (usize, usize), bool)> = None;
        // the cell of the last kept point, and whether every point dropped
        // since stayed in it
        let mut last_cell = (0, 0);
        let mut stayed = true;
        for (i, p) in points.enumerate() {
            if !finite(&p) {
                if breaks {
                    if let Some((q, _, false)) = prev {
                        out.push(q);
                    }
                    if prev.take().is_some() {
                        out.push(BREAK);
                    }
                }
                continue;
            }
            let c = self.cell(p);
            let fresh = !visited[c.0 * self.cells + c.1];
            // a jump past the neighbouring cells is drawn once (a periodic
            // record repeats its jumps every period)
            let new_jump = match prev {
                Some((_, pc, _)) if pc.0.abs_diff(c.0) > 1 || pc.1.abs_diff(c.1) > 1 => {
                    jumps.insert((pc, c))
                }
                _ => false,
            };
            if prev.is_none() || new_jump || fresh || extremes.contains(i) {
                if let Some((q, _, false)) = prev {
                    if !stayed {
                        out.push(BREAK);
                        out.push(q);
                    }
                }
                out.push(p);
                visited[c.0 * self.cells + c.1] = true;
                last_cell = c;
                stayed = true;
                prev = Some((p, c, true));
                if out.len() > max {
                    return None;
                }
            } else {
                stayed &= c == last_cell;
                prev = Some((p, c, false));
            }
        }
        if let Some((q, _, false)) = prev {
            out.push(q);
        }
        if out.last().is_some_and(|p| !finite(p)) {
            out.pop();
        }
        Some(out)
    }
}

/// Points `(x, y)` of a long record kept for a figure, in chunks (no
/// reallocation of one large buffer, so 16 bytes per point at most), with
/// their bounds.
#[derive(Debug, Clone, Default)]
pub struct PointStore {
    chunks: Vec<Vec<(f64, f64)>>,
    len: usize,
}

impl PointStore {
    /// Points per chunk.
    const CHUNK: usize = 1 << 16;

    /// Appends points.
    pub fn extend(&mut self, points: impl IntoIterator<Item = (f64, f64)>) {
        for p in points {
            match self.chunks.last_mut() {
                Some(c) if c.len() < Self::CHUNK => c.push(p),
                _ => {
                    let mut c = Vec::with_capacity(Self::CHUNK);
                    c.push(p);
                    self.chunks.push(c);
                }
            }
            self.len += 1;
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when no point is stored.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The points in order.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + Clone + '_ {
        self.chunks.iter().flatten().copied()
    }

    /// `(x_min, x_max, y_min, y_max)` of the finite points.
    pub fn bounds(&self) -> Option<(f64, f64, f64, f64)> {
        bounds_of(self.iter())
    }
}

fn bounds_of(points: impl Iterator<Item = (f64, f64)>) -> Option<(f64, f64, f64, f64)> {
    let mut it = points.filter(finite);
    let first = it.next()?;
    Some(it.fold((first.0, first.0, first.1, first.1), |b, p| {
        (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1))
    }))
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
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
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
                let stroke = match s.style {
                    Style::Line => c.stroke_width(1),
                    Style::ThickLine => c.stroke_width(3),
                    _ => c.mix(0.35).stroke_width(7),
                };
                let pts = decimate(
                    s.points.iter().copied(),
                    (x0, x1),
                    (y0, y1),
                    s.style.tolerance(),
                    MAX_LINE_POINTS,
                );
                chart
                    .draw_series(
                        pts.split(|p| !finite(p))
                            .filter(|run| !run.is_empty())
                            .map(|run| PathElement::new(run.to_vec(), stroke)),
                    )
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

/// An axis tick's label as plotters writes it, except that a zero is
/// never `-0` or `-0.0`: a tick computed as a tiny negative number, or a
/// negative zero, is labelled as zero.
pub fn tick_label(v: &f64) -> String {
    use plotters::coord::ranged1d::ValueFormatter;
    let text = <plotters::coord::types::RangedCoordf64 as ValueFormatter<f64>>::format(v);
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| matches!(c, '0' | '.')) => rest.to_string(),
        _ => text,
    }
}

/// The points `(x_i, y_i)` of a line of `y` over `x` (as many as the
/// shorter has).
pub fn pairs(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().copied().zip(y.iter().copied()).collect()
}

/// How a figure's title names the file at `path`: its file name, or the
/// whole path where it has none.
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    )
}

/// A panel of `y` over `x` (a hysteresis loop), one unlabelled line.
pub fn loop_panel(title: &str, x_label: &str, y_label: &str, x: &[f64], y: &[f64]) -> Panel {
    let mut p = Panel::new(title, x_label, y_label);
    p.series.push(Series::line("", pairs(x, y), 0));
    p
}

/// [`loop_panel`] over points kept in a [`PointStore`] (a long record):
/// the axis ranges are set from the points' bounds and the line is
/// [`decimate`]d here, so the panel holds at most about
/// [`MAX_LINE_POINTS`] points, not a copy of the record.
pub fn loop_panel_from_store(
    title: &str,
    x_label: &str,
    y_label: &str,
    points: &PointStore,
) -> Panel {
    let mut p = Panel::new(title, x_label, y_label);
    let b = points.bounds().unwrap_or((-1.0, 1.0, -1.0, 1.0));
    let (xr, yr) = (padded(b.0, b.1), padded(b.2, b.3));
    let kept = decimate(
        points.iter(),
        xr,
        yr,
        Style::Line.tolerance(),
        MAX_LINE_POINTS,
    );
    p.series.push(Series::line("", kept, 0));
    p.x_range = Some(xr);
    p.y_range = Some(yr);
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

    /// Points of a long record: bounded however they move, the first, last
    /// and extreme points kept exactly, small inputs thinned as before.
    #[test]
    fn decimation_is_bounded_and_keeps_the_extremes() {
        let mut seed: u64 = 0x853c_49e6_748f_ea9b;
        let mut noise = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // white noise (the worst case: every sample jumps), a retraced loop
        // with one spike, and a noisy time series
        let sets: Vec<Vec<(f64, f64)>> = vec![
            (0..300_000).map(|_| (noise(), noise())).collect(),
            (0..1_000_000)
                .map(|i| {
                    let th = i as f64 * 0.00314;
                    let y = if i == 777_777 { 9.0 } else { th.cos() };
                    (th.sin(), y)
                })
                .collect(),
            (0..500_000).map(|i| (i as f64, noise())).collect(),
        ];
        for pts in &sets {
            let b = bounds_of(pts.iter().copied()).unwrap();
            let (xr, yr) = (padded(b.0, b.1), padded(b.2, b.3));
            let kept = decimate(pts.iter().copied(), xr, yr, 1.0 / 400.0, MAX_LINE_POINTS);
            assert!(kept.len() <= MAX_LINE_POINTS + 20, "{}", kept.len());
            assert_eq!(bounds_of(kept.iter().copied()), Some(b));
            let finite_kept: Vec<_> = kept.iter().filter(|p| finite(p)).collect();
            assert_eq!(finite_kept.first(), Some(&&pts[0]));
            assert_eq!(finite_kept.last(), Some(&pts.last().unwrap()));
            // every kept point is a data point, in order
            let mut it = pts.iter();
            for p in &finite_kept {
                assert!(it.any(|q| q == *p), "{p:?} out of order");
            }
        }
        // a small series is thinned exactly as thin() does
        let pts: Vec<(f64, f64)> = (0..5000)
            .map(|i| ((i as f64 * 0.01).sin(), i as f64))
            .collect();
        let kept = decimate(
            pts.iter().copied(),
            (-1.0, 1.0),
            (0.0, 5000.0),
            0.01,
            MAX_LINE_POINTS,
        );
        assert_eq!(kept, thin(&pts, 2.0, 5000.0, 0.01));
        // a non-finite point breaks the line
        let kept = decimate(
            [
                (0.0, 0.0),
                (1.0, 1.0),
                (f64::NAN, 0.0),
                (2.0, 2.0),
                (3.0, 3.0),
            ]
            .into_iter(),
            (0.0, 3.0),
            (0.0, 3.0),
            0.01,
            MAX_LINE_POINTS,
        );
        assert_eq!(kept.len(), 5);
        assert!(kept[2].0.is_nan());
    }

    #[test]
    fn no_tick_is_labelled_minus_zero() {
        for v in [-0.0, -1e-17, -4.0e-300] {
            let label = tick_label(&v);
            assert!(!label.starts_with('-'), "{v}: {label}");
        }
        assert_eq!(tick_label(&-0.5), "-0.5");
        assert!(tick_label(&-2.0).starts_with("-2"), "{}", tick_label(&-2.0));
        // in a drawn figure too: an axis from -1 to 1 has a tick at 0
        let mut panel = Panel::new("t", "x", "y");
        panel
            .series
            .push(Series::line("", vec![(-1.0, -1.0), (1.0, 1.0)], 0));
        let svg = render(&[panel], 1, 1, (400, 300)).unwrap();
        assert!(
            !svg.contains(">-0<") && !svg.contains(">-0.0<"),
            "a -0 label"
        );
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(padded(0.0, 0.0), (-1.0, 1.0));
        let (a, b) = padded(2.0, 2.0);
        assert!(a < 2.0 && b > 2.0);
    }
}
