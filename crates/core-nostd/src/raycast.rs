//! A fixed-point ray caster for small scenes: spheres, planes and the scene's
//! triangle meshes, Blinn lighting through any [`Specular`] model, and hard
//! shadows from the first light. It is the costly per-pixel function that
//! [`crate::sampler`] samples sparsely (seed 002, §2.6).
//!
//! Everything happens in eye space (the camera at the origin looking down −z), so
//! the per-point lighting is the scene's own [`LightingSetup::shade`] — the same
//! OpenGL fixed-function model the vertex stage uses, evaluated at the hit point
//! with the hit normal (Phong shading by rays).
//!
//! # Primary rays
//!
//! * Meshes: the rays of all pixels share the eye, so the watertight ray–triangle
//!   test (Woop, Benthin and Wald 2013: edge functions in the ray's own 2-D frame)
//!   is the 2-D edge-function test of the pixel centre against the triangle
//!   projected with the rasterizer's own viewport mapping ([`Viewport::project`],
//!   Q12.4) and its top-left rule. Shared edges are therefore hit exactly once, and
//!   a mesh covers exactly the pixels the rasterizer covers. Barycentric weights
//!   are perspective-corrected with the vertices' clip `w` and interpolate the
//!   eye-space position and normal. The hit is kept only if its depth lies between
//!   the near and far planes (per-pixel clipping). Triangles with a vertex behind the
//!   eye (`w ≤ 0`) or outside the guard band are not hit (documented cull: the
//!   rasterizer clips them instead). Back faces are skipped when the scene culls
//!   them. Each mesh is first tested against its screen bounding box.
//! * Spheres and planes: analytic, with the exact pixel-centre ray.
//!
//! # Shadow rays
//!
//! From the hit point, moved [`SHADOW_BIAS`] along the normal, towards the scene's
//! first light (any distance for a directional light, up to the light for a point
//! light). Meshes are tested with a fixed-point Möller–Trumbore test after a
//! bounding-sphere test per mesh. A shadowed point keeps that light's ambient
//! term; its diffuse and specular terms vanish (OpenGL semantics of a light whose
//! diffuse and specular colours are zero).
//!
//! # Numbers
//!
//! Eye-space positions are Q16.16 in `i32`, unit vectors Q2.30, products in `i64`
//! or `i128` with the bound written beside each. All integer: the same scene gives
//! the same pixels on every machine.

use crate::fixed::Q16_16;
use crate::geometry::Viewport;
use crate::light::{Light, LightKind, LightingSetup, Material};
use crate::math::{isqrt_u128, normalize_to_q30, Affine3, ClipMatrix, Vec3, ONE_Q30};
use crate::sampler::PixelFn;
use crate::scene::{Projection, Scene, MAX_OBJECTS};
use crate::specular::Specular;
use crate::target::PixelFormat;

/// Most analytic spheres in a [`RayScene`].
pub const MAX_SPHERES: usize = 8;
/// Most planes in a [`RayScene`].
pub const MAX_PLANES: usize = 4;
/// How far a shadow ray starts off the surface, along the normal: 2⁻⁹ world
/// units (Q16.16 raw 128). Smaller values let facets of a coarse mesh shadow
/// themselves near the terminator ("shadow acne").
pub const SHADOW_BIAS: i32 = 1 << 7;

/// An analytic sphere.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::Material;
/// use fixshade::raycast::Sphere;
/// let ball = Sphere { centre: [Q16_16::ZERO; 3], radius: Q16_16::ONE, material: Material::default() };
/// assert!(ball.radius > Q16_16::ZERO);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Sphere {
    /// Centre, world space.
    pub centre: Vec3,
    /// Radius, > 0 (a sphere of radius ≤ 0 is never hit).
    pub radius: Q16_16,
    /// Material.
    pub material: Material,
}

/// An infinite plane through `point` with normal `normal` (both sides are lit as
/// the side facing the ray).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::Material;
/// use fixshade::raycast::Plane;
/// // The floor y = -1.
/// let floor = Plane {
///     point: [Q16_16::ZERO, Q16_16::from_int(-1), Q16_16::ZERO],
///     normal: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
///     material: Material::default(),
/// };
/// assert_eq!(floor.normal[1], Q16_16::ONE);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Plane {
    /// A point of the plane, world space.
    pub point: Vec3,
    /// Normal, any non-zero length (a zero normal makes the plane invisible).
    pub normal: Vec3,
    /// Material.
    pub material: Material,
}

/// What the ray caster draws: the scene (camera, lights, meshes) plus analytic
/// spheres and planes.
///
/// ```
/// use fixshade::raycast::RayScene;
/// # let scene = fixshade::doc_support::scene();
/// // The scene's mesh objects only, no analytic primitives, no shadows.
/// let rs = RayScene { scene: &scene, spheres: &[], planes: &[], shadows: false };
/// assert_eq!(rs.triangle_count(), 1);
/// ```
#[derive(Copy, Clone, Debug)]
pub struct RayScene<'s, 'a> {
    /// Camera, lights and mesh objects.
    pub scene: &'s Scene<'a>,
    /// Spheres (at most [`MAX_SPHERES`]).
    pub spheres: &'s [Sphere],
    /// Planes (at most [`MAX_PLANES`]).
    pub planes: &'s [Plane],
    /// Cast shadow rays towards the first light.
    pub shadows: bool,
}

/// Why a ray caster could not be prepared.
///
/// ```
/// use fixshade::specular::BlinnExact;
/// use fixshade::raycast::{Caster, RayError, RayScene};
/// # let scene = fixshade::doc_support::scene();
/// let rs = RayScene { scene: &scene, spheres: &[], planes: &[], shadows: false };
/// // The scene has 3 vertices; an empty cache is refused with the size it needs.
/// let err = Caster::<BlinnExact>::prepare(rs, 32, 32, &mut [], &mut []).err();
/// assert_eq!(err, Some(RayError::CacheTooSmall { needed: 3 }));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum RayError {
    /// Width or height outside 1..=4096.
    BadSize,
    /// The vertex cache holds fewer entries than the scene's vertices.
    CacheTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// The box buffer holds fewer entries than the scene's triangles.
    BoxesTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// The camera's eye equals its target, or `up` is parallel to the view.
    BadView,
    /// The projection parameters are invalid.
    BadProjection,
    /// An object's model matrix is singular.
    SingularModel {
        /// The object's index.
        object: usize,
    },
    /// More than [`MAX_SPHERES`] spheres or [`MAX_PLANES`] planes.
    TooManyPrimitives,
}

impl core::fmt::Display for RayError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RayError::BadSize => f.write_str("frame width and height must be 1..=4096"),
            RayError::CacheTooSmall { needed } => {
                write!(f, "vertex cache too small: {needed} entries needed")
            }
            RayError::BoxesTooSmall { needed } => {
                write!(f, "triangle box buffer too small: {needed} entries needed")
            }
            RayError::BadView => f.write_str("camera eye equals target or up is parallel"),
            RayError::BadProjection => f.write_str("invalid projection parameters"),
            RayError::SingularModel { object } => {
                write!(f, "object {object} has a singular model matrix")
            }
            RayError::TooManyPrimitives => f.write_str("at most 8 spheres and 4 planes"),
        }
    }
}

/// A mesh vertex in eye space, prepared once per frame.
///
/// ```
/// use fixshade::raycast::RayVertex;
/// // Caller-owned per-vertex storage of the caster, one entry per scene vertex.
/// let cache = [RayVertex::default(); 3];
/// assert_eq!(cache[0].w, 0); // not yet prepared: no ray can hit it
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct RayVertex {
    /// Eye-space position, Q16.16.
    pub eye: [i32; 3],
    /// Eye-space unit normal, Q2.30.
    pub normal: [i32; 3],
    /// Screen position, Q12.4 (valid only if `w > 0`).
    pub screen: [i32; 2],
    /// Clip `w` for perspective correction, Q16.16 (`−z` for a perspective camera,
    /// 1 for an orthographic one); 0 marks a vertex no primary ray can hit.
    pub w: i32,
}

/// The pixels a mesh triangle may cover for primary rays: columns `x0..=x1`, rows
/// `y0..=y1` (empty when `x0 > x1`: back-facing with culling on, zero area, or a
/// vertex no primary ray can hit). Scanning these 8-byte boxes is what a primary ray
/// pays per triangle that is not near its pixel.
///
/// ```
/// use fixshade::raycast::TriBox;
/// // Caller-owned, one per mesh triangle (`RayScene::triangle_count`); 8 bytes each.
/// let boxes = [TriBox::default(); 4];
/// assert_eq!(core::mem::size_of_val(&boxes), 32);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TriBox {
    x0: i16,
    y0: i16,
    x1: i16,
    y1: i16,
}

impl Default for TriBox {
    /// An empty box.
    fn default() -> Self {
        TriBox {
            x0: 1,
            y0: 1,
            x1: 0,
            y1: 0,
        }
    }
}

impl RayScene<'_, '_> {
    /// Triangles of all meshes: the size of the box buffer of [`Caster::prepare`].
    pub fn triangle_count(&self) -> usize {
        self.scene
            .objects
            .iter()
            .map(|o| o.mesh.triangles().len())
            .sum()
    }
}

/// A mesh object as the caster sees it.
#[derive(Copy, Clone, Debug, Default)]
struct MeshInfo {
    offset: usize,
    tri_offset: usize,
    /// Screen bounding box of the hittable vertices, Q12.4: x0, y0, x1, y1.
    bbox: [i32; 4],
    /// Eye-space bounding sphere: centre Q16.16, radius Q16.16 (i64).
    centre: [i64; 3],
    radius: i64,
}

/// Eye-space sphere.
#[derive(Copy, Clone, Debug, Default)]
struct EyeSphere {
    c: [i64; 3],
    r: i64,
}

/// Eye-space plane: unit normal Q2.30, `d = n·X` for points X on it, Q16.16.
#[derive(Copy, Clone, Debug, Default)]
struct EyePlane {
    n: [i32; 3],
    d: i64,
    valid: bool,
}

/// The first light in eye space, for shadow rays.
#[derive(Copy, Clone, Debug)]
enum ShadowLight {
    None,
    /// Unit direction towards the light, Q2.30.
    Directional([i32; 3]),
    /// Position, Q16.16.
    Point([i64; 3]),
}

/// What a surface hit is on.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Surface {
    Mesh(usize),
    Sphere(usize),
    Plane(usize),
}

/// The nearest hit along a primary ray.
#[derive(Copy, Clone, Debug)]
struct Hit {
    /// Depth −z, Q16.16.
    depth: i64,
    /// Eye-space point, Q16.16.
    p: [i64; 3],
    /// Unit normal facing the viewer side it was hit from, Q2.30.
    n: [i32; 3],
    what: Surface,
}

/// The lighting of one surface: lit, and with the first light shadowed.
struct SurfaceLight<S: Specular> {
    lit: LightingSetup<S>,
    shadowed: LightingSetup<S>,
}

/// Everything the per-pixel ray cast needs, prepared once per frame.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{Material};
/// use fixshade::specular::BlinnExact;
/// use fixshade::raycast::{Caster, RayScene, RayVertex, Sphere, TriBox};
/// # let scene = fixshade::doc_support::scene();
/// // A unit sphere in front of the scene's triangle, casting a shadow onto it.
/// let spheres = [Sphere {
///     centre: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE],
///     radius: Q16_16::from_ratio(1, 2),
///     material: Material::default(),
/// }];
/// let rs = RayScene { scene: &scene, spheres: &spheres, planes: &[], shadows: true };
/// let mut cache = [RayVertex::default(); 3];
/// let mut boxes = [TriBox::default(); 1];
/// let caster = Caster::<BlinnExact>::prepare(rs, 32, 32, &mut cache, &mut boxes).unwrap();
/// assert!(caster.trace(16, 16).is_some()); // the sphere, in the middle
/// assert!(caster.trace(0, 0).is_none()); // nothing in the corner
/// ```
pub struct Caster<'s, 'a, 'c, S: Specular> {
    rs: RayScene<'s, 'a>,
    cache: &'c [RayVertex],
    boxes: &'c [TriBox],
    meshes: heapless::Vec<MeshInfo, MAX_OBJECTS>,
    spheres: heapless::Vec<EyeSphere, MAX_SPHERES>,
    planes: heapless::Vec<EyePlane, MAX_PLANES>,
    lights: heapless::Vec<SurfaceLight<S>, { MAX_OBJECTS + MAX_SPHERES + MAX_PLANES }>,
    shadow: ShadowLight,
    width: u32,
    height: u32,
    ortho: bool,
    /// Projection entries p00, p11, p03, p13 (Q32.32) for the pixel rays.
    p00: i64,
    p11: i64,
    p03: i64,
    p13: i64,
    /// Near and far depths, Q16.16.
    near: i64,
    far: i64,
}

/// Q16.16 of a Q32.32 value, rounded.
fn q32_to_q16(v: i64) -> i64 {
    (v + (1 << 15)) >> 16
}

/// Dot product of a Q2.30 vector and an `i64` vector (any format F), in F:
/// products < 2³¹·2⁶³ fit i128.
fn dot30(a: [i32; 3], b: [i64; 3]) -> i128 {
    (a[0] as i128 * b[0] as i128 + a[1] as i128 * b[1] as i128 + a[2] as i128 * b[2] as i128) >> 30
}

fn sub3(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `o + t·d` for Q16.16 `o`, Q16.16 `t` < 2⁴⁰ and Q2.30 `d`: |t·d| < 2⁷¹ in i128,
/// shifted back to Q16.16 (< 2⁴¹).
fn along(o: [i64; 3], d: [i32; 3], t: i64) -> [i64; 3] {
    core::array::from_fn(|i| o[i] + ((t as i128 * d[i] as i128) >> 30) as i64)
}

/// Rays through pixel centres never go beyond this ray parameter (Q16.16, 2²⁴
/// world units); farther hits are treated as misses, which keeps every product
/// below in range.
const T_MAX: i64 = 1 << 40;

impl<'s, 'a, 'c, S: Specular> Caster<'s, 'a, 'c, S> {
    /// Prepares a `width × height` frame of `rs`. `cache` must hold
    /// `rs.scene.vertex_count()` vertices and `boxes` [`RayScene::triangle_count`]
    /// boxes.
    pub fn prepare(
        rs: RayScene<'s, 'a>,
        width: u32,
        height: u32,
        cache: &'c mut [RayVertex],
        boxes: &'c mut [TriBox],
    ) -> Result<Self, RayError> {
        if width == 0 || width > 4096 || height == 0 || height > 4096 {
            return Err(RayError::BadSize);
        }
        if rs.spheres.len() > MAX_SPHERES || rs.planes.len() > MAX_PLANES {
            return Err(RayError::TooManyPrimitives);
        }
        let scene = rs.scene;
        let needed = scene.vertex_count();
        if cache.len() < needed {
            return Err(RayError::CacheTooSmall { needed });
        }
        let needed = rs.triangle_count();
        if boxes.len() < needed {
            return Err(RayError::BoxesTooSmall { needed });
        }
        let view = scene.camera.view().ok_or(RayError::BadView)?;
        let proj = scene
            .camera
            .projection_matrix(width, height)
            .ok_or(RayError::BadProjection)?;
        let (ortho, near, far) = match scene.camera.projection {
            Projection::Perspective { near, far, .. } => (false, near, far),
            Projection::Orthographic { near, far, .. } => (true, near, far),
        };
        let vp = Viewport { width, height };
        let mut lights = heapless::Vec::new();
        let mut shadowed_lights: heapless::Vec<Light, { crate::light::MAX_LIGHTS }> =
            scene.lights.clone();
        if let Some(l) = shadowed_lights.first_mut() {
            l.diffuse = [Q16_16::ZERO; 3];
            l.specular = [Q16_16::ZERO; 3];
        }
        let surface = |m: &Material| SurfaceLight {
            lit: LightingSetup::<S>::new(
                &scene.lights,
                &view,
                m,
                scene.global_ambient,
                scene.local_viewer,
            ),
            shadowed: LightingSetup::<S>::new(
                &shadowed_lights,
                &view,
                m,
                scene.global_ambient,
                scene.local_viewer,
            ),
        };

        let mut meshes = heapless::Vec::new();
        let mut offset = 0;
        let mut tri_offset = 0;
        for (i, obj) in scene.objects.iter().enumerate() {
            let mv = view.mul(&obj.placement.matrix());
            let clip =
                ClipMatrix::new(&proj.mul(&mv)).ok_or(RayError::SingularModel { object: i })?;
            let aff = Affine3::new(&mv).ok_or(RayError::SingularModel { object: i })?;
            let mesh = &obj.mesh;
            let out = &mut cache[offset..offset + mesh.positions().len()];
            let mut bbox = [i32::MAX, i32::MAX, i32::MIN, i32::MIN];
            let mut lo = [i64::MAX; 3];
            let mut hi = [i64::MIN; 3];
            let nm = &aff.normal;
            for ((o, p), n) in out.iter_mut().zip(mesh.positions()).zip(mesh.normals()) {
                let eye = aff.point(p);
                let nv = n.map(|c| c.to_bits() as i64);
                // Entries < 2^31, components < 2^15: sums of three < 2^48.
                let ne: [i64; 3] = core::array::from_fn(|r| {
                    nm[r][0] as i64 * nv[0] + nm[r][1] as i64 * nv[1] + nm[r][2] as i64 * nv[2]
                });
                let normal = normalize_to_q30(ne).unwrap_or([0, 0, ONE_Q30]);
                let c = clip.transform(p);
                // The screen position does not depend on z: project with z = 0 so
                // vertices beyond near/far keep their position (depth is clipped
                // per pixel instead).
                let screen = vp.project([c[0], c[1], 0, c[3]]);
                let w = if ortho { 1 << 16 } else { -eye[2] };
                let (screen, w) = match screen {
                    Some((x, y, _)) if w > 0 => ([x, y], w),
                    _ => ([0, 0], 0),
                };
                if w > 0 {
                    bbox = [
                        bbox[0].min(screen[0]),
                        bbox[1].min(screen[1]),
                        bbox[2].max(screen[0]),
                        bbox[3].max(screen[1]),
                    ];
                }
                for k in 0..3 {
                    lo[k] = lo[k].min(eye[k] as i64);
                    hi[k] = hi[k].max(eye[k] as i64);
                }
                *o = RayVertex {
                    eye,
                    normal,
                    screen,
                    w,
                };
            }
            // Bounding sphere: the box centre and the farthest vertex (|d| < 2^33,
            // squares summed in u128).
            let centre: [i64; 3] = core::array::from_fn(|k| {
                if lo[k] > hi[k] {
                    0
                } else {
                    (lo[k] + hi[k]) >> 1
                }
            });
            let mut r2: u128 = 0;
            for v in out.iter() {
                let d = sub3(v.eye.map(|c| c as i64), centre);
                let s: u128 = d.iter().map(|c| (*c as i128 * *c as i128) as u128).sum();
                r2 = r2.max(s);
            }
            let radius = isqrt_u128(r2) as i64 + 2;
            let tb = &mut boxes[tri_offset..tri_offset + mesh.triangles().len()];
            for (b, tri) in tb.iter_mut().zip(mesh.triangles()) {
                *b = tri_box(
                    &tri.map(|i| out[i as usize]),
                    scene.cull_back,
                    width,
                    height,
                );
            }
            let _ = meshes.push(MeshInfo {
                offset,
                tri_offset,
                bbox,
                centre,
                radius,
            });
            let _ = lights.push(surface(&obj.material));
            offset += mesh.positions().len();
            tri_offset += mesh.triangles().len();
        }
        let mut spheres = heapless::Vec::new();
        for s in rs.spheres {
            let c = view.transform_point(s.centre).map(q32_to_q16);
            let _ = spheres.push(EyeSphere {
                c,
                r: s.radius.to_bits() as i64,
            });
            let _ = lights.push(surface(&s.material));
        }
        let mut planes = heapless::Vec::new();
        for p in rs.planes {
            let n = normalize_to_q30(view.transform_dir(p.normal));
            let q = view.transform_point(p.point).map(q32_to_q16);
            let plane = match n {
                Some(n) => EyePlane {
                    n,
                    d: dot30(n, q) as i64,
                    valid: true,
                },
                None => EyePlane::default(),
            };
            let _ = planes.push(plane);
            let _ = lights.push(surface(&p.material));
        }
        let shadow = match scene.lights.first() {
            Some(l) if rs.shadows => match l.kind {
                LightKind::Directional { direction } => {
                    normalize_to_q30(view.transform_dir(direction))
                        .map_or(ShadowLight::None, ShadowLight::Directional)
                }
                LightKind::Point { position, .. } => {
                    ShadowLight::Point(view.transform_point(position).map(q32_to_q16))
                }
            },
            _ => ShadowLight::None,
        };
        Ok(Caster {
            rs,
            cache,
            boxes,
            meshes,
            spheres,
            planes,
            lights,
            shadow,
            width,
            height,
            ortho,
            p00: proj.m[0][0],
            p11: proj.m[1][1],
            p03: proj.m[0][3],
            p13: proj.m[1][3],
            near: near.to_bits() as i64,
            far: far.to_bits() as i64,
        })
    }

    /// The eye-space ray through the centre of pixel `(x, y)`: origin Q16.16 and
    /// unit direction Q2.30.
    ///
    /// NDC `x_n = (2x + 1 − W)/W`; perspective: direction `(x_n/p00, y_n/p11, −1)`;
    /// orthographic: origin `((x_n − p03)/p00, (y_n − p13)/p11, 0)`, direction −z.
    /// The numerators `(2x + 1 − W)·2⁶⁴` < 2⁷⁸ and the denominators `W·p` fit i128.
    fn pixel_ray(&self, x: u32, y: u32) -> ([i64; 3], [i32; 3]) {
        let (w, h) = (self.width as i128, self.height as i128);
        let xn = 2 * x as i128 + 1 - w; // x_n · W
        let yn = h - 2 * y as i128 - 1; // y_n · H
        let div = |n: i128, d: i128| if d == 0 { 0 } else { n / d };
        if self.ortho {
            // Q16.16: (x_n − p03)/p00 = (xn·2^32 − p03·W) · 2^16 / (W·p00).
            let ox = div(
                ((xn << 32) - self.p03 as i128 * w) << 16,
                w * self.p00 as i128,
            );
            let oy = div(
                ((yn << 32) - self.p13 as i128 * h) << 16,
                h * self.p11 as i128,
            );
            ([ox as i64, oy as i64, 0], [0, 0, -ONE_Q30])
        } else {
            // Q32.32: x_n / p00 = xn · 2^64 / (W · p00).
            let dx = div(xn << 64, w * self.p00 as i128);
            let dy = div(yn << 64, h * self.p11 as i128);
            let clamp = |v: i128| v.clamp(-(1i128 << 62), 1 << 62) as i64;
            let d =
                normalize_to_q30([clamp(dx), clamp(dy), -(1i64 << 32)]).unwrap_or([0, 0, -ONE_Q30]);
            ([0, 0, 0], d)
        }
    }

    /// The lit colour of pixel `(x, y)`, Q16.16 per channel in [0, 1], or `None`
    /// where the ray hits nothing.
    pub fn trace(&self, x: u32, y: u32) -> Option<[i32; 3]> {
        let (o, d) = self.pixel_ray(x, y);
        let mut best: Option<Hit> = None;
        let mut consider = |h: Hit| {
            if h.depth >= self.near && h.depth <= self.far && best.is_none_or(|b| h.depth < b.depth)
            {
                best = Some(h);
            }
        };
        for (i, s) in self.spheres.iter().enumerate() {
            for t in sphere_roots(o, d, s).into_iter().flatten() {
                let p = along(o, d, t);
                let depth = -p[2];
                if depth < self.near || depth > self.far {
                    continue;
                }
                let n = normalize_to_q30(sub3(p, s.c)).unwrap_or([0, 0, ONE_Q30]);
                consider(Hit {
                    depth,
                    p,
                    n,
                    what: Surface::Sphere(i),
                });
                break;
            }
        }
        for (i, pl) in self.planes.iter().enumerate() {
            if let Some(t) = plane_hit(o, d, pl) {
                let p = along(o, d, t);
                let facing = dot30(pl.n, d.map(|c| c as i64)) < 0;
                let n = if facing { pl.n } else { pl.n.map(|c| -c) };
                consider(Hit {
                    depth: -p[2],
                    p,
                    n,
                    what: Surface::Plane(i),
                });
            }
        }
        let px = 16 * x as i32 + 8;
        let py = 16 * y as i32 + 8;
        for (mi, (m, obj)) in self
            .meshes
            .iter()
            .zip(self.rs.scene.objects.iter())
            .enumerate()
        {
            if px < m.bbox[0] || px > m.bbox[2] || py < m.bbox[1] || py > m.bbox[3] {
                continue;
            }
            let verts = &self.cache[m.offset..m.offset + obj.mesh.positions().len()];
            let tris = obj.mesh.triangles();
            let boxes = &self.boxes[m.tri_offset..m.tri_offset + tris.len()];
            let (bx, by) = (x as i32, y as i32);
            for (tri, b) in tris.iter().zip(boxes) {
                if bx < b.x0 as i32 || bx > b.x1 as i32 || by < b.y0 as i32 || by > b.y1 as i32 {
                    continue;
                }
                let t = tri.map(|i| verts[i as usize]);
                if let Some(h) = self.triangle_hit(&t, px, py) {
                    consider(Hit {
                        what: Surface::Mesh(mi),
                        ..h
                    });
                }
            }
        }
        let hit = best?;
        let idx = match hit.what {
            Surface::Mesh(i) => i,
            Surface::Sphere(i) => self.meshes.len() + i,
            Surface::Plane(i) => self.meshes.len() + self.spheres.len() + i,
        };
        let sl = self.lights.get(idx)?;
        let p = hit
            .p
            .map(|c| c.clamp(i32::MIN as i64, i32::MAX as i64) as i32);
        let setup = if self.in_shadow(hit.p, hit.n) {
            &sl.shadowed
        } else {
            &sl.lit
        };
        Some(setup.shade(p, hit.n))
    }

    /// The primary hit of pixel centre `(px, py)` (Q12.4) on a triangle, with the
    /// perspective-correct eye position and normal.
    ///
    /// Bounds: screen coordinates are inside the guard band (|·| < 2¹⁶), so edge
    /// functions are below 2³⁵; `w` < 2³¹, products `e·w·w` < 2⁹⁷ in i128; the
    /// weights are then shifted below 2³⁰ so that `Σ q·eye` < 3·2⁶¹ fits i64.
    #[inline]
    fn triangle_hit(&self, t: &[RayVertex; 3], px: i32, py: i32) -> Option<Hit> {
        if t[0].w <= 0 || t[1].w <= 0 || t[2].w <= 0 {
            return None;
        }
        let (a, b, c) = (t[0].screen, t[1].screen, t[2].screen);
        if (px < a[0] && px < b[0] && px < c[0])
            || (px > a[0] && px > b[0] && px > c[0])
            || (py < a[1] && py < b[1] && py < c[1])
            || (py > a[1] && py > b[1] && py > c[1])
        {
            return None;
        }
        let area = crate::clip::signed_area((a[0], a[1]), (b[0], b[1]), (c[0], c[1]));
        if area == 0 || (self.rs.scene.cull_back && area > 0) {
            return None;
        }
        // Orient so the area is positive (y down); `ord` maps positions to vertices.
        let ord = if area < 0 { [0, 2, 1] } else { [0, 1, 2] };
        let v = ord.map(|i| t[i].screen);
        let mut e = [0i64; 3]; // e[i]: weight of vertex ord[(i + 2) % 3]
        for i in 0..3 {
            let (p, q) = (v[i], v[(i + 1) % 3]);
            let (dx, dy) = ((q[0] - p[0]) as i64, (q[1] - p[1]) as i64);
            let f = dx * (py - p[1]) as i64 - dy * (px - p[0]) as i64;
            let top_left = dy < 0 || (dy == 0 && dx > 0);
            if f < 0 || (f == 0 && !top_left) {
                return None;
            }
            e[i] = f;
        }
        // Weight of vertex ord[k] is e[(k + 1) % 3].
        let mut wgt = [0i64; 3];
        for k in 0..3 {
            wgt[ord[k]] = e[(k + 1) % 3];
        }
        let ws = [t[0].w as i128, t[1].w as i128, t[2].w as i128];
        let q128 = [
            wgt[0] as i128 * ws[1] * ws[2],
            wgt[1] as i128 * ws[0] * ws[2],
            wgt[2] as i128 * ws[0] * ws[1],
        ];
        let max = q128[0].max(q128[1]).max(q128[2]);
        if max <= 0 {
            return None;
        }
        let bits = 128 - max.leading_zeros() as i32;
        let shift = (bits - 30).max(0);
        let q = q128.map(|v| (v >> shift) as i64);
        let sum = q[0] + q[1] + q[2];
        if sum <= 0 {
            return None;
        }
        let p: [i64; 3] = core::array::from_fn(|k| {
            let s =
                q[0] * t[0].eye[k] as i64 + q[1] * t[1].eye[k] as i64 + q[2] * t[2].eye[k] as i64;
            s.div_euclid(sum)
        });
        let depth = -p[2];
        if depth < self.near || depth > self.far {
            return None;
        }
        let n: [i64; 3] = core::array::from_fn(|k| {
            q[0] * t[0].normal[k] as i64
                + q[1] * t[1].normal[k] as i64
                + q[2] * t[2].normal[k] as i64
        });
        let n = normalize_to_q30(n).unwrap_or([0, 0, ONE_Q30]);
        Some(Hit {
            depth,
            p,
            n,
            what: Surface::Mesh(0),
        })
    }

    /// True if the first light is blocked as seen from `p` (normal `n`).
    fn in_shadow(&self, p: [i64; 3], n: [i32; 3]) -> bool {
        let o: [i64; 3] =
            core::array::from_fn(|k| p[k] + ((n[k] as i64 * SHADOW_BIAS as i64) >> 30));
        let (d, t_max) = match self.shadow {
            ShadowLight::None => return false,
            ShadowLight::Directional(l) => (l, T_MAX),
            ShadowLight::Point(lp) => {
                let to = sub3(lp, o);
                let Some(d) = normalize_to_q30(to) else {
                    return false;
                };
                let len: u128 = to.iter().map(|c| (*c as i128 * *c as i128) as u128).sum();
                (d, isqrt_u128(len) as i64)
            }
        };
        // A light below the surface cannot light it: no ray needed.
        if dot30(n, d.map(|c| c as i64)) <= 0 {
            return false;
        }
        let before = |t: i64| t > 0 && t < t_max;
        if self
            .spheres
            .iter()
            .any(|s| sphere_roots(o, d, s).into_iter().flatten().any(before))
        {
            return true;
        }
        if self
            .planes
            .iter()
            .any(|pl| plane_hit(o, d, pl).is_some_and(before))
        {
            return true;
        }
        for (m, obj) in self.meshes.iter().zip(self.rs.scene.objects.iter()) {
            let bs = EyeSphere {
                c: m.centre,
                r: m.radius,
            };
            let [t0, t1] = sphere_roots(o, d, &bs);
            // Inside the bounding sphere t0 is None and t1 > 0.
            if t0.is_none() && t1.is_none() {
                continue;
            }
            let verts = &self.cache[m.offset..m.offset + obj.mesh.positions().len()];
            for tri in obj.mesh.triangles() {
                let t = tri.map(|i| verts[i as usize].eye.map(|c| c as i64));
                if blocks(o, d, &t, t_max) {
                    return true;
                }
            }
        }
        false
    }
}

/// The pixel box of a triangle for primary rays (see [`TriBox`]): pixels whose
/// centre `16k + 8` lies within the triangle's Q12.4 bounds, clamped to the frame.
fn tri_box(t: &[RayVertex; 3], cull: bool, width: u32, height: u32) -> TriBox {
    if t.iter().any(|v| v.w <= 0) {
        return TriBox::default();
    }
    let (a, b, c) = (t[0].screen, t[1].screen, t[2].screen);
    let area = crate::clip::signed_area((a[0], a[1]), (b[0], b[1]), (c[0], c[1]));
    if area == 0 || (cull && area > 0) {
        return TriBox::default();
    }
    // First centre ≥ lo: ⌈(lo − 8)/16⌉; last centre ≤ hi: ⌊(hi − 8)/16⌋. Screen
    // coordinates are inside the guard band (|·| < 2¹⁶), the frame ≤ 4096.
    let first = |lo: i32| (lo - 8 + 15).div_euclid(16);
    let last = |hi: i32| (hi - 8).div_euclid(16);
    let x0 = first(a[0].min(b[0]).min(c[0])).max(0);
    let x1 = last(a[0].max(b[0]).max(c[0])).min(width as i32 - 1);
    let y0 = first(a[1].min(b[1]).min(c[1])).max(0);
    let y1 = last(a[1].max(b[1]).max(c[1])).min(height as i32 - 1);
    if x0 > x1 || y0 > y1 {
        return TriBox::default();
    }
    TriBox {
        x0: x0 as i16,
        y0: y0 as i16,
        x1: x1 as i16,
        y1: y1 as i16,
    }
}

/// The ray parameters (Q16.16, ascending, each in (0, [`T_MAX`])) where the ray
/// `o + t·d` (unit `d`) meets the sphere; `None` for roots outside that range.
///
/// `oc = c − o` < 2⁴² (Q16.16), `b = d·oc` < 2⁴³, `b²` and `|oc|²` < 2⁸⁶ in
/// i128 (Q32.32); the root of the discriminant is Q16.16.
fn sphere_roots(o: [i64; 3], d: [i32; 3], s: &EyeSphere) -> [Option<i64>; 2] {
    if s.r <= 0 {
        return [None, None];
    }
    let oc = sub3(s.c, o);
    let b = dot30(d, oc);
    let c: i128 =
        oc.iter().map(|v| *v as i128 * *v as i128).sum::<i128>() - s.r as i128 * s.r as i128;
    let disc = b * b - c;
    if disc < 0 {
        return [None, None];
    }
    let root = isqrt_u128(disc as u128) as i128;
    let ok = |t: i128| (t > 0 && t < T_MAX as i128).then_some(t as i64);
    [ok(b - root), ok(b + root)]
}

/// The ray parameter (Q16.16) where the ray meets the plane, if in (0, [`T_MAX`]);
/// `None` for a ray parallel to the plane. `n·d` is Q2.30, `d − n·o` Q16.16 <
/// 2⁴³, so `(d − n·o)·2³⁰` < 2⁷³ in i128.
fn plane_hit(o: [i64; 3], d: [i32; 3], pl: &EyePlane) -> Option<i64> {
    if !pl.valid {
        return None;
    }
    let nd = dot30(pl.n, d.map(|c| c as i64));
    if nd == 0 {
        return None;
    }
    let num = pl.d as i128 - dot30(pl.n, o);
    let t = (num << 30) / nd;
    (t > 0 && t < T_MAX as i128).then_some(t as i64)
}

/// Möller–Trumbore: does the ray `o + t·d` (unit `d`, Q2.30) meet the triangle
/// `v` (Q16.16) at some `0 < t < t_max`? Both faces block.
///
/// Every product is an `i64 × i64 → i128` widening multiply. Edges and `o − v0`
/// are below 2³³ (Q16.16); `p = d × e2` is Q16.16 < 2³⁵ (fits i64); `det = e1·p`
/// and `u = s·p` are Q32.32 < 2⁷⁰; `q = s × e1` is rounded down to Q16.16
/// (< 2⁵¹, fits i64); `v = d·q` and `t·det = e2·q` are Q32.32 < 2⁸⁶. The final
/// comparison multiplies below 2⁸⁶ by 2¹⁶ and 2⁴⁰ by 2⁷⁰: all within i128.
fn blocks(o: [i64; 3], d: [i32; 3], v: &[[i64; 3]; 3], t_max: i64) -> bool {
    let m = |a: i64, b: i64| a as i128 * b as i128;
    let e1 = sub3(v[1], v[0]);
    let e2 = sub3(v[2], v[0]);
    let d = d.map(|c| c as i64);
    // d × e2: Q2.30 · Q16.16 → Q16.16 after >> 30.
    let p = [
        ((m(d[1], e2[2]) - m(d[2], e2[1])) >> 30) as i64,
        ((m(d[2], e2[0]) - m(d[0], e2[2])) >> 30) as i64,
        ((m(d[0], e2[1]) - m(d[1], e2[0])) >> 30) as i64,
    ];
    let mut det = m(e1[0], p[0]) + m(e1[1], p[1]) + m(e1[2], p[2]);
    if det == 0 {
        return false;
    }
    let s = sub3(o, v[0]);
    let mut u = m(s[0], p[0]) + m(s[1], p[1]) + m(s[2], p[2]);
    let q = [
        ((m(s[1], e1[2]) - m(s[2], e1[1])) >> 16) as i64,
        ((m(s[2], e1[0]) - m(s[0], e1[2])) >> 16) as i64,
        ((m(s[0], e1[1]) - m(s[1], e1[0])) >> 16) as i64,
    ];
    // d·q: Q2.30 · Q16.16 → Q32.32 after >> 14; e2·q: Q16.16 · Q16.16 = Q32.32.
    let mut vv = (m(d[0], q[0]) + m(d[1], q[1]) + m(d[2], q[2])) >> 14;
    let mut tn = m(e2[0], q[0]) + m(e2[1], q[1]) + m(e2[2], q[2]);
    if det < 0 {
        det = -det;
        u = -u;
        vv = -vv;
        tn = -tn;
    }
    // t = tn / det in Q16.16 units: 0 < t < t_max  ⇔  0 < tn·2^16 < t_max·det.
    u >= 0 && vv >= 0 && u + vv <= det && tn > 0 && (tn << 16) < t_max as i128 * det
}

/// The caster as a [`PixelFn`] for the target format `P`: lit colours rounded to
/// `P`'s channel integers, `background` (channel integers) where nothing is hit.
///
/// ```
/// use fixshade::specular::BlinnExact;
/// use fixshade::raycast::{Caster, RayPixels, RayScene, RayVertex, TriBox};
/// use fixshade::sampler::{fill_row, Threshold, SEED_K_Q8};
/// use fixshade::target::Rgb888;
/// # let scene = fixshade::doc_support::scene();
/// let rs = RayScene { scene: &scene, spheres: &[], planes: &[], shadows: false };
/// let (mut cache, mut boxes) = ([RayVertex::default(); 3], [TriBox::default(); 1]);
/// let caster = Caster::<BlinnExact>::prepare(rs, 32, 32, &mut cache, &mut boxes).unwrap();
/// // Row 20 with segments of 8 pixels: far fewer rays than pixels.
/// let mut px = RayPixels::<_, Rgb888>::new(&caster, [0, 0, 40]);
/// let mut row = [[0u32; 3]; 32];
/// let rays = fill_row(&mut px, 20, 8, Threshold::from_q8(SEED_K_Q8, [255; 3]), &mut row);
/// assert!(rays < 32);
/// assert_eq!(row[0], [0, 0, 40]); // background left of the triangle
/// ```
pub struct RayPixels<'r, 's, 'a, 'c, S: Specular, P: PixelFormat> {
    caster: &'r Caster<'s, 'a, 'c, S>,
    background: [u32; 3],
    _format: core::marker::PhantomData<P>,
}

impl<'r, 's, 'a, 'c, S: Specular, P: PixelFormat> RayPixels<'r, 's, 'a, 'c, S, P> {
    /// Wraps a prepared caster.
    pub fn new(caster: &'r Caster<'s, 'a, 'c, S>, background: [u32; 3]) -> Self {
        RayPixels {
            caster,
            background,
            _format: core::marker::PhantomData,
        }
    }
}

/// Rounds a Q16.16 colour in [0, 1] to channel integers of `P`: `⌊c·M + ½⌋`
/// (`c·M` < 2¹⁶·2⁸); grey is `(77r + 150g + 29b)/256` first (< 2²⁴·2⁸ in i64).
///
/// ```
/// use fixshade::raycast::to_channels;
/// use fixshade::target::{Rgb565Le, Rgb888};
/// assert_eq!(to_channels::<Rgb888>([1 << 16, 1 << 15, 0]), [255, 128, 0]);
/// assert_eq!(to_channels::<Rgb565Le>([1 << 16, 1 << 15, 0]), [31, 32, 0]);
/// ```
pub fn to_channels<P: PixelFormat>(c: [i32; 3]) -> [u32; 3] {
    let r = |v: i64, m: u32| ((v * m as i64 + (1 << 15)) >> 16).clamp(0, m as i64) as u32;
    if P::GRAY {
        let y = (77 * c[0] as i64 + 150 * c[1] as i64 + 29 * c[2] as i64 + 128) >> 8;
        let g = r(y, P::MAX[0]);
        [g, g, g]
    } else {
        [
            r(c[0] as i64, P::MAX[0]),
            r(c[1] as i64, P::MAX[1]),
            r(c[2] as i64, P::MAX[2]),
        ]
    }
}

impl<S: Specular, P: PixelFormat> PixelFn for RayPixels<'_, '_, '_, '_, S, P> {
    fn eval(&mut self, x: u32, y: u32) -> [u32; 3] {
        match self.caster.trace(x, y) {
            Some(c) => to_channels::<P>(c),
            None => self.background,
        }
    }
}
