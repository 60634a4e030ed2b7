//! The comparison chart: for each scene, wall time (log) against the fraction of contacts
//! missed and against the median contact-time error, one point per method and step.

use crate::compare::Row;
use kinetic_render::Frame;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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

/// Every method the chart may show, each with a colour and a marker of its own (the
/// kinetic structures first, then the time-stepped methods).
const METHODS: [(&str, RGBColor, Marker); 17] = [
    ("rolling-tree", RGBColor(148, 103, 189), Marker::Circle),
    (
        "rolling-global-lists",
        RGBColor(188, 189, 34),
        Marker::Square,
    ),
    ("sweep", RGBColor(23, 190, 207), Marker::Triangle),
    ("guards", RGBColor(140, 86, 75), Marker::Diamond),
    ("grid", RGBColor(227, 119, 194), Marker::Square),
    ("loose-grid", RGBColor(0, 90, 50), Marker::Circle),
    ("cells", RGBColor(120, 60, 160), Marker::Triangle),
    ("lists", RGBColor(160, 120, 40), Marker::Circle),
    ("periodic", RGBColor(60, 60, 160), Marker::Diamond),
    ("brute-force", RGBColor(90, 90, 90), Marker::Cross),
    ("stepped", RGBColor(31, 119, 180), Marker::Circle),
    ("rapier", RGBColor(214, 39, 40), Marker::Square),
    ("rapier+ccd", RGBColor(255, 127, 14), Marker::Triangle),
    ("rapier+kinetic", RGBColor(44, 160, 44), Marker::Diamond),
    ("avian", RGBColor(75, 0, 130), Marker::Square),
    ("avian+ccd", RGBColor(128, 128, 0), Marker::Triangle),
    ("avian+kinetic", RGBColor(0, 128, 128), Marker::Diamond),
];

/// A point's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
}

/// The colour and marker of a method (black circles for one the chart does not know).
fn style(method: &str) -> (RGBColor, Marker) {
    METHODS
        .iter()
        .find(|(m, ..)| *m == method)
        .map_or((BLACK, Marker::Circle), |&(_, c, k)| (c, k))
}

/// Draws `marker` in colour `c` centred at pixel `(x, y)` of `area`.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (x, y): (i32, i32),
    marker: Marker,
    c: RGBColor,
) -> Result<(), String> {
    let fill = c.filled();
    let r = 5;
    let result = match marker {
        Marker::Circle => area.draw(&Circle::new((x, y), r, fill)),
        Marker::Square => area.draw(&Rectangle::new(
            [(x - r + 1, y - r + 1), (x + r - 1, y + r - 1)],
            fill,
        )),
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x - r, y + r - 1), (x + r, y + r - 1)],
            fill,
        )),
        Marker::Diamond => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x + r, y), (x, y + r + 1), (x - r, y)],
            fill,
        )),
        Marker::Cross => {
            let s = c.stroke_width(2);
            area.draw(&PathElement::new(vec![(x - r, y - r), (x + r, y + r)], s))
                .and_then(|()| {
                    area.draw(&PathElement::new(vec![(x - r, y + r), (x + r, y - r)], s))
                })
        }
    };
    result.map_err(|e| e.to_string())
}

/// Height of the legend strip above each scene's panels, in pixels.
const LEGEND_HEIGHT: u32 = 34;

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
    let (w, h) = (1400u32, (380 + LEGEND_HEIGHT) * scenes.len() as u32);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let rows_of = root.split_evenly((scenes.len(), 1));
        for (k, scene) in scenes.iter().enumerate() {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.scene == *scene).collect();
            let (strip, panels) = rows_of[k].split_vertically(LEGEND_HEIGHT);
            legend(&strip, &mine)?;
            let halves = panels.split_evenly((1, 2));
            panel(&halves[0], scene, &mine, Axis::Missed).map_err(|e| e.to_string())?;
            panel(&halves[1], scene, &mine, Axis::Error).map_err(|e| e.to_string())?;
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

/// The legend of one scene's methods, in a strip of its own above its panels (never over
/// the data): each method's marker and name, in the order they first appear.
fn legend(strip: &Area, rows: &[&Row]) -> Result<(), String> {
    let mut x = 76;
    let mut seen: Vec<&str> = Vec::new();
    for r in rows {
        if seen.contains(&r.method) {
            continue;
        }
        seen.push(r.method);
        let (c, m) = style(r.method);
        draw_marker(strip, (x, 20), m, c)?;
        let name = if r.default {
            format!("{} (default)", r.method)
        } else {
            r.method.to_string()
        };
        let font = ("sans-serif", 13).into_font().color(&c);
        let (width, _) = strip
            .estimate_text_size(&name, &font)
            .map_err(|e| e.to_string())?;
        strip
            .draw(&Text::new(name, (x + 9, 13), font))
            .map_err(|e| e.to_string())?;
        x += width as i32 + 30;
    }
    Ok(())
}

/// Pixel rectangles of the labels placed so far in a panel, to keep new ones off them.
struct Placed {
    /// The plotting area's size in pixels: a label stays inside it.
    size: (i32, i32),
    labels: Vec<(i32, i32, i32, i32)>,
}

impl Placed {
    fn new(size: (u32, u32)) -> Self {
        Self {
            size: (size.0 as i32, size.1 as i32),
            labels: Vec::new(),
        }
    }

    /// Where the top-left corner of a label `width` x `height` pixels goes beside the point
    /// at pixel `p`: the first spot, nearest first (right, left, above, below, then the
    /// diagonals, then twice as far), that stays inside the plot and meets no label already
    /// placed and no point (each point is a 12-pixel box); `None` when every spot does, and
    /// the label is left out.
    fn place(
        &mut self,
        p: (i32, i32),
        width: i32,
        height: i32,
        points: &[(i32, i32)],
    ) -> Option<(i32, i32)> {
        let meets = |a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)| {
            a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
        };
        for gap in [8, 16] {
            let (right, left) = (p.0 + gap, p.0 - gap - width);
            let (above, below) = (p.1 - gap - height, p.1 + gap);
            let (middle_x, middle_y) = (p.0 - width / 2, p.1 - height / 2);
            let tries = [
                (right, middle_y),
                (left, middle_y),
                (middle_x, above),
                (middle_x, below),
                (right, above),
                (right, below),
                (left, above),
                (left, below),
            ];
            for (x, y) in tries {
                let rect = (x, y, x + width, y + height);
                let inside = x >= 0 && y >= 0 && rect.2 <= self.size.0 && rect.3 <= self.size.1;
                let clear = inside
                    && self.labels.iter().all(|&r| !meets(r, rect))
                    && points
                        .iter()
                        .all(|&(px, py)| !meets((px - 6, py - 6, px + 6, py + 6), rect));
                if clear {
                    self.labels.push(rect);
                    return Some((x, y));
                }
            }
        }
        None
    }
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
            let shown: Vec<(&Row, (i32, i32))> = rows
                .iter()
                .filter(|r| !x_of(r).is_nan())
                .map(|r| {
                    (
                        *r,
                        chart.backend_coord(&(x_of(r), r.wall_seconds.max(1e-5))),
                    )
                })
                .collect();
            let points: Vec<(i32, i32)> = shown.iter().map(|(_, p)| *p).collect();
            let root = chart.plotting_area().strip_coord_spec();
            let (dx, dy) = root.get_base_pixel();
            let mut placed = Placed::new(root.dim_in_pixel());
            for &(r, (px, py)) in &shown {
                let (c, m) = style(r.method);
                let at = (px - dx, py - dy);
                draw_marker(&root, at, m, c)?;
                if r.default {
                    root.draw(&Circle::new(at, 9, c.stroke_width(2)))?;
                }
                // The stepped methods' points say their step; the exact ones are named by
                // the legend.
                if r.step != "exact" {
                    let label = r.step.clone();
                    let font = ("sans-serif", 12)
                        .into_font()
                        .color(&c)
                        .pos(Pos::new(HPos::Left, VPos::Top));
                    let (width, height) = root.estimate_text_size(&label, &font)?;
                    let local: Vec<(i32, i32)> =
                        points.iter().map(|&(x, y)| (x - dx, y - dy)).collect();
                    if let Some(spot) = placed.place(at, width as i32, height as i32, &local) {
                        root.draw(&Text::new(label, spot, font))?;
                    }
                }
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
