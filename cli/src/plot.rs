//! Figures for the example binaries, as SVG or PNG (chosen by the file extension), drawn with
//! plotters and an embedded DejaVu Sans, so no system font library is needed.
#![allow(dead_code)] // each example binary draws a different subset of these figures

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// DejaVu Sans (Bitstream Vera licence, see `fonts/LICENSE-DejaVu.txt`).
const FONT: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Colours of successive series: readable on white, distinguishable in grey.
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(127, 127, 127),
];

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in and known to parse; a failure would only lose the labels.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// The colour of series `i`.
pub fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

fn text_error(e: impl std::fmt::Display) -> String {
    format!("cannot draw the figure: {e}")
}

/// Runs `$draw(&root, args..)` on an SVG or PNG drawing area for `$path`, then writes it.
macro_rules! on_backend {
    ($path:expr, $size:expr, $draw:ident ( $($arg:expr),* )) => {{
        let path: &Path = $path;
        register_font();
        match path.extension().and_then(|e| e.to_str()) {
            Some("svg") => {
                // Drawn to a string and written here: plotters' own SVG file writer drops
                // write errors (a full disk), and this reports them.
                let mut text = String::new();
                {
                    let root = SVGBackend::with_string(&mut text, $size).into_drawing_area();
                    $draw(&root, $($arg),*)?;
                    root.present().map_err(text_error)?;
                }
                std::fs::write(path, text)
                    .map_err(|e| format!("cannot write '{}': {e}", path.display()))
            }
            Some("png") => {
                let root = BitMapBackend::new(path, $size).into_drawing_area();
                $draw(&root, $($arg),*)?;
                root.present().map_err(text_error)
            }
            _ => Err(format!(
                "cannot draw to '{}': the file name must end in .svg or .png",
                path.display()
            )),
        }
    }};
}

/// Grid lines drawn behind a point set: `cells` equal strata per axis (0 for none).
#[derive(Debug, Clone, Copy)]
pub struct Strata {
    pub x: u32,
    pub y: u32,
}

/// A scatter plot of 2-D points in the unit square, with optional strata.
pub fn scatter(
    path: &Path,
    title: &str,
    points: &[(f64, f64)],
    strata: Option<Strata>,
) -> Result<(), String> {
    on_backend!(path, (640, 680), draw_scatter(title, points, strata))
}

fn draw_scatter<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    points: &[(f64, f64)],
    strata: Option<Strata>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(text_error)?;
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FAMILY, 20))
        .margin(12)
        .x_label_area_size(28)
        .y_label_area_size(36)
        .build_cartesian_2d(0f64..1f64, 0f64..1f64)
        .map_err(text_error)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(3)
        .y_labels(3)
        .label_style((FAMILY, 12))
        .draw()
        .map_err(text_error)?;
    if let Some(s) = strata {
        let line = RGBColor(200, 200, 200);
        for i in 1..s.x {
            let x = i as f64 / s.x as f64;
            chart
                .draw_series(LineSeries::new([(x, 0.0), (x, 1.0)], line))
                .map_err(text_error)?;
        }
        for j in 1..s.y {
            let y = j as f64 / s.y as f64;
            chart
                .draw_series(LineSeries::new([(0.0, y), (1.0, y)], line))
                .map_err(text_error)?;
        }
    }
    let radius = if points.len() > 2048 { 1 } else { 2 };
    chart
        .draw_series(
            points
                .iter()
                .map(|&(x, y)| Circle::new((x, y), radius, BLACK.filled())),
        )
        .map_err(text_error)?;
    Ok(())
}

/// All pairwise projections of `d`-dimensional points (given as columns), in a `d x d` grid
/// of small scatter plots (the diagonal names the dimension).
pub fn pairs(path: &Path, title: &str, columns: &[Vec<f64>]) -> Result<(), String> {
    let d = columns.len().max(1) as u32;
    let cell = (900 / d).clamp(120, 300);
    on_backend!(path, (cell * d, cell * d + 30), draw_pairs(title, columns))
}

fn draw_pairs<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    columns: &[Vec<f64>],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(text_error)?;
    let root = root.titled(title, (FAMILY, 18)).map_err(text_error)?;
    let d = columns.len();
    let panels = root.split_evenly((d, d));
    for (k, panel) in panels.iter().enumerate() {
        let (row, col) = (k / d, k % d);
        let mut chart = ChartBuilder::on(panel)
            .margin(4)
            .build_cartesian_2d(0f64..1f64, 0f64..1f64)
            .map_err(text_error)?;
        chart
            .plotting_area()
            .draw(&Rectangle::new(
                [(0.0, 0.0), (1.0, 1.0)],
                RGBColor(180, 180, 180),
            ))
            .map_err(text_error)?;
        if row == col {
            chart
                .draw_series([Text::new(format!("dim {row}"), (0.3, 0.55), (FAMILY, 16))])
                .map_err(text_error)?;
            continue;
        }
        chart
            .draw_series(
                columns[col]
                    .iter()
                    .zip(&columns[row])
                    .map(|(&x, &y)| Circle::new((x, y), 1, BLACK.filled())),
            )
            .map_err(text_error)?;
    }
    Ok(())
}

/// One named line of a log-log plot.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A log-log plot of several series, with dashed reference lines of the given slopes
/// through the first point of the first series.
pub fn loglog(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    reference_slopes: &[f64],
) -> Result<(), String> {
    on_backend!(
        path,
        (800, 600),
        draw_loglog(title, x_label, y_label, series, reference_slopes)
    )
}

fn draw_loglog<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    reference_slopes: &[f64],
) -> Result<(), String> {
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in all.filter(|(x, y)| *x > 0.0 && *y > 0.0) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 >= x1 || y0 > y1 {
        return Err("cannot draw a log-log plot without two positive points".into());
    }
    let (y0, y1) = (y0 / 2.0, y1 * 2.0);
    root.fill(&WHITE).map_err(text_error)?;
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FAMILY, 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(text_error)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FAMILY, 12))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(text_error)?;
    if let Some(&(xa, ya)) = series.first().and_then(|s| s.points.first()) {
        for &slope in reference_slopes {
            let style = ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(1);
            let line = [(xa, ya), (x1, ya * (x1 / xa).powf(slope))];
            chart
                .draw_series(DashedLineSeries::new(line, 6, 4, style))
                .map_err(text_error)?
                .label(format!("slope {slope}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
    }
    for (i, s) in series.iter().enumerate() {
        let c = colour(i);
        chart
            .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
            .map_err(text_error)?
            .label(s.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart
            .draw_series(s.points.iter().map(|&p| Circle::new(p, 3, c.filled())))
            .map_err(text_error)?;
    }
    chart
        .configure_series_labels()
        .label_font((FAMILY, 12))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerLeft)
        .draw()
        .map_err(text_error)?;
    Ok(())
}

/// A square image of `values` (row-major, `size x size`, row 0 at the top) on a logarithmic
/// grey scale from `lo` to `hi`.
pub fn heatmap(
    path: &Path,
    title: &str,
    values: &[f64],
    size: usize,
    lo: f64,
    hi: f64,
) -> Result<(), String> {
    if size == 0 || values.len() != size * size {
        return Err(format!(
            "cannot draw a {size} x {size} image from {} values",
            values.len()
        ));
    }
    let pixels = (512 / size).max(1) as u32 * size as u32;
    on_backend!(
        path,
        (pixels + 20, pixels + 50),
        draw_heatmap(title, values, size, lo, hi)
    )
}

fn draw_heatmap<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    values: &[f64],
    size: usize,
    lo: f64,
    hi: f64,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(text_error)?;
    let area = root.titled(title, (FAMILY, 18)).map_err(text_error)?;
    let area = area.margin(5, 5, 5, 5);
    let mut chart = ChartBuilder::on(&area)
        .build_cartesian_2d(0..size, 0..size)
        .map_err(text_error)?;
    let (llo, lhi) = (lo.max(1e-300).ln(), hi.max(lo * 1.000_001).ln());
    chart
        .draw_series(values.iter().enumerate().map(|(k, &v)| {
            let (row, col) = (k / size, k % size);
            let t = ((v.max(1e-300).ln() - llo) / (lhi - llo)).clamp(0.0, 1.0);
            let g = (255.0 * t).round() as u8;
            let top = size - 1 - row;
            Rectangle::new([(col, top), (col + 1, top + 1)], RGBColor(g, g, g).filled())
        }))
        .map_err(text_error)?;
    Ok(())
}

/// A line plot of `y` against `x` on linear axes, with a dashed horizontal reference at
/// `reference` (for example the flat spectrum 1 of independent points).
pub fn line(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    reference: Option<f64>,
) -> Result<(), String> {
    on_backend!(
        path,
        (800, 500),
        draw_line(title, x_label, y_label, series, reference)
    )
}

fn draw_line<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    reference: Option<f64>,
) -> Result<(), String> {
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.points.clone()).collect();
    let x1 = all.iter().map(|p| p.0).fold(0.0, f64::max).max(1e-9);
    let y1 = all
        .iter()
        .map(|p| p.1)
        .chain(reference)
        .fold(0.0, f64::max)
        .max(1e-9)
        * 1.1;
    // Below 0 only when a value is (logarithms of small quantities).
    let y0 = all.iter().map(|p| p.1).fold(0.0, f64::min) * 1.1;
    root.fill(&WHITE).map_err(text_error)?;
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FAMILY, 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0f64..x1, y0..y1)
        .map_err(text_error)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style((FAMILY, 12))
        .draw()
        .map_err(text_error)?;
    if let Some(r) = reference {
        let style = ShapeStyle::from(&RGBColor(150, 150, 150)).stroke_width(1);
        chart
            .draw_series(DashedLineSeries::new([(0.0, r), (x1, r)], 6, 4, style))
            .map_err(text_error)?;
    }
    for (i, s) in series.iter().enumerate() {
        let c = colour(i);
        chart
            .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
            .map_err(text_error)?
            .label(s.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    if series.len() > 1 {
        chart
            .configure_series_labels()
            .label_font((FAMILY, 12))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(text_error)?;
    }
    Ok(())
}

/// One sampler's card: its points (with strata) on the left, the mean periodogram (log grey
/// scale from `lo` to `hi`) on the right, the radially averaged spectrum below.
pub struct Card<'a> {
    pub title: &'a str,
    pub points: &'a [(f64, f64)],
    pub strata: Option<Strata>,
    pub periodogram: &'a [f64],
    pub size: usize,
    pub lo: f64,
    pub hi: f64,
    pub radial: &'a [(f64, f64)],
}

/// Draws a [`Card`] into one image.
pub fn card(path: &Path, card: &Card<'_>) -> Result<(), String> {
    if card.size == 0 || card.periodogram.len() != card.size * card.size {
        return Err(format!(
            "cannot draw a {0} x {0} periodogram from {1} values",
            card.size,
            card.periodogram.len()
        ));
    }
    on_backend!(path, (1100, 860), draw_card(card))
}

fn draw_card<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    card: &Card<'_>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(text_error)?;
    let root = root.titled(card.title, (FAMILY, 22)).map_err(text_error)?;
    let (top, bottom) = root.split_vertically(560);
    let (left, right) = top.split_horizontally(550);
    draw_scatter(&left, "points", card.points, card.strata)?;
    draw_heatmap(
        &right,
        "mean periodogram",
        card.periodogram,
        card.size,
        card.lo,
        card.hi,
    )?;
    let series = [Series {
        name: "radial power".into(),
        points: card.radial.to_vec(),
    }];
    draw_line(
        &bottom,
        "radially averaged power spectrum",
        "frequency |k|",
        "power",
        &series,
        Some(1.0),
    )
}
