//! The presentation layer, above [`crate::render`]: the ways a frame reaches a
//! display. [`Renderer`] draws a scene in one call; [`linebuf`] streams bands to a
//! display that lends its own buffers; `eg` (with the feature `embedded-graphics`) draws a
//! model into any embedded-graphics `DrawTarget`. Nothing below this module
//! imports it.
//!
//! The front door: [`Renderer`] draws a [`Scene`] into a [`Target`] in one call, and
//! builder methods set a scene up in one expression.
//!
//! `Renderer::new(&mut target).draw(&scene, &mut cache)` runs the vertex stage
//! ([`Frame::prepare`]) and rasterizes ([`Frame::draw`]) with the constant-gradient
//! span method and exact Blinn specular; [`Renderer::span`] and
//! [`Renderer::specular`] pick other variants by type. The vertex cache is
//! caller-owned: one [`XfVertex`] per vertex of the scene ([`Scene::vertex_count`]).
//! To draw one prepared frame into several targets (strips, a line buffer, an
//! embedded-graphics display), use [`Frame`] directly.
//!
//! ```
//! use fixshade::prelude::*;
//!
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
//!
//! let eye = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)];
//! let scene = Scene::new(Camera::perspective(eye, [Q16_16::ZERO; 3], Angle::from_degrees(60)))
//!     .with_light(Light::directional(eye, rgb(255, 255, 255), rgb(255, 255, 255)))
//!     .unwrap()
//!     .with_object(Object::new(Mesh::new(&POS, &NRM, &TRI).unwrap()).with_material(
//!         Material::default().with_diffuse(rgb(230, 120, 40)),
//!     ))
//!     .unwrap();
//!
//! let mut color = [0u16; 32 * 24];
//! let mut depth = [0xFFFFu16; 32 * 24];
//! let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), 32, 24).unwrap();
//! let mut cache = [XfVertex::default(); 3];
//! let stats = Renderer::new(&mut fb).draw(&scene, &mut cache).unwrap();
//! assert_eq!(stats.drawn, 1);
//! // The same scene with the idx3d per-span division instead.
//! let classic = Renderer::new(&mut fb).span::<Classic>().draw(&scene, &mut cache).unwrap();
//! assert_eq!(classic.pixels, stats.pixels);
//! ```

#[cfg(feature = "embedded-graphics")]
pub mod eg;
pub mod linebuf;

use core::marker::PhantomData;

use crate::fixed::{Angle, Q16_16};
use crate::geometry::Mesh;
use crate::light::{Color, Light, Material};
use crate::math::Vec3;
use crate::raster::span::{Gradient, SpanMethod};
use crate::render::{Frame, RenderError, Stats, XfVertex};
use crate::scene::{Camera, CapacityError, Object, Placement, Projection, Scene, ShadingMode};
use crate::specular::{BlinnExact, Specular};
use crate::target::{PixelFormat, Target, TargetError};

/// Draws scenes into one target, with the span method `S` and specular model `Sp`
/// chosen by type (defaults: [`Gradient`], [`BlinnExact`]).
///
/// ```
/// use fixshade::prelude::*;
/// let mut px = [0u8; 8 * 8];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 8, 8).unwrap();
/// // An empty scene draws nothing; no depth buffer is needed without a depth test.
/// let scene = Scene::new(Camera::perspective(
///     [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)],
///     [Q16_16::ZERO; 3],
///     Angle::from_degrees(45),
/// ))
/// .with_depth_test(false);
/// let stats = Renderer::new(&mut fb).draw(&scene, &mut []).unwrap();
/// assert_eq!(stats, Stats::default());
/// ```
pub struct Renderer<'t, P, T, S = Gradient, Sp = BlinnExact>
where
    P: PixelFormat,
    T: Target<P>,
{
    target: &'t mut T,
    _variants: PhantomData<(P, S, Sp)>,
}

impl<'t, P: PixelFormat, T: Target<P>> Renderer<'t, P, T> {
    /// A renderer drawing into `target` with the default variants.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// let mut px = [[0u8; 3]; 4 * 4];
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, None, 4, 4).unwrap();
    /// let r = Renderer::new(&mut fb);
    /// assert_eq!(r.target().width(), 4);
    /// ```
    pub fn new(target: &'t mut T) -> Self {
        Renderer {
            target,
            _variants: PhantomData,
        }
    }
}

impl<'t, P: PixelFormat, T: Target<P>, S: SpanMethod, Sp: Specular> Renderer<'t, P, T, S, Sp> {
    /// The same renderer with the span method `S2` (see [`crate::raster::span`],
    /// [`crate::raster::parallel`], [`crate::raster::sierpinski`]).
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// let mut px = [0u8; 4];
    /// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 2, 2).unwrap();
    /// let _kway = Renderer::new(&mut fb).span::<KWay<4>>();
    /// ```
    pub fn span<S2: SpanMethod>(self) -> Renderer<'t, P, T, S2, Sp> {
        Renderer {
            target: self.target,
            _variants: PhantomData,
        }
    }

    /// The same renderer with the specular model `Sp2` (see [`crate::specular`]).
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::specular::Schlick;
    /// let mut px = [0u8; 4];
    /// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 2, 2).unwrap();
    /// let _schlick = Renderer::new(&mut fb).specular::<Schlick>();
    /// ```
    pub fn specular<Sp2: Specular>(self) -> Renderer<'t, P, T, S, Sp2> {
        Renderer {
            target: self.target,
            _variants: PhantomData,
        }
    }

    /// The target.
    pub fn target(&self) -> &T {
        self.target
    }

    /// Runs the vertex stage of `scene` into `cache` (at least
    /// [`Scene::vertex_count`] entries) and rasterizes it into the target, with the
    /// scene's depth and shading settings. The frame size is the target's
    /// ([`Target::width`], [`Target::frame_height`]), so a [`crate::target::Strip`]
    /// draws its rows of the whole frame.
    ///
    /// See the [module docs](self) for an example.
    pub fn draw(
        &mut self,
        scene: &Scene<'_>,
        cache: &mut [XfVertex],
    ) -> Result<Stats, RenderError> {
        let (w, h) = (self.target.width(), self.target.frame_height());
        let frame = Frame::<P>::prepare_with::<Sp>(scene, w, h, cache)?;
        frame.draw::<S, T>(self.target)
    }
}

/// Why a draw through an adapter ([`crate::present::linebuf`], the `eg` module) failed: the
/// frame, or a buffer the caller handed over.
///
/// ```
/// use fixshade::present::DrawError;
/// use fixshade::target::TargetError;
/// let e: DrawError = TargetError::DepthBufferTooSmall.into();
/// assert_eq!(e, DrawError::Buffer(TargetError::DepthBufferTooSmall));
/// assert_eq!(e.to_string(), TargetError::DepthBufferTooSmall.to_string());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum DrawError {
    /// Preparing or drawing the frame failed.
    Render(RenderError),
    /// A colour or depth buffer is too small for the rows asked of it.
    Buffer(TargetError),
}

impl From<RenderError> for DrawError {
    fn from(e: RenderError) -> Self {
        DrawError::Render(e)
    }
}

impl From<TargetError> for DrawError {
    fn from(e: TargetError) -> Self {
        DrawError::Buffer(e)
    }
}

impl core::fmt::Display for DrawError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DrawError::Render(e) => e.fmt(f),
            DrawError::Buffer(e) => e.fmt(f),
        }
    }
}

/// The +y axis, the default up direction of the camera constructors.
const UP: Vec3 = [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO];

impl Camera {
    /// A perspective camera at `eye` looking at `target`, up +y, near plane 1 and far
    /// plane 100 (change them with [`Camera::with_depth_range`]).
    ///
    /// ```
    /// use fixshade::fixed::{Angle, Q16_16};
    /// use fixshade::scene::{Camera, Projection};
    /// let cam = Camera::perspective([Q16_16::from_int(4); 3], [Q16_16::ZERO; 3], Angle::from_degrees(45));
    /// assert!(cam.view().is_some());
    /// assert!(matches!(cam.projection, Projection::Perspective { .. }));
    /// ```
    pub fn perspective(eye: Vec3, target: Vec3, fovy: Angle) -> Camera {
        Camera {
            eye,
            target,
            up: UP,
            projection: Projection::Perspective {
                fovy,
                near: Q16_16::ONE,
                far: Q16_16::from_int(100),
            },
        }
    }

    /// An orthographic camera at `eye` looking at `target`, up +y, showing a
    /// view volume `height` world units tall (the width follows the frame's aspect),
    /// near plane 0 and far plane 100 (see [`Camera::with_depth_range`]). The usual
    /// choice for gauges and HUDs.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::scene::Camera;
    /// let cam = Camera::orthographic([Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(5)], [Q16_16::ZERO; 3], Q16_16::from_int(2));
    /// assert!(cam.projection_matrix(320, 240).is_some());
    /// ```
    pub fn orthographic(eye: Vec3, target: Vec3, height: Q16_16) -> Camera {
        Camera {
            eye,
            target,
            up: UP,
            projection: Projection::Orthographic {
                height,
                near: Q16_16::ZERO,
                far: Q16_16::from_int(100),
            },
        }
    }

    /// The same camera with another up direction.
    ///
    /// ```
    /// use fixshade::fixed::{Angle, Q16_16};
    /// use fixshade::scene::Camera;
    /// let z_up = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE];
    /// let cam = Camera::perspective([Q16_16::from_int(4), Q16_16::ZERO, Q16_16::ZERO], [Q16_16::ZERO; 3], Angle::from_degrees(45))
    ///     .with_up(z_up);
    /// assert_eq!(cam.up, z_up);
    /// ```
    pub fn with_up(mut self, up: Vec3) -> Camera {
        self.up = up;
        self
    }

    /// The same camera with the near and far planes `near` and `far`.
    ///
    /// ```
    /// use fixshade::fixed::{Angle, Q16_16};
    /// use fixshade::scene::Camera;
    /// let cam = Camera::perspective([Q16_16::from_int(4); 3], [Q16_16::ZERO; 3], Angle::from_degrees(45))
    ///     .with_depth_range(Q16_16::from_int(2), Q16_16::from_int(10));
    /// assert!(cam.projection_matrix(64, 64).is_some());
    /// ```
    pub fn with_depth_range(mut self, near: Q16_16, far: Q16_16) -> Camera {
        match &mut self.projection {
            Projection::Perspective {
                near: n, far: f, ..
            }
            | Projection::Orthographic {
                near: n, far: f, ..
            } => {
                *n = near;
                *f = far;
            }
        }
        self
    }
}

impl<'a> Object<'a> {
    /// `mesh` at the origin, unrotated, unscaled, with OpenGL's default material.
    ///
    /// ```
    /// use fixshade::fixed::{Angle, Q16_16, Q2_14};
    /// use fixshade::geometry::Mesh;
    /// use fixshade::scene::Object;
    /// static POS: [[Q16_16; 3]; 3] = [[Q16_16::ZERO; 3], [Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO], [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO]];
    /// static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
    /// let obj = Object::new(Mesh::new(&POS, &NRM, &[[0, 1, 2]]).unwrap())
    ///     .translated([Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO])
    ///     .rotated([Angle::from_degrees(0), Angle::from_degrees(30), Angle::from_degrees(0)])
    ///     .scaled(Q16_16::from_int(2));
    /// assert_eq!(obj.placement.scale, Q16_16::from_int(2));
    /// ```
    pub fn new(mesh: Mesh<'a>) -> Object<'a> {
        Object {
            mesh,
            placement: Placement::default(),
            material: Material::default(),
            back_material: None,
        }
    }

    /// The same object moved to `translate`.
    pub fn translated(mut self, translate: Vec3) -> Object<'a> {
        self.placement.translate = translate;
        self
    }

    /// The same object rotated about x, y and z (x applied first).
    pub fn rotated(mut self, rotate: [Angle; 3]) -> Object<'a> {
        self.placement.rotate = rotate;
        self
    }

    /// The same object with uniform scale `scale`.
    pub fn scaled(mut self, scale: Q16_16) -> Object<'a> {
        self.placement.scale = scale;
        self
    }

    /// The same object with `material`.
    pub fn with_material(mut self, material: Material) -> Object<'a> {
        self.material = material;
        self
    }

    /// The same object with `material` on its back faces (used by two-sided
    /// lighting, [`crate::effects::TwoSided`]).
    ///
    /// ```
    /// use fixshade::prelude::{rgb, Material, Object};
    /// # let mesh = fixshade::doc_support::triangle().unwrap();
    /// let inside = Material::default().with_diffuse(rgb(200, 40, 40));
    /// let obj = Object::new(mesh).with_back_material(&inside);
    /// assert_eq!(obj.back_material, Some(&inside));
    /// ```
    pub fn with_back_material(mut self, material: &'a Material) -> Object<'a> {
        self.back_material = Some(material);
        self
    }
}

impl Material {
    /// The same material with diffuse reflectance `diffuse`, and ambient reflectance
    /// a quarter of it (OpenGL's default ratio 0.2 : 0.8).
    ///
    /// ```
    /// use fixshade::light::Material;
    /// use fixshade::light::rgb;
    /// let m = Material::default().with_diffuse(rgb(200, 100, 40));
    /// assert_eq!(m.diffuse, rgb(200, 100, 40));
    /// assert_eq!(m.ambient[0].to_bits(), m.diffuse[0].to_bits() / 4);
    /// ```
    pub fn with_diffuse(mut self, diffuse: Color) -> Material {
        self.diffuse = diffuse;
        self.ambient = diffuse.map(|c| Q16_16::from_bits(c.to_bits() / 4));
        self
    }

    /// The same material with specular reflectance `specular` and Blinn exponent
    /// `shininess` (1..=1000).
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::light::Material;
    /// use fixshade::light::rgb;
    /// let m = Material::default().with_specular(rgb(255, 255, 255), 40);
    /// assert_eq!(m.shininess, Q16_16::from_int(40));
    /// ```
    pub fn with_specular(mut self, specular: Color, shininess: u16) -> Material {
        self.specular = specular;
        self.shininess = Q16_16::from_int(shininess as i32);
        self
    }
}

impl<'a> Scene<'a> {
    /// The same scene with one more light; fails if it has 8 already.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// let cam = Camera::perspective([Q16_16::from_int(4); 3], [Q16_16::ZERO; 3], Angle::from_degrees(45));
    /// let sun = Light::directional([Q16_16::ONE; 3], rgb(255, 255, 255), rgb(0, 0, 0));
    /// let scene = Scene::new(cam).with_light(sun).unwrap();
    /// assert_eq!(scene.lights.len(), 1);
    /// ```
    pub fn with_light(mut self, light: Light) -> Result<Scene<'a>, CapacityError> {
        self.add_light(light)?;
        Ok(self)
    }

    /// The same scene with one more object; fails if it has 16 already.
    ///
    /// See the [module docs](crate::present) for an example.
    pub fn with_object(mut self, object: Object<'a>) -> Result<Scene<'a>, CapacityError> {
        self.add_object(object)?;
        Ok(self)
    }

    /// The same scene with shading `mode`.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// let cam = Camera::perspective([Q16_16::from_int(4); 3], [Q16_16::ZERO; 3], Angle::from_degrees(45));
    /// let scene = Scene::new(cam).with_shading(ShadingMode::Flat);
    /// assert_eq!(scene.shading, ShadingMode::Flat);
    /// ```
    pub fn with_shading(mut self, mode: ShadingMode) -> Scene<'a> {
        self.shading = mode;
        self
    }

    /// The same scene with the depth test on or off (off: later triangles overwrite
    /// earlier ones, and the target needs no depth buffer).
    pub fn with_depth_test(mut self, on: bool) -> Scene<'a> {
        self.depth_test = on;
        self
    }

    /// The same scene with back-face culling on or off.
    pub fn with_cull_back(mut self, on: bool) -> Scene<'a> {
        self.cull_back = on;
        self
    }

    /// The same scene with the global ambient light `ambient`.
    pub fn with_ambient(mut self, ambient: Color) -> Scene<'a> {
        self.global_ambient = ambient;
        self
    }
}
