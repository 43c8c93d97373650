//! The one dispatch point: from the names of a scene description (shading, depth
//! test, span method, divider, perspective correction, sampling) to a function of the
//! core's types, chosen once per frame.
//!
//! The core is generic over every variant (`Frame::draw_with::<Span, Depth,
//! Shading, _>`), which a firmware names once and the compiler specialises. The host
//! offers every combination on the command line, so it compiles each function the
//! pixel loop needs once and picks among them by name at run time:
//!
//! - flat and Gouraud shading: one function per span method, depth mode and shading
//!   (the span method, the depth test and the interpolation are the pixel loop);
//! - quadratic, Phong and adaptive shading, whose fills ignore the span method: one
//!   per shading and depth mode, drawn with `gradient`'s setup (the span methods'
//!   `Divider`, the only part those fills take from them, is the same for all);
//! - perspective correction and sampled Phong: one each.
//!
//! Those draw into strips with 16-bit depth cells. Scenes with `depth_bits = 32`
//! take the same set again for strips with 32-bit cells, depth-tested draws only (a
//! draw without the depth test never reads the cells, so it takes the 16-bit set).
//!
//! The divider, the specular model, the specular term and two-sided lighting are
//! not parameters here: every frame is lit with [`HostSpecular`] and divides with
//! [`HostDivide`], which take them from the run-time selection (see
//! [`super::host`]), so each pixel format has one set of draws.
//! The functions are fn pointers into the table of the frame's pixel format, built
//! from the core's registry ([`fixshade::for_each_span_method!`],
//! [`fixshade::for_each_shading!`]), so a new span method needs no line here.

use fixshade::raster::perspective::Perspective;
use fixshade::raster::phong::Sampling;
use fixshade::raster::span::{DepthMode, DepthTest, Gradient, NoDepth, SpanMethod, WithDivide};
use fixshade::render::{Frame, RenderError, Stats};
use fixshade::sampler::Threshold;
use fixshade::shade::{Flat, Gouraud, Shading};
use fixshade::target::{DepthFormat, PixelFormat, Strip};

use super::host::{HostDivide, HostSpecular};
use crate::scene::convert::threshold_q8;
use crate::scene::desc::{DivideName, SceneDesc, ShadingName, SpanName};

/// What a draw takes besides the frame and the target.
#[derive(Copy, Clone, Debug, Default)]
pub struct Args {
    /// Phong lighting sampled by pixel segments.
    sampling: Option<Sampling>,
    /// Perspective-correct interpolation, one division per span of this many pixels.
    perspective: Option<Perspective>,
}

/// A frame's draw into a strip with depth cells `C`, with its arguments.
pub type DrawFn<P, C = u16> = fn(
    &Frame<'_, '_, '_, P, HostSpecular>,
    &mut Strip<'_, P, C>,
    &Args,
) -> Result<Stats, RenderError>;

/// A strip with the depth cells its scene asks for (`depth_bits`).
pub enum DepthStrip<'s, 'b, P: PixelFormat> {
    /// 16-bit cells (or no depth buffer).
    D16(&'s mut Strip<'b, P, u16>),
    /// 32-bit cells.
    D32(&'s mut Strip<'b, P, u32>),
}

impl<'b, P: PixelFormat> DepthStrip<'_, 'b, P> {
    /// The same strip, borrowed again (to draw into it more than once).
    pub fn reborrow(&mut self) -> DepthStrip<'_, 'b, P> {
        match self {
            DepthStrip::D16(s) => DepthStrip::D16(s),
            DepthStrip::D32(s) => DepthStrip::D32(s),
        }
    }
}

/// The draw function of either depth cell.
enum Fn16or32<P: PixelFormat> {
    D16(DrawFn<P, u16>),
    D32(DrawFn<P, u32>),
}

/// The draw a scene description asks for, chosen once: call [`Draw::run`] for
/// every strip of every frame.
pub struct Draw<P: PixelFormat> {
    f: Fn16or32<P>,
    args: Args,
    /// True if the draw is the core's [`Gradient`] with the exact divider, flat or
    /// Gouraud, one-sided: a frame of it binned ([`Frame::bin`]) draws its bands
    /// from the records ([`Draw::records`]).
    records: bool,
}

impl<P: PixelFormat> Draw<P> {
    /// True if the draw takes strips with 32-bit depth cells.
    pub fn depth32(&self) -> bool {
        matches!(self.f, Fn16or32::D32(_))
    }

    /// True if the draw's pixels are those of the core's [`Gradient`] (exact
    /// divider, flat or Gouraud, one-sided lighting), so that a binned frame can
    /// draw its bands from records with it
    /// ([`fixshade::render::Binned::draw_band`]).
    pub fn records(&self) -> bool {
        self.records
    }

    /// Draws `frame` into `target`, whose depth cells must be the draw's
    /// ([`Draw::depth32`]).
    pub fn run(
        &self,
        frame: &Frame<'_, '_, '_, P, HostSpecular>,
        target: DepthStrip<'_, '_, P>,
    ) -> Result<Stats, String> {
        match (&self.f, target) {
            (Fn16or32::D16(f), DepthStrip::D16(t)) => f(frame, t, &self.args),
            (Fn16or32::D32(f), DepthStrip::D32(t)) => f(frame, t, &self.args),
            _ => return Err("the strip's depth cells are not the draw's".into()),
        }
        .map_err(|e| e.to_string())
    }
}

fn with<P: PixelFormat, S: SpanMethod, Z: DepthMode, Sh: Shading, C: DepthFormat>(
    frame: &Frame<'_, '_, '_, P, HostSpecular>,
    target: &mut Strip<'_, P, C>,
    _: &Args,
) -> Result<Stats, RenderError> {
    frame.draw_with::<S, Z, Sh, _>(target)
}

fn sampled<P: PixelFormat, C: DepthFormat>(
    frame: &Frame<'_, '_, '_, P, HostSpecular>,
    target: &mut Strip<'_, P, C>,
    args: &Args,
) -> Result<Stats, RenderError> {
    let sampling = args.sampling.expect("chosen with a sampling");
    frame.draw_phong_sampled(target, sampling)
}

fn perspective<P: PixelFormat, C: DepthFormat>(
    frame: &Frame<'_, '_, '_, P, HostSpecular>,
    target: &mut Strip<'_, P, C>,
    args: &Args,
) -> Result<Stats, RenderError> {
    let mode = args.perspective.expect("chosen with a perspective mode");
    frame.draw_perspective::<HostDivide, _>(target, mode)
}

/// Flat and Gouraud draws of every span method, indexed `[method][2·gouraud +
/// depth]`.
macro_rules! span_table {
    ([$P:ty] $($S:ty),* $(,)?) => {
        [$([
            with::<$P, $S, NoDepth, Flat, u16> as DrawFn<$P>,
            with::<$P, $S, DepthTest, Flat, u16>,
            with::<$P, $S, NoDepth, Gouraud, u16>,
            with::<$P, $S, DepthTest, Gouraud, u16>,
        ]),*]
    };
}

/// Depth-tested flat and Gouraud draws of every span method into 32-bit depth
/// cells, indexed `[method][gouraud]`.
macro_rules! span_table32 {
    ([$P:ty] $($S:ty),* $(,)?) => {
        [$([
            with::<$P, $S, DepthTest, Flat, u32> as DrawFn<$P, u32>,
            with::<$P, $S, DepthTest, Gouraud, u32>,
        ]),*]
    };
}

/// Draws of every core shading mode with the span method `$G`, indexed
/// `[shading][depth]`.
macro_rules! shading_table {
    ([$P:ty, $G:ty] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
        [$([
            with::<$P, $G, NoDepth, $Sh, u16> as DrawFn<$P>,
            with::<$P, $G, DepthTest, $Sh, u16>,
        ]),*]
    };
}

/// Depth-tested draws of every core shading mode with the span method `$G` into
/// 32-bit depth cells, indexed `[shading]`.
macro_rules! shading_table32 {
    ([$P:ty, $G:ty] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
        [$(with::<$P, $G, DepthTest, $Sh, u32> as DrawFn<$P, u32>),*]
    };
}

/// True for the shadings perspective correction applies to: Gouraud colours, Phong
/// normals and positions, adaptive (both).
pub fn perspective_shading(s: ShadingName) -> bool {
    matches!(
        s,
        ShadingName::GOURAUD
            | ShadingName::PHONG
            | ShadingName::PHONG_EVEN_ODD
            | ShadingName::ADAPTIVE
    )
}

/// Flat and Gouraud draws of every span method, `[method][2·gouraud + depth]`.
fn spans<P: PixelFormat>() -> Vec<[DrawFn<P>; 4]> {
    fixshade::for_each_span_method!(span_table[P]; HostDivide).to_vec()
}

/// Draws of every core shading mode with `gradient`, `[shading][depth]`.
fn shadings<P: PixelFormat>() -> Vec<[DrawFn<P>; 2]> {
    fixshade::for_each_shading!(shading_table[P, WithDivide<Gradient, HostDivide>]).to_vec()
}

/// Depth-tested flat and Gouraud draws into 32-bit cells, `[method][gouraud]`.
fn spans32<P: PixelFormat>() -> Vec<[DrawFn<P, u32>; 2]> {
    fixshade::for_each_span_method!(span_table32[P]; HostDivide).to_vec()
}

/// Depth-tested draws of every core shading mode into 32-bit cells, `[shading]`.
fn shadings32<P: PixelFormat>() -> Vec<DrawFn<P, u32>> {
    fixshade::for_each_shading!(shading_table32[P, WithDivide<Gradient, HostDivide>]).to_vec()
}

/// Chooses the draw of `d` (not ray casting). Two-sided lighting takes the exact
/// divider only, and not adaptive shading (the core does not support it there).
pub fn choose<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P>, String> {
    if d.two_sided {
        if d.shading == ShadingName::ADAPTIVE {
            return Err(fixshade::render::RenderError::TwoSidedUnsupported.to_string());
        }
        if d.divide != DivideName::EXACT {
            return Err("two-sided lighting takes the exact divider (divide = \"exact\")".into());
        }
    }
    choose_draw::<P>(d)
}

/// The draw of `d`: sampled Phong when the scene samples
/// Phong lighting, perspective-correct colours or normals when a Gouraud, Phong or
/// adaptive scene asks for them (coverage then follows `gradient`), the shading's
/// own fill for quadratic, Phong and adaptive, the span method otherwise; with the
/// scene's depth test, into 32-bit depth cells when the scene asks for them and
/// tests depth.
fn choose_draw<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P>, String> {
    if d.shading.core().is_none() {
        return Err(format!("{} has no raster pipeline", d.shading));
    }
    let depth = usize::from(d.depth_test);
    let d32 = d.depth_test && d.depth_bits == 32;
    let draw = |f16: DrawFn<P>, f32: DrawFn<P, u32>, args: Args| Draw {
        f: if d32 {
            Fn16or32::D32(f32)
        } else {
            Fn16or32::D16(f16)
        },
        args,
        records: false,
    };
    if d.shading == ShadingName::PHONG && d.raycast.sampled {
        let threshold = Threshold::from_q8(threshold_q8(d.raycast.threshold), P::MAX);
        let args = Args {
            sampling: Some(Sampling {
                segment: d.raycast.segment,
                threshold,
            }),
            ..Args::default()
        };
        return Ok(draw(sampled::<P, u16>, sampled::<P, u32>, args));
    }
    if d.perspective_correct && perspective_shading(d.shading) {
        let mode = Perspective::new(d.perspective_span).ok_or_else(|| {
            format!(
                "perspective span {} is not a power of two from 1 to 64",
                d.perspective_span
            )
        })?;
        let args = Args {
            perspective: Some(mode),
            ..Args::default()
        };
        return Ok(draw(perspective::<P, u16>, perspective::<P, u32>, args));
    }
    let args = Args::default();
    if d.shading.own_fill() {
        let i = d.shading.index();
        return Ok(draw(shadings::<P>()[i][depth], shadings32::<P>()[i], args));
    }
    let gouraud = usize::from(d.shading == ShadingName::GOURAUD);
    let i = d.span.index();
    Ok(Draw {
        records: d.span == SpanName::GRADIENT && d.divide == DivideName::EXACT && !d.two_sided,
        ..draw(
            spans::<P>()[i][2 * gouraud + depth],
            spans32::<P>()[i][gouraud],
            args,
        )
    })
}
