//! The pipeline, end to end: vertex stage, clip & cull, rasterization.
//!
//! [`Frame::prepare`] runs the vertex stage once per frame: every vertex of every
//! object is transformed, projected and lit once (not once per triangle corner) into
//! a caller-owned cache of [`XfVertex`]. [`Frame::draw`] then rasterizes into any
//! [`Target`], as many times as needed: once for a framebuffer, or once per strip.
//!
//! ```
//! use fixshade::fixed::{Angle, Q16_16, Q2_14};
//! use fixshade::geometry::Mesh;
//! use fixshade::light::{Light, Material};
//! use fixshade::raster::span::Gradient;
//! use fixshade::render::{Frame, XfVertex};
//! use fixshade::scene::{Camera, Object, Placement, Projection, Scene};
//! use fixshade::target::{Framebuffer, Rgb565Le, Target};
//!
//! // One triangle facing the camera.
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
//!
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
//! scene
//!     .add_object(Object { mesh, placement: Placement::default(), material: Material::default() })
//!     .unwrap();
//!
//! let (w, h) = (32, 24);
//! let mut color = [0u16; 32 * 24];
//! let mut depth = [0xFFFFu16; 32 * 24];
//! let mut cache = [XfVertex::default(); 3];
//! let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), w, h).unwrap();
//! let frame = Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).unwrap();
//! let stats = frame.draw::<Gradient, _>(&mut fb).unwrap();
//! assert_eq!(stats.drawn, 1);
//! assert!(stats.pixels > 60, "{stats:?}");
//! ```

use core::marker::PhantomData;

use crate::clip::{clip_triangle, is_front, ClipVertex};
use crate::divide::{Divide, Exact};
use crate::fixed::Q16_16;
use crate::geometry::{normalize_clip, Viewport};
use crate::light::{BlinnExact, LightingSetup, Specular};
use crate::math::{mul_wide_16, normalize_to_q30, Affine3, ClipMatrix, Mat4, Vec3, ONE_Q30};
use crate::raster::perspective::{draw_phong_perspective, draw_triangle_perspective, Perspective};
use crate::raster::phong::{
    self, draw_phong_div, draw_phong_sampled, PhongFill, PhongVertex, Sampling,
};
use crate::raster::quadratic::draw_quadratic_div;
use crate::raster::span::{DepthMode, DepthTest, NoDepth, SpanMethod};
use crate::raster::span::{Gradient, WithDivide};
use crate::raster::{draw_in_guard, draw_triangle, ScreenVertex, GUARD};
use crate::scene::{Object, Scene, ShadingMode, MAX_OBJECTS};
use crate::shade::{Adaptive, Flat, Gouraud, Phong, PhongEvenOdd, Quadratic, Shading};
use crate::target::{to_channels, PixelFormat, Target};

mod adaptive;
pub mod bands;

pub use bands::{BandMemory, Binned};

/// A vertex after the vertex stage: its screen position, depth and lit colour in the
/// target's channel units, and flags.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// // The caller owns the vertex cache: one entry per scene vertex (16 bytes or so each).
/// let mut cache = vec![XfVertex::default(); scene.vertex_count()];
/// let frame = Frame::<Rgb565Le>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// # let _ = frame;
/// assert_eq!(cache.len(), 3);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct XfVertex {
    /// Screen vertex (position valid only without [`OUTSIDE`]; colour only with
    /// [`NEEDED`]).
    pub s: ScreenVertex,
    /// [`OUTSIDE`] and [`NEEDED`] bits.
    pub flags: u8,
}

/// Flag: the vertex lies outside the guard band or the depth range (its triangles go
/// through the clipper).
pub const OUTSIDE: u8 = 1;
/// Flag: some triangle that may be drawn uses the vertex, so it was lit.
pub const NEEDED: u8 = 2;

/// What to do with a triangle.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Class {
    /// Culled, zero-area, or entirely off the frame rows/columns.
    Skip,
    /// All vertices inside the guard band: rasterize directly.
    Draw,
    /// Some vertex outside: clip first.
    Clip,
}

/// Classifies a triangle by its vertex-stage output. `rows` are the frame rows a
/// target holds; a triangle entirely above, below, left or right of them is skipped.
#[inline]
fn classify(t: &[XfVertex; 3], cull: bool, vp: &Viewport, rows: core::ops::Range<i32>) -> Class {
    classify_refs([&t[0], &t[1], &t[2]], cull, vp, rows)
}

/// [`classify`] on references into the vertex cache (the hot loops read the three
/// vertices in place instead of copying them out first).
#[inline(always)]
fn classify_refs(
    t: [&XfVertex; 3],
    cull: bool,
    vp: &Viewport,
    rows: core::ops::Range<i32>,
) -> Class {
    if (t[0].flags | t[1].flags | t[2].flags) & OUTSIDE != 0 {
        return Class::Clip;
    }
    let (a, b, c) = (t[0].s, t[1].s, t[2].s);
    let area = crate::clip::signed_area((a.x, a.y), (b.x, b.y), (c.x, c.y));
    if area == 0 || (cull && area > 0) {
        return Class::Skip;
    }
    // Pixel centres at 16k + 8: a triangle whose max coordinate is below the first
    // centre, or whose min coordinate is past the last, covers nothing.
    let (x_min, x_max) = (a.x.min(b.x).min(c.x), a.x.max(b.x).max(c.x));
    let (y_min, y_max) = (a.y.min(b.y).min(c.y), a.y.max(b.y).max(c.y));
    if x_max < 8
        || x_min > 16 * vp.width as i32 - 8
        || y_max < 16 * rows.start + 8
        || y_min > 16 * rows.end - 8
    {
        return Class::Skip;
    }
    Class::Draw
}

/// Why a frame could not be prepared or drawn.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// let err = Frame::<Gray8>::prepare(&scene, 64, 48, &mut []).err();
/// assert_eq!(err, Some(RenderError::CacheTooSmall { needed: 3 }));
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Gray8>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let mut px = [0u8; 64 * 48];
/// let mut no_depth = Framebuffer::<Gray8>::new(&mut px, None, 64, 48).unwrap();
/// // The scene tests depth, the target has no depth buffer.
/// assert_eq!(frame.draw::<Gradient, _>(&mut no_depth), Err(RenderError::NoDepthBuffer));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum RenderError {
    /// The vertex cache holds fewer entries than the scene has vertices.
    CacheTooSmall {
        /// Entries needed ([`Scene::vertex_count`]).
        needed: usize,
    },
    /// Frame width or height is zero or above 4096.
    BadSize,
    /// The camera's view is undefined (eye = target, or up parallel to the view).
    BadView,
    /// The projection parameters are invalid (fovy, near, far).
    BadProjection,
    /// An object's model matrix is singular (scale 0).
    SingularModel {
        /// The object's index.
        object: usize,
    },
    /// The target's frame size differs from the prepared frame's.
    TargetSizeMismatch,
    /// The scene asks for a depth test but the target has no depth buffer.
    NoDepthBuffer,
}

impl core::fmt::Display for RenderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RenderError::CacheTooSmall { needed } => {
                write!(
                    f,
                    "vertex cache too small: the scene needs {needed} entries"
                )
            }
            RenderError::BadSize => f.write_str("frame width and height must be 1..=4096"),
            RenderError::BadView => {
                f.write_str("camera eye equals target, or up is parallel to the view direction")
            }
            RenderError::BadProjection => f.write_str("invalid projection (fovy, near or far)"),
            RenderError::SingularModel { object } => {
                write!(f, "object {object} has a singular model matrix (scale 0)")
            }
            RenderError::TargetSizeMismatch => {
                f.write_str("target frame size differs from the prepared frame")
            }
            RenderError::NoDepthBuffer => {
                f.write_str("the scene uses the depth test but the target has no depth buffer")
            }
        }
    }
}

/// What a draw call did.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Gray8>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let (mut px, mut z) = ([0u8; 64 * 48], [0xFFFFu16; 64 * 48]);
/// let st = frame.draw::<Gradient, _>(&mut Framebuffer::new(&mut px, Some(&mut z), 64, 48).unwrap()).unwrap();
/// assert_eq!((st.triangles, st.drawn, st.culled, st.clipped), (1, 1, 0, 0));
/// assert_eq!(st.pixels as usize, px.iter().filter(|&&p| p != 0).count());
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Triangles submitted.
    pub triangles: u32,
    /// Dropped as back faces, zero area, or outside the target.
    pub culled: u32,
    /// Went through the clipper.
    pub clipped: u32,
    /// Triangles rasterized (after clipping, fans count once per piece).
    pub drawn: u32,
    /// Pixels covered inside the target (before the depth test).
    pub pixels: u32,
    /// Triangles that asked for the quadratic surface but were drawn with Gouraud
    /// (those that went through the clipper: their pieces have no midpoint colours).
    pub fallback: u32,
    /// Per-pixel lighting evaluations of sampled Phong shading
    /// ([`Frame::draw_phong_sampled`]); 0 for every other path.
    pub evaluations: u32,
    /// Adaptive shading only: triangles (clipped pieces count once per triangle)
    /// that a highlight may reach and so were drawn with per-pixel lighting.
    pub per_pixel: u32,
    /// Bands drawn by walking every triangle again instead of from set-up records
    /// ([`Binned::draw_band`]: the band memory was too small, or the method or the
    /// shading has no records).
    pub rewalked: u32,
}

impl core::ops::AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.triangles += o.triangles;
        self.culled += o.culled;
        self.clipped += o.clipped;
        self.drawn += o.drawn;
        self.pixels += o.pixels;
        self.fallback += o.fallback;
        self.evaluations += o.evaluations;
        self.per_pixel += o.per_pixel;
        self.rewalked += o.rewalked;
    }
}

#[derive(Copy, Clone, Debug)]
struct Prepared {
    clip: ClipMatrix,
    offset: usize,
}

/// A frame whose vertex stage has run; draw it into one or more targets.
///
/// `Sp` is the specular model ([`BlinnExact`] unless prepared with
/// [`Frame::prepare_with`]); every shading mode uses it.
///
/// Quadratic and Phong shading light points inside the triangle at draw time.
/// Rather than keeping eye-space positions and normals per vertex (24 more bytes per
/// cache entry, paid on every path) or per-object lighting setups in the frame (about
/// 1 KB per object), the draw recomputes each object's model-view [`Affine3`] and
/// [`LightingSetup`] (a few dozen multiplies and 8 normalisations per object) and
/// takes positions and normals from the mesh: position through the affine map,
/// normal through the normal matrix, normalised. The model-view is a similarity
/// (rigid view, uniform scale), so a midpoint normal `normal_matrix·(n_a + n_b)`
/// normalised equals `normalize(n̂_a + n̂_b)` of the eye-space unit normals.
///
/// ```
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// // Prepare once (vertex stage), draw into as many targets as needed: here the top and
/// // bottom halves of a 64×48 frame from one 64×24 buffer.
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// assert_eq!(frame.size(), (64, 48));
/// let (mut px, mut z) = ([0u16; 64 * 24], [0u16; 64 * 24]);
/// let mut covered = 0;
/// for y0 in [0, 24] {
///     let mut strip = Strip::new(&mut px, Some(&mut z), 64, 48, y0, 24).unwrap();
///     strip.clear(0);
///     covered += frame.draw::<Gradient, _>(&mut strip).unwrap().pixels;
///     // ... send strip.color() to the display
/// }
/// assert!(covered > 300);
/// ```
pub struct Frame<'s, 'a, 'c, P: PixelFormat, Sp: Specular = BlinnExact> {
    scene: &'s Scene<'a>,
    cache: &'c [XfVertex],
    objects: heapless::Vec<Prepared, MAX_OBJECTS>,
    vp: Viewport,
    _format: PhantomData<(P, Sp)>,
}

impl<'s, 'a, 'c, P: PixelFormat> Frame<'s, 'a, 'c, P, BlinnExact> {
    /// Runs the vertex stage with exact Blinn specular ([`BlinnExact`]).
    pub fn prepare(
        scene: &'s Scene<'a>,
        width: u32,
        height: u32,
        cache: &'c mut [XfVertex],
    ) -> Result<Self, RenderError> {
        Self::prepare_with::<BlinnExact>(scene, width, height, cache)
    }

    /// Runs the vertex stage with the specular model `Sp`.
    pub fn prepare_with<Sp: Specular>(
        scene: &'s Scene<'a>,
        width: u32,
        height: u32,
        cache: &'c mut [XfVertex],
    ) -> Result<Frame<'s, 'a, 'c, P, Sp>, RenderError> {
        if width == 0 || width > 4096 || height == 0 || height > 4096 {
            return Err(RenderError::BadSize);
        }
        let needed = scene.vertex_count();
        if cache.len() < needed {
            return Err(RenderError::CacheTooSmall { needed });
        }
        let view = scene.camera.view().ok_or(RenderError::BadView)?;
        let proj = scene
            .camera
            .projection_matrix(width, height)
            .ok_or(RenderError::BadProjection)?;
        let vp = Viewport { width, height };
        let mut objects = heapless::Vec::new();
        let mut offset = 0;
        for (i, obj) in scene.objects.iter().enumerate() {
            let mv = view.mul(&obj.placement.matrix());
            let clip =
                ClipMatrix::new(&proj.mul(&mv)).ok_or(RenderError::SingularModel { object: i })?;
            let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
            let light = LightingSetup::<Sp>::new(
                &scene.lights,
                &view,
                &obj.material,
                scene.global_ambient,
                scene.local_viewer,
            );
            let mesh = &obj.mesh;
            let out = &mut cache[offset..offset + mesh.positions().len()];
            // 1. Transform and project every vertex once.
            for (o, p) in out.iter_mut().zip(mesh.positions()) {
                *o = match vp.project(clip.transform(p)) {
                    Some((x, y, z)) => XfVertex {
                        s: ScreenVertex { x, y, z, c: [0; 3] },
                        flags: 0,
                    },
                    None => XfVertex {
                        s: ScreenVertex::default(),
                        flags: OUTSIDE,
                    },
                };
            }
            // 2. Cull before lighting: only vertices of triangles that may be drawn
            //    are lit.
            for tri in mesh.triangles() {
                let t = tri.map(|i| &out[i as usize]);
                if classify_refs(t, scene.cull_back, &vp, 0..height as i32) != Class::Skip {
                    for i in tri {
                        out[*i as usize].flags |= NEEDED;
                    }
                }
            }
            // 3. Light the vertices that are needed (the eye-space position only
            //    where a point light or a local viewer reads it).
            let at = light.needs_position();
            for ((o, p), n) in out.iter_mut().zip(mesh.positions()).zip(mesh.normals()) {
                if o.flags & NEEDED == 0 {
                    continue;
                }
                let unit = eye_normal(&aff, n);
                let p = if at { aff.point(p) } else { [0; 3] };
                o.s.c = to_channels::<P>(light.shade(p, unit));
            }
            // Capacity equals the scene's object capacity.
            let _ = objects.push(Prepared { clip, offset });
            offset += mesh.positions().len();
        }
        Ok(Frame {
            scene,
            cache,
            objects,
            vp,
            _format: PhantomData,
        })
    }
}

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// Builds an object's lighting setup for this frame's specular model.
    fn lighting(&self, obj: &Object<'_>, view: &Mat4) -> LightingSetup<Sp> {
        LightingSetup::<Sp>::new(
            &self.scene.lights,
            view,
            &obj.material,
            self.scene.global_ambient,
            self.scene.local_viewer,
        )
    }

    /// Draws with the scene's depth and shading settings and the span method `S`.
    pub fn draw<S: SpanMethod, T: Target<P>>(&self, target: &mut T) -> Result<Stats, RenderError> {
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        match (self.scene.depth_test, self.scene.shading) {
            (true, ShadingMode::Gouraud) => self.draw_with::<S, DepthTest, Gouraud, T>(target),
            (true, ShadingMode::Flat) => self.draw_with::<S, DepthTest, Flat, T>(target),
            (false, ShadingMode::Gouraud) => self.draw_with::<S, NoDepth, Gouraud, T>(target),
            (false, ShadingMode::Flat) => self.draw_with::<S, NoDepth, Flat, T>(target),
            (true, ShadingMode::Quadratic) => self.draw_with::<S, DepthTest, Quadratic, T>(target),
            (false, ShadingMode::Quadratic) => self.draw_with::<S, NoDepth, Quadratic, T>(target),
            (true, ShadingMode::Phong) => self.draw_with::<S, DepthTest, Phong, T>(target),
            (false, ShadingMode::Phong) => self.draw_with::<S, NoDepth, Phong, T>(target),
            (true, ShadingMode::PhongEvenOdd) => {
                self.draw_with::<S, DepthTest, PhongEvenOdd, T>(target)
            }
            (false, ShadingMode::PhongEvenOdd) => {
                self.draw_with::<S, NoDepth, PhongEvenOdd, T>(target)
            }
            (true, ShadingMode::Adaptive) => {
                self.draw_with::<S, DepthTest, crate::shade::Adaptive, T>(target)
            }
            (false, ShadingMode::Adaptive) => {
                self.draw_with::<S, NoDepth, crate::shade::Adaptive, T>(target)
            }
        }
    }

    /// Draws with every variant chosen by type: span method, depth mode, shading.
    ///
    /// Quadratic ([`Shading::QUADRATIC`]), Phong ([`Shading::PER_PIXEL`]) and
    /// adaptive shading have their own fills and take from `S` only its
    /// [`SpanMethod::Divider`] (for their setup's reciprocal); their coverage is that
    /// of [`Gradient`].
    pub fn draw_with<S: SpanMethod, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if Sh::ADAPTIVE {
            return self.draw_adaptive::<S::Divider, Z, T>(target, None);
        }
        if Sh::QUADRATIC {
            return self.draw_quadratic::<S::Divider, Z, Sh, T>(target);
        }
        if Sh::PER_PIXEL {
            return if Sh::EVEN_ODD {
                self.draw_phong::<S::Divider, Z, phong::EvenOdd, T>(target, None, None)
            } else {
                self.draw_phong::<S::Divider, Z, phong::Rows, T>(target, None, None)
            };
        }
        let mut st = Stats::default();
        let cull = self.scene.cull_back;
        let rows = target.rows();
        for (obj, prep) in self.scene.objects.iter().zip(self.objects.iter()) {
            let verts = &self.cache[prep.offset..prep.offset + obj.mesh.positions().len()];
            let pos = obj.mesh.positions();
            for tri in obj.mesh.triangles() {
                st.triangles += 1;
                if !S::SNAPS {
                    // The usual path: the three vertices are read in place.
                    let t = tri.map(|i| &verts[i as usize]);
                    let class = classify_refs(t, cull, &self.vp, rows.clone());
                    self.draw_classified::<S, Z, Sh, T>(
                        target,
                        t,
                        class,
                        (pos, tri, prep),
                        &mut st,
                    );
                    continue;
                }
                // A method that moves vertices is culled on the moved ones, and only
                // triangles drawable before the move are drawn (the vertex stage lit
                // only their vertices): a sliver that turns front by snapping is
                // dropped (a documented coverage exception). The test is on the
                // triangle itself over the whole frame, so the result does not depend
                // on its neighbours or on the target's rows.
                let mut t = tri.map(|i| verts[i as usize]);
                let whole = 0..self.vp.height as i32;
                if classify(&t, cull, &self.vp, whole) == Class::Skip {
                    st.culled += 1;
                    continue;
                }
                for v in t.iter_mut().filter(|v| v.flags & OUTSIDE == 0) {
                    v.s = S::snap(v.s);
                }
                let class = classify(&t, cull, &self.vp, rows.clone());
                let t = [&t[0], &t[1], &t[2]];
                self.draw_classified::<S, Z, Sh, T>(target, t, class, (pos, tri, prep), &mut st);
            }
        }
        Ok(st)
    }

    /// Draws one triangle of [`Frame::draw_with`] as classified: `t` its vertices
    /// (snapped for a method that snaps), `tri` its indices into the object's
    /// positions `pos` (clipping transforms them again). Flat shading takes the last
    /// vertex's colour. A triangle classified inside the guard band goes to the setup
    /// directly; snapped vertices are tested again, since snapping moves them.
    #[inline(always)]
    fn draw_classified<S: SpanMethod, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
        t: [&XfVertex; 3],
        class: Class,
        (pos, tri, prep): (&[Vec3], &[u16; 3], &Prepared),
        st: &mut Stats,
    ) {
        let colour = |k: usize| if Sh::INTERPOLATE { t[k].s.c } else { t[2].s.c };
        match class {
            Class::Skip => st.culled += 1,
            Class::Draw => {
                st.drawn += 1;
                st.pixels += if S::SNAPS {
                    let s = core::array::from_fn(|k| ScreenVertex {
                        c: colour(k),
                        ..t[k].s
                    });
                    draw_triangle::<P, T, S, Z, Sh>(target, s)
                } else if Sh::INTERPOLATE {
                    // The cached vertices as they are: no copy.
                    draw_in_guard::<P, T, S, Z, Sh>(target, [&t[0].s, &t[1].s, &t[2].s])
                } else {
                    let s: [ScreenVertex; 3] = core::array::from_fn(|k| ScreenVertex {
                        c: colour(k),
                        ..t[k].s
                    });
                    draw_in_guard::<P, T, S, Z, Sh>(target, [&s[0], &s[1], &s[2]])
                };
            }
            Class::Clip => {
                st.clipped += 1;
                let cv: [ClipVertex; 3] = core::array::from_fn(|k| ClipVertex {
                    pos: prep.clip.transform(&pos[tri[k] as usize]),
                    c: colour(k),
                });
                self.draw_clipped::<S, Z, Sh, T>(target, cv, self.scene.cull_back, st);
            }
        }
    }

    /// Phong shading with the lighting sampled by pixel segments (seed 002 §2.6, see
    /// [`Sampling`]): the same coverage and depth as [`Frame::draw_with`] with
    /// [`crate::shade::Phong`], and with `segment = 1` the same pixels; larger
    /// segments light fewer pixels ([`Stats::evaluations`]) and interpolate the
    /// rest where the segment ends differ by at most the threshold. The depth test
    /// follows the scene.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::raster::phong::Sampling;
    /// use fixshade::sampler::{Threshold, SEED_K_Q8};
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let k = Threshold::from_q8(SEED_K_Q8, [255; 3]);
    /// let st = frame.draw_phong_sampled(&mut fb, Sampling { segment: 8, threshold: k }).unwrap();
    /// assert!(st.evaluations < st.pixels); // fewer lighting evaluations than pixels
    /// ```
    pub fn draw_phong_sampled<T: Target<P>>(
        &self,
        target: &mut T,
        sampling: Sampling,
    ) -> Result<Stats, RenderError> {
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        if self.scene.depth_test {
            self.draw_phong::<Exact, DepthTest, phong::Rows, T>(target, Some(sampling), None)
        } else {
            self.draw_phong::<Exact, NoDepth, phong::Rows, T>(target, Some(sampling), None)
        }
    }

    /// The quadratic path of [`Frame::draw_with`].
    fn draw_quadratic<D: Divide, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        let view = self.scene.camera.view().ok_or(RenderError::BadView)?;
        let mut st = Stats::default();
        let cull = self.scene.cull_back;
        let rows = target.rows();
        for (i, (obj, prep)) in self
            .scene
            .objects
            .iter()
            .zip(self.objects.iter())
            .enumerate()
        {
            let mv = view.mul(&obj.placement.matrix());
            let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
            let verts = &self.cache[prep.offset..prep.offset + obj.mesh.positions().len()];
            let (pos, nrm) = (obj.mesh.positions(), obj.mesh.normals());
            let nm = &aff.normal;
            let light = self.lighting(obj, &view);
            {
                let shade = |p: [i32; 3], n: [i32; 3]| light.shade(p, n);
                // The colour lit at the midpoint of the edge a–b.
                let mid = |a: usize, b: usize, ca: [i32; 3], cb: [i32; 3]| -> [i32; 3] {
                    let m: Vec3 = core::array::from_fn(|k| {
                        Q16_16::from_bits(
                            ((pos[a][k].to_bits() as i64 + pos[b][k].to_bits() as i64) >> 1) as i32,
                        )
                    });
                    let n: [i64; 3] = core::array::from_fn(|k| {
                        nrm[a][k].to_bits() as i64 + nrm[b][k].to_bits() as i64
                    });
                    // Entries < 2^31, components < 2^16: sums of three < 2^49.
                    let ne: [i64; 3] = core::array::from_fn(|r| {
                        nm[r][0] as i64 * n[0] + nm[r][1] as i64 * n[1] + nm[r][2] as i64 * n[2]
                    });
                    match normalize_to_q30(ne) {
                        Some(unit) => to_channels::<P>(shade(aff.point(&m), unit)),
                        // Opposite normals: no midpoint normal, average the colours.
                        None => {
                            core::array::from_fn(|k| ((ca[k] as i64 + cb[k] as i64) >> 1) as i32)
                        }
                    }
                };
                for tri in obj.mesh.triangles() {
                    st.triangles += 1;
                    let t = tri.map(|i| verts[i as usize]);
                    let s = [t[0].s, t[1].s, t[2].s];
                    match classify(&t, cull, &self.vp, rows.clone()) {
                        Class::Skip => st.culled += 1,
                        Class::Draw => {
                            let m = core::array::from_fn(|k| {
                                let (a, b) = (k, (k + 1) % 3);
                                mid(tri[a] as usize, tri[b] as usize, s[a].c, s[b].c)
                            });
                            st.drawn += 1;
                            st.pixels += draw_quadratic_div::<P, T, Z, D>(target, s, m, Sh::FILL);
                        }
                        Class::Clip => {
                            st.clipped += 1;
                            st.fallback += 1;
                            let cv: [ClipVertex; 3] = core::array::from_fn(|k| ClipVertex {
                                pos: prep.clip.transform(&pos[tri[k] as usize]),
                                c: s[k].c,
                            });
                            self.draw_clipped::<WithDivide<Gradient, D>, Z, Gouraud, T>(
                                target, cv, cull, &mut st,
                            );
                        }
                    }
                }
            }
        }
        Ok(st)
    }

    /// The frame's size in pixels, `(width, height)`: what a target must match.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Gray8>::prepare(&scene, 240, 135, &mut cache).unwrap();
    /// assert_eq!(frame.size(), (240, 135));
    /// ```
    pub fn size(&self) -> (u32, u32) {
        (self.vp.width, self.vp.height)
    }

    /// The Phong path of [`Frame::draw_with`]: eye-space normals and positions from
    /// the mesh (see [`Frame`]), every covered pixel lit with this frame's
    /// [`LightingSetup`]. Clipped triangles carry normal and position through the
    /// clipper as six attributes, so they are Phong-shaded too. With `persp` the
    /// attributes are perspective-correct (unless `sampling` is given).
    fn draw_phong<D: Divide, Z: DepthMode, F: PhongFill, T: Target<P>>(
        &self,
        target: &mut T,
        sampling: Option<Sampling>,
        persp: Option<Perspective>,
    ) -> Result<Stats, RenderError> {
        // One Phong triangle with its clip-space w: (pixels covered, evaluations).
        let draw =
            |target: &mut T, v: [PhongVertex; 3], w: [i64; 3], light: &LightingSetup<Sp>| match (
                sampling, persp,
            ) {
                (Some(sm), _) => draw_phong_sampled::<P, T, Z, _>(target, v, light, sm),
                (None, Some(m)) => (
                    draw_phong_perspective::<P, T, Z, D, _>(target, v, w, m, light),
                    0,
                ),
                (None, None) => (draw_phong_div::<P, T, Z, F, D, _>(target, v, light), 0),
            };
        let view = self.scene.camera.view().ok_or(RenderError::BadView)?;
        let mut st = Stats::default();
        let cull = self.scene.cull_back;
        let rows = target.rows();
        for (i, (obj, prep)) in self
            .scene
            .objects
            .iter()
            .zip(self.objects.iter())
            .enumerate()
        {
            let mv = view.mul(&obj.placement.matrix());
            let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
            let light = self.lighting(obj, &view);
            let verts = &self.cache[prep.offset..prep.offset + obj.mesh.positions().len()];
            let (pos, nrm) = (obj.mesh.positions(), obj.mesh.normals());
            // Eye-space unit normal and position of mesh vertex `i`.
            let eye = |i: usize| -> ([i32; 3], [i32; 3]) {
                (eye_normal(&aff, &nrm[i]), aff.point(&pos[i]))
            };
            for tri in obj.mesh.triangles() {
                st.triangles += 1;
                let t = tri.map(|i| verts[i as usize]);
                match classify(&t, cull, &self.vp, rows.clone()) {
                    Class::Skip => st.culled += 1,
                    Class::Draw => {
                        let pv = core::array::from_fn(|k| {
                            let (n, p) = eye(tri[k] as usize);
                            let s = t[k].s;
                            PhongVertex {
                                x: s.x,
                                y: s.y,
                                z: s.z,
                                n,
                                p,
                            }
                        });
                        st.drawn += 1;
                        let w = clip_w(persp, &prep.clip, pos, *tri);
                        let (px, ev) = draw(target, pv, w, &light);
                        st.pixels += px;
                        st.evaluations += ev;
                    }
                    Class::Clip => {
                        st.clipped += 1;
                        let cv: [ClipVertex<6>; 3] = core::array::from_fn(|k| {
                            let (n, p) = eye(tri[k] as usize);
                            ClipVertex {
                                pos: prep.clip.transform(&pos[tri[k] as usize]),
                                c: [n[0], n[1], n[2], p[0], p[1], p[2]],
                            }
                        });
                        let poly = clip_triangle(cv, &self.vp);
                        let mut pv = [PhongVertex::default(); crate::clip::MAX_POLY];
                        let mut pw = [1i64; crate::clip::MAX_POLY];
                        for ((o, ow), v) in pv
                            .iter_mut()
                            .zip(pw.iter_mut())
                            .zip(poly.v[..poly.len].iter())
                        {
                            let Some((x, y, z)) = project_clamped(&self.vp, v.pos) else {
                                continue;
                            };
                            *ow = v.pos[3];
                            let c = v.c;
                            *o = PhongVertex {
                                x,
                                y,
                                z,
                                n: [c[0], c[1], c[2]],
                                p: [c[3], c[4], c[5]],
                            };
                        }
                        for k in 1..poly.len.saturating_sub(1) {
                            let tri = [pv[0], pv[k], pv[k + 1]];
                            let pts = tri.map(|v| (v.x, v.y));
                            let area = crate::clip::signed_area(pts[0], pts[1], pts[2]);
                            if area == 0 || (cull && !is_front(pts[0], pts[1], pts[2])) {
                                continue;
                            }
                            st.drawn += 1;
                            let (px, ev) = draw(target, tri, [pw[0], pw[k], pw[k + 1]], &light);
                            st.pixels += px;
                            st.evaluations += ev;
                        }
                    }
                }
            }
        }
        Ok(st)
    }

    fn draw_clipped<S: SpanMethod, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
        t: [ClipVertex; 3],
        cull: bool,
        st: &mut Stats,
    ) {
        self.clip_fan(t, cull, st, |tri, _| {
            draw_triangle::<P, T, S, Z, Sh>(target, tri)
        });
    }

    /// Clips a triangle and hands each front-facing, non-degenerate triangle of the
    /// resulting fan to `draw` with its vertices' clip-space w; counts them and the
    /// pixels `draw` returns in `st`.
    fn clip_fan(
        &self,
        t: [ClipVertex; 3],
        cull: bool,
        st: &mut Stats,
        mut draw: impl FnMut([ScreenVertex; 3], [i64; 3]) -> u32,
    ) {
        let poly = clip_triangle(t, &self.vp);
        let mut sv = [ScreenVertex::default(); crate::clip::MAX_POLY];
        let mut w = [0i64; crate::clip::MAX_POLY];
        for ((o, ow), v) in sv
            .iter_mut()
            .zip(w.iter_mut())
            .zip(poly.v[..poly.len].iter())
        {
            let Some((x, y, z)) = project_clamped(&self.vp, v.pos) else {
                return;
            };
            *o = ScreenVertex { x, y, z, c: v.c };
            *ow = v.pos[3];
        }
        for i in 1..poly.len.saturating_sub(1) {
            let tri = [sv[0], sv[i], sv[i + 1]];
            let front = is_front(
                (tri[0].x, tri[0].y),
                (tri[1].x, tri[1].y),
                (tri[2].x, tri[2].y),
            );
            let area = crate::clip::signed_area(
                (tri[0].x, tri[0].y),
                (tri[1].x, tri[1].y),
                (tri[2].x, tri[2].y),
            );
            if area == 0 || (cull && !front) {
                continue;
            }
            st.drawn += 1;
            st.pixels += draw(tri, [w[0], w[i], w[i + 1]]);
        }
    }

    /// Draws with perspective-correct Gouraud colours (see [`crate::raster::perspective`]): the
    /// colour is sampled with one reciprocal through `D` at every pixel or at the
    /// ends of sub-spans (`mode`), and interpolated linearly in between; coverage and
    /// depth are those of [`Frame::draw`] with [`Gradient`]. The depth test follows
    /// the scene.
    ///
    /// Phong shading interpolates its normals and eye positions perspective-correctly
    /// ([`crate::raster::perspective::draw_phong_perspective`]; the even/odd fill
    /// draws as the one-accumulator fill does), and adaptive shading draws its
    /// Gouraud triangles and its per-pixel ones each through its perspective fill.
    /// Flat shading needs no correction, and the quadratic surface draws as
    /// [`Frame::draw`] draws it (its surface interpolates in screen space).
    ///
    /// ```
    /// use fixshade::divide::Exact;
    /// use fixshade::prelude::*;
    /// use fixshade::raster::perspective::Perspective;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let st = frame.draw_perspective::<Exact, _>(&mut fb, Perspective::SUB16).unwrap();
    /// assert!(st.pixels > 0);
    /// ```
    pub fn draw_perspective<D: Divide, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        use ShadingMode as M;
        let shading = self.scene.shading;
        if !matches!(
            shading,
            M::Gouraud | M::Phong | M::PhongEvenOdd | M::Adaptive
        ) {
            return self.draw::<Gradient, T>(target);
        }
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        // Even/odd Phong draws with the one-accumulator fill (the same pixels).
        match (shading, self.scene.depth_test) {
            (M::Gouraud, true) => {
                self.draw_perspective_as::<D, DepthTest, Gouraud, T>(target, mode)
            }
            (M::Gouraud, false) => self.draw_perspective_as::<D, NoDepth, Gouraud, T>(target, mode),
            (M::Adaptive, true) => {
                self.draw_perspective_as::<D, DepthTest, Adaptive, T>(target, mode)
            }
            (M::Adaptive, false) => {
                self.draw_perspective_as::<D, NoDepth, Adaptive, T>(target, mode)
            }
            (_, true) => self.draw_perspective_as::<D, DepthTest, Phong, T>(target, mode),
            (_, false) => self.draw_perspective_as::<D, NoDepth, Phong, T>(target, mode),
        }
    }

    /// [`Frame::draw_perspective`] with the depth mode and the shading fixed by type,
    /// as [`Frame::draw_with`] fixes them: only that combination's code is linked (a
    /// Gouraud-only firmware carries no Phong fill). Flat and quadratic shading draw
    /// as [`Frame::draw_with`] with [`Gradient`] draws them.
    ///
    /// ```
    /// use fixshade::divide::Exact;
    /// use fixshade::prelude::*;
    /// use fixshade::raster::perspective::Perspective;
    /// use fixshade::raster::span::DepthTest;
    /// use fixshade::shade::Gouraud;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let st = frame
    ///     .draw_perspective_as::<Exact, DepthTest, Gouraud, _>(&mut fb, Perspective::SUB16)
    ///     .unwrap();
    /// assert!(st.pixels > 0);
    /// ```
    pub fn draw_perspective_as<D: Divide, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        if !Sh::INTERPOLATE || Sh::QUADRATIC {
            return self.draw_with::<Gradient, Z, Sh, T>(target);
        }
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if Sh::ADAPTIVE {
            return self.draw_adaptive::<D, Z, T>(target, Some(mode));
        }
        if Sh::PER_PIXEL {
            return self.draw_phong::<D, Z, phong::Rows, T>(target, None, Some(mode));
        }
        Ok(self.draw_perspective_with::<D, Z, T>(target, mode))
    }

    fn draw_perspective_with<D: Divide, Z: DepthMode, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Stats {
        let mut st = Stats::default();
        let cull = self.scene.cull_back;
        let rows = target.rows();
        for (obj, prep) in self.scene.objects.iter().zip(self.objects.iter()) {
            let pos = obj.mesh.positions();
            let verts = &self.cache[prep.offset..prep.offset + pos.len()];
            for tri in obj.mesh.triangles() {
                st.triangles += 1;
                let t = tri.map(|i| verts[i as usize]);
                let s = [t[0].s, t[1].s, t[2].s];
                match classify(&t, cull, &self.vp, rows.clone()) {
                    Class::Skip => st.culled += 1,
                    Class::Draw => {
                        st.drawn += 1;
                        // Clip-space w, recomputed: the vertex cache keeps none.
                        let w = tri.map(|i| prep.clip.transform(&pos[i as usize])[3]);
                        st.pixels +=
                            draw_triangle_perspective::<P, T, Z, Gouraud, D>(target, s, w, mode);
                    }
                    Class::Clip => {
                        st.clipped += 1;
                        let cv: [ClipVertex; 3] = core::array::from_fn(|k| ClipVertex {
                            pos: prep.clip.transform(&pos[tri[k] as usize]),
                            c: s[k].c,
                        });
                        self.clip_fan(cv, cull, &mut st, |tri, w| {
                            draw_triangle_perspective::<P, T, Z, Gouraud, D>(target, tri, w, mode)
                        });
                    }
                }
            }
        }
        st
    }
}

/// The clip-space w of the mesh triangle `tri` under `clip` when `persp` asks for
/// perspective correction (the vertex cache keeps none); else unused, `[1; 3]`.
fn clip_w(persp: Option<Perspective>, clip: &ClipMatrix, pos: &[Vec3], tri: [u16; 3]) -> [i64; 3] {
    match persp {
        Some(_) => tri.map(|i| clip.transform(&pos[i as usize])[3]),
        None => [1; 3],
    }
}

/// The eye-space unit normal (Q2.30) of a mesh normal under `aff`'s normal matrix;
/// `(0, 0, 1)` for a zero normal.
fn eye_normal(aff: &Affine3, n: &[crate::fixed::Q2_14; 3]) -> [i32; 3] {
    let nm = &aff.normal;
    let nv = n.map(|c| c.to_bits());
    // Entries < 2^31, components < 2^15: sums of three < 2^48.
    let ne: [i64; 3] = core::array::from_fn(|r| {
        mul_wide_16(nm[r][0], nv[0]) + mul_wide_16(nm[r][1], nv[1]) + mul_wide_16(nm[r][2], nv[2])
    });
    normalize_to_q30(ne).unwrap_or([0, 0, ONE_Q30])
}

/// Projects a clipped vertex: like [`Viewport::project`] but clamps what rounding in
/// the clipper may have pushed a hair outside (depth to [0, 1], x and y into the guard
/// band). `None` only if `w ≤ 0`.
fn project_clamped(vp: &Viewport, c: [i64; 4]) -> Option<(i32, i32, u32)> {
    let [x, y, z, w] = normalize_clip(c);
    if w <= 0 {
        return None;
    }
    let lim = (GUARD - 1) as i64;
    let (sx, sy, sz) = vp.divide(x, y, z.clamp(-w, w), w);
    Some((
        sx.clamp(-lim, lim) as i32,
        sy.clamp(-lim, lim) as i32,
        sz as u32,
    ))
}
