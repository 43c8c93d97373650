//! The accuracy report's configurations beyond span methods, dividers and
//! perspective correction (`fixshade report`, docs/accuracy-vs-time.md): every
//! shading mode of the core with `gradient`, Phong with the dividers of the report's
//! Phong setup rows, and every specular model with Phong shading; and the
//! instructions of one specular evaluation (docs/specular.md).
//!
//! The lists come from the core's registry (`fixshade::for_each_shading!`,
//! `fixshade::for_each_specular!`); an image composes each frame's case name from
//! them as the host names the settings (`<shading>+<span>@<divider>`, with
//! `+<specular>+<n>` for the specular rows), see `xtask/src/qemu/report.rs`.

use core::hint::black_box;

use fixshade::divide::{Divide, ShiftAdd, Table};
use fixshade::fixed::Q16_16;
use fixshade::raster::span::{DepthTest, Gradient, WithDivide};
use fixshade::render::{Frame, RenderError, Stats, XfVertex};
use fixshade::scene::{Scene, ShadingMode};
use fixshade::shade::Phong;
use fixshade::specular::{BlinnExact, Specular};
use fixshade::target::{PixelFormat, Target};

use crate::{entry, DrawFn, Fixed, SysTickCounter};

/// Number of shading modes in [`shading_cases`].
pub const SHADINGS: usize = 6;

/// A case of [`shading_cases`]: the mode's name, the mode to set in the scene before
/// the vertex stage, and the draw.
pub type ShadingCase<P, T> = (&'static str, ShadingMode, DrawFn<P, T>);

macro_rules! shading_list {
    ([$P:ty, $T:ty] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
        [$((
            $name,
            $mode,
            entry::<Gradient, Fixed<DepthTest, $Sh>, $P, $T, BlinnExact> as DrawFn<$P, $T>,
        )),*]
    };
}

/// Every shading mode of the core with `gradient`, the exact divider and the depth
/// test: what `Frame::draw` draws for a depth-tested scene of that mode
/// (`fixshade render --shading NAME --span gradient`).
pub fn shading_cases<P: PixelFormat, T: Target<P>>() -> [ShadingCase<P, T>; SHADINGS] {
    fixshade::for_each_shading!(shading_list[P, T])
}

/// Number of dividers in [`phong_setup_cases`].
pub const PHONG_SETUPS: usize = 5;

/// Phong with `gradient` and divider `$D` in the setup, named `$name` (a name that is
/// not `D::NAME` does not compile).
macro_rules! phong_setup {
    ($P:ty, $T:ty; $($D:ty => $name:literal),* $(,)?) => {
        [$({
            const _: () = assert!(crate::same(<$D as Divide>::NAME, $name), "divider name");
            (
                $name,
                entry::<WithDivide<Gradient, $D>, Fixed<DepthTest, Phong>, $P, $T, BlinnExact>
                    as DrawFn<$P, $T>,
            )
        }),*]
    };
}

/// Phong shading with `gradient` and the dividers of the report's Phong setup rows
/// (`fixshade render --shading phong --divide NAME`); their `exact` is the `phong`
/// case of [`shading_cases`], drawn by the same image. The scene must be set to
/// Phong shading before the vertex stage.
pub fn phong_setup_cases<P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); PHONG_SETUPS] {
    phong_setup!(P, T;
        Table => "table",
        ShiftAdd<8> => "shift-add-8",
        ShiftAdd<4> => "shift-add-4",
        ShiftAdd<12> => "shift-add-12",
        ShiftAdd<16> => "shift-add-16",
    )
}

/// Number of specular models in [`specular_cases`] and [`eval_costs`].
pub const SPECULARS: usize = 6;

/// A whole frame lit with one specular model: the vertex stage of `scene` at
/// `width` × `height` into `cache`, then the Phong draw with `gradient` into the
/// target; the instructions of each (`prepare`, `draw`) and the draw's statistics.
pub type SpecularFn<T> = fn(
    &Scene<'_>,
    u32,
    u32,
    &mut [XfVertex],
    &mut T,
    &mut SysTickCounter,
) -> Result<(u64, u64, Stats), RenderError>;

fn specular_entry<Sp: Specular, P: PixelFormat, T: Target<P>>(
    scene: &Scene<'_>,
    width: u32,
    height: u32,
    cache: &mut [XfVertex],
    target: &mut T,
    counter: &mut SysTickCounter,
) -> Result<(u64, u64, Stats), RenderError> {
    let (frame, prepare) =
        counter.measure(|| Frame::<P, BlinnExact>::prepare_with::<Sp>(scene, width, height, cache));
    let frame = frame?;
    let (stats, draw) =
        counter.measure(|| frame.draw_with::<Gradient, DepthTest, Phong, T>(target));
    Ok((prepare, draw, stats?))
}

macro_rules! specular_list {
    ([$P:ty, $T:ty] $(($name:expr, $Sp:ty)),* $(,)?) => {
        [$(($name, specular_entry::<$Sp, $P, $T> as SpecularFn<$T>)),*]
    };
}

/// Every specular model of the core (`fixshade render --shading phong --specular
/// NAME`), by name. The scene must be set to Phong shading.
pub fn specular_cases<P: PixelFormat, T: Target<P>>() -> [(&'static str, SpecularFn<T>); SPECULARS]
{
    fixshade::for_each_specular!(specular_list[P, T])
}

/// The instructions of `inputs.len()` calls of one model's `eval` at exponent `n`
/// (`with`) and of the same loop without the call (`without`).
pub type EvalFn = fn(u32, &[i32], &mut SysTickCounter) -> (u64, u64);

fn eval_cost<Sp: Specular>(n: u32, inputs: &[i32], counter: &mut SysTickCounter) -> (u64, u64) {
    // As the host's `fixshade specular` times it: parameters and inputs behind
    // `black_box`, the results summed.
    let p = black_box(Sp::prepare(Q16_16::from_int(n as i32)));
    let (acc, with) = counter.measure(|| {
        let mut acc = 0u32;
        for &c in inputs {
            acc = acc.wrapping_add(Sp::eval(&p, black_box(c)) as u32);
        }
        acc
    });
    black_box(acc);
    let (acc, without) = counter.measure(|| {
        let mut acc = 0u32;
        for &c in inputs {
            acc = acc.wrapping_add(black_box(c) as u32);
        }
        acc
    });
    black_box(acc);
    (with, without)
}

macro_rules! eval_list {
    ([] $(($name:expr, $Sp:ty)),* $(,)?) => {
        [$(($name, eval_cost::<$Sp> as EvalFn)),*]
    };
}

/// Every specular model's evaluation cost, by name (see [`EvalFn`]).
pub fn eval_costs() -> [(&'static str, EvalFn); SPECULARS] {
    fixshade::for_each_specular!(eval_list)
}

/// The inputs of [`eval_costs`]: the host's sequence (`fixshade specular`), `c`
/// uniform in (0, 1] in Q2.30 from a fixed xorshift.
pub fn eval_inputs(out: &mut [i32]) {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    for c in out {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        // Below 2^30 + 1: fits i32.
        *c = 1 + (x % (1 << 30)) as i32;
    }
}
