//! `fixshade report`: what accuracy costs in time.
//!
//! Every figure (sphere, teapot, robot) is rendered with every span method (with
//! Gouraud shading) and every shading mode (with the `gradient` span). Each
//! configuration is compared against the matching exact f64 reference and timed on
//! the host; the timing rounds interleave the configurations so that noise on a
//! shared machine hits them alike, and each configuration's time is the median over
//! the rounds. The result is a text table (stdout), `accuracy-vs-time.md`,
//! `accuracy-vs-time.csv` and `accuracy-vs-time.png` (NMSE, log scale, against host
//! ns per covered pixel, with the Pareto front of each figure connected).
//!
//! Further sweeps: the `classic` span with every divider of the `Divide` seam
//! (its per-span division), the `gradient` span with every divider (the triangle
//! setup's reciprocal), and, on the sphere with Phong shading, every specular model
//! at n = 8, 32, 128, 512, 1000.
//!
//! The MCU columns are read from `docs/mcu-instructions.csv` (written by
//! `cargo xtask qemu`): instructions per covered pixel on Cortex-M0 (`microbit`)
//! and Cortex-M4 (`mps2-an386`) for the configurations it holds (each span method
//! with Gouraud, exact divider, on the three figures; `classic` and `gradient` with
//! each divider, the divide and setup rows, where the divider images drew them);
//! every other cell says `not measured`.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::image::compare::compare;
use crate::image::Image;
use crate::render;
use crate::scene::desc::{DivideName, Named, ShadingName, SpanName, SpecularName};
use crate::scene::load::{self, LoadedScene};

/// The figures of the full report.
pub const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

/// What the MCU columns say until the boards issue fills them.
pub const NOT_MEASURED: &str = "not measured";

/// The machine note written into the markdown.
pub const MACHINE_NOTE: &str = "2 cores, shared";

/// File stem of the outputs.
pub const STEM: &str = "accuracy-vs-time";

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
        }
    }

    /// The command line that reproduces this run.
    fn command(&self) -> String {
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
    fn new(kind: Kind, span: SpanName, shading: ShadingName) -> Config {
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

/// One row of `docs/mcu-instructions.csv`: its board, figure, span method, divider,
/// and sweep (`span`: the span-method images; `divide`: the divider images, whose
/// `exact` rows are their own reference).
type McuKey = (String, String, String, String, String);

/// Instructions of one frame of `docs/mcu-instructions.csv`, per covered pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
struct McuCount {
    /// The whole frame (vertex stage and draw).
    per_pixel: f64,
    /// The draw alone.
    draw_per_pixel: f64,
}

/// Instructions per covered pixel from `docs/mcu-instructions.csv`; empty when the
/// file is missing.
fn mcu_counts() -> HashMap<McuKey, McuCount> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/mcu-instructions.csv"
    );
    std::fs::read_to_string(path)
        .map(|t| parse_mcu_counts(&t))
        .unwrap_or_default()
}

/// The rows of an `mcu-instructions.csv` text, columns found by name; a file
/// without the `divide` and `sweep` columns holds span rows with `exact`.
fn parse_mcu_counts(text: &str) -> HashMap<McuKey, McuCount> {
    let mut m = HashMap::new();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n);
    let (Some(b), Some(f), Some(me), Some(pp), Some(dp)) = (
        col("board"),
        col("figure"),
        col("method"),
        col("per_pixel"),
        col("draw_per_pixel"),
    ) else {
        return m;
    };
    let (dv, sw) = (col("divide"), col("sweep"));
    for l in lines {
        let c: Vec<&str> = l.split(',').collect();
        let num = |i: usize| c.get(i).and_then(|v| v.parse::<f64>().ok());
        let text = |i: Option<usize>, default: &'static str| {
            i.map_or(Some(default), |i| c.get(i).copied())
        };
        if let (Some(board), Some(fig), Some(meth), Some(divide), Some(sweep), Some(p), Some(d)) = (
            c.get(b),
            c.get(f),
            c.get(me),
            text(dv, "exact"),
            text(sw, "span"),
            num(pp),
            num(dp),
        ) {
            // The first row of a key is kept: the Cortex-M0 sphere's divider images
            // each draw `exact`, and the first of them also draws the dividers the
            // summary compares with it.
            m.entry((
                board.to_string(),
                fig.to_string(),
                meth.to_string(),
                divide.to_string(),
                sweep.to_string(),
            ))
            .or_insert(McuCount {
                per_pixel: p,
                draw_per_pixel: d,
            });
        }
    }
    m
}

fn mcu_key(board: &str, figure: &str, span: &str, divide: &str, sweep: &str) -> McuKey {
    (
        board.to_string(),
        figure.to_string(),
        span.to_string(),
        divide.to_string(),
        sweep.to_string(),
    )
}

/// The MCU cell of a row: measured for the span rows (exact divider, Gouraud) and
/// the divide and setup rows (`classic`, `gradient` with a divider) whose figure,
/// method and divider the file holds, `not measured` otherwise.
fn mcu_cell(
    counts: &HashMap<McuKey, McuCount>,
    board: &str,
    figure: &str,
    c: &Config,
) -> Option<f64> {
    let (divide, sweep) = match c.kind {
        Kind::Span => ("exact", "span"),
        // The firmware draws the divider rows with Gouraud only (not the Phong
        // setup rows).
        Kind::Divide | Kind::Setup if c.shading == ShadingName::GOURAUD => {
            (c.divide.name(), "divide")
        }
        _ => return None,
    };
    counts
        .get(&mcu_key(board, figure, c.span.name(), divide, sweep))
        .map(|m| m.per_pixel)
}

/// The dividers under QEMU, for the summary: `table` and `shift-add-8` in `classic`
/// and `gradient` on each board, against `exact` drawn by the same firmware image
/// (medians over the figures that have both); empty when the file has none.
fn mcu_dividers(rows: &[Row], figures: &[String], counts: &HashMap<McuKey, McuCount>) -> String {
    let mut boards = Vec::new();
    let mut most = 0.0f64;
    for (board, label) in [
        ("microbit", "Cortex-M0 (no divide instruction)"),
        ("mps2-an386", "Cortex-M4 (32-bit hardware divide)"),
    ] {
        let mut parts = Vec::new();
        for (kind, span) in [
            (Kind::Divide, SpanName::CLASSIC),
            (Kind::Setup, SpanName::GRADIENT),
        ] {
            let mut ds = Vec::new();
            for d in [DivideName::named("table"), DivideName::named("shift-add-8")] {
                // Figures of the report that ran this row and whose pair was measured.
                let pairs: Vec<(McuCount, McuCount)> = figures
                    .iter()
                    .filter(|f| {
                        rows.iter().any(|r| {
                            &r.figure == *f
                                && r.config.kind == kind
                                && r.config.shading == ShadingName::GOURAUD
                                && r.config.divide == d
                        })
                    })
                    .filter_map(|f| {
                        let at = |d: &str| counts.get(&mcu_key(board, f, span.name(), d, "divide"));
                        Some((*at(d.name())?, *at("exact")?))
                    })
                    .collect();
                if pairs.is_empty() {
                    continue;
                }
                let m = |g: &dyn Fn(&(McuCount, McuCount)) -> f64| {
                    median_f(pairs.iter().map(g).collect())
                };
                let draw = m(&|p| p.0.draw_per_pixel);
                let draw0 = m(&|p| p.1.draw_per_pixel);
                let whole = m(&|p| p.0.per_pixel);
                let whole0 = m(&|p| p.1.per_pixel);
                let change = m(&|p| p.0.draw_per_pixel / p.1.draw_per_pixel - 1.0) * 100.0;
                most = most.max(-change);
                ds.push(format!(
                    "`{}` {draw:.0} against {draw0:.0} ({change:+.1} %; whole frame {whole:.0} \
                     against {whole0:.0})",
                    d.name()
                ));
            }
            if !ds.is_empty() {
                parts.push(format!("`{}` {}", span.name(), ds.join(", ")));
            }
        }
        if !parts.is_empty() {
            boards.push(format!("on {label} {}", parts.join("; ")));
        }
    }
    if boards.is_empty() {
        return String::new();
    }
    let why = if most < 10.0 {
        ": the `classic` span keeps its wide products of the exact edge crossings whatever \
         the divider, and the setup's reciprocal is paid once per triangle, not per pixel"
    } else {
        ""
    };
    format!(
        "Under QEMU the rasterizer's instructions per covered pixel with a divider, against \
         `exact` compiled into the same firmware image{}: {}. The approximate dividers save \
         at most {:.1} % of the draw here{why}. ",
        if figures.len() > 1 {
            ", medians over the figures"
        } else {
            ""
        },
        boards.join("; "),
        most.max(0.0)
    )
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
    /// Median frame time over the rounds.
    pub frame: Duration,
    /// Host ns per covered pixel.
    pub ns_per_px: f64,
    /// Round-to-round spread of the frame time: interquartile range over median.
    pub spread: f64,
    /// Frame time over the baseline's of the same figure.
    pub ratio: f64,
    /// The render's bytes equal those of the `gradient` + Gouraud render.
    pub same_as_gradient: bool,
    /// On the figure's Pareto front: no other configuration is both cheaper and
    /// closer to the per-pixel reference.
    pub pareto: bool,
    /// Cortex-M0 instructions per covered pixel (QEMU), where measured.
    pub mcu_m0: Option<f64>,
    /// Cortex-M4 instructions per covered pixel (QEMU), where measured.
    pub mcu_m4: Option<f64>,
}

/// The result of a report run.
#[derive(Clone, Debug)]
pub struct Report {
    /// Rows, figure by figure in configuration order.
    pub rows: Vec<Row>,
    /// The text table printed on stdout.
    pub table: String,
    /// The generated trade-off paragraph.
    pub summary: String,
    /// Paths written.
    pub files: Vec<PathBuf>,
}

fn progress(on: bool, k: usize, n: usize, what: &str) {
    if on {
        let mut e = std::io::stderr();
        let _ = write!(e, "\r[{k}/{n}] {what:<48}");
        let _ = e.flush();
    }
}

fn median(v: &mut [Duration]) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// Runs the report and writes its files into `opts.out_dir`.
pub fn run_report(opts: &ReportOptions) -> Result<Report, String> {
    let per_figure: Vec<Vec<Config>> = opts
        .figures
        .iter()
        .map(|f| configurations(opts.quick, specular_rows(f)))
        .collect();
    let n_meas: usize = per_figure.iter().map(Vec::len).sum();
    let rounds = opts.rounds.max(1);
    let total = n_meas * (1 + rounds);
    let mut step = 0;

    // Accuracy: render and compare every configuration once.
    struct Item {
        figure: String,
        config: Config,
        ls: LoadedScene,
        cmp: crate::image::compare::Comparison,
        nmse_vs_gouraud: f64,
        nmse_vs_phong: f64,
        covered: usize,
        bytes: Vec<u8>,
    }
    let mut items: Vec<Item> = Vec::with_capacity(n_meas);
    for (fig, configs) in opts.figures.iter().zip(&per_figure) {
        let base = load::load_arg(fig)?;
        let mut refs: HashMap<(&'static str, bool, u32), Image> = HashMap::new();
        for c in configs {
            step += 1;
            progress(
                opts.progress,
                step,
                total,
                &format!("{fig} {} {}", c.kind.as_str(), c.name()),
            );
            let mut ls = base.clone();
            ls.desc.span = c.span;
            ls.desc.shading = c.shading;
            ls.desc.divide = c.divide;
            ls.desc.specular = c.specular;
            ls.desc.perspective_correct = c.perspective > 0;
            if c.perspective > 0 {
                ls.desc.perspective_span = c.perspective;
            }
            if c.shininess > 0 {
                for o in &mut ls.desc.objects {
                    o.material.shininess = c.shininess as f64;
                }
            }
            let key = (c.reference_name(), c.phong_reference(), c.shininess);
            refs.entry(key).or_insert_with(|| {
                let mut r = ls.clone();
                r.desc.perspective_correct = c.kind == Kind::Perspective;
                render::reference(&r, key.1)
            });
            let gkey = ("gouraud", false, c.shininess);
            refs.entry(gkey).or_insert_with(|| {
                let mut g = ls.clone();
                g.desc.shading = ShadingName::GOURAUD;
                g.desc.perspective_correct = false;
                render::reference(&g, false)
            });
            let pkey = ("phong", true, c.shininess);
            refs.entry(pkey).or_insert_with(|| {
                let mut r = ls.clone();
                r.desc.perspective_correct = false;
                render::reference(&r, true)
            });
            let r = render::render(&ls, None)?;
            let cmp = compare(&refs[&key], &r.image)?;
            let nmse_vs_gouraud = compare(&refs[&gkey], &r.image)?.nmse;
            let nmse_vs_phong = compare(&refs[&pkey], &r.image)?.nmse;
            items.push(Item {
                figure: fig.clone(),
                config: *c,
                ls,
                cmp,
                nmse_vs_gouraud,
                nmse_vs_phong,
                covered: r.image.covered_count(),
                bytes: r.bytes,
            });
        }
    }

    // Time: interleaved rounds, each timing every configuration once; the start
    // rotates so no configuration always runs first.
    let mut times: Vec<Vec<Duration>> = vec![Vec::with_capacity(rounds); items.len()];
    for round in 0..rounds {
        for j in 0..items.len() {
            let i = (j + round) % items.len();
            step += 1;
            if j % 4 == 0 || j + 1 == items.len() {
                progress(
                    opts.progress,
                    step,
                    total,
                    &format!("timing round {}/{rounds}", round + 1),
                );
            }
            times[i].push(render::time_frame(&items[i].ls, opts.runs_per_round)?);
        }
    }
    if opts.progress {
        eprintln!();
    }

    let counts = mcu_counts();
    let mut rows = Vec::with_capacity(items.len());
    for (it, t) in items.iter().zip(times.iter_mut()) {
        let frame = median(t);
        let q = |f: usize| t[(t.len() - 1) * f / 4].as_secs_f64();
        let spread = (q(3) - q(1)) / frame.as_secs_f64().max(1e-12);
        rows.push(Row {
            figure: it.figure.clone(),
            config: it.config,
            nmse: it.cmp.nmse,
            nmse_vs_gouraud: it.nmse_vs_gouraud,
            nmse_vs_phong: it.nmse_vs_phong,
            verdict: it.cmp.verdict.as_str(),
            max_channel_error: it.cmp.max_channel_error,
            coverage_mismatch: it.cmp.coverage_mismatch,
            covered: it.covered,
            frame,
            ns_per_px: frame.as_nanos() as f64 / it.covered.max(1) as f64,
            spread,
            ratio: f64::NAN,
            same_as_gradient: false,
            pareto: false,
            mcu_m0: mcu_cell(&counts, "microbit", &it.figure, &it.config),
            mcu_m4: mcu_cell(&counts, "mps2-an386", &it.figure, &it.config),
        });
    }
    for fig in &opts.figures {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| &rows[i].figure == fig)
            .collect();
        let base = idx
            .iter()
            .find(|&&i| is_baseline(&rows[i].config))
            .map(|&i| rows[i].frame.as_secs_f64());
        let grad = idx.iter().copied().find(|&i| {
            rows[i].config.kind == Kind::Span && rows[i].config.span == SpanName::GRADIENT
        });
        for &i in &idx {
            if let Some(b) = base {
                rows[i].ratio = rows[i].frame.as_secs_f64() / b;
            }
            if let Some(g) = grad {
                rows[i].same_as_gradient = items[i].bytes == items[g].bytes;
            }
        }
        // Pareto front on one yardstick for all rows, the per-pixel (Phong) reference:
        // cheapest first, a row is on it if it is more exact than every cheaper row.
        let mut order = idx.clone();
        order.sort_by(|&a, &b| {
            rows[a]
                .ns_per_px
                .total_cmp(&rows[b].ns_per_px)
                .then(rows[a].nmse_vs_phong.total_cmp(&rows[b].nmse_vs_phong))
        });
        let mut best = f64::INFINITY;
        for i in order {
            if rows[i].nmse_vs_phong < best {
                best = rows[i].nmse_vs_phong;
                rows[i].pareto = true;
            }
        }
    }

    let summary = summarize(&rows, &opts.figures, &counts);
    let table = text_table(&rows);
    std::fs::create_dir_all(&opts.out_dir)
        .map_err(|e| format!("cannot create {}: {e}", opts.out_dir.display()))?;
    let md = opts.out_dir.join(format!("{STEM}.md"));
    let csv = opts.out_dir.join(format!("{STEM}.csv"));
    let png = opts.out_dir.join(format!("{STEM}.png"));
    let write = |p: &Path, s: &str| {
        std::fs::write(p, s).map_err(|e| format!("cannot write {}: {e}", p.display()))
    };
    write(&md, &markdown(opts, &rows, &summary))?;
    write(&csv, &to_csv(&rows))?;
    plot::write_chart(&rows, &opts.figures, &png)?;
    Ok(Report {
        rows,
        table,
        summary,
        files: vec![md, csv, png],
    })
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".to_string()
    } else {
        format!("{x:.3e}")
    }
}

/// The cells of a row in table order, shared by the text and markdown tables.
fn cells(r: &Row) -> [String; 13] {
    [
        r.figure.clone(),
        r.config.kind.as_str().to_string(),
        r.config.name(),
        sci(r.nmse),
        r.verdict.to_string(),
        r.max_channel_error.to_string(),
        r.coverage_mismatch.to_string(),
        sci(r.nmse_vs_phong),
        format!("{:.2}", r.ns_per_px),
        format!("{:.3}", r.ratio),
        if r.pareto { "yes" } else { "" }.to_string(),
        mcu_text(r.mcu_m0),
        mcu_text(r.mcu_m4),
    ]
}

fn mcu_text(v: Option<f64>) -> String {
    v.map_or(NOT_MEASURED.to_string(), |v| format!("{v:.1}"))
}

fn text_table(rows: &[Row]) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<8} {:<8} {:<22} {:>10} {:<17} {:>4} {:>6} {:>10} {:>7} {:>7} {:>6}  {:<12} {:<12}",
        "figure",
        "kind",
        "configuration",
        "NMSE",
        "verdict",
        "max",
        "cov",
        "NMSE/pixref",
        "ns/px",
        "ratio",
        "pareto",
        "instr/px M0",
        "instr/px M4"
    );
    for r in rows {
        let c = cells(r);
        let _ = writeln!(
            t,
            "{:<8} {:<8} {:<22} {:>10} {:<17} {:>4} {:>6} {:>10} {:>7} {:>7} {:>6}  {:<12} {:<12}",
            c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9], c[10], c[11], c[12]
        );
    }
    t.pop();
    t
}

/// The CSV header.
pub const CSV_HEADER: &str = "figure,kind,configuration,span,shading,reference,nmse,verdict,\
max_channel_error,coverage_mismatch,covered_pixels,frame_ns,ns_per_px,ratio_to_classic_gouraud,\
pareto,instr_per_px_m0,instr_per_px_m4,nmse_vs_gouraud_reference,nmse_vs_phong_reference,timing_spread,divide,specular_model,shininess";

fn to_csv(rows: &[Row]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:e},{},{},{},{},{},{:.4},{:.4},{},{},{},{:e},{:e},{:.4},{},{},{}",
            r.figure,
            r.config.kind.as_str(),
            r.config.name(),
            r.config.span.name(),
            r.config.shading.name(),
            r.config.reference_name(),
            r.nmse,
            r.verdict,
            r.max_channel_error,
            r.coverage_mismatch,
            r.covered,
            r.frame.as_nanos(),
            r.ns_per_px,
            r.ratio,
            r.pareto,
            mcu_text(r.mcu_m0),
            mcu_text(r.mcu_m4),
            r.nmse_vs_gouraud,
            r.nmse_vs_phong,
            r.spread,
            r.config.divide.name(),
            r.config.specular.name(),
            r.config.shininess
        );
    }
    s
}

fn markdown(opts: &ReportOptions, rows: &[Row], summary: &str) -> String {
    let mut m = String::new();
    let _ = writeln!(m, "# Accuracy versus time\n");
    let _ = writeln!(
        m,
        "<!-- Generated by `fixshade report`; rerun the command below instead of editing. -->\n"
    );
    let _ = writeln!(m, "Made by `{}`.", opts.command());
    let _ = writeln!(
        m,
        "Machine: {MACHINE_NOTE}. Host time is the median over {} interleaved rounds \
         (each round times every configuration once, each time the median of {} frames); \
         the ratio is to `classic` + `gouraud` of the same figure in the same run.\n",
        opts.rounds.max(1),
        opts.runs_per_round.max(1)
    );
    let _ = writeln!(m, "## What it shows\n\n{summary}\n");
    let _ = writeln!(m, "![NMSE against host ns per covered pixel]({STEM}.png)\n");
    let _ = writeln!(m, "## Table\n");
    let _ = writeln!(
        m,
        "| figure | kind | configuration | NMSE | verdict | max channel error | coverage mismatch | NMSE vs per-pixel | host ns/px | × classic | Pareto | instr/px M0 | instr/px M4 |"
    );
    let _ = writeln!(
        m,
        "|---|---|---|---:|---|---:|---:|---:|---:|---:|---|---|---|"
    );
    for r in rows {
        let mut c = cells(r);
        c[2] = format!("`{}`", c[2]);
        let _ = writeln!(m, "| {} |", c.join(" | "));
    }
    let _ = writeln!(
        m,
        "\nSpan rows use Gouraud shading; shading rows use the `gradient` span (Gouraud with \
         `gradient` is the span row `gradient`). NMSE is against the matching exact f64 reference: \
         the flat one for flat, the Gouraud one for Gouraud, the per-pixel (Phong) one for \
         `quadratic` and `phong`; the CSV also gives every row's NMSE against the Gouraud \
         and the per-pixel references. The Pareto column and the plot use one yardstick \
         for every row, the NMSE against the per-pixel reference: a row is on the front when \
         every cheaper row of its figure is further from that reference. Max channel error is in 8-bit units; coverage mismatch counts pixels covered in one \
         image only. Host ns/px is the frame time (vertex stage and rasterization) over the \
         covered pixels. The MCU columns are instructions per covered pixel (whole frame: \
         vertex stage and rasterization) under QEMU, from `docs/mcu-instructions.csv` \
         (`cargo xtask qemu`, Cortex-M0 = micro:bit, Cortex-M4 = MPS2-AN386); the firmware \
         draws every span method with Gouraud and the exact divider, and `classic` and \
         `gradient` with each divider (all of them on the Cortex-M4 on the three figures; \
         on the Cortex-M0 all of them on the sphere and the quick report's six on teapot \
         and robot), so only those span, divide and setup rows have them. Every other cell says `not measured` and is \
         never estimated.\n\n\
         Divide rows are the `classic` span with the named divider in its per-span \
         division; setup rows are the `gradient` span with the divider in the triangle \
         setup's reciprocal (their `exact` rows are the span rows `classic` and \
         `gradient`). In the pipeline every divider but `exact` sees a wide divisor \
         rounded up to a mantissa of b bits (12 for `table`, ⌊(N + 1)/2⌋ for the \
         shift-and-add ones) and reciprocates it through the seam \
         (`fixshade::divide::wide_recip`), so `table` is not bit-identical to `exact` \
         here. The host draws the approximate dividers through one run-time-selected \
         type, which adds a predictable branch per division to their host time. \
         Specular rows (sphere only) are Phong shading with the `gradient` span, every \
         material's shininess set to n, against the per-pixel reference with the same n. \
         Perspective rows are Gouraud with perspective-correct colours, one reciprocal \
         per N pixels (`Npx`) through the named divider and linear in between, against \
         the perspective-correct reference (`off`: screen-space interpolation against \
         that same reference); their coverage is `gradient`'s.\n"
    );
    m
}

fn median_f(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

/// Writes the trade-off paragraph from the measured rows.
fn summarize(rows: &[Row], figures: &[String], counts: &HashMap<McuKey, McuCount>) -> String {
    use crate::image::compare::Verdict;
    let nf = figures.len();
    let of = |pred: &dyn Fn(&Config) -> bool| -> Vec<&Row> {
        rows.iter().filter(|r| pred(&r.config)).collect()
    };
    let med = |rs: &[&Row], f: &dyn Fn(&Row) -> f64| median_f(rs.iter().map(|r| f(r)).collect());
    let mult = |x: f64| {
        if x >= 100.0 {
            format!("{x:.0}")
        } else if x >= 10.0 {
            format!("{x:.1}")
        } else {
            format!("{x:.2}")
        }
    };
    let word = |n: f64| Verdict::from_nmse(n).as_str();
    let figs = if nf == 1 {
        format!("the {}", figures[0])
    } else {
        format!("all {nf} figures")
    };
    let over = if nf == 1 {
        String::new()
    } else {
        format!(", medians over {nf} figures")
    };
    let mut s = String::new();

    let base = of(&is_baseline);
    let base_ns: Vec<String> = base
        .iter()
        .map(|r| format!("{:.1} ns/px on the {}", r.ns_per_px, r.figure))
        .collect();
    let spread = median_f(rows.iter().map(|r| r.spread).collect());
    let _ = write!(
        s,
        "The baseline, the `classic` span with Gouraud shading, costs {}; times below are \
         relative to it{over}. The round-to-round spread of a configuration's time \
         (interquartile range over median) is typically {:.0} %, so time differences smaller \
         than that are noise on this machine. ",
        base_ns.join(", "),
        spread * 100.0
    );

    // Span methods: (name, median ratio, figures with gradient's image, median NMSE).
    let grad_rows = of(&|c: &Config| c.kind == Kind::Span && c.span == SpanName::GRADIENT);
    let grad_nmse = med(&grad_rows, &|r| r.nmse);
    let mut spans: Vec<(&'static str, f64, usize, f64)> = SpanName::ALL
        .iter()
        .map(|&(sp, name)| {
            let rs = of(&|c: &Config| c.kind == Kind::Span && c.span == sp);
            let same = rs.iter().filter(|r| r.same_as_gradient).count();
            (name, med(&rs, &|r| r.ratio), same, med(&rs, &|r| r.nmse))
        })
        .filter(|x| x.1.is_finite())
        .collect();
    spans.sort_by(|a, b| a.1.total_cmp(&b.1));
    if let Some(fast) = spans.first() {
        let _ = write!(
            s,
            "The fastest span method is `{}` at {:.2}× classic, with NMSE {} ({}). ",
            fast.0,
            fast.1,
            sci(fast.3),
            word(fast.3)
        );
    }
    let lossless: Vec<String> = spans
        .iter()
        .filter(|x| x.2 == nf && x.0 != "gradient")
        .map(|x| format!("`{}` {:.2}×", x.0, x.1))
        .collect();
    if !lossless.is_empty() {
        let _ = write!(
            s,
            "These span methods give exactly `gradient`'s image on {figs} (NMSE {}), so they \
             lose nothing and differ only in time: {} (`gradient` itself: {:.2}×). ",
            sci(grad_nmse),
            lossless.join(", "),
            spans
                .iter()
                .find(|g| g.0 == "gradient")
                .map(|g| g.1)
                .unwrap_or(f64::NAN)
        );
    }
    for x in spans.iter().filter(|x| x.2 < nf && x.0 != "gradient") {
        let rel = if grad_nmse > 0.0 {
            format!(", {}× gradient's", mult(x.3 / grad_nmse))
        } else {
            String::new()
        };
        let grad_ratio = spans
            .iter()
            .find(|g| g.0 == "gradient")
            .map(|g| g.1)
            .unwrap_or(f64::NAN);
        if x.0 == "classic" {
            let _ = write!(
                s,
                "`classic` itself, with its division per span, takes {:.2}× `gradient`'s time and \
                 does not match its image: NMSE {} ({}{rel}). ",
                1.0 / grad_ratio,
                sci(x.3),
                word(x.3)
            );
        } else {
            let _ = write!(
                s,
                "`{}` costs {:.2}× classic and does not match `gradient`'s image: NMSE {} ({}{rel}). ",
                x.0,
                x.1,
                sci(x.3),
                word(x.3)
            );
        }
    }

    // Shading modes, each against Gouraud with the same (gradient) span.
    let gouraud = of(&|c: &Config| {
        c.kind == Kind::Span && c.span == SpanName::GRADIENT && c.shading == ShadingName::GOURAUD
    });
    for &(sh, name) in ShadingName::ALL {
        if sh == ShadingName::GOURAUD {
            continue;
        }
        let rs = of(&|c: &Config| c.kind == Kind::Shading && c.shading == sh);
        if rs.is_empty() {
            continue;
        }
        let t = median_f(
            rs.iter()
                .filter_map(|r| {
                    gouraud
                        .iter()
                        .find(|g| g.figure == r.figure)
                        .map(|g| r.frame.as_secs_f64() / g.frame.as_secs_f64())
                })
                .collect(),
        );
        let n = med(&rs, &|r| r.nmse);
        let _ = write!(
            s,
            "Shading `{name}` takes {t:.2}× Gouraud's time (both with `gradient`); "
        );
        if rs[0].config.phong_reference() {
            let g = med(&gouraud, &|r| r.nmse_vs_phong);
            let _ = write!(
                s,
                "against the per-pixel (Phong) reference its NMSE is {} ({}), where Gouraud's is {} ({}). ",
                sci(n),
                word(n),
                sci(g),
                word(g)
            );
        } else {
            let m = med(&rs, &|r| r.nmse_vs_gouraud);
            let g = med(&gouraud, &|r| r.nmse);
            let _ = write!(
                s,
                "it matches its own f64 reference with NMSE {}, but against the smooth Gouraud \
                 reference its NMSE is {} ({}), where Gouraud's is {}. ",
                sci(n),
                sci(m),
                word(m),
                sci(g)
            );
        }
    }

    // Dividers: each against the exact row of its own sweep, same figure, same run.
    for (kind, span, shading, where_) in [
        (
            Kind::Divide,
            SpanName::CLASSIC,
            ShadingName::GOURAUD,
            "the `classic` span's per-span division",
        ),
        (
            Kind::Setup,
            SpanName::GRADIENT,
            ShadingName::GOURAUD,
            "the triangle setup's reciprocal (`gradient` span)",
        ),
        (
            Kind::Setup,
            SpanName::GRADIENT,
            ShadingName::PHONG,
            "the Phong setup's reciprocal (normals, eye positions and depth)",
        ),
    ] {
        // The exact row of the sweep: the span row (Gouraud) or the shading row.
        let exact = of(&|c: &Config| {
            matches!(c.kind, Kind::Span | Kind::Shading) && c.span == span && c.shading == shading
        });
        let mut parts = Vec::new();
        let mut within = None;
        for &(d, name) in DivideName::ALL {
            let rs = of(&|c: &Config| c.kind == kind && c.shading == shading && c.divide == d);
            if rs.is_empty() {
                continue;
            }
            let t = median_f(
                rs.iter()
                    .filter_map(|r| {
                        exact
                            .iter()
                            .find(|e| e.figure == r.figure)
                            .map(|e| r.frame.as_secs_f64() / e.frame.as_secs_f64())
                    })
                    .collect(),
            );
            let n = med(&rs, &|r| r.nmse);
            let mx = rs.iter().map(|r| r.max_channel_error).max().unwrap_or(0);
            let n0 = med(&exact, &|r| r.nmse);
            let truncated =
                d.name().starts_with("shift-add-") && !d.name().starts_with("shift-add-rounded-");
            if within.is_none() && truncated && n <= n0 * 1.1 {
                within = Some((name, n));
            }
            if QUICK_DIVIDERS.contains(&d) {
                parts.push(format!(
                    "`{name}` costs {t:.2}× `exact`'s host time and reaches NMSE {} ({}; max \
                     channel error {mx})",
                    sci(n),
                    word(n)
                ));
            }
        }
        if parts.is_empty() {
            continue;
        }
        let n0 = med(&exact, &|r| r.nmse);
        let _ = write!(
            s,
            "In {where_}, against `exact` there (NMSE {}{over}): {}. ",
            sci(n0),
            parts.join("; ")
        );
        if let Some((name, n)) = within {
            let _ = write!(
                s,
                "The truncated shift-and-add first comes within 10 % of `exact`'s NMSE at \
                 `{name}` (NMSE {}). ",
                sci(n)
            );
        }
    }
    // Perspective correction: each row against the perspective-correct reference,
    // time against the screen-space row of the same figure.
    let off = of(&|c: &Config| c.kind == Kind::Perspective && c.perspective == 0);
    if !off.is_empty() {
        let mut parts = Vec::new();
        for (px, d) in PERSPECTIVE_ROWS.iter().skip(1) {
            let rs = of(&|c: &Config| {
                c.kind == Kind::Perspective && c.perspective == *px && c.divide == *d
            });
            if rs.is_empty() {
                continue;
            }
            let t = median_f(
                rs.iter()
                    .filter_map(|r| {
                        off.iter()
                            .find(|e| e.figure == r.figure)
                            .map(|e| r.frame.as_secs_f64() / e.frame.as_secs_f64())
                    })
                    .collect(),
            );
            let n = med(&rs, &|r| r.nmse);
            let every = if *px == 1 {
                "every pixel".to_string()
            } else {
                format!("every {px} pixels")
            };
            parts.push(format!(
                "one division {every} with `{}` reaches NMSE {} at {t:.2}× the time",
                d.name(),
                sci(n)
            ));
        }
        let n0 = med(&off, &|r| r.nmse);
        let _ = write!(
            s,
            "Perspective correction (Gouraud, against the perspective-correct reference): \
             screen-space interpolation has NMSE {} ({}) on these finely tessellated \
             figures; {}. The figures' triangles are a few pixels wide, so the affine \
             error is small here; on large triangles it is not (docs/effects.md, \
             ground plane). ",
            sci(n0),
            word(n0),
            parts.join("; ")
        );
    }
    if of(&|c: &Config| c.kind == Kind::Divide)
        .iter()
        .any(|r| r.ratio.is_finite())
    {
        let _ = write!(
            s,
            "On the host the dividers barely move the time: a 64-bit host divides in a few \
             cycles, and the approximate ones pay a run-time dispatch here. "
        );
        let _ = write!(s, "{}", mcu_dividers(rows, figures, counts));
    }

    // MCU instruction counts of the span rows.
    for board in [("M0", true), ("M4", false)] {
        let pick = |r: &Row| if board.1 { r.mcu_m0 } else { r.mcu_m4 };
        let base = of(&is_baseline);
        let grad = of(&|c: &Config| c.kind == Kind::Span && c.span == SpanName::GRADIENT);
        let b: Vec<f64> = base.iter().filter_map(|r| pick(r)).collect();
        let g: Vec<f64> = grad.iter().filter_map(|r| pick(r)).collect();
        if !b.is_empty() && !g.is_empty() {
            let _ = write!(
                s,
                "On Cortex-{} (QEMU) `classic` takes {:.0} instructions per covered pixel and \
                 `gradient` {:.0}{over}. ",
                board.0,
                median_f(b),
                median_f(g)
            );
        }
    }

    // Specular models, per exponent, against the per-pixel reference with that n.
    let spec = of(&|c: &Config| c.kind == Kind::Specular);
    if !spec.is_empty() {
        let ns: Vec<u32> = {
            let mut v: Vec<u32> = spec.iter().map(|r| r.config.shininess).collect();
            v.sort();
            v.dedup();
            v
        };
        let mut parts = Vec::new();
        for &(sp, name) in SpecularName::ALL {
            let rs: Vec<&&Row> = spec.iter().filter(|r| r.config.specular == sp).collect();
            if rs.is_empty() {
                continue;
            }
            let per_n: Vec<String> = ns
                .iter()
                .filter_map(|n| rs.iter().find(|r| r.config.shininess == *n))
                .map(|r| sci(r.nmse))
                .collect();
            let t = median_f(
                rs.iter()
                    .filter_map(|r| {
                        spec.iter()
                            .find(|e| {
                                e.config.specular == SpecularName::EXACT
                                    && e.config.shininess == r.config.shininess
                                    && e.figure == r.figure
                            })
                            .map(|e| r.frame.as_secs_f64() / e.frame.as_secs_f64())
                    })
                    .collect(),
            );
            parts.push(format!(
                "`{name}` {} at {t:.2}× `exact`'s time",
                per_n.join(" / ")
            ));
        }
        let ns_txt: Vec<String> = ns.iter().map(u32::to_string).collect();
        let _ = write!(
            s,
            "With Phong shading on the sphere, NMSE against the per-pixel reference at n = {}: \
             {}. ",
            ns_txt.join(" / "),
            parts.join("; ")
        );
    }

    // Pareto fronts.
    for f in figures {
        let mut front: Vec<&Row> = rows.iter().filter(|r| &r.figure == f && r.pareto).collect();
        front.sort_by(|a, b| a.ns_per_px.total_cmp(&b.ns_per_px));
        let names: Vec<String> = front
            .iter()
            .map(|r| {
                format!(
                    "{} ({:.2} ns/px, NMSE {})",
                    r.config.label(),
                    r.ns_per_px,
                    sci(r.nmse_vs_phong)
                )
            })
            .collect();
        let _ = write!(
            s,
            "On the {f} the Pareto front (NMSE against the per-pixel reference, cheapest \
             first) is {}. ",
            names.join(", ")
        );
    }
    s.pop();
    s
}

/// The chart: plotters draws the geometry into a memory buffer; labels use a small
/// built-in pixel font (plotters' own text needs a font library); the `png` crate
/// encodes it.
mod plot {
    use super::{Kind, Row};
    use crate::chart::plot::{nice_step, Canvas, Label};
    use plotters::prelude::*;
    use std::path::Path;

    const W: u32 = 1000;
    const H: u32 = 680;
    const COLORS: [RGBColor; 6] = [
        RGBColor(0, 90, 200),
        RGBColor(220, 80, 0),
        RGBColor(0, 150, 60),
        RGBColor(150, 0, 150),
        RGBColor(120, 90, 0),
        RGBColor(0, 140, 150),
    ];

    pub fn write_chart(rows: &[Row], figures: &[String], path: &Path) -> Result<(), String> {
        let mut canvas = Canvas::new(W, H);
        let labels = draw(rows, figures, &mut canvas.buf).map_err(|e| format!("chart: {e}"))?;
        canvas.finish(&labels, path)
    }

    fn draw(
        rows: &[Row],
        figures: &[String],
        buf: &mut [u8],
    ) -> Result<Vec<Label>, Box<dyn std::error::Error>> {
        let mut labels = Vec::new();
        let black = RGBColor(0, 0, 0);
        let grey = RGBColor(215, 215, 215);
        // NMSE 0 (exact) is drawn a decade below the smallest positive NMSE.
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
        let nm = |r: &Row| r.nmse_vs_phong.max(floor);
        let finite: Vec<&Row> = rows.iter().filter(|r| r.ns_per_px.is_finite()).collect();
        let xmax = finite.iter().map(|r| r.ns_per_px).fold(0.0, f64::max) * 1.08;
        let xmin = finite
            .iter()
            .map(|r| r.ns_per_px)
            .fold(f64::INFINITY, f64::min)
            .min(xmax)
            * 0.9;
        let (xmin, xmax) = if xmax > xmin {
            (xmin, xmax)
        } else {
            (0.0, 1.0)
        };
        let lo = finite.iter().map(|r| nm(r)).fold(f64::INFINITY, f64::min);
        let hi = finite.iter().map(|r| nm(r)).fold(0.0, f64::max);
        let (ylo_e, yhi_e) = if lo.is_finite() && hi > 0.0 {
            (
                lo.log10().floor() as i32,
                (hi.log10().ceil() as i32).max(lo.log10().floor() as i32 + 1),
            )
        } else {
            (-7, -2)
        };
        let (ylo, yhi) = (10f64.powi(ylo_e), 10f64.powi(yhi_e));

        let root = BitMapBackend::with_buffer(buf, (W, H)).into_drawing_area();
        root.fill(&WHITE)?;
        let chart = ChartBuilder::on(&root)
            .margin_top(64)
            .margin_right(30)
            .margin_left(90)
            .margin_bottom(70)
            .build_cartesian_2d(xmin..xmax, (ylo..yhi).log_scale())?;
        let px = |x: f64, y: f64| chart.backend_coord(&(x, y));

        // Grid and tick labels.
        let step = nice_step(xmax - xmin);
        let mut x = (xmin / step).ceil() * step;
        while x <= xmax {
            chart.plotting_area().draw(&PathElement::new(
                vec![(x, ylo), (x, yhi)],
                grey.stroke_width(1),
            ))?;
            let (bx, by) = px(x, ylo);
            let t = if step >= 1.0 {
                format!("{x:.0}")
            } else {
                format!("{x:.1}")
            };
            labels.push(Label {
                x: bx - 6 * t.len() as i32,
                y: by + 10,
                text: t,
                scale: 2,
                color: black,
            });
            x += step;
        }
        for e in ylo_e..=yhi_e {
            let y = 10f64.powi(e);
            chart.plotting_area().draw(&PathElement::new(
                vec![(xmin, y), (xmax, y)],
                grey.stroke_width(1),
            ))?;
            let (bx, by) = px(xmin, y);
            let t = format!("1e{e}");
            labels.push(Label {
                x: bx - 12 * t.len() as i32 - 8,
                y: by - 7,
                text: t,
                scale: 2,
                color: black,
            });
        }
        let (x0, y0) = px(xmin, ylo);
        let (x1, y1) = px(xmax, yhi);
        root.draw(&Rectangle::new([(x0, y1), (x1, y0)], black.stroke_width(1)))?;
        labels.push(Label {
            x: (x0 + x1) / 2 - 6 * 28,
            y: y0 + 40,
            text: "host ns per covered pixel".into(),
            scale: 2,
            color: black,
        });
        labels.push(Label {
            x: x0 - 85,
            y: 6,
            text: "NMSE against the per-pixel f64 reference (log) and host time".into(),
            scale: 2,
            color: black,
        });
        labels.push(Label {
            x: x0 - 85,
            y: y1 - 28,
            text: "NMSE, lines join each figure's pareto front".into(),
            scale: 2,
            color: black,
        });

        // Points and fronts.
        for (fi, f) in figures.iter().enumerate() {
            let col = COLORS[fi % COLORS.len()];
            let mine: Vec<&Row> = finite.iter().copied().filter(|r| &r.figure == f).collect();
            let mut front: Vec<&Row> = mine.iter().copied().filter(|r| r.pareto).collect();
            front.sort_by(|a, b| a.ns_per_px.total_cmp(&b.ns_per_px));
            chart.plotting_area().draw(&PathElement::new(
                front
                    .iter()
                    .map(|r| (r.ns_per_px, nm(r)))
                    .collect::<Vec<_>>(),
                col.stroke_width(2),
            ))?;
            for r in &mine {
                let p = (r.ns_per_px, nm(r));
                let style = if r.pareto {
                    col.filled()
                } else {
                    col.stroke_width(2)
                };
                match r.config.kind {
                    Kind::Span => {
                        chart.plotting_area().draw(&Circle::new(p, 5, style))?;
                    }
                    Kind::Shading => {
                        let (bx, by) = px(p.0, p.1);
                        root.draw(&Rectangle::new([(bx - 5, by - 5), (bx + 5, by + 5)], style))?;
                    }
                    Kind::Divide | Kind::Setup | Kind::Specular | Kind::Perspective => {
                        // Small markers: many rows, close together.
                        chart.plotting_area().draw(&Circle::new(p, 2, style))?;
                    }
                }
                if r.pareto || r.config.kind == Kind::Shading {
                    let (bx, by) = px(p.0, p.1);
                    labels.push(Label {
                        x: bx + 4,
                        y: by + 8,
                        text: r.config.name().to_string(),
                        scale: 1,
                        color: col,
                    });
                }
            }
            // Legend.
            let ly = y1 + 14 + 22 * fi as i32;
            let lx = x1 - 230;
            root.draw(&Circle::new((lx, ly + 6), 5, col.filled()))?;
            labels.push(Label {
                x: lx + 12,
                y: ly,
                text: f.clone(),
                scale: 2,
                color: col,
            });
        }
        let ly = y1 + 14 + 22 * figures.len() as i32;
        let lx = x1 - 230;
        root.draw(&Circle::new((lx, ly + 6), 5, black.stroke_width(2)))?;
        labels.push(Label {
            x: lx + 12,
            y: ly,
            text: "span (gouraud)".into(),
            scale: 2,
            color: black,
        });
        root.draw(&Rectangle::new(
            [(lx - 5, ly + 23), (lx + 5, ly + 33)],
            black.stroke_width(2),
        ))?;
        labels.push(Label {
            x: lx + 12,
            y: ly + 22,
            text: "shading (gradient)".into(),
            scale: 2,
            color: black,
        });
        labels.push(Label {
            x: lx - 5,
            y: ly + 44,
            text: "filled: on the front".into(),
            scale: 2,
            color: black,
        });
        if rows.iter().any(|r| r.nmse_vs_phong < floor) {
            labels.push(Label {
                x: lx - 5,
                y: ly + 66,
                text: format!("NMSE 0 drawn at 1e{}", floor.log10().round()),
                scale: 2,
                color: black,
            });
        }
        root.present()?;
        Ok(labels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CSV: &str = "\
board,figure,method,width,height,triangles,drawn,pixels,prepare,draw,total,per_pixel,per_triangle,draw_per_pixel,divide,sweep
microbit,sphere,classic,320,240,2976,3990,28456,400,300,700,24366.00,1.00,10258.00,exact,span
microbit,sphere,classic,320,240,2976,3990,28456,400,290,690,24400.00,1.00,10250.00,exact,divide
microbit,sphere,classic,320,240,2976,3990,28456,400,280,680,24253.00,1.00,10145.00,shift-add-8,divide
microbit,sphere,gradient,320,240,2976,3990,28456,400,40,440,15590.00,1.00,1460.00,table,divide
";

    fn row(kind: Kind, span: SpanName, divide: DivideName) -> Config {
        Config {
            divide,
            ..Config::new(kind, span, ShadingName::GOURAUD)
        }
    }

    #[test]
    fn divider_rows_read_their_own_csv_rows() {
        let m = parse_mcu_counts(CSV);
        let cell = |c: &Config| mcu_cell(&m, "microbit", "sphere", c);
        // The divide row: classic with shift-add-8 from the divider image.
        let sa8 = row(
            Kind::Divide,
            SpanName::CLASSIC,
            DivideName::named("shift-add-8"),
        );
        assert_eq!(cell(&sa8), Some(24253.0));
        // The setup row: gradient with the table.
        let table = row(Kind::Setup, SpanName::GRADIENT, DivideName::named("table"));
        assert_eq!(cell(&table), Some(15590.0));
        // The span row reads the span image, not the divider image's own `exact`.
        let span = row(Kind::Span, SpanName::CLASSIC, DivideName::EXACT);
        assert_eq!(cell(&span), Some(24366.0));
        // Not in the file: not measured, on the other board too.
        let sa4 = row(
            Kind::Divide,
            SpanName::CLASSIC,
            DivideName::named("shift-add-4"),
        );
        assert_eq!(cell(&sa4), None);
        assert_eq!(mcu_cell(&m, "mps2-an386", "sphere", &sa8), None);
        // A setup row is `gradient`'s, never `classic`'s with the same divider.
        let setup8 = row(
            Kind::Setup,
            SpanName::GRADIENT,
            DivideName::named("shift-add-8"),
        );
        assert_eq!(cell(&setup8), None);
        // Shading and perspective rows are never measured.
        let persp = Config {
            perspective: 16,
            ..row(
                Kind::Perspective,
                SpanName::GRADIENT,
                DivideName::named("shift-add-8"),
            )
        };
        assert_eq!(cell(&persp), None);
    }

    #[test]
    fn a_csv_without_divider_columns_holds_exact_span_rows() {
        let old: String = CSV
            .lines()
            .take(2)
            .map(|l| l.rsplitn(3, ',').nth(2).unwrap().to_string() + "\n")
            .collect();
        let m = parse_mcu_counts(&old);
        let span = row(Kind::Span, SpanName::CLASSIC, DivideName::EXACT);
        assert_eq!(mcu_cell(&m, "microbit", "sphere", &span), Some(24366.0));
        let sa8 = row(
            Kind::Divide,
            SpanName::CLASSIC,
            DivideName::named("shift-add-8"),
        );
        assert_eq!(mcu_cell(&m, "microbit", "sphere", &sa8), None);
    }
}
