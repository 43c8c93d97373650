//! The span methods compute the same lattice values as the constant-gradient
//! method in a different order (even/odd, k-way, counter, segment, exact
//! Sierpinski); in exact integer arithmetic they must give the same bytes. Every
//! method of the core's registry is held to it but the approximations named in
//! [`APPROXIMATE`]. Checked on the three figures and on random triangles of every
//! size.

use fixshade::raster::span::{DepthTest, Gradient, SpanMethod};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::shade::Gouraud;
use fixshade::target::{Framebuffer, Rgb888};
use fixshade_sim::render;
use fixshade_sim::scene::desc::{Named, SpanName};
use fixshade_sim::scene::load;

/// The methods that do not give `gradient`'s bytes: the per-span division rounds
/// otherwise, and `sierpinski` snaps vertices to even pixels.
const APPROXIMATE: [&str; 2] = ["classic", "sierpinski"];

/// Every method that must give `gradient`'s bytes.
fn exact_methods() -> Vec<SpanName> {
    SpanName::ALL
        .iter()
        .map(|(s, _)| *s)
        .filter(|s| *s != SpanName::GRADIENT && !APPROXIMATE.contains(&s.name()))
        .collect()
}

#[test]
fn figures_are_bit_identical_to_gradient() {
    for fig in ["sphere", "teapot", "robot"] {
        let mut ls = load::load_arg(fig).unwrap();
        ls.desc.span = SpanName::GRADIENT;
        let want = render::render(&ls, None).unwrap().bytes;
        for m in exact_methods() {
            ls.desc.span = m;
            let got = render::render(&ls, None).unwrap().bytes;
            let diff = want.iter().zip(&got).filter(|(a, b)| a != b).count();
            assert_eq!(
                diff,
                0,
                "{fig}: {} differs from gradient in {diff} bytes",
                m.name()
            );
        }
    }
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as u32
    }
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo) as u32) as i32
    }
}

fn render<S: SpanMethod>(w: u32, h: u32, tris: &[[ScreenVertex; 3]]) -> Vec<[u8; 3]> {
    let n = (w * h) as usize;
    let mut color = vec![[0u8; 3]; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut fb = Framebuffer::<Rgb888>::new(&mut color, Some(&mut depth), w, h).unwrap();
    for t in tris {
        draw_triangle::<Rgb888, _, S, DepthTest, Gouraud>(&mut fb, *t);
    }
    color
}

#[test]
fn random_triangles_are_bit_identical_to_gradient() {
    let (w, h) = (256u32, 96u32);
    let mut rng = Rng(0x5EED);
    let mut tris = Vec::new();
    for i in 0..3000 {
        // Mostly small and medium triangles, some spanning far beyond the target.
        let reach = [40, 400, 4000, 60000][i % 4];
        let cx = rng.range(0, 16 * w as i32);
        let cy = rng.range(0, 16 * h as i32);
        let v = |rng: &mut Rng| ScreenVertex {
            x: (cx + rng.range(-reach, reach)).clamp(-65535, 65535),
            y: (cy + rng.range(-reach, reach)).clamp(-65535, 65535),
            z: rng.next() % (65534 << 16),
            c: [0; 3].map(|_| rng.range(0, 256 << 16)),
        };
        tris.push([v(&mut rng), v(&mut rng), v(&mut rng)]);
    }
    let want = render::<Gradient>(w, h, &tris);
    assert!(want.iter().any(|p| *p != [0, 0, 0]));
    let check = |name: &str, got: Vec<[u8; 3]>| {
        let diff = want.iter().zip(&got).filter(|(a, b)| a != b).count();
        assert_eq!(diff, 0, "{name} differs from gradient at {diff} pixels");
    };
    let exact = exact_methods();
    assert!(exact.len() >= 12, "{exact:?}");
    for m in exact {
        check(
            m.name(),
            fixshade_sim::with_span_method!(m, S => render::<S>(w, h, &tris)),
        );
    }
}

#[test]
fn the_checker_notices_a_different_method() {
    // Classic divides per span and rounds differently: the comparison above must be
    // able to see a difference on the same input.
    let (w, h) = (64u32, 64u32);
    let mut rng = Rng(7);
    let tris: Vec<_> = (0..200)
        .map(|_| {
            [0; 3].map(|_| ScreenVertex {
                x: rng.range(0, 16 * 64),
                y: rng.range(0, 16 * 64),
                z: rng.next() % (65534 << 16),
                c: [0; 3].map(|_| rng.range(0, 256 << 16)),
            })
        })
        .collect();
    let a = render::<Gradient>(w, h, &tris);
    let b = render::<fixshade::raster::span::Classic>(w, h, &tris);
    assert_ne!(a, b);
}
