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
pub mod model;
pub mod recommend;
pub mod text;

use std::collections::HashMap;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use crate::image::compare::compare;
use crate::image::Image;
use crate::render;
use crate::scene::desc::{ShadingName, SpanName};
use crate::scene::load::{self, LoadedScene};

pub use model::*;

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
