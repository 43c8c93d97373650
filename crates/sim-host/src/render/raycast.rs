//! Ray casting on the host: the core's fixed-point ray caster
//! ([`fixshade::raycast`]) sampled by the adaptive pixel-segment sampler
//! ([`fixshade::sampler`], seed 002 §2.6). The measurement behind `docs/raycast.md`
//! is [`crate::tables::raycast`].
//!
//! Scene files select it with `shading = "raycast"`, `segment = L` and
//! `threshold = K` in `[render]`; `[[sphere]]` and `[[plane]]` tables add analytic
//! primitives that only the ray caster draws.

use std::time::{Duration, Instant};

use super::output::Render;
use crate::image::Image;
use crate::scene::convert::{
    background8, background_channels, core_scene, material, q16, threshold_q8,
};
use crate::scene::desc::SceneDesc;
use crate::scene::load::LoadedScene;
use fixshade::raycast::{Caster, Plane, RayPixels, RayScene, RayVertex, Sphere, TriBox};
use fixshade::render::Stats;
use fixshade::sampler::{fill_blocks, fill_row, PixelFn, Threshold};
use fixshade::specular::{BlinnExact, Specular};
use fixshade::target::PixelFormat;

/// How to sample: segment length, K, rows or blocks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Segment length L (1: every pixel).
    pub segment: u32,
    /// K in Q8 8-bit levels.
    pub k_q8: u32,
    /// Blocks instead of rows.
    pub block: bool,
}

impl Sampling {
    /// The sampling a scene asks for.
    pub fn of(d: &SceneDesc) -> Sampling {
        Sampling {
            segment: d.raycast.segment,
            k_q8: threshold_q8(d.raycast.threshold),
            block: d.raycast.block,
        }
    }

    /// Every pixel evaluated.
    pub const EVERY_PIXEL: Sampling = Sampling {
        segment: 1,
        k_q8: 0,
        block: false,
    };
}

/// A ray-cast image with its cost.
#[derive(Clone, Debug)]
pub struct RayImage {
    /// The image; `covered` marks evaluated pixels that hit something and
    /// interpolated pixels whose colour differs from the background.
    pub image: Image,
    /// Channel integers per pixel, row-major.
    pub channels: Vec<[u32; 3]>,
    /// Evaluations (primary rays) made.
    pub evaluations: u64,
    /// Evaluations per row (row sampling only; empty for blocks).
    pub row_evaluations: Vec<u32>,
    /// Wall time of the sampling (frame preparation excluded).
    pub time: Duration,
}

/// Counts hits of evaluated pixels.
struct Recording<'p, F: PixelFn> {
    inner: F,
    width: u32,
    background: [u32; 3],
    hit: &'p mut [bool],
}

impl<F: PixelFn> PixelFn for Recording<'_, F> {
    fn eval(&mut self, x: u32, y: u32) -> [u32; 3] {
        let c = self.inner.eval(x, y);
        if let Some(h) = self
            .hit
            .get_mut(y as usize * self.width as usize + x as usize)
        {
            *h = c != self.background;
        }
        c
    }
}

fn run<S: Specular, P: PixelFormat>(ls: &LoadedScene, s: Sampling) -> Result<RayImage, String> {
    let d = &ls.desc;
    if d.two_sided {
        return Err("two-sided lighting is not supported by the ray caster \
                    (shading = \"raycast\"); use a rasterizing shading"
            .into());
    }
    let scene = core_scene(d, &ls.fixed)?;
    let spheres: Vec<Sphere> = d
        .raycast
        .spheres
        .iter()
        .map(|s| Sphere {
            centre: s.centre.map(q16),
            radius: q16(s.radius),
            material: material(&s.material),
        })
        .collect();
    let planes: Vec<Plane> = d
        .raycast
        .planes
        .iter()
        .map(|p| Plane {
            point: p.point.map(q16),
            normal: p.normal.map(q16),
            material: material(&p.material),
        })
        .collect();
    let rs = RayScene {
        scene: &scene,
        spheres: &spheres,
        planes: &planes,
        shadows: d.raycast.shadows,
    };
    let (w, h) = (d.width, d.height);
    let mut cache = vec![RayVertex::default(); scene.vertex_count()];
    let mut boxes = vec![TriBox::default(); rs.triangle_count()];
    let caster =
        Caster::<S>::prepare(rs, w, h, &mut cache, &mut boxes).map_err(|e| e.to_string())?;
    let bg = background_channels(d.format, d.background);
    let n = w as usize * h as usize;
    let mut out = vec![[0u32; 3]; n];
    let mut hit = vec![false; n];
    let k = Threshold::from_q8(s.k_q8, P::MAX);
    let mut f = Recording {
        inner: RayPixels::<S, P>::new(&caster, bg),
        width: w,
        background: bg,
        hit: &mut hit,
    };
    let mut row_evaluations = Vec::new();
    let t = Instant::now();
    let evaluations = if s.block {
        fill_blocks(&mut f, w, h, s.segment, k, &mut out) as u64
    } else {
        row_evaluations.reserve(h as usize);
        for (y, row) in out.chunks_mut(w as usize).enumerate() {
            row_evaluations.push(fill_row(&mut f, y as u32, s.segment, k, row));
        }
        row_evaluations.iter().map(|e| *e as u64).sum()
    };
    let time = t.elapsed();
    let bg8 = background8(d);
    let pixels: Vec<[u8; 3]> = out.iter().map(|c| d.format.expand(*c)).collect();
    let covered = pixels
        .iter()
        .zip(&hit)
        .map(|(p, h)| *h || *p != bg8)
        .collect();
    Ok(RayImage {
        image: Image {
            width: w,
            height: h,
            pixels,
            covered,
            background: bg8,
        },
        channels: out,
        evaluations,
        row_evaluations,
        time,
    })
}

/// Ray casts `ls` with sampling `s` and the exact Blinn specular.
pub fn ray_image(ls: &LoadedScene, s: Sampling) -> Result<RayImage, String> {
    ray_image_with::<BlinnExact>(ls, s)
}

/// Ray casts `ls` with sampling `s` and the specular model `S`.
pub fn ray_image_with<S: Specular>(ls: &LoadedScene, s: Sampling) -> Result<RayImage, String> {
    with_format!(ls.desc.format, P => run::<S, P>(ls, s))
}

/// The `shading = "raycast"` render of the pipeline: the scene's own sampling.
pub fn render(ls: &LoadedScene) -> Result<Render, String> {
    fn pack<P: PixelFormat>(c: &[[u32; 3]]) -> Vec<u8> {
        c.iter()
            .flat_map(|c| {
                P::bytes(P::pack(c[0], c[1], c[2]))
                    .into_iter()
                    .take(P::BYTES)
            })
            .collect()
    }
    let r = ray_image(ls, Sampling::of(&ls.desc))?;
    let bytes = with_format!(ls.desc.format, P => pack::<P>(&r.channels));
    Ok(Render {
        image: r.image,
        bytes,
        stats: Stats::default(),
    })
}

/// Median wall time of the sampling of one ray-cast frame (the scene's own
/// sampling; frame preparation excluded) over `runs` runs.
pub fn time_frame(ls: &LoadedScene, runs: usize) -> Result<Duration, String> {
    let s = Sampling::of(&ls.desc);
    let mut t: Vec<Duration> = (0..runs.max(1))
        .map(|_| ray_image(ls, s).map(|r| r.time))
        .collect::<Result<_, _>>()?;
    t.sort();
    Ok(t[t.len() / 2])
}
