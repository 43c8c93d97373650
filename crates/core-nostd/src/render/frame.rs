//! The frame: the vertex stage ([`Frame::prepare`]) and what the draw calls of a
//! prepared frame (`Frame::draw*` in [`super::draw`], each a [`super::walk`] with
//! its shading mode's fill) report ([`Stats`], [`RenderError`]). Re-exported by [`super`], whose docs hold the example.

use crate::arrays;
use core::marker::PhantomData;

use crate::geometry::{Projector, Viewport, DEPTH_SCALE};
use crate::light::LightingSetup;
use crate::math::{mul_wide_16, normalize_to_q30, Affine3, Mat4, Vec3, VertexTransform, ONE_Q30};
use crate::raster::vertex::GUARD;
use crate::raster::ScreenVertex;
use crate::scene::{Object, Projection, Scene, MAX_OBJECTS};
use crate::specular::{BlinnExact, Specular};
use crate::target::{to_channels, PixelFormat};

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

/// Why a triangle is not drawn.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Skip {
    /// A back face, culled.
    Back,
    /// Zero area after snapping to the subpixel grid.
    Degenerate,
    /// Entirely off the frame rows or columns the target holds.
    Outside,
}

/// What to do with a triangle.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Class {
    /// Culled, zero-area, or entirely off the frame rows/columns.
    Skip(Skip),
    /// All vertices inside the guard band: rasterize directly.
    Draw,
    /// Some vertex outside: clip first.
    Clip,
}

/// Classifies a triangle by its vertex-stage output. `rows` are the frame rows a
/// target holds; a triangle entirely above, below, left or right of them is skipped.
#[inline]
pub(super) fn classify(
    t: &[XfVertex; 3],
    cull: bool,
    vp: &Viewport,
    rows: core::ops::Range<i32>,
) -> Class {
    classify_refs([&t[0], &t[1], &t[2]], cull, vp, rows)
}

/// [`classify`] on references into the vertex cache (the hot loops read the three
/// vertices in place instead of copying them out first).
#[inline(always)]
pub(super) fn classify_refs(
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
    if area == 0 {
        return Class::Skip(Skip::Degenerate);
    }
    if cull && area > 0 {
        return Class::Skip(Skip::Back);
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
        return Class::Skip(Skip::Outside);
    }
    Class::Draw
}

/// Whether the cull pass takes the area with 32-bit products first
/// ([`crate::clip::signed_area_i32`]): on ARMv6-M, where a 64-bit product is a
/// library call. Both forms give the same sign (tested).
const SMALL_AREA: bool = cfg!(fixshade_v6m);

/// The vertex stage's step 1 under a perspective projection: x, y and w of every
/// position ([`VertexTransform::xyw`]), the depth range tested on w, the screen
/// position and depth from [`Projector::project`]; [`OUTSIDE`] for a vertex
/// outside the depth range or the guard band. Returns whether some vertex is.
/// (Out of line, as the other passes: each loop gets the registers to itself.)
#[inline(never)]
fn project_perspective<const S: u32, const SH: u8>(
    out: &mut [XfVertex],
    pos: &[Vec3],
    clip: &VertexTransform,
    proj: &Projector,
    depth: &crate::geometry::PerspectiveDepth,
) -> bool {
    let (w_lo, w_hi) = depth.w_range();
    let mut flags = 0;
    for (o, p) in out.iter_mut().zip(pos) {
        let [x, y, w] = clip.xyw::<S, SH>(p);
        let s = if w < w_lo || w > w_hi {
            None
        } else {
            proj.project_perspective(depth, x, y, w)
        };
        *o = vertex(s);
        flags |= o.flags;
    }
    flags & OUTSIDE != 0
}

/// [`project_perspective`] for any other projection (orthographic): z from the
/// matrix, the depth range `−w ≤ z ≤ w`.
#[inline(never)]
fn project_general<const S: u32, const SH: u8>(
    out: &mut [XfVertex],
    pos: &[Vec3],
    clip: &VertexTransform,
    proj: &Projector,
) -> bool {
    let mut flags = 0;
    for (o, p) in out.iter_mut().zip(pos) {
        let [x, y, z, w] = clip.xyzw::<S, SH>(p);
        let s = if w <= 0 || z < -w || z > w {
            None
        } else {
            proj.project_orthographic(x, y, z, w)
        };
        *o = vertex(s);
        flags |= o.flags;
    }
    flags & OUTSIDE != 0
}

/// The vertex stage's step 3: the colour of every [`NEEDED`] vertex, lit in eye
/// space (the normal through the normal matrix and renormalised, the position
/// only where a point light or a local viewer reads it).
///
/// [`crate::light::ObjectLighting`] lights in the object's space instead, with no
/// normal matrix (about 150 fewer instructions a vertex on the Cortex-M4, 700 on
/// ARMv6-M), but its figures drift from the f64 reference (teapot NMSE 1.6e-6
/// against 1.1e-6 here), so the vertex stage keeps the eye-space sums.
#[inline(never)]
fn light_needed<P: PixelFormat, Sp: Specular>(
    out: &mut [XfVertex],
    pos: &[Vec3],
    nrm: &[[crate::fixed::Q2_14; 3]],
    aff: &Affine3,
    light: &LightingSetup<Sp>,
) {
    let position = light.needs_position();
    for ((o, p), n) in out.iter_mut().zip(pos).zip(nrm) {
        if o.flags & NEEDED == 0 {
            continue;
        }
        let unit = eye_normal(aff, n);
        let at = if position { aff.point(p) } else { [0; 3] };
        o.s.c = to_channels::<P>(light.shade(at, unit));
    }
}

/// The vertex stage's step 3 for the back faces of two-sided lighting
/// ([`crate::effects::TwoSided`]): the colour of every vertex that `front` marks
/// [`NEEDED`], lit with the negated eye-space normal (components within ±2³⁰ in
/// Q2.30, so the negation cannot overflow) and `light`, the back material's setup;
/// written to `back`'s colours.
#[inline(never)]
fn light_back<P: PixelFormat, Sp: Specular>(
    back: &mut [XfVertex],
    front: &[XfVertex],
    pos: &[Vec3],
    nrm: &[[crate::fixed::Q2_14; 3]],
    aff: &Affine3,
    light: &LightingSetup<Sp>,
) {
    let position = light.needs_position();
    for (((b, f), p), n) in back.iter_mut().zip(front).zip(pos).zip(nrm) {
        if f.flags & NEEDED == 0 {
            continue;
        }
        let unit = arrays::map(eye_normal(aff, n), |c| -c);
        let at = if position { aff.point(p) } else { [0; 3] };
        b.s.c = to_channels::<P>(light.shade(at, unit));
    }
}

/// True if the screen triangle `t` is a back face: the sign test of back-face
/// culling ([`classify_refs`]: positive area with y down).
#[inline(always)]
pub(super) fn is_back(t: [&ScreenVertex; 3]) -> bool {
    crate::clip::signed_area((t[0].x, t[0].y), (t[1].x, t[1].y), (t[2].x, t[2].y)) > 0
}

/// A cache entry for a projected vertex, or an [`OUTSIDE`] one.
#[inline(always)]
fn vertex(s: Option<(i32, i32, u32)>) -> XfVertex {
    match s {
        Some((x, y, z)) => XfVertex {
            s: ScreenVertex { x, y, z, c: [0; 3] },
            flags: 0,
        },
        None => XfVertex {
            s: ScreenVertex::default(),
            flags: OUTSIDE,
        },
    }
}

/// The triangles the cull pass ([`mark_needed`]) dropped over the whole frame, by
/// reason, of those with no vertex [`OUTSIDE`]: with them the walk counts the
/// triangles it skips on the flags alone (see [`Frame::walk`]).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Dropped {
    /// Back faces (with culling).
    pub(super) back: u32,
    /// Zero area.
    pub(super) degenerate: u32,
}

impl core::ops::AddAssign for Dropped {
    fn add_assign(&mut self, o: Dropped) {
        self.back += o.back;
        self.degenerate += o.degenerate;
    }
}

/// The vertex stage's cull pass: marks [`NEEDED`] the vertices of every triangle
/// that [`classify_refs`] over the whole frame does not skip (`CULL`: the scene
/// culls back faces), with the same tests in a cheaper form: the flags first (only
/// with `OUTSIDE`: some vertex of the mesh is), then the sign of the area (`SMALL`:
/// with 32-bit products when the edges are under 2048 pixels), then the frame's
/// edges, each a comparison of the three vertices that stops at the first one
/// inside (the bounding-box test without the minima and maxima). Returns how many
/// it dropped as back faces and for zero area (the reasons `classify_refs` gives
/// first; the rest it dropped lie outside the frame).
#[inline(never)]
fn mark_needed<const CULL: bool, const OUTSIDE_ANY: bool, const SMALL: bool>(
    out: &mut [XfVertex],
    tris: &[[u16; 3]],
    vp: &Viewport,
) -> Dropped {
    // Pixel centres at 16k + 8 (see `classify_refs`).
    let (right, bottom) = (16 * vp.width as i32 - 8, 16 * vp.height as i32 - 8);
    // Counted on the rarer paths (a back face, the usual drop, costs nothing more):
    // the triangles with a vertex outside, the zero areas and, with culling, the
    // front faces. Counts of a slice's triangles: they fit u32, as `Stats` does.
    let (mut clipped, mut degenerate, mut front) = (0u32, 0u32, 0u32);
    for tri in tris {
        let [a, b, c] = arrays::map(*tri, |i| &out[i as usize]);
        let draw = if OUTSIDE_ANY && (a.flags | b.flags | c.flags) & OUTSIDE != 0 {
            clipped += 1;
            true
        } else {
            let (a, b, c) = (a.s, b.s, c.s);
            let small = if SMALL {
                crate::clip::signed_area_i32((a.x, a.y), (b.x, b.y), (c.x, c.y))
            } else {
                None
            };
            let (gt, eq) = match small {
                Some(area) => (area > 0, area == 0),
                None => {
                    let area = crate::clip::signed_area((a.x, a.y), (b.x, b.y), (c.x, c.y));
                    (area > 0, area == 0)
                }
            };
            // A back face first: the usual drop takes one test.
            if CULL && gt {
                false
            } else if eq {
                degenerate += 1;
                false
            } else {
                if CULL {
                    front += 1;
                }
                !((a.x < 8 && b.x < 8 && c.x < 8)
                    || (a.x > right && b.x > right && c.x > right)
                    || (a.y < 8 && b.y < 8 && c.y < 8)
                    || (a.y > bottom && b.y > bottom && c.y > bottom))
            }
        };
        if draw {
            for i in tri {
                out[*i as usize].flags |= NEEDED;
            }
        }
    }
    Dropped {
        // Every triangle without a vertex outside is a zero area, a front face or
        // (with culling) a back face.
        back: if CULL {
            (tris.len() as u32)
                .wrapping_sub(clipped)
                .wrapping_sub(degenerate)
                .wrapping_sub(front)
        } else {
            0
        },
        degenerate,
    }
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
    /// Two-sided lighting ([`crate::effects::TwoSided`]) with adaptive shading,
    /// which does not support it.
    TwoSidedUnsupported,
    /// A [`FrameSetup`] used with a scene it was not made for (another number of
    /// objects, or a mesh of another bound), or made for more objects than it holds.
    SetupMismatch,
    /// A cache given to [`Frame::resume`] holds a vertex the vertex stage does not
    /// write (a position outside the guard band, a depth or colour out of range).
    CacheNotPrepared,
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
            RenderError::TwoSidedUnsupported => f.write_str(
                "two-sided lighting is not supported with adaptive shading \
                 (use phong, gouraud, flat or quadratic)",
            ),
            RenderError::SetupMismatch => f.write_str(
                "the frame setup was not made for this scene (objects or mesh bounds differ)",
            ),
            RenderError::CacheNotPrepared => {
                f.write_str("the vertex cache holds a vertex no vertex stage wrote")
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
    /// Back faces dropped by back-face culling (0 without culling).
    pub culled: u32,
    /// Dropped for zero area after snapping to the subpixel grid.
    pub degenerate: u32,
    /// Dropped for lying entirely outside the rows and columns of the target.
    pub outside: u32,
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
    /// ([`super::Binned::draw_band`]: the band memory was too small, or the method or the
    /// shading has no records).
    pub rewalked: u32,
}

impl Stats {
    /// Triangles dropped before rasterizing, for any reason: culled back faces,
    /// zero area, outside the target.
    ///
    /// ```
    /// use fixshade::render::Stats;
    /// let st = Stats { triangles: 10, culled: 4, degenerate: 1, outside: 2, drawn: 3, ..Stats::default() };
    /// assert_eq!(st.skipped(), 7);
    /// ```
    pub fn skipped(&self) -> u32 {
        self.culled + self.degenerate + self.outside
    }

    /// Counts a triangle skipped for `why`.
    #[inline]
    pub(super) fn skip(&mut self, why: Skip) {
        match why {
            Skip::Back => self.culled += 1,
            Skip::Degenerate => self.degenerate += 1,
            Skip::Outside => self.outside += 1,
        }
    }
}

impl core::ops::AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.triangles += o.triangles;
        self.culled += o.culled;
        self.degenerate += o.degenerate;
        self.outside += o.outside;
        self.clipped += o.clipped;
        self.drawn += o.drawn;
        self.pixels += o.pixels;
        self.fallback += o.fallback;
        self.evaluations += o.evaluations;
        self.per_pixel += o.per_pixel;
        self.rewalked += o.rewalked;
    }
}

/// What a draw keeps of an object's vertex stage: where its vertices are in the
/// cache, and its clip transform, rebuilt on first use by the same arithmetic as in
/// [`Frame::prepare`] (so the same bits): only the clipper and the perspective fills
/// need it, and a frame holding a 200-byte transform per object (3.6 KiB for 16
/// objects) would not fit the few KiB of stack of a Cortex-M0 board.
pub(super) struct Prepared<'f> {
    pub(super) offset: usize,
    obj: &'f Object<'f>,
    view: &'f Mat4,
    proj: &'f Mat4,
    map: &'f Projector,
    clip: core::cell::OnceCell<VertexTransform>,
}

impl Prepared<'_> {
    /// The object's clip transform.
    pub(super) fn clip(&self) -> &VertexTransform {
        self.clip.get_or_init(|| {
            // `prepare` built this transform from the same values: it exists.
            let mv = self.view.mul(&self.obj.placement.matrix());
            object_transform(&mv, self.proj, self.map, self.obj).unwrap_or_default()
        })
    }
}

/// The clip transform of `obj` with the model-view matrix `mv` in the frame of
/// `proj` and `map`: `None` if it does not fit (see [`VertexTransform::new`]).
fn object_transform(
    mv: &Mat4,
    proj: &Mat4,
    map: &Projector,
    obj: &Object<'_>,
) -> Option<VertexTransform> {
    VertexTransform::new(
        &proj.mul(mv),
        map.scale(),
        obj.mesh.bound(),
        map.w_bits(),
        map.z_from_w(),
    )
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
    pub(super) scene: &'s Scene<'a>,
    pub(super) cache: &'c [XfVertex],
    /// Where the back colours of two-sided lighting start in the cache (the scene's
    /// vertex count; unused by one-sided lighting).
    back: usize,
    /// Each object's first vertex in the cache.
    offsets: heapless::Vec<usize, MAX_OBJECTS>,
    /// The frame's view and projection matrices (for [`Prepared::clip`]).
    view: Mat4,
    proj: Mat4,
    /// The frame's projection (dereferences to its [`Viewport`]).
    pub(super) vp: Projector,
    /// What the cull pass dropped, when this frame's vertex stage ran it (not for
    /// [`Frame::resume`], whose cache the pass marked before).
    pub(super) dropped: Option<Dropped>,
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
        // Borrowed where the call left them (a `?` would copy them out first).
        let consts = frame_setup(scene, width, height);
        let (view, proj, map) = match &consts {
            Ok(c) => c,
            Err(e) => return Err(*e),
        };
        Frame::<P, Sp>::run(scene, cache, view, proj, map, None)
    }
}

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// Runs the vertex stage from a [`FrameSetup`] made for `scene`: the same
    /// vertices, bit for bit, as [`Frame::prepare_with`] with the setup's size,
    /// without building the matrices, the projection and the lighting again.
    ///
    /// For drawing one scene in parts: firmware whose RAM holds the vertex cache of
    /// a chunk of the mesh but not of the whole mesh swaps the objects' meshes for
    /// their chunks and prepares each chunk from one setup. A chunk must have the
    /// bound of the mesh the setup was made with ([`Mesh::with_bound`](crate::geometry::Mesh::with_bound)), which the
    /// transform's range is chosen for; anything else the setup read (the camera,
    /// the lights, the placements and materials, the frame size) must not have
    /// changed: a changed camera, say, is not detected and draws the old view.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::render::FrameSetup;
    /// # let scene = fixshade::doc_support::scene();
    /// let setup: FrameSetup = FrameSetup::new(&scene, 64, 48).unwrap();
    /// let (mut a, mut b) = ([XfVertex::default(); 3], [XfVertex::default(); 3]);
    /// Frame::<Rgb565Le>::prepare(&scene, 64, 48, &mut a).unwrap();
    /// let frame = Frame::<Rgb565Le>::prepare_from(&scene, &setup, &mut b).unwrap();
    /// assert_eq!(frame.size(), (64, 48));
    /// drop(frame);
    /// assert_eq!(a, b);
    /// ```
    ///
    /// # Errors
    ///
    /// [`RenderError::SetupMismatch`] when the scene has another number of objects
    /// than the setup, or an object's mesh another bound, or the setup is
    /// [`FrameSetup::EMPTY`];
    /// [`RenderError::CacheTooSmall`] as [`Frame::prepare`].
    pub fn prepare_from<const N: usize>(
        scene: &'s Scene<'a>,
        setup: &FrameSetup<Sp, N>,
        cache: &'c mut [XfVertex],
    ) -> Result<Self, RenderError> {
        if !setup.fits(scene) {
            return Err(RenderError::SetupMismatch);
        }
        Frame::run(
            scene,
            cache,
            &setup.view,
            &setup.proj,
            &setup.map,
            Some(&setup.objects),
        )
    }

    /// The frame whose vertex stage [`Frame::prepare_from`] has already run into
    /// `cache` for `scene` and `setup`, without running it again: the same frame,
    /// drawing the same bytes.
    ///
    /// For firmware that prepares the chunks of a mesh into a few caches and draws
    /// each chunk in many bands: a chunk whose cache is still there is drawn again
    /// from it, for a pass over its vertices instead of the vertex stage. The scene
    /// must be the one the cache was prepared for (its meshes swapped for the same
    /// chunks); the checks are [`Frame::prepare_from`]'s and a range check of every
    /// vertex the draw reads, so a cache of anything else either draws wrong but
    /// in-range triangles or is refused; it never panics.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::render::FrameSetup;
    /// # let scene = fixshade::doc_support::scene();
    /// let setup: FrameSetup = FrameSetup::new(&scene, 64, 48).unwrap();
    /// let mut cache = [XfVertex::default(); 3];
    /// let (mut a, mut b) = ([0u8; 64 * 48], [0u8; 64 * 48]);
    /// let (mut za, mut zb) = ([0xFFFFu16; 64 * 48], [0xFFFFu16; 64 * 48]);
    /// let frame = Frame::<Gray8>::prepare_from(&scene, &setup, &mut cache).unwrap();
    /// frame.draw::<Gradient, _>(&mut Framebuffer::new(&mut a, Some(&mut za), 64, 48).unwrap()).unwrap();
    /// drop(frame);
    /// // Later, with the cache untouched: no vertex stage.
    /// let frame = Frame::<Gray8>::resume(&scene, &setup, &cache).unwrap();
    /// frame.draw::<Gradient, _>(&mut Framebuffer::new(&mut b, Some(&mut zb), 64, 48).unwrap()).unwrap();
    /// assert_eq!(a, b);
    /// ```
    ///
    /// # Errors
    ///
    /// As [`Frame::prepare_from`], and [`RenderError::CacheNotPrepared`] when a
    /// vertex of `cache` is out of the vertex stage's range.
    pub fn resume<const N: usize>(
        scene: &'s Scene<'a>,
        setup: &FrameSetup<Sp, N>,
        cache: &'c [XfVertex],
    ) -> Result<Self, RenderError> {
        if !setup.fits(scene) {
            return Err(RenderError::SetupMismatch);
        }
        let needed = Self::checked_cache_len(scene, cache.len())?;
        let (front, back) = cache[..needed].split_at(scene.vertex_count());
        // What the vertex stage writes: positions inside the guard band and depths
        // inside the depth range (unless `OUTSIDE`, whose triangles the clipper
        // takes from the mesh), colour channels within [0, 2^30) (the lattice's
        // range). Two-sided lighting writes only the colours of the back half.
        // One pass of ORs and no early exit (a cache is checked per strip and chunk on
        // a small board): every channel below 2^30 exactly when their OR is.
        let colour = |v: &XfVertex| (v.s.c[0] | v.s.c[1] | v.s.c[2]) as u32 >> 30 != 0;
        let mut bad = false;
        for v in front {
            bad |= colour(v)
                | (v.flags & OUTSIDE == 0
                    && (v.s.x.unsigned_abs() >= GUARD as u32
                        || v.s.y.unsigned_abs() >= GUARD as u32
                        || v.s.z as i64 > DEPTH_SCALE));
        }
        for v in back {
            bad |= colour(v);
        }
        if bad {
            return Err(RenderError::CacheNotPrepared);
        }
        Ok(Frame::assemble(
            scene,
            cache,
            &setup.view,
            &setup.proj,
            &setup.map,
            None,
        ))
    }

    /// The frame of `scene` over its prepared `cache`, in the frame of `view`,
    /// `proj` and `map`, with what the cull pass `dropped` if it ran.
    #[inline(always)]
    fn assemble(
        scene: &'s Scene<'a>,
        cache: &'c [XfVertex],
        view: &Mat4,
        proj: &Mat4,
        map: &Projector,
        dropped: Option<Dropped>,
    ) -> Self {
        let mut offsets = heapless::Vec::new();
        let mut offset = 0;
        for obj in scene.objects.iter() {
            // Capacity equals the scene's object capacity.
            let _ = offsets.push(offset);
            offset += obj.mesh.positions().len();
        }
        Frame {
            scene,
            cache,
            back: scene.vertex_count(),
            offsets,
            view: *view,
            proj: *proj,
            vp: *map,
            dropped,
            _format: PhantomData,
        }
    }

    /// The vertex stage's passes over every object of `scene` in the frame of
    /// `view`, `proj` and `map`, each object with its setup from `stored` (by
    /// index), or built here when there is none.
    #[inline(always)]
    fn run(
        scene: &'s Scene<'a>,
        cache: &'c mut [XfVertex],
        view: &Mat4,
        proj: &Mat4,
        map: &Projector,
        stored: Option<&[ObjectSetup<Sp>]>,
    ) -> Result<Self, RenderError> {
        // Two-sided lighting keeps the back colours in a second half of the cache.
        let count = scene.vertex_count();
        Self::checked_cache_len(scene, cache.len())?;
        let vp = *map.viewport();
        let mut offset = 0;
        let mut dropped = Dropped::default();
        let (front, back) = cache.split_at_mut(count);
        for (i, obj) in scene.objects.iter().enumerate() {
            // Built in place when not stored (as locals: a struct or a tuple moved
            // out of a call would be copied, on the stack of a small board).
            let (built_clip, built_aff, built_light);
            let (clip, aff, light) = match stored {
                Some(s) => (&s[i].clip, &s[i].aff, &s[i].light),
                None => {
                    let mv = view.mul(&obj.placement.matrix());
                    built_clip = object_transform(&mv, proj, map, obj)
                        .ok_or(RenderError::SingularModel { object: i })?;
                    // A singular model (scale 0) has no normals.
                    built_aff =
                        Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
                    built_light = ObjectSetup::<Sp>::lighting(scene, obj, view);
                    (&built_clip, &built_aff, &built_light)
                }
            };
            let mesh = &obj.mesh;
            let out = &mut front[offset..offset + mesh.positions().len()];
            // 1. Transform and project every vertex once.
            let pos = mesh.positions();
            use crate::math::PositionShift as Sh;
            let outside = match (map.perspective_depth(), clip.form()) {
                (Some(d), (13, Sh::None)) => project_perspective::<13, 0>(out, pos, clip, map, d),
                (Some(d), (13, _)) => project_perspective::<13, 1>(out, pos, clip, map, d),
                (Some(d), (_, Sh::Right)) => project_perspective::<18, 2>(out, pos, clip, map, d),
                (Some(d), _) => project_perspective::<18, 1>(out, pos, clip, map, d),
                (None, (13, _)) => project_general::<13, 1>(out, pos, clip, map),
                (None, (_, Sh::Right)) => project_general::<18, 2>(out, pos, clip, map),
                (None, _) => project_general::<18, 1>(out, pos, clip, map),
            };
            // 2. Cull before lighting: only vertices of triangles that may be drawn
            //    are lit (the flags are read only if some vertex is outside).
            let tris = mesh.triangles();
            dropped += match (scene.cull_back, outside) {
                (true, true) => mark_needed::<true, true, SMALL_AREA>(out, tris, &vp),
                (true, false) => mark_needed::<true, false, SMALL_AREA>(out, tris, &vp),
                (false, true) => mark_needed::<false, true, SMALL_AREA>(out, tris, &vp),
                (false, false) => mark_needed::<false, false, SMALL_AREA>(out, tris, &vp),
            };
            // 3. Light the vertices that are needed, in eye space.
            light_needed::<P, Sp>(out, pos, mesh.normals(), aff, light);
            if Sp::two_sided() {
                // 4. Two-sided: the same vertices with the negated normal and the
                //    back material (the front material when the object has none).
                let back_light = LightingSetup::<Sp>::new(
                    &scene.lights,
                    view,
                    obj.back_material.unwrap_or(&obj.material),
                    scene.global_ambient,
                    scene.local_viewer,
                );
                let b = &mut back[offset..offset + pos.len()];
                light_back::<P, Sp>(b, out, pos, mesh.normals(), aff, &back_light);
            }
            offset += mesh.positions().len();
        }
        Ok(Frame::assemble(
            scene,
            cache,
            view,
            proj,
            map,
            Some(dropped),
        ))
    }
}

/// The frame-wide part of the vertex stage's setup: the view and projection
/// matrices and the projector of a frame of `width` × `height` pixels.
fn frame_setup(
    scene: &Scene<'_>,
    width: u32,
    height: u32,
) -> Result<(Mat4, Mat4, Projector), RenderError> {
    if width == 0 || width > 4096 || height == 0 || height > 4096 {
        return Err(RenderError::BadSize);
    }
    let view = scene.camera.view().ok_or(RenderError::BadView)?;
    let proj = scene
        .camera
        .projection_matrix(width, height)
        .ok_or(RenderError::BadProjection)?;
    let vp = Viewport { width, height };
    // One clip scale for the frame: from how far any vertex lies from the eye,
    // per eye-space coordinate (the view is rigid, the model a rotation and a
    // uniform scale: |offset from the object's origin| ≤ scale·√3·bound).
    let reach = scene.objects.iter().fold(0i64, |r, obj| {
        let pl = &obj.placement;
        let origin = view.transform_point(pl.translate);
        let far = origin.iter().map(|c| c.saturating_abs()).max().unwrap_or(0);
        let extent = 2 * (pl.scale.to_bits().unsigned_abs() as i64) * obj.mesh.bound() as i64;
        r.max(far.saturating_add(extent))
    });
    let depth_range = match scene.camera.projection {
        Projection::Perspective { near, far, .. } => Some((near, far)),
        Projection::Orthographic { .. } => None,
    };
    let map = Projector::new(vp, &proj, depth_range, reach).ok_or(RenderError::BadProjection)?;
    Ok((view, proj, map))
}

/// One object's part of the vertex stage's setup: its clip transform, its
/// model-view [`Affine3`] (the normal matrix) and its (front) lighting, for a mesh
/// of bound `bound`.
struct ObjectSetup<Sp: Specular> {
    clip: VertexTransform,
    aff: Affine3,
    light: LightingSetup<Sp>,
    bound: i32,
}

impl<Sp: Specular> ObjectSetup<Sp> {
    /// Object `i` of `scene`, `obj`, in the frame of `view`, `proj` and `map`.
    fn new(
        scene: &Scene<'_>,
        i: usize,
        obj: &Object<'_>,
        view: &Mat4,
        proj: &Mat4,
        map: &Projector,
    ) -> Result<Self, RenderError> {
        // As `Frame::run` builds them. Written out there as well: a shared function
        // returning the two transforms cost the micro:bit scenes image 160 to 352 bytes
        // more peak stack (measured on its painted stack).
        let mv = view.mul(&obj.placement.matrix());
        let clip = object_transform(&mv, proj, map, obj)
            .ok_or(RenderError::SingularModel { object: i })?;
        let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
        Ok(ObjectSetup {
            clip,
            aff,
            light: Self::lighting(scene, obj, view),
            bound: obj.mesh.bound(),
        })
    }

    /// The (front) lighting setup of `obj` under `view`.
    #[inline(always)]
    fn lighting(scene: &Scene<'_>, obj: &Object<'_>, view: &Mat4) -> LightingSetup<Sp> {
        LightingSetup::<Sp>::new(
            &scene.lights,
            view,
            &obj.material,
            scene.global_ambient,
            scene.local_viewer,
        )
    }
}

/// The setup of a frame's vertex stage, kept to prepare the frame again
/// ([`Frame::prepare_from`]) with its meshes swapped for chunks of them: the view,
/// the projection and, for each of at most `N` objects, its transforms and
/// lighting. It costs what [`Frame::prepare`] spends before its first vertex: a
/// fixed cost that was two thirds of the vertex stage's instructions in the
/// micro:bit image's 64-vertex chunks when every chunk paid it.
///
/// About 1.25 KB for one object (its lighting setup holds eight lights), so a
/// firmware keeps it in a `static` rather than on a small stack.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::render::FrameSetup;
/// # let scene = fixshade::doc_support::scene();
/// let setup: FrameSetup = FrameSetup::new(&scene, 64, 48).unwrap();
/// assert_eq!(setup.size(), (64, 48));
/// // A scene of more objects than the setup holds:
/// assert_eq!(
///     FrameSetup::<fixshade::specular::BlinnExact, 0>::new(&scene, 64, 48).err(),
///     Some(RenderError::SetupMismatch)
/// );
/// ```
pub struct FrameSetup<Sp: Specular = BlinnExact, const N: usize = 1> {
    view: Mat4,
    proj: Mat4,
    map: Projector,
    objects: heapless::Vec<ObjectSetup<Sp>, N>,
}

impl<Sp: Specular, const N: usize> FrameSetup<Sp, N> {
    /// The setup of no frame, for a `static` to start from: [`Frame::prepare_from`]
    /// rejects it until [`FrameSetup::set`] has made it a scene's.
    pub const EMPTY: Self = FrameSetup {
        view: Mat4 { m: [[0; 4]; 4] },
        proj: Mat4 { m: [[0; 4]; 4] },
        map: Projector::UNSET,
        objects: heapless::Vec::new(),
    };

    /// The setup of `scene` for a frame of `width` × `height` pixels.
    ///
    /// # Errors
    ///
    /// As [`FrameSetup::set`].
    pub fn new(scene: &Scene<'_>, width: u32, height: u32) -> Result<Self, RenderError> {
        let mut s = Self::EMPTY;
        s.set(scene, width, height)?;
        Ok(s)
    }

    /// Makes this the setup of `scene` for a frame of `width` × `height` pixels, in
    /// place (a firmware's `static`, with no second copy on the stack).
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::render::FrameSetup;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut setup: FrameSetup = FrameSetup::EMPTY;
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Gray8>::prepare_from(&scene, &setup, &mut cache);
    /// assert_eq!(frame.err(), Some(RenderError::SetupMismatch));
    /// setup.set(&scene, 64, 48).unwrap();
    /// assert!(Frame::<Gray8>::prepare_from(&scene, &setup, &mut cache).is_ok());
    /// ```
    ///
    /// # Errors
    ///
    /// What [`Frame::prepare`] reports for the scene and size, and
    /// [`RenderError::SetupMismatch`] for a scene of more than `N` objects. The
    /// setup is then left empty: its size is `(0, 0)` and [`Frame::prepare_from`]
    /// rejects it.
    pub fn set(&mut self, scene: &Scene<'_>, width: u32, height: u32) -> Result<(), RenderError> {
        self.objects.clear();
        self.map = Projector::UNSET;
        let (view, proj, map) = frame_setup(scene, width, height)?;
        for (i, obj) in scene.objects.iter().enumerate() {
            let o = if self.objects.is_full() {
                Err(RenderError::SetupMismatch)
            } else {
                ObjectSetup::new(scene, i, obj, &view, &proj, &map)
            };
            match o {
                // Not full: the push succeeds.
                Ok(o) => {
                    let _ = self.objects.push(o);
                }
                Err(e) => {
                    self.objects.clear();
                    return Err(e);
                }
            }
        }
        (self.view, self.proj, self.map) = (view, proj, map);
        Ok(())
    }

    /// The frame's size in pixels, `(width, height)` (`(0, 0)` for
    /// [`FrameSetup::EMPTY`]).
    pub fn size(&self) -> (u32, u32) {
        (self.map.width, self.map.height)
    }

    /// Whether this setup was made for a scene like `scene`: not empty, with as
    /// many objects, each mesh of the same bound.
    fn fits(&self, scene: &Scene<'_>) -> bool {
        self.size() != (0, 0)
            && self.objects.len() == scene.objects.len()
            && self
                .objects
                .iter()
                .zip(scene.objects.iter())
                .all(|(s, o)| s.bound == o.mesh.bound())
    }
}

impl<Sp: Specular, const N: usize> core::fmt::Debug for FrameSetup<Sp, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("FrameSetup")
            .field("size", &self.size())
            .field("objects", &self.objects.len())
            .finish_non_exhaustive()
    }
}

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// The vertex cache entries a frame of `scene` needs: one per vertex
    /// ([`Scene::vertex_count`]), twice that under two-sided lighting
    /// ([`crate::effects::TwoSided`], whose back colours take the second half).
    ///
    /// ```
    /// use fixshade::effects::TwoSided;
    /// use fixshade::prelude::*;
    /// # let scene = fixshade::doc_support::scene();
    /// assert_eq!(Frame::<Gray8>::cache_len(&scene), 3);
    /// assert_eq!(Frame::<Gray8, TwoSided>::cache_len(&scene), 6);
    /// ```
    pub fn cache_len(scene: &Scene<'_>) -> usize {
        if Sp::two_sided() {
            2 * scene.vertex_count()
        } else {
            scene.vertex_count()
        }
    }

    /// [`Frame::cache_len`] of `scene`, or [`RenderError::CacheTooSmall`] for a
    /// cache of `len` entries that holds fewer.
    #[inline(always)]
    fn checked_cache_len(scene: &Scene<'_>, len: usize) -> Result<usize, RenderError> {
        let needed = Self::cache_len(scene);
        if len < needed {
            return Err(RenderError::CacheTooSmall { needed });
        }
        Ok(needed)
    }

    /// Every object with what its draw needs of the vertex stage.
    pub(super) fn prepared(&self) -> impl Iterator<Item = (&'s Object<'a>, Prepared<'_>)> + '_ {
        let scene: &'s Scene<'a> = self.scene;
        scene
            .objects
            .iter()
            .zip(self.offsets.iter())
            .map(move |(obj, &offset)| {
                (
                    obj,
                    Prepared {
                        offset,
                        obj,
                        view: &self.view,
                        proj: &self.proj,
                        map: &self.vp,
                        clip: core::cell::OnceCell::new(),
                    },
                )
            })
    }

    /// The cache entries of an object's `n` vertices from `offset`, front and back:
    /// the back entries hold the back colours of two-sided lighting; one-sided,
    /// they are the front entries again.
    #[inline(always)]
    pub(super) fn sides(&self, offset: usize, n: usize) -> (&[XfVertex], &[XfVertex]) {
        let front = &self.cache[offset..offset + n];
        if Sp::two_sided() {
            let b = self.back + offset;
            (front, &self.cache[b..b + n])
        } else {
            (front, front)
        }
    }

    /// An object's lighting setup for its back faces under two-sided lighting: the
    /// back material, or the front one when it has none.
    pub(super) fn back_lighting(&self, obj: &Object<'_>, view: &Mat4) -> LightingSetup<Sp> {
        LightingSetup::<Sp>::new(
            &self.scene.lights,
            view,
            obj.back_material.unwrap_or(&obj.material),
            self.scene.global_ambient,
            self.scene.local_viewer,
        )
    }

    /// The frame's view matrix (the camera's, as [`Frame::prepare`] built it).
    pub(super) fn view(&self) -> &Mat4 {
        &self.view
    }

    /// Builds an object's lighting setup for this frame's specular model.
    pub(super) fn lighting(&self, obj: &Object<'_>, view: &Mat4) -> LightingSetup<Sp> {
        LightingSetup::<Sp>::new(
            &self.scene.lights,
            view,
            &obj.material,
            self.scene.global_ambient,
            self.scene.local_viewer,
        )
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
}

/// The eye-space unit normal (Q2.30) of a mesh normal under `aff`'s normal matrix;
/// `(0, 0, 1)` for a zero normal.
pub(super) fn eye_normal(aff: &Affine3, n: &[crate::fixed::Q2_14; 3]) -> [i32; 3] {
    let nm = &aff.normal;
    let nv = arrays::map(*n, |c| c.to_bits());
    // Entries < 2^31, components < 2^15: sums of three < 2^48.
    let ne: [i64; 3] = arrays::from_fn(|r| {
        mul_wide_16(nm[r][0], nv[0]) + mul_wide_16(nm[r][1], nv[1]) + mul_wide_16(nm[r][2], nv[2])
    });
    normalize_to_q30(ne).unwrap_or([0, 0, ONE_Q30])
}

/// Projects a clipped vertex ([`Projector::project_clip`]): clamps what rounding in
/// the clipper may have pushed a hair outside (depth to [0, 1], x and y into the
/// guard band); a vertex the vertex stage projected gets its cached position.
/// `None` only if `w ≤ 0`.
pub(super) fn project_clamped(vp: &Projector, c: [i64; 4]) -> Option<(i32, i32, u32)> {
    vp.project_clip(c)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::geometry::Mesh;
    use crate::raster::span::Gradient;
    use crate::raster::GUARD;
    use crate::scene::ShadingMode;
    use std::vec::Vec;

    fn xorshift(seed: &mut u64) -> u64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        *seed
    }

    /// The cull pass marks exactly what `classify_refs` over the whole frame keeps,
    /// and counts the back faces and zero areas it skips (of the triangles with no
    /// vertex outside), with and without back-face culling and with either form of
    /// the area: small and huge triangles, zero areas, vertices outside the guard
    /// band, triangles beside every edge of the frame.
    #[test]
    fn cull_pass_marks_what_classify_keeps() {
        let mut seed = 0x0bad_cafe_1234_5678u64;
        let vp = Viewport {
            width: 320,
            height: 240,
        };
        for round in 0..400 {
            // Spreads from a few subpixels to the whole guard band.
            let spread = 1i64 << (2 + round % 15);
            let centre = |r: u64, size: u32| (r % (16 * size as u64 + 64)) as i64 - 32;
            let mut verts = [XfVertex::default(); 64];
            let (cx, cy) = (
                centre(xorshift(&mut seed), vp.width) * 16,
                centre(xorshift(&mut seed), vp.height) * 16,
            );
            for v in verts.iter_mut() {
                let mut c = |base: i64| {
                    let d = (xorshift(&mut seed) % (2 * spread as u64 + 1)) as i64 - spread;
                    (base + d).clamp(-(GUARD as i64) + 1, GUARD as i64 - 1) as i32
                };
                v.s.x = c(cx);
                v.s.y = c(cy);
                if round % 2 == 0 && xorshift(&mut seed) % 16 == 0 {
                    v.flags = OUTSIDE;
                }
            }
            // Some exact zero areas: repeated and collinear vertices.
            verts[1].s = verts[0].s;
            verts[3].s.x = 2 * verts[2].s.x - verts[4].s.x;
            verts[3].s.y = 2 * verts[2].s.y - verts[4].s.y;
            let tris: [[u16; 3]; 96] = core::array::from_fn(|_| {
                core::array::from_fn(|_| (xorshift(&mut seed) % 64) as u16)
            });
            for cull in [false, true] {
                let mut want = verts;
                let mut skipped = Stats::default();
                for tri in &tris {
                    let t = tri.map(|i| &verts[i as usize]);
                    match classify_refs(t, cull, &vp, 0..vp.height as i32) {
                        Class::Skip(why) => skipped.skip(why),
                        _ => {
                            for i in tri {
                                want[*i as usize].flags |= NEEDED;
                            }
                        }
                    }
                }
                let want_dropped = Dropped {
                    back: skipped.culled,
                    degenerate: skipped.degenerate,
                };
                for small in [false, true] {
                    let mut got = verts;
                    let dropped = match (cull, small) {
                        (false, false) => mark_needed::<false, true, false>(&mut got, &tris, &vp),
                        (false, true) => mark_needed::<false, true, true>(&mut got, &tris, &vp),
                        (true, false) => mark_needed::<true, true, false>(&mut got, &tris, &vp),
                        (true, true) => mark_needed::<true, true, true>(&mut got, &tris, &vp),
                    };
                    // Without the flags when no vertex is outside.
                    if verts.iter().all(|v| v.flags & OUTSIDE == 0) {
                        let mut fast = verts;
                        let fast_dropped = match (cull, small) {
                            (false, false) => {
                                mark_needed::<false, false, false>(&mut fast, &tris, &vp)
                            }
                            (false, true) => {
                                mark_needed::<false, false, true>(&mut fast, &tris, &vp)
                            }
                            (true, false) => {
                                mark_needed::<true, false, false>(&mut fast, &tris, &vp)
                            }
                            (true, true) => mark_needed::<true, false, true>(&mut fast, &tris, &vp),
                        };
                        assert_eq!(fast, want, "round {round} cull {cull} small {small}");
                        assert_eq!(fast_dropped, want_dropped, "round {round} cull {cull}");
                    }
                    assert_eq!(got, want, "round {round} cull {cull} small {small}");
                    assert_eq!(
                        dropped, want_dropped,
                        "round {round} cull {cull} small {small}"
                    );
                }
            }
        }
    }

    /// The walk skips the triangles the cull pass dropped on their vertex flags
    /// alone and counts them from the pass's counts: the same bytes and the same
    /// [`Stats`], reason by reason, as classifying every triangle (what a frame
    /// without the counts, a resumed one, does), over random scenes with and
    /// without culling, whole and in bands, with a span method that snaps.
    #[test]
    fn skipping_on_the_flags_draws_and_counts_as_classifying() {
        use crate::raster::sierpinski::Sierpinski;
        use crate::raster::span::SpanMethod;
        use crate::target::{Rgb565Le, Strip};
        fn draw<S: SpanMethod>(
            frame: &Frame<'_, '_, '_, Rgb565Le>,
            (w, h): (u32, u32),
        ) -> (Vec<u16>, Stats) {
            let n = (w * h) as usize;
            let (mut px, mut z) = (std::vec![0u16; n], std::vec![u16::MAX; n]);
            let mut st = Stats::default();
            // Bands of 7, 33 and the rest of the rows, then the whole frame.
            for (y0, rows) in [(0, 7), (7, 33), (40, h - 40)] {
                let a = (y0 * w) as usize..((y0 + rows) * w) as usize;
                let mut strip =
                    Strip::<Rgb565Le>::new(&mut px[a.clone()], Some(&mut z[a]), w, h, y0, rows)
                        .unwrap();
                st += frame.draw::<S, _>(&mut strip).unwrap();
            }
            let (mut whole, mut zw) = (std::vec![0u16; n], std::vec![u16::MAX; n]);
            let mut strip = Strip::<Rgb565Le>::new(&mut whole, Some(&mut zw), w, h, 0, h).unwrap();
            st += frame.draw::<S, _>(&mut strip).unwrap();
            assert_eq!(px, whole);
            (px, st)
        }
        let mut seed = 0x5eed_f1a9_0000_7777u64;
        let size = (96, 72);
        let (mut flagged_back, mut flagged_outside) = (0, 0);
        for round in 0..80 {
            let (pos, nrm, tris) = random_mesh(&mut seed);
            let mut scene = random_scene(&mut seed, &pos, &nrm, &tris);
            scene.cull_back = round % 3 != 0;
            let mut cache = std::vec![XfVertex::default(); scene.vertex_count()];
            let mut frame = Frame::<Rgb565Le>::prepare(&scene, size.0, size.1, &mut cache).unwrap();
            let counts = frame.dropped.expect("the vertex stage ran the cull pass");
            let (g, gs) = draw::<Gradient>(&frame, size);
            let (k, ks) = draw::<Sierpinski>(&frame, size);
            frame.dropped = None;
            let (g0, gs0) = draw::<Gradient>(&frame, size);
            let (k0, ks0) = draw::<Sierpinski>(&frame, size);
            assert!(
                g == g0 && gs == gs0,
                "round {round}: gradient {gs:?} {gs0:?}"
            );
            assert!(
                k == k0 && ks == ks0,
                "round {round}: sierpinski {ks:?} {ks0:?}"
            );
            flagged_back += counts.back;
            flagged_outside += gs.outside;
        }
        // The rounds cull back faces and drop triangles off the frame.
        assert!(
            flagged_back > 1000 && flagged_outside > 1000,
            "{flagged_back} {flagged_outside}"
        );
    }

    /// A scene of random meshes under random cameras: some vertices behind the
    /// near plane, beyond the far plane, outside the guard band.
    fn random_scene<'a>(
        seed: &mut u64,
        pos: &'a [Vec3],
        nrm: &'a [[crate::fixed::Q2_14; 3]],
        tris: &'a [[u16; 3]],
    ) -> Scene<'a> {
        use crate::fixed::{Angle, Q16_16};
        use crate::light::{Light, LightKind, Material};
        use crate::scene::{Camera, Placement};
        let q = |v: i64| Q16_16::from_bits(v as i32);
        let mut r = |range: i64| (xorshift(seed) % (2 * range as u64 + 1)) as i64 - range;
        let eye = [q(r(6 << 16)), q(r(6 << 16)), q(8 << 16)];
        let mut camera =
            Camera::perspective(eye, [q(0); 3], Angle::from_degrees(30 + r(25) as i32));
        if r(3) == 3 {
            camera.projection = Projection::Orthographic {
                height: q(4 << 16),
                near: q(1 << 16),
                far: q(14 << 16),
            };
        } else {
            camera = camera.with_depth_range(q((1 << 15) + r(1 << 15)), q((12 << 16) + r(4 << 16)));
        }
        let mut scene = Scene::new(camera);
        let white = [Q16_16::ONE; 3];
        let _ = scene.add_light(Light::directional(
            [q(r(1 << 16)), q(1 << 16), q(r(1 << 16))],
            white,
            white,
        ));
        if r(1) == 1 {
            let mut lamp = Light::directional([q(0); 3], [q(40000); 3], [q(50000); 3]);
            lamp.kind = LightKind::Point {
                position: [q(r(3 << 16)), q(2 << 16), q(3 << 16)],
                attenuation: [Q16_16::ONE, q(3000), q(700)],
            };
            lamp.ambient = [q(3000); 3];
            let _ = scene.add_light(lamp);
        }
        scene.local_viewer = r(1) == 1;
        scene.global_ambient = [q(5000); 3];
        let mesh = Mesh::new(pos, nrm, tris).unwrap();
        let mat = Material {
            specular: [q(40000); 3],
            shininess: Q16_16::from_int(1 + r(20) as i32 + 20),
            ..Material::default()
        };
        let placement = Placement {
            translate: [q(r(1 << 16)), q(r(1 << 16)), q(r(1 << 16))],
            rotate: [
                Angle::from_degrees(r(180) as i32),
                Angle::from_degrees(r(180) as i32),
                Angle::default(),
            ],
            scale: q((1 << 16) + r(1 << 15)),
        };
        let _ = scene.add_object(crate::scene::Object {
            mesh,
            placement,
            material: mat,
            back_material: None,
        });
        scene
    }

    /// Random mesh data: positions within ±3 units, unit normals (Q2.14),
    /// triangles over them.
    fn random_mesh(seed: &mut u64) -> (Vec<Vec3>, Vec<[crate::fixed::Q2_14; 3]>, Vec<[u16; 3]>) {
        use crate::fixed::{Q16_16, Q2_14};
        let n = 300;
        let mut pos = Vec::new();
        let mut nrm = Vec::new();
        for _ in 0..n {
            let p: [i64; 3] =
                core::array::from_fn(|_| (xorshift(seed) % (6 << 16)) as i64 - (3 << 16));
            pos.push(p.map(|c| Q16_16::from_bits(c as i32)));
            let d: [i64; 3] = core::array::from_fn(|_| (xorshift(seed) % 2001) as i64 - 1000);
            let u = normalize_to_q30(d).unwrap_or([0, 0, ONE_Q30]);
            nrm.push(u.map(|c| Q2_14::from_bits(((c + (1 << 15)) >> 16) as i16)));
        }
        let tris = (0..2 * n)
            .map(|_| core::array::from_fn(|_| (xorshift(seed) % n as u64) as u16))
            .collect();
        (pos, nrm, tris)
    }

    /// Every vertex the vertex stage projected gets the same position and depth
    /// from the clipper's path (`project_clamped` of `VertexTransform::transform`):
    /// a triangle that goes through the clipper meets its unclipped neighbours
    /// exactly.
    #[test]
    fn clip_path_reproduces_the_vertex_stage() {
        let mut seed = 0x5eed_0001_dead_beefu64;
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..200 {
            let (pos, nrm, tris) = random_mesh(&mut seed);
            let scene = random_scene(&mut seed, &pos, &nrm, &tris);
            let mut cache = Vec::new();
            cache.resize(scene.vertex_count(), XfVertex::default());
            let frame = Frame::<crate::target::Rgb888>::prepare(
                &scene,
                160 + (xorshift(&mut seed) % 200) as u32,
                120,
                &mut cache,
            )
            .unwrap();
            let (_, prep) = frame.prepared().next().unwrap();
            for (v, p) in frame.cache.iter().zip(pos.iter()) {
                if v.flags & OUTSIDE != 0 {
                    outside += 1;
                    continue;
                }
                inside += 1;
                let c = prep.clip().transform(p);
                assert_eq!(
                    project_clamped(&frame.vp, c),
                    Some((v.s.x, v.s.y, v.s.z)),
                    "{c:?}"
                );
            }
        }
        assert!(inside > 10_000 && outside > 1_000, "{inside} {outside}");
    }

    /// Two-sided lighting: the front half of the vertex cache is the one-sided
    /// vertex stage's, the back half holds every needed vertex lit with its
    /// negated normal and the back material; with back faces culled, every shading
    /// draws the one-sided pixels.
    #[test]
    fn two_sided_vertex_stage_and_culled_frames() {
        use crate::effects::TwoSided;
        use crate::fixed::Q16_16;
        use crate::light::Material;
        use crate::target::{Framebuffer, Rgb888};
        let mut seed = 0x2515_1dedu64;
        let (w, h) = (96u32, 72u32);
        let shadings = [
            ShadingMode::Gouraud,
            ShadingMode::Flat,
            ShadingMode::Phong,
            ShadingMode::QuadraticSurface,
        ];
        let mut backs = 0;
        for round in 0..40 {
            let back = Material {
                diffuse: [Q16_16::from_ratio(1, 3), Q16_16::ONE, Q16_16::ZERO],
                ..Material::default()
            };
            let (pos, nrm, tris) = random_mesh(&mut seed);
            let mut scene = random_scene(&mut seed, &pos, &nrm, &tris);
            scene.objects[0].back_material = Some(&back);
            scene.shading = shadings[round % shadings.len()];
            let n = scene.vertex_count();
            let mut one = std::vec![XfVertex::default(); n];
            let mut two = std::vec![XfVertex::default(); 2 * n];
            let f1 = Frame::<Rgb888>::prepare(&scene, w, h, &mut one).unwrap();
            let f2 = Frame::<Rgb888>::prepare_with::<TwoSided>(&scene, w, h, &mut two).unwrap();
            assert_eq!(&f2.cache[..n], f1.cache);
            let view = scene.camera.view().unwrap();
            let obj = &scene.objects[0];
            let aff = Affine3::new(&view.mul(&obj.placement.matrix())).unwrap();
            let light = f2.back_lighting(obj, &view);
            for ((v, b), (p, nn)) in f2.cache[..n]
                .iter()
                .zip(&f2.cache[n..])
                .zip(pos.iter().zip(nrm.iter()))
            {
                if v.flags & NEEDED == 0 {
                    continue;
                }
                let unit = eye_normal(&aff, nn).map(|c| -c);
                let want = to_channels::<Rgb888>(light.shade(aff.point(p), unit));
                assert_eq!(b.s.c, want);
                backs += 1;
            }
            let draw = |frame: &dyn Fn(&mut Framebuffer<'_, Rgb888>) -> Stats| {
                let mut px = std::vec![[0u8; 3]; (w * h) as usize];
                let mut z = std::vec![0xFFFFu16; (w * h) as usize];
                let st = frame(&mut Framebuffer::new(&mut px, Some(&mut z), w, h).unwrap());
                (px, st)
            };
            let a = draw(&|fb| f1.draw::<Gradient, _>(fb).unwrap());
            let b = draw(&|fb| f2.draw::<Gradient, _>(fb).unwrap());
            assert_eq!(a, b, "round {round}");
        }
        assert!(backs > 5_000, "{backs}");
    }

    /// The vertex stage's colours are the eye-space setup's (`LightingSetup::shade`
    /// of the eye-space normal and position); the object-space lighting
    /// (`ObjectLighting`, which the vertex stage does not use) against them: within
    /// 2⁻¹⁰ of the full scale per channel, and on average within 2⁻¹⁵ — both work
    /// from the mesh's Q2.14 normals; the object-space directions are Q1.15 and
    /// `cⁿ` amplifies N·H's rounding n-fold.
    #[test]
    fn object_lighting_matches_eye_space() {
        let mut seed = 0x0b1e_c7ed_1234_4321u64;
        let (mut worst, mut sum, mut count) = (0i64, 0i64, 0i64);
        for _ in 0..150 {
            let (pos, nrm, tris) = random_mesh(&mut seed);
            let scene = random_scene(&mut seed, &pos, &nrm, &tris);
            let mut cache = Vec::new();
            cache.resize(scene.vertex_count(), XfVertex::default());
            let frame =
                Frame::<crate::target::Rgb888>::prepare(&scene, 320, 240, &mut cache).unwrap();
            let view = scene.camera.view().unwrap();
            let obj = &scene.objects[0];
            let mv = view.mul(&obj.placement.matrix());
            let aff = Affine3::new(&mv).unwrap();
            let light = frame.lighting(obj, &view);
            let object = light.for_object(&mv);
            for ((v, p), n) in frame.cache.iter().zip(pos.iter()).zip(nrm.iter()) {
                if v.flags & NEEDED == 0 {
                    continue;
                }
                let want = to_channels::<crate::target::Rgb888>(
                    light.shade(aff.point(p), eye_normal(&aff, n)),
                );
                // The vertex stage lights in eye space: the same colour.
                assert_eq!(v.s.c, want);
                let got = to_channels::<crate::target::Rgb888>(object.shade(p, n));
                for (g, w) in got.iter().zip(want) {
                    let d = (*g as i64 - w as i64).abs();
                    worst = worst.max(d);
                    sum += d;
                    count += 1;
                }
            }
        }
        let full = 255i64 << 16;
        std::eprintln!("worst {worst} mean {} of {full}", sum / count.max(1));
        assert!(count > 10_000, "{count}");
        assert!(worst * 1024 <= full, "worst {worst}");
        assert!(sum * (1 << 15) <= full * count, "mean {}", sum / count);
    }
}
