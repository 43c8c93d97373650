//! The hard-case triangle catalogue (`tests/catalogue/triangles.toml`, baked into
//! `boards/baked/catalogue/triangles.rs`) drawn on the MCU: every case with every span
//! method in four modes (flat and Gouraud, each without and with the u16 depth test;
//! flat gives every vertex the provoking, last, colour as the renderer does), into an
//! Rgb888 strip so every interpolated channel bit reaches the host. The drawn rows
//! stream out in frame order (colour, and depth in the depth modes), whatever strip
//! height the board's RAM allows, so `cargo xtask qemu` compares them byte for byte
//! with the host drawing the case's rows at once.

use fixshade::raster::span::{DepthMode, DepthTest, NoDepth, SpanMethod};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::shade::{Flat, Gouraud, Shading};
use fixshade::target::{PixelFormat, Rgb888, Strip};

use core::ffi::CStr;
use core::fmt::Write as _;

use semihosting::fs::File;
use semihosting::io::Write as _;

use crate::SysTickCounter;

/// The baked catalogue.
#[rustfmt::skip]
#[path = "../../baked/catalogue/triangles.rs"]
pub mod baked;

/// Draws one triangle into a strip.
pub type TriFn = fn(&mut Strip<'_, Rgb888>, [ScreenVertex; 3]) -> u32;

fn tri<S: SpanMethod, Z: DepthMode, Sh: Shading>(
    t: &mut Strip<'_, Rgb888>,
    v: [ScreenVertex; 3],
) -> u32 {
    draw_triangle::<Rgb888, Strip<'_, Rgb888>, S, Z, Sh>(t, v)
}

/// The modes, in the order of [`methods`]' function arrays: (name, flat, depth).
pub const MODES: [(&str, bool, bool); 4] = [
    ("flat", true, false),
    ("flat-z", true, true),
    ("gouraud", false, false),
    ("gouraud-z", false, true),
];

macro_rules! methods {
    ([] $($S:ty),* $(,)?) => {
        [$((<$S as SpanMethod>::NAME, [
            tri::<$S, NoDepth, Flat> as TriFn,
            tri::<$S, DepthTest, Flat> as TriFn,
            tri::<$S, NoDepth, Gouraud> as TriFn,
            tri::<$S, DepthTest, Gouraud> as TriFn,
        ])),*]
    };
}

/// Every span method in the host's order (`fixshade list`, the core's registry),
/// with one function per mode of [`MODES`].
pub fn methods() -> [(&'static str, [TriFn; 4]); crate::CASES] {
    fixshade::for_each_span_method!(methods)
}

/// Where the drawn rows go: two streams per case, colour bytes and depth bytes
/// (little-endian u16), each in frame-row order.
pub trait Sink {
    /// Starts case `name` (closes the previous one).
    fn begin(&mut self, name: &str) -> Result<(), &'static str>;
    /// Appends colour bytes.
    fn color(&mut self, bytes: &[u8]) -> Result<(), &'static str>;
    /// Appends depth bytes.
    fn depth(&mut self, bytes: &[u8]) -> Result<(), &'static str>;
}

/// The background every strip is cleared to (a colour the cases' triangles do not
/// produce in their untouched pixels, so a stray write or a missing one shows).
pub const BACKGROUND: [u32; 3] = [7, 77, 177];

/// Draws every case whose rows fit: a strip holds `min(rows, color.len() / width,
/// depth.len() / width)` rows. Logs `TRIMETHODS` (the method order), then per case
/// `TRICASE board name width y0 rows strip_rows pixels instructions` (pixels the
/// rasterizer reported and instructions of the draws, over all methods and modes)
/// or `TRISKIP board name width` when not one row fits.
pub fn run(
    board: &str,
    color: &mut [[u8; 3]],
    depth: &mut [u16],
    counter: &mut SysTickCounter,
    sink: &mut impl Sink,
    log: &mut impl core::fmt::Write,
) -> Result<(), &'static str> {
    let table = methods();
    let _ = write!(log, "TRIMETHODS");
    for (name, _) in &table {
        let _ = write!(log, " {name}");
    }
    let _ = writeln!(log);
    let bg = Rgb888::pack(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]);
    for case in baked::CASES {
        let w = case.width as usize;
        let fit = (color.len().min(depth.len()) / w).min(case.rows as usize) as u32;
        if fit == 0 {
            let _ = writeln!(log, "TRISKIP {board} {} {}", case.name, case.width);
            continue;
        }
        sink.begin(case.name)?;
        let (mut pixels, mut instructions) = (0u64, 0u64);
        for (_, fns) in &table {
            for (f, (_, flat, with_depth)) in fns.iter().zip(MODES) {
                let end = case.y0 + case.rows;
                let mut y = case.y0;
                while y < end {
                    let n = fit.min(end - y);
                    let len = n as usize * w;
                    let mut s = Strip::new(
                        &mut color[..len],
                        if with_depth {
                            Some(&mut depth[..len])
                        } else {
                            None
                        },
                        case.width,
                        case.height,
                        y,
                        n,
                    )
                    .map_err(|_| "catalogue strip rejected")?;
                    s.clear(bg);
                    let (drawn, cost) = counter.measure(|| {
                        let mut drawn = 0u64;
                        for t in case.tris {
                            let t = if flat {
                                let pc = t[2].c;
                                t.map(|v| ScreenVertex { c: pc, ..v })
                            } else {
                                *t
                            };
                            drawn += f(&mut s, t) as u64;
                        }
                        drawn
                    });
                    pixels += drawn;
                    instructions += cost;
                    sink.color(s.color().as_flattened())?;
                    drop(s);
                    if with_depth {
                        let mut buf = [0u8; 256];
                        for chunk in depth[..len].chunks(buf.len() / 2) {
                            for (b, z) in buf.chunks_exact_mut(2).zip(chunk) {
                                b.copy_from_slice(&z.to_le_bytes());
                            }
                            sink.depth(&buf[..chunk.len() * 2])?;
                        }
                    }
                    y += n;
                }
            }
        }
        let _ = writeln!(
            log,
            "TRICASE {board} {} {} {} {} {fit} {pixels} {instructions}",
            case.name, case.width, case.y0, case.rows
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------
// The firmware around `run`, shared by the QEMU images: host files through
// semihosting, the console, and the exit status.

/// The semihosting console as a `fmt::Write`.
pub struct Console;

impl core::fmt::Write for Console {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        semihosting::print!("{s}");
        Ok(())
    }
}

/// `<name><ext>` as a C string in `buf`.
fn c_name<'b>(buf: &'b mut [u8; 96], name: &str, ext: &str) -> &'b CStr {
    let mut n = 0;
    for part in [name.as_bytes(), ext.as_bytes()] {
        let k = part.len().min(buf.len() - 1 - n);
        buf[n..n + k].copy_from_slice(&part[..k]);
        n += k;
    }
    buf[n] = 0;
    CStr::from_bytes_with_nul(&buf[..=n]).unwrap_or(c"case")
}

/// The two host files of the current case.
struct Files(Option<(File, File)>);

impl Sink for Files {
    fn begin(&mut self, name: &str) -> Result<(), &'static str> {
        self.0 = None;
        let mut b = [0u8; 96];
        let c = File::create(c_name(&mut b, name, ".rgb")).map_err(|_| "cannot create a file")?;
        let z = File::create(c_name(&mut b, name, ".z")).map_err(|_| "cannot create a file")?;
        self.0 = Some((c, z));
        Ok(())
    }
    fn color(&mut self, bytes: &[u8]) -> Result<(), &'static str> {
        let (c, _) = self.0.as_mut().ok_or("no case")?;
        c.write_all(bytes).map_err(|_| "cannot write")
    }
    fn depth(&mut self, bytes: &[u8]) -> Result<(), &'static str> {
        let (_, z) = self.0.as_mut().ok_or("no case")?;
        z.write_all(bytes).map_err(|_| "cannot write")
    }
}

/// Runs the catalogue on `board` (SysTick at `core_hz`, QEMU's `-icount shift`
/// `icount_shift`) into the strip buffers `color` and `depth`, writes every case to
/// the host and exits QEMU with status 0, or 1 after printing the error.
pub fn firmware(
    board: &str,
    core_hz: u32,
    icount_shift: u32,
    color: &mut [[u8; 3]],
    depth: &mut [u16],
) -> ! {
    let result = cortex_m::Peripherals::take()
        .ok_or("peripherals taken twice")
        .and_then(|cp| {
            let mut counter = SysTickCounter::start(cp.SYST, core_hz, icount_shift);
            run(
                board,
                color,
                depth,
                &mut counter,
                &mut Files(None),
                &mut Console,
            )
        });
    match result {
        Ok(()) => {
            let _ = writeln!(Console, "DONE {board}");
            semihosting::process::exit(0)
        }
        Err(e) => {
            let _ = writeln!(Console, "ERROR {board}: {e}");
            semihosting::process::exit(1)
        }
    }
}
