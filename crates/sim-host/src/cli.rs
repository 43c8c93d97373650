//! The `fixshade` command line: the only module that parses arguments (with
//! `clap`), turning them into a call of [`crate::commands`].
//!
//! Exit status: 0 success, 1 failure (unreadable file, bad scene, render error), 2
//! bad usage. Every error is one line.

use std::path::PathBuf;

use clap::error::ErrorKind;
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

pub use crate::commands::CliError;
use crate::commands::{self, bake, demo, list, scene, scene::SceneOptions, tables, usage};

/// The help layout of every command: what it does, its usage, its options.
const TEMPLATE: &str = "{about-with-newline}\nUSAGE:\n    {usage}\n\n{all-args}{after-help}";

/// fixshade — integer-only triangle rasterizer for MCU displays, host simulator.
///
/// Without a command: render the demo figures (sphere, teapot, robot) into out/ and
/// print a table against the f64 reference.
#[derive(Parser, Debug)]
#[command(
    name = "fixshade",
    help_template = TEMPLATE,
    after_help = "\
Examples:
    fixshade render teapot -o out/teapot-classic.png --span classic
    fixshade reference teapot -o out/teapot-ref.png
    fixshade compare out/teapot-ref.png out/teapot-classic.png
    fixshade list

`fixshade COMMAND --help` prints the options of a command. Exit status: 0 success,
1 failure (unreadable file, bad scene, render error), 2 bad usage."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Cmd>,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Render with the fixed-point core (OUT defaults to out/SCENE.png); prints the
    /// draw statistics. The effects (depth test, culling, lighting, shading, ...) are
    /// derived from the scene; --effects forces some on or off.
    Render(RenderArgs),
    /// The exact f64 reference render.
    Reference(ReferenceArgs),
    /// NMSE, verdict, largest channel error and coverage mismatch of TEST against REF.
    Compare(CompareArgs),
    /// Accuracy against time for every span method and shading mode: a table, and
    /// DIR/accuracy-vs-time.{md,csv,png}.
    Report(MeasureArgs),
    /// The specular models against c^n, in renders and in time:
    /// DIR/specular.{md,csv}, DIR/specular-reflectance.png.
    Specular(MeasureArgs),
    /// The effects table: --explain, NMSE and time for the scenes in
    /// crates/sim-host/scenes/effects/ (FILE: docs/effects.md, or
    /// out/effects-quick.md with --quick).
    Effects(DocArgs),
    /// Pixel-segment ray casting: evaluations, NMSE and time for L in 1..16 and
    /// several K.
    RaycastTable(RaycastTableArgs),
    /// An OBJ, scene file or built-in scene as static arrays in the core's
    /// fixed-point formats (for flash).
    Bake(BakeArgs),
    /// Built-in scenes, span methods, shading modes, specular models, dividers and
    /// pixel formats, with a line on each.
    List,
}

#[derive(Args, Debug)]
struct RenderArgs {
    #[command(flatten)]
    scene: SceneOptions,
    /// Output PNG.
    #[arg(short, long, value_name = "OUT.png")]
    output: Option<PathBuf>,
    /// Render in strips of ROWS rows (the bytes are those of the whole frame).
    #[arg(long, value_name = "ROWS", value_parser = clap::value_parser!(u32).range(1..))]
    strip: Option<u32>,
    /// Print each effect, the rule that chose it and its measured share of the
    /// frame time.
    #[arg(long)]
    explain: bool,
}

#[derive(Args, Debug)]
struct ReferenceArgs {
    #[command(flatten)]
    scene: SceneOptions,
    /// Output PNG.
    #[arg(short, long, value_name = "OUT.png")]
    output: PathBuf,
    /// Per-pixel (Phong) lighting.
    #[arg(long)]
    phong: bool,
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// The reference and the image to test.
    #[arg(value_name = "REF.png TEST.png")]
    images: Vec<PathBuf>,
    /// One JSON object {"nmse", "verdict", "max_channel_error", "coverage_mismatch"}.
    #[arg(long)]
    json: bool,
}

#[derive(Args, Debug)]
struct DocArgs {
    /// A smaller, faster run (CI).
    #[arg(long)]
    quick: bool,
    /// Where to write (a directory for report and specular, a file for effects).
    #[arg(long, value_name = "DIR|FILE")]
    out: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct MeasureArgs {
    /// A smaller, faster run (CI).
    #[arg(long)]
    quick: bool,
    /// The directory to write into.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// The firmware's instruction counts (report: docs/mcu-instructions.csv,
    /// specular: docs/mcu-specular.csv). A configuration missing from it is an error.
    #[arg(long, value_name = "FILE")]
    mcu_csv: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct RaycastTableArgs {
    /// The markdown file.
    #[arg(long, value_name = "FILE", default_value = "docs/raycast.md")]
    out: PathBuf,
    /// Frames per measurement (the median is kept).
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..))]
    runs: u64,
}

#[derive(Args, Debug)]
struct BakeArgs {
    /// An OBJ file, a scene file or a built-in scene.
    #[arg(value_name = "INPUT")]
    input: String,
    /// The Rust file to write.
    #[arg(short, long, value_name = "OUT.rs")]
    output: PathBuf,
    /// Split each mesh into runs of triangles using at most N vertices.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(3..))]
    chunk: Option<u64>,
}

/// A checked command line: what [`run`] will do, parsed without opening any file.
#[derive(Debug)]
pub struct Command(Parsed);

#[derive(Debug)]
enum Parsed {
    /// `--help`, `help`: the text to print.
    Help(String),
    Run(Option<Cmd>),
}

/// The clap command, every subcommand with [`TEMPLATE`].
fn command() -> clap::Command {
    Cli::command()
        .mut_subcommands(|c| c.help_template(TEMPLATE))
        .disable_version_flag(true)
}

/// One line of a clap error: its message, and its hint if it has one (a similar
/// option, a value to quote), without the usage lines clap adds.
fn one_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let mut out = String::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if line.is_empty() {
            continue;
        }
        if !out.is_empty() {
            out.push_str(if line.starts_with("tip:") { "; " } else { " " });
        }
        out.push_str(line.strip_prefix("error: ").unwrap_or(line));
    }
    out
}

/// Parses `args` (without the program name): the command, its options and their
/// values. Files are not touched.
pub fn parse(args: &[String]) -> Result<Command, CliError> {
    let argv = std::iter::once("fixshade").chain(args.iter().map(String::as_str));
    let matches = match command().try_get_matches_from(argv) {
        Ok(m) => m,
        Err(e) => {
            return match e.kind() {
                ErrorKind::DisplayHelp
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
                | ErrorKind::DisplayVersion => Ok(Command(Parsed::Help(
                    e.render().to_string().trim_end().to_string(),
                ))),
                _ => Err(usage(one_line(&e))),
            }
        }
    };
    let cli = Cli::from_arg_matches(&matches).map_err(|e| usage(one_line(&e)))?;
    if let Some(Cmd::Compare(c)) = &cli.command {
        if c.images.len() != 2 {
            return Err(usage("compare takes two PNG files: REF.png TEST.png"));
        }
    }
    Ok(Command(Parsed::Run(cli.command)))
}

/// Runs the CLI with `args` (without the program name); returns what to print.
pub fn run(args: &[String]) -> Result<String, CliError> {
    let cmd = match parse(args)?.0 {
        Parsed::Help(text) => return Ok(text),
        Parsed::Run(None) => return demo::run_demo().map_err(commands::fail),
        Parsed::Run(Some(cmd)) => cmd,
    };
    match cmd {
        Cmd::Render(a) => scene::render(&a.scene, a.output.as_deref(), a.strip, a.explain),
        Cmd::Reference(a) => scene::reference(&a.scene, &a.output, a.phong),
        Cmd::Compare(a) => scene::compare_files(&a.images[0], &a.images[1], a.json),
        Cmd::Report(a) => tables::report(a.quick, a.out, a.mcu_csv),
        Cmd::Specular(a) => tables::specular(a.quick, a.out, a.mcu_csv),
        Cmd::Effects(a) => tables::effects(a.quick, a.out.as_deref()),
        Cmd::RaycastTable(a) => tables::raycast_table(&a.out, a.runs as usize),
        Cmd::Bake(a) => bake::run(&a.input, &a.output, a.chunk.map(|n| n as usize)),
        Cmd::List => Ok(list::list()),
    }
}

/// The `fixshade` program: runs [`run`] on the process's arguments, prints the
/// result or the error, and exits with its status.
pub fn main() -> ! {
    use std::io::Write;
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        // A closed pipe (`fixshade list | head -1`) is not an error worth a panic.
        Ok(out) => {
            let _ = writeln!(std::io::stdout(), "{out}");
            std::process::exit(0)
        }
        Err(e) => {
            eprintln!("fixshade: {}", e.message);
            std::process::exit(e.code)
        }
    }
}
