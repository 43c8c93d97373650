//! The report's data: its configurations, options, rows, and the number formats
//! and medians every part of it shares (a leaf: it imports no other part of the
//! report).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::scene::desc::{DivideName, Named, ShadingName, SpanName, SpecularName};

/// The figures of the full report.
pub const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

/// The machine note written into the markdown.
pub const MACHINE_NOTE: &str = "2 cores, shared";

/// File stem of the outputs.
pub const STEM: &str = "accuracy-vs-time";

/// Default path of the firmware's instruction counts.
pub const MCU_CSV: &str = "docs/mcu-instructions.csv";

/// Default path of the specular table (read for the seed claims).
pub const SPECULAR_CSV: &str = "docs/specular.csv";

/// Default path of the specular models' instruction counts.
pub const MCU_SPECULAR_CSV: &str = "docs/mcu-specular.csv";

/// How a report run is done.
#[derive(Clone, Debug)]
pub struct ReportOptions {
    /// Quick mode (CI): one figure, few timing runs.
    pub quick: bool,
    /// Directory the `.md`, `.csv` and `.png` go into.
    pub out_dir: PathBuf,
    /// Figures (built-in scene names or scene files).
    pub figures: Vec<String>,
    /// Timing rounds; each round times every configuration once.
    pub rounds: usize,
    /// Frames per configuration per round (`time_frame`'s median of these).
    pub runs_per_round: usize,
    /// Print a progress line on stderr.
    pub progress: bool,
    /// The firmware's instruction counts (`docs/mcu-instructions.csv`).
    pub mcu_csv: PathBuf,
    /// The specular table the seed claims read (`docs/specular.csv`).
    pub specular_csv: PathBuf,
    /// The specular instruction counts (`docs/mcu-specular.csv`).
    pub mcu_specular_csv: PathBuf,
}

impl ReportOptions {
    /// The full report: all figures, into `docs/`.
    pub fn full() -> ReportOptions {
        ReportOptions {
            quick: false,
            out_dir: PathBuf::from("docs"),
            figures: FIGURES.iter().map(|s| s.to_string()).collect(),
            rounds: 51,
            runs_per_round: 11,
            progress: true,
            mcu_csv: PathBuf::from(MCU_CSV),
            specular_csv: PathBuf::from(SPECULAR_CSV),
            mcu_specular_csv: PathBuf::from(MCU_SPECULAR_CSV),
        }
    }

    /// The quick report: the sphere only, few runs, into `out/report-quick/`.
    pub fn quick() -> ReportOptions {
        ReportOptions {
            quick: true,
            out_dir: PathBuf::from("out/report-quick"),
            figures: vec!["sphere".to_string()],
            rounds: 7,
            runs_per_round: 5,
            progress: true,
            mcu_csv: PathBuf::from(MCU_CSV),
            specular_csv: PathBuf::from(SPECULAR_CSV),
            mcu_specular_csv: PathBuf::from(MCU_SPECULAR_CSV),
        }
    }

    /// The command line that reproduces this run.
    pub fn command(&self) -> String {
        let mut c = String::from("cargo run --release -- report");
        if self.quick {
            c.push_str(" --quick");
        }
        let default = if self.quick {
            ReportOptions::quick().out_dir
        } else {
            ReportOptions::full().out_dir
        };
        if self.out_dir != default {
            let _ = write!(c, " --out {}", self.out_dir.display());
        }
        if self.mcu_csv != Path::new(MCU_CSV) {
            let _ = write!(c, " --mcu-csv {}", self.mcu_csv.display());
        }
        c
    }
}

/// Which sweep a configuration belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A span method, with Gouraud shading.
    Span,
    /// A shading mode, with the `gradient` span.
    Shading,
    /// A divider in the `classic` span's per-span division (Gouraud).
    Divide,
    /// A divider in the triangle setup's reciprocal (`gradient` span; Gouraud, and
    /// a few rows with Phong shading, whose setup interpolates normals and eye
    /// positions through the same reciprocal).
    Setup,
    /// A specular model at one exponent (Phong shading, `gradient` span).
    Specular,
    /// Perspective correction of Gouraud colours, off or with a perspective span
    /// and divider, against the perspective-correct reference.
    Perspective,
}

impl Kind {
    /// `span` or `shading`.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Span => "span",
            Kind::Shading => "shading",
            Kind::Divide => "divide",
            Kind::Setup => "setup",
            Kind::Specular => "specular",
            Kind::Perspective => "perspective",
        }
    }
}

/// One configuration of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Which sweep.
    pub kind: Kind,
    /// Span method.
    pub span: SpanName,
    /// Shading mode.
    pub shading: ShadingName,
    /// Divider.
    pub divide: DivideName,
    /// Specular model.
    pub specular: SpecularName,
    /// Shininess n of every material; 0 keeps the scene's own.
    pub shininess: u32,
    /// Pixels per perspective division; 0: screen-space interpolation.
    pub perspective: u32,
}

impl Config {
    /// A configuration of `kind` with the exact divider and specular model.
    pub fn new(kind: Kind, span: SpanName, shading: ShadingName) -> Config {
        Config {
            kind,
            span,
            shading,
            divide: DivideName::EXACT,
            specular: SpecularName::EXACT,
            shininess: 0,
            perspective: 0,
        }
    }

    /// The name of what varies: the span, shading, divider, or specular model and n.
    pub fn name(&self) -> String {
        match self.kind {
            Kind::Span => self.span.name().to_string(),
            Kind::Shading => self.shading.name().to_string(),
            Kind::Setup if self.shading != ShadingName::GOURAUD => {
                format!("{} {}", self.shading.name(), self.divide.name())
            }
            Kind::Divide | Kind::Setup => self.divide.name().to_string(),
            Kind::Specular => format!("{} n={}", self.specular.name(), self.shininess),
            Kind::Perspective if self.perspective == 0 => "off".to_string(),
            Kind::Perspective => format!("{}px {}", self.perspective, self.divide.name()),
        }
    }

    /// The name with its sweep where the name alone is ambiguous: `` `gradient` ``,
    /// `` `phong` ``, `` divide `table` ``, `` setup `table` ``, `` perspective `16px exact` ``,
    /// `` specular `schlick n=8` ``.
    pub fn label(&self) -> String {
        match self.kind {
            Kind::Span | Kind::Shading => format!("`{}`", self.name()),
            k => format!("{} `{}`", k.as_str(), self.name()),
        }
    }

    /// Whether the matching reference is the per-pixel (Phong) one.
    pub fn phong_reference(&self) -> bool {
        self.shading.phong_reference()
    }

    /// The name of the matching exact f64 reference: `phong` (per-pixel) for
    /// `quadratic` and `phong`, else the shading's own (`gouraud`, `flat`).
    pub fn reference_name(&self) -> &'static str {
        if self.kind == Kind::Perspective {
            "gouraud-perspective"
        } else if self.phong_reference() {
            "phong"
        } else {
            self.shading.name()
        }
    }
}

/// The perspective rows: (pixels per division, divider); `(0, exact)` is
/// screen-space interpolation against the same perspective-correct reference.
pub const PERSPECTIVE_ROWS: [(u32, DivideName); 6] = [
    (0, DivideName::EXACT),
    (1, DivideName::EXACT),
    (8, DivideName::EXACT),
    (16, DivideName::EXACT),
    (16, DivideName::named("table")),
    (16, DivideName::named("shift-add-8")),
];

/// The exponents of the specular rows.
pub const SHININESS: [u32; 5] = [8, 32, 128, 512, 1000];

/// The dividers of the Phong setup rows (the first two in the quick report).
const PHONG_SETUP_DIVIDERS: [DivideName; 5] = [
    DivideName::named("table"),
    DivideName::named("shift-add-8"),
    DivideName::named("shift-add-4"),
    DivideName::named("shift-add-12"),
    DivideName::named("shift-add-16"),
];

/// The dividers of the quick report (every one in the full report).
const QUICK_DIVIDERS: [DivideName; 6] = [
    DivideName::named("table"),
    DivideName::named("shift-add-4"),
    DivideName::named("shift-add-8"),
    DivideName::named("shift-add-rounded-8"),
    DivideName::named("shift-add-12"),
    DivideName::named("shift-add-16"),
];

/// The configurations of one figure, in report order: every span method with
/// Gouraud, then every shading mode with the `gradient` span (Gouraud + gradient
/// appears once, as a span row), then `classic` and `gradient` with every divider
/// other than `exact` (their `exact` rows are the span rows), then `gradient` with
/// Phong shading and the dividers of `PHONG_SETUP_DIVIDERS` in its setup (its
/// `exact` row is the shading row), then the perspective
/// rows ([`PERSPECTIVE_ROWS`], against the perspective-correct reference), then, on the sphere
/// only (`specular`), every specular model at every n of [`SHININESS`] with Phong
/// shading. `quick` takes a few dividers and two exponents.
pub fn configurations(quick: bool, specular: bool) -> Vec<Config> {
    let mut v: Vec<Config> = SpanName::ALL
        .iter()
        .map(|&(span, _)| Config::new(Kind::Span, span, ShadingName::GOURAUD))
        .collect();
    for &(shading, _) in ShadingName::ALL {
        // Ray casting has its own table (docs/raycast.md, `fixshade raycast-table`).
        if shading == ShadingName::RAYCAST {
            continue;
        }
        let c = Config::new(Kind::Shading, SpanName::GRADIENT, shading);
        if !v.iter().any(|o| o.span == c.span && o.shading == c.shading) {
            v.push(c);
        }
    }
    let dividers: Vec<DivideName> = if quick {
        QUICK_DIVIDERS.to_vec()
    } else {
        DivideName::ALL
            .iter()
            .map(|(d, _)| *d)
            .filter(|d| *d != DivideName::EXACT)
            .collect()
    };
    for (kind, span) in [
        (Kind::Divide, SpanName::CLASSIC),
        (Kind::Setup, SpanName::GRADIENT),
    ] {
        for &d in &dividers {
            v.push(Config {
                divide: d,
                ..Config::new(kind, span, ShadingName::GOURAUD)
            });
        }
    }
    let phong: &[DivideName] = if quick {
        &PHONG_SETUP_DIVIDERS[..2]
    } else {
        &PHONG_SETUP_DIVIDERS
    };
    for &d in phong {
        v.push(Config {
            divide: d,
            ..Config::new(Kind::Setup, SpanName::GRADIENT, ShadingName::PHONG)
        });
    }
    for (px, d) in PERSPECTIVE_ROWS {
        v.push(Config {
            perspective: px,
            divide: d,
            ..Config::new(Kind::Perspective, SpanName::GRADIENT, ShadingName::GOURAUD)
        });
    }
    if specular {
        let ns: &[u32] = if quick { &[8, 128] } else { &SHININESS };
        for &(sp, _) in SpecularName::ALL {
            for &n in ns {
                v.push(Config {
                    specular: sp,
                    shininess: n,
                    ..Config::new(Kind::Specular, SpanName::GRADIENT, ShadingName::PHONG)
                });
            }
        }
    }
    v
}

/// Whether a figure gets the specular rows: the sphere (its highlight is the
/// largest).
pub fn specular_rows(figure: &str) -> bool {
    figure == "sphere"
}

/// The baseline configuration: `classic` span with Gouraud shading (exact divider).
pub fn is_baseline(c: &Config) -> bool {
    c.kind == Kind::Span && c.span == SpanName::CLASSIC && c.shading == ShadingName::GOURAUD
}

/// One measured row.
#[derive(Clone, Debug)]
pub struct Row {
    /// Figure name.
    pub figure: String,
    /// The configuration.
    pub config: Config,
    /// NMSE against the matching reference.
    pub nmse: f64,
    /// Verdict word.
    pub verdict: &'static str,
    /// NMSE against the Gouraud f64 reference (the smooth surface), whatever the
    /// shading: what a shading mode loses against per-vertex smooth shading.
    pub nmse_vs_gouraud: f64,
    /// NMSE against the per-pixel (Phong) f64 reference.
    pub nmse_vs_phong: f64,
    /// Largest channel error.
    pub max_channel_error: u8,
    /// Pixels covered in one image only.
    pub coverage_mismatch: usize,
    /// Covered pixels of the fixed-point render.
    pub covered: usize,
    /// The render's bytes equal those of the `gradient` + Gouraud render.
    pub same_as_gradient: bool,
    /// Median host frame time over the rounds.
    pub frame: Duration,
    /// Host ns per covered pixel.
    pub ns_per_px: f64,
    /// Round-to-round spread of the host frame time: interquartile range over
    /// median, rounded to 4 decimals (as the CSV keeps it).
    pub spread: f64,
    /// Host frame time over the baseline's of the same figure.
    pub ratio: f64,
    /// Instructions per covered pixel on each core of [`BOARDS`].
    pub mcu: [McuCount; 2],
    /// On the figure's Pareto front on each core of [`BOARDS`]: no other
    /// configuration of the figure is both cheaper there and closer to the
    /// per-pixel reference.
    pub pareto: [bool; 2],
}

/// The result of a report run.
#[derive(Clone, Debug)]
pub struct Report {
    /// Rows, figure by figure in configuration order.
    pub rows: Vec<Row>,
    /// The text table printed on stdout.
    pub table: String,
    /// The generated summary.
    pub summary: String,
    /// Paths written.
    pub files: Vec<PathBuf>,
}

/// Which of `points` (cost, error) are on the Pareto front: cheapest first, a
/// point is on it if its error is below that of every cheaper point (ties in cost
/// go to the smaller error).
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut on = vec![false; points.len()];
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].1 < best {
            best = points[i].1;
            on[i] = true;
        }
    }
    on
}

/// An NMSE (or other small number) in three significant digits; `0` for zero.
pub fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else {
        format!("{x:.3e}")
    }
}

/// Instructions per pixel as the tables print them.
pub fn instr(x: f64) -> String {
    format!("{x:.1}")
}

/// Median of `v` (the upper one of an even count); NaN when empty.
pub fn median_f(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

/// Median over figures of instructions per pixel on `core`.
pub fn med_instr(rs: &[&Row], core: usize) -> f64 {
    median_f(rs.iter().map(|r| r.mcu[core].per_pixel).collect())
}

/// Rows whose configuration satisfies `pred`.
pub fn of<'a>(rows: &'a [Row], pred: &dyn Fn(&Config) -> bool) -> Vec<&'a Row> {
    rows.iter().filter(|r| pred(&r.config)).collect()
}

/// The cores of the MCU columns: (board of `docs/mcu-instructions.csv`, column
/// name). ARMv6-M (Cortex-M0/M0+ class: no divide instruction, no 32×32→64
/// multiply) first, then Cortex-M4.
pub const BOARDS: [(&str, &str); 2] = [("mps2-an385-v6m", "ARMv6-M"), ("mps2-an386", "M4")];

/// Instructions of one frame, per covered pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct McuCount {
    /// The whole frame (vertex stage and draw).
    pub per_pixel: f64,
    /// The draw alone.
    pub draw_per_pixel: f64,
}
