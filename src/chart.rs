//! The comparison chart: for each scene, wall time (log) against the fraction of contacts
//! missed and against the median contact-time error, one point per method and step.

use crate::compare::Row;
use kinetic_render::Frame;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;

/// Where a system font may be found (DejaVu ships with most Linux distributions).
const FONTS: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
];

/// Registers the first font found as "sans-serif", once.
fn font() -> Result<(), String> {
    static FONT: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    FONT.get_or_init(|| {
        let bytes = FONTS
            .iter()
            .find_map(|p| std::fs::read(p).ok())
            .ok_or_else(|| {
                format!(
                    "no font found for the chart's text (tried {})",
                    FONTS.join(", ")
                )
            })?;
        register_font("sans-serif", FontStyle::Normal, Vec::leak(bytes))
            .map_err(|_| "the chart's font could not be read".to_string())
    })
    .clone()
}

/// Errors below this are drawn on the axis floor (kinetic structures are exact: 0).
const ERROR_FLOOR: f64 = 1e-10;

/// The colour of a method.
fn colour(method: &str) -> RGBColor {
    match method {
        "stepped" => RGBColor(31, 119, 180),
        "rapier" => RGBColor(214, 39, 40),
        "rapier+ccd" => RGBColor(255, 127, 14),
        "rapier+kinetic" => RGBColor(44, 160, 44),
        "brute-force" => RGBColor(90, 90, 90),
        "guards" => RGBColor(140, 86, 75),
        "grid" => RGBColor(227, 119, 194),
        "rolling-global-lists" => RGBColor(188, 189, 34),
        _ => RGBColor(148, 103, 189),
    }
}

/// Draws the chart for `rows` (in scene order) to a PNG at `path`.
pub fn draw(rows: &[Row], path: &Path) -> Result<(), String> {
    font()?;
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    if scenes.is_empty() {
        return Err("nothing to chart".into());
    }
    let (w, h) = (1400u32, 380 * scenes.len() as u32);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let panels = root.split_evenly((scenes.len(), 2));
        for (k, scene) in scenes.iter().enumerate() {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.scene == *scene).collect();
            panel(&panels[2 * k], scene, &mine, Axis::Missed).map_err(|e| e.to_string())?;
            panel(&panels[2 * k + 1], scene, &mine, Axis::Error).map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    Frame::new(w, h, rgba)
        .save_png(path)
        .map_err(|e| e.to_string())
}

/// An axis label: plain for tenths, powers of ten otherwise.
fn short(x: f64) -> String {
    if x == 0.0 || (x.abs() >= 0.1 && x.abs() <= 1.0) {
        format!("{x:.1}")
    } else {
        format!("{x:.0e}")
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Axis {
    Missed,
    Error,
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

fn panel(
    area: &Area,
    scene: &str,
    rows: &[&Row],
    axis: Axis,
) -> Result<(), Box<dyn std::error::Error>> {
    let times = rows.iter().map(|r| r.wall_seconds.max(1e-5));
    let (lo, hi) = times.fold((f64::INFINITY, 0.0f64), |(lo, hi), t| {
        (lo.min(t), hi.max(t))
    });
    let (lo, hi) = (lo / 2.0, hi * 2.0);
    let x_of = |r: &Row| match axis {
        Axis::Missed => r.missed_fraction,
        Axis::Error => r.time_error_median.unwrap_or(f64::NAN).max(ERROR_FLOOR),
    };
    let caption = match axis {
        Axis::Missed => format!(
            "{scene} ({}): missed contacts",
            rows.first().map_or(0, |r| r.objects)
        ),
        Axis::Error => format!("{scene}: median contact-time error"),
    };
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(64);
    let mut legend_done = std::collections::BTreeSet::new();
    macro_rules! body {
        ($chart:expr, $xdesc:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc($xdesc)
                .y_desc("wall time (s)")
                .label_style(("sans-serif", 13))
                .x_label_formatter(&|x: &f64| short(*x))
                .y_label_formatter(&|y: &f64| short(*y))
                .draw()?;
            for r in rows {
                let x = x_of(r);
                if x.is_nan() {
                    continue;
                }
                let c = colour(r.method);
                let p = (x, r.wall_seconds.max(1e-5));
                let label = if r.default {
                    format!("{} (default)", r.method)
                } else if r.step == "exact" {
                    r.method.to_string()
                } else {
                    r.step.clone()
                };
                let font = ("sans-serif", 12).into_font().color(&c);
                let point = EmptyElement::at(p)
                    + Circle::new((0, 0), 5, c.filled())
                    + Text::new(label, (7, -4), font);
                let series = chart.draw_series(std::iter::once(point))?;
                if axis == Axis::Missed && legend_done.insert(r.method) {
                    series
                        .label(r.method)
                        .legend(move |(x, y)| Circle::new((x, y), 5, c.filled()));
                }
            }
            if axis == Axis::Missed {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 13))
                    .position(SeriesLabelPosition::UpperMiddle)
                    .draw()?;
            }
        }};
    }
    match axis {
        Axis::Missed => body!(
            builder.build_cartesian_2d(-0.02f64..1.02f64, (lo..hi).log_scale())?,
            "fraction of contacts missed"
        ),
        Axis::Error => body!(
            builder.build_cartesian_2d(
                (ERROR_FLOOR / 2.0..2.0f64).log_scale(),
                (lo..hi).log_scale()
            )?,
            "median |detected - exact| contact time (s); exact methods on the floor"
        ),
    }
    Ok(())
}
