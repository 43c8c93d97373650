//! Scenes: camera, up to 8 lights, objects (a mesh, a placement and a material) and
//! the render settings, in fixed capacity (no allocation).
//!
//! ```
//! use fixshade::fixed::{Angle, Q16_16};
//! use fixshade::scene::{Camera, Projection};
//! let cam = Camera {
//!     eye: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(4)],
//!     target: [Q16_16::ZERO; 3],
//!     up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
//!     projection: Projection::Perspective {
//!         fovy: Angle::from_degrees(45),
//!         near: Q16_16::ONE,
//!         far: Q16_16::from_int(10),
//!     },
//! };
//! assert!(cam.view().is_some());
//! assert!(cam.projection_matrix(320, 240).is_some());
//! ```

use crate::fixed::{Angle, Q16_16};
use crate::geometry::Mesh;
use crate::light::{Color, Light, Material, MAX_LIGHTS};
use crate::math::{Mat4, Vec3};

/// Maximum number of objects in a scene.
pub const MAX_OBJECTS: usize = 16;

/// A projection.
///
/// ```
/// use fixshade::fixed::{Angle, Q16_16};
/// use fixshade::scene::{Camera, Projection};
/// let q = Q16_16::from_int;
/// // A flat HUD: 10 units of world seen top to bottom, no perspective.
/// let mut cam = Camera::orthographic([q(0), q(0), q(5)], [q(0); 3], q(10));
/// assert!(matches!(cam.projection, Projection::Orthographic { .. }));
/// cam.projection = Projection::Perspective { fovy: Angle::from_degrees(90), near: q(1), far: q(1) };
/// assert!(cam.projection_matrix(320, 240).is_none()); // far must exceed near
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Projection {
    /// `gluPerspective(fovy, width / height, near, far)`.
    Perspective {
        /// Vertical field of view, strictly between 0 and 180°.
        fovy: Angle,
        /// Near plane distance, > 0.
        near: Q16_16,
        /// Far plane distance, > near.
        far: Q16_16,
    },
    /// `glOrtho(-h·a/2, h·a/2, -h/2, h/2, near, far)`, a = width / height.
    Orthographic {
        /// View-volume height.
        height: Q16_16,
        /// Near plane.
        near: Q16_16,
        /// Far plane, > near.
        far: Q16_16,
    },
}

/// A `gluLookAt` camera with its projection.
///
/// ```
/// use fixshade::fixed::{Angle, Q16_16};
/// use fixshade::scene::Camera;
/// let q = Q16_16::from_int;
/// let cam = Camera::perspective([q(0), q(2), q(6)], [q(0); 3], Angle::from_degrees(45))
///     .with_depth_range(q(1), q(20));
/// assert!(cam.view().is_some() && cam.projection_matrix(240, 240).is_some());
/// // Looking straight down with the default +y up has no defined view.
/// let down = Camera::perspective([q(0), q(5), q(0)], [q(0); 3], Angle::from_degrees(45));
/// assert!(down.view().is_none());
/// assert!(down.with_up([q(0), q(0), q(-1)]).view().is_some());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction.
    pub up: Vec3,
    /// Projection.
    pub projection: Projection,
}

impl Camera {
    /// The view matrix, `None` if eye = target or up is parallel to the view direction.
    pub fn view(&self) -> Option<Mat4> {
        Mat4::look_at(self.eye, self.target, self.up)
    }

    /// The projection matrix for a `width` × `height` frame, `None` for invalid
    /// parameters.
    pub fn projection_matrix(&self, width: u32, height: u32) -> Option<Mat4> {
        match self.projection {
            Projection::Perspective { fovy, near, far } => {
                Mat4::perspective(fovy, width, height, near, far)
            }
            Projection::Orthographic {
                height: h,
                near,
                far,
            } => Mat4::orthographic(h, width, height, near, far),
        }
    }
}

/// Where an object sits: the model matrix `T · Rz · Ry · Rx · S`.
///
/// ```
/// use fixshade::fixed::{Angle, Q16_16};
/// use fixshade::math::ONE_Q32;
/// use fixshade::scene::Placement;
/// let p = Placement {
///     translate: [Q16_16::from_int(1), Q16_16::ZERO, Q16_16::ZERO],
///     rotate: [Angle::default(), Angle::from_degrees(90), Angle::default()],
///     scale: Q16_16::from_int(2),
/// };
/// // (0, 0, 1) is scaled to (0, 0, 2), turned about y to (2, 0, 0), moved to (3, 0, 0).
/// let m = p.matrix().transform_point([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE]);
/// assert!((m[0] - 3 * ONE_Q32).abs() <= 8 && m[2].abs() <= 8);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Placement {
    /// Translation.
    pub translate: Vec3,
    /// Rotation about x, y and z (x applied first).
    pub rotate: [Angle; 3],
    /// Uniform scale.
    pub scale: Q16_16,
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            translate: [Q16_16::ZERO; 3],
            rotate: [Angle::default(); 3],
            scale: Q16_16::ONE,
        }
    }
}

impl Placement {
    /// The model matrix.
    pub fn matrix(&self) -> Mat4 {
        Mat4::model(self.translate, self.rotate, [self.scale; 3])
    }
}

/// A mesh placed in the world with a material.
///
/// ```
/// use fixshade::fixed::{Angle, Q16_16};
/// use fixshade::prelude::{rgb, Material, Object};
/// # let mesh = fixshade::doc_support::triangle().unwrap();
/// let obj = Object::new(mesh)
///     .translated([Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO])
///     .rotated([Angle::default(), Angle::from_degrees(30), Angle::default()])
///     .scaled(Q16_16::from_ratio(1, 2))
///     .with_material(Material::default().with_diffuse(rgb(40, 200, 90)));
/// assert_eq!(obj.placement.scale, Q16_16::from_ratio(1, 2));
/// ```
#[derive(Copy, Clone, Debug)]
pub struct Object<'a> {
    /// The mesh (usually in flash).
    pub mesh: Mesh<'a>,
    /// Placement.
    pub placement: Placement,
    /// Material.
    pub material: Material,
    /// The material of its back faces under two-sided lighting
    /// ([`crate::effects::TwoSided`]), borrowed (usually from flash: 4 bytes an
    /// object in RAM); `None`: [`Object::material`] on both sides (OpenGL's
    /// `GL_FRONT_AND_BACK`). One-sided lighting never reads it.
    pub back_material: Option<&'a Material>,
}

/// A scene's fixed capacity (8 lights, 16 objects) is exhausted.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// let mut scene = scene;
/// let sun = scene.lights[0];
/// while scene.lights.len() < 8 {
///     scene.add_light(sun).unwrap();
/// }
/// assert_eq!(scene.add_light(sun), Err(CapacityError));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct CapacityError;

impl core::fmt::Display for CapacityError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("scene capacity exhausted (at most 8 lights and 16 objects)")
    }
}

/// Shading mode chosen in a scene.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// // Per-pixel lighting for this scene; `Frame::draw` picks the matching pipeline.
/// let scene = scene.with_shading(ShadingMode::Phong);
/// assert_eq!(scene.shading, ShadingMode::Phong);
/// assert_eq!(ShadingMode::default(), ShadingMode::Gouraud);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum ShadingMode {
    /// One colour per triangle.
    Flat,
    /// Vertex colours interpolated.
    #[default]
    Gouraud,
    /// Quadratic intensity surface through the vertex and edge-midpoint colours
    /// (seed 003; [`crate::shade::QuadraticSurface`]).
    QuadraticSurface,
    /// Per-pixel lighting from interpolated normals ([`crate::shade::Phong`]).
    Phong,
    /// Phong with the even/odd fill ([`crate::shade::PhongEvenOdd`], same pixels).
    PhongEvenOdd,
    /// Phong where a highlight can reach inside a triangle, Gouraud elsewhere
    /// ([`crate::shade::Adaptive`]).
    Adaptive,
}

/// Everything a frame needs.
///
/// ```
/// use fixshade::prelude::*;
/// # let mesh = fixshade::doc_support::triangle().unwrap();
/// let eye = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)];
/// let mut scene = Scene::new(Camera::perspective(eye, [Q16_16::ZERO; 3], Angle::from_degrees(60)));
/// scene.add_light(Light::directional(eye, rgb(255, 255, 255), rgb(0, 0, 0))).unwrap();
/// scene.add_object(Object::new(mesh)).unwrap();
/// scene.add_object(Object::new(mesh).translated([Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO])).unwrap();
/// assert_eq!(scene.vertex_count(), 6); // the size of the vertex cache to hand `Frame::prepare`
/// assert!(scene.cull_back && scene.depth_test);
/// ```
#[derive(Clone, Debug)]
pub struct Scene<'a> {
    /// Camera.
    pub camera: Camera,
    /// Lights (at most 8).
    pub lights: heapless::Vec<Light, MAX_LIGHTS>,
    /// Global ambient light.
    pub global_ambient: Color,
    /// Local viewer (`GL_LIGHT_MODEL_LOCAL_VIEWER`).
    pub local_viewer: bool,
    /// Objects (at most 16).
    pub objects: heapless::Vec<Object<'a>, MAX_OBJECTS>,
    /// Cull back faces.
    pub cull_back: bool,
    /// Test and write depth.
    pub depth_test: bool,
    /// Shading mode.
    pub shading: ShadingMode,
}

impl<'a> Scene<'a> {
    /// An empty scene with OpenGL's global ambient (0.2), back-face culling, depth
    /// test and Gouraud shading.
    pub fn new(camera: Camera) -> Scene<'a> {
        Scene {
            camera,
            lights: heapless::Vec::new(),
            global_ambient: [Q16_16::from_ratio(1, 5); 3],
            local_viewer: false,
            objects: heapless::Vec::new(),
            cull_back: true,
            depth_test: true,
            shading: ShadingMode::Gouraud,
        }
    }

    /// Adds a light; fails if 8 are already there.
    pub fn add_light(&mut self, light: Light) -> Result<(), CapacityError> {
        self.lights.push(light).map_err(|_| CapacityError)
    }

    /// Adds an object; fails if 16 are already there.
    pub fn add_object(&mut self, object: Object<'a>) -> Result<(), CapacityError> {
        self.objects.push(object).map_err(|_| CapacityError)
    }

    /// Total vertex count of all objects: the size a vertex cache needs.
    pub fn vertex_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.positions().len()).sum()
    }
}
