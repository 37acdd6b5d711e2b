//! PNG plots for the benchmarks: panels of log-log scatter or line series,
//! with a Pareto front where one is given. Text needs a font: the one
//! Bevy's `default_font` feature carries (on with the default `app`
//! feature); without it the plot is skipped with a note.

use std::path::Path;

/// One set of points in a panel.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// RGB colour.
    pub color: (u8, u8, u8),
    /// (x, y) points; drawn joined in order when `line` is set.
    pub points: Vec<(f64, f64)>,
    /// Join the points.
    pub line: bool,
}

/// One chart.
pub struct Panel {
    /// Caption.
    pub title: String,
    /// X axis label.
    pub x: String,
    /// Y axis label.
    pub y: String,
    /// The data.
    pub series: Vec<Series>,
    /// Points of the Pareto front, drawn as a black step line.
    pub front: Vec<(f64, f64)>,
}

/// The points of `points` that no other point beats on both coordinates
/// (lower x and lower y), sorted by x.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<_> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in sorted {
        if front.last().is_none_or(|last| p.1 < last.1) {
            front.push(p);
        }
    }
    front
}

/// Colours for series, in order.
pub const PALETTE: [(u8, u8, u8); 6] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
];

/// Draws `panels` in a grid `cols` wide into a PNG at `path`; values are
/// clamped below at `floor` so zeros show on the log axes.
///
/// # Errors
/// Drawing or writing failed, or there is no font (built without the
/// `app` feature): the message says which.
pub fn draw(path: &Path, panels: &[Panel], cols: usize, floor: f64) -> Result<(), String> {
    font()?;
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (420 * cols as u32, 340 * rows as u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    draw_into(&mut buf, (w, h), panels, (rows, cols), floor).map_err(|e| format!("plot: {e}"))?;
    image::save_buffer(path, &buf, w, h, image::ColorType::Rgb8).map_err(|e| format!("{}: {e}", path.display()))
}

fn draw_into(
    buf: &mut [u8],
    size: (u32, u32),
    panels: &[Panel],
    grid: (usize, usize),
    floor: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let root = BitMapBackend::with_buffer(buf, size).into_drawing_area();
    root.fill(&WHITE)?;
    for (area, panel) in root.split_evenly(grid).iter().zip(panels) {
        let clamp = |(x, y): (f64, f64)| (x.max(floor), y.max(floor));
        // Each series' finite points, clamped, as drawn.
        let drawn: Vec<(Vec<(f64, f64)>, bool)> = panel
            .series
            .iter()
            .map(|s| {
                let points = s.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite());
                (points.map(clamp).collect(), s.line)
            })
            .collect();
        let range = |f: fn(&(f64, f64)) -> f64| {
            let all = drawn.iter().flat_map(|(points, _)| points);
            let lo = all.clone().map(f).fold(f64::INFINITY, f64::min);
            let hi = all.map(f).fold(f64::NEG_INFINITY, f64::max);
            if lo.is_finite() && hi.is_finite() {
                (lo / 1.5)..(hi * 1.5).max(lo * 2.0)
            } else {
                floor..1.0
            }
        };
        let (xr, yr) = (range(|p| p.0), range(|p| p.1));
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(34)
            .y_label_area_size(58)
            .build_cartesian_2d(xr.clone().log_scale(), yr.clone().log_scale())?;
        // Labels at 1, 2 and 5 of each decade only, and faint minor lines:
        // a log axis keys every 1-9 of each decade (and 10 twice, as the
        // last of one decade and the first of the next), whose labels ran
        // into one another and whose lines shaded whole decades grey.
        chart
            .configure_mesh()
            .x_desc(panel.x.as_str())
            .y_desc(panel.y.as_str())
            .label_style(("sans-serif", 11))
            .x_labels(10)
            .y_labels(10)
            .max_light_lines(1)
            .light_line_style(RGBColor(238, 238, 238))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .draw()?;
        for (s, (points, _)) in panel.series.iter().zip(&drawn) {
            let color = RGBColor(s.color.0, s.color.1, s.color.2);
            if s.line {
                chart.draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))?;
            }
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))?
                .label(s.label.as_str())
                .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
        }
        if !panel.front.is_empty() {
            let front: Vec<_> = panel.front.iter().copied().map(clamp).collect();
            chart
                .draw_series(LineSeries::new(front, BLACK.stroke_width(1)))?
                .label("Pareto front")
                .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK));
        }
        let entries = panel.series.len() + usize::from(!panel.front.is_empty());
        chart
            .configure_series_labels()
            .position(legend_corner(&drawn, (xr.start, xr.end), (yr.start, yr.end), entries))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// A tick's label: none unless `v` is 1, 2 or 5 times a power of ten;
/// whole numbers from 10 up, else two significant digits (0.25, 1.5,
/// 0.0012), trailing zeros dropped.
fn tick(v: f64) -> String {
    if v.is_finite() && v != 0.0 {
        let mantissa = v.abs() / 10f64.powf(v.abs().log10().floor());
        if ![1.0, 2.0, 5.0, 10.0].iter().any(|m| (mantissa - m).abs() < 1e-6) {
            return String::new();
        }
    }
    if !v.is_finite() || v == 0.0 || v.abs() >= 10.0 {
        return format!("{v:.0}");
    }
    let digits = (1 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The corner whose legend box (`entries` lines of it) covers the fewest
/// of `series`' points and line samples, in the panel's log-log frame
/// `x` by `y` (the first such of upper right, upper left, lower right,
/// lower left).
fn legend_corner(
    series: &[(Vec<(f64, f64)>, bool)],
    x: (f64, f64),
    y: (f64, f64),
    entries: usize,
) -> plotters::chart::SeriesLabelPosition {
    use plotters::chart::SeriesLabelPosition as Corner;
    let unit = |v: f64, (lo, hi): (f64, f64)| (v.log10() - lo.log10()) / (hi.log10() - lo.log10());
    let mut samples: Vec<(f64, f64)> = Vec::new();
    for (points, line) in series {
        let at: Vec<(f64, f64)> = points.iter().map(|&(a, b)| (unit(a, x), unit(b, y))).collect();
        samples.extend(&at);
        if *line {
            for w in at.windows(2) {
                samples.extend((1..8).map(|k| {
                    let t = f64::from(k) / 8.0;
                    (w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1))
                }));
            }
        }
    }
    // The legend box: about 40% of the plot's width, a line per entry.
    let (w, h) = (0.42, (0.06 + 0.075 * entries as f64).min(0.7));
    let count = |right: bool, upper: bool| {
        samples
            .iter()
            .filter(|(u, v)| {
                let inside_x = if right { *u >= 1.0 - w } else { *u <= w };
                let inside_y = if upper { *v >= 1.0 - h } else { *v <= h };
                inside_x && inside_y
            })
            .count()
    };
    [
        (Corner::UpperRight, count(true, true)),
        (Corner::UpperLeft, count(false, true)),
        (Corner::LowerRight, count(true, false)),
        (Corner::LowerLeft, count(false, false)),
    ]
    .into_iter()
    .min_by_key(|(_, n)| *n)
    .map_or(Corner::UpperRight, |(c, _)| c)
}

fn font() -> Result<(), String> {
    use plotters::style::FontStyle;
    static REGISTERED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font("sans-serif", FontStyle::Normal, bevy::text::DEFAULT_FONT_DATA)
                .map_err(|_| "plot: Bevy's default font did not load".to_string())
        })
        .clone()
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::chart::SeriesLabelPosition as Corner;

    #[test]
    fn ticks_read_as_numbers() {
        assert_eq!(tick(100.0), "100");
        assert_eq!(tick(20.0), "20");
        assert_eq!(tick(2.0), "2");
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(0.002), "0.002");
        assert_eq!(tick(5e-4), "0.0005");
        // Ten reached as nine steps of a decade past one.
        assert_eq!(tick(1.0 + 9.0 * (1.0 + 1e-15)), "10");
        // The other keys of a decade go unlabelled.
        assert_eq!(tick(3.0), "");
        assert_eq!(tick(70.0), "");
        assert_eq!(tick(0.25), "");
    }

    #[test]
    fn the_legend_goes_where_the_points_are_not() {
        let frame = ((0.5, 32.0), (0.5, 512.0));
        // Rising, joined: the upper left is empty (the first empty corner
        // after the upper right, which the line runs into).
        let rising: Vec<_> = (0..=4).map(|k| (f64::from(1 << k), f64::from(1 << (2 * k)))).collect();
        let one = [(rising.clone(), true)];
        assert_eq!(legend_corner(&one, frame.0, frame.1, 3), Corner::UpperLeft);
        // A flat line along the top as well: the lower right is left.
        let top: Vec<_> = (0..=4).map(|k| (f64::from(1 << k), 400.0)).collect();
        let two = [(rising, true), (top, true)];
        assert_eq!(legend_corner(&two, frame.0, frame.1, 3), Corner::LowerRight);
        assert_eq!(legend_corner(&[], frame.0, frame.1, 3), Corner::UpperRight);
    }
}
