//! fixshade on a Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz) driving a 240×240
//! ST7789 over SPI0 with `mipidsi`: Newell's teapot (the built-in scene, baked by
//! `fixshade bake teapot`) turning about y, drawn in strips of 16 rows
//! (7.5 KiB colour + 7.5 KiB depth) and sent strip by strip. Each frame's time is
//! logged over defmt-rtt.
//!
//! Wiring (Pico pin → display): GP18 → SCL/SCK, GP19 → SDA/MOSI, GP17 → CS,
//! GP16 → DC, GP20 → RES, 3V3 → VCC and BLK, GND → GND.
//!
//! Run: `cargo run --release` in this directory with a debug probe attached
//! (`probe-rs run --chip RP2040`).
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;

use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_hal_bus::spi::ExclusiveDevice;
use fixshade::fixed::Angle;
use fixshade::raster::span::Gradient;
use fixshade::render::{Frame, XfVertex};
use fixshade::target::{PixelFormat, Rgb565Le, Strip};
use hal::fugit::RateExtU32;
use hal::Clock;
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::ColorInversion;
use rp2040_hal as hal;

#[path = "../../baked/full/teapot.rs"]
mod teapot;

/// The second-stage bootloader for the Pico's W25Q080 flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

const XOSC_HZ: u32 = 12_000_000;
const W: u32 = 240;
const H: u32 = 240;
const ROWS: u32 = 16;
const STRIP: usize = (W * ROWS) as usize;

static mut CACHE: [XfVertex; teapot::MAX_CHUNK_VERTICES] = [XfVertex {
    s: fixshade::raster::ScreenVertex {
        x: 0,
        y: 0,
        z: 0,
        c: [0; 3],
    },
    flags: 0,
}; teapot::MAX_CHUNK_VERTICES];

#[hal::entry]
fn main() -> ! {
    let mut pac = hal::pac::Peripherals::take().unwrap();
    let mut watchdog = hal::Watchdog::new(pac.WATCHDOG);
    let clocks = hal::clocks::init_clocks_and_plls(
        XOSC_HZ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    )
    .ok()
    .unwrap();
    let sio = hal::Sio::new(pac.SIO);
    let pins = hal::gpio::Pins::new(
        pac.IO_BANK0,
        pac.PADS_BANK0,
        sio.gpio_bank0,
        &mut pac.RESETS,
    );
    let mut timer = hal::Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

    let sck = pins.gpio18.into_function::<hal::gpio::FunctionSpi>();
    let mosi = pins.gpio19.into_function::<hal::gpio::FunctionSpi>();
    let spi = hal::spi::Spi::<_, _, _, 8>::new(pac.SPI0, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        62_500_000u32.Hz(),
        embedded_hal::spi::MODE_3,
    );
    let cs = pins.gpio17.into_push_pull_output();
    let dc = pins.gpio16.into_push_pull_output();
    let rst = pins.gpio20.into_push_pull_output();
    let device = ExclusiveDevice::new_no_delay(spi, cs).unwrap();
    let mut buffer = [0u8; 512];
    let di = SpiInterface::new(device, dc, &mut buffer);
    let mut display = mipidsi::Builder::new(ST7789, di)
        .display_size(W as u16, H as u16)
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut timer)
        .unwrap();

    let mut scene = teapot::scene().unwrap();
    // SAFETY: the only reference to the cache, taken once.
    #[allow(unsafe_code)]
    let cache = unsafe { &mut *core::ptr::addr_of_mut!(CACHE) };
    let mut color = [0u16; STRIP];
    let mut depth = [0u16; STRIP];
    let bg = Rgb565Le::pack(
        teapot::BACKGROUND[0],
        teapot::BACKGROUND[1],
        teapot::BACKGROUND[2],
    );
    let step = Angle::from_degrees(3);
    loop {
        let t0 = timer.get_counter();
        let yaw = &mut scene.objects[0].placement.rotate[1];
        *yaw = yaw.wrapping_add(step);
        let frame = Frame::<Rgb565Le>::prepare(&scene, W, H, &mut cache[..]).unwrap();
        let t1 = timer.get_counter();
        let mut pixels = 0;
        for y0 in (0..H).step_by(ROWS as usize) {
            let mut strip =
                Strip::<Rgb565Le>::new(&mut color, Some(&mut depth), W, H, y0, ROWS).unwrap();
            strip.clear(bg);
            pixels += frame.draw::<Gradient, _>(&mut strip).unwrap().pixels;
            let px = strip
                .color()
                .iter()
                .map(|p| Rgb565::from(RawU16::new(u16::from_le(*p))));
            display
                .set_pixels(0, y0 as u16, W as u16 - 1, (y0 + ROWS - 1) as u16, px)
                .unwrap();
        }
        let t2 = timer.get_counter();
        defmt::info!(
            "frame: {=u64} us (vertex stage {=u64} us, strips incl. SPI {=u64} us), {=u32} px",
            (t2 - t0).to_micros(),
            (t1 - t0).to_micros(),
            (t2 - t1).to_micros(),
            pixels
        );
    }
}
