//! Two-sided lighting (`TwoSided<BlinnExact>`), no depth buffer, Gouraud shading: `specular` plus the back colours of the vertex stage and their choice per triangle only.
#![no_std]
#![no_main]

use fixshade::effects::*;
use fixshade::raster::span::{DepthTest, Gradient, NoDepth};
use fixshade::render::{Frame, XfVertex};
use fixshade::shade::{Gouraud, Phong};
use fixshade::specular::BlinnExact;
use fixshade::target::{Framebuffer, Rgb565Le};
use fixshade_effects_size::{scene, SIZE};

#[allow(dead_code)]
type Unused = (BlinnExact, NoSpecular, DepthTest, NoDepth, Gouraud, Phong);

/// Entry point: draws frames forever.
#[no_mangle]
pub extern "C" fn _start() -> ! {
    let mut color = [0u16; (SIZE * SIZE) as usize];
    #[allow(unused_mut)]
    let mut depth = [0xFFFFu16; (SIZE * SIZE) as usize];
    let mut spin = 0;
    loop {
        let s = scene(core::hint::black_box(spin));
        let mut cache = [XfVertex::default(); 8];
        depth.fill(0xFFFF);
        if let Ok(mut fb) = Framebuffer::<Rgb565Le>::new(&mut color, None, SIZE, SIZE) {
            if let Ok(frame) =
                Frame::<Rgb565Le>::prepare_with::<TwoSided<BlinnExact>>(&s, SIZE, SIZE, &mut cache)
            {
                let _ = core::hint::black_box(
                    frame.draw_with::<Gradient, NoDepth, Gouraud, _>(&mut fb),
                );
            }
        }
        core::hint::black_box(&color);
        spin += 1;
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
