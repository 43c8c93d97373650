//! Property tests: random triangles from the hard distributions (huge, tiny,
//! near-degenerate, axis-aligned, on the pixel grid, beyond the guard band, extreme
//! colours and depths), each run through `fixshade_tests::hard::check_all` with
//! every span method and shading mode: no panic, no write outside the target, exact
//! coverage, colour and depth within their bounds; pairs sharing an edge are
//! watertight. `PROPTEST_CASES` sets the number of cases (default 256 per test).
//! A shrunk failure is added to `tests/catalogue/triangles.toml`.

use fixshade::raster::{ScreenVertex, GUARD};
use fixshade_tests::hard::{check_all, Case, Holds};
use proptest::prelude::*;

const G: i32 = GUARD - 1;

/// A frame: small, or 4096 wide seen through a few rows somewhere down a 4096-row
/// frame.
fn frame() -> impl Strategy<Value = ((u32, u32), (u32, u32))> {
    prop_oneof![
        (1u32..=40, 1u32..=40).prop_map(|(w, h)| ((w, h), (0, h))),
        (1u32..=40, 1u32..=40, 0u32..40, 1u32..8).prop_map(|(w, h, y0, r)| {
            let y0 = y0 % h;
            ((w, h), (y0, r.min(h - y0)))
        }),
        (0u32..4092, 1u32..5).prop_map(|(y0, r)| ((4096, 4096), (y0, r))),
        (1u32..5).prop_map(|h| ((4095, h), (0, h))),
    ]
}

/// A colour channel in Q.16: often 0 or 255, else anything in between.
fn channel() -> impl Strategy<Value = i32> {
    prop_oneof![
        Just(0),
        Just(255 << 16),
        0..=255 << 16,
        (0..=255).prop_map(|c| c << 16)
    ]
}

fn depth() -> impl Strategy<Value = u32> {
    prop_oneof![Just(0u32), Just(65534 << 16), 0..=65534u32 << 16]
}

fn attrs() -> impl Strategy<Value = (u32, [i32; 3])> {
    (depth(), [channel(), channel(), channel()])
}

/// Vertex positions (Q12.4) of the hard kinds, around the frame `(w, h)`.
fn positions(w: u32, h: u32) -> impl Strategy<Value = [(i32, i32); 3]> {
    let (wx, hy) = (16 * w as i32, 16 * h as i32);
    let anywhere = (-G..=G, -G..=G);
    let near = (-64..wx + 64, -64..hy + 64);
    prop_oneof![
        // Huge: anywhere in the guard band.
        [anywhere.clone(), anywhere.clone(), anywhere.clone()],
        // Tiny: within a few subpixels of a point near the frame.
        (
            near.clone(),
            [(-3..=3, -3..=3), (-3..=3, -3..=3), (-3..=3, -3..=3)]
        )
            .prop_map(|((cx, cy), d)| d.map(|(dx, dy)| (cx + dx, cy + dy))),
        // Near-degenerate: the third vertex within 2 subpixels of a point of the
        // segment between two far-apart vertices.
        (anywhere.clone(), near.clone(), 0u32..=65536, -2..=2, -2..=2).prop_map(
            |(a, b, t, dx, dy)| {
                let m = |p: i32, q: i32| (p as i64 + (q - p) as i64 * t as i64 / 65536) as i32;
                [a, b, (m(a.0, b.0) + dx, m(a.1, b.1) + dy)]
            }
        ),
        // Axis-aligned: a horizontal and a vertical edge.
        (near.clone(), anywhere.clone()).prop_map(|((x0, y0), (x1, y1))| [
            (x0, y0),
            (x1, y0),
            (x0, y1)
        ]),
        // On the pixel grid: corners and centres.
        [
            (-8..2 * w as i32 + 8, -8..2 * h as i32 + 8),
            (-8..2 * w as i32 + 8, -8..2 * h as i32 + 8),
            (-8..2 * w as i32 + 8, -8..2 * h as i32 + 8)
        ]
        .prop_map(|p| p.map(|(x, y)| (8 * x, 8 * y))),
        // Near the frame, any subpixel.
        [near.clone(), near.clone(), near],
        // Beyond the guard band or anywhere in i32: culled.
        (
            (any::<i32>(), any::<i32>()),
            (-G..=G, -G..=G),
            (-G..=G, -G..=G)
        )
            .prop_map(|(a, b, c)| [a, b, c]),
    ]
}

fn case() -> impl Strategy<Value = Case> {
    frame().prop_flat_map(|((w, h), strip)| {
        (positions(w, h), [attrs(), attrs(), attrs()]).prop_map(move |(p, a)| Case {
            frame: (w, h),
            strip,
            tris: vec![std::array::from_fn(|k| ScreenVertex {
                x: p[k].0,
                y: p[k].1,
                z: a[k].0,
                c: a[k].1,
            })],
            holds: Holds {
                coverage: true,
                colour: true,
                depth: true,
                strip: w * h <= 1 << 14,
                ..Holds::default()
            },
        })
    })
}

/// Two triangles sharing an edge (a quadrilateral split along a diagonal), same
/// orientation: watertight.
fn pair() -> impl Strategy<Value = Case> {
    (case(), 0usize..3).prop_filter_map("folded or degenerate quad", |(mut c, k)| {
        let t = c.tris[0];
        let (a, b, o) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        // The fourth vertex: `o` reflected through the midpoint of a–b.
        let d = ScreenVertex {
            x: a.x.checked_add(b.x)?.checked_sub(o.x)?,
            y: a.y.checked_add(b.y)?.checked_sub(o.y)?,
            ..o
        };
        let area = |p: &ScreenVertex, q: &ScreenVertex, r: &ScreenVertex| {
            fixshade_tests::area2((p.x, p.y), (q.x, q.y), (r.x, r.y))
        };
        let first = [a, b, o];
        let second = [b, a, d];
        let (s1, s2) = (area(&a, &b, &o), area(&b, &a, &d));
        if s1 == 0 || s1.signum() != s2.signum() {
            return None;
        }
        c.tris = vec![first, second];
        c.holds.watertight = true;
        Some(c)
    })
}

proptest! {
    // Shrunk failures go into the catalogue, not into a regressions file.
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn hard_triangles(c in case()) {
        check_all(&c).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn hard_pairs_are_watertight(c in pair()) {
        check_all(&c).map_err(TestCaseError::fail)?;
    }
}
