//! The hard-case triangle catalogue on QEMU's mps2-an386 (Cortex-M4F): every case
//! with every span method in flat and Gouraud, without and with depth, drawn in one
//! strip per case (see `fixshade_boards_common::catalogue`); the rows go to the host
//! files `<case>.rgb` and `<case>.z` through semihosting. `cargo xtask qemu` builds it
//! (`--features catalogue --bin fixshade-mps2-catalogue`) and compares every byte with
//! the host.
#![no_std]
#![no_main]

use cortex_m_rt::{entry, exception};
use fixshade_boards_common::catalogue;

const BOARD: &str = "mps2-an386";
/// The core clock SysTick counts (QEMU's mps2 SYSCLK).
const CORE_HZ: u32 = 25_000_000;
/// QEMU's `-icount shift`.
const ICOUNT_SHIFT: u32 = 10;

/// Pixels of the strip: the largest drawn window of the catalogue (4096 × 32).
const PIXELS: usize = 4096 * 32;

static mut COLOR: [[u8; 3]; PIXELS] = [[0; 3]; PIXELS];
static mut DEPTH: [u16; PIXELS] = [0; PIXELS];

#[exception]
fn SysTick() {
    fixshade_boards_common::on_systick();
}

#[entry]
fn main() -> ! {
    // SAFETY: the only references to the buffers, taken once before any use.
    #[allow(unsafe_code)]
    let (color, depth) = unsafe {
        (
            &mut *core::ptr::addr_of_mut!(COLOR),
            &mut *core::ptr::addr_of_mut!(DEPTH),
        )
    };
    catalogue::firmware(BOARD, CORE_HZ, ICOUNT_SHIFT, color, depth)
}
