//! ASCII-pattern tests of the fill rule, in the style of embedded-graphics'
//! `MockDisplay::assert_pattern`.
//!
//! The rule under test: pixel `(x, y)` is sampled at its centre `(x + ½, y + ½)`; it is
//! covered iff the centre is inside the triangle, and a centre exactly on an edge
//! counts only if that edge is a left edge or a horizontal top edge (the top-left
//! rule of Direct3D and OpenGL). Equivalently: sample at `(x + ½ + ε, y + ½ + ε²)`.
//!
//! Every expected picture below was worked out by hand from that rule; the comment
//! above each one gives the inequalities it comes from, in pixel indices `i` (column)
//! and `j` (row). Vertices are given in Q12.4 (1/16 pixel): [`px`] makes a pixel
//! corner, [`c`] a pixel centre.
//!
//! The mock pixel format [`Mark`] counts stores, so overdraw shows as `2`, `3`, …;
//! every picture is drawn with both [`Gradient`] and [`Classic`], which must agree,
//! and the pixel counts `draw_triangle` returns must match the marks.

extern crate std;

use std::format;
use std::string::String;
use std::vec;
use std::vec::Vec;

use super::span::{Classic, Gradient, NoDepth, SpanMethod};
use super::{draw_triangle, ScreenVertex, GUARD};
use crate::shade::Flat;
use crate::target::{Framebuffer, PixelFormat, Strip};

/// A triangle's vertices in Q12.4.
type Tri = [(i32, i32); 3];

/// Pixel corner `(x, y)` (the top-left corner of pixel `(x, y)`), Q12.4.
fn px(x: i32, y: i32) -> (i32, i32) {
    (x * 16, y * 16)
}

/// Centre of pixel `(x, y)`, Q12.4.
fn c(x: i32, y: i32) -> (i32, i32) {
    (x * 16 + 8, y * 16 + 8)
}

/// Mock pixel format: every store adds one, so overdraw is visible.
struct Mark;

impl PixelFormat for Mark {
    type Raw = u8;
    const MAX: [u32; 3] = [1, 1, 1];
    const GRAY: bool = true;
    const BYTES: usize = 1;
    const NAME: &'static str = "mark";
    const PLAIN_STORE: bool = false;
    fn pack(_: u32, _: u32, _: u32) -> u8 {
        0
    }
    fn unpack(p: u8) -> [u32; 3] {
        [u32::from(p); 3]
    }
    fn store(dst: &mut u8, _: u8) {
        *dst = dst.saturating_add(1);
    }
    fn bytes(p: u8) -> [u8; 3] {
        [p, 0, 0]
    }
}

fn sv((x, y): (i32, i32)) -> ScreenVertex {
    ScreenVertex {
        x,
        y,
        z: 0,
        c: [0; 3],
    }
}

/// Draws `tris` into a `w` × `h` frame with span method `S`; returns the marks and
/// the sum of the pixel counts `draw_triangle` reported.
fn marks<S: SpanMethod>(w: u32, h: u32, tris: &[Tri]) -> (Vec<u8>, u32) {
    let mut buf = vec![0u8; (w * h) as usize];
    let mut fb = Framebuffer::<Mark>::new(&mut buf, None, w, h).unwrap();
    let mut n = 0;
    for t in tris {
        n += draw_triangle::<Mark, _, S, NoDepth, Flat>(&mut fb, t.map(sv));
    }
    (buf, n)
}

/// The same, through strips of `rows` rows (the target clips rows too).
fn marks_in_strips(w: u32, h: u32, rows: u32, tris: &[Tri]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut buf = vec![0u8; (w * rows) as usize];
    let mut y0 = 0;
    while y0 < h {
        let hh = rows.min(h - y0);
        buf.fill(0);
        let mut strip = Strip::<Mark>::new(&mut buf, None, w, h, y0, hh).unwrap();
        for t in tris {
            draw_triangle::<Mark, _, Gradient, NoDepth, Flat>(&mut strip, t.map(sv));
        }
        out.extend_from_slice(&buf[..(w * hh) as usize]);
        y0 += hh;
    }
    out
}

fn rows_of(w: u32, m: &[u8]) -> Vec<String> {
    m.chunks(w as usize)
        .map(|r| {
            r.iter()
                .map(|&k| match k {
                    0 => '.',
                    1 => '#',
                    2..=9 => char::from(b'0' + k),
                    _ => '+',
                })
                .collect()
        })
        .collect()
}

/// Draws `tris` (Q12.4 vertices) into a `w` × `h` frame and returns its rows:
/// `.` untouched, `#` stored once, `2`… stored that many times.
///
/// Checks on the way that [`Classic`] stores exactly the pixels [`Gradient`] stores
/// and that the reported pixel counts match the marks.
#[track_caller]
fn draw(w: u32, h: u32, tris: &[Tri]) -> Vec<String> {
    let (g, ng) = marks::<Gradient>(w, h, tris);
    let (k, nk) = marks::<Classic>(w, h, tris);
    let got = rows_of(w, &g);
    assert_eq!(
        got,
        rows_of(w, &k),
        "Classic and Gradient cover different pixels for {tris:?}"
    );
    let total: u32 = g.iter().map(|&m| u32::from(m)).sum();
    assert_eq!(ng, total, "Gradient reported {ng} pixels, stored {total}");
    assert_eq!(nk, total, "Classic reported {nk} pixels, stored {total}");
    got
}

/// Compares a picture with the expected rows; on failure prints expected, got and
/// a diff (`+` stored but not expected, `-` expected but missing, `!` wrong count).
#[track_caller]
fn assert_pattern(got: &[String], want: &[&str]) {
    let same = got.len() == want.len() && got.iter().zip(want).all(|(g, w)| g == w);
    if same {
        return;
    }
    let width = want
        .iter()
        .map(|r| r.len())
        .chain(got.iter().map(|r| r.len()))
        .max()
        .unwrap_or(0);
    let mut msg = String::from("pattern mismatch\n");
    msg += &format!(
        "  {:w$}   {:w$}   diff\n",
        "expected",
        "got",
        w = width.max(8)
    );
    for j in 0..got.len().max(want.len()) {
        let e = want.get(j).copied().unwrap_or("");
        let g = got.get(j).map(String::as_str).unwrap_or("");
        let diff: String = (0..width)
            .map(|i| {
                let (a, b) = (e.as_bytes().get(i), g.as_bytes().get(i));
                match (a, b) {
                    (Some(a), Some(b)) if a == b => '.',
                    (Some(b'.'), Some(_)) => '+',
                    (Some(_), Some(b'.')) => '-',
                    _ => '!',
                }
            })
            .collect();
        let mark = if e == g { ' ' } else { '>' };
        msg += &format!(
            "{mark} {e:w$}   {g:w$}   {diff}  row {j}\n",
            w = width.max(8)
        );
    }
    panic!("{msg}");
}

/// Pixels stored more than once.
fn overdraw(rows: &[String]) -> usize {
    rows.iter()
        .map(|r| r.chars().filter(|&ch| ch != '.' && ch != '#').count())
        .sum()
}

// --- Single triangles ---------------------------------------------------------------

#[test]
fn right_triangle_with_legs_on_the_axes() {
    // Corners (0,0), (5,0), (0,5): inside iff x + y < 5, the hypotenuse is a right
    // edge. Centre test: (i+½) + (j+½) < 5 ⇔ i + j < 4; centres with i + j = 4 lie
    // on the hypotenuse and are excluded. The legs run along pixel boundaries.
    let got = draw(6, 6, &[[px(0, 0), px(5, 0), px(0, 5)]]);
    assert_pattern(
        &got,
        &[
            "####..", //
            "###...", //
            "##....", //
            "#.....", //
            "......", //
            "......", //
        ],
    );
}

#[test]
fn mirrored_right_triangles_hypotenuse_left_versus_right() {
    // Mirrored left-right: corners (6,0), (1,0), (6,5). Inside iff x − y ≥ 1 with the
    // hypotenuse now a LEFT edge, so the centres on it (i − j = 1) are covered:
    // i − j ≥ 1. The picture is the mirror of the one above plus that diagonal.
    let got = draw(6, 6, &[[px(6, 0), px(1, 0), px(6, 5)]]);
    assert_pattern(
        &got,
        &[
            ".#####", //
            "..####", //
            "...###", //
            "....##", //
            ".....#", //
            "......", //
        ],
    );
    // Mirrored top-bottom: corners (0,1), (0,6), (5,6). Hypotenuse y = x + 1 with the
    // triangle left of it: a right edge. Inside iff j + ½ > i + ½ + 1 ⇔ j ≥ i + 2;
    // the on-edge centres (j = i + 1) are excluded, so this is exactly the first
    // triangle's picture upside down.
    let got = draw(6, 6, &[[px(0, 1), px(0, 6), px(5, 6)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            "......", //
            "#.....", //
            "##....", //
            "###...", //
            "####..", //
        ],
    );
    // Both mirrors: corners (6,1), (6,6), (1,6). Hypotenuse x + y = 7, a left edge:
    // i + j + 1 ≥ 7 ⇔ i + j ≥ 6, on-edge centres included.
    let got = draw(6, 6, &[[px(6, 1), px(6, 6), px(1, 6)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            ".....#", //
            "....##", //
            "...###", //
            "..####", //
            ".#####", //
        ],
    );
}

#[test]
fn edges_at_45_degrees_through_pixel_centres() {
    // Apex up: centres (3,0), (0,3), (6,3), i.e. (3.5,0.5), (0.5,3.5), (6.5,3.5).
    // Left edge x + y = 4 (included): i + j ≥ 3. Right edge x − y = 3 (excluded):
    // i − j < 3. Base y = 3.5 is a bottom edge (excluded): j < 3. The apex pixel (3,0)
    // sits on both slanted edges; the right one excludes it.
    let got = draw(7, 5, &[[c(3, 0), c(0, 3), c(6, 3)]]);
    assert_pattern(
        &got,
        &[
            ".......", //
            "..##...", //
            ".####..", //
            ".......", //
            ".......", //
        ],
    );
    // Apex down: centres (0,0), (6,0), (3,3). Top edge y = 0.5 (included): j ≥ 0.
    // Left edge x − y = 0 (included): i ≥ j. Right edge x + y = 7 (excluded):
    // i + j < 6. The bottom apex (3,3) is on both slanted edges: excluded.
    let got = draw(7, 5, &[[c(0, 0), c(6, 0), c(3, 3)]]);
    assert_pattern(
        &got,
        &[
            "######.", //
            ".####..", //
            "..##...", //
            ".......", //
            ".......", //
        ],
    );
}

#[test]
fn vertical_edges_on_pixel_centres() {
    // Long thin triangles whose slanted edges lie far outside the 6×4 target, so only
    // the vertical edge x = 1.5 (resp. 4.5) crosses it.
    // Left edge at x = 1.5: covered iff i + ½ ≥ 1.5 ⇔ i ≥ 1 (column 1 included).
    let left: Tri = [(24, -160), (24, 320), (480, 80)];
    assert_pattern(
        &draw(6, 4, &[left]),
        &[".#####", ".#####", ".#####", ".#####"],
    );
    // Right edge at x = 4.5: covered iff i + ½ < 4.5 ⇔ i < 4 (column 4 excluded).
    let right: Tri = [(72, -160), (72, 320), (-384, 80)];
    assert_pattern(
        &draw(6, 4, &[right]),
        &["####..", "####..", "####..", "####.."],
    );
    // Compact: centres (1,0), (1,4), (5,4). Left edge x = 1.5 (included): i ≥ 1;
    // hypotenuse x − y = 1 (a right edge): i − j < 1; bottom y = 4.5: j < 4.
    let got = draw(6, 5, &[[c(1, 0), c(1, 4), c(5, 4)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            ".#....", //
            ".##...", //
            ".###..", //
            "......", //
        ],
    );
    // Its mirror: centres (4,0), (4,4), (0,4). Right edge x = 4.5 (excluded): i < 4;
    // hypotenuse x + y = 5 (a left edge): i + j ≥ 4; bottom y = 4.5: j < 4.
    let got = draw(6, 5, &[[c(4, 0), c(4, 4), c(0, 4)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            "...#..", //
            "..##..", //
            ".###..", //
            "......", //
        ],
    );
}

#[test]
fn horizontal_edges_on_pixel_centres() {
    // Wide triangles whose slanted edges lie far outside the 6×5 target.
    // Top edge at y = 1.5: covered iff j + ½ ≥ 1.5 ⇔ j ≥ 1 (row 1 included).
    let top: Tri = [(-160, 24), (320, 24), (80, 480)];
    assert_pattern(
        &draw(6, 5, &[top]),
        &["......", "######", "######", "######", "######"],
    );
    // Bottom edge at y = 3.5: covered iff j + ½ < 3.5 ⇔ j < 3 (row 3 excluded).
    let bottom: Tri = [(-160, 56), (320, 56), (80, -400)];
    assert_pattern(
        &draw(6, 5, &[bottom]),
        &["######", "######", "######", "......", "......"],
    );
    // Compact, top edge: centres (0,1), (4,1), (0,5). Top y = 1.5 (included): j ≥ 1;
    // left x = 0.5 (included): i ≥ 0; hypotenuse x + y = 6 (right edge): i + j < 5.
    // The pixel (4,1) is a vertex on the top edge and the hypotenuse: excluded.
    let got = draw(6, 6, &[[c(0, 1), c(4, 1), c(0, 5)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            "####..", //
            "###...", //
            "##....", //
            "#.....", //
            "......", //
        ],
    );
    // Compact, bottom edge: centres (0,0), (0,4), (4,4). Left x = 0.5: i ≥ 0;
    // hypotenuse x − y = 0 (right edge): i < j; bottom y = 4.5 (excluded): j < 4.
    let got = draw(6, 6, &[[c(0, 0), c(0, 4), c(4, 4)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            "#.....", //
            "##....", //
            "###...", //
            "......", //
            "......", //
        ],
    );
}

#[test]
fn vertices_on_pixel_corners() {
    // Corners A (1,0), B (7,2), C (3,6).
    //   AB: x − 1 − 3y = 0, triangle below it, a right edge: i < 3j + 2
    //       (centres (2,0) and (5,1) lie on it and are excluded);
    //   BC: x + y = 9, a right edge: i + j < 8;
    //   CA: 3x − y = 3, a left edge: 3i − j ≥ 2
    //       (centres (1,1) and (2,4) lie on it and are included).
    let got = draw(8, 7, &[[px(1, 0), px(7, 2), px(3, 6)]]);
    assert_pattern(
        &got,
        &[
            ".#......", //
            ".####...", //
            "..####..", //
            "..###...", //
            "..##....", //
            "........", //
            "........", //
        ],
    );
}

#[test]
fn one_pixel_triangles() {
    // Around the centre (40, 24) of pixel (2,1), inside the pixel's square: exactly
    // that pixel.
    let around: Tri = [(36, 20), (46, 20), (40, 29)];
    // Around the pixel corner (32, 16), no centre inside: nothing.
    let corner: Tri = [(28, 12), (36, 12), (32, 20)];
    // Between centres in both directions: x in [41, 55], y in [10, 22]: nothing.
    let between: Tri = [(41, 10), (55, 12), (47, 22)];
    assert_pattern(&draw(5, 3, &[around]), &[".....", "..#..", "....."]);
    assert_pattern(&draw(5, 3, &[corner]), &[".....", ".....", "....."]);
    assert_pattern(&draw(5, 3, &[between]), &[".....", ".....", "....."]);
    // A tiny triangle whose top-left corner is the centre of pixel (2,1): the centre is
    // on its top edge and its left edge, so it is covered.
    let top_left: Tri = [(40, 24), (44, 24), (40, 28)];
    assert_pattern(&draw(5, 3, &[top_left]), &[".....", "..#..", "....."]);
    // The same with the centre as its top-right corner: on the top edge but also on
    // the vertical right edge, so it is not covered.
    let top_right: Tri = [(36, 24), (40, 24), (40, 28)];
    assert_pattern(&draw(5, 3, &[top_right]), &[".....", ".....", "....."]);
    // Centre as the bottom-left corner: on the left edge but on the bottom edge too.
    let bottom_left: Tri = [(40, 20), (44, 24), (40, 24)];
    assert_pattern(&draw(5, 3, &[bottom_left]), &[".....", ".....", "....."]);
}

#[test]
fn slivers_cover_nothing() {
    let empty = [
        "..........",
        "..........",
        "..........",
        "..........",
        "..........",
    ];
    // Between the centre rows y = 8 and y = 24.
    assert_pattern(&draw(10, 5, &[[(2, 17), (90, 20), (90, 22)]]), &empty);
    // Between the centre columns x = 24 and x = 40, across every row.
    assert_pattern(&draw(10, 5, &[[(33, 0), (35, 0), (38, 79)]]), &empty);
    // Across five rows between y = x/2 and y = 81x/160: at row j the span is
    // [ (16j+8)·160/81, 32j+16 ), less than a pixel wide and ending on a pixel
    // boundary, and no centre 16i+8 falls in it.
    assert_pattern(&draw(10, 5, &[[(0, 0), (160, 80), (160, 81)]]), &empty);
    // A needle whose RIGHT edge is the 45° line through the centres (k, k): those
    // centres are on a right edge, and the left edge x = 8 + 15.6k leaves no other
    // centre inside.
    assert_pattern(&draw(10, 5, &[[c(0, 0), c(5, 5), (86, 88)]]), &empty);
}

#[test]
fn needle_along_a_left_edge_covers_its_centres() {
    // The same needle mirrored to the other side of the 45° line: the line is now its
    // LEFT edge, so the centres (k, k) on it are covered, for rows 1..=4 (row 0: the
    // top vertex is also on the right edge x = 8 + 16.4k; row 5: the bottom edge).
    let got = draw(6, 6, &[[c(0, 0), c(5, 5), (90, 88)]]);
    assert_pattern(
        &got,
        &[
            "......", //
            ".#....", //
            "..#...", //
            "...#..", //
            "....#.", //
            "......", //
        ],
    );
}

// --- Shared edges and vertices --------------------------------------------------------

#[test]
fn two_triangles_sharing_a_diagonal() {
    // Square with corners (1,1)–(5,5): pixels 1..=4 in both directions, whatever the
    // diagonal. The main diagonal x = y runs through the centres (i, i), the other one
    // x + y = 6 through the centres with i + j = 5.
    let sq = [
        "......", //
        ".####.", //
        ".####.", //
        ".####.", //
        ".####.", //
        "......", //
    ];
    let (a, b, cc, d) = (px(1, 1), px(5, 1), px(5, 5), px(1, 5));
    assert_pattern(&draw(6, 6, &[[a, b, cc], [a, cc, d]]), &sq);
    assert_pattern(&draw(6, 6, &[[a, b, d], [b, cc, d]]), &sq);

    // Rectangle on centres (0,0), (5,0), (5,4), (0,4): top and left edges included,
    // right x = 5.5 and bottom y = 4.5 excluded: i in 0..5, j in 0..4.
    let rect = [
        "#####..", //
        "#####..", //
        "#####..", //
        "#####..", //
        ".......", //
        ".......", //
    ];
    let (a, b, cc, d) = (c(0, 0), c(5, 0), c(5, 4), c(0, 4));
    assert_pattern(&draw(7, 6, &[[a, b, cc], [a, cc, d]]), &rect);
    assert_pattern(&draw(7, 6, &[[a, b, d], [b, cc, d]]), &rect);

    // Diamond on centres N (3,0), E (6,3), S (3,6), W (0,3), split along the
    // horizontal diagonal y = 3.5 (a bottom edge above, a top edge below) and along
    // the vertical one x = 3.5 (a right edge on the left, a left edge on the right),
    // both through centres. Diamond: NW x + y = 4 and SW x − y = −3 are left edges
    // (i + j ≥ 3, i − j ≥ −3), NE x − y = 3 and SE x + y = 10 right edges
    // (i − j < 3, i + j < 9).
    let diamond = [
        ".......", //
        "..##...", //
        ".####..", //
        "######.", //
        ".####..", //
        "..##...", //
        ".......", //
    ];
    let (n, e, s, w) = (c(3, 0), c(6, 3), c(3, 6), c(0, 3));
    assert_pattern(&draw(7, 7, &[[n, w, e], [w, e, s]]), &diamond);
    assert_pattern(&draw(7, 7, &[[n, e, s], [n, s, w]]), &diamond);
    // The halves on their own: the horizontal split gives rows 1–2 and rows 3–5.
    assert_pattern(
        &draw(7, 7, &[[n, w, e]]),
        &[
            ".......", //
            "..##...", //
            ".####..", //
            ".......", //
            ".......", //
            ".......", //
            ".......", //
        ],
    );
    // Vertical split, right half: left edge x = 3.5 included: i ≥ 3.
    assert_pattern(
        &draw(7, 7, &[[n, e, s]]),
        &[
            ".......", //
            "...#...", //
            "...##..", //
            "...###.", //
            "...##..", //
            "...#...", //
            ".......", //
        ],
    );

    // A diagonal through no centre: rectangle (0,0)–(7,3) split along (0,0)–(7,3),
    // which passes the centre (3,1) only; and along (7,0)–(0,3).
    let wide = [
        "#######.", //
        "#######.", //
        "#######.", //
        "........", //
    ];
    let (a, b, cc, d) = (px(0, 0), px(7, 0), px(7, 3), px(0, 3));
    assert_pattern(&draw(8, 4, &[[a, b, cc], [a, cc, d]]), &wide);
    assert_pattern(&draw(8, 4, &[[a, b, d], [b, cc, d]]), &wide);

    // Subpixel vertices: a quad A (3,5), B (100,21), C (90,90), D (10,70) split both
    // ways must cover the same pixels once each.
    let (a, b, cc, d) = ((3, 5), (100, 21), (90, 90), (10, 70));
    let ac = draw(8, 7, &[[a, b, cc], [a, cc, d]]);
    let bd = draw(8, 7, &[[a, b, d], [b, cc, d]]);
    assert_eq!(overdraw(&ac), 0, "{ac:#?}");
    assert_eq!(ac, bd);
}

#[test]
fn four_triangles_around_a_centre_vertex() {
    // Diamond N (3,0), E (6,3), S (3,6), W (0,3) as a fan around V = centre of (3,3).
    // At V, only the triangle V-E-S has both edges through V as top/left edges (the
    // horizontal top edge V–E and the vertical left edge V–S): it alone takes (3,3).
    let (v, n, e, s, w) = (c(3, 3), c(3, 0), c(6, 3), c(3, 6), c(0, 3));
    let fan = [[v, n, e], [v, e, s], [v, s, w], [v, w, n]];
    assert_pattern(
        &draw(7, 7, &fan),
        &[
            ".......", //
            "..##...", //
            ".####..", //
            "######.", //
            ".####..", //
            "..##...", //
            ".......", //
        ],
    );
    // V-E-S alone: top y = 3.5 (j ≥ 3), left x = 3.5 (i ≥ 3), right x + y = 10
    // (i + j < 9).
    assert_pattern(
        &draw(7, 7, &[[v, e, s]]),
        &[
            ".......", //
            ".......", //
            ".......", //
            "...###.", //
            "...##..", //
            "...#...", //
            ".......", //
        ],
    );

    // Square of centres (0,0), (6,0), (6,6), (0,6) cut into four by its diagonals,
    // which meet at V and run through centres. The square: top and left included,
    // right x = 6.5 and bottom y = 6.5 excluded: a 6×6 block. At V only the right
    // triangle (V, NE, SE) has both edges through V as left edges.
    let (nw, ne, se, sw) = (c(0, 0), c(6, 0), c(6, 6), c(0, 6));
    let fan = [[v, nw, ne], [v, ne, se], [v, se, sw], [v, sw, nw]];
    let block = [
        "######.", //
        "######.", //
        "######.", //
        "######.", //
        "######.", //
        "######.", //
        ".......", //
    ];
    assert_pattern(&draw(7, 7, &fan), &block);
    // Right triangle: left edges NE→V (x + y = 7: i + j ≥ 6) and V→SE (x = y:
    // i ≥ j), right edge x = 6.5 (i < 6). NE and SE sit on the right edge: excluded.
    assert_pattern(
        &draw(7, 7, &[[v, ne, se]]),
        &[
            ".......", //
            ".....#.", //
            "....##.", //
            "...###.", //
            "....##.", //
            ".....#.", //
            ".......", //
        ],
    );
}

/// A tiny deterministic generator (LCG).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self, lo: i32, hi: i32) -> i32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + ((self.0 >> 33) % (hi - lo) as u64) as i32
    }
}

fn cross(o: (i32, i32), a: (i32, i32), b: (i32, i32)) -> i64 {
    let (ax, ay) = (i64::from(a.0 - o.0), i64::from(a.1 - o.1));
    let (bx, by) = (i64::from(b.0 - o.0), i64::from(b.1 - o.1));
    ax * by - ay * bx
}

#[test]
fn random_convex_quads_tile_without_gaps_or_overdraw() {
    // Any tessellation of a convex quad covers the same pixels, each once: the two
    // diagonal splits and a fan of four around an interior point. Coordinates are
    // snapped to a coarse grid half the time so that edges and vertices often meet
    // pixel centres exactly.
    let mut rng = Lcg(7);
    let (w, h) = (10u32, 9u32);
    let (mut tested, mut fans) = (0, 0);
    while tested < 1000 {
        let snap = tested % 2 == 0;
        let mut p = || {
            let (x, y) = (rng.next(-40, 200), rng.next(-40, 180));
            if snap {
                (x & !7, y & !7)
            } else {
                (x, y)
            }
        };
        let q = [p(), p(), p(), p()];
        let v = p();
        let turns: Vec<i64> = (0..4)
            .map(|k| cross(q[k], q[(k + 1) % 4], q[(k + 2) % 4]))
            .collect();
        let convex = turns.iter().all(|&t| t > 0) || turns.iter().all(|&t| t < 0);
        if !convex {
            continue;
        }
        let sign = turns[0].signum();
        let inside = |v| (0..4).all(|k| cross(q[k], q[(k + 1) % 4], v).signum() == sign);
        // The random point if it falls inside, else the vertex centroid (inside a
        // convex quad), snapped like the vertices when that keeps it inside.
        let sum = q.iter().fold((0, 0), |s, p| (s.0 + p.0, s.1 + p.1));
        let mid = (sum.0 / 4, sum.1 / 4);
        let v = [v, (mid.0 & !7, mid.1 & !7), mid]
            .into_iter()
            .find(|&v| inside(v));
        tested += 1;
        let [a, b, cc, d] = q;
        let ac = draw(w, h, &[[a, b, cc], [a, cc, d]]);
        let bd = draw(w, h, &[[a, b, d], [b, cc, d]]);
        assert_eq!(overdraw(&ac), 0, "quad {q:?}\n{ac:#?}");
        assert_eq!(ac, bd, "quad {q:?}: the two diagonals differ");
        if let Some(v) = v {
            fans += 1;
            let fan = draw(w, h, &[[v, a, b], [v, b, cc], [v, cc, d], [v, d, a]]);
            assert_eq!(ac, fan, "quad {q:?} fanned around {v:?}");
        }
    }
    assert!(fans > 900, "only {fans} fans");
}

// --- Orientation, clipping -------------------------------------------------------------

#[test]
fn vertex_order_and_winding_do_not_matter() {
    // draw_triangle does not cull: all six orders (three clockwise, three
    // counter-clockwise) give the same pixels.
    let tris: [Tri; 5] = [
        [px(1, 0), px(7, 2), px(3, 6)],
        [c(3, 0), c(0, 3), c(6, 3)],
        [c(1, 0), c(1, 4), c(5, 4)],
        [(3, 5), (100, 21), (90, 90)],
        [c(0, 0), c(5, 5), (90, 88)],
    ];
    for [a, b, cc] in tris {
        let want = draw(8, 7, &[[a, b, cc]]);
        assert!(overdraw(&want) == 0 && want.iter().any(|r| r.contains('#')));
        for t in [[a, cc, b], [b, a, cc], [b, cc, a], [cc, a, b], [cc, b, a]] {
            assert_eq!(draw(8, 7, &[t]), want, "{t:?}");
        }
    }
    // The corner triangle's picture, clockwise and counter-clockwise.
    let want = [
        ".#......", //
        ".####...", //
        "..####..", //
        "..###...", //
        "..##....", //
        "........", //
        "........", //
    ];
    assert_pattern(&draw(8, 7, &[[px(1, 0), px(7, 2), px(3, 6)]]), &want);
    assert_pattern(&draw(8, 7, &[[px(1, 0), px(3, 6), px(7, 2)]]), &want);
}

#[test]
fn triangles_partly_outside_are_clipped() {
    // Off the top and left: corners (−3,−2), (9,−2), (−3,10); the hypotenuse
    // x + y = 7 is a right edge and leaves by the right border: i + j < 6.
    let tl: Tri = [px(-3, -2), px(9, -2), px(-3, 10)];
    let want_tl = [
        "######", //
        "#####.", //
        "####..", //
        "###...", //
        "##....", //
    ];
    assert_pattern(&draw(6, 5, &[tl]), &want_tl);
    // Off the right and bottom: corners (2,1), (9,1), (2,8); the hypotenuse
    // x + y = 10 (right edge) only excludes the corner pixel (5,4): i + j < 9.
    let br: Tri = [px(2, 1), px(9, 1), px(2, 8)];
    let want_br = [
        "......", //
        "..####", //
        "..####", //
        "..####", //
        "..###.", //
    ];
    assert_pattern(&draw(6, 5, &[br]), &want_br);
    // Negative coordinates on pixel centres: centres (−1,−1), (3,−1), (−1,3). Top
    // y = −0.5 and left x = −0.5 are outside; hypotenuse x + y = 3 (right edge):
    // i + j < 2.
    let neg: Tri = [c(-1, -1), c(3, -1), c(-1, 3)];
    assert_pattern(
        &draw(6, 4, &[neg]),
        &["##....", "#.....", "......", "......"],
    );
    // Strips clip rows the same way as a whole frame.
    for rows in [1, 2, 3] {
        for (t, want) in [(tl, &want_tl), (br, &want_br)] {
            assert_eq!(rows_of(6, &marks_in_strips(6, 5, rows, &[t])), *want);
        }
    }
    // Entirely outside on each side: nothing, no panic.
    let outside: [Tri; 4] = [
        [px(-9, 0), px(-1, 0), px(-5, 4)],
        [px(7, 0), px(12, 0), px(9, 4)],
        [px(0, -6), px(5, -6), px(2, -1)],
        [px(0, 6), px(5, 6), px(2, 9)],
    ];
    for t in outside {
        assert_pattern(&draw(6, 5, &[t]), &["......"; 5]);
    }
    // Huge, at the edge of the guard band: covers the whole target once.
    let g = GUARD - 1;
    assert_pattern(&draw(6, 5, &[[(-g, -g), (g, -g), (0, g)]]), &["######"; 5]);
    assert_pattern(&draw(6, 5, &[[(-g, g), (g, g), (0, -g)]]), &["######"; 5]);
    // The lower-right half plane x + y ≥ 0 holds every centre of the target; the
    // upper-left one x + y ≤ 0 none (its hypotenuse passes the origin, a corner).
    assert_pattern(&draw(6, 5, &[[(g, g), (-g, g), (g, -g)]]), &["######"; 5]);
    assert_pattern(&draw(6, 5, &[[(-g, -g), (g, -g), (-g, g)]]), &["......"; 5]);
    // A vertex on or beyond the guard band: rejected, nothing drawn.
    assert_pattern(
        &draw(6, 5, &[[(-GUARD, 0), (64, 0), (0, 64)]]),
        &["......"; 5],
    );
    assert_pattern(
        &draw(6, 5, &[[(0, 0), (64, i32::MAX), (0, 64)]]),
        &["......"; 5],
    );
}

/// Two triangles over the same pixels whose depths differ by less than one step of
/// a 16-bit buffer: with `u16` cells the second one drawn ties and loses every
/// pixel; with `u32` cells the nearer second one wins every pixel, for every span
/// method.
#[test]
fn u32_depth_resolves_what_u16_ties() {
    use super::span::DepthTest;
    use crate::shade::Gouraud;
    use crate::target::{DepthFormat, Gray8};

    fn frame<S: SpanMethod, D: DepthFormat + Default + Clone>() -> Vec<u8> {
        let mut color = vec![0u8; 16 * 16];
        let mut depth = vec![D::FAR; 16 * 16];
        let mut fb =
            Framebuffer::<Gray8, D>::with_depth_format(&mut color, Some(&mut depth), 16, 16)
                .unwrap();
        let v = |x: i32, y: i32, g: i32, z: u32| ScreenVertex {
            x: x * 16,
            y: y * 16,
            z,
            c: [g << 16, 0, 0],
        };
        // Far: depth 1000.25; near: 1000 + 1/16. With the setup's rounding bias of
        // one half both are 1000 in a u16 cell.
        let (far, near) = ((1000 << 16) | 0x4000, (1000 << 16) | 0x1000);
        let tri = |g, z| [v(0, 0, g, z), v(0, 16, g, z), v(16, 0, g, z)];
        draw_triangle::<Gray8, _, S, DepthTest, Gouraud>(&mut fb, tri(100, far));
        draw_triangle::<Gray8, _, S, DepthTest, Gouraud>(&mut fb, tri(200, near));
        color
    }
    fn check<S: SpanMethod>() {
        let (c16, c32) = (frame::<S, u16>(), frame::<S, u32>());
        let drawn = c16.iter().filter(|&&p| p != 0).count();
        assert!(drawn > 50, "{}: {drawn} pixels drawn", S::NAME);
        assert!(
            c16.iter().all(|&p| p == 0 || p == 100),
            "{}: u16 {c16:?}",
            S::NAME
        );
        assert!(
            c32.iter().all(|&p| p == 0 || p == 200),
            "{}: u32 {c32:?}",
            S::NAME
        );
        assert_eq!(
            c32.iter().filter(|&&p| p != 0).count(),
            drawn,
            "{}",
            S::NAME
        );
    }
    macro_rules! each {
        ([] $($S:ty),* $(,)?) => {
            $(check::<$S>();)*
        };
    }
    crate::for_each_span_method!(each);
}
