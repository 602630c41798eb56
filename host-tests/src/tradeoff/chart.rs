//! Charts with `plotters`, each written as SVG and as PNG (bitmap backend
//! into a buffer, encoded by `output::image::write_png`). Text is drawn by
//! `ab_glyph` with DejaVu Sans embedded from the `dejavu` crate, so no
//! system font or fontconfig is needed.
//!
//! * [`Scatter`]: time (log axis) against error, one colour per series
//!   (legend), the Pareto front joined by a line and drawn filled (other
//!   points hollow); only Pareto points labelled, each label placed inside
//!   the plotting area where it meets no other label and no marker, or left
//!   out ([`place_labels`]; a chart with overlapping labels is an error);
//!   one panel per group.
//! * [`Curves`]: lines on log–log axes (convergence over frames).

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::error::FileError;
use crate::output::OutputError;
use crate::output::image::write_png;

/// One point of a scatter chart.
#[derive(Clone, Debug)]
pub struct Point {
    /// x (time or firmware cost; > 0).
    pub x: f64,
    /// y (error or PSNR).
    pub y: f64,
    /// Label drawn beside the point.
    pub label: String,
    /// Series (colour and legend entry).
    pub series: String,
    /// On the Pareto front.
    pub front: bool,
}

/// A panel of a scatter chart.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Panel caption.
    pub title: String,
    /// x-axis description of this panel, when not the chart's.
    pub x: Option<String>,
    /// The points.
    pub points: Vec<Point>,
}

/// Axes of a chart.
#[derive(Clone, Debug)]
pub struct Axes {
    /// x-axis description.
    pub x: String,
    /// y-axis description.
    pub y: String,
    /// Logarithmic y axis (values ≤ `y_floor` drawn at the floor).
    pub log_y: bool,
    /// Smallest y drawn on a log axis.
    pub y_floor: f64,
}

/// A line of a curve chart.
#[derive(Clone, Debug)]
pub struct Line {
    /// Legend entry.
    pub name: String,
    /// `(x, y)` points, both > 0.
    pub points: Vec<(f64, f64)>,
    /// Dashed (reference lines).
    pub dashed: bool,
}

const WIDTH: u32 = 1400;
const HEIGHT: u32 = 900;

/// Registers the embedded font once.
fn fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Colour of series `i`.
#[must_use]
pub fn colour(i: usize) -> RGBColor {
    const P: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(90, 90, 90),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    P[i % P.len()]
}

/// `v` with three significant digits, plain when in `[0.01, 10⁵)`.
#[must_use]
pub fn sig(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (0.01..1e5).contains(&a) {
        let d = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.1e}")
    }
}

/// Tick label of a log10-transformed axis value.
fn exp_label(v: &f64) -> String {
    sig(10f64.powf(*v))
}

/// `(lo, hi)` with a margin, for a log axis (`log`) or a linear one.
fn range(vals: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        (lo / 1.6, hi * 1.6)
    } else {
        let m = ((hi - lo) * 0.08).max(0.05);
        (lo - m, hi + m)
    }
}

/// A chart drawable on any backend.
pub trait Draw {
    /// Draws the chart on `root`.
    ///
    /// # Errors
    /// [`ChartError::Draw`] (the backend's error) or
    /// [`ChartError::LabelsOverlap`].
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ChartError>;
}

/// Why a chart could not be drawn or written.
#[derive(Debug)]
pub enum ChartError {
    /// The plotting backend failed. Its error type is a parameter of the
    /// backend (SVG string, bitmap buffer), so its message is kept.
    Draw {
        /// The backend's message.
        message: String,
    },
    /// Two placed labels overlap (the label placement is wrong).
    LabelsOverlap {
        /// The panel's title.
        panel: String,
        /// Index of the first label among the panel's labelled points.
        a: usize,
        /// Index of the second.
        b: usize,
    },
    /// The SVG or PNG file could not be written (names the file).
    Output(OutputError),
}

impl std::fmt::Display for ChartError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Draw { message } => write!(f, "drawing failed: {message}"),
            Self::LabelsOverlap { panel, a, b } => {
                write!(f, "panel {panel:?}: labels {a} and {b} overlap")
            }
            Self::Output(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ChartError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Output(e) => Some(e),
            Self::Draw { .. } | Self::LabelsOverlap { .. } => None,
        }
    }
}

impl From<OutputError> for ChartError {
    fn from(e: OutputError) -> Self {
        Self::Output(e)
    }
}

fn err(e: impl std::fmt::Display) -> ChartError {
    ChartError::Draw {
        message: e.to_string(),
    }
}

/// Writes `chart` as `stem.svg` and `stem.png`.
///
/// # Errors
/// Drawing or file errors, naming the file.
pub fn write(stem: &Path, chart: &impl Draw) -> Result<(), ChartError> {
    fonts();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        chart.draw(&root)?;
        root.present().map_err(err)?;
    }
    let svg_path = stem.with_extension("svg");
    std::fs::write(&svg_path, svg)
        .map_err(|e| OutputError::from(FileError::write(&svg_path, e)))?;
    let mut buf = vec![0u8; (WIDTH * HEIGHT * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)).into_drawing_area();
        chart.draw(&root)?;
        root.present().map_err(err)?;
    }
    let px: Vec<[u8; 3]> = buf.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(write_png(&stem.with_extension("png"), WIDTH, HEIGHT, &px)?)
}

/// A panel on log10-transformed x (and y where the caller transforms it):
/// caption, ranges, mesh with the axis descriptions.
fn panel_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    axes: &Axes,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    y_fmt: &dyn Fn(&f64) -> String,
) -> Result<Panel2d<'a, DB>, ChartError> {
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axes.x.as_str())
        .y_desc(axes.y.as_str())
        .x_labels(6)
        .y_labels(8)
        .x_label_formatter(&exp_label)
        .y_label_formatter(y_fmt)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// A chart panel over f64 axes.
type Panel2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// `root` filled white under `title`, the area below split into a
/// `(rows, columns)` grid whose first `n` cells are drawn by `panel(i, cell)`.
fn draw_panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    grid: (usize, usize),
    n: usize,
    mut panel: impl FnMut(usize, &DrawingArea<DB, Shift>) -> Result<(), ChartError>,
) -> Result<(), ChartError> {
    root.fill(&WHITE).map_err(err)?;
    let below = root.titled(title, ("sans-serif", 24)).map_err(err)?;
    for (i, cell) in below.split_evenly(grid).iter().enumerate().take(n) {
        panel(i, cell)?;
    }
    Ok(())
}

/// The legend box, upper right.
fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut Panel2d<'a, DB>,
    position: SeriesLabelPosition,
) -> Result<(), ChartError> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .position(position)
        .draw()
        .map_err(err)
}

/// Cost (time or instructions) against error, one panel per group.
#[derive(Clone, Debug)]
pub struct Scatter {
    /// Chart title.
    pub title: String,
    /// Axes.
    pub axes: Axes,
    /// Panels (one or more).
    pub panels: Vec<Panel>,
    /// One front per series (drawn in its colour) instead of one front
    /// over every point (black).
    pub front_per_series: bool,
    /// The legend in the lower right corner instead of the upper right
    /// (charts whose best points lie top right: PSNR against cost).
    pub legend_lower_right: bool,
}

impl Scatter {
    /// Series names in order of first appearance (stable colours).
    fn series(&self) -> Vec<String> {
        let mut s: Vec<String> = Vec::new();
        for p in self.panels.iter().flat_map(|p| &p.points) {
            if !s.contains(&p.series) {
                s.push(p.series.clone());
            }
        }
        s
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        p: &Panel,
    ) -> Result<(), ChartError> {
        let log_y = self.axes.log_y;
        let floor = self.axes.y_floor;
        let ty = move |y: f64| if log_y { y.max(floor).log10() } else { y };
        let tx = |x: f64| x.log10();
        let (x0, x1) = range(p.points.iter().map(|q| tx(q.x)), false);
        // Room for the labels right of the last points.
        let x1 = x1 + 0.18 * (x1 - x0);
        let (y0, y1) = range(p.points.iter().map(|q| ty(q.y)), false);
        let y_fmt = move |v: &f64| {
            if log_y {
                exp_label(v)
            } else {
                format!("{v:.1}")
            }
        };
        let axes = Axes {
            x: p.x.clone().unwrap_or_else(|| self.axes.x.clone()),
            ..self.axes.clone()
        };
        let mut chart = panel_chart(area, &p.title, &axes, (x0, x1), (y0, y1), &y_fmt)?;
        let front_line = |pts: &[&Point]| {
            let mut f: Vec<(f64, f64)> = pts
                .iter()
                .filter(|q| q.front)
                .map(|q| (tx(q.x), ty(q.y)))
                .collect();
            f.sort_by(|a, b| a.0.total_cmp(&b.0));
            f
        };
        let all: Vec<&Point> = p.points.iter().collect();
        let (label, c) = if self.front_per_series {
            ("Pareto front (per method)", BLACK.mix(0.0))
        } else {
            ("Pareto front", BLACK.mix(1.0))
        };
        chart
            .draw_series(LineSeries::new(
                if self.front_per_series {
                    Vec::new()
                } else {
                    front_line(&all)
                },
                c.stroke_width(2),
            ))
            .map_err(err)?
            .label(label)
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
        for (si, name) in self.series().iter().enumerate() {
            let c = colour(si);
            let pts: Vec<&Point> = p.points.iter().filter(|q| &q.series == name).collect();
            if pts.is_empty() {
                continue;
            }
            if self.front_per_series {
                chart
                    .draw_series(LineSeries::new(front_line(&pts), c.stroke_width(2)))
                    .map_err(err)?;
            }
            chart
                .draw_series(pts.iter().map(|q| {
                    let style = if q.front {
                        c.filled()
                    } else {
                        c.stroke_width(2)
                    };
                    Circle::new((tx(q.x), ty(q.y)), if q.front { 6 } else { 5 }, style)
                }))
                .map_err(err)?
                .label(name.as_str())
                .legend(move |(x, y)| Circle::new((x + 9, y), 5, c.filled()));
        }
        labels(&self.series(), area, &mut chart, p, &tx, &ty)?;
        legend(
            &mut chart,
            if self.legend_lower_right {
                SeriesLabelPosition::LowerRight
            } else {
                SeriesLabelPosition::UpperRight
            },
        )
    }
}

/// Draws the labels of `p`'s points on `chart` (see [`place_labels`]).
fn labels<DB: DrawingBackend>(
    series: &[String],
    area: &DrawingArea<DB, Shift>,
    chart: &mut Panel2d<'_, DB>,
    p: &Panel,
    tx: &dyn Fn(f64) -> f64,
    ty: &dyn Fn(f64) -> f64,
) -> Result<(), ChartError> {
    // Labels: the Pareto points only (the rest are told apart by colour,
    // the legend and the full table in tradeoff.md), each placed where
    // its box meets no other label and no marker, or left out.
    let labelled: Vec<&Point> = p.points.iter().filter(|q| q.front).collect();
    let markers: Vec<(i32, i32)> = p
        .points
        .iter()
        .map(|q| chart.backend_coord(&(tx(q.x), ty(q.y))))
        .collect();
    let font = ("sans-serif", LABEL_FONT).into_font();
    let mut sizes = Vec::with_capacity(labelled.len());
    for q in &labelled {
        let (w, h) = area
            .estimate_text_size(&q.label, &plotters::style::TextStyle::from(font.clone()))
            .map_err(err)?;
        sizes.push((w as i32, h as i32));
    }
    let anchors: Vec<(i32, i32)> = labelled
        .iter()
        .map(|q| chart.backend_coord(&(tx(q.x), ty(q.y))))
        .collect();
    // The plotting area in pixels: a label outside it would cover the
    // tick labels or be cut at the panel's edge.
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let bounds = (xr.start, yr.start, xr.end, yr.end);
    let boxes = place_labels(&anchors, &sizes, &markers, bounds);
    if let Some((a, b)) = first_overlap(&boxes) {
        return Err(ChartError::LabelsOverlap {
            panel: p.title.clone(),
            a,
            b,
        });
    }
    for (q, (b, &(px, py))) in labelled.iter().zip(boxes.iter().zip(&anchors)) {
        let Some(b) = b else { continue };
        let si = series.iter().position(|s| s == &q.series).unwrap_or(0);
        let f = font.clone().color(&colour(si));
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((tx(q.x), ty(q.y)))
                    + Text::new(q.label.clone(), (b.0 - px, b.1 - py), f),
            ))
            .map_err(err)?;
    }
    Ok(())
}

/// Point size of the labels beside chart points.
const LABEL_FONT: f64 = 12.0;

/// Half the side of the square kept free around each marker (pixels).
const MARKER_HALF: i32 = 7;

/// A label box in pixels: `(left, top, right, bottom)`, right and bottom
/// exclusive.
pub type LabelBox = (i32, i32, i32, i32);

fn overlap(a: LabelBox, b: LabelBox) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// For each label of size `sizes[i]` at the point `anchors[i]` (pixels),
/// the first of eight places around the point (right, left, above, below
/// and the corners) whose box lies inside `bounds` and meets no box placed
/// before it and no marker of `markers` (squares of side `2·MARKER_HALF`;
/// the label's own point included); `None` (label left out) when every
/// place is taken.
#[must_use]
pub fn place_labels(
    anchors: &[(i32, i32)],
    sizes: &[(i32, i32)],
    markers: &[(i32, i32)],
    bounds: LabelBox,
) -> Vec<Option<LabelBox>> {
    let g = MARKER_HALF + 2;
    let mut placed: Vec<LabelBox> = Vec::new();
    let mut out = Vec::with_capacity(anchors.len());
    for (&(px, py), &(w, h)) in anchors.iter().zip(sizes) {
        let candidates = [
            (px + g, py - h / 2),
            (px - g - w, py - h / 2),
            (px - w / 2, py - g - h),
            (px - w / 2, py + g),
            (px + g, py - g - h),
            (px + g, py + g),
            (px - g - w, py - g - h),
            (px - g - w, py + g),
        ];
        let free = |b: LabelBox| {
            b.0 >= bounds.0
                && b.1 >= bounds.1
                && b.2 <= bounds.2
                && b.3 <= bounds.3
                && placed.iter().all(|&o| !overlap(b, o))
                && markers.iter().all(|&(mx, my)| {
                    !overlap(
                        b,
                        (
                            mx - MARKER_HALF,
                            my - MARKER_HALF,
                            mx + MARKER_HALF,
                            my + MARKER_HALF,
                        ),
                    )
                })
        };
        let chosen = candidates
            .iter()
            .map(|&(x, y)| (x, y, x + w, y + h))
            .find(|&b| free(b));
        if let Some(b) = chosen {
            placed.push(b);
        }
        out.push(chosen);
    }
    out
}

/// The first pair `(i, j)` of placed boxes that overlap, if any.
#[must_use]
pub fn first_overlap(boxes: &[Option<LabelBox>]) -> Option<(usize, usize)> {
    for (i, a) in boxes.iter().enumerate() {
        for (j, b) in boxes.iter().enumerate().skip(i + 1) {
            if let (Some(a), Some(b)) = (a, b)
                && overlap(*a, *b)
            {
                return Some((i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod label_tests {
    use super::*;

    #[test]
    fn a_lone_label_goes_right_of_its_point() {
        let b = place_labels(&[(100, 100)], &[(40, 12)], &[(100, 100)], AREA);
        assert_eq!(b, vec![Some((109, 94, 149, 106))]);
    }

    #[test]
    fn labels_stay_inside_the_plotting_area() {
        // At the right edge the label goes left; in the top-left corner
        // below right; a label wider than the area is left out.
        let b = place_labels(&[(990, 500)], &[(40, 12)], &[(990, 500)], AREA);
        assert_eq!(b, vec![Some((941, 494, 981, 506))]);
        let b = place_labels(&[(2, 2)], &[(40, 12)], &[(2, 2)], AREA);
        assert_eq!(b, vec![Some((11, 11, 51, 23))]);
        assert_eq!(
            place_labels(&[(500, 500)], &[(2000, 12)], &[], AREA),
            vec![None]
        );
    }

    /// A 1000 × 1000 plotting area.
    const AREA: LabelBox = (0, 0, 1000, 1000);

    #[test]
    fn crowded_labels_never_overlap_each_other_or_a_marker() {
        // 60 points on a 6-pixel grid (far denser than a label): most
        // labels must be left out, none may overlap.
        let pts: Vec<(i32, i32)> = (0..60)
            .map(|i| (200 + (i % 10) * 6, 200 + (i / 10) * 6))
            .collect();
        let sizes = vec![(50, 12); pts.len()];
        let boxes = place_labels(&pts, &sizes, &pts, AREA);
        assert_eq!(first_overlap(&boxes), None);
        let placed: Vec<LabelBox> = boxes.iter().flatten().copied().collect();
        assert!(!placed.is_empty() && placed.len() < pts.len());
        for b in &placed {
            for &(mx, my) in &pts {
                let m = (
                    mx - MARKER_HALF,
                    my - MARKER_HALF,
                    mx + MARKER_HALF,
                    my + MARKER_HALF,
                );
                assert!(!overlap(*b, m), "{b:?} covers the marker at ({mx}, {my})");
            }
        }
    }

    #[test]
    fn overlap_is_detected() {
        assert_eq!(
            first_overlap(&[Some((0, 0, 10, 10)), None, Some((9, 9, 20, 20))]),
            Some((0, 2))
        );
        assert_eq!(
            first_overlap(&[Some((0, 0, 10, 10)), Some((10, 0, 20, 10))]),
            None
        );
    }
}

impl Draw for Scatter {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ChartError> {
        let n = self.panels.len();
        let grid = match n {
            0 | 1 => (1, 1),
            2 => (1, 2),
            _ => (2, n.div_ceil(2)),
        };
        draw_panels(root, &self.title, grid, n, |i, a| {
            self.panel(a, &self.panels[i])
        })
    }
}

/// Lines on log–log axes.
#[derive(Clone, Debug)]
pub struct Curves {
    /// Chart title.
    pub title: String,
    /// Axes (both logarithmic; `log_y` ignored).
    pub axes: Axes,
    /// Panels: a caption and its lines.
    pub panels: Vec<(String, Vec<Line>)>,
}

impl Curves {
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        title: &str,
        lines: &[Line],
    ) -> Result<(), ChartError> {
        let floor = self.axes.y_floor;
        let t = move |(x, y): (f64, f64)| (x.log10(), y.max(floor).log10());
        let all = || lines.iter().flat_map(|l| l.points.iter().map(|&p| t(p)));
        let (x0, x1) = range(all().map(|p| p.0), false);
        let (y0, y1) = range(all().map(|p| p.1), false);
        let mut chart = panel_chart(area, title, &self.axes, (x0, x1), (y0, y1), &exp_label)?;
        for (i, l) in lines.iter().enumerate() {
            let c = if l.dashed { BLACK } else { colour(i) };
            let pts = l.points.iter().map(|&p| t(p));
            let s = if l.dashed {
                chart.draw_series(DashedLineSeries::new(pts, 8, 6, c.stroke_width(2)))
            } else {
                chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))
            };
            s.map_err(err)?
                .label(l.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

impl Draw for Curves {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ChartError> {
        let n = self.panels.len();
        draw_panels(root, &self.title, (1, n.max(1)), n, |i, a| {
            let (title, lines) = &self.panels[i];
            self.panel(a, title, lines)
        })
    }
}
