//! `fixshade report`: what accuracy costs, and on which core it is paid.
//!
//! Every figure (sphere, teapot, robot) is rendered with every span method (with
//! Gouraud shading), every shading mode (with the `gradient` span), `classic` and
//! `gradient` with every divider (the per-span division and the setup reciprocal),
//! Phong with a few dividers in its setup, the perspective rows, and, on the sphere,
//! every specular model at n = 8, 32, 128, 512, 1000. Each configuration is compared
//! against the matching exact f64 reference (NMSE, deterministic) and priced by the
//! firmware's instruction counts per covered pixel under QEMU ([`mcu`]: ARMv6-M on
//! `mps2-an385-v6m`, Cortex-M4 on `mps2-an386`, full-frame images); host time is a
//! secondary column (interleaved rounds, medians).
//!
//! The document opens with a short generated summary and a recommendation table
//! ([`recommend`]), then one chart per core ([`chart`]: NMSE against instructions per
//! covered pixel, each figure's Pareto front drawn and labelled), the seed claims
//! measured ([`crate::tables::claims`]) and the full table. [`currency`] recomputes
//! the deterministic part of the committed documents so a test can tell when they
//! are stale.

pub mod chart;
pub mod currency;
pub mod mcu;
pub mod recommend;
pub mod text;

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
    /// Instructions per covered pixel on each core of [`mcu::BOARDS`].
    pub mcu: [mcu::McuCount; 2],
    /// On the figure's Pareto front on each core of [`mcu::BOARDS`]: no other
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

/// One configuration rendered and compared (no timing): the deterministic part of
/// a row.
pub struct Measured {
    /// Figure name.
    pub figure: String,
    /// The configuration.
    pub config: Config,
    /// The scene as rendered (for timing).
    pub scene: LoadedScene,
    /// Against the matching reference.
    pub cmp: crate::image::compare::Comparison,
    /// NMSE against the Gouraud reference.
    pub nmse_vs_gouraud: f64,
    /// NMSE against the per-pixel reference.
    pub nmse_vs_phong: f64,
    /// Covered pixels.
    pub covered: usize,
    /// Same bytes as the `gradient` + Gouraud render of the figure.
    pub same_as_gradient: bool,
}

/// The scene of configuration `c` on `base`.
fn scene_of(base: &LoadedScene, c: &Config) -> LoadedScene {
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
    ls
}

/// Renders every configuration of `figure` once and compares it with its
/// references (one reference per kind and shininess).
fn measure_figure(
    figure: &str,
    configs: &[Config],
    tick: &mut dyn FnMut(&str),
) -> Result<Vec<Measured>, String> {
    let base = load::load_arg(figure)?;
    let mut refs: HashMap<(&'static str, bool, u32), Image> = HashMap::new();
    let mut out: Vec<Measured> = Vec::with_capacity(configs.len());
    let mut bytes: Vec<Vec<u8>> = Vec::with_capacity(configs.len());
    for c in configs {
        tick(&format!("{figure} {} {}", c.kind.as_str(), c.name()));
        let ls = scene_of(&base, c);
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
        out.push(Measured {
            figure: figure.to_string(),
            config: *c,
            cmp: compare(&refs[&key], &r.image)?,
            nmse_vs_gouraud: compare(&refs[&gkey], &r.image)?.nmse,
            nmse_vs_phong: compare(&refs[&pkey], &r.image)?.nmse,
            covered: r.image.covered_count(),
            scene: ls,
            same_as_gradient: false,
        });
        bytes.push(r.bytes);
    }
    let grad = configs
        .iter()
        .position(|c| c.kind == Kind::Span && c.span == SpanName::GRADIENT);
    if let Some(g) = grad {
        for (i, m) in out.iter_mut().enumerate() {
            m.same_as_gradient = bytes[i] == bytes[g];
        }
    }
    Ok(out)
}

/// The configurations of `opts`, figure by figure.
pub fn plan(opts: &ReportOptions) -> Vec<(String, Vec<Config>)> {
    opts.figures
        .iter()
        .map(|f| (f.clone(), configurations(opts.quick, specular_rows(f))))
        .collect()
}

/// Renders and compares every configuration of `opts` (no timing); the figures
/// run on parallel threads, the result is in [`plan`] order whatever the threads.
pub fn measure(opts: &ReportOptions) -> Result<Vec<Measured>, String> {
    let plan = plan(opts);
    let results: Vec<Result<Vec<Measured>, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = plan
            .iter()
            .enumerate()
            .map(|(i, (fig, configs))| {
                let show = opts.progress && i == 0;
                let n = configs.len();
                s.spawn(move || {
                    let mut k = 0;
                    measure_figure(fig, configs, &mut |what| {
                        k += 1;
                        progress(show, k, n, what);
                    })
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("a render thread panicked".to_string()))
            })
            .collect()
    });
    if opts.progress {
        eprintln!();
    }
    let mut all = Vec::new();
    for r in results {
        all.extend(r?);
    }
    Ok(all)
}

/// Host frame times of `items`: interleaved rounds, each timing every
/// configuration once (the start rotates so no configuration always runs first);
/// per configuration the median and the interquartile spread.
fn time(opts: &ReportOptions, items: &[Measured]) -> Result<Vec<(Duration, f64)>, String> {
    let rounds = opts.rounds.max(1);
    let total = items.len() * rounds;
    let mut times: Vec<Vec<Duration>> = vec![Vec::with_capacity(rounds); items.len()];
    for round in 0..rounds {
        for j in 0..items.len() {
            let i = (j + round) % items.len();
            if j % 4 == 0 || j + 1 == items.len() {
                progress(
                    opts.progress,
                    round * items.len() + j + 1,
                    total,
                    &format!("timing round {}/{rounds}", round + 1),
                );
            }
            times[i].push(render::time_frame(&items[i].scene, opts.runs_per_round)?);
        }
    }
    if opts.progress {
        eprintln!();
    }
    Ok(times
        .iter_mut()
        .map(|t| {
            let frame = median(t);
            let q = |f: usize| t[(t.len() - 1) * f / 4].as_secs_f64();
            let spread = (q(3) - q(1)) / frame.as_secs_f64().max(1e-12);
            (frame, (spread * 1e4).round() / 1e4)
        })
        .collect())
}

/// The rows of `items` with their host times and MCU counts; ratios and Pareto
/// fronts filled in. A configuration the MCU table lacks is an error.
pub fn assemble(
    items: &[Measured],
    times: &[(Duration, f64)],
    counts: &mcu::McuTable,
) -> Result<Vec<Row>, String> {
    let mut rows = Vec::with_capacity(items.len());
    for (it, &(frame, spread)) in items.iter().zip(times) {
        let at = |b: usize| counts.lookup(mcu::BOARDS[b].0, &it.figure, &it.config);
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
            same_as_gradient: it.same_as_gradient,
            frame,
            ns_per_px: frame.as_nanos() as f64 / it.covered.max(1) as f64,
            spread,
            ratio: f64::NAN,
            mcu: [at(0)?, at(1)?],
            pareto: [false; 2],
        });
    }
    let mut figures: Vec<String> = rows.iter().map(|r| r.figure.clone()).collect();
    figures.dedup();
    for fig in &figures {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| &rows[i].figure == fig)
            .collect();
        let base = idx
            .iter()
            .find(|&&i| is_baseline(&rows[i].config))
            .map(|&i| rows[i].frame.as_secs_f64());
        for &i in &idx {
            if let Some(b) = base {
                rows[i].ratio = rows[i].frame.as_secs_f64() / b;
            }
        }
        for core in 0..mcu::BOARDS.len() {
            let points: Vec<(f64, f64)> = idx
                .iter()
                .map(|&i| (rows[i].mcu[core].per_pixel, rows[i].nmse_vs_phong))
                .collect();
            for (k, on) in pareto_front(&points).into_iter().enumerate() {
                rows[idx[k]].pareto[core] = on;
            }
        }
    }
    Ok(rows)
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

/// Runs the report and writes its files into `opts.out_dir`.
pub fn run_report(opts: &ReportOptions) -> Result<Report, String> {
    // Read the inputs first: a missing MCU row fails before the long timing run.
    let counts = mcu::McuTable::read(&opts.mcu_csv)?;
    let inputs = crate::tables::claims::Inputs::read(opts)?;
    let items = measure(opts)?;
    let placeholder = vec![(Duration::ZERO, 0.0); items.len()];
    assemble(&items, &placeholder, &counts)?;
    let times = time(opts, &items)?;
    let rows = assemble(&items, &times, &counts)?;
    let files = write(opts, &rows, &inputs)?;
    Ok(Report {
        table: text::text_table(&rows),
        summary: text::summary(&rows, &opts.figures, &inputs),
        rows,
        files,
    })
}

/// The documents of a report: markdown, CSV, and the charts (PNG bytes by file
/// name).
pub struct Documents {
    /// `accuracy-vs-time.md`.
    pub markdown: String,
    /// `accuracy-vs-time.csv`.
    pub csv: String,
    /// The per-core charts (deterministic) and the host chart (not).
    pub charts: Vec<(String, Vec<u8>)>,
}

/// Generates the documents of `rows` in memory.
pub fn documents(
    opts: &ReportOptions,
    rows: &[Row],
    inputs: &crate::tables::claims::Inputs,
) -> Result<Documents, String> {
    let mut charts = Vec::new();
    for core in 0..mcu::BOARDS.len() {
        charts.push((
            chart::core_file(core),
            chart::png_bytes(&chart::ChartSpec::core(core), rows, &opts.figures)?,
        ));
    }
    charts.push((
        format!("{STEM}.png"),
        chart::png_bytes(&chart::ChartSpec::host(), rows, &opts.figures)?,
    ));
    Ok(Documents {
        markdown: text::markdown(opts, rows, inputs),
        csv: text::to_csv(rows),
        charts,
    })
}

fn write(
    opts: &ReportOptions,
    rows: &[Row],
    inputs: &crate::tables::claims::Inputs,
) -> Result<Vec<PathBuf>, String> {
    let docs = documents(opts, rows, inputs)?;
    std::fs::create_dir_all(&opts.out_dir)
        .map_err(|e| format!("cannot create {}: {e}", opts.out_dir.display()))?;
    let mut files = Vec::new();
    let mut put = |name: &str, bytes: &[u8]| {
        let p = opts.out_dir.join(name);
        std::fs::write(&p, bytes).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
        files.push(p);
        Ok::<(), String>(())
    };
    put(&format!("{STEM}.md"), docs.markdown.as_bytes())?;
    put(&format!("{STEM}.csv"), docs.csv.as_bytes())?;
    for (name, bytes) in &docs.charts {
        put(name, bytes)?;
    }
    Ok(files)
}
