//! The whole-pipeline hard cases (`tests/catalogue/scenes.toml`, baked into
//! `boards/baked/scenes/` by `cargo xtask bake`) on the MCU: what the scene
//! images of the boards share. Each image renders every case it holds with every
//! span method and shading mode it carries, writes each frame (Rgb565 little-endian
//! bytes) to the host file `<case>-<shading>-<span>.rgb565` through semihosting and
//! logs one `SCENE` line per frame; `cargo xtask qemu` compares every frame with the
//! host render of the same case, method, shading and strip/chunk layout.

use core::ffi::CStr;
use core::fmt::Write as _;

use fixshade::render::{RenderError, Stats};
use fixshade::scene::ShadingMode;

pub use crate::catalogue::Console;

/// The host's name of a shading mode (`fixshade render --shading NAME`).
pub fn shading_name(m: ShadingMode) -> &'static str {
    match m {
        ShadingMode::Flat => "flat",
        ShadingMode::Gouraud => "gouraud",
        ShadingMode::QuadraticSurface => "quadratic",
        ShadingMode::Phong => "phong",
        ShadingMode::PhongEvenOdd => "phong-even-odd",
        ShadingMode::Adaptive => "adaptive",
    }
}

/// True for the shading modes with their own fills, which ignore the span method
/// (`Frame::draw_with`): the images draw them once, with `gradient`.
pub fn ignores_span(m: ShadingMode) -> bool {
    !matches!(m, ShadingMode::Flat | ShadingMode::Gouraud)
}

/// `<case>-<shading>-<span>.rgb565` as a C string in `buf`.
pub fn file_name<'b>(buf: &'b mut [u8; 96], case: &str, shading: &str, span: &str) -> &'b CStr {
    let mut n = 0;
    for part in [
        case.as_bytes(),
        b"-",
        shading.as_bytes(),
        b"-",
        span.as_bytes(),
        b".rgb565",
    ] {
        let k = part.len().min(buf.len() - 1 - n);
        buf[n..n + k].copy_from_slice(&part[..k]);
        n += k;
    }
    buf[n] = 0;
    CStr::from_bytes_with_nul(&buf[..=n]).unwrap_or(c"frame.rgb565")
}

/// Rgb565 pixels as their bytes in memory order (`Rgb565Le` keeps little-endian
/// bytes in each `u16`, and the Cortex-M cores run little-endian).
pub fn as_bytes(p: &[u16]) -> &[u8] {
    // SAFETY: u16 has no padding and every byte pattern is a valid u8; the length in
    // bytes is twice the length in u16; alignment of u8 is 1.
    #[allow(unsafe_code)]
    unsafe {
        core::slice::from_raw_parts(p.as_ptr().cast::<u8>(), p.len() * 2)
    }
}

/// One frame of a scene image, as its `SCENE` line carries it.
#[derive(Copy, Clone, Debug, Default)]
pub struct SceneLog {
    /// Frame width and height.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// Rows per strip (0: one whole framebuffer).
    pub rows: u32,
    /// The chunks' vertex limit (0: whole meshes).
    pub chunk: u32,
    /// Instructions of the vertex stage, summed over its runs.
    pub prepare: u64,
    /// Instructions of the draws, summed.
    pub draw: u64,
    /// Draw statistics, summed.
    pub stats: Stats,
}

impl SceneLog {
    /// Adds one draw's statistics.
    pub fn add(&mut self, st: Result<Stats, RenderError>) -> Result<(), &'static str> {
        let st = st.map_err(|_| "draw failed")?;
        self.stats.triangles += st.triangles;
        self.stats.drawn += st.drawn;
        self.stats.pixels += st.pixels;
        Ok(())
    }

    /// Writes `SCENE board case shading span width height rows chunk triangles drawn
    /// pixels prepare draw`.
    pub fn write(&self, board: &str, case: &str, shading: &str, span: &str) {
        let _ = writeln!(
            Console,
            "SCENE {board} {case} {shading} {span} {} {} {} {} {} {} {} {} {}",
            self.width,
            self.height,
            self.rows,
            self.chunk,
            self.stats.triangles,
            self.stats.drawn,
            self.stats.pixels,
            self.prepare,
            self.draw
        );
    }
}

/// Logs `SCENESKIP board case why` (`why` one word).
pub fn skip(board: &str, case: &str, why: &str) {
    let _ = writeln!(Console, "SCENESKIP {board} {case} {why}");
}

/// Prints `DONE board` and exits QEMU with status 0, or prints the error and exits
/// with 1.
pub fn exit(board: &str, r: Result<(), &'static str>) -> ! {
    match r {
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

/// Word written over the free RAM between the statics and the stack by
/// [`paint_stack`]; the lowest word that no longer holds it shows how deep the stack
/// went.
const PAINT: u32 = 0x5AA5_C33C;

extern "C" {
    static mut __ebss: u32;
    static mut _stack_start: u32;
}

/// Fills the RAM from the end of the statics to 256 bytes below the current stack
/// pointer with [`PAINT`] (for a board whose stack is short of room; see
/// [`stack_check`]).
#[allow(unsafe_code)]
pub fn paint_stack() {
    let sp = cortex_m::register::msp::read() as usize - 256;
    // SAFETY: the words between the end of .bss and (SP − 256) belong to no static
    // and lie below every live stack frame.
    unsafe {
        let mut p = core::ptr::addr_of_mut!(__ebss);
        while (p as usize) < sp {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// Bytes of stack used at the deepest point since [`paint_stack`], logged as
/// `STACK board scenes used room` (room: the RAM above the statics); an error when the stack used every painted word
/// (it reached the statics below it).
pub fn stack_check(board: &str) -> Result<(), &'static str> {
    let (used, room) = stack_peak();
    let _ = writeln!(Console, "STACK {board} scenes {used} {room}");
    if used >= room {
        Err("stack overflow: the stack used all the RAM above the statics")
    } else {
        Ok(())
    }
}

/// Bytes of stack used at the deepest point since [`paint_stack`], and the RAM
/// above the statics (`used ≥ room`: the stack reached the statics).
#[allow(unsafe_code)]
pub fn stack_peak() -> (usize, usize) {
    // SAFETY: reads words between the end of .bss and the top of RAM; only the
    // symbols' addresses are taken.
    unsafe {
        let top = core::ptr::addr_of_mut!(_stack_start) as usize;
        let bottom = core::ptr::addr_of_mut!(__ebss);
        let mut p = bottom;
        while (p as usize) < top && p.read_volatile() == PAINT {
            p = p.add(1);
        }
        (top - p as usize, top - bottom as usize)
    }
}
