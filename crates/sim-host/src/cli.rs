//! The `fixshade` command line.

use std::path::PathBuf;

use crate::compare::compare;
use crate::desc::{FormatName, Named, ShadingName, SpanName, SpecularName};
use crate::image::Image;
use crate::pipeline::{self, LoadedScene};

/// Usage text.
pub const USAGE: &str = "\
fixshade — integer-only triangle rasterizer for MCU displays, host simulator

USAGE:
    fixshade                      render the demo figures (sphere, teapot, robot)
                                  into out/ and print a table against the f64 reference
    fixshade render SCENE -o OUT.png [--span METHOD] [--shading MODE] [--format FMT]
                                  [--specular MODEL] [--strip ROWS]
    fixshade reference SCENE -o OUT.png [--phong]
    fixshade compare REF.png TEST.png [--json]
    fixshade report [--quick] [--out DIR]
                                  accuracy against time for every span method and
                                  shading mode: a table, and DIR/accuracy-vs-time.{md,csv,png}
                                  (DIR: docs/, or out/report-quick/ with --quick)
    fixshade specular [--quick] [--out DIR]
                                  the specular models against c^n, in renders and in
                                  time: DIR/specular.{md,csv}, DIR/specular-reflectance.png
                                  (DIR: docs/, or out/specular-quick/ with --quick)
    fixshade list                 built-in scenes, span methods, shading modes,
                                  specular models, formats
    fixshade help                 this text

SCENE is a scene file (TOML) or a built-in scene: sphere, teapot, robot, bench-sphere.
Options override the scene file. Exit status: 0 success, 1 failure, 2 bad usage.";

/// A failure with its exit code: 2 for bad usage, 1 otherwise.
#[derive(Debug)]
pub struct CliError {
    /// Exit code.
    pub code: i32,
    /// One sentence for the user.
    pub message: String,
}

fn usage(msg: impl Into<String>) -> CliError {
    CliError {
        code: 2,
        message: msg.into(),
    }
}

fn fail(msg: impl Into<String>) -> CliError {
    CliError {
        code: 1,
        message: msg.into(),
    }
}

/// Parsed options of one subcommand.
#[derive(Default)]
struct Opts {
    positional: Vec<String>,
    output: Option<PathBuf>,
    span: Option<SpanName>,
    shading: Option<ShadingName>,
    specular: Option<SpecularName>,
    format: Option<FormatName>,
    strip: Option<u32>,
    phong: bool,
    json: bool,
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
            "--strip" => {
                let v = value(a)?;
                let n: u32 =
                    v.parse().ok().filter(|n| *n >= 1).ok_or_else(|| {
                        usage(format!("--strip takes a row count >= 1, found `{v}`"))
                    })?;
                o.strip = Some(n);
            }
            "--phong" => o.phong = true,
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
    pipeline::load(arg, &d, &dir).map_err(fail)
}

fn output(o: &Opts) -> Result<&PathBuf, CliError> {
    o.output.as_ref().ok_or_else(|| usage("missing -o OUT.png"))
}

fn write(img: &Image, path: &std::path::Path) -> Result<(), CliError> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| fail(format!("cannot create {}: {e}", dir.display())))?;
    }
    img.write_png(path).map_err(fail)
}

/// Runs the CLI with `args` (without the program name); returns what to print.
pub fn run(args: &[String]) -> Result<String, CliError> {
    let Some(cmd) = args.first() else {
        return crate::demo::run_demo().map_err(fail);
    };
    let rest = &args[1..];
    match cmd.as_str() {
        "help" | "--help" | "-h" => Ok(USAGE.to_string()),
        "list" => Ok(list()),
        "render" => {
            let o = parse_opts(
                rest,
                &[
                    "-o",
                    "--output",
                    "--span",
                    "--shading",
                    "--format",
                    "--specular",
                    "--strip",
                ],
            )?;
            let out = output(&o)?;
            let ls = load_with(&o)?;
            let r = pipeline::render(&ls, o.strip).map_err(fail)?;
            write(&r.image, out)?;
            Ok(format!(
                "{}: {} triangles ({} drawn, {} culled, {} clipped), {} covered pixels -> {}",
                ls.name,
                r.stats.triangles,
                r.stats.drawn,
                r.stats.culled,
                r.stats.clipped,
                r.image.covered_count(),
                out.display()
            ))
        }
        "reference" => {
            let o = parse_opts(
                rest,
                &["-o", "--output", "--phong", "--format", "--shading"],
            )?;
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
        "compare" => {
            let o = parse_opts(rest, &["--json"])?;
            let [a, b] = o.positional.as_slice() else {
                return Err(usage("compare takes two PNG files: REF.png TEST.png"));
            };
            let ra = Image::read_png(a.as_ref()).map_err(fail)?;
            let rb = Image::read_png(b.as_ref()).map_err(fail)?;
            let c = compare(&ra, &rb).map_err(fail)?;
            Ok(if o.json { c.to_json() } else { c.to_text() })
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
            let r = crate::report::run_report(&opts).map_err(fail)?;
            let files: Vec<String> = r.files.iter().map(|p| p.display().to_string()).collect();
            Ok(format!(
                "{}\n\n{}\nwrote {}",
                r.table,
                r.summary,
                files.join(", ")
            ))
        }
        "specular" => crate::specular_table::run_cli(rest)
            .map_err(|(code, message)| CliError { code, message }),
        other => Err(usage(format!(
            "unknown command `{other}`; try `fixshade help`"
        ))),
    }
}

fn list() -> String {
    let names = |all: &[&str]| all.join(", ");
    format!(
        "built-in scenes: {}\nspan methods: {}\nshading modes: {}\nspecular models: {}\npixel formats: {}",
        names(crate::scene_file::BUILTIN_SCENES),
        names(&SpanName::ALL.iter().map(|(_, n)| *n).collect::<Vec<_>>()),
        names(&ShadingName::ALL.iter().map(|(_, n)| *n).collect::<Vec<_>>()),
        names(&SpecularName::ALL.iter().map(|(_, n)| *n).collect::<Vec<_>>()),
        names(&FormatName::ALL.iter().map(|(_, n)| *n).collect::<Vec<_>>()),
    )
}
