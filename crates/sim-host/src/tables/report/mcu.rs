//! The MCU columns of the report: instructions per covered pixel from
//! `docs/mcu-instructions.csv` (written by `cargo xtask qemu`), read from the
//! full-frame images of the two MPS2 boards only.
//!
//! Every report row maps to exactly one CSV row per board ([`McuTable::lookup`]);
//! a missing one is an error naming the board, figure and configuration, never a
//! placeholder. Rows of other boards (`microbit`) and other layouts (`bands-*`,
//! `strips-*`) are ignored: those images repeat or split the vertex stage, so their
//! per-pixel counts do not price a whole frame.

use std::collections::HashMap;
use std::path::Path;

use super::model::{Config, Kind};
pub use super::model::{McuCount, BOARDS};
use crate::scene::desc::{Named, ShadingName};

/// The only layout the report reads.
pub const LAYOUT: &str = "full";

/// What identifies a row of the CSV: board, figure, method, divide, sweep,
/// shading, specular, shininess.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct McuKey {
    /// Board name.
    pub board: String,
    /// Figure name.
    pub figure: String,
    /// Span method (or `perspective-N`).
    pub method: String,
    /// Divider.
    pub divide: String,
    /// Sweep of the firmware image.
    pub sweep: String,
    /// Shading mode.
    pub shading: String,
    /// Specular model.
    pub specular: String,
    /// Shininess, 0: the scene's own.
    pub shininess: u32,
}

impl std::fmt::Display for McuKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "board {}, figure {}, sweep {}: method {}, divide {}, shading {}, specular {}, \
             shininess {}",
            self.board,
            self.figure,
            self.sweep,
            self.method,
            self.divide,
            self.shading,
            self.specular,
            self.shininess
        )
    }
}

/// The full-frame rows of the two MPS2 boards.
#[derive(Clone, Debug, Default)]
pub struct McuTable {
    rows: HashMap<McuKey, McuCount>,
}

impl McuTable {
    /// Reads `path`; an unreadable file or a header without the columns the
    /// report needs is an error naming the file.
    pub fn read(path: &Path) -> Result<McuTable, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        McuTable::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses the CSV text (columns found by name; the first row of a key wins).
    pub fn parse(text: &str) -> Result<McuTable, String> {
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let col = |n: &str| {
            header
                .iter()
                .position(|h| *h == n)
                .ok_or_else(|| format!("no column `{n}` in the header"))
        };
        let names = [
            "board",
            "figure",
            "method",
            "divide",
            "sweep",
            "shading",
            "specular",
            "shininess",
            "layout",
            "per_pixel",
            "draw_per_pixel",
        ];
        let idx: Vec<usize> = names.iter().map(|n| col(n)).collect::<Result<_, _>>()?;
        let mut rows = HashMap::new();
        for (ln, l) in lines.enumerate() {
            let c: Vec<&str> = l.split(',').collect();
            let cell = |i: usize| c.get(idx[i]).copied().unwrap_or("");
            if cell(8) != LAYOUT || !BOARDS.iter().any(|b| b.0 == cell(0)) {
                continue;
            }
            let num = |i: usize| {
                cell(i).parse::<f64>().map_err(|_| {
                    format!(
                        "line {}: `{}` is not a number in column {}",
                        ln + 2,
                        cell(i),
                        names[i]
                    )
                })
            };
            let shininess = cell(7).parse::<u32>().map_err(|_| {
                format!("line {}: shininess `{}` is not an integer", ln + 2, cell(7))
            })?;
            let key = McuKey {
                board: cell(0).to_string(),
                figure: cell(1).to_string(),
                method: cell(2).to_string(),
                divide: cell(3).to_string(),
                sweep: cell(4).to_string(),
                shading: cell(5).to_string(),
                specular: cell(6).to_string(),
                shininess,
            };
            let count = McuCount {
                per_pixel: num(9)?,
                draw_per_pixel: num(10)?,
            };
            rows.entry(key).or_insert(count);
        }
        Ok(McuTable { rows })
    }

    /// The row that prices `c` on `figure` on `board`, or an error naming it.
    pub fn lookup(&self, board: &str, figure: &str, c: &Config) -> Result<McuCount, String> {
        let key = key(board, figure, c);
        self.rows.get(&key).copied().ok_or_else(|| {
            format!(
                "docs/mcu-instructions.csv has no row for {key} (the report's {} row `{}`); \
                 rerun `cargo xtask qemu` with that image, or pass --mcu-csv",
                c.kind.as_str(),
                c.name()
            )
        })
    }
}

/// The CSV key of configuration `c` on `figure` and `board`: which firmware sweep
/// drew it and with what.
pub fn key(board: &str, figure: &str, c: &Config) -> McuKey {
    let gouraud = ShadingName::GOURAUD.name();
    let (method, sweep, shading, specular, shininess) = match c.kind {
        Kind::Span => (c.span.name().to_string(), "span", gouraud, "exact", 0),
        Kind::Divide => (c.span.name().to_string(), "divide", gouraud, "exact", 0),
        Kind::Setup if c.shading == ShadingName::GOURAUD => {
            (c.span.name().to_string(), "divide", gouraud, "exact", 0)
        }
        Kind::Setup => (
            c.span.name().to_string(),
            "setup",
            c.shading.name(),
            "exact",
            0,
        ),
        Kind::Shading => (
            c.span.name().to_string(),
            "shading",
            c.shading.name(),
            "exact",
            0,
        ),
        Kind::Perspective if c.perspective == 0 => (
            c.span.name().to_string(),
            "perspective",
            gouraud,
            "exact",
            0,
        ),
        Kind::Perspective => (
            format!("perspective-{}", c.perspective),
            "perspective",
            gouraud,
            "exact",
            0,
        ),
        Kind::Specular => (
            c.span.name().to_string(),
            "specular",
            c.shading.name(),
            c.specular.name(),
            c.shininess,
        ),
    };
    McuKey {
        board: board.to_string(),
        figure: figure.to_string(),
        method,
        divide: c.divide.name().to_string(),
        sweep: sweep.to_string(),
        shading: shading.to_string(),
        specular: specular.to_string(),
        shininess,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::desc::{DivideName, SpanName, SpecularName};

    const CSV: &str = "\
board,figure,method,width,height,triangles,drawn,pixels,prepare,draw,total,per_pixel,per_triangle,draw_per_pixel,divide,sweep,layout,helpers,shading,specular,shininess
mps2-an385-v6m,sphere,classic,320,240,1,1,1,1,1,1,500.00,1,400.00,exact,span,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,classic,320,240,1,1,1,1,1,1,510.00,1,410.00,exact,divide,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,classic,320,240,1,1,1,1,1,1,490.00,1,390.00,shift-add-8,divide,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,gradient,320,240,1,1,1,1,1,1,300.00,1,200.00,table,divide,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,gradient,320,240,1,1,1,1,1,1,900.00,1,800.00,table,setup,full,0,phong,exact,0
mps2-an385-v6m,sphere,gradient,320,240,1,1,1,1,1,1,950.00,1,850.00,exact,specular,full,0,phong,schlick,128
mps2-an385-v6m,sphere,perspective-16,320,240,1,1,1,1,1,1,700.00,1,600.00,shift-add-8,perspective,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,gradient,320,240,1,1,1,1,1,1,250.00,1,150.00,exact,perspective,full,0,gouraud,exact,0
mps2-an385-v6m,sphere,gradient,320,240,1,1,1,1,1,1,99.00,1,80.00,exact,shading,bands-2,0,flat,exact,0
microbit,sphere,gradient,320,240,1,1,1,1,1,1,98.00,1,80.00,exact,shading,full,0,flat,exact,0
";

    fn cfg(kind: Kind, span: SpanName, shading: ShadingName, divide: &'static str) -> Config {
        Config {
            divide: DivideName::named(divide),
            ..Config::new(kind, span, shading)
        }
    }

    #[test]
    fn every_kind_reads_its_own_sweep() {
        let t = McuTable::parse(CSV).unwrap();
        let v6m = |c: &Config| t.lookup("mps2-an385-v6m", "sphere", c).map(|m| m.per_pixel);
        let g = ShadingName::GOURAUD;
        // The span row reads the span image, not the divider image's own `exact`.
        assert_eq!(
            v6m(&cfg(Kind::Span, SpanName::CLASSIC, g, "exact")),
            Ok(500.0)
        );
        let sa8 = cfg(Kind::Divide, SpanName::CLASSIC, g, "shift-add-8");
        assert_eq!(v6m(&sa8), Ok(490.0));
        let table = cfg(Kind::Setup, SpanName::GRADIENT, g, "table");
        assert_eq!(v6m(&table), Ok(300.0));
        // Phong setup rows come from the setup sweep.
        let phong = cfg(Kind::Setup, SpanName::GRADIENT, ShadingName::PHONG, "table");
        assert_eq!(v6m(&phong), Ok(900.0));
        let spec = Config {
            specular: SpecularName::named("schlick"),
            shininess: 128,
            ..cfg(
                Kind::Specular,
                SpanName::GRADIENT,
                ShadingName::PHONG,
                "exact",
            )
        };
        assert_eq!(v6m(&spec), Ok(950.0));
        let persp = Config {
            perspective: 16,
            ..cfg(Kind::Perspective, SpanName::GRADIENT, g, "shift-add-8")
        };
        assert_eq!(v6m(&persp), Ok(700.0));
        let off = cfg(Kind::Perspective, SpanName::GRADIENT, g, "exact");
        assert_eq!(v6m(&off), Ok(250.0));
    }

    #[test]
    fn missing_rows_are_errors_naming_board_figure_and_configuration() {
        let t = McuTable::parse(CSV).unwrap();
        // Only in a band layout and on the micro:bit: both ignored.
        let flat = cfg(
            Kind::Shading,
            SpanName::GRADIENT,
            ShadingName::FLAT,
            "exact",
        );
        let e = t.lookup("mps2-an385-v6m", "sphere", &flat).unwrap_err();
        assert!(e.contains("board mps2-an385-v6m"), "{e}");
        assert!(e.contains("figure sphere"), "{e}");
        assert!(e.contains("`flat`"), "{e}");
        let sa8 = cfg(
            Kind::Divide,
            SpanName::CLASSIC,
            ShadingName::GOURAUD,
            "shift-add-8",
        );
        assert!(t.lookup("mps2-an386", "sphere", &sa8).is_err());
        assert!(t.lookup("mps2-an385-v6m", "teapot", &sa8).is_err());
    }

    #[test]
    fn a_header_without_the_new_columns_is_an_error() {
        let old = "board,figure,method,per_pixel,draw_per_pixel,divide,sweep,layout\n";
        let e = McuTable::parse(old).unwrap_err();
        assert!(e.contains("shading"), "{e}");
    }
}
