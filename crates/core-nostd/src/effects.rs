//! Effects chosen at compile time: a firmware build names the work each frame does,
//! and the compiler links that work and nothing else.
//!
//! Every effect of a frame is a type parameter of [`crate::render::Frame`] or of
//! [`crate::render::Frame::draw_with`]:
//!
//! | effect | choice | types |
//! | --- | --- | --- |
//! | lighting | none, diffuse, diffuse + specular | no lights in the scene; [`NoSpecular`]; any [`Specular`] model |
//! | depth test | on, off | [`crate::raster::span::DepthTest`], [`crate::raster::span::NoDepth`] |
//! | shading | flat, Gouraud, quadratic, Phong, adaptive | [`crate::shade`] |
//! | span filling | classic, gradient, parallel, … | [`crate::raster::span::SpanMethod`] |
//!
//! | two-sided lighting | off, on | any [`Specular`] model; [`TwoSided`] of one |
//!
//! Back-face culling and the local viewer stay run-time flags of the
//! [`crate::scene::Scene`]: each costs one branch per triangle or per vertex.
//! A frame lit without a specular term and drawn with Gouraud shading and no depth
//! buffer:
//!
//! ```
//! use fixshade::effects::NoSpecular;
//! use fixshade::fixed::{Angle, Q16_16, Q2_14};
//! use fixshade::geometry::Mesh;
//! use fixshade::light::{Light, Material};
//! use fixshade::raster::span::{Gradient, NoDepth};
//! use fixshade::render::{Frame, XfVertex};
//! use fixshade::scene::{Camera, Object, Placement, Projection, Scene};
//! use fixshade::shade::Gouraud;
//! use fixshade::target::{Framebuffer, Rgb565Le};
//!
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
//! let camera = Camera {
//!     eye: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)],
//!     target: [Q16_16::ZERO; 3],
//!     up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
//!     projection: Projection::Perspective {
//!         fovy: Angle::from_degrees(60),
//!         near: Q16_16::ONE,
//!         far: Q16_16::from_int(10),
//!     },
//! };
//! let mut scene = Scene::new(camera);
//! let white = [Q16_16::ONE; 3];
//! scene.add_light(Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white)).unwrap();
//! let mesh = Mesh::new(&POS, &NRM, &TRI).unwrap();
//! scene.add_object(Object { mesh, placement: Placement::default(), material: Material::default(), back_material: None }).unwrap();
//!
//! let mut color = [0u16; 32 * 24];
//! let mut cache = [XfVertex::default(); 3];
//! let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, None, 32, 24).unwrap();
//! let frame = Frame::<Rgb565Le>::prepare_with::<NoSpecular>(&scene, 32, 24, &mut cache).unwrap();
//! let stats = frame.draw_with::<Gradient, NoDepth, Gouraud, _>(&mut fb).unwrap();
//! assert_eq!(stats.drawn, 1);
//! ```

use core::marker::PhantomData;

use crate::fixed::Q16_16;
pub use crate::specular::Specular;

/// Lighting without a specular term: ambient and diffuse only. With it the vertex
/// stage and per-pixel lighting compile without the half vector, the power and the
/// specular sums ([`Specular::ENABLED`] is false); for a scene whose materials or
/// lights have no specular colour the pixels are those of any other model.
///
/// ```
/// use fixshade::effects::NoSpecular;
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// // The same scene without its specular term: dimmer where the highlight was.
/// let mut cache = [XfVertex::default(); 3];
/// let full = Frame::<Gray8>::prepare(&scene, 1, 1, &mut cache).unwrap();
/// let (mut a, mut b) = ([0u8; 1], [0u8; 1]);
/// full.draw::<Gradient, _>(&mut Framebuffer::new(&mut a, Some(&mut [0xFFFFu16]), 1, 1).unwrap()).unwrap();
/// let mut cache = [XfVertex::default(); 3];
/// let diffuse = Frame::<Gray8>::prepare_with::<NoSpecular>(&scene, 1, 1, &mut cache).unwrap();
/// diffuse.draw::<Gradient, _>(&mut Framebuffer::new(&mut b, Some(&mut [0xFFFFu16]), 1, 1).unwrap()).unwrap();
/// assert!(b[0] < a[0]);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct NoSpecular;

impl Specular for NoSpecular {
    const ENABLED: bool = false;
    type Params = ();
    fn prepare(_: Q16_16) {}
    #[inline]
    fn eval(_: &(), _: i32) -> i32 {
        0
    }
}

/// Two-sided lighting (OpenGL's `GL_LIGHT_MODEL_TWO_SIDE`) with the specular model
/// `Sp`: a triangle whose screen winding makes it a back face (the sign test of
/// back-face culling) is lit with its vertex normals negated and its object's
/// [`crate::scene::Object::back_material`] (the front material when it has none).
///
/// A frame prepared with it ([`crate::render::Frame::prepare_with`]) lights every
/// needed vertex twice, front and back; the second half of the vertex cache holds
/// the back colours, so the cache takes twice [`crate::scene::Scene::vertex_count`]
/// entries. Flat and Gouraud shading pick the front or back colours per triangle;
/// quadratic and Phong shading negate the normals they interpolate on back faces.
/// Adaptive shading does not support it: its draws return
/// [`crate::render::RenderError::TwoSidedUnsupported`]. A frame of one-sided
/// lighting (any other model) compiles none of this: the choice is the constant
/// [`Specular::TWO_SIDED`].
///
/// ```
/// use fixshade::effects::TwoSided;
/// use fixshade::specular::BlinnExact;
/// use fixshade::prelude::*;
/// # let mut scene = fixshade::doc_support::scene();
/// // Seen from behind the triangle is a back face: culling off, it is drawn.
/// scene.camera.eye[2] = -scene.camera.eye[2];
/// scene.cull_back = false;
/// let draw = |two_sided: bool| {
///     let mut cache = [XfVertex::default(); 6];
///     let (mut px, mut z) = ([0u8; 16 * 16], [0xFFFFu16; 16 * 16]);
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 16, 16).unwrap();
///     if two_sided {
///         let frame =
///             Frame::<Gray8>::prepare_with::<TwoSided<BlinnExact>>(&scene, 16, 16, &mut cache)
///                 .unwrap();
///         frame.draw::<Gradient, _>(&mut fb).unwrap();
///     } else {
///         let frame = Frame::<Gray8>::prepare(&scene, 16, 16, &mut cache).unwrap();
///         frame.draw::<Gradient, _>(&mut fb).unwrap();
///     }
///     px[8 * 16 + 8]
/// };
/// // The light shines on the front. One-sided, the back face is lit with the
/// // front's normal, as if it faced the light; two-sided, its normal faces away
/// // from the light and only the ambient term is left.
/// assert!(draw(true) < draw(false));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct TwoSided<Sp: Specular = crate::specular::BlinnExact>(PhantomData<Sp>);

impl<Sp: Specular> Specular for TwoSided<Sp> {
    const ENABLED: bool = Sp::ENABLED;
    const TWO_SIDED: bool = true;
    type Params = Sp::Params;
    #[inline(always)]
    fn enabled() -> bool {
        Sp::enabled()
    }
    #[inline]
    fn prepare(n: Q16_16) -> Sp::Params {
        Sp::prepare(n)
    }
    #[inline]
    fn eval(p: &Sp::Params, c: i32) -> i32 {
        Sp::eval(p, c)
    }
    #[inline]
    fn eval_wide(p: &Sp::Params, c: i32) -> u64 {
        Sp::eval_wide(p, c)
    }
}
