//! The recommendation table: for each need, the configuration the measured rows
//! pick by a rule written here (never typed by hand). Costs are medians over the
//! figures of whole-frame instructions per covered pixel; NMSE is the worst figure.

use std::fmt::Write as _;

use super::mcu::BOARDS;
use super::model::{instr, med_instr, sci};
use super::model::{Config, Kind, Row, SHININESS};
use crate::image::compare::Verdict;
use crate::scene::desc::{DivideName, ShadingName};

/// One recommendation.
#[derive(Clone, Debug, PartialEq)]
pub struct Pick {
    /// What the user needs.
    pub need: String,
    /// The configuration picked.
    pub config: Config,
    /// Median instructions per covered pixel on each core of [`BOARDS`].
    pub cost: [f64; 2],
    /// Worst NMSE over the figures, on the rule's yardstick.
    pub nmse: f64,
    /// Whether the rule found an indistinguishable candidate (else the pick is the
    /// closest one).
    pub indistinguishable: bool,
}

/// Which NMSE a rule judges by.
#[derive(Clone, Copy)]
enum Yardstick {
    /// The row's own reference.
    Own,
    /// The per-pixel (Phong) reference: highlights must survive.
    PerPixel,
}

/// The rows of each configuration matching `pred`, across figures, in table order.
fn groups<'a>(rows: &'a [Row], pred: &dyn Fn(&Config) -> bool) -> Vec<(Config, Vec<&'a Row>)> {
    let mut g: Vec<(Config, Vec<&Row>)> = Vec::new();
    for r in rows.iter().filter(|r| pred(&r.config)) {
        match g.iter_mut().find(|(c, _)| *c == r.config) {
            Some((_, v)) => v.push(r),
            None => g.push((r.config, vec![r])),
        }
    }
    g
}

/// The cheapest configuration on `core` among those matching `pred` whose worst
/// NMSE is indistinguishable; if none is, the one with the smallest worst NMSE.
fn cheapest(
    rows: &[Row],
    pred: &dyn Fn(&Config) -> bool,
    y: Yardstick,
    core: usize,
) -> Option<(Config, [f64; 2], f64, bool)> {
    let cands: Vec<(Config, [f64; 2], f64)> = groups(rows, pred)
        .into_iter()
        .map(|(c, rs)| {
            let worst = rs
                .iter()
                .map(|r| match y {
                    Yardstick::Own => r.nmse,
                    Yardstick::PerPixel => r.nmse_vs_phong,
                })
                .fold(0.0, f64::max);
            (c, [med_instr(&rs, 0), med_instr(&rs, 1)], worst)
        })
        .collect();
    let ok = |n: f64| Verdict::from_nmse(n) == Verdict::Indistinguishable;
    let best = cands
        .iter()
        .filter(|c| ok(c.2))
        .min_by(|a, b| a.1[core].total_cmp(&b.1[core]))
        .or_else(|| cands.iter().min_by(|a, b| a.2.total_cmp(&b.2)))?;
    Some((best.0, best.1, best.2, ok(best.2)))
}

/// A need answered per core: one pick when both cores pick the same, else one
/// per core.
fn per_core(
    out: &mut Vec<Pick>,
    need: &str,
    rows: &[Row],
    pred: &dyn Fn(&Config) -> bool,
    y: Yardstick,
) {
    let picks: Vec<_> = (0..BOARDS.len())
        .filter_map(|k| cheapest(rows, pred, y, k))
        .collect();
    if picks.len() == 2 && picks[0].0 == picks[1].0 {
        let p = picks[0];
        out.push(Pick {
            need: format!("{need}, either core"),
            config: p.0,
            cost: p.1,
            nmse: p.2,
            indistinguishable: p.3,
        });
    } else {
        for (k, p) in picks.into_iter().enumerate() {
            out.push(Pick {
                need: format!("{need}, on {}", BOARDS[k].1),
                config: p.0,
                cost: p.1,
                nmse: p.2,
                indistinguishable: p.3,
            });
        }
    }
}

/// Every recommendation the rows support, in a fixed order of needs.
pub fn picks(rows: &[Row]) -> Vec<Pick> {
    let mut out = Vec::new();
    per_core(
        &mut out,
        "smooth (Gouraud) shading indistinguishable from exact",
        rows,
        &|c| c.kind == Kind::Span,
        Yardstick::Own,
    );
    per_core(
        &mut out,
        "highlights inside triangles (against per-pixel lighting)",
        rows,
        &|c| {
            c.kind == Kind::Shading
                && matches!(
                    c.shading,
                    ShadingName::QUADRATIC
                        | ShadingName::ADAPTIVE
                        | ShadingName::PHONG
                        | ShadingName::PHONG_EVEN_ODD
                )
        },
        Yardstick::PerPixel,
    );
    if let Some(p) = cheapest(
        rows,
        &|c| {
            matches!(c.kind, Kind::Divide | Kind::Setup)
                && c.shading == ShadingName::GOURAUD
                && c.divide != DivideName::EXACT
        },
        Yardstick::Own,
        0,
    ) {
        out.push(Pick {
            need: format!(
                "an approximate divider on a core without a divide instruction ({})",
                BOARDS[0].1
            ),
            config: p.0,
            cost: p.1,
            nmse: p.2,
            indistinguishable: p.3,
        });
    }
    per_core(
        &mut out,
        "perspective-correct colours",
        rows,
        &|c| c.kind == Kind::Perspective && c.perspective > 0,
        Yardstick::Own,
    );
    for n in SHININESS {
        per_core(
            &mut out,
            &format!("a specular highlight at n = {n}"),
            rows,
            &|c| c.kind == Kind::Specular && c.shininess == n,
            Yardstick::Own,
        );
    }
    per_core(
        &mut out,
        "the cheapest lit frame (flat shading, HUDs)",
        rows,
        &|c| c.kind == Kind::Shading && c.shading == ShadingName::FLAT,
        Yardstick::Own,
    );
    out
}

/// The recommendation table in markdown.
pub fn markdown(rows: &[Row]) -> String {
    let mut m = String::new();
    let _ = writeln!(
        m,
        "| you need | pick | costs on {} / {} (instr/px) | NMSE |",
        BOARDS[0].1, BOARDS[1].1
    );
    let _ = writeln!(m, "|---|---|---:|---:|");
    for p in picks(rows) {
        let _ = writeln!(
            m,
            "| {} | {} | {} / {} | {}{} |",
            p.need,
            p.config.label(),
            instr(p.cost[0]),
            instr(p.cost[1]),
            sci(p.nmse),
            if p.indistinguishable {
                ""
            } else {
                " (none indistinguishable; the closest)"
            }
        );
    }
    m
}
