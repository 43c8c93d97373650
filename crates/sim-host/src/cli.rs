//! The `fixshade` command line.

use std::path::PathBuf;

use crate::compare::compare;
use crate::desc::{DivideName, FormatName, Named, ShadingName, SpanName, SpecularName};
use crate::image::Image;
use crate::pipeline::{self, LoadedScene};

/// Usage text.
pub const USAGE: &str = "\
fixshade — integer-only triangle rasterizer for MCU displays, host simulator

USAGE:
    fixshade                      render the demo figures (sphere, teapot, robot)
                                  into out/ and print a table against the f64 reference
    fixshade render SCENE [-o OUT.png] [--span METHOD] [--shading MODE] [--format FMT]
                                  [--specular MODEL] [--divide DIV] [--strip ROWS] [--segment L]
                                  [--threshold K] [--perspective on|off] [--perspective-span N]
                                  [--effects LIST] [--explain]
                                  render with the fixed-point core (OUT defaults to
                                  out/SCENE.png); prints the draw statistics. The
                                  effects (depth test, culling, lighting, shading, ...)
                                  are derived from the scene; --effects forces some on
                                  or off (e.g. -depth,+specular; names: depth, cull,
                                  specular, lighting, local-viewer, perspective);
                                  --perspective on corrects Gouraud colours and
                                  Phong normals and positions (adaptive: both) for
                                  perspective, one division per N pixels (1..64,
                                  default 16);
                                  --explain prints each effect, the rule that chose it
                                  and its measured share of the frame time
    fixshade effects [--out FILE] [--quick]
                                  the effects table: --explain, NMSE and time for the
                                  scenes in crates/sim-host/scenes/effects/ (FILE:
                                  docs/effects.md, or out/effects-quick.md with --quick)
    fixshade reference SCENE -o OUT.png [--phong] [--perspective on|off]
    fixshade compare REF.png TEST.png [--json]
    fixshade report [--quick] [--out DIR]
                                  accuracy against time for every span method and
                                  shading mode: a table, and DIR/accuracy-vs-time.{md,csv,png}
                                  (DIR: docs/, or out/report-quick/ with --quick)
    fixshade bake INPUT -o OUT.rs [--chunk N]
                                  an OBJ, scene file or built-in scene as static arrays
                                  in the core's fixed-point formats (for flash)
    fixshade raycast-table [--out FILE] [--runs N]
                                  pixel-segment ray casting: evaluations, NMSE and
                                  time for L in 1..16 and several K (FILE: docs/raycast.md)
    fixshade specular [--quick] [--out DIR]
                                  the specular models against c^n, in renders and in
                                  time: DIR/specular.{md,csv}, DIR/specular-reflectance.png
                                  (DIR: docs/, or out/specular-quick/ with --quick)
    fixshade list                 built-in scenes, span methods, shading modes (with adaptive),
                                  specular models, dividers, formats
    fixshade help                 this text

SCENE is a scene file (TOML, see docs/scene-files.md) or a built-in scene: sphere,
teapot, robot, bench-sphere, spheres-plane. Options override the scene file; `fixshade list` names
every METHOD, MODE, MODEL, DIV and FMT with a line on each. `fixshade COMMAND --help`
prints this text. Exit status: 0 success, 1 failure (unreadable file, bad scene,
render error), 2 bad usage.";

/// A failure with its exit code: 2 for bad usage, 1 otherwise.
#[derive(Debug)]
pub struct CliError {
    /// Exit code.
    pub code: i32,
    /// One sentence for the user.
    pub message: String,
}

pub(crate) fn usage(msg: impl Into<String>) -> CliError {
    CliError {
        code: 2,
        message: msg.into(),
    }
}

pub(crate) fn fail(msg: impl Into<String>) -> CliError {
    CliError {
        code: 1,
        message: msg.into(),
    }
}

/// Parsed options of one subcommand.
#[derive(Default)]
pub(crate) struct Opts {
    positional: Vec<String>,
    output: Option<PathBuf>,
    span: Option<SpanName>,
    shading: Option<ShadingName>,
    specular: Option<SpecularName>,
    divide: Option<DivideName>,
    format: Option<FormatName>,
    strip: Option<u32>,
    pub(crate) segment: Option<u32>,
    pub(crate) threshold: Option<f64>,
    phong: bool,
    json: bool,
    effects: Option<String>,
    explain: bool,
    perspective: Option<bool>,
    perspective_span: Option<u32>,
}

fn parse_opts(args: &[String], allowed: &[&str]) -> Result<Opts, CliError> {
    let mut o = Opts::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| usage(format!("option {name} needs a value")))
        };
        if a.starts_with('-') && !allowed.contains(&a.as_str()) {
            return Err(usage(format!(
                "unknown option `{a}` here; this command takes: {}",
                if allowed.is_empty() {
                    "no options".to_string()
                } else {
                    allowed.join(", ")
                }
            )));
        }
        match a.as_str() {
            "-o" | "--output" => o.output = Some(PathBuf::from(value(a)?)),
            "--span" => o.span = Some(SpanName::parse(&value(a)?).map_err(usage)?),
            "--shading" => o.shading = Some(ShadingName::parse(&value(a)?).map_err(usage)?),
            "--format" => o.format = Some(FormatName::parse(&value(a)?).map_err(usage)?),
            "--specular" => o.specular = Some(SpecularName::parse(&value(a)?).map_err(usage)?),
            "--divide" => o.divide = Some(DivideName::parse(&value(a)?).map_err(usage)?),
            "--strip" => {
                let v = value(a)?;
                let n: u32 =
                    v.parse().ok().filter(|n| *n >= 1).ok_or_else(|| {
                        usage(format!("--strip takes a row count >= 1, found `{v}`"))
                    })?;
                o.strip = Some(n);
            }
            "--perspective" => {
                let v = value(a)?;
                o.perspective = Some(match v.as_str() {
                    "on" => true,
                    "off" => false,
                    _ => return Err(usage(format!("--perspective takes on or off, found `{v}`"))),
                });
            }
            "--perspective-span" => {
                let v = value(a)?;
                let n = v
                    .parse::<u32>()
                    .ok()
                    .filter(|n| n.is_power_of_two() && *n <= 64)
                    .ok_or_else(|| {
                        usage(format!(
                            "--perspective-span takes 1, 2, 4, 8, 16, 32 or 64 pixels, found `{v}`"
                        ))
                    })?;
                o.perspective_span = Some(n);
            }
            "--segment" | "--threshold" => crate::raycast::cli_option(&mut o, a, &value(a)?)?,
            "--phong" => o.phong = true,
            "--effects" => {
                let v = value(a)?;
                crate::effects::Overrides::parse(&v, crate::effects::Source::CommandLine)
                    .map_err(usage)?;
                o.effects = Some(v);
            }
            "--explain" => o.explain = true,
            "--json" => o.json = true,
            _ => o.positional.push(a.clone()),
        }
    }
    Ok(o)
}

fn load_with(o: &Opts) -> Result<LoadedScene, CliError> {
    let arg = o.positional.first().ok_or_else(|| {
        usage("missing SCENE (a scene file or one of: sphere, teapot, robot, bench-sphere)")
    })?;
    if o.positional.len() > 1 {
        return Err(usage(format!("unexpected argument `{}`", o.positional[1])));
    }
    let (mut d, dir) = pipeline::read_scene(arg).map_err(fail)?;
    if let Some(s) = o.span {
        d.span = s;
    }
    if let Some(s) = o.shading {
        d.shading = s;
    }
    if let Some(f) = o.format {
        d.format = f;
    }
    if let Some(s) = o.specular {
        d.specular = s;
    }
    if let Some(v) = o.divide {
        d.divide = v;
    }
    if let Some(v) = o.perspective {
        d.perspective_correct = v;
    }
    if let Some(v) = o.perspective_span {
        d.perspective_span = v;
    }
    if let Some(list) = &o.effects {
        // Checked by `parse_opts`.
        let forced = crate::effects::Overrides::parse(list, crate::effects::Source::CommandLine)
            .map_err(usage)?;
        d.effects.extend(&forced);
    }
    d.raycast.segment = o.segment.unwrap_or(d.raycast.segment);
    d.raycast.threshold = o.threshold.unwrap_or(d.raycast.threshold);
    d.raycast.sampled |= o.segment.is_some() || o.threshold.is_some();
    pipeline::load(arg, &d, &dir).map_err(fail)
}

fn output(o: &Opts) -> Result<&PathBuf, CliError> {
    o.output.as_ref().ok_or_else(|| usage("missing -o OUT.png"))
}

/// `-o OUT`, or `out/<scene name>.png` (the file stem of a scene file).
fn output_or_default(o: &Opts) -> PathBuf {
    o.output.clone().unwrap_or_else(|| {
        let scene = o.positional.first().map(String::as_str).unwrap_or("scene");
        let stem = std::path::Path::new(scene)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene");
        PathBuf::from("out").join(format!("{stem}.png"))
    })
}

fn write(img: &Image, path: &std::path::Path) -> Result<(), CliError> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| fail(format!("cannot create {}: {e}", dir.display())))?;
    }
    img.write_png(path).map_err(fail)
}

/// A checked command line: what [`run`] will do, parsed without opening any file.
pub struct Command(Cmd);

enum Cmd {
    Demo,
    Help,
    List,
    Render(Opts),
    Reference(Opts),
    Compare(Opts),
    Report(crate::report::ReportOptions),
    /// `bake` and `raycast-table` parse their own arguments.
    Bake(Vec<String>),
    RaycastTable(Vec<String>),
    Specular(Vec<String>),
    Effects(Vec<String>),
}

/// Parses `args` (without the program name): the command, its options and their
/// values, and the number of positional arguments. Files are not touched.
pub fn parse(args: &[String]) -> Result<Command, CliError> {
    let Some(cmd) = args.first() else {
        return Ok(Command(Cmd::Demo));
    };
    let rest = &args[1..];
    if rest.iter().any(|a| a == "--help" || a == "-h") {
        return Ok(Command(Cmd::Help));
    }
    let scene_opts = |allowed: &[&str], needs_output: bool| -> Result<Opts, CliError> {
        let o = parse_opts(rest, allowed)?;
        if needs_output {
            output(&o)?;
        }
        if o.positional.is_empty() {
            return Err(usage(
                "missing SCENE (a scene file or one of: sphere, teapot, robot, bench-sphere)",
            ));
        }
        if o.positional.len() > 1 {
            return Err(usage(format!("unexpected argument `{}`", o.positional[1])));
        }
        Ok(o)
    };
    Ok(Command(match cmd.as_str() {
        "help" | "--help" | "-h" => Cmd::Help,
        "list" => Cmd::List,
        "bake" => Cmd::Bake(rest.to_vec()),
        "raycast-table" => Cmd::RaycastTable(rest.to_vec()),
        "specular" => Cmd::Specular(rest.to_vec()),
        "effects" => Cmd::Effects(rest.to_vec()),
        "render" => Cmd::Render(scene_opts(
            &[
                "-o",
                "--output",
                "--span",
                "--shading",
                "--format",
                "--specular",
                "--divide",
                "--strip",
                "--segment",
                "--threshold",
                "--perspective",
                "--perspective-span",
                "--effects",
                "--explain",
            ],
            false,
        )?),
        "reference" => Cmd::Reference(scene_opts(
            &[
                "-o",
                "--output",
                "--phong",
                "--format",
                "--shading",
                "--perspective",
            ],
            true,
        )?),
        "compare" => {
            let o = parse_opts(rest, &["--json"])?;
            if o.positional.len() != 2 {
                return Err(usage("compare takes two PNG files: REF.png TEST.png"));
            }
            Cmd::Compare(o)
        }
        "report" => {
            let mut opts = crate::report::ReportOptions::full();
            let mut out = None;
            let mut it = rest.iter();
            while let Some(a) = it.next() {
                match a.as_str() {
                    "--quick" => opts = crate::report::ReportOptions::quick(),
                    "--out" => {
                        out = Some(PathBuf::from(
                            it.next()
                                .ok_or_else(|| usage("option --out needs a value"))?,
                        ))
                    }
                    other => {
                        return Err(usage(format!(
                            "unexpected `{other}` here; report takes: --quick, --out DIR"
                        )))
                    }
                }
            }
            if let Some(dir) = out {
                opts.out_dir = dir;
            }
            Cmd::Report(opts)
        }
        other => {
            return Err(usage(format!(
                "unknown command `{other}`; try `fixshade help`"
            )))
        }
    }))
}

/// Runs the CLI with `args` (without the program name); returns what to print.
pub fn run(args: &[String]) -> Result<String, CliError> {
    match parse(args)?.0 {
        Cmd::Demo => crate::demo::run_demo().map_err(fail),
        Cmd::Help => Ok(USAGE.to_string()),
        Cmd::List => Ok(list()),
        Cmd::Bake(rest) => crate::bake::run(&rest),
        Cmd::RaycastTable(rest) => crate::raycast::table_command(&rest),
        Cmd::Specular(rest) => crate::specular_table::run_cli(&rest)
            .map_err(|(code, message)| CliError { code, message }),
        Cmd::Effects(rest) => crate::effects::run_cli(&rest),
        Cmd::Render(o) => {
            let scene = load_with(&o)?;
            let effects = crate::effects::derive(&scene).map_err(usage)?;
            let ls = crate::effects::apply(&scene, &effects);
            let out = &output_or_default(&o);
            let r = pipeline::render(&ls, o.strip).map_err(fail)?;
            write(&r.image, out)?;
            // Sampled Phong lights only some pixels: say how many.
            let evals = match r.stats.evaluations {
                0 => String::new(),
                e => format!(", {e} lighting evaluations"),
            };
            let mut text = format!(
                "{}: {} triangles ({} drawn, {} culled, {} clipped), {} covered pixels{evals} -> {}",
                ls.name,
                r.stats.triangles,
                r.stats.drawn,
                r.stats.culled,
                r.stats.clipped,
                r.image.covered_count(),
                out.display()
            );
            if ls.desc.shading == ShadingName::Adaptive {
                text.push_str(&format!(
                    "\nadaptive: {} of {} polygons lit per pixel",
                    r.stats.per_pixel,
                    r.stats.triangles - r.stats.culled
                ));
            }
            if o.explain {
                let costs = crate::effects::costs(&scene, &effects, 5, 3).map_err(fail)?;
                text.push('\n');
                text.push_str(&crate::effects::explain(&ls.name, &effects, Some(&costs)));
            }
            Ok(text)
        }
        Cmd::Reference(o) => {
            let out = output(&o)?;
            let ls = load_with(&o)?;
            let img = pipeline::reference(&ls, o.phong);
            write(&img, out)?;
            Ok(format!(
                "{}: reference{} with {} covered pixels -> {}",
                ls.name,
                if o.phong { " (Phong)" } else { "" },
                img.covered_count(),
                out.display()
            ))
        }
        Cmd::Compare(o) => {
            let [a, b] = o.positional.as_slice() else {
                return Err(usage("compare takes two PNG files: REF.png TEST.png"));
            };
            let ra = Image::read_png(a.as_ref()).map_err(fail)?;
            let rb = Image::read_png(b.as_ref()).map_err(fail)?;
            let c = compare(&ra, &rb).map_err(fail)?;
            Ok(if o.json { c.to_json() } else { c.to_text() })
        }
        Cmd::Report(opts) => {
            let r = crate::report::run_report(&opts).map_err(fail)?;
            let files: Vec<String> = r.files.iter().map(|p| p.display().to_string()).collect();
            Ok(format!(
                "{}\n\n{}\nwrote {}",
                r.table,
                r.summary,
                files.join(", ")
            ))
        }
    }
}

/// One line on what each selectable name does, for `fixshade list`.
fn describe(name: &str) -> &'static str {
    match name {
        "classic" => "per-span division of the end values (baseline)",
        "gradient" => "constant per-triangle increment (seed 000 §2.1)",
        "even-odd" => "two accumulators over even and odd pixels; same pixels as gradient",
        "kway2" | "kway3" | "kway4" => "K accumulators stepping K·ΔI; same pixels as gradient",
        "counter" => "two interpolators from both span ends; same pixels as gradient",
        "segment2" | "segment4" | "segment8" | "segment16" | "segment32" | "segment64" => {
            "P units filling segments of w pixels; same pixels as gradient"
        }
        "sierpinski" => "midpoint subdivision with vertices snapped to even pixels (approximate)",
        "sierpinski-exact" => "midpoint subdivision only where exact; same pixels as gradient",
        "flat" => "one colour per triangle (its last vertex's)",
        "gouraud" => "vertex colours interpolated",
        "quadratic" => "quadratic surface through vertex and edge-midpoint colours (seed 003)",
        "phong" => "normals interpolated, every pixel lit (with --segment/--threshold: lit at segment ends, interpolated inside)",
        "phong-even-odd" => "phong with two accumulators per normal component; same pixels",
        "adaptive" => {
            "phong where a highlight can reach a triangle (conservative bound), gouraud elsewhere"
        }
        "raycast" => "fixed-point ray casting sampled by pixel segments (--segment, --threshold)",
        "exact" => "c^n",
        "schlick" => "c / (n - n·c + c)",
        "schlick-mod" => "the seed's modified Schlick",
        "cos-quad" => "(σ(c - 1) + 1)², σ = (n + 1)/3",
        "cos-quad-energy" => "energy-conserving cosine-quadratic, (n + 6)/24.55 factor",
        "rgb565le" => "RGB 5-6-5, little-endian bytes",
        "rgb565be" => "RGB 5-6-5, big-endian bytes (ST7789/ILI9341 over SPI)",
        "rgb888" => "RGB 8-8-8",
        "gray8" => "8-bit grey",
        _ => "",
    }
}

/// One line on a divider (`exact` also names a specular model).
fn describe_divider(n: &str) -> &'static str {
    match n {
        "exact" => "full-precision integer division (the default)",
        "table" => "16 KiB reciprocal table of k = 1..4096, one multiply; exact on that range",
        _ if n.starts_with("shift-add-rounded-") => {
            "N shifts and adds, expansion of 1/k rounded at bit N (N = 4..16)"
        }
        _ => "N shifts and adds, truncated binary expansion of 1/k (N = 4..16)",
    }
}

fn list() -> String {
    let mut out = format!(
        "built-in scenes: {}\nbuilt-in meshes (scene files): sphere, teapot, robot, obj (with path)\n",
        crate::scene_file::BUILTIN_SCENES.join(", ")
    );
    let mut section = |title: &str, names: Vec<&'static str>| {
        out.push_str(&format!("\n{title}:\n"));
        for n in names {
            // `quadratic` names both a shading mode and a specular model.
            let d = match (title, n) {
                ("specular models (--specular)", "quadratic") => {
                    "a·c² + (1 - a)·c, a(n) from a table"
                }
                ("dividers (--divide)", n) => describe_divider(n),
                _ => describe(n),
            };
            out.push_str(&format!("  {n:18} {d}\n"));
        }
    };
    section(
        "span methods (--span)",
        SpanName::ALL.iter().map(|(_, n)| *n).collect(),
    );
    section(
        "shading modes (--shading)",
        ShadingName::ALL.iter().map(|(_, n)| *n).collect(),
    );
    section(
        "specular models (--specular)",
        SpecularName::ALL.iter().map(|(_, n)| *n).collect(),
    );
    section(
        "dividers (--divide)",
        DivideName::ALL.iter().map(|(_, n)| *n).collect(),
    );
    section(
        "pixel formats (--format)",
        FormatName::ALL.iter().map(|(_, n)| *n).collect(),
    );
    out.trim_end().to_string()
}
