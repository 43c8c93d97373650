//! The f64 reference renderer: the yardstick every accuracy figure is measured
//! against.
//!
//! It follows the same conventions as the fixed-point core, so that differences
//! between the two measure only the core's arithmetic:
//!
//! * OpenGL matrices (column vectors): model `T * Rz * Ry * Rx * S`, `gluLookAt`,
//!   `gluPerspective` / `glOrtho` ([`model_matrix`], [`view_matrix`],
//!   [`projection_matrix`]).
//! * OpenGL 1.x fixed-function lighting in eye space with `GL_NORMALIZE`
//!   ([`light_vertex`], [`LightingContext`]).
//! * Sutherland–Hodgman clipping against the near (`z >= -w`) and far (`z <= w`)
//!   planes in clip space, interpolating all attributes linearly in the clip-space
//!   parameter; the polygon is fan-triangulated from its first vertex.
//! * Screen vertices snapped to 1/16 pixel (`floor(X*16 + 0.5)`), y down, origin at
//!   the top-left image corner; exact integer coverage at pixel centres with the
//!   top-left rule; back faces (positive snapped area with y down) culled on request.
//! * Two-sided lighting on request (`GL_LIGHT_MODEL_TWO_SIDE`): a back face (the
//!   same sign test) is lit with the negated normals and the object's back material
//!   (its front material when it has none).
//! * Barycentric interpolation at pixel centres from the snapped positions:
//!   screen-affine or perspective-correct colours (Gouraud), the provoking (last)
//!   vertex's colour (flat), or per-pixel lighting (Phong); depth `(z_ndc+1)/2`
//!   interpolated affinely, strict less-than test.
//! * Channel quantisation `floor(c*m + 0.5)` for the output format, then
//!   `FormatName::expand`.
#![warn(missing_docs)]

mod lighting;
mod matrix;
mod raster;

#[cfg(test)]
mod tests;

pub use lighting::{light_vertex, EyeLight, EyeLightKind, LightingContext};
pub use matrix::{
    mat_mul, mat_vec, model_matrix, normal_matrix, projection_matrix, rotation, transform_dir,
    transform_point, translation, uniform_scale, view_matrix, Mat4, IDENTITY,
};

use crate::image::Image;
use crate::scene::convert::background8;
use crate::scene::desc::{FormatName, MaterialDesc, MeshData, SceneDesc, ShadingName};
use crate::scene::load::LoadedScene;

/// Options of the reference renderer that are not part of the scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RefOptions {
    /// Per-pixel (Phong) lighting: interpolate the eye-space normal and position,
    /// renormalise the normal and light every pixel. Overrides the scene's shading
    /// mode.
    pub phong: bool,
}

/// Snapped screen coordinates beyond this magnitude (1/16 pixel units, about 2^36
/// pixels) are treated as invalid and their polygon is skipped; real scenes never
/// come near it (clipping against the near plane keeps `w >= near`).
const MAX_SNAPPED: f64 = (1u64 << 40) as f64;

/// A vertex in clip space with everything that is interpolated.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ClipVertex {
    /// Clip-space position `(x, y, z, w)`.
    clip: [f64; 4],
    /// Lit, clamped colour (unused with Phong shading).
    colour: [f64; 3],
    /// The colour lit with the negated normal and the back material (two-sided
    /// lighting only; unused otherwise).
    back: [f64; 3],
    /// Eye-space normal (unit at the original vertices, not renormalised after
    /// interpolation).
    normal: [f64; 3],
    /// Eye-space position.
    eye: [f64; 3],
}

impl ClipVertex {
    /// `a + (b - a) * t` for every attribute.
    fn lerp(a: &ClipVertex, b: &ClipVertex, t: f64) -> ClipVertex {
        fn l<const N: usize>(a: [f64; N], b: [f64; N], t: f64) -> [f64; N] {
            std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t)
        }
        ClipVertex {
            clip: l(a.clip, b.clip, t),
            colour: l(a.colour, b.colour, t),
            back: l(a.back, b.back, t),
            normal: l(a.normal, b.normal, t),
            eye: l(a.eye, b.eye, t),
        }
    }
}

/// Signed distance to the near plane (`z >= -w`) inside when `>= 0`.
fn near_distance(v: &ClipVertex) -> f64 {
    v.clip[2] + v.clip[3]
}

/// Signed distance to the far plane (`z <= w`), inside when `>= 0`.
fn far_distance(v: &ClipVertex) -> f64 {
    v.clip[3] - v.clip[2]
}

/// One Sutherland–Hodgman pass against the plane `dist >= 0`. The intersection on
/// an edge is always computed from its inside end towards its outside end, so an
/// edge shared by two triangles is cut at the same point whatever its direction.
fn clip_against(poly: &[ClipVertex], dist: fn(&ClipVertex) -> f64) -> Vec<ClipVertex> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for (i, a) in poly.iter().enumerate() {
        let b = &poly[(i + 1) % poly.len()];
        let (da, db) = (dist(a), dist(b));
        if da >= 0.0 {
            out.push(*a);
        }
        if da >= 0.0 && db < 0.0 {
            out.push(ClipVertex::lerp(a, b, da / (da - db)));
        } else if da < 0.0 && db >= 0.0 {
            out.push(ClipVertex::lerp(b, a, db / (db - da)));
        }
    }
    out
}

/// Clips a triangle against the near and far planes; returns the convex polygon
/// (empty when nothing is left). Triangles entirely inside are returned unchanged.
fn clip_triangle(tri: [ClipVertex; 3]) -> Vec<ClipVertex> {
    let inside = |v: &ClipVertex| near_distance(v) >= 0.0 && far_distance(v) >= 0.0;
    if tri.iter().all(inside) {
        return tri.to_vec();
    }
    let poly = clip_against(&tri, near_distance);
    if poly.len() < 3 {
        return Vec::new();
    }
    let poly = clip_against(&poly, far_distance);
    if poly.len() < 3 {
        return Vec::new();
    }
    poly
}

/// A polygon vertex after the perspective division and viewport mapping.
#[derive(Clone, Copy, Debug)]
struct ScreenVertex {
    /// Snapped position, 1/16 pixel units, y down.
    pos: [i64; 2],
    /// `(z_ndc + 1) / 2`, not snapped.
    depth: f64,
    /// Clip-space w (for perspective-correct interpolation).
    w: f64,
    /// Interpolated attributes.
    v: ClipVertex,
}

/// Perspective division, viewport mapping and snapping; `None` for vertices that
/// cannot be mapped (w <= 0, non-finite or absurdly far coordinates).
fn to_screen(v: &ClipVertex, width: u32, height: u32) -> Option<ScreenVertex> {
    let [x, y, z, w] = v.clip;
    if w.is_nan() || w <= 0.0 {
        return None;
    }
    let (xn, yn, zn) = (x / w, y / w, z / w);
    let sx = (xn + 1.0) / 2.0 * width as f64;
    let sy = (1.0 - yn) / 2.0 * height as f64;
    let snap = |s: f64| {
        let q = (s * 16.0 + 0.5).floor();
        (q.is_finite() && q.abs() <= MAX_SNAPPED).then_some(q as i64)
    };
    Some(ScreenVertex {
        pos: [snap(sx)?, snap(sy)?],
        depth: (zn + 1.0) / 2.0,
        w,
        v: *v,
    })
}

/// Colour buffer and depth buffer being rendered into.
struct Target<'a> {
    scene: &'a SceneDesc,
    opts: &'a RefOptions,
    ctx: &'a LightingContext,
    image: Image,
    depth: Vec<f64>,
}

impl Target<'_> {
    /// Rasterises one (fan) triangle. `flat` is the colour of the original
    /// triangle's provoking vertex, front and back; `material` the front and back
    /// materials (the back ones used by two-sided lighting on back faces).
    fn draw_triangle(
        &mut self,
        t: [&ScreenVertex; 3],
        flat: [[f64; 3]; 2],
        material: [&MaterialDesc; 2],
    ) {
        let pos = [t[0].pos, t[1].pos, t[2].pos];
        let area = raster::signed_area(&pos);
        if area == 0 || (self.scene.cull_back && area > 0) {
            return;
        }
        // Two-sided lighting: a back face takes the back colours, or is lit per
        // pixel with the negated normal and the back material.
        let back = self.scene.two_sided && area > 0;
        let side = usize::from(back);
        let (flat, material) = (flat[side], material[side]);
        let sign = if back { -1.0 } else { 1.0 };
        let (width, height) = (self.scene.width, self.scene.height);
        let scene = self.scene;
        let (opts, ctx) = (self.opts, self.ctx);
        let image = &mut self.image;
        let zbuf = &mut self.depth;
        let inv_w = [1.0 / t[0].w, 1.0 / t[1].w, 1.0 / t[2].w];
        raster::rasterize(&pos, width, height, |x, y, b| {
            let idx = y as usize * width as usize + x as usize;
            let d = b[0] * t[0].depth + b[1] * t[1].depth + b[2] * t[2].depth;
            if scene.depth_test {
                if !((0.0..=1.0).contains(&d) && d < zbuf[idx]) {
                    return;
                }
                zbuf[idx] = d;
            }
            let q = if scene.perspective_correct {
                let q = [b[0] * inv_w[0], b[1] * inv_w[1], b[2] * inv_w[2]];
                let s = q[0] + q[1] + q[2];
                [q[0] / s, q[1] / s, q[2] / s]
            } else {
                b
            };
            let mix = |f: fn(&ClipVertex) -> [f64; 3]| -> [f64; 3] {
                let (a0, a1, a2) = (f(&t[0].v), f(&t[1].v), f(&t[2].v));
                std::array::from_fn(|i| q[0] * a0[i] + q[1] * a1[i] + q[2] * a2[i])
            };
            let colour = if opts.phong {
                let n = mix(|v| v.normal).map(|c| sign * c);
                light_vertex(ctx, mix(|v| v.eye), n, material)
            } else {
                match scene.shading {
                    ShadingName::FLAT => flat,
                    // Every other shading interpolates the vertex colours here: the
                    // quadratic surface's reference is the Phong render (`phong`),
                    // and the Phong shadings are lit per pixel above (`opts.phong`
                    // is forced).
                    _ if back => mix(|v| v.back),
                    _ => mix(|v| v.colour),
                }
            };
            debug_assert!(
                colour.iter().all(|c| c.is_finite()) && !d.is_nan(),
                "non-finite colour {colour:?} / depth {d} at ({x}, {y})"
            );
            image.pixels[idx] = quantise(scene.format, colour);
            image.covered[idx] = true;
        });
    }
}

/// Quantises a colour (channels 0..1) to the output format and expands it to 8 bits:
/// `floor(c * m + 0.5)` per channel with `m` = `FormatName::channel_max`; for a
/// grey format the grey `(77 r + 150 g + 29 b) / 256` (in f64) is quantised
/// the same way into all three channels.
pub fn quantise(format: FormatName, c: [f64; 3]) -> [u8; 3] {
    let m = format.channel_max();
    let q = |v: f64, max: u32| ((v * max as f64 + 0.5).floor().max(0.0) as u32).min(max);
    let ints = if format.is_gray() {
        let g = (77.0 * c[0] + 150.0 * c[1] + 29.0 * c[2]) / 256.0;
        [q(g, m[0]); 3]
    } else {
        [q(c[0], m[0]), q(c[1], m[1]), q(c[2], m[2])]
    };
    format.expand(ints)
}

/// The exact f64 reference that matches the scene's shading: per-pixel lighting
/// for Phong, the quadratic surface and adaptive shading, the scene's own shading
/// otherwise.
pub fn matching_reference(ls: &LoadedScene) -> Image {
    reference(ls, ls.desc.shading.phong_reference())
}

/// The f64 reference render of a loaded scene (per-pixel lighting if `phong`), with
/// the background quantised like the core's.
pub fn reference(ls: &LoadedScene, phong: bool) -> Image {
    let mut img = render_reference(&ls.desc, &ls.meshes, &RefOptions { phong });
    let bg = background8(&ls.desc);
    img.background = bg;
    for (p, c) in img.pixels.iter_mut().zip(&img.covered) {
        if !c {
            *p = bg;
        }
    }
    img
}

/// Renders `scene` in f64 following the project's normative conventions (see the
/// module documentation). `meshes[i]` is the mesh of `scene.objects[i]`, already
/// quantised by the caller; extra objects or meshes are ignored, as are triangles
/// with out-of-range indices (a missing normal counts as zero). Objects are drawn
/// in order, triangles in index order. The returned image has
/// `background = scene.background` and `covered` set on every written pixel.
pub fn render_reference(scene: &SceneDesc, meshes: &[MeshData], opts: &RefOptions) -> Image {
    // A Phong scene is lit per pixel whatever the options say.
    let opts = &RefOptions {
        phong: opts.phong
            || matches!(
                scene.shading,
                ShadingName::PHONG | ShadingName::PHONG_EVEN_ODD | ShadingName::ADAPTIVE
            ),
    };
    let (width, height) = (scene.width, scene.height);
    let view = view_matrix(&scene.camera);
    let proj = projection_matrix(&scene.camera, width as f64 / height as f64);
    let ctx = LightingContext::new(scene, &view);
    let mut target = Target {
        scene,
        opts,
        ctx: &ctx,
        image: Image::new(width, height, scene.background),
        depth: vec![f64::INFINITY; width as usize * height as usize],
    };
    for (obj, mesh) in scene.objects.iter().zip(meshes) {
        let model_view = mat_mul(&view, &model_matrix(obj));
        let nmat = normal_matrix(&model_view);
        let material = &obj.material;
        let back_material = obj.back_material.as_ref().unwrap_or(material);
        let verts: Vec<ClipVertex> = mesh
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let eye = transform_point(&model_view, p);
                let n = mesh.normals.get(i).copied().unwrap_or([0.0; 3]);
                let normal = matrix::normalize(transform_dir(&nmat, n));
                let colour = if opts.phong {
                    [0.0; 3]
                } else {
                    light_vertex(&ctx, eye, normal, material)
                };
                let back = if opts.phong || !scene.two_sided {
                    [0.0; 3]
                } else {
                    light_vertex(&ctx, eye, normal.map(|c| -c), back_material)
                };
                ClipVertex {
                    clip: mat_vec(&proj, [eye[0], eye[1], eye[2], 1.0]),
                    colour,
                    back,
                    normal,
                    eye,
                }
            })
            .collect();
        for tri in &mesh.triangles {
            let Some(tv) = tri
                .iter()
                .map(|&i| verts.get(i as usize).copied())
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let flat = [tv[2].colour, tv[2].back];
            let poly = clip_triangle([tv[0], tv[1], tv[2]]);
            let Some(screen) = poly
                .iter()
                .map(|v| to_screen(v, width, height))
                .collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            for i in 1..screen.len().saturating_sub(1) {
                target.draw_triangle(
                    [&screen[0], &screen[i], &screen[i + 1]],
                    flat,
                    [material, back_material],
                );
            }
        }
    }
    target.image
}
