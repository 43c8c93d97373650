//! The divider sweep of `cargo xtask qemu`. The images built with the feature
//! `dividers` draw `classic` and `gradient` with the 28 dividers of the `Divide`
//! seam (boards/common: `divider_cases`) on the Cortex-M4 and on the full-frame
//! ARMv6-M image. Their frames are named `span@divider`; the host renders them with
//! that span method and divider (`fixshade render --divide`), as
//! `WithDivide<Classic<D>, D>` and `WithDivide<Gradient, D>`.
//!
//! Each image also draws the `exact` pair, so every divider is compared with
//! `exact` compiled into the same image (the span-method images inline the
//! pipeline differently, a few per cent apart).

use std::fmt::Write as _;

use fixshade_sim::scene::desc::{DivideName, Named, SceneDesc, SpanName};

use super::{fmt_per, m4, v6m, FrameRow, Image, Kind};

/// The divider images, run after the others: the Cortex-M4, then ARMv6-M.
pub(super) const IMAGES: &[Image] = &[
    m4("dividers", "fixshade-qemu-mps2-an386", Kind::Figures),
    v6m("dividers", "fixshade-qemu-mps2-an386", Kind::Figures),
];

/// `span@divider` → `(span, divider)`; `None` for a case of the span-method images.
pub(super) fn split(case: &str) -> Option<(&str, &str)> {
    case.split_once('@')
}

/// Sets the host scene's span method and divider from a case name.
pub(super) fn apply(desc: &mut SceneDesc, case: &str) -> Result<(), String> {
    match split(case) {
        Some((span, divider)) => {
            desc.span = SpanName::parse(span)?;
            desc.divide = DivideName::parse(divider)?;
        }
        None => {
            desc.span = SpanName::parse(case)?;
            desc.divide = DivideName::EXACT;
        }
    }
    Ok(())
}

/// The CSV's `method`, `divide` and `sweep` of a case: `sweep` is `span` for the
/// span-method images, `divide` for the divider images (whose `exact` rows are that
/// image's own reference).
pub(super) fn csv_names(case: &str) -> (&str, &str, &str) {
    match split(case) {
        Some((span, divider)) => (span, divider, "divide"),
        None => (case, "exact", "span"),
    }
}

/// The markdown section: per board and figure, every divider against the same
/// image's `exact`.
pub(super) fn section(rows: &[FrameRow]) -> String {
    let div: Vec<&FrameRow> = rows
        .iter()
        .filter(|r| {
            split(&r.case).is_some()
                && !super::perspective::is_case(&r.case)
                && !super::report::is_case(&r.case)
        })
        .collect();
    if div.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Dividers\n\n\
         `classic` (the divider in its per-span division and in the setup's reciprocal)\n\
         and `gradient` (the divider in the setup's reciprocal) with each divider of the\n\
         `Divide` seam, drawn as `fixshade render --divide NAME` draws them and compared\n\
         byte for byte with that host render. The Cortex-M4 and the full-frame ARMv6-M\n\
         images draw every divider on sphere, teapot, robot and the bench spheres at\n\
         320 × 240. Each image draws the `exact` pair too, and every ratio is to that\n\
         `exact`, compiled into the same image. Per pixel and per triangle are the whole\n\
         frame (vertex stage and draw) as above; `draw ×` compares the rasterizer alone\n\
         (the vertex stage does not divide).\n",
    );
    for here in super::by_board_figure(&div) {
        let (board, figure) = (here[0].board.as_str(), here[0].figure.as_str());
        let find = |span: &str, d: &str| {
            here.iter()
                .find(|r| split(&r.case) == Some((span, d)))
                .copied()
        };
        // The `exact` frame drawn last up to `r` in the log (each image draws its
        // `exact` pair first).
        let exact_for = |r: &FrameRow, span: &str| {
            let i = here.iter().position(|x| std::ptr::eq(*x, r))?;
            here[..=i]
                .iter()
                .rev()
                .find(|x| split(&x.case) == Some((span, "exact")))
                .copied()
        };
        let mut dividers: Vec<&str> = Vec::new();
        for r in &here {
            if let Some((_, d)) = split(&r.case) {
                if !dividers.contains(&d) {
                    dividers.push(d);
                }
            }
        }
        let _ = writeln!(
            md,
            "\n### {board} — {figure} ({} triangles, {} covered pixels)\n\n\
             | divider | classic per pixel | classic per triangle | classic draw × exact | gradient per pixel | gradient per triangle | gradient draw × exact |\n\
             | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
            here[0].triangles, here[0].pixels
        );
        // In the host's order (`fixshade list`).
        let order = |d: &&str| {
            DivideName::ALL
                .iter()
                .position(|(_, n)| n == d)
                .unwrap_or(usize::MAX)
        };
        dividers.sort_by_key(order);
        for d in dividers {
            let mut cells = Vec::new();
            for span in ["classic", "gradient"] {
                match find(span, d) {
                    Some(r) => {
                        let e = exact_for(r, span);
                        cells.push(fmt_per(r.total(), r.pixels));
                        cells.push(fmt_per(r.total(), r.triangles));
                        cells.push(e.map_or("-".into(), |e| ratio(r.draw, e.draw)));
                    }
                    None => cells.extend(["-".to_string(), "-".into(), "-".into()]),
                }
            }
            let _ = writeln!(md, "| {d} | {} |", cells.join(" | "));
        }
    }
    md
}

fn ratio(a: u64, b: u64) -> String {
    if b == 0 {
        "-".into()
    } else {
        format!("{:.3}", a as f64 / b as f64)
    }
}
