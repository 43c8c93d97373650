//! `cargo xtask qemu`: builds the QEMU firmware images in `boards/`, runs them under
//! `qemu-system-arm -icount shift=10`, compares every frame they write byte for byte
//! with the host render of the same scene and span method, and writes the
//! instruction table (docs/mcu-instructions.md and .csv).
//!
//! It first builds the real-board crates (`boards/rp-pico-st7789`,
//! `boards/stm32f429i-disco`), which need a
//! board to run, and prints their flash and RAM sizes.
//!
//! QEMU comes from the system (`apt-get install qemu-system-arm`, done here when
//! running as root). Without it the task fails under `CI=true` and is skipped, loudly,
//! elsewhere.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use fixshade_sim::render;
use fixshade_sim::render::render_chunked;
use fixshade_sim::scene::load;
use fixshade_sim::scene::load::LoadedScene;

mod dividers;
mod helpers;
mod perspective;
mod report;

/// One firmware image: the board crate, cargo features, the QEMU machine.
struct Image {
    /// Directory under `boards/`.
    krate: &'static str,
    /// Cargo features selecting what the image renders.
    features: &'static str,
    /// Target triple (the crate's `.cargo/config.toml` names it too).
    target: &'static str,
    /// Binary name.
    bin: &'static str,
    /// QEMU `-machine` and `-cpu`.
    machine: &'static str,
    cpu: &'static str,
    /// What the image renders.
    kind: Kind,
}

/// What an image renders and how its output is checked.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// The built-in figures (`FRAME` lines).
    Figures,
    /// The hard-case triangle catalogue (its binary alone is built; checked by
    /// `crate::catalogue`).
    Catalogue,
    /// Ray-cast scenes (`RAY` lines; its binary alone is built).
    Ray,
    /// The whole-pipeline hard cases (`SCENE` lines; its binary alone is built;
    /// checked by `crate::scenes`).
    Scenes,
}

/// An image for QEMU's mps2-an386 (Cortex-M4), `boards/qemu-mps2-an386`.
const fn m4(features: &'static str, bin: &'static str, kind: Kind) -> Image {
    Image {
        krate: "qemu-mps2-an386",
        features,
        target: "thumbv7em-none-eabihf",
        bin,
        machine: "mps2-an386",
        cpu: "cortex-m4",
        kind,
    }
}

/// An image for QEMU's microbit (Cortex-M0), `boards/qemu-microbit`.
const fn m0(features: &'static str, bin: &'static str, kind: Kind) -> Image {
    Image {
        krate: "qemu-microbit",
        features,
        target: "thumbv6m-none-eabi",
        bin,
        machine: "microbit",
        cpu: "cortex-m0",
        kind,
    }
}

/// The mps2 image built for ARMv6-M, on QEMU's mps2-an385 (a Cortex-M3 machine
/// with 4 MiB of RAM, which runs ARMv6-M code unchanged): the full-frame ARMv6-M
/// image, named `mps2-an385-v6m` in its logs.
const fn v6m(features: &'static str, bin: &'static str, kind: Kind) -> Image {
    Image {
        krate: "qemu-mps2-an386",
        features,
        target: "thumbv6m-none-eabi",
        bin,
        machine: "mps2-an385",
        cpu: "cortex-m3",
        kind,
    }
}

const IMAGES: &[Image] = &[
    m4("", "fixshade-qemu-mps2-an386", Kind::Figures),
    v6m("", "fixshade-qemu-mps2-an386", Kind::Figures),
    // The bench sphere in 16-row bands with 64 KiB of RAM (`RAM` line checked).
    v6m("ram64k", "fixshade-mps2-ram64k", Kind::Figures),
    m4("catalogue", "fixshade-mps2-catalogue", Kind::Catalogue),
    m4("ray", "fixshade-mps2-ray", Kind::Ray),
    m4("scenes", "fixshade-mps2-scenes", Kind::Scenes),
    m0("sphere", "fixshade-qemu-microbit", Kind::Figures),
    m0("teapot", "fixshade-qemu-microbit", Kind::Figures),
    m0("robot", "fixshade-qemu-microbit", Kind::Figures),
    m0("bench-sphere", "fixshade-qemu-microbit", Kind::Figures),
    m0("catalogue", "fixshade-microbit-catalogue", Kind::Catalogue),
    // The scene cases: one shading mode and half of the meshes per image (flash).
    m0("scenes", "fixshade-microbit-scenes", Kind::Scenes),
    m0(
        "scenes,scenes-flat",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0("scenes,scenes-b", "fixshade-microbit-scenes", Kind::Scenes),
    m0(
        "scenes,scenes-flat,scenes-b",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    // The guard-band sphere alone (its 149 KB mesh), a third of the span methods each.
    m0(
        "scenes,scenes-guard",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0(
        "scenes,scenes-flat,scenes-guard",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0(
        "scenes,scenes-guard-b",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0(
        "scenes,scenes-flat,scenes-guard-b",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0(
        "scenes,scenes-guard-c",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
    m0(
        "scenes,scenes-flat,scenes-guard-c",
        "fixshade-microbit-scenes",
        Kind::Scenes,
    ),
];

/// Firmware for real boards: built (not run) by `cargo xtask qemu`, sizes printed.
/// (crate under boards/, target, binary).
const REAL_BOARDS: &[(&str, &str, &str)] = &[
    (
        "rp-pico-st7789",
        "thumbv6m-none-eabi",
        "fixshade-rp-pico-st7789",
    ),
    (
        "stm32f429i-disco",
        "thumbv7em-none-eabihf",
        "fixshade-stm32f429i-disco",
    ),
];

/// Builds the real-board crates; returns (label, flash, static RAM) per image.
fn build_real_boards(root: &Path) -> Result<Vec<(String, u64, u64)>, String> {
    let mut sizes = Vec::new();
    for (krate, target, bin) in REAL_BOARDS {
        let dir = root.join("boards").join(krate);
        cargo_build(&dir, None, "", None)?;
        let elf = dir.join("target").join(target).join("release").join(bin);
        let (flash, ram) = elf_sizes(&elf)?;
        eprintln!("xtask: {krate}: flash {flash} B, static RAM {ram} B (built, not run)");
        sizes.push((format!("{krate} (built, not run)"), flash, ram));
    }
    Ok(sizes)
}

/// The longest a firmware run may take in wall time before it counts as hung.
const RUN_LIMIT: Duration = Duration::from_secs(300);

/// One `FRAME` line.
#[derive(Clone, Debug)]
struct FrameRow {
    board: String,
    figure: String,
    case: String,
    width: u32,
    height: u32,
    triangles: u64,
    drawn: u64,
    pixels: u64,
    prepare: u64,
    draw: u64,
    /// `full`, `bands-N` (bands of N rows from one binning) or `strips-N`.
    layout: String,
    /// Instructions inside compiler runtime helpers (`helpers` module).
    helpers: Option<u64>,
}

impl FrameRow {
    fn parse(line: &str) -> Option<FrameRow> {
        let f: Vec<&str> = line.split_whitespace().collect();
        if !(f.len() == 11 || f.len() == 12) || f[0] != "FRAME" {
            return None;
        }
        let n = |i: usize| f[i].parse::<u64>().ok();
        Some(FrameRow {
            board: f[1].into(),
            figure: f[2].into(),
            case: f[3].into(),
            width: n(4)? as u32,
            height: n(5)? as u32,
            triangles: n(6)?,
            drawn: n(7)?,
            pixels: n(8)?,
            prepare: n(9)?,
            draw: n(10)?,
            layout: f.get(11).unwrap_or(&"full").to_string(),
            helpers: None,
        })
    }

    /// The frame file the image wrote: `figure-case.rgb565`, or for a banded frame
    /// `figure-case.bands-N.rgb565`.
    fn file(&self) -> String {
        if self.layout.starts_with("bands-") {
            format!("{}-{}.{}.rgb565", self.figure, self.case, self.layout)
        } else {
            format!("{}-{}.rgb565", self.figure, self.case)
        }
    }

    /// The method column: the case, with the layout when it is banded.
    fn method(&self) -> String {
        if self.layout.starts_with("bands-") {
            format!("{} ({})", self.case, self.layout)
        } else {
            self.case.clone()
        }
    }

    fn total(&self) -> u64 {
        self.prepare + self.draw
    }
}

/// Flash and RAM of an ELF image, from its loadable segments: file bytes go to
/// flash, memory bytes of segments placed at or above 0x2000_0000 are RAM (static
/// data; the stack takes the rest of RAM).
fn elf_sizes(path: &Path) -> Result<(u64, u64), String> {
    let b = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = || format!("{}: not a 32-bit little-endian ELF", path.display());
    if b.len() < 52 || &b[..4] != b"\x7fELF" || b[4] != 1 || b[5] != 1 {
        return Err(bad());
    }
    let u32_at = |o: usize| -> Result<u64, String> {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]) as u64)
            .ok_or_else(bad)
    };
    let u16_at = |o: usize| -> Result<u64, String> {
        b.get(o..o + 2)
            .map(|s| u16::from_le_bytes([s[0], s[1]]) as u64)
            .ok_or_else(bad)
    };
    let phoff = u32_at(28)? as usize;
    let phentsize = u16_at(42)? as usize;
    let phnum = u16_at(44)? as usize;
    let (mut flash, mut ram) = (0, 0);
    for i in 0..phnum {
        let o = phoff + i * phentsize;
        if u32_at(o)? != 1 {
            continue; // not PT_LOAD
        }
        let (vaddr, filesz, memsz) = (u32_at(o + 8)?, u32_at(o + 16)?, u32_at(o + 20)?);
        flash += filesz;
        if vaddr >= 0x2000_0000 {
            ram += memsz;
        }
    }
    Ok((flash, ram))
}

fn have_qemu() -> bool {
    Command::new("qemu-system-arm")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// Installs qemu-system-arm with apt when running as root.
fn ensure_qemu() -> bool {
    if have_qemu() {
        return true;
    }
    if is_root() {
        eprintln!("xtask: qemu-system-arm not found; installing it with apt-get");
        let ok = Command::new("apt-get")
            .arg("update")
            .status()
            .is_ok_and(|s| s.success())
            && Command::new("apt-get")
                .args(["install", "-y", "qemu-system-arm"])
                .env("DEBIAN_FRONTEND", "noninteractive")
                .status()
                .is_ok_and(|s| s.success());
        if !ok {
            eprintln!("xtask: apt-get could not install qemu-system-arm");
        }
    }
    have_qemu()
}

fn cargo_build(
    dir: &Path,
    target: Option<&str>,
    features: &str,
    bin: Option<&str>,
) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(dir).args(["build", "--release"]);
    if let Some(t) = target {
        cmd.args(["--target", t]);
    }
    if !features.is_empty() {
        cmd.args(["--no-default-features", "--features", features]);
    }
    if let Some(b) = bin {
        cmd.args(["--bin", b]);
    }
    // The board crates have their own target and lock file: nothing of the outer
    // cargo invocation's environment may leak into them.
    for (k, _) in std::env::vars() {
        if k.starts_with("CARGO_") && k != "CARGO_HOME" {
            cmd.env_remove(k);
        }
    }
    // The images hold file paths (panic locations): one name for the checkout and
    // one for cargo's home, so that an image's size and layout do not depend on
    // where it was cloned (the micro:bit scene images fill their 256 KiB to within
    // a few hundred bytes; a longer path overflowed one).
    let home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")));
    let mut flags = format!("--remap-path-prefix={}=/fixshade", root().display());
    if let Some(h) = home {
        flags.push_str(&format!("\x1f--remap-path-prefix={}=/cargo", h.display()));
    }
    cmd.env_remove("RUSTFLAGS")
        .env("CARGO_ENCODED_RUSTFLAGS", flags);
    eprintln!(
        "xtask: cargo build --release {} (in {})",
        if features.is_empty() {
            String::new()
        } else {
            format!("--no-default-features --features {features}")
        },
        dir.display()
    );
    let st = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if st.success() {
        Ok(())
    } else {
        Err(format!("building {} failed ({st})", dir.display()))
    }
}

/// The table row of a `RAM board limit statics stack parts…` line, checked: the
/// statics must be what the ELF places in RAM (`elf_ram`) and statics plus stack
/// must fit the limit.
fn ram_budget(rest: &str, elf_ram: u64) -> Result<String, String> {
    let f: Vec<&str> = rest.splitn(5, ' ').collect();
    let [board, limit, statics, stack, parts] = f.as_slice() else {
        return Err(format!("bad line: RAM {rest}"));
    };
    let n = |v: &str| {
        v.parse::<u64>()
            .map_err(|_| format!("bad line: RAM {rest}"))
    };
    let (limit, statics, stack) = (n(limit)?, n(statics)?, n(stack)?);
    if statics != elf_ram {
        return Err(format!(
            "{board}: the image counts {statics} B of statics, its ELF places {elf_ram} B in RAM"
        ));
    }
    if statics + stack > limit {
        return Err(format!(
            "{board}: statics {statics} B and stack {stack} B exceed the {limit} B of RAM"
        ));
    }
    Ok(format!(
        "| {board} | {limit} | {statics} | {stack} | {} | {parts} |",
        statics + stack
    ))
}

/// Runs an image in `out_dir`; returns its console output.
fn run_qemu(img: &Image, elf: &Path, out_dir: &Path) -> Result<String, String> {
    std::fs::create_dir_all(out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    // The console goes to files, read once QEMU has exited: a pipe nobody drains
    // while it runs would fill (64 KiB) and QEMU would drop the rest of the log.
    let (out_file, err_file) = (
        out_dir.join("qemu-stdout.txt"),
        out_dir.join("qemu-stderr.txt"),
    );
    let create = |p: &Path| std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()));
    let mut child = Command::new("qemu-system-arm")
        .current_dir(out_dir)
        .args(["-cpu", img.cpu, "-machine", img.machine, "-nographic"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-icount", "shift=10", "-kernel"])
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(create(&out_file)?)
        .stderr(create(&err_file)?)
        .spawn()
        .map_err(|e| format!("cannot start qemu-system-arm: {e}"))?;
    let start = Instant::now();
    loop {
        if let Some(st) = child.try_wait().map_err(|e| e.to_string())? {
            let read = |p: &Path| {
                std::fs::read(p)
                    .map(|b| String::from_utf8_lossy(&b).into_owned())
                    .map_err(|e| format!("{}: {e}", p.display()))
            };
            let text = read(&out_file)?;
            if !st.success() {
                return Err(format!(
                    "{} ({}) exited with {st}\n{}{}",
                    img.krate,
                    img.features,
                    text,
                    read(&err_file)?
                ));
            }
            return Ok(text);
        }
        if start.elapsed() > RUN_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "{} ({}) still running after {} s: killed",
                img.krate,
                img.features,
                RUN_LIMIT.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The host render of `figure` at `w`×`h` with span method `case` (`span@divider`
/// for the divider images): its bytes. With
/// `cut = Some((rows, chunk))` rendered strip by strip and chunk by chunk as the
/// small-RAM firmware does.
fn host_frame(
    scenes: &mut HashMap<String, LoadedScene>,
    figure: &str,
    case: &str,
    w: u32,
    h: u32,
    cut: Option<(u32, usize)>,
) -> Result<Vec<u8>, String> {
    if !scenes.contains_key(figure) {
        scenes.insert(
            figure.to_string(),
            load::load_arg(&perspective::source(figure))?,
        );
    }
    let mut ls = scenes[figure].clone();
    ls.desc.width = w;
    ls.desc.height = h;
    if !report::apply(&mut ls.desc, case)? && !perspective::apply(&mut ls.desc, case)? {
        dividers::apply(&mut ls.desc, case)?;
    }
    match cut {
        None => Ok(render::render(&ls, None)?.bytes),
        Some((rows, chunk)) => render_chunked(&ls, chunk, rows),
    }
}

pub(crate) fn first_difference(a: &[u8], b: &[u8]) -> String {
    match a.iter().zip(b).position(|(x, y)| x != y) {
        Some(i) => format!("first difference at byte {i}"),
        None if a.len() != b.len() => "lengths differ".into(),
        None => "identical".into(),
    }
}

/// Helper instructions and their share of the frame, e.g. `1204 (0.03 %)`.
fn helper_share(r: &FrameRow) -> String {
    match r.helpers {
        None => "—".into(),
        Some(h) if r.total() == 0 => h.to_string(),
        Some(h) => format!("{h} ({:.2} %)", 100.0 * h as f64 / r.total() as f64),
    }
}

/// `rows` grouped by board and figure, in the order each pair first appears.
fn by_board_figure<'r>(rows: &[&'r FrameRow]) -> Vec<Vec<&'r FrameRow>> {
    let mut groups: Vec<Vec<&FrameRow>> = Vec::new();
    for r in rows {
        match groups
            .iter_mut()
            .find(|g| g[0].board == r.board && g[0].figure == r.figure)
        {
            Some(g) => g.push(r),
            None => groups.push(vec![r]),
        }
    }
    groups
}

fn fmt_per(a: u64, b: u64) -> String {
    if b == 0 {
        "-".into()
    } else {
        format!("{:.2}", a as f64 / b as f64)
    }
}

/// The workspace root.
pub fn root() -> PathBuf {
    let m = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    m.parent().map(Path::to_path_buf).unwrap_or(m)
}

/// The task.
pub fn qemu() -> Result<(), String> {
    let ci = std::env::var("CI").is_ok_and(|v| v == "true");
    let root = root();
    crate::bake::run(&root)?;
    let status = Command::new("rustup")
        .args([
            "target",
            "add",
            "thumbv6m-none-eabi",
            "thumbv7em-none-eabihf",
        ])
        .status()
        .map_err(|e| format!("cannot run rustup: {e}"))?;
    if !status.success() {
        return Err("`rustup target add` failed".into());
    }
    let real = build_real_boards(&root)?;
    if !ensure_qemu() {
        let msg = "qemu-system-arm is not installed: the MCU frames were NOT checked \
                   (install it with `apt-get install qemu-system-arm`, as root)";
        if ci {
            return Err(msg.into());
        }
        eprintln!("\n!!!!!!!!\nxtask: SKIPPED `cargo xtask qemu`: {msg}\n!!!!!!!!\n");
        return Ok(());
    }
    let out_root = root.join("target").join("qemu");
    let mut rows: Vec<FrameRow> = Vec::new();
    let mut setup_lines = Vec::new();
    let mut specular_lines = Vec::new();
    let mut sizes = real;
    let mut calibration = Vec::new();
    let mut ram_lines = Vec::new();
    let mut scenes = HashMap::new();
    let (mut checked, mut mismatched) = (0, Vec::new());
    // Frames of the strip-and-chunk path that differ from the host's whole-frame
    // render (they match the host's strip-and-chunk render, or they are mismatches).
    let mut layout_differs = Vec::new();
    let (mut catalogue_frames, mut catalogue_rows, mut catalogue_skipped) =
        (0, Vec::new(), Vec::new());
    let (mut ray_frames, mut ray_rows) = (0, Vec::new());
    let mut scene_checked = crate::scenes::Checked::default();
    for img in IMAGES
        .iter()
        .chain(dividers::IMAGES)
        .chain(perspective::IMAGES)
        .chain(report::IMAGES)
    {
        let dir = root.join("boards").join(img.krate);
        cargo_build(&dir, Some(img.target), img.features, Some(img.bin))?;
        let elf = dir
            .join("target")
            .join(img.target)
            .join("release")
            .join(img.bin);
        let (flash, ram) = elf_sizes(&elf)?;
        // The mps2 crate builds for two cores: the ARMv6-M build is its own image.
        let krate = if img.machine == "mps2-an385" {
            format!("{} (ARMv6-M, mps2-an385)", img.krate)
        } else {
            img.krate.to_string()
        };
        let label = if img.features.is_empty() {
            krate
        } else {
            format!("{krate} ({})", img.features)
        };
        sizes.push((label.clone(), flash, ram));
        let out_dir = out_root.join(format!("{}-{}-{}", img.krate, img.machine, img.features));
        let _ = std::fs::remove_dir_all(&out_dir);
        let t = Instant::now();
        let log = run_qemu(img, &elf, &out_dir)?;
        eprintln!(
            "xtask: {label}: ran in {:.1} s; flash {flash} B, static RAM {ram} B",
            t.elapsed().as_secs_f64()
        );
        if !log.lines().any(|l| l.starts_with("DONE ")) {
            return Err(format!("{label}: no DONE line\n{log}"));
        }
        if img.kind == Kind::Ray {
            for line in log.lines() {
                let Some(rest) = line.strip_prefix("RAY ") else {
                    continue;
                };
                let f: Vec<&str> = rest.split_whitespace().collect();
                let [board, name, w, h, ..] = f.as_slice() else {
                    return Err(format!("bad line: {line}"));
                };
                let file = out_dir.join(format!("ray-{name}.rgb565"));
                let mcu = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
                let mut ls = load::load_arg(name)?;
                ls.desc.width = w.parse().map_err(|_| format!("bad line: {line}"))?;
                ls.desc.height = h.parse().map_err(|_| format!("bad line: {line}"))?;
                let host = fixshade_sim::render::raycast::render(&ls)?.bytes;
                checked += 1;
                ray_frames += 1;
                if mcu != host {
                    mismatched.push(format!(
                        "{board} ray {name}: {} bytes on the MCU, {} on the host, {}",
                        mcu.len(),
                        host.len(),
                        first_difference(&mcu, &host)
                    ));
                }
                ray_rows.push(rest.to_string());
            }
            continue;
        }
        if img.kind == Kind::Scenes {
            let c = crate::scenes::check(&log, &out_dir)?;
            eprintln!(
                "xtask: {label}: {} scene frames compared, {} cases skipped",
                c.frames,
                c.skipped.len()
            );
            checked += c.frames;
            scene_checked.frames += c.frames;
            scene_checked.bad.extend(c.bad);
            scene_checked.rows.extend(c.rows);
            scene_checked.skipped.extend(c.skipped);
            scene_checked.drawn.extend(c.drawn);
            scene_checked.seen.extend(c.seen);
            scene_checked.stack.extend(c.stack);
            scene_checked.layout_differs.extend(c.layout_differs);
            continue;
        }
        if img.kind == Kind::Catalogue {
            let crate::catalogue::Checked {
                frames: n,
                bad,
                rows,
                skipped,
            } = crate::catalogue::check(&log, &out_dir)?;
            eprintln!(
                "xtask: {label}: {n} catalogue frames compared, {} cases skipped",
                skipped.len()
            );
            checked += n;
            catalogue_frames += n;
            mismatched.extend(bad);
            catalogue_rows.extend(rows);
            catalogue_skipped.extend(skipped);
            continue;
        }
        // The full-frame span-method images: a second run with the execution log
        // gives each frame's instructions in compiler runtime helpers, in FRAME
        // order (the micro:bit's and the sweep images are left out: their logged
        // runs take minutes each).
        let helper_counts = if img.krate == "qemu-mps2-an386" && img.features.is_empty() {
            Some(helpers::per_frame(img.machine, img.cpu, &elf, &out_dir)?)
        } else {
            None
        };
        let first_row = rows.len();
        let mut layout: HashMap<String, (u32, usize)> = HashMap::new();
        for line in log.lines() {
            if line.starts_with("SETUP ") {
                setup_lines.push(line.to_string());
            } else if line.starts_with("SPECULAR ") {
                specular_lines.push(line.to_string());
            } else if line.starts_with("CALIBRATE ") || line.starts_with("STACK ") {
                calibration.push(line.to_string());
            } else if let Some(rest) = line.strip_prefix("RAM ") {
                ram_lines.push(ram_budget(rest, ram)?);
            } else if let Some(rest) = line.strip_prefix("LAYOUT ") {
                let f: Vec<&str> = rest.split_whitespace().collect();
                if let [_, fig, rows, chunk] = f.as_slice() {
                    let rows = rows.parse().map_err(|_| format!("bad line: {line}"))?;
                    let chunk = chunk.parse().map_err(|_| format!("bad line: {line}"))?;
                    layout.insert(fig.to_string(), (rows, chunk));
                }
            }
            let Some(r) = FrameRow::parse(line) else {
                continue;
            };
            let file = out_dir.join(r.file());
            let mcu = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            let whole = host_frame(&mut scenes, &r.figure, &r.case, r.width, r.height, None)?;
            let host = match layout.get(&r.figure) {
                Some(&(rows, chunk)) if chunk > 0 => {
                    let cut = host_frame(
                        &mut scenes,
                        &r.figure,
                        &r.case,
                        r.width,
                        r.height,
                        Some((rows, chunk)),
                    )?;
                    if cut != whole {
                        layout_differs.push(format!(
                            "{} {} {}: the host's own strip ({rows} rows) and chunk ({chunk} vertices) render differs from its whole-frame render ({})",
                            r.board,
                            r.figure,
                            r.case,
                            first_difference(&cut, &whole)
                        ));
                    }
                    cut
                }
                _ => whole,
            };
            checked += 1;
            if mcu != host {
                mismatched.push(format!(
                    "{} {} {}: {} bytes on the MCU, {} on the host, {}",
                    r.board,
                    r.figure,
                    r.case,
                    mcu.len(),
                    host.len(),
                    first_difference(&mcu, &host)
                ));
            }
            rows.push(r);
        }
        let image_rows = &mut rows[first_row..];
        if let Some(helper_counts) = helper_counts {
            if helper_counts.len() != image_rows.len() {
                return Err(format!(
                    "{label}: {} FRAME lines but {} frames in the execution log",
                    image_rows.len(),
                    helper_counts.len()
                ));
            }
            for (r, h) in image_rows.iter_mut().zip(helper_counts) {
                r.helpers = Some(h);
            }
        }
    }
    perspective::check(&rows)?;
    report::check(&rows, &specular_lines)?;
    let specular_csv = report::specular_csv(&specular_lines)?;
    let (mut md, csv) = tables(&rows, &setup_lines, &sizes, &calibration, &specular_csv);
    md.push_str(&catalogue_table(
        catalogue_frames,
        &catalogue_rows,
        &catalogue_skipped,
    ));
    md.push_str(&ray_table(ray_frames, &ray_rows));
    md.push_str(&crate::scenes::finish(&scene_checked)?);
    if !ram_lines.is_empty() {
        md.push_str(
            "\n## RAM of the low-RAM images\n\n\
             Each image's statics (`.data` and `.bss`, as linked) and peak stack (painted\n\
             RAM) against the RAM its linker script gives it, and what the statics hold\n\
             (bytes; the arena is the vertex cache until the frame is binned, then the\n\
             band's colour and depth):\n\n\
             | image | RAM | statics | stack | used | parts |\n| --- | ---: | ---: | ---: | ---: | --- |\n",
        );
        for l in &ram_lines {
            let _ = writeln!(md, "{l}");
        }
    }
    mismatched.extend(scene_checked.bad);
    if !layout_differs.is_empty() {
        md.push_str(
            "\n## Strip and chunk renders that differ from the whole frame\n\n\
             The Cortex-M0 frames are compared with the host rendering the same way (strips,\n\
             chunked meshes); these cases of that host render differ from the host's\n\
             whole-frame render (a property of the core, reproducible on the host alone):\n\n",
        );
        for l in &layout_differs {
            let _ = writeln!(md, "- {l}");
        }
    }
    println!("{md}");
    if !mismatched.is_empty() {
        return Err(format!(
            "{} of {checked} MCU frames differ from the host:\n{}",
            mismatched.len(),
            mismatched.join("\n")
        ));
    }
    let docs = root.join("docs");
    let compiler = rustc_version();
    let _ = write!(
        md,
        "\n{} Compiler: `{compiler}`.\n",
        fixshade_sim::tables::provenance::made_line("cargo xtask qemu")
    );
    if ci {
        stale_counts(
            &docs,
            &compiler,
            &[
                ("mcu-instructions.csv", &csv),
                ("mcu-specular.csv", &specular_csv),
            ],
        )?;
    }
    // Under CI the committed files stay: they passed the comparison above, and the
    // documents made from them (`docs_current`) are checked against them.
    if !ci {
        std::fs::write(docs.join("mcu-instructions.md"), &md).map_err(|e| e.to_string())?;
        std::fs::write(docs.join("mcu-instructions.csv"), &csv).map_err(|e| e.to_string())?;
        std::fs::write(docs.join("mcu-specular.csv"), &specular_csv).map_err(|e| e.to_string())?;
        eprintln!(
            "xtask: wrote docs/mcu-instructions.md, docs/mcu-instructions.csv and docs/mcu-specular.csv"
        );
    }
    if checked == 0 {
        return Err("no frames were checked".into());
    }
    for l in &layout_differs {
        eprintln!("xtask: WARNING: {l}");
    }
    println!("qemu: {checked} frames bit-identical to the host render of the same scene, method and strip/chunk layout");
    Ok(())
}

/// `rustc --version` (the counts hold for the compiler that built the images).
fn rustc_version() -> String {
    Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map_or("rustc (unknown version)".into(), |o| {
            String::from_utf8_lossy(&o.stdout).trim().to_string()
        })
}

/// Fails when a committed count file differs from what the images measured now,
/// if the committed docs/mcu-instructions.md names the same compiler (a different
/// compiler emits different code and counts: then only a note). The `helpers`
/// column is left out: it comes from a second run under QEMU's execution log,
/// whose attribution moves by a few instructions from run to run. Numbers may
/// differ by [`count_spread`]: an image built in another directory places its
/// code and data elsewhere, which moves SysTick's wraps against the spans (see
/// boards/common's `Counter`).
fn stale_counts(docs: &Path, compiler: &str, files: &[(&str, &str)]) -> Result<(), String> {
    let committed_md =
        std::fs::read_to_string(docs.join("mcu-instructions.md")).unwrap_or_default();
    let line = format!("Compiler: `{compiler}`.");
    if !committed_md.lines().any(|l| l.ends_with(&line)) {
        eprintln!(
            "xtask: NOTE: docs/mcu-instructions.md was made with another compiler than `{compiler}`: \
             the committed counts were not compared"
        );
        return Ok(());
    }
    for (name, now) in files {
        let before = std::fs::read_to_string(docs.join(name)).unwrap_or_default();
        let (before, now) = (without_helpers(&before), without_helpers(now));
        if before.len() != now.len() || before.iter().zip(&now).any(|(a, b)| !same_row(a, b)) {
            let at = before
                .iter()
                .zip(&now)
                .position(|(a, b)| !same_row(a, b))
                .map_or("its length".to_string(), |i| format!("line {}", i + 1));
            return Err(format!(
                "docs/{name} is stale: the firmware measures other counts (first difference at \
                 {at}); run `cargo xtask qemu` and commit docs/mcu-instructions.* and \
                 docs/mcu-specular.csv"
            ));
        }
    }
    Ok(())
}

/// How far a committed number may lie from the one measured now: 16 instructions,
/// and 16 more per SysTick wrap the span may hold (one per 655 360 instructions at
/// 25 MHz, per 1 024 000 at the micro:bit's 16 MHz; a wrap in a span costs it
/// about 8 instructions on mps2 and 20 on the micro:bit, see boards/common's
/// `Counter`).
fn count_spread(x: f64) -> f64 {
    16.0 + x.abs() / 40_000.0
}

/// Two CSV rows with the same text cells and numbers within [`count_spread`].
fn same_row(a: &str, b: &str) -> bool {
    let (a, b): (Vec<&str>, Vec<&str>) = (a.split(',').collect(), b.split(',').collect());
    a.len() == b.len()
        && a.iter().zip(&b).all(|(x, y)| {
            x == y
                || match (x.parse::<f64>(), y.parse::<f64>()) {
                    (Ok(x), Ok(y)) => (x - y).abs() <= count_spread(x.max(y)),
                    _ => false,
                }
        })
}

/// The lines of a CSV text with the cells of its `helpers` column emptied.
fn without_helpers(csv: &str) -> Vec<String> {
    let mut lines = csv.lines();
    let header = lines.next().unwrap_or("");
    let col = header.split(',').position(|h| h == "helpers");
    std::iter::once(header.to_string())
        .chain(lines.map(|l| {
            match col {
                Some(c) => l
                    .split(',')
                    .enumerate()
                    .map(|(i, v)| if i == c { "" } else { v })
                    .collect::<Vec<_>>()
                    .join(","),
                None => l.to_string(),
            }
        }))
        .collect()
}

/// The CSV's `method`, `divide`, `sweep`, `shading`, `specular` and `shininess` of
/// a case of any figure image (shininess 0: the scene's own).
fn csv_names(case: &str) -> [&str; 6] {
    if let Some(n) = report::csv_names(case) {
        return n;
    }
    let (method, divide, sweep) =
        perspective::csv_names(case).unwrap_or_else(|| dividers::csv_names(case));
    [method, divide, sweep, "gouraud", "exact", "0"]
}

/// The ray-caster section of the document.
fn ray_table(frames: usize, rows: &[String]) -> String {
    let mut md = format!(
        "\n## Ray caster\n\n\
         `fixshade render --shading raycast` of the built-in scenes at a small size, with their\n\
         own sampling (segment L, threshold K in Q8 8-bit levels; the exact Blinn specular),\n\
         baked by `cargo xtask bake`; {frames} frames, each identical to the host's bytes.\n\
         `prepare` is `Caster::prepare`, `sampling` the rows (`fill_row`, every ray cast in it).\n\n\
         | board | scene | width | height | L | K (Q8) | evaluations | prepare | sampling | per evaluation |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    for r in rows {
        let f: Vec<&str> = r.split_whitespace().collect();
        if let [_, _, _, _, _, _, e, _, s] = f.as_slice() {
            let per = fmt_per(s.parse().unwrap_or(0), e.parse().unwrap_or(0));
            let _ = writeln!(md, "| {} | {per} |", f.join(" | "));
        }
    }
    md
}

/// The catalogue section of the document.
fn catalogue_table(frames: usize, rows: &[String], skipped: &[String]) -> String {
    let mut md = format!(
        "\n## Hard-case triangle catalogue\n\n\
         Every case of tests/catalogue/triangles.toml (baked into\n\
         boards/baked/catalogue/triangles.rs) drawn with `draw_triangle` by every span method in\n\
         four modes (flat and Gouraud, each without and with the u16 depth test) into Rgb888\n\
         rows; colour and depth bytes compared with the host drawing the same case:\n\
         {frames} frames, all identical. The Cortex-M0 draws each case in strips of as many rows\n\
         as its RAM holds and is compared with the host drawing all rows at once.\n\
         `instructions` are those of the draws over all 60 method × mode frames of the case.\n\n\
         | board | case | width | first row | rows | rows per strip | pixels | instructions |\n\
         | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    for r in rows {
        let f: Vec<&str> = r.split_whitespace().collect();
        let _ = writeln!(md, "| {} |", f.join(" | "));
    }
    if !skipped.is_empty() {
        md.push_str(
            "\nNot drawn (one row with its depth row does not fit the board's strip buffers):\n\n",
        );
        for s in skipped {
            let f: Vec<&str> = s.split_whitespace().collect();
            if let [board, name, width] = f.as_slice() {
                let _ = writeln!(md, "- {board}: {name} ({width} pixels wide)");
            }
        }
    }
    md
}

fn tables(
    rows: &[FrameRow],
    setup: &[String],
    sizes: &[(String, u64, u64)],
    calibration: &[String],
    specular_csv: &str,
) -> (String, String) {
    let mut md = String::new();
    let mut csv = String::from(
        "board,figure,method,width,height,triangles,drawn,pixels,prepare,draw,total,per_pixel,per_triangle,draw_per_pixel,divide,sweep,layout,helpers,shading,specular,shininess\n",
    );
    md.push_str(
        "# Instructions on Cortex-M0 and Cortex-M4 (QEMU, `-icount shift=10`)\n\n\
         Written by `cargo xtask qemu`; every frame below was compared byte for byte with\n\
         the host render of the same scene and span method, and was identical (the\n\
         Cortex-M0 frames with the host rendering the same strips and mesh chunks).\n\
         Counts are instructions (SysTick under `-icount`, see boards/common), not cycles.\n\
         `prepare` is the vertex stage (`Frame::prepare`), `draw` the rasterizer\n\
         (`Frame::draw`); per pixel and per triangle divide the whole frame (prepare + draw)\n\
         by the covered pixels and by the submitted triangles, as the host benchmark does.\n\
         On the Cortex-M0 (micro:bit) the frame is drawn in strips and the mesh in\n\
         vertex-bounded chunks, so its `prepare` runs once per strip and chunk that is not\n\
         still in one of its chunk caches (see boards/qemu-microbit; the figure images make\n\
         one `FrameSetup` a frame, prepare chunks from it with `Frame::prepare_from` and draw\n\
         a chunk still in a cache again with `Frame::resume`); `mps2-an385-v6m` is the same ARMv6-M code drawing whole\n\
         frames. A method with `(bands-N)` drew the frame in bands of N rows from one\n\
         binning (`Frame::bin`), its `draw` the binning and every band. `helpers` is the\n\
         instructions inside compiler runtime helpers (`__aeabi_*`, `__*di3`, `memcpy`, …)\n\
         during prepare and draw, from QEMU's execution log, and their share of the frame\n\
         (measured on the full-frame images; `—` on the micro:bit's). Every micro:bit\n\
         image is built at opt-level \"z\" (boards/qemu-microbit/Cargo.toml: at \"s\" the\n\
         code of the 15 span methods with a figure's mesh overflows its 256 KiB of flash).\n\n",
    );
    let _ = writeln!(
        md,
        "## Firmware sizes\n\n| image | flash (B) | static RAM (B) |\n| --- | ---: | ---: |"
    );
    for (l, f, r) in sizes {
        let _ = writeln!(md, "| {l} | {f} | {r} |");
    }
    md.push('\n');
    if !setup.is_empty() {
        md.push_str("## Triangle setup\n\n| board | figure | triangles | instructions per triangle |\n| --- | --- | ---: | ---: |\n");
        for l in setup {
            let f: Vec<&str> = l.split_whitespace().collect();
            if let [_, board, fig, n, with, without] = f.as_slice() {
                let (n, with, without): (u64, u64, u64) = (
                    n.parse().unwrap_or(0),
                    with.parse().unwrap_or(0),
                    without.parse().unwrap_or(0),
                );
                let _ = writeln!(
                    md,
                    "| {board} | {fig} | {n} | {} |",
                    fmt_per(with.saturating_sub(without), n)
                );
            }
        }
        md.push('\n');
    }
    let mut key = None;
    for r in rows {
        let [method, divide, sweep, shading, specular, shininess] = csv_names(&r.case);
        let _ = writeln!(
            csv,
            "{},{},{method},{},{},{},{},{},{},{},{},{},{},{},{divide},{sweep},{},{},{shading},{specular},{shininess}",
            r.board,
            r.figure,
            r.width,
            r.height,
            r.triangles,
            r.drawn,
            r.pixels,
            r.prepare,
            r.draw,
            r.total(),
            fmt_per(r.total(), r.pixels),
            fmt_per(r.total(), r.triangles),
            fmt_per(r.draw, r.pixels),
            r.layout,
            r.helpers.map_or(String::new(), |h| h.to_string())
        );
        if sweep != "span" {
            continue; // in the dividers section
        }
        let k = (r.board.clone(), r.figure.clone(), r.width, r.height);
        if key.as_ref() != Some(&k) {
            let _ = writeln!(
                md,
                "\n## {} — {} at {}×{} ({} triangles)\n\n\
                 | method | drawn | pixels | prepare | draw | total | per pixel | per triangle | draw per pixel | helpers |\n\
                 | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
                r.board, r.figure, r.width, r.height, r.triangles
            );
            key = Some(k);
        }
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.method(),
            r.drawn,
            r.pixels,
            r.prepare,
            r.draw,
            r.total(),
            fmt_per(r.total(), r.pixels),
            fmt_per(r.total(), r.triangles),
            fmt_per(r.draw, r.pixels),
            helper_share(r)
        );
    }
    md.push_str(&dividers::section(rows));
    md.push_str(&perspective::section(rows));
    md.push_str(&report::section(rows, specular_csv));
    if !calibration.is_empty() {
        md.push_str("\n## Counter calibration\n\n`CALIBRATE board empty measured expected`: the counter around nothing, and around a loop of\nexactly `expected` instructions (holding nine or more SysTick wraps, each of which the count\nincludes with its exception handler). `STACK board bytes`: peak stack (painted RAM).\n\n```text\n");
        for l in calibration {
            md.push_str(l);
            md.push('\n');
        }
        md.push_str("```\n");
    }
    (md, csv)
}

#[cfg(test)]
mod tests {
    use super::same_row;

    #[test]
    fn committed_counts_match_within_the_counters_spread_only() {
        let row = "mps2-an386,sphere,gradient,320,240,852,6212,25228449,886.58";
        // One instruction off a short span, 200 off 25 million, a rounded ratio.
        assert!(same_row(
            row,
            "mps2-an386,sphere,gradient,320,240,852,6213,25228249,886.59"
        ));
        // 20 off a short span, 700 off 25 million, another name: not the same.
        assert!(!same_row(
            row,
            "mps2-an386,sphere,gradient,320,240,852,6232,25228449,886.58"
        ));
        assert!(!same_row(
            row,
            "mps2-an386,sphere,gradient,320,240,852,6212,25229149,886.58"
        ));
        assert!(!same_row(
            row,
            "mps2-an386,sphere,classic,320,240,852,6212,25228449,886.58"
        ));
        assert!(!same_row(row, "mps2-an386,sphere,gradient,320,240"));
    }
}
