//! The report's charts: NMSE against the per-pixel reference (log y) against a cost
//! (log x): instructions per covered pixel on one core (one chart per core of
//! [`BOARDS`]), or host ns per pixel (the secondary chart). Each figure's Pareto
//! front is a line and only its points are labelled, placed by
//! [`crate::chart::labels::place`] so that no label overlaps another label, a
//! marker or the legend; the other rows are dots coloured by kind.

use plotters::prelude::*;

use super::mcu::BOARDS;
use super::model::{pareto_front, Kind, Row, STEM};
use crate::chart::labels::{self, Rect};
use crate::chart::plot::{Canvas, Label};

const W: u32 = 1100;
const H: u32 = 760;

/// What a chart plots on x.
#[derive(Clone, Copy, Debug)]
pub enum Cost {
    /// Whole-frame instructions per covered pixel on core `k` of [`BOARDS`].
    Mcu(usize),
    /// Host ns per covered pixel.
    Host,
}

/// A chart: its cost axis and title.
pub struct ChartSpec {
    /// The x axis.
    pub cost: Cost,
}

impl ChartSpec {
    /// The chart of core `k` of [`BOARDS`].
    pub fn core(k: usize) -> ChartSpec {
        ChartSpec { cost: Cost::Mcu(k) }
    }

    /// The secondary host-time chart.
    pub fn host() -> ChartSpec {
        ChartSpec { cost: Cost::Host }
    }

    fn x(&self, r: &Row) -> f64 {
        match self.cost {
            Cost::Mcu(k) => r.mcu[k].per_pixel,
            Cost::Host => r.ns_per_px,
        }
    }

    fn x_title(&self) -> String {
        match self.cost {
            Cost::Mcu(k) => format!("{} instructions per covered pixel (log)", BOARDS[k].1),
            Cost::Host => "host ns per covered pixel (log)".to_string(),
        }
    }
}

/// File name of the chart of core `k`: `accuracy-vs-time-m0.png` (ARMv6-M),
/// `accuracy-vs-time-m4.png`.
pub fn core_file(k: usize) -> String {
    format!("{STEM}-{}.png", ["m0", "m4"][k.min(1)])
}

const FIGURE_COLORS: [RGBColor; 3] = [
    RGBColor(0, 0, 0),
    RGBColor(150, 40, 40),
    RGBColor(40, 40, 170),
];

/// Colours of the kinds, in the order of [`KINDS`].
const KIND_COLORS: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

const KINDS: [Kind; 6] = [
    Kind::Span,
    Kind::Shading,
    Kind::Divide,
    Kind::Setup,
    Kind::Perspective,
    Kind::Specular,
];

fn kind_color(k: Kind) -> RGBColor {
    KIND_COLORS[KINDS.iter().position(|x| *x == k).unwrap_or(0)]
}

/// The label of a front point: the configuration's name, with its sweep where
/// the name alone is ambiguous.
fn short(r: &Row) -> String {
    match r.config.kind {
        Kind::Span | Kind::Shading => r.config.name(),
        k => format!("{} {}", k.as_str(), r.config.name()),
    }
}

/// Decades from `lo` to `hi` (at least one).
fn decades(lo: f64, hi: f64) -> (i32, i32) {
    let a = lo.log10().floor() as i32;
    let b = (hi.log10().ceil() as i32).max(a + 1);
    (a, b)
}

/// The chart as PNG bytes.
pub fn png_bytes(spec: &ChartSpec, rows: &[Row], figures: &[String]) -> Result<Vec<u8>, String> {
    let mut canvas = Canvas::new(W, H);
    let labels = draw(spec, rows, figures, &mut canvas.buf).map_err(|e| format!("chart: {e}"))?;
    canvas.png_bytes(&labels)
}

fn draw(
    spec: &ChartSpec,
    rows: &[Row],
    figures: &[String],
    buf: &mut [u8],
) -> Result<Vec<Label>, Box<dyn std::error::Error>> {
    let black = RGBColor(0, 0, 0);
    let grey = RGBColor(220, 220, 220);
    let mut labels = Vec::new();
    let rows: Vec<&Row> = rows
        .iter()
        .filter(|r| spec.x(r).is_finite() && spec.x(r) > 0.0)
        .collect();
    // NMSE 0 (identical to the reference) is drawn on the floor, a decade below the
    // smallest positive NMSE.
    let min_pos = rows
        .iter()
        .map(|r| r.nmse_vs_phong)
        .filter(|n| *n > 0.0)
        .fold(f64::INFINITY, f64::min);
    let floor = if min_pos.is_finite() {
        10f64.powf(min_pos.log10().floor() - 1.0)
    } else {
        1e-9
    };
    let y = |r: &Row| r.nmse_vs_phong.max(floor);
    let (xlo_e, xhi_e) = decades(
        rows.iter()
            .map(|r| spec.x(r))
            .fold(f64::INFINITY, f64::min)
            .min(1e9),
        rows.iter().map(|r| spec.x(r)).fold(1.0, f64::max),
    );
    let (ylo_e, yhi_e) = decades(floor, rows.iter().map(|r| y(r)).fold(floor, f64::max));
    let (xlo, xhi) = (10f64.powi(xlo_e), 10f64.powi(xhi_e));
    let (ylo, yhi) = (10f64.powi(ylo_e), 10f64.powi(yhi_e));

    let root = BitMapBackend::with_buffer(buf, (W, H)).into_drawing_area();
    root.fill(&WHITE)?;
    let chart = ChartBuilder::on(&root)
        .margin_top(50)
        .margin_right(250)
        .margin_left(90)
        .margin_bottom(60)
        .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())?;
    let px = |x: f64, y: f64| chart.backend_coord(&(x, y));
    let area = chart.plotting_area();

    // Grid and ticks: 1, 2, 5 per decade on x, decades on y.
    for e in xlo_e..xhi_e + 1 {
        for m in [1.0, 2.0, 5.0] {
            let x = m * 10f64.powi(e);
            if x < xlo || x > xhi {
                continue;
            }
            area.draw(&PathElement::new(
                vec![(x, ylo), (x, yhi)],
                grey.stroke_width(1),
            ))?;
            let (bx, by) = px(x, ylo);
            let t = if x >= 1.0 {
                format!("{x:.0}")
            } else {
                format!("{x}")
            };
            labels.push(Label {
                x: bx - 6 * t.len() as i32,
                y: by + 8,
                text: t,
                scale: 2,
                color: black,
            });
        }
    }
    for e in ylo_e..=yhi_e {
        let v = 10f64.powi(e);
        area.draw(&PathElement::new(
            vec![(xlo, v), (xhi, v)],
            grey.stroke_width(1),
        ))?;
        let (bx, by) = px(xlo, v);
        let t = format!("1e{e}");
        labels.push(Label {
            x: bx - 12 * t.len() as i32 - 8,
            y: by - 7,
            text: t,
            scale: 2,
            color: black,
        });
    }
    let (x0, y0) = px(xlo, ylo);
    let (x1, y1) = px(xhi, yhi);
    root.draw(&Rectangle::new([(x0, y1), (x1, y0)], black.stroke_width(1)))?;
    let xt = spec.x_title();
    labels.push(Label {
        x: (x0 + x1) / 2 - 6 * xt.len() as i32,
        y: y0 + 32,
        text: xt,
        scale: 2,
        color: black,
    });
    labels.push(Label {
        x: 10,
        y: 8,
        text: "NMSE against the per-pixel f64 reference (log)".into(),
        scale: 2,
        color: black,
    });

    // Dots by kind, then each figure's front on top.
    let mut obstacles: Vec<Rect> = Vec::new();
    for r in &rows {
        let p = (spec.x(r), y(r));
        area.draw(&Circle::new(p, 3, kind_color(r.config.kind).filled()))?;
        let (bx, by) = px(p.0, p.1);
        obstacles.push(Rect::around(bx, by, 3));
    }
    let mut anchors = Vec::new();
    let mut texts = Vec::new();
    let mut colors = Vec::new();
    for (fi, f) in figures.iter().enumerate() {
        let col = FIGURE_COLORS[fi % FIGURE_COLORS.len()];
        let mine: Vec<&Row> = rows.iter().copied().filter(|r| &r.figure == f).collect();
        let on = match spec.cost {
            Cost::Mcu(k) => mine.iter().map(|r| r.pareto[k]).collect(),
            Cost::Host => pareto_front(
                &mine
                    .iter()
                    .map(|r| (r.ns_per_px, r.nmse_vs_phong))
                    .collect::<Vec<_>>(),
            ),
        };
        let mut front: Vec<&Row> = mine
            .iter()
            .zip(on)
            .filter(|(_, o)| *o)
            .map(|(r, _)| *r)
            .collect();
        front.sort_by(|a, b| spec.x(a).total_cmp(&spec.x(b)));
        area.draw(&PathElement::new(
            front.iter().map(|r| (spec.x(r), y(r))).collect::<Vec<_>>(),
            col.stroke_width(2),
        ))?;
        for r in &front {
            let p = (spec.x(r), y(r));
            area.draw(&Circle::new(p, 6, col.stroke_width(2)))?;
            let (bx, by) = px(p.0, p.1);
            obstacles.push(Rect::around(bx, by, 7));
            anchors.push((bx, by));
            texts.push(format!("{}: {}", f, short(r)));
            colors.push(col);
        }
    }

    // Legend, right of the plot: (marker: front line or kind dot, text, colour).
    let mut entries: Vec<(bool, String, RGBColor)> = Vec::new();
    for (fi, f) in figures.iter().enumerate() {
        entries.push((
            true,
            format!("{f} front"),
            FIGURE_COLORS[fi % FIGURE_COLORS.len()],
        ));
    }
    for (k, col) in KINDS.iter().zip(KIND_COLORS) {
        if rows.iter().any(|r| r.config.kind == *k) {
            entries.push((false, k.as_str().to_string(), col));
        }
    }
    let lx = x1 + 20;
    let mut ly = y1;
    for (line, text, col) in entries {
        if line {
            root.draw(&PathElement::new(
                vec![(lx - 4, ly + 7), (lx + 10, ly + 7)],
                col.stroke_width(2),
            ))?;
            root.draw(&Circle::new((lx + 3, ly + 7), 6, col.stroke_width(2)))?;
        } else {
            root.draw(&Circle::new((lx + 3, ly + 7), 4, col.filled()))?;
        }
        labels.push(Label {
            x: lx + 16,
            y: ly,
            text,
            scale: 2,
            color: col,
        });
        ly += 24;
    }
    labels.push(Label {
        x: lx - 4,
        y: ly + 10,
        text: format!("NMSE 0 at 1e{ylo_e}"),
        scale: 2,
        color: black,
    });
    area.draw(&PathElement::new(
        vec![(xlo, floor), (xhi, floor)],
        RGBColor(120, 120, 120).stroke_width(1),
    ))?;

    // Front labels, inside the plot area, never over a marker or each other.
    let bounds = Rect {
        x0: x0 + 1,
        y0: y1 + 1,
        x1,
        y1: y0,
    };
    let chars: Vec<usize> = texts.iter().map(|t| t.chars().count()).collect();
    for (i, spot) in labels::place(&anchors, &chars, &obstacles, bounds)
        .into_iter()
        .enumerate()
    {
        if let Some((x, y)) = spot {
            labels.push(Label {
                x,
                y,
                text: texts[i].clone(),
                scale: 1,
                color: colors[i],
            });
        }
    }
    root.present()?;
    Ok(labels)
}
