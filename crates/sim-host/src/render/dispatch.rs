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
//! Each comes twice: with the exact divider, and with [`HostDivide`] (every
//! approximate divider, chosen at run time, see [`super::host`]). The specular model
//! is not a parameter here: frames are prepared with [`super::host::HostSpecular`]
//! (or without a specular term, `NoSpecular`), whose model is chosen at run time.
//! The functions are fn pointers into the table of the frame's pixel format, built
//! from the core's registry ([`fixshade::for_each_span_method!`],
//! [`fixshade::for_each_shading!`]), so a new span method needs no line here.

use fixshade::divide::{Divide, Exact};
use fixshade::effects::{NoSpecular, TwoSided};
use fixshade::raster::perspective::Perspective;
use fixshade::raster::phong::Sampling;
use fixshade::raster::span::{DepthMode, DepthTest, Gradient, NoDepth, SpanMethod, WithDivide};
use fixshade::render::{Frame, RenderError, Stats};
use fixshade::sampler::Threshold;
use fixshade::shade::{Flat, Gouraud, Shading};
use fixshade::specular::Specular;
use fixshade::target::{PixelFormat, Strip};

use super::host::{HostDivide, HostSpecular};
use crate::scene::convert::threshold_q8;
use crate::scene::desc::{DivideName, SceneDesc, ShadingName};

/// What a draw takes besides the frame and the target.
#[derive(Copy, Clone, Debug, Default)]
pub struct Args {
    /// Phong lighting sampled by pixel segments.
    sampling: Option<Sampling>,
    /// Perspective-correct interpolation, one division per span of this many pixels.
    perspective: Option<Perspective>,
}

/// A frame's draw into a strip, with its arguments.
pub type DrawFn<P, Sp> =
    fn(&Frame<'_, '_, '_, P, Sp>, &mut Strip<'_, P>, &Args) -> Result<Stats, RenderError>;

/// The draw a scene description asks for, chosen once: call [`Draw::run`] for
/// every strip of every frame.
pub struct Draw<P: PixelFormat, Sp: Specular> {
    f: DrawFn<P, Sp>,
    args: Args,
}

impl<P: PixelFormat, Sp: Specular> Draw<P, Sp> {
    /// Draws `frame` into `target`.
    pub fn run(
        &self,
        frame: &Frame<'_, '_, '_, P, Sp>,
        target: &mut Strip<'_, P>,
    ) -> Result<Stats, String> {
        (self.f)(frame, target, &self.args).map_err(|e| e.to_string())
    }
}

fn with<P: PixelFormat, Sp: Specular, S: SpanMethod, Z: DepthMode, Sh: Shading>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    target: &mut Strip<'_, P>,
    _: &Args,
) -> Result<Stats, RenderError> {
    frame.draw_with::<S, Z, Sh, _>(target)
}

fn sampled<P: PixelFormat, Sp: Specular>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    target: &mut Strip<'_, P>,
    args: &Args,
) -> Result<Stats, RenderError> {
    let sampling = args.sampling.expect("chosen with a sampling");
    frame.draw_phong_sampled(target, sampling)
}

fn perspective<D: Divide, P: PixelFormat, Sp: Specular>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    target: &mut Strip<'_, P>,
    args: &Args,
) -> Result<Stats, RenderError> {
    let mode = args.perspective.expect("chosen with a perspective mode");
    frame.draw_perspective::<D, _>(target, mode)
}

/// Flat and Gouraud draws of every span method, indexed `[method][2·gouraud +
/// depth]`.
macro_rules! span_table {
    ([$P:ty, $Sp:ty] $($S:ty),* $(,)?) => {
        [$([
            with::<$P, $Sp, $S, NoDepth, Flat> as DrawFn<$P, $Sp>,
            with::<$P, $Sp, $S, DepthTest, Flat>,
            with::<$P, $Sp, $S, NoDepth, Gouraud>,
            with::<$P, $Sp, $S, DepthTest, Gouraud>,
        ]),*]
    };
}

/// Draws of every core shading mode with the span method `$G`, indexed
/// `[shading][depth]`.
macro_rules! shading_table {
    ([$P:ty, $Sp:ty, $G:ty] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
        [$([
            with::<$P, $Sp, $G, NoDepth, $Sh> as DrawFn<$P, $Sp>,
            with::<$P, $Sp, $G, DepthTest, $Sh>,
        ]),*]
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

/// The draws of one divider: the exact one (the plain span types) or
/// [`HostDivide`] (every approximate divider).
trait Divided: Divide {
    /// Flat and Gouraud draws of every span method, `[method][2·gouraud + depth]`.
    fn spans<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 4]>;
    /// Draws of every core shading mode with `gradient`, `[shading][depth]`.
    fn shadings<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 2]>;
}

impl Divided for Exact {
    fn spans<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 4]> {
        fixshade::for_each_span_method!(span_table[P, Sp]).to_vec()
    }
    fn shadings<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 2]> {
        fixshade::for_each_shading!(shading_table[P, Sp, Gradient]).to_vec()
    }
}

impl Divided for HostDivide {
    fn spans<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 4]> {
        fixshade::for_each_span_method!(span_table[P, Sp]; HostDivide).to_vec()
    }
    fn shadings<P: PixelFormat, Sp: Specular>() -> Vec<[DrawFn<P, Sp>; 2]> {
        fixshade::for_each_shading!(shading_table[P, Sp, WithDivide<Gradient, HostDivide>]).to_vec()
    }
}

/// The frames' lighting types and the draws each is compiled for.
pub trait Lighting: Specular + Sized {
    /// Chooses the draw of `d` (not ray casting) for frames lit with `Self`.
    fn choose<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P, Self>, String>;
}

/// Without a specular term: the exact divider only ([`super::frame::specular_pipeline`]).
impl Lighting for NoSpecular {
    fn choose<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P, Self>, String> {
        if d.divide != DivideName::EXACT {
            return Err("frames without the specular term take the exact divider".into());
        }
        choose_with::<P, Self, Exact>(d)
    }
}

/// With the specular model chosen at run time: every divider.
impl Lighting for HostSpecular {
    fn choose<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P, Self>, String> {
        if d.divide == DivideName::EXACT {
            choose_with::<P, Self, Exact>(d)
        } else {
            choose_with::<P, Self, HostDivide>(d)
        }
    }
}

/// Two-sided lighting with the specular model chosen at run time: the exact
/// divider only, and not adaptive shading (the core does not support it there).
impl Lighting for TwoSided<HostSpecular> {
    fn choose<P: PixelFormat>(d: &SceneDesc) -> Result<Draw<P, Self>, String> {
        if d.shading == ShadingName::ADAPTIVE {
            return Err(fixshade::render::RenderError::TwoSidedUnsupported.to_string());
        }
        if d.divide != DivideName::EXACT {
            return Err("two-sided lighting takes the exact divider (divide = \"exact\")".into());
        }
        choose_with::<P, Self, Exact>(d)
    }
}

/// Chooses the draw of `d` with the divider `D`: sampled Phong when the scene samples
/// Phong lighting, perspective-correct colours or normals when a Gouraud, Phong or
/// adaptive scene asks for them (coverage then follows `gradient`), the shading's
/// own fill for quadratic, Phong and adaptive, the span method otherwise; with the
/// scene's depth test.
fn choose_with<P: PixelFormat, Sp: Specular, D: Divided>(
    d: &SceneDesc,
) -> Result<Draw<P, Sp>, String> {
    if d.shading.core().is_none() {
        return Err(format!("{} has no raster pipeline", d.shading));
    }
    let depth = usize::from(d.depth_test);
    if d.shading == ShadingName::PHONG && d.raycast.sampled {
        let threshold = Threshold::from_q8(threshold_q8(d.raycast.threshold), P::MAX);
        let args = Args {
            sampling: Some(Sampling {
                segment: d.raycast.segment,
                threshold,
            }),
            ..Args::default()
        };
        return Ok(Draw {
            f: sampled::<P, Sp>,
            args,
        });
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
        return Ok(Draw {
            f: perspective::<D, P, Sp>,
            args,
        });
    }
    let args = Args::default();
    if d.shading.own_fill() {
        return Ok(Draw {
            f: D::shadings::<P, Sp>()[d.shading.index()][depth],
            args,
        });
    }
    let gouraud = usize::from(d.shading == ShadingName::GOURAUD);
    Ok(Draw {
        f: D::spans::<P, Sp>()[d.span.index()][2 * gouraud + depth],
        args,
    })
}
