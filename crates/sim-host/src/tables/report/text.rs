//! The report as text: the stdout table, the CSV, the markdown and its summary.

use std::fmt::Write as _;

use super::mcu::BOARDS;
pub use super::model::{instr, med_instr, median_f, of, sci};
use super::model::{Kind, ReportOptions, Row, MACHINE_NOTE, STEM};
use super::{chart, recommend};
use crate::scene::desc::{DivideName, Named, ShadingName, SpanName};
use crate::tables::{claims, provenance};

/// The full table's header, shared by the text and markdown tables.
pub const HEADER: [&str; 14] = [
    "figure",
    "kind",
    "configuration",
    "NMSE",
    "verdict",
    "max channel error",
    "coverage mismatch",
    "NMSE vs per-pixel",
    "instr/px ARMv6-M",
    "instr/px M4",
    "Pareto",
    "host ns/px",
    "× classic (host)",
    "host spread",
];

/// The cells of a row in table order, shared by the text and markdown tables.
fn cells(r: &Row) -> [String; 14] {
    let pareto: Vec<&str> = BOARDS
        .iter()
        .zip(r.pareto)
        .filter(|(_, on)| *on)
        .map(|(b, _)| b.1)
        .collect();
    [
        r.figure.clone(),
        r.config.kind.as_str().to_string(),
        r.config.name(),
        sci(r.nmse),
        r.verdict.to_string(),
        r.max_channel_error.to_string(),
        r.coverage_mismatch.to_string(),
        sci(r.nmse_vs_phong),
        instr(r.mcu[0].per_pixel),
        instr(r.mcu[1].per_pixel),
        pareto.join(", "),
        format!("{:.2}", r.ns_per_px),
        format!("{:.3}", r.ratio),
        format!("{:.0} %", r.spread * 100.0),
    ]
}

/// The table printed on stdout.
pub fn text_table(rows: &[Row]) -> String {
    let widths = [8, 11, 22, 10, 17, 4, 4, 10, 9, 9, 12, 7, 7, 6];
    let line = |c: &[String]| {
        let mut l = String::new();
        for (i, (cell, w)) in c.iter().zip(widths).enumerate() {
            if i < 3 || i == 4 || i == 10 {
                let _ = write!(l, "{cell:<w$} ");
            } else {
                let _ = write!(l, "{cell:>w$} ");
            }
        }
        l.trim_end().to_string()
    };
    let short = [
        "figure",
        "kind",
        "configuration",
        "NMSE",
        "verdict",
        "max",
        "cov",
        "NMSE/pix",
        "ARMv6-M",
        "M4",
        "pareto",
        "ns/px",
        "ratio",
        "spread",
    ];
    let mut t = line(&short.map(String::from));
    for r in rows {
        t.push('\n');
        t.push_str(&line(&cells(r)));
    }
    t
}

/// The CSV header.
pub const CSV_HEADER: &str = "figure,kind,configuration,span,shading,divide,specular_model,\
shininess,perspective_px,reference,nmse,verdict,max_channel_error,coverage_mismatch,\
covered_pixels,nmse_vs_gouraud_reference,nmse_vs_phong_reference,same_as_gradient,\
instr_per_px_armv6m,instr_per_px_m4,draw_instr_per_px_armv6m,draw_instr_per_px_m4,\
pareto_armv6m,pareto_m4,frame_ns,ns_per_px,ratio_to_classic_gouraud,timing_spread";

/// The CSV text of `rows`.
pub fn to_csv(rows: &[Row]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        let c = &r.config;
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{:e},{},{},{},{},{:e},{:e},{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4}",
            r.figure,
            c.kind.as_str(),
            c.name(),
            c.span.name(),
            c.shading.name(),
            c.divide.name(),
            c.specular.name(),
            c.shininess,
            c.perspective,
            c.reference_name(),
            r.nmse,
            r.verdict,
            r.max_channel_error,
            r.coverage_mismatch,
            r.covered,
            r.nmse_vs_gouraud,
            r.nmse_vs_phong,
            r.same_as_gradient,
            r.mcu[0].per_pixel,
            r.mcu[1].per_pixel,
            r.mcu[0].draw_per_pixel,
            r.mcu[1].draw_per_pixel,
            r.pareto[0],
            r.pareto[1],
            r.frame.as_nanos(),
            r.ns_per_px,
            r.ratio,
            r.spread
        );
    }
    s
}

/// `a / b` of the medians on both cores, as `1.23× / 4.56×`.
fn times_both(a: &[&Row], b: &[&Row]) -> String {
    let t: Vec<String> = (0..BOARDS.len())
        .map(|k| format!("{:.2}×", med_instr(a, k) / med_instr(b, k)))
        .collect();
    t.join(" / ")
}

/// The summary: a few generated sentences, at most [`SUMMARY_WORDS`] words with
/// the title and the provenance line.
pub fn summary(rows: &[Row], figures: &[String], inputs: &claims::Inputs) -> String {
    let mut s = String::new();
    let nf = figures.len();
    let cores = format!(
        "ARMv6-M (`{}`, no divide instruction) / Cortex-M4 (`{}`)",
        BOARDS[0].0, BOARDS[1].0
    );
    let over = if nf > 1 {
        format!(", medians over {nf} figures")
    } else {
        String::new()
    };
    let _ = write!(
        s,
        "{} configurations on {}, each compared with its exact f64 reference (NMSE) and \
         priced in whole-frame instructions per covered pixel under QEMU on {cores}{over}. ",
        rows.len() / nf.max(1),
        figures.join(", ")
    );
    let span = |sp: SpanName| of(rows, &|c| c.kind == Kind::Span && c.span == sp);
    let classic = span(SpanName::CLASSIC);
    let grad = span(SpanName::GRADIENT);
    if !classic.is_empty() && !grad.is_empty() {
        let _ = write!(
            s,
            "`classic` (a division per span) costs {} / {} instr/px; `gradient`, the same \
             image up to rounding, {} / {}. ",
            instr(med_instr(&classic, 0)),
            instr(med_instr(&classic, 1)),
            instr(med_instr(&grad, 0)),
            instr(med_instr(&grad, 1))
        );
    }
    let mut shading = Vec::new();
    for sh in [
        ShadingName::FLAT,
        ShadingName::QUADRATIC,
        ShadingName::ADAPTIVE,
        ShadingName::PHONG,
    ] {
        let rs = of(rows, &|c| c.kind == Kind::Shading && c.shading == sh);
        if !rs.is_empty() && !grad.is_empty() {
            shading.push(format!("`{}` {}", sh.name(), times_both(&rs, &grad)));
        }
    }
    if !shading.is_empty() {
        let _ = write!(s, "Against Gouraud (both cores): {}. ", shading.join(", "));
    }
    for (kind, span) in [
        (Kind::Divide, SpanName::CLASSIC),
        (Kind::Setup, SpanName::GRADIENT),
    ] {
        let sa = of(rows, &|c| {
            c.kind == kind
                && c.shading == ShadingName::GOURAUD
                && c.divide == DivideName::named("shift-add-8")
        });
        let ex = of(rows, &|c| c.kind == Kind::Span && c.span == span);
        if !sa.is_empty() {
            let _ = write!(
                s,
                "`{}` with `shift-add-8` instead of `exact` ({}): {}. ",
                span.name(),
                if kind == Kind::Divide {
                    "per span"
                } else {
                    "in the setup"
                },
                times_both(&sa, &ex)
            );
        }
    }
    let off = of(rows, &|c| c.kind == Kind::Perspective && c.perspective == 0);
    let p16 = of(rows, &|c| {
        c.kind == Kind::Perspective && c.perspective == 16 && c.divide == DivideName::EXACT
    });
    if !off.is_empty() && !p16.is_empty() {
        let _ = write!(
            s,
            "Perspective-correct colours every 16 px cost {} the affine frame. ",
            times_both(&p16, &off)
        );
    }
    let _ = write!(s, "{} ", claims::tally(rows, inputs));
    let _ = write!(
        s,
        "Host time is secondary: medians of interleaved rounds on a shared machine \
         ({MACHINE_NOTE})."
    );
    s
}

/// Largest word count of the markdown before its first table.
pub const SUMMARY_WORDS: usize = 300;

/// The markdown document.
pub fn markdown(opts: &ReportOptions, rows: &[Row], inputs: &claims::Inputs) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "# Accuracy versus time\n");
    let _ = writeln!(
        m,
        "<!-- Generated by `fixshade report`; rerun it instead of editing. -->\n"
    );
    let _ = writeln!(m, "{}\n", provenance::made_line(&opts.command()));
    let _ = writeln!(m, "{}\n", summary(rows, &opts.figures, inputs));
    let _ = writeln!(m, "## What to pick\n");
    m.push_str(&recommend::markdown(rows));
    let _ = writeln!(
        m,
        "\nCosts are whole-frame instructions per covered pixel (medians over the \
         figures); NMSE is the largest over the figures, against the per-pixel reference \
         for rows that must keep highlights and against the row's own reference \
         otherwise. Each row is chosen by a rule in `tables/report/recommend.rs`.\n"
    );
    let _ = writeln!(m, "## Accuracy against MCU instructions\n");
    for (core, board) in BOARDS.iter().enumerate() {
        let _ = writeln!(
            m,
            "![NMSE against {} instructions per covered pixel]({})\n",
            board.1,
            chart::core_file(core)
        );
    }
    let _ = writeln!(
        m,
        "NMSE against the per-pixel (Phong) f64 reference, log scale; NMSE 0 is drawn at \
         the floor line at the bottom. Lines join each figure's Pareto front on that core; \
         only front points are labelled. A secondary chart against host ns per pixel: \
         [{STEM}.png]({STEM}.png).\n"
    );
    let _ = writeln!(m, "## The seeds' claims, measured\n");
    m.push_str(&claims::markdown(rows, inputs));
    let _ = writeln!(m, "\n## All rows\n");
    let _ = writeln!(m, "| {} |", super::text::HEADER.join(" | "));
    let _ = writeln!(
        m,
        "|---|---|---|---:|---|---:|---:|---:|---:|---:|---|---:|---:|---:|"
    );
    for r in rows {
        let mut c = cells(r);
        c[2] = format!("`{}`", c[2]);
        let _ = writeln!(m, "| {} |", c.join(" | "));
    }
    let _ = writeln!(
        m,
        "\nSpan rows use Gouraud shading; shading rows the `gradient` span. NMSE is against \
         the matching exact f64 reference (flat, Gouraud, per-pixel for `quadratic`, \
         `phong`, `adaptive` and the specular rows, perspective-correct for the \
         perspective rows); \"NMSE vs per-pixel\" is the one yardstick of the charts and \
         the Pareto column. Divide rows put the divider in `classic`'s per-span division, \
         setup rows in the triangle setup's reciprocal. The MCU columns are from the \
         instruction table of the command above (`cargo xtask qemu`, full-frame images, \
         vertex stage included). Host: {} interleaved rounds, each the median of {} \
         frames; spread is the interquartile range over the median.",
        opts.rounds.max(1),
        opts.runs_per_round.max(1)
    );
    m
}

#[cfg(test)]
mod tests {
    use super::super::model::Config;
    use super::*;
    use crate::tables::report::is_baseline;

    #[test]
    fn header_and_cells_agree() {
        assert_eq!(HEADER.len(), 14);
        assert_eq!(CSV_HEADER.split(',').count(), 28);
    }

    #[test]
    fn is_baseline_is_classic_gouraud() {
        let c = Config::new(Kind::Span, SpanName::CLASSIC, ShadingName::GOURAUD);
        assert!(is_baseline(&c));
    }
}
