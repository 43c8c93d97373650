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
//! scene.add_object(Object { mesh, placement: Placement::default(), material: Material::default() }).unwrap();
//!
//! let mut color = [0u16; 32 * 24];
//! let mut cache = [XfVertex::default(); 3];
//! let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, None, 32, 24).unwrap();
//! let frame = Frame::<Rgb565Le>::prepare_with::<NoSpecular>(&scene, 32, 24, &mut cache).unwrap();
//! let stats = frame.draw_with::<Gradient, NoDepth, Gouraud, _>(&mut fb).unwrap();
//! assert_eq!(stats.drawn, 1);
//! ```

use crate::fixed::Q16_16;
pub use crate::light::Specular;

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
