//! Does switching an unused effect off cost anything? A diffuse-only frame through
//! the generic pipeline against a hand-specialised diffuse-only path.
//!
//! Scene: the built-in "sphere" with every specular colour set to zero (two
//! directional lights, diffuse only).
//!
//! 1. Vertex lighting: every vertex of the sphere lit by
//!    - `LightingSetup::<NoSpecular>::shade` (the generic lighting, specular term
//!      compiled out: what a derived diffuse frame runs),
//!    - `LightingSetup::<BlinnExact>::shade` (specular code present, skipped at run
//!      time because no light has a specular colour),
//!    - a hand-written diffuse-only loop over directional lights (no specular code,
//!      no local viewer, no point lights), checked to give the same colours.
//!
//!    Every variant gets each vertex's position and normal through `black_box`,
//!    the hand loop too (it ignores the position), so all three load the same
//!    inputs.
//! 2. Whole frames (vertex stage + Gouraud draw, no depth buffer) with
//!    `Frame::<_, NoSpecular>` and `Frame::<_, BlinnExact>`.
//!
//! The variants alternate within each round (the order swaps every round) and the
//! ratio printed is the median of the per-round ratios, so machine drift hits all
//! alike.
//!
//! Run: `cargo run --release -p fixshade-sim --example effects_bench [-- ROUNDS]`
//! (default 301).

use std::hint::black_box;
use std::time::Instant;

use fixshade::effects::NoSpecular;
use fixshade::fixed::Q16_16;
use fixshade::light::{LightKind, LightingSetup};
use fixshade::math::{dot_q30, normalize_to_q30, Affine3};
use fixshade::raster::span::{Gradient, NoDepth};
use fixshade::render::{Frame, XfVertex};
use fixshade::shade::Gouraud;
use fixshade::specular::BlinnExact;
use fixshade::target::{Framebuffer, Rgb565Le};
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::load;

fn mul_q16(a: Q16_16, b: Q16_16) -> i64 {
    (a.to_bits() as i64 * b.to_bits() as i64 + (1 << 15)) >> 16
}

/// Diffuse-only lighting of directional lights, written out by hand.
struct HandDiffuse {
    base: [i64; 3],
    lights: Vec<([i32; 3], [i64; 3], [i64; 3])>,
}

impl HandDiffuse {
    #[inline(never)]
    fn shade(&self, n: [i32; 3]) -> [i32; 3] {
        let mut acc = self.base;
        for (l, amb, dif) in &self.lights {
            for k in 0..3 {
                acc[k] += amb[k];
            }
            let nl = dot_q30(n, *l);
            if nl <= 0 {
                continue;
            }
            let f = ((1i64 << 16) * nl as i64) >> 30;
            for k in 0..3 {
                acc[k] += (dif[k] * f) >> 16;
            }
        }
        acc.map(|c| c.clamp(0, 1 << 16) as i32)
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(301);
    let mut ls = load::load_arg("sphere").expect("built-in scene");
    for l in &mut ls.desc.lights {
        l.specular = [0.0; 3];
    }
    for o in &mut ls.desc.objects {
        o.material.specular = [0.0; 3];
    }
    let scene = core_scene(&ls.desc, &ls.fixed).expect("scene converts");
    let view = scene.camera.view().expect("view");
    let obj = &scene.objects[0];
    let aff = Affine3::new(&view.mul(&obj.placement.matrix())).expect("model");
    // Eye-space positions and unit normals of every vertex.
    let verts: Vec<([i32; 3], [i32; 3])> = obj
        .mesh
        .positions()
        .iter()
        .zip(obj.mesh.normals())
        .map(|(p, n)| {
            let nv = n.map(|c| c.to_bits() as i64);
            let ne: [i64; 3] = core::array::from_fn(|r| {
                (0..3).map(|c| aff.normal[r][c] as i64 * nv[c]).sum::<i64>()
            });
            (aff.point(p), normalize_to_q30(ne).expect("normal"))
        })
        .collect();
    let m = &obj.material;
    let generic = LightingSetup::<NoSpecular>::new(
        &scene.lights,
        &view,
        m,
        scene.global_ambient,
        scene.local_viewer,
    );
    let runtime = LightingSetup::<BlinnExact>::new(
        &scene.lights,
        &view,
        m,
        scene.global_ambient,
        scene.local_viewer,
    );
    let hand = HandDiffuse {
        base: core::array::from_fn(|i| {
            m.emission[i].to_bits() as i64 + mul_q16(scene.global_ambient[i], m.ambient[i])
        }),
        lights: scene
            .lights
            .iter()
            .map(|l| {
                let LightKind::Directional { direction } = l.kind else {
                    panic!("the sphere scene has directional lights only");
                };
                let d = view.transform_dir(direction);
                (
                    normalize_to_q30(d).expect("direction"),
                    core::array::from_fn(|k| mul_q16(l.ambient[k], m.ambient[k])),
                    core::array::from_fn(|k| mul_q16(l.diffuse[k], m.diffuse[k])),
                )
            })
            .collect(),
    };
    for (p, n) in &verts {
        let g = generic.shade(*p, *n);
        assert_eq!(g, hand.shade(*n), "hand-written lighting differs");
        assert_eq!(g, runtime.shade(*p, *n));
    }

    // 1. Vertex lighting.
    let time = |f: &dyn Fn() -> i64| {
        let t = Instant::now();
        black_box(f());
        t.elapsed().as_secs_f64()
    };
    let run_generic = || {
        verts
            .iter()
            .map(|(p, n)| generic.shade(black_box(*p), black_box(*n))[0] as i64)
            .sum()
    };
    let run_runtime = || {
        verts
            .iter()
            .map(|(p, n)| runtime.shade(black_box(*p), black_box(*n))[0] as i64)
            .sum()
    };
    let run_hand = || {
        verts
            .iter()
            .map(|(p, n)| {
                // The same inputs as the generic calls: the position goes through
                // `black_box` as well (the hand loop has no use for it).
                black_box(*p);
                hand.shade(black_box(*n))[0] as i64
            })
            .sum()
    };
    let (mut g_h, mut r_h, mut tg) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        let (a, b, c) = if round % 2 == 0 {
            (time(&run_generic), time(&run_runtime), time(&run_hand))
        } else {
            let c = time(&run_hand);
            let b = time(&run_runtime);
            (time(&run_generic), b, c)
        };
        g_h.push(a / c);
        r_h.push(b / c);
        tg.push(a);
    }
    println!(
        "vertex lighting, {} vertices, {rounds} rounds (median of per-round ratios):",
        verts.len()
    );
    println!(
        "  generic NoSpecular           {:8.1} ns/vertex   {:.3} x hand-written",
        1e9 * median(tg) / verts.len() as f64,
        median(g_h)
    );
    println!(
        "  generic BlinnExact (k_s = 0)                     {:.3} x hand-written",
        median(r_h)
    );

    // 2. Whole frames.
    let (w, h) = (ls.desc.width, ls.desc.height);
    let n = (w * h) as usize;
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut color = vec![0u16; n];
    let mut frame_ns = |spec: bool| {
        let t = Instant::now();
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, None, w, h).expect("fb");
        let st = if spec {
            Frame::<Rgb565Le>::prepare_with::<BlinnExact>(&scene, w, h, &mut cache)
                .expect("frame")
                .draw_with::<Gradient, NoDepth, Gouraud, _>(&mut fb)
        } else {
            Frame::<Rgb565Le>::prepare_with::<NoSpecular>(&scene, w, h, &mut cache)
                .expect("frame")
                .draw_with::<Gradient, NoDepth, Gouraud, _>(&mut fb)
        };
        black_box(st.expect("draw"));
        t.elapsed().as_secs_f64()
    };
    let (mut ratio, mut tn) = (Vec::new(), Vec::new());
    for round in 0..rounds {
        let (a, b) = if round % 2 == 0 {
            let a = frame_ns(false);
            (a, frame_ns(true))
        } else {
            let b = frame_ns(true);
            (frame_ns(false), b)
        };
        ratio.push(a / b);
        tn.push(a);
    }
    println!("whole frame {w}x{h}, Gouraud, no depth buffer:");
    println!(
        "  Frame<NoSpecular> {:8.1} us   {:.3} x Frame<BlinnExact> (k_s = 0)",
        1e6 * median(tn),
        median(ratio)
    );
}
