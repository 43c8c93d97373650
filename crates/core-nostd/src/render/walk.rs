//! The triangle walk: the one loop over every object and triangle of a prepared
//! frame, for every shading mode and for the binning of bands.
//!
//! Contract: the walk counts each triangle ([`Stats::triangles`]), reads its three
//! cached vertices (and back colours, for two-sided lighting), classifies it
//! ([`classify_refs`]: culled, zero-area or outside the target's rows are skipped
//! and counted; inside the guard band it is drawn; otherwise clipped) and counts
//! the outcome ([`Stats::drawn`], [`Stats::clipped`]). A shading mode says only how
//! a triangle is set up and filled, and how a clipped one is: a [`TriangleFill`],
//! monomorphised into the walk, so each mode's loop is compiled as if written out.
//! The clipper's fan ([`Triangle::clip_fan_with`]) is likewise written once: it
//! projects the clipped polygon, culls and counts its pieces, and hands each piece
//! to the fill.

use crate::arrays;
use core::ops::Range;

use super::frame::{
    classify, classify_refs, is_back, project_clamped, Class, Dropped, Frame, Prepared,
    RenderError, Stats, XfVertex, NEEDED, OUTSIDE,
};
use crate::clip::{clip_triangle, is_front, signed_area, ClipVertex, Polygon, MAX_POLY};
use crate::geometry::Projector;
use crate::raster::ScreenVertex;
use crate::scene::Object;
use crate::specular::Specular;
use crate::target::PixelFormat;

/// One shading mode's part of the triangle walk ([`Frame::walk`]): how a triangle
/// inside the guard band is set up and filled, and how one that needs the clipper
/// is. Implemented by each mode's fill state (which holds the target).
pub(super) trait TriangleFill<P: PixelFormat, Sp: Specular> {
    /// What the fill keeps per object (its lighting setups); `()` for the fills that
    /// draw the vertex stage's colours.
    type PerObject: ObjectSetup<P, Sp>;

    /// Whether the vertices move to the span method's grid before the triangle is
    /// classified again ([`crate::raster::span::SpanMethod::SNAPS`]).
    const SNAPS: bool = false;

    /// Moves a vertex to the span method's grid (only with [`TriangleFill::SNAPS`]).
    #[inline(always)]
    fn snap(v: ScreenVertex) -> ScreenVertex {
        v
    }

    /// Sets up and fills a triangle lying inside the guard band; returns the pixels
    /// it covered (the walk counts it drawn). Counts in `st` what else it did
    /// ([`Stats::evaluations`], [`Stats::per_pixel`]).
    fn inside(&mut self, o: &Self::PerObject, tri: &Triangle<'_, '_>, st: &mut Stats) -> u32;

    /// Draws a triangle that goes through the clipper (the walk counts it clipped),
    /// usually through [`Triangle::clip_fan_with`], which counts the pieces drawn
    /// and their pixels.
    fn clipped(&mut self, o: &Self::PerObject, tri: &Triangle<'_, '_>, st: &mut Stats);
}

/// What a [`TriangleFill`] keeps per object, made before the object's triangles.
pub(super) trait ObjectSetup<P: PixelFormat, Sp: Specular>: Sized {
    /// The setup of object number `index` of `frame`.
    fn new(
        frame: &Frame<'_, '_, '_, P, Sp>,
        index: usize,
        obj: &Object<'_>,
    ) -> Result<Self, RenderError>;
}

/// Nothing kept.
impl<P: PixelFormat, Sp: Specular> ObjectSetup<P, Sp> for () {
    #[inline(always)]
    fn new(_: &Frame<'_, '_, '_, P, Sp>, _: usize, _: &Object<'_>) -> Result<(), RenderError> {
        Ok(())
    }
}

/// A triangle as the walk hands it to a [`TriangleFill`].
pub(super) struct Triangle<'v, 'o> {
    /// Its vertices in the vertex cache (copies moved to the grid for a fill that
    /// snaps).
    pub(super) v: [&'v XfVertex; 3],
    /// Its back colours under two-sided lighting ([`crate::effects::TwoSided`]);
    /// one-sided, the same entries as `v`.
    pub(super) back: [&'v XfVertex; 3],
    /// Its indices into the object's mesh.
    pub(super) idx: [u16; 3],
    /// Its object.
    pub(super) obj: &'o Object<'o>,
    /// What the draw keeps of the object's vertex stage.
    pub(super) prep: &'o Prepared<'o>,
    /// The frame's projection, for the clipper.
    pub(super) vp: &'o Projector,
    /// Whether the clipper's pieces are culled as back faces.
    pub(super) cull: bool,
}

impl Triangle<'_, '_> {
    /// The screen vertices, in place.
    #[inline(always)]
    pub(super) fn screen(&self) -> [&ScreenVertex; 3] {
        [&self.v[0].s, &self.v[1].s, &self.v[2].s]
    }

    /// Whether the triangle takes the back colours or the back material: a back
    /// face under two-sided lighting (the sign test of culling).
    #[inline(always)]
    pub(super) fn faces_back<Sp: Specular>(&self) -> bool {
        Sp::two_sided() && is_back(self.screen())
    }

    /// The colour of vertex `k` for Gouraud (`interpolate`) or flat shading (the
    /// last vertex's), from the front or the `back` colours.
    #[inline(always)]
    pub(super) fn colour(&self, k: usize, interpolate: bool, back: bool) -> [i32; 3] {
        let v = if back { self.back } else { self.v };
        if interpolate {
            v[k].s.c
        } else {
            v[2].s.c
        }
    }

    /// The screen vertices with the colours [`Triangle::colour`] gives them.
    #[inline(always)]
    pub(super) fn coloured(&self, interpolate: bool, back: bool) -> [ScreenVertex; 3] {
        arrays::from_fn(|k| ScreenVertex {
            c: self.colour(k, interpolate, back),
            ..self.v[k].s
        })
    }

    /// The clip-space w of the vertices, recomputed (the vertex cache keeps none).
    #[inline(always)]
    pub(super) fn clip_w(&self) -> [i64; 3] {
        let pos = self.obj.mesh.positions();
        arrays::map(self.idx, |i| self.prep.clip().w(&pos[i as usize]) as i64)
    }

    /// The vertices for the clipper: clip-space positions, recomputed, and the
    /// attributes `attr(k)` of vertex `k`.
    #[inline(always)]
    pub(super) fn clip_vertices<const N: usize>(
        &self,
        attr: impl Fn(usize) -> [i32; N],
    ) -> [ClipVertex<N>; 3] {
        let pos = self.obj.mesh.positions();
        arrays::from_fn(|k| ClipVertex {
            pos: self.prep.clip().transform(&pos[self.idx[k] as usize]),
            c: attr(k),
        })
    }

    /// Clips the triangle with the vertex colours of Gouraud (`interpolate`) or flat
    /// shading, and under two-sided lighting the back colours too, and hands each
    /// piece of the fan to `draw` (see [`Triangle::clip_fan_with`]) with the colours
    /// of its facing.
    #[inline(always)]
    pub(super) fn clip_coloured<Sp: Specular>(
        &self,
        interpolate: bool,
        st: &mut Stats,
        draw: impl FnMut([ScreenVertex; 3], [i64; 3]) -> u32,
    ) {
        if Sp::two_sided() {
            let cv = self.clip_vertices(|k| {
                let f = self.colour(k, interpolate, false);
                let r = self.colour(k, interpolate, true);
                [f[0], f[1], f[2], r[0], r[1], r[2]]
            });
            clip_fan_colours(self, cv, st, draw);
        } else {
            let cv = self.clip_vertices(|k| self.colour(k, interpolate, false));
            clip_fan_colours(self, cv, st, draw);
        }
    }

    /// The clipper's fan, for any vertex type `V`: clips `t` (the triangle's
    /// vertices with `N` attributes each), projects the polygon (nothing is drawn if
    /// a vertex cannot be), and for each triangle of its fan that is not degenerate
    /// and not culled builds its vertices with `vertex` (screen position,
    /// attributes, whether the triangle faces front), hands them to `draw` with
    /// their clip-space w and facing, and counts it and the pixels `draw` returns
    /// in `st`.
    #[inline(always)]
    pub(super) fn clip_fan_with<const N: usize, V: Copy>(
        &self,
        t: [ClipVertex<N>; 3],
        st: &mut Stats,
        vertex: impl Fn((i32, i32, u32), &[i32; N], bool) -> V,
        mut draw: impl FnMut([V; 3], [i64; 3], bool) -> u32,
    ) {
        let Some((poly, sv, w)) = clip_project(t, self.vp) else {
            return;
        };
        for i in 1..poly.len.saturating_sub(1) {
            let k = [0, i, i + 1];
            let xy = arrays::map(k, |k| (sv[k].0, sv[k].1));
            let front = is_front(xy[0], xy[1], xy[2]);
            let area = signed_area(xy[0], xy[1], xy[2]);
            if area == 0 || (self.cull && !front) {
                continue;
            }
            let v = arrays::map(k, |k| vertex(sv[k], &poly.v[k].c, front));
            st.drawn += 1;
            st.pixels += draw(v, arrays::map(k, |k| w[k]), front);
        }
    }
}

/// Clips `t` and projects the polygon: its vertices, their screen positions and
/// their clip-space w; `None` if a vertex cannot be projected (w <= 0). Not
/// inlined: one copy for each attribute count serves every fill, which keeps the
/// clipper's code out of each fill's walk (flash on the small chips).
#[inline(never)]
#[allow(clippy::type_complexity)]
fn clip_project<const N: usize>(
    t: [ClipVertex<N>; 3],
    vp: &Projector,
) -> Option<(Polygon<N>, [(i32, i32, u32); MAX_POLY], [i64; MAX_POLY])> {
    let poly = clip_triangle(t, vp);
    let mut sv = [(0, 0, 0); MAX_POLY];
    let mut w = [0i64; MAX_POLY];
    for ((o, ow), v) in sv
        .iter_mut()
        .zip(w.iter_mut())
        .zip(poly.v[..poly.len].iter())
    {
        *o = project_clamped(vp, v.pos)?;
        *ow = v.pos[3];
    }
    Some((poly, sv, w))
}

/// [`Triangle::clip_fan_with`] with colours: `N` = 3 attributes a vertex (its
/// colour), or 6 (front colour, then back colour: each piece takes the colours of
/// its facing, the same sign test as culling).
fn clip_fan_colours<const N: usize>(
    tri: &Triangle<'_, '_>,
    t: [ClipVertex<N>; 3],
    st: &mut Stats,
    mut draw: impl FnMut([ScreenVertex; 3], [i64; 3]) -> u32,
) {
    let vertex = |(x, y, z), c: &[i32; N], front: bool| {
        let k = if front || N < 6 { 0 } else { 3 };
        ScreenVertex {
            x,
            y,
            z,
            c: [c[k], c[k + 1], c[k + 2]],
        }
    };
    tri.clip_fan_with(t, st, vertex, |v, w, _| draw(v, w));
}

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// Walks every triangle of the frame that may cover the frame rows `rows`,
    /// drawing it with `fill` (see the [module docs](self)).
    ///
    /// When this frame's vertex stage ran the cull pass ([`Frame::dropped`]), a
    /// triangle with a vertex not [`NEEDED`] is one the pass dropped, and it is
    /// skipped on the flags alone: the pass classified it over the whole frame as
    /// [`classify_refs`] does, and a triangle it keeps marks all three vertices. The
    /// walk counts those by reason from the pass's counts: each back face and each
    /// zero area of the frame was dropped by the pass, so the walk's own counts of
    /// the two (on the triangles it classifies, by the same tests) are short by
    /// exactly the ones skipped on the flags; the rest of those lie outside the
    /// frame, and so outside any rows.
    ///
    /// A fill that snaps ([`TriangleFill::SNAPS`]) is culled on the moved vertices,
    /// and only triangles drawable before the move are drawn (the vertex stage lit
    /// only their vertices): a sliver that turns front by snapping is dropped (a
    /// documented coverage exception). That first test is on the triangle itself
    /// over the whole frame, so the result does not depend on its neighbours or on
    /// the target's rows; snapped vertices are then classified again.
    #[inline(always)]
    pub(super) fn walk<F: TriangleFill<P, Sp>>(
        &self,
        rows: Range<i32>,
        fill: &mut F,
    ) -> Result<Stats, RenderError> {
        let mut st = Stats::default();
        // The skips of the classification the cull pass made (the only one, or
        // the first of a fill that snaps), and the triangles not skipped on the
        // flags (counted on that path: most triangles are skipped).
        let (mut first, mut classified) = (Stats::default(), 0u32);
        let cull = self.scene.cull_back;
        for (i, (obj, prep)) in self.prepared().enumerate() {
            let o = F::PerObject::new(self, i, obj)?;
            let (verts, backs) = self.sides(prep.offset, obj.mesh.positions().len());
            // Below 2^32 (a mesh that many triangles would take 24 GiB).
            st.triangles += obj.mesh.triangles().len() as u32;
            for &idx in obj.mesh.triangles() {
                // The three vertices, read in place.
                let v = arrays::map(idx, |i| &verts[i as usize]);
                if self.dropped.is_some() && v[0].flags & v[1].flags & v[2].flags & NEEDED == 0 {
                    continue;
                }
                classified += 1;
                let snapped;
                let (v, class) = if F::SNAPS {
                    let mut t = arrays::map(v, |v| *v);
                    let whole = 0..self.vp.height as i32;
                    if let Class::Skip(why) = classify(&t, cull, &self.vp, whole) {
                        first.skip(why);
                        continue;
                    }
                    for v in t.iter_mut().filter(|v| v.flags & OUTSIDE == 0) {
                        v.s = F::snap(v.s);
                    }
                    snapped = t;
                    let class = classify(&snapped, cull, &self.vp, rows.clone());
                    ([&snapped[0], &snapped[1], &snapped[2]], class)
                } else {
                    (v, classify_refs(v, cull, &self.vp, rows.clone()))
                };
                // A skipped triangle (most are: culled) builds nothing more.
                let drawn = match class {
                    Class::Skip(why) => {
                        // Without snapping, the rows' classification gives each
                        // triangle the pass dropped its reason (outside the frame
                        // is outside any rows); those it kept, at most `Outside`.
                        if F::SNAPS {
                            st.skip(why);
                        } else {
                            first.skip(why);
                        }
                        continue;
                    }
                    Class::Draw => true,
                    Class::Clip => false,
                };
                let tri = Triangle {
                    v,
                    back: arrays::map(idx, |i| &backs[i as usize]),
                    idx,
                    obj,
                    prep: &prep,
                    vp: &self.vp,
                    cull,
                };
                if drawn {
                    st.drawn += 1;
                    st.pixels += fill.inside(&o, &tri, &mut st);
                } else {
                    st.clipped += 1;
                    fill.clipped(&o, &tri, &mut st);
                }
            }
        }
        count_skips(&mut st, &first, classified, self.dropped);
        Ok(st)
    }
}

/// Adds to `st` the triangles a walk skipped: `first`, its own counts (back faces,
/// zero areas, outside) of the classification the cull pass made, and with the
/// pass's counts (`dropped`) those it skipped on the flags, the `st.triangles`
/// less the `classified` (see [`Frame::walk`]). Out of line: one copy for every
/// fill's walk (flash on the small chips).
#[inline(never)]
fn count_skips(st: &mut Stats, first: &Stats, classified: u32, dropped: Option<Dropped>) {
    match dropped {
        // Each count of the pass is at least the walk's (see `Frame::walk`);
        // saturating all the same: never a panic.
        Some(d) => {
            st.culled += d.back;
            st.degenerate += d.degenerate;
            let flagged = st.triangles.saturating_sub(classified);
            st.outside += first
                .skipped()
                .saturating_add(flagged)
                .saturating_sub(d.back)
                .saturating_sub(d.degenerate);
        }
        None => {
            st.culled += first.culled;
            st.degenerate += first.degenerate;
            st.outside += first.outside;
        }
    }
}
