//! The hard-case triangle catalogue on QEMU's microbit (Cortex-M0, 16 KiB RAM):
//! every case with every span method in flat and Gouraud, without and with depth,
//! drawn in strips of as many rows as [`PIXELS`] pixels hold (see
//! `fixshade_boards_common::catalogue`); the rows go to the host files `<case>.rgb`
//! and `<case>.z` through semihosting. `cargo xtask qemu` builds it (`--features
//! catalogue --bin fixshade-microbit-catalogue`) and compares every byte with the
//! host.
#![no_std]
#![no_main]

use cortex_m_rt::{entry, exception};
use fixshade_boards_common::catalogue;

const BOARD: &str = "microbit";
/// The core clock SysTick counts (QEMU's nRF51 HCLK).
const CORE_HZ: u32 = 16_000_000;
/// QEMU's `-icount shift`.
const ICOUNT_SHIFT: u32 = 10;

/// Pixels of a strip (5 KiB with its depth): every case up to 1024 pixels wide is
/// drawn, in strips of `1024 / width` rows; the 4095- and 4096-wide cases need 20 KiB
/// for one row with its depth and are skipped.
const PIXELS: usize = 1024;

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
