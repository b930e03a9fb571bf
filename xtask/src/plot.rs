//! Line plots for the figures (convergence histories, timings against size), drawn by
//! `plotters` into an in-memory RGB buffer and returned as a [`render::Image`](crate::render::Image).
//!
//! Text uses the embedded DejaVu Sans ([`render::FONT_BYTES`](crate::render::FONT_BYTES)), registered
//! with plotters' `ab_glyph` font table, so no system font is needed. Each series gets its own
//! colour and marker; log axes are padded to whole decades and labelled 10ᵏ; the legend goes in
//! the corner with the fewest data points.
// The plotting API is called by the reproduce-paper task; until each entry point has a caller in
// the binary, rustc would report the rest as dead code.
#![allow(dead_code)]

use std::ops::Range;
use std::sync::Once;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::render::{Image, FONT_BYTES};

/// One named curve of a [`line_plot`].
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// (x, y) points in drawing order; non-finite points, and non-positive ones on a log axis,
    /// are left out.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series named `name` through `points`.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self { name: name.into(), points }
    }

    /// A series of `values` against their index `0, 1, 2, …` (e.g. an error history).
    pub fn from_history(name: impl Into<String>, values: &[f64]) -> Self {
        Self::new(name, values.iter().enumerate().map(|(i, &v)| (i as f64, v)).collect())
    }
}

/// Series colours (Tableau 10), in order; the list repeats past ten series.
pub const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// At most this many markers per series: long histories get a marker every few points.
const MAX_MARKERS: usize = 16;
/// Marker shapes, in order: circle, triangle, square, diamond, cross.
const MARKERS: usize = 5;
const FONT_FAMILY: &str = "sans-serif";

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, FONT_BYTES).is_err() {
            panic!("the embedded DejaVu Sans is not a valid font");
        }
    });
}

/// Plots `series` as lines with markers and a legend under `title`, into a `width × height`
/// image; `log_x` / `log_y` make an axis logarithmic (base 10).
///
/// An axis with no usable point spans [1, 10] (log) or [0, 1] (linear).
#[allow(clippy::too_many_arguments)]
pub fn line_plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_x: bool,
    log_y: bool,
    width: u32,
    height: u32,
) -> Image {
    register_font();
    let usable = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite() && (!log_x || x > 0.0) && (!log_y || y > 0.0);
    let clean: Vec<Series> = series
        .iter()
        .map(|s| Series { name: s.name.clone(), points: s.points.iter().copied().filter(usable).collect() })
        .collect();
    let all = || clean.iter().flat_map(|s| s.points.iter().copied());
    let x_range = axis_range(all().map(|p| p.0), log_x);
    let y_range = axis_range(all().map(|p| p.1), log_y);
    let text = Text { title, x_label, y_label, log_x, log_y };
    let mut image = Image::new(width, height, [255, 255, 255]);
    {
        let root = BitMapBackend::with_buffer(&mut image.rgb, (width, height)).into_drawing_area();
        let legend = legend_corner(&clean, &x_range, &y_range, log_x, log_y);
        let result = match (log_x, log_y) {
            (false, false) => draw(&root, x_range, y_range, &clean, &text, legend),
            (true, false) => draw(&root, x_range.log_scale(), y_range, &clean, &text, legend),
            (false, true) => draw(&root, x_range, y_range.log_scale(), &clean, &text, legend),
            (true, true) => draw(&root, x_range.log_scale(), y_range.log_scale(), &clean, &text, legend),
        };
        // Drawing into a memory buffer fails only if the font is missing, which is a bug here.
        result.unwrap_or_else(|e| panic!("plotting into memory failed: {e}"));
        root.present().unwrap_or_else(|e| panic!("plotting into memory failed: {e}"));
    }
    image
}

struct Text<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    log_x: bool,
    log_y: bool,
}

/// The axis range: whole decades on a log axis, the data ± 4 % on a linear one.
fn axis_range(values: impl Iterator<Item = f64>, log: bool) -> Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        return if log { 1.0..10.0 } else { 0.0..1.0 };
    }
    if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        let b = if b <= a { a + 1.0 } else { b };
        // A hair wider than whole decades, so that round-off in plotters' tick search
        // (ceil of ln(start)/ln(10)) cannot skip the end decades' labels.
        10f64.powf(a) * (1.0 - 1e-9)..10f64.powf(b) * (1.0 + 1e-9)
    } else if hi > lo {
        let pad = 0.04 * (hi - lo);
        // Keep 0 as the lower end when the data start there (iteration counts, sizes).
        let start = if lo >= 0.0 && lo - pad < 0.0 { 0.0 } else { lo - pad };
        start..hi + pad
    } else {
        let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        lo - pad..hi + pad
    }
}

/// Where the legend covers the fewest points: each corner's quarter of the plot is counted.
fn legend_corner(series: &[Series], x: &Range<f64>, y: &Range<f64>, log_x: bool, log_y: bool) -> SeriesLabelPosition {
    let unit = |v: f64, r: &Range<f64>, log: bool| {
        if log {
            (v.log10() - r.start.log10()) / (r.end.log10() - r.start.log10())
        } else {
            (v - r.start) / (r.end - r.start)
        }
    };
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|&&(px, py)| {
                let (u, v) = (unit(px, x, log_x), unit(py, y, log_y));
                (if right { u > 0.55 } else { u < 0.45 }) && (if upper { v > 0.6 } else { v < 0.4 })
            })
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (position, right, upper) in corners {
        let n = count(right, upper);
        if n < best.0 {
            best = (n, position);
        }
    }
    best.1
}

/// Axis labels: 10ᵏ at powers of ten on a log axis (other ticks unlabelled), short decimals or
/// scientific notation on a linear one.
fn format_tick(v: f64, log: bool) -> String {
    if log {
        let k = v.log10().round();
        if (v / 10f64.powf(k) - 1.0).abs() > 1e-9 {
            return String::new();
        }
        return format!("10{}", superscript(k as i64));
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.1e}");
        return s.replace(".0e", "e");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn superscript(k: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = k.unsigned_abs().to_string().bytes().map(|b| DIGITS[usize::from(b - b'0')]).collect::<String>();
    if k < 0 {
        format!("⁻{digits}")
    } else {
        digits
    }
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> = Result<(), DrawingAreaErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>>;

fn draw<'a, X, Y>(
    root: &Area<'a>,
    x_spec: X,
    y_spec: Y,
    series: &[Series],
    text: &Text<'_>,
    legend: SeriesLabelPosition,
) -> DrawResult<'a>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    let small = w.min(h);
    let title_size = (small / 20).clamp(15, 28);
    let label_size = (small / 26).clamp(12, 22);
    let tick_size = (small / 28).clamp(11, 20);
    let mut chart = ChartBuilder::on(root)
        .caption(text.title, (FONT_FAMILY, title_size))
        .margin(14)
        .margin_right(24)
        .x_label_area_size(2 * label_size + tick_size)
        .y_label_area_size(3 * label_size + 2 * tick_size)
        .build_cartesian_2d(x_spec, y_spec)?;
    let (x_log, y_log) = (text.log_x, text.log_y);
    let x_fmt = move |v: &f64| format_tick(*v, x_log);
    let y_fmt = move |v: &f64| format_tick(*v, y_log);
    chart
        .configure_mesh()
        .x_desc(text.x_label)
        .y_desc(text.y_label)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT_FAMILY, tick_size))
        .axis_desc_style((FONT_FAMILY, label_size))
        .bold_line_style(RGBColor(200, 200, 200).stroke_width(1))
        .light_line_style(RGBColor(236, 236, 236).stroke_width(1))
        .max_light_lines(9)
        .draw()?;
    let marker_size = (small / 110).clamp(3, 6) as i32;
    for (k, s) in series.iter().enumerate() {
        let [r, g, b] = PALETTE[k % PALETTE.len()];
        let colour = RGBColor(r, g, b);
        let line = colour.stroke_width(2);
        let kind = k % MARKERS;
        chart.draw_series(LineSeries::new(s.points.iter().copied(), line))?;
        let step = s.points.len().div_ceil(MAX_MARKERS).max(1);
        let mut marks: Vec<(f64, f64)> = s.points.iter().copied().step_by(step).collect();
        if let Some(&last) = s.points.last() {
            if marks.last() != Some(&last) {
                marks.push(last);
            }
        }
        let name = s.name.clone();
        // One branch per marker shape: plotters' series and legend entries are statically typed.
        macro_rules! markers {
            ($shape:expr) => {{
                let shape = $shape;
                chart.draw_series(marks.iter().map(|&p| EmptyElement::at(p) + shape(marker_size)))?.label(name).legend(
                    move |(x, y)| {
                        EmptyElement::at((x, y)) + PathElement::new(vec![(-10, 0), (10, 0)], line) + shape(marker_size)
                    },
                );
            }};
        }
        let filled = colour.filled();
        match kind {
            0 => markers!(move |s: i32| Circle::new((0, 0), s, filled)),
            1 => markers!(move |s: i32| TriangleMarker::new((0, 0), s + 1, filled)),
            2 => markers!(move |s: i32| Rectangle::new([(1 - s, 1 - s), (s - 1, s - 1)], filled)),
            3 => markers!(move |s: i32| Polygon::new(vec![(0, -s - 1), (s + 1, 0), (0, s + 1), (-s - 1, 0)], filled)),
            _ => markers!(move |s: i32| Cross::new((0, 0), s, colour.stroke_width(2))),
        }
    }
    if series.iter().any(|s| !s.name.is_empty()) {
        chart
            .configure_series_labels()
            .position(legend)
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(160, 160, 160))
            .label_font((FONT_FAMILY, label_size))
            .margin(10)
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_read_as_powers_of_ten() {
        assert_eq!(format_tick(1000.0, true), "10³");
        assert_eq!(format_tick(1e-4, true), "10⁻⁴");
        assert_eq!(format_tick(1.0, true), "10⁰");
        assert_eq!(format_tick(2000.0, true), "");
        assert_eq!(format_tick(0.25, false), "0.25");
        assert_eq!(format_tick(40.0, false), "40");
        assert_eq!(format_tick(2.5e6, false), "2.5e6");
    }

    #[test]
    fn ranges_pad_to_decades() {
        let close = |r: Range<f64>, a: f64, b: f64| (r.start / a - 1.0).abs() < 1e-6 && (r.end / b - 1.0).abs() < 1e-6;
        assert!(close(axis_range([3e3, 2e5].into_iter(), true), 1e3, 1e6));
        assert!(close(axis_range([10.0].into_iter(), true), 10.0, 100.0));
        assert_eq!(axis_range(std::iter::empty(), false), 0.0..1.0);
        let r = axis_range([0.0, 100.0].into_iter(), false);
        assert_eq!(r.start, 0.0);
        assert!(r.end > 100.0);
    }

    #[test]
    fn log_log_plot_of_a_square_has_series_coloured_pixels() {
        let xs: Vec<f64> = (0..=30).map(|i| 10f64.powf(1.0 + 2.0 * f64::from(i) / 30.0)).collect();
        let square = Series::new("y = x²", xs.iter().map(|&x| (x, x * x)).collect());
        let linear = Series::new("y = 10·x", xs.iter().map(|&x| (x, 10.0 * x)).collect());
        let img = line_plot("Power laws", "x", "y", &[square, linear], true, true, 640, 480);
        assert_eq!((img.width, img.height), (640, 480));
        let count = |c: [u8; 3]| img.rgb.chunks_exact(3).filter(|p| *p == c.as_slice()).count();
        assert!(count(PALETTE[0]) > 300, "first series drawn with {} pixels", count(PALETTE[0]));
        assert!(count(PALETTE[1]) > 300, "second series drawn with {} pixels", count(PALETTE[1]));
        // y = x² rises to the right: its pixels sit higher (smaller rows) further right.
        let mean_row = |x0: f64, x1: f64| {
            let rows: Vec<f64> = (0..img.height)
                .flat_map(|y| (0..img.width).map(move |x| (x, y)))
                .filter(|&(x, y)| {
                    let fx = f64::from(x) / f64::from(img.width);
                    (x0..x1).contains(&fx) && img.pixel(x, y) == PALETTE[0]
                })
                .map(|(_, y)| f64::from(y))
                .collect();
            assert!(!rows.is_empty(), "no series pixels in columns {x0}..{x1}");
            rows.iter().sum::<f64>() / rows.len() as f64
        };
        assert!(mean_row(0.3, 0.45) > mean_row(0.55, 0.7) + 20.0);
        // Text: dark anti-aliased pixels outside the plotting area (title, ticks, labels).
        assert!(img.rgb.chunks_exact(3).filter(|p| p[0] < 60 && p[1] < 60 && p[2] < 60).count() > 200);
        let file = tempfile::Builder::new().prefix("xtask-plot-").suffix(".png").tempfile().unwrap();
        img.save_png(file.path()).unwrap();
        assert!(std::fs::metadata(file.path()).unwrap().len() > 1000);
        let tiny = line_plot("Power laws", "x", "y", &[Series::new("y = x²", vec![(10.0, 100.0)])], true, true, 64, 48);
        assert_eq!((tiny.width, tiny.height), (64, 48));
    }

    #[test]
    fn bad_points_are_dropped_not_fatal() {
        let s = Series::new("history", vec![(0.0, 1.0), (1.0, 0.0), (2.0, f64::NAN), (3.0, 1e-6)]);
        let img = line_plot("Convergence", "iteration", "max error", &[s], false, true, 320, 240);
        assert!(img.rgb.chunks_exact(3).any(|p| p == PALETTE[0].as_slice()));
        let empty = line_plot("Nothing", "x", "y", &[], true, true, 200, 150);
        assert_eq!(empty.rgb.len(), 200 * 150 * 3);
    }
}
