//! The hard-case triangle catalogue on QEMU's mps2-an386 (Cortex-M4F): every case
//! with every span method in flat and Gouraud, without and with depth, drawn in one
//! strip per case (see `fixshade_boards_common::catalogue`); the rows go to the host
//! files `<case>.rgb` and `<case>.z` through semihosting. `cargo xtask qemu` builds it
//! (`--features catalogue --bin fixshade-mps2-catalogue`) and compares every byte with
//! the host.
#![no_std]
#![no_main]

use core::ffi::CStr;
use core::fmt::Write as _;

use cortex_m_rt::{entry, exception};
use fixshade_boards_common::catalogue::{self, Sink};
use fixshade_boards_common::Counter;
use semihosting::fs::File;
use semihosting::io::Write as _;

const BOARD: &str = "mps2-an386";
/// The core clock SysTick counts (QEMU's mps2 SYSCLK).
const CORE_HZ: u32 = 25_000_000;
/// QEMU's `-icount shift`.
const ICOUNT_SHIFT: u32 = 10;

/// Pixels of the strip: the largest drawn window of the catalogue (4096 × 32).
const PIXELS: usize = 4096 * 32;

static mut COLOR: [[u8; 3]; PIXELS] = [[0; 3]; PIXELS];
static mut DEPTH: [u16; PIXELS] = [0; PIXELS];

struct Console;

impl core::fmt::Write for Console {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        semihosting::print!("{s}");
        Ok(())
    }
}

#[exception]
fn SysTick() {
    fixshade_boards_common::on_systick();
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

fn run() -> Result<(), &'static str> {
    let cp = cortex_m::Peripherals::take().ok_or("peripherals taken twice")?;
    let mut counter = Counter::start(cp.SYST, CORE_HZ, ICOUNT_SHIFT);
    // SAFETY: the only references to the buffers, taken once before any use.
    #[allow(unsafe_code)]
    let (color, depth) = unsafe {
        (
            &mut *core::ptr::addr_of_mut!(COLOR),
            &mut *core::ptr::addr_of_mut!(DEPTH),
        )
    };
    catalogue::run(
        BOARD,
        color,
        depth,
        &mut counter,
        &mut Files(None),
        &mut Console,
    )
}

#[entry]
fn main() -> ! {
    match run() {
        Ok(()) => {
            let _ = writeln!(Console, "DONE {BOARD}");
            semihosting::process::exit(0)
        }
        Err(e) => {
            let _ = writeln!(Console, "ERROR {BOARD}: {e}");
            semihosting::process::exit(1)
        }
    }
}
