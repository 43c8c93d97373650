//! Strip rendering gives the same bytes as rendering the whole frame.
//!
//! * The figures through the host pipeline, both span methods, strips of 1, 7, 16
//!   and 240 rows against the whole frame.
//! * Random overlapping Gouraud triangles with a depth test, drawn directly into
//!   strips whose boundaries cut exactly through vertex rows (the row whose centre
//!   a vertex lies on or just above, and its neighbours) and through rows in
//!   between, against one full framebuffer: colour and depth byte for byte.
//! * A frame prepared from a [`FrameSetup`] (what a board drawing a mesh chunk by
//!   chunk keeps per frame): every figure and every scene of the hard-case
//!   catalogue, one- and two-sided, give the vertex cache of `Frame::prepare`;
//!   each mesh cut into chunks of 64 triangles and prepared chunk by chunk from
//!   one setup gives every chunk vertex the whole mesh's bits; a setup used with
//!   the wrong scene is refused.

use fixshade::effects::TwoSided;
use fixshade::fixed::Q2_14;
use fixshade::geometry::Mesh;
use fixshade::math::Vec3;
use fixshade::raster::edge::first_row;
use fixshade::raster::span::{Classic, DepthTest, Gradient, SpanMethod};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::render::{Frame, FrameSetup, RenderError, XfVertex, NEEDED, OUTSIDE};
use fixshade::scene::{Scene, MAX_OBJECTS};
use fixshade::shade::Gouraud;
use fixshade::specular::{BlinnExact, Specular};
use fixshade::target::{Framebuffer, Rgb565Le, Rgb888, Strip};
use fixshade_sim::render;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::{ShadingName, SpanName};
use fixshade_sim::scene::load::load_arg;
use fixshade_tests::catalogue::scene_cases;
use fixshade_tests::*;

#[test]
fn figures_strips_equal_whole_frame() {
    for name in FIGURES {
        let mut ls = load_arg(name).unwrap();
        for span in [SpanName::GRADIENT, SpanName::CLASSIC] {
            ls.desc.span = span;
            let whole = render::render(&ls, None).unwrap();
            assert!(whole.image.covered_count() > 5000);
            for rows in [1, 7, 16, 240] {
                let strips = render::render(&ls, Some(rows)).unwrap();
                let differ = whole
                    .bytes
                    .iter()
                    .zip(&strips.bytes)
                    .filter(|(a, b)| a != b)
                    .count();
                assert_eq!(whole.bytes.len(), strips.bytes.len());
                assert_eq!(
                    differ, 0,
                    "{name} {span:?}: strips of {rows} rows differ from the whole frame in {differ} bytes"
                );
            }
        }
    }
}

/// The fill-bound bench sphere at 640×480 in one-, two- and three-row strips: here
/// `classic` once differed from the whole frame (its edge values were evaluated
/// afresh at a strip's first row instead of stepped from the triangle half's own),
/// caught by the Cortex-M0 firmware, which renders in strips.
#[test]
fn bench_sphere_640_strips_equal_whole_frame() {
    let mut ls = load_arg("bench-sphere").unwrap();
    ls.desc.width = 640;
    ls.desc.height = 480;
    for (span, shading) in [
        (SpanName::CLASSIC, ShadingName::GOURAUD),
        (SpanName::GRADIENT, ShadingName::GOURAUD),
        (SpanName::named("sierpinski"), ShadingName::GOURAUD),
        (SpanName::GRADIENT, ShadingName::PHONG),
    ] {
        ls.desc.span = span;
        ls.desc.shading = shading;
        let whole = render::render(&ls, None).unwrap();
        for rows in [1, 2, 3] {
            let strips = render::render(&ls, Some(rows)).unwrap();
            assert!(
                whole.bytes == strips.bytes,
                "{span:?} {shading:?}: strips of {rows} rows differ from the whole frame"
            );
        }
    }
}

const W: u32 = 160;
const H: u32 = 120;

fn draw_all<S: SpanMethod, T: fixshade::target::Target<Rgb888>>(
    t: &mut T,
    tris: &[[ScreenVertex; 3]],
) {
    for v in tris {
        draw_triangle::<Rgb888, _, S, DepthTest, Gouraud>(t, *v);
    }
}

/// Whole frame: colour and depth.
fn whole<S: SpanMethod>(tris: &[[ScreenVertex; 3]]) -> (Vec<[u8; 3]>, Vec<u16>) {
    let n = (W * H) as usize;
    let mut c = vec![[1, 2, 3]; n];
    let mut d = vec![0xFFFF; n];
    let mut fb = Framebuffer::<Rgb888>::new(&mut c, Some(&mut d), W, H).unwrap();
    draw_all::<S, _>(&mut fb, tris);
    (c, d)
}

/// The frame assembled from strips `[cuts[i], cuts[i + 1])`.
fn stripped<S: SpanMethod>(tris: &[[ScreenVertex; 3]], cuts: &[u32]) -> (Vec<[u8; 3]>, Vec<u16>) {
    let n = (W * H) as usize;
    let mut c = vec![[9, 9, 9]; n];
    let mut d = vec![0; n];
    for s in cuts.windows(2) {
        let (y0, h) = (s[0], s[1] - s[0]);
        let m = (W * h) as usize;
        let mut sc = vec![[7, 7, 7]; m];
        let mut sd = vec![0; m];
        let mut strip = Strip::<Rgb888>::new(&mut sc, Some(&mut sd), W, H, y0, h).unwrap();
        strip.clear([1, 2, 3]);
        draw_all::<S, _>(&mut strip, tris);
        let at = (y0 * W) as usize;
        c[at..at + m].copy_from_slice(&sc);
        d[at..at + m].copy_from_slice(&sd);
    }
    (c, d)
}

fn random_scene(rng: &mut Rng) -> Vec<[ScreenVertex; 3]> {
    let k = rng.range(1, 12) as usize;
    (0..k)
        .map(|_| {
            let (cx, cy) = (
                rng.int(-200, 16 * W as i32 + 200),
                rng.int(-200, 16 * H as i32 + 200),
            );
            let s = *rng.pick(&[40, 300, 1200, 3000]);
            std::array::from_fn(|_| {
                let y = cy + rng.int(-s, s);
                // Vertex rows: on a row centre, on a row edge, or anywhere.
                let y = match rng.below(3) {
                    0 => (y & !15) + 8,
                    1 => y & !15,
                    _ => y,
                };
                ScreenVertex {
                    x: cx + rng.int(-s, s),
                    y,
                    z: rng.below(65534 << 16) as u32,
                    c: std::array::from_fn(|_| rng.int(0, 255 << 16)),
                }
            })
        })
        .collect()
}

/// Strip boundaries: every row a vertex starts (its first row, and the rows just
/// before and after), plus a few random ones.
fn cuts_through_vertices(rng: &mut Rng, tris: &[[ScreenVertex; 3]]) -> Vec<u32> {
    let mut cuts = vec![0, H];
    for v in tris.iter().flatten() {
        let r = first_row(v.y);
        for c in [r - 1, r, r + 1] {
            if c > 0 && c < H as i32 && rng.chance(2, 3) {
                cuts.push(c as u32);
            }
        }
    }
    for _ in 0..3 {
        cuts.push(rng.int(1, H as i32 - 1) as u32);
    }
    cuts.sort_unstable();
    cuts.dedup();
    cuts
}

fn compare_scene<S: SpanMethod>(i: usize, tris: &[[ScreenVertex; 3]], cuts: &[u32]) -> usize {
    let (wc, wd) = whole::<S>(tris);
    let (sc, sd) = stripped::<S>(tris, cuts);
    let bad: Vec<usize> = (0..wc.len())
        .filter(|&k| wc[k] != sc[k] || wd[k] != sd[k])
        .collect();
    assert!(
        bad.is_empty(),
        "[{}] scene {i} cut at rows {cuts:?}: {} pixels differ, first at ({}, {}): whole {:?}/{} strips {:?}/{}\n{tris:?}",
        S::NAME,
        bad.len(),
        bad[0] % W as usize,
        bad[0] / W as usize,
        wc[bad[0]],
        wd[bad[0]],
        sc[bad[0]],
        sd[bad[0]]
    );
    wc.iter().filter(|p| **p != [1, 2, 3]).count()
}

#[test]
fn strips_cut_through_vertex_rows() {
    let mut rng = Rng::new(0x57_1195);
    let n = scaled(800, 400);
    let (mut covered, mut strips) = (0, 0);
    for i in 0..n {
        let tris = random_scene(&mut rng);
        let cuts = cuts_through_vertices(&mut rng, &tris);
        strips += cuts.len() - 1;
        covered += compare_scene::<Gradient>(i, &tris, &cuts);
        compare_scene::<Classic>(i, &tris, &cuts);
        // One-row strips everywhere.
        if i % 10 == 0 {
            let all: Vec<u32> = (0..=H).collect();
            compare_scene::<Gradient>(i, &tris, &all);
            compare_scene::<Classic>(i, &tris, &all);
        }
    }
    println!("strips: {n} scenes, {strips} strips, {covered} covered pixels compared (×2 methods)");
    assert!(covered > 1000);
}

/// The comparison is not a tautology: a strip drawn with one triangle left out
/// differs from the whole frame.
#[test]
fn strip_comparison_detects_a_difference() {
    let tris = [[
        ScreenVertex {
            x: 8,
            y: 8,
            z: 0,
            c: [255 << 16, 0, 0],
        },
        ScreenVertex {
            x: 8,
            y: 16 * 100 + 8,
            z: 0,
            c: [0, 255 << 16, 0],
        },
        ScreenVertex {
            x: 16 * 100,
            y: 8,
            z: 0,
            c: [0, 0, 255 << 16],
        },
    ]];
    let (wc, _) = whole::<Gradient>(&tris);
    let (sc, _) = stripped::<Gradient>(&tris, &[0, 50, H]);
    assert_eq!(wc, sc);
    let (sc2, _) = stripped::<Gradient>(&[], &[0, 50, H]);
    assert_ne!(wc, sc2);
}

/// The vertex cache of `Frame::prepare_with::<Sp>`, of `prepare_from` a setup,
/// and, chunk by chunk, of each object's mesh cut into runs of 64 triangles
/// (each chunk alone in the scene, with its object's bound) prepared from the
/// setup of the scene holding that object alone: the same bits.
/// A chunk of 64 consecutive triangles of a mesh, as the micro:bit images bake
/// them: its vertices renumbered in order of first use.
struct Chunk {
    /// The mesh's index of each chunk vertex.
    used: Vec<usize>,
    pos: Vec<Vec3>,
    nrm: Vec<[Q2_14; 3]>,
    tris: Vec<[u16; 3]>,
}

impl Chunk {
    /// `scene` with its first object's mesh swapped for this chunk, which carries
    /// the whole mesh's bound.
    fn scene<'p>(&'p self, scene: &Scene<'p>) -> Scene<'p> {
        let mut part = scene.clone();
        let bound = scene.objects[0].mesh.bound();
        part.objects[0].mesh = Mesh::new(&self.pos, &self.nrm, &self.tris)
            .unwrap()
            .with_bound(bound);
        part
    }
}

/// `m` cut into chunks of 64 consecutive triangles.
fn chunks(m: &Mesh<'_>) -> Vec<Chunk> {
    m.triangles()
        .chunks(64)
        .map(|tris| {
            let mut map = vec![u16::MAX; m.positions().len()];
            let mut used = Vec::new();
            let tris = tris
                .iter()
                .map(|t| {
                    t.map(|i| {
                        if map[i as usize] == u16::MAX {
                            map[i as usize] = used.len() as u16;
                            used.push(i as usize);
                        }
                        map[i as usize]
                    })
                })
                .collect();
            Chunk {
                pos: used.iter().map(|&i| m.positions()[i]).collect(),
                nrm: used.iter().map(|&i| m.normals()[i]).collect(),
                used,
                tris,
            }
        })
        .collect()
}

fn check_setup<Sp: Specular>(name: &str, scene: &Scene<'_>, (w, h): (u32, u32)) {
    let n = Frame::<Rgb565Le, Sp>::cache_len(scene);
    let mut whole = vec![XfVertex::default(); n];
    Frame::<Rgb565Le>::prepare_with::<Sp>(scene, w, h, &mut whole).unwrap();
    let setup = FrameSetup::<Sp, MAX_OBJECTS>::new(scene, w, h).unwrap();
    let mut from = vec![XfVertex::default(); n];
    Frame::<Rgb565Le, Sp>::prepare_from(scene, &setup, &mut from).unwrap();
    assert!(from == whole, "{name}: prepare_from differs from prepare");
    for (k, obj) in scene.objects.iter().enumerate() {
        let mut alone = scene.clone();
        alone.objects.clear();
        alone.add_object(*obj).unwrap();
        let mut one = vec![XfVertex::default(); Frame::<Rgb565Le, Sp>::cache_len(&alone)];
        Frame::<Rgb565Le>::prepare_with::<Sp>(&alone, w, h, &mut one).unwrap();
        let setup = FrameSetup::<Sp>::new(&alone, w, h).unwrap();
        let m = &obj.mesh;
        let count = m.positions().len();
        for c in chunks(m) {
            let used = &c.used;
            let part = c.scene(&alone);
            let mut cache = vec![XfVertex::default(); Frame::<Rgb565Le, Sp>::cache_len(&part)];
            Frame::<Rgb565Le, Sp>::prepare_from(&part, &setup, &mut cache).unwrap();
            let back = (Sp::two_sided(), used.len(), count);
            for (j, &i) in used.iter().enumerate() {
                let (c, o) = (cache[j], one[i]);
                assert_eq!(c.flags & OUTSIDE, o.flags & OUTSIDE, "{name} object {k}");
                if c.flags & OUTSIDE == 0 {
                    assert_eq!(
                        (c.s.x, c.s.y, c.s.z),
                        (o.s.x, o.s.y, o.s.z),
                        "{name} object {k}"
                    );
                }
                // A vertex some drawable triangle of the chunk uses is one of the
                // whole mesh's too: lit alike, front and back.
                if c.flags & NEEDED != 0 {
                    assert!(o.flags & NEEDED != 0, "{name} object {k}");
                    assert_eq!(c.s.c, o.s.c, "{name} object {k}: colour");
                    if back.0 {
                        assert_eq!(
                            cache[back.1 + j].s.c,
                            one[back.2 + i].s.c,
                            "{name} object {k}: back colour"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn frames_prepared_from_a_setup_equal_prepared_frames() {
    let mut scenes: Vec<(String, fixshade_sim::scene::load::LoadedScene)> = FIGURES
        .iter()
        .map(|n| (n.to_string(), load_arg(n).unwrap()))
        .collect();
    scenes.extend(
        scene_cases()
            .into_iter()
            .map(|c| (c.name.clone(), c.load().unwrap())),
    );
    let mut chunked = 0;
    for (name, ls) in &scenes {
        let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
        let size = (ls.desc.width, ls.desc.height);
        if scene.camera.view().is_none()
            || FrameSetup::<BlinnExact, MAX_OBJECTS>::new(&scene, size.0, size.1).is_err()
        {
            // The catalogue's invalid cameras and sizes: the setup reports what
            // prepare reports.
            let mut cache = vec![XfVertex::default(); scene.vertex_count()];
            assert_eq!(
                FrameSetup::<BlinnExact, MAX_OBJECTS>::new(&scene, size.0, size.1).err(),
                Frame::<Rgb565Le>::prepare(&scene, size.0, size.1, &mut cache).err(),
                "{name}"
            );
            continue;
        }
        check_setup::<BlinnExact>(name, &scene, size);
        check_setup::<TwoSided<BlinnExact>>(&format!("{name} two-sided"), &scene, size);
        chunked += scene
            .objects
            .iter()
            .filter(|o| o.mesh.triangles().len() > 64)
            .count();
    }
    assert!(chunked >= 3, "the figures are cut into chunks");

    // The wrong scene: another bound, another number of objects, the empty setup.
    let ls = load_arg("teapot").unwrap();
    let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
    let (w, h) = (ls.desc.width, ls.desc.height);
    let setup = FrameSetup::<BlinnExact>::new(&scene, w, h).unwrap();
    assert_eq!(setup.size(), (w, h));
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut other = scene.clone();
    let m = other.objects[0].mesh;
    other.objects[0].mesh = m.with_bound(m.bound() + 1);
    assert_eq!(
        Frame::<Rgb565Le>::prepare_from(&other, &setup, &mut cache).err(),
        Some(RenderError::SetupMismatch)
    );
    let mut two = scene.clone();
    two.add_object(scene.objects[0]).unwrap();
    assert_eq!(
        FrameSetup::<BlinnExact>::new(&two, w, h).err(),
        Some(RenderError::SetupMismatch)
    );
    let mut cache2 = vec![XfVertex::default(); two.vertex_count()];
    assert_eq!(
        Frame::<Rgb565Le>::prepare_from(&two, &setup, &mut cache2).err(),
        Some(RenderError::SetupMismatch)
    );
    assert_eq!(
        Frame::<Rgb565Le>::prepare_from(&scene, &FrameSetup::<BlinnExact>::EMPTY, &mut cache).err(),
        Some(RenderError::SetupMismatch)
    );
    let mut s = FrameSetup::<BlinnExact>::new(&scene, w, h).unwrap();
    assert_eq!(s.set(&two, w, h).err(), Some(RenderError::SetupMismatch));
    assert_eq!(s.size(), (0, 0), "a failed set leaves the empty setup");
    assert!(Frame::<Rgb565Le>::prepare_from(&scene, &s, &mut cache).is_err());
}

/// Draws `frame` with the gradient span into `color`/`depth` (a `w` × `h` frame).
fn draw_into<Sp: Specular>(
    frame: &Frame<'_, '_, '_, Rgb565Le, Sp>,
    color: &mut [u16],
    depth: &mut [u16],
    (w, h): (u32, u32),
) {
    let mut fb = Framebuffer::<Rgb565Le>::new(color, Some(depth), w, h).unwrap();
    frame.draw::<Gradient, _>(&mut fb).unwrap();
}

/// A frame resumed from a cache `prepare_from` filled ([`Frame::resume`]) draws
/// the prepared frame's bytes: every figure cut into chunks, each chunk prepared
/// into a cache of its own and drawn, then every chunk drawn again from its cache;
/// one- and two-sided. A cache of another chunk draws other bytes, and caches no
/// vertex stage writes are refused.
#[test]
fn frames_resumed_from_a_prepared_cache_draw_the_same_bytes() {
    fn check<Sp: Specular>(name: &str, scene: &Scene<'_>, (w, h): (u32, u32)) -> usize {
        let m = scene.objects[0].mesh;
        let setup = FrameSetup::<Sp>::new(scene, w, h).unwrap();
        let parts = chunks(&m);
        let n = (w * h) as usize;
        let (mut a, mut za) = (vec![0u16; n], vec![u16::MAX; n]);
        let (mut b, mut zb) = (vec![0u16; n], vec![u16::MAX; n]);
        let mut caches = Vec::new();
        for c in &parts {
            let part = c.scene(scene);
            let mut cache = vec![XfVertex::default(); Frame::<Rgb565Le, Sp>::cache_len(&part)];
            let frame = Frame::<Rgb565Le, Sp>::prepare_from(&part, &setup, &mut cache).unwrap();
            draw_into(&frame, &mut a, &mut za, (w, h));
            drop(frame);
            caches.push(cache);
        }
        for (c, cache) in parts.iter().zip(&caches) {
            let part = c.scene(scene);
            let frame = Frame::<Rgb565Le, Sp>::resume(&part, &setup, cache).unwrap();
            draw_into(&frame, &mut b, &mut zb, (w, h));
        }
        assert!(a.iter().any(|&p| p != 0), "{name}: something drawn");
        assert!(a == b && za == zb, "{name}: the resumed chunks differ");
        // A chunk that draws something, drawn from the previous chunk's cache (if
        // as large): other bytes.
        let mut swapped = 0;
        for (k, c) in parts.iter().enumerate().skip(1) {
            let prev = &caches[k - 1];
            let part = c.scene(scene);
            if prev.len() < Frame::<Rgb565Le, Sp>::cache_len(&part) {
                continue;
            }
            let (mut x, mut zx) = (vec![0u16; n], vec![u16::MAX; n]);
            let (mut y, mut zy) = (vec![0u16; n], vec![u16::MAX; n]);
            let right = Frame::<Rgb565Le, Sp>::resume(&part, &setup, &caches[k]).unwrap();
            draw_into(&right, &mut x, &mut zx, (w, h));
            if x.iter().all(|&p| p == 0) {
                continue; // back faces only
            }
            let wrong = Frame::<Rgb565Le, Sp>::resume(&part, &setup, prev).unwrap();
            draw_into(&wrong, &mut y, &mut zy, (w, h));
            assert!(
                x != y,
                "{name}: chunk {k} drawn alike from another chunk's cache"
            );
            swapped += 1;
        }
        swapped
    }
    let mut swapped = 0;
    for name in FIGURES {
        let ls = load_arg(name).unwrap();
        let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
        let size = (ls.desc.width, ls.desc.height);
        swapped += check::<BlinnExact>(name, &scene, size);
        swapped += check::<TwoSided<BlinnExact>>(&format!("{name} two-sided"), &scene, size);
    }
    assert!(
        swapped > 10,
        "chunks drawn from another chunk's cache: {swapped}"
    );

    // Refused: caches no vertex stage writes, and what prepare_from refuses.
    let ls = load_arg("teapot").unwrap();
    let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
    let (w, h) = (ls.desc.width, ls.desc.height);
    let setup = FrameSetup::<BlinnExact>::new(&scene, w, h).unwrap();
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    Frame::<Rgb565Le>::prepare_from(&scene, &setup, &mut cache).unwrap();
    assert!(Frame::<Rgb565Le>::resume(&scene, &setup, &cache).is_ok());
    let resume = |c: &[XfVertex]| Frame::<Rgb565Le>::resume(&scene, &setup, c).err();
    let k = cache.iter().position(|v| v.flags & OUTSIDE == 0).unwrap();
    let edit = |f: &dyn Fn(&mut XfVertex)| {
        let mut c = cache.clone();
        f(&mut c[k]);
        c
    };
    let guard = fixshade::raster::vertex::GUARD;
    for (what, bad) in [
        ("x at the guard band", edit(&|v| v.s.x = guard)),
        ("y below the guard band", edit(&|v| v.s.y = -guard)),
        ("depth past the range", edit(&|v| v.s.z = u32::MAX)),
        ("negative colour", edit(&|v| v.s.c[1] = -1)),
        ("colour of 2^30", edit(&|v| v.s.c[2] = 1 << 30)),
    ] {
        assert_eq!(resume(&bad), Some(RenderError::CacheNotPrepared), "{what}");
    }
    // Inside the guard band, and anything where the clipper takes the mesh instead.
    assert!(resume(&edit(&|v| v.s.x = guard - 1)).is_none());
    assert!(resume(&edit(&|v| {
        v.flags |= OUTSIDE;
        v.s.x = i32::MIN;
    }))
    .is_none());
    assert_eq!(
        resume(&cache[..cache.len() - 1]),
        Some(RenderError::CacheTooSmall {
            needed: cache.len()
        })
    );
    let mut other = scene.clone();
    let m = other.objects[0].mesh;
    other.objects[0].mesh = m.with_bound(m.bound() + 1);
    assert_eq!(
        Frame::<Rgb565Le>::resume(&other, &setup, &cache).err(),
        Some(RenderError::SetupMismatch)
    );
    assert_eq!(
        Frame::<Rgb565Le>::resume(&scene, &FrameSetup::<BlinnExact>::EMPTY, &cache).err(),
        Some(RenderError::SetupMismatch)
    );
    // Two-sided: the back half's colours are checked too.
    let mut two = vec![XfVertex::default(); 2 * scene.vertex_count()];
    let setup2 = FrameSetup::<TwoSided<BlinnExact>>::new(&scene, w, h).unwrap();
    Frame::<Rgb565Le, TwoSided<BlinnExact>>::prepare_from(&scene, &setup2, &mut two).unwrap();
    let last = two.len() - 1;
    two[last].s.c[0] = -5;
    assert_eq!(
        Frame::<Rgb565Le, TwoSided<BlinnExact>>::resume(&scene, &setup2, &two).err(),
        Some(RenderError::CacheNotPrepared)
    );
}
