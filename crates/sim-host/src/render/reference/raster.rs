//! Exact coverage of triangles with snapped vertices (1/16-pixel integer
//! coordinates), the top-left rule, and barycentric weights at pixel centres.
//!
//! Coverage follows the normative span formulation: pixel `(x, y)` is sampled at its
//! centre `(16x+8, 16y+8)`; an edge spans the rows whose centre `Yc` satisfies
//! `min(ya, yb) <= Yc < max(ya, yb)`; a row of a non-degenerate triangle is crossed
//! by exactly two edges, at exact rational abscissae `X1 <= X2`, and the covered
//! pixels are those with `X1 <= 16x+8 < X2`. Everything is integer arithmetic.

/// Signed doubled area (in 1/256 pixel² units) of a snapped triangle:
/// `(x1-x0)*(y2-y0) - (x2-x0)*(y1-y0)`. With y pointing down, a counter-clockwise
/// (front-facing) triangle has a negative area.
pub(crate) fn signed_area(v: &[[i64; 2]; 3]) -> i128 {
    let d = |a: i64, b: i64| a as i128 - b as i128;
    d(v[1][0], v[0][0]) * d(v[2][1], v[0][1]) - d(v[2][0], v[0][0]) * d(v[1][1], v[0][1])
}

/// `ceil(n / d)` for `d > 0`.
fn ceil_div(n: i128, d: i128) -> i128 {
    let q = n.div_euclid(d);
    if n.rem_euclid(d) != 0 {
        q + 1
    } else {
        q
    }
}

/// The first row/column index `i` whose centre `16i + 8` is `>= c` (1/16 units).
fn first_centre_at_or_after(c: i128) -> i128 {
    ceil_div(c - 8, 16)
}

/// A non-horizontal edge from its top end (smaller y) to its bottom end.
#[derive(Clone, Copy, Debug)]
struct Edge {
    xt: i128,
    yt: i128,
    xb: i128,
    yb: i128,
}

impl Edge {
    /// The exact abscissa at row centre `yc` as a fraction `num / den`, `den > 0`.
    fn x_at(&self, yc: i128) -> (i128, i128) {
        let den = self.yb - self.yt;
        (self.xt * den + (self.xb - self.xt) * (yc - self.yt), den)
    }
}

/// Calls `pixel(x, y, weights)` for every pixel of the `width` x `height` image
/// covered by the snapped triangle `v` (1/16-pixel integer coordinates), row by row,
/// left to right. `weights[i]` is the barycentric weight of vertex `i` at the pixel
/// centre, computed exactly in integers and divided in f64 (so they sum to 1 up to
/// rounding and are all in `[0, 1]`). Degenerate (zero-area) triangles cover nothing.
pub(crate) fn rasterize(
    v: &[[i64; 2]; 3],
    width: u32,
    height: u32,
    mut pixel: impl FnMut(u32, u32, [f64; 3]),
) {
    let area = signed_area(v);
    if area == 0 {
        return;
    }
    let p: [[i128; 2]; 3] = v.map(|q| [q[0] as i128, q[1] as i128]);
    let mut edges = [None; 3];
    for (i, e) in edges.iter_mut().enumerate() {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        if a[1] != b[1] {
            let (t, btm) = if a[1] < b[1] { (a, b) } else { (b, a) };
            *e = Some(Edge {
                xt: t[0],
                yt: t[1],
                xb: btm[0],
                yb: btm[1],
            });
        }
    }
    let ymin = p.iter().map(|q| q[1]).min().unwrap_or(0);
    let ymax = p.iter().map(|q| q[1]).max().unwrap_or(0);
    let row_start = first_centre_at_or_after(ymin).max(0);
    let row_end = first_centre_at_or_after(ymax).min(height as i128);
    let area_f = area as f64;
    // Edge function of vertex i (zero on the opposite edge, `area` at vertex i):
    // e_i(px, py) = (xj-px)*(yk-py) - (xk-px)*(yj-py), (i, j, k) cyclic.
    let edge_fn = |i: usize, px: i128, py: i128| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        (p[j][0] - px) * (p[k][1] - py) - (p[k][0] - px) * (p[j][1] - py)
    };
    // d e_i / d px = yj - yk; one pixel is 16 units.
    let step: [i128; 3] = std::array::from_fn(|i| 16 * (p[(i + 1) % 3][1] - p[(i + 2) % 3][1]));
    for y in row_start..row_end {
        let yc = 16 * y + 8;
        let mut crossing = [(0i128, 1i128); 2];
        let mut n = 0;
        for e in edges.iter().flatten() {
            if e.yt <= yc && yc < e.yb {
                if n < 2 {
                    crossing[n] = e.x_at(yc);
                }
                n += 1;
            }
        }
        if n != 2 {
            debug_assert_eq!(n, 0, "row crossed by {n} edges");
            continue;
        }
        let [(mut n1, mut d1), (mut n2, mut d2)] = crossing;
        if n1 * d2 > n2 * d1 {
            std::mem::swap(&mut n1, &mut n2);
            std::mem::swap(&mut d1, &mut d2);
        }
        // X1 <= 16x+8  <=>  x >= ceil((n1 - 8 d1) / (16 d1)); likewise the first
        // excluded pixel on the right.
        let x_start = ceil_div(n1 - 8 * d1, 16 * d1).max(0);
        let x_end = ceil_div(n2 - 8 * d2, 16 * d2).min(width as i128);
        if x_start >= x_end {
            continue;
        }
        let px = 16 * x_start + 8;
        let mut e = [edge_fn(0, px, yc), edge_fn(1, px, yc), edge_fn(2, px, yc)];
        for x in x_start..x_end {
            pixel(
                x as u32,
                y as u32,
                [
                    e[0] as f64 / area_f,
                    e[1] as f64 / area_f,
                    e[2] as f64 / area_f,
                ],
            );
            for i in 0..3 {
                e[i] += step[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coverage as an ASCII picture ('#' covered, '.' not), rows joined by '\n'.
    fn picture(v: &[[i64; 2]; 3], w: u32, h: u32) -> String {
        let mut grid = vec![vec!['.'; w as usize]; h as usize];
        rasterize(v, w, h, |x, y, _| {
            assert_eq!(grid[y as usize][x as usize], '.', "pixel visited twice");
            grid[y as usize][x as usize] = '#';
        });
        grid.into_iter()
            .map(|r| r.into_iter().collect::<String>())
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn coverage(v: &[[i64; 2]; 3], w: u32, h: u32) -> Vec<u32> {
        let mut c = vec![0; (w * h) as usize];
        rasterize(v, w, h, |x, y, _| c[(y * w + x) as usize] += 1);
        c
    }

    /// The alternative formulation: integer edge functions with the top-left rule.
    fn covered_by_edge_functions(v: &[[i64; 2]; 3], x: i64, y: i64) -> bool {
        let mut v = *v;
        let area = signed_area(&v);
        if area == 0 {
            return false;
        }
        if area < 0 {
            v.swap(1, 2);
        }
        let (px, py) = (16 * x + 8, 16 * y + 8);
        (0..3).all(|i| {
            let (a, b) = (v[i], v[(i + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            // Positive inside for area > 0 (y down).
            let e = dx * (py - a[1]) - dy * (px - a[0]);
            // Left edge: interior to its right (dy < 0); top edge: horizontal with
            // the interior below (dx > 0).
            let top_left = dy < 0 || (dy == 0 && dx > 0);
            e > 0 || (e == 0 && top_left)
        })
    }

    /// xorshift64*, deterministic.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo + 1) as u64) as i64
        }
    }

    #[test]
    fn right_triangle_picture() {
        // (0,0), (8,0), (0,8) pixels: the hypotenuse passes through pixel centres
        // (x + y = 7), which belong to the right edge and are excluded.
        let v = [[0, 0], [0, 128], [128, 0]];
        let want = "\
#######.
######..
#####...
####....
###.....
##......
#.......
........";
        assert_eq!(picture(&v, 8, 8), want);
        // Winding does not matter for coverage.
        assert_eq!(picture(&[v[0], v[2], v[1]], 8, 8), want);
    }

    #[test]
    fn sub_pixel_triangle_picture() {
        // Vertices exactly on pixel centres: (1.5,0.5), (6.5,2.5), (2.5,6.5).
        let v = [[24, 8], [104, 40], [40, 104]];
        let want = "\
........
..##....
..####..
..###...
..##....
..#.....
........
........";
        assert_eq!(picture(&v, 8, 8), want);
    }

    #[test]
    fn clamps_to_the_image() {
        let v = [[-1000, -1000], [5000, -900], [-800, 4000]];
        let c = coverage(&v, 10, 7);
        assert!(c.iter().all(|&n| n == 1));
    }

    #[test]
    fn degenerate_triangles_cover_nothing() {
        assert_eq!(coverage(&[[8, 8], [72, 8], [40, 8]], 8, 8), vec![0; 64]);
        assert_eq!(coverage(&[[0, 0], [64, 64], [32, 32]], 8, 8), vec![0; 64]);
        assert_eq!(coverage(&[[9, 9], [9, 9], [9, 9]], 8, 8), vec![0; 64]);
    }

    #[test]
    fn weights_interpolate_the_vertices() {
        let v = [[3, 5], [150, 20], [40, 120]];
        rasterize(&v, 16, 16, |x, y, w| {
            assert!(w.iter().all(|&a| (-1e-12..=1.0 + 1e-12).contains(&a)));
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let px: f64 = (0..3).map(|i| w[i] * v[i][0] as f64).sum();
            let py: f64 = (0..3).map(|i| w[i] * v[i][1] as f64).sum();
            assert!((px - (16 * x + 8) as f64).abs() < 1e-9);
            assert!((py - (16 * y + 8) as f64).abs() < 1e-9);
        });
    }

    #[test]
    fn shared_edge_covers_each_pixel_once() {
        // A square split along a diagonal through pixel centres, in both triangle
        // orders and both windings; the square extends beyond the image.
        let (a, b, c, d) = ([-16, -16], [144, -16], [144, 144], [-16, 144]);
        for tris in [[[a, b, d], [b, c, d]], [[d, b, a], [b, d, c]]] {
            for order in [[0, 1], [1, 0]] {
                let mut cov = vec![0; 64];
                for &i in &order {
                    for (n, k) in cov.iter_mut().zip(coverage(&tris[i], 8, 8)) {
                        *n += k;
                    }
                }
                assert!(cov.iter().all(|&n| n == 1), "{cov:?}");
            }
        }
    }

    #[test]
    fn random_fans_cover_each_pixel_once() {
        // A fan around an inner point with corners outside a 12x10 image tiles it.
        let mut rng = Rng(0x1234_5678_9abc_def1);
        let (w, h) = (12u32, 10u32);
        for _ in 0..300 {
            let centre = [
                rng.range(-8, 16 * w as i64 + 8),
                rng.range(-8, 16 * h as i64 + 8),
            ];
            // Snap some coordinates to pixel centres or edges to create ties.
            let centre = if rng.next() % 2 == 0 {
                [centre[0] / 8 * 8, centre[1] / 8 * 8]
            } else {
                centre
            };
            let ring = [
                [-16, -16],
                [rng.range(0, 192), -16],
                [16 * w as i64 + 16, -16],
                [16 * w as i64 + 16, rng.range(0, 160)],
                [16 * w as i64 + 16, 16 * h as i64 + 16],
                [rng.range(0, 192), 16 * h as i64 + 16],
                [-16, 16 * h as i64 + 16],
                [-16, rng.range(0, 160)],
            ];
            let reversed = rng.next() % 2 == 0;
            let mut cov = vec![0; (w * h) as usize];
            for i in 0..ring.len() {
                let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
                let tri = if reversed {
                    [centre, q, p]
                } else {
                    [centre, p, q]
                };
                for (n, k) in cov.iter_mut().zip(coverage(&tri, w, h)) {
                    *n += k;
                }
            }
            assert!(cov.iter().all(|&n| n == 1), "centre {centre:?}: {cov:?}");
        }
    }

    #[test]
    fn span_and_edge_function_formulations_agree() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (w, h) = (8u32, 8u32);
        for iter in 0..20_000 {
            let mut v = [[0i64; 2]; 3];
            for q in v.iter_mut() {
                *q = [rng.range(-24, 152), rng.range(-24, 152)];
                match rng.next() % 4 {
                    // On pixel centres.
                    0 => *q = [q[0] / 16 * 16 + 8, q[1] / 16 * 16 + 8],
                    // On a coarse grid (many horizontal/vertical edges).
                    1 => *q = [q[0] / 32 * 32, q[1] / 32 * 32],
                    _ => {}
                }
            }
            if iter % 5 == 0 {
                v[1][1] = v[0][1]; // horizontal edge
            } else if iter % 5 == 1 {
                v[2][0] = v[1][0]; // vertical edge
            }
            let cov = coverage(&v, w, h);
            for y in 0..h as i64 {
                for x in 0..w as i64 {
                    let a = cov[(y * w as i64 + x) as usize] == 1;
                    let b = covered_by_edge_functions(&v, x, y);
                    assert_eq!(a, b, "triangle {v:?}, pixel ({x}, {y})");
                }
            }
        }
    }
}
