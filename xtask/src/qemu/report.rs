//! The accuracy report's sweep of `cargo xtask qemu`: the images built with the
//! feature `report` (boards/common's `report`) draw, on the Cortex-M4 and on the
//! full-frame ARMv6-M image, every shading mode with `gradient`
//! (`<shading>+gradient@exact`), Phong with the report's setup dividers
//! (`phong+gradient@<divider>`) and every specular model at the report's exponents
//! (`phong+gradient@exact+<model>+<n>`, sphere), each compared byte for byte with
//! the host render of the same settings; and they log the instructions of one
//! `Specular::eval` per model and exponent (`SPECULAR` lines, docs/mcu-specular.csv).

use std::fmt::Write as _;

use fixshade_sim::scene::desc::{
    DivideName, Named, SceneDesc, ShadingName, SpanName, SpecularName,
};

use super::{fmt_per, m4, v6m, FrameRow, Image, Kind};

/// The report images: Cortex-M4, then ARMv6-M.
pub(super) const IMAGES: &[Image] = &[
    m4("report", "fixshade-qemu-mps2-an386", Kind::Figures),
    v6m("report", "fixshade-qemu-mps2-an386", Kind::Figures),
];

/// A case of the report images, by its parts.
struct Case<'a> {
    shading: &'a str,
    span: &'a str,
    divide: &'a str,
    /// Specular model and exponent (the specular rows).
    specular: Option<(&'a str, &'a str)>,
}

/// `shading+span@divider[+model+n]` → its parts; `None` for the other images' cases.
fn split(case: &str) -> Option<Case<'_>> {
    let mut parts = case.split('+');
    let shading = parts.next()?;
    let (span, divide) = parts.next()?.split_once('@')?;
    let specular = match (parts.next(), parts.next()) {
        (Some(model), Some(n)) => Some((model, n)),
        (None, None) => None,
        _ => return None,
    };
    if parts.next().is_some() {
        return None;
    }
    Some(Case {
        shading,
        span,
        divide,
        specular,
    })
}

/// True for a case of the report images.
pub(super) fn is_case(case: &str) -> bool {
    split(case).is_some()
}

/// Sets the host scene from a case of the report images (`fixshade render --shading
/// S --span M --divide D [--specular X]`, every material's shininess set to n as
/// `fixshade report` sets it); false for the other images' cases.
pub(super) fn apply(desc: &mut SceneDesc, case: &str) -> Result<bool, String> {
    let Some(c) = split(case) else {
        return Ok(false);
    };
    desc.shading = ShadingName::parse(c.shading)?;
    desc.span = SpanName::parse(c.span)?;
    desc.divide = DivideName::parse(c.divide)?;
    if let Some((model, n)) = c.specular {
        desc.specular = SpecularName::parse(model)?;
        let n: u32 = n
            .parse()
            .map_err(|_| format!("bad exponent in case {case}"))?;
        for o in &mut desc.objects {
            o.material.shininess = f64::from(n);
        }
    }
    Ok(true)
}

/// The CSV's `method`, `divide`, `sweep`, `shading`, `specular` and `shininess` of a
/// case of the report images: sweep `specular` for the specular rows, `setup` for
/// Phong with an approximate divider, `shading` for the rest.
pub(super) fn csv_names(case: &str) -> Option<[&str; 6]> {
    let c = split(case)?;
    let (sweep, specular, n) = match c.specular {
        Some((model, n)) => ("specular", model, n),
        None if c.divide != DivideName::EXACT.name() => ("setup", "exact", "0"),
        None => ("shading", "exact", "0"),
    };
    Some([c.span, c.divide, sweep, c.shading, specular, n])
}

/// The `SPECULAR board model n evaluations with without` lines as
/// docs/mcu-specular.csv: instructions per `eval`, the loop without the call
/// subtracted.
pub(super) fn specular_csv(lines: &[String]) -> Result<String, String> {
    let mut csv = String::from("board,model,n,evals,instructions,per_eval\n");
    for l in lines {
        let f: Vec<&str> = l.split_whitespace().collect();
        let [_, board, model, n, evals, with, without] = f.as_slice() else {
            return Err(format!("bad line: {l}"));
        };
        let num = |v: &str| v.parse::<u64>().map_err(|_| format!("bad line: {l}"));
        let (evals, with, without) = (num(evals)?, num(with)?, num(without)?);
        let cost = with.saturating_sub(without);
        let _ = writeln!(
            csv,
            "{board},{model},{n},{evals},{cost},{}",
            fmt_per(cost, evals)
        );
    }
    Ok(csv)
}

/// Every report case each report image must have drawn: every shading mode and
/// Phong setup divider on sphere, teapot and robot, every specular model at every
/// exponent on the sphere, and every `SPECULAR` line.
pub(super) fn check(rows: &[FrameRow], specular: &[String]) -> Result<(), String> {
    for board in ["mps2-an386", "mps2-an385-v6m"] {
        let have = |figure: &str, case: &str| {
            rows.iter()
                .any(|r| r.board == board && r.figure == figure && r.case == case)
        };
        let mut want: Vec<(&str, String)> = Vec::new();
        for figure in ["sphere", "teapot", "robot"] {
            for (s, _) in ShadingName::ALL {
                if s.core().is_some() {
                    want.push((figure, format!("{}+gradient@exact", s.name())));
                }
            }
            for d in [
                "table",
                "shift-add-8",
                "shift-add-4",
                "shift-add-12",
                "shift-add-16",
            ] {
                want.push((figure, format!("phong+gradient@{d}")));
            }
        }
        for n in fixshade_sim::tables::report::SHININESS {
            for (m, _) in SpecularName::ALL {
                want.push(("sphere", format!("phong+gradient@exact+{}+{n}", m.name())));
            }
        }
        for (figure, case) in &want {
            if !have(figure, case) {
                return Err(format!(
                    "{board} {figure}: no frame {case} (expected from the `report` images)"
                ));
            }
        }
        for n in fixshade_sim::tables::specular::NS {
            for (m, _) in SpecularName::ALL {
                let prefix = format!("SPECULAR {board} {} {n} ", m.name());
                if !specular.iter().any(|l| l.starts_with(&prefix)) {
                    return Err(format!(
                        "{board}: no line {prefix}… from the `report` images"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The markdown section: per board and figure, every report case's instructions per
/// covered pixel, against the same image's Gouraud `gradient`; then the specular
/// evaluations.
pub(super) fn section(rows: &[FrameRow], specular_csv: &str) -> String {
    let here: Vec<&FrameRow> = rows.iter().filter(|r| is_case(&r.case)).collect();
    if here.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Shading modes, Phong setup dividers and specular models\n\n\
         The accuracy report's other configurations (`fixshade report`,\n\
         docs/accuracy-vs-time.md), drawn by the `report` images on the Cortex-M4 and on\n\
         the full-frame ARMv6-M image: every shading mode with `gradient`, Phong with the\n\
         report's setup dividers, and on the sphere every specular model with every\n\
         material's shininess set to n; each frame compared byte for byte with the host\n\
         render of the same settings. `per pixel` is the whole frame (vertex stage and\n\
         draw) per covered pixel, `draw per pixel` the rasterizer alone, `draw × gouraud`\n\
         the draw against the same image's Gouraud `gradient` draw.\n",
    );
    for mine in super::by_board_figure(&here) {
        let (board, figure) = (mine[0].board.as_str(), mine[0].figure.as_str());
        let gouraud = mine.iter().find(|r| r.case == "gouraud+gradient@exact");
        let _ = writeln!(
            md,
            "\n### {board} — {figure} at {}×{} ({} triangles)\n\n\
             | case | pixels | per pixel | draw per pixel | draw × gouraud |\n\
             | --- | ---: | ---: | ---: | ---: |",
            mine[0].width, mine[0].height, mine[0].triangles
        );
        for r in &mine {
            let ratio = gouraud.map_or("-".to_string(), |g| {
                if g.draw == 0 {
                    "-".into()
                } else {
                    format!("{:.3}", r.draw as f64 / g.draw as f64)
                }
            });
            let _ = writeln!(
                md,
                "| `{}` | {} | {} | {} | {ratio} |",
                r.case,
                r.pixels,
                fmt_per(r.total(), r.pixels),
                fmt_per(r.draw, r.pixels)
            );
        }
    }
    md.push_str(
        "\n### One specular evaluation\n\n\
         Instructions per `Specular::eval` call (docs/mcu-specular.csv): a loop of 1024\n\
         calls with `c` uniform in (0, 1] (the inputs of `fixshade specular`), minus the\n\
         same loop without the call.\n\n\
         | board | model | n | instructions per eval |\n| --- | --- | ---: | ---: |\n",
    );
    for l in specular_csv.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        if let [board, model, n, _, _, per] = f.as_slice() {
            let _ = writeln!(md, "| {board} | {model} | {n} | {per} |");
        }
    }
    md
}
