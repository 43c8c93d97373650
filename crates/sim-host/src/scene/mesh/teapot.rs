//! Newell's teapot, tessellated from its 32 bicubic Bézier patches.
//!
//! Steps: evaluate each patch on a `(level + 1)^2` grid, weld equal positions
//! across patch seams, fit the model into the unit box, drop the degenerate
//! triangles of the patches that collapse to a point (the top of the knob and
//! the centre of the bottom), orient every triangle outward, and compute
//! area-weighted normals.

use std::collections::HashMap;

use super::teapot_data::PATCHES;
use super::vector::{add, area_weighted_normals, dot, face_normal, fit_unit_box, scale, sub};
use crate::scene::desc::MeshData;

/// Positions that differ by at most this much in every coordinate (in the units
/// of the patch data, about 3.5 wide) become one vertex. Points evaluated on a
/// shared border by two patches can differ by an ulp or so, for example where
/// the patches run in opposite parameter directions.
const WELD_EPS: f64 = 1e-9;

/// Newell's teapot with each of its 32 patches cut into `level` x `level` quads of
/// two triangles, evaluated at `u, v = k / level`.
///
/// The model is turned from the data's z-up to y-up (`(x, y, z) -> (x, z, -y)`:
/// spout towards +x, handle towards -x), then centred and scaled so that the
/// bounding box of the tessellated points is centred at the origin and its
/// largest half-extent (along x) is 1. The centre is taken from the tessellated
/// points, so it depends very slightly on `level`.
///
/// Vertices are shared across patch seams. Degenerate triangles are dropped: one
/// per quad along the sides of the knob-top and bottom patches that collapse to a
/// point, which leaves `64 * level^2 - 8 * level` triangles for `level >= 2`
/// (992 at level 4, 4032 at 8, 16256 at 16; level 1 also loses the flat spout
/// tip, leaving 52). All triangles face outward. The mesh is not closed: the
/// rim's inner edge, the lid's lower edge and both ends of the handle and of the
/// spout are open, `16 * level` boundary edges for `level >= 2`. Normals are
/// area-weighted vertex normals of the welded mesh.
///
/// There are `32 * level^2 + 4 * level + 1` vertices for `level >= 2`, so
/// levels above 45 have more than the 65535 a 16-bit index can address.
///
/// # Panics
///
/// If `level` is 0; [`build`](super::build) checks its argument first.
pub fn teapot(level: u32) -> MeshData {
    assert!(level >= 1, "teapot level must be at least 1");
    let n = level as usize;
    let weights: Vec<[f64; 4]> = (0..=n).map(|k| bernstein(k as f64 / n as f64)).collect();

    let mut welder = Welder::default();
    let mut triangles = Vec::with_capacity(PATCHES.len() * n * n * 2);
    for patch in &PATCHES {
        let mut grid = Vec::with_capacity((n + 1) * (n + 1));
        for wu in &weights {
            for wv in &weights {
                grid.push(welder.index(y_up(evaluate(patch, wu, wv))));
            }
        }
        let at = |i: usize, j: usize| grid[i * (n + 1) + j];
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (at(i, j), at(i, j + 1));
                let (c, d) = (at(i + 1, j), at(i + 1, j + 1));
                // Orientation is fixed below, patch data being inconsistent.
                triangles.extend([[a, b, d], [a, d, c]]);
            }
        }
    }

    let mut positions = welder.positions;
    fit_unit_box(&mut positions);
    triangles.retain(|t| !is_degenerate(&positions, t));
    orient_outward(&positions, &mut triangles, [0.0; 3]);
    let normals = area_weighted_normals(&positions, &triangles);
    MeshData {
        positions,
        normals,
        triangles,
    }
}

/// The cubic Bernstein polynomials at `t`.
fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

/// Point of a bicubic patch (row-major control points) for the Bernstein weights
/// of `u` (across rows) and `v` (across columns).
fn evaluate(patch: &[[f64; 3]; 16], wu: &[f64; 4], wv: &[f64; 4]) -> [f64; 3] {
    let mut p = [0.0; 3];
    for (i, bu) in wu.iter().enumerate() {
        for (j, bv) in wv.iter().enumerate() {
            p = add(p, scale(patch[4 * i + j], bu * bv));
        }
    }
    p
}

/// z-up to y-up, keeping the coordinate system right-handed.
fn y_up([x, y, z]: [f64; 3]) -> [f64; 3] {
    [x, z, -y]
}

/// True if a triangle repeats a vertex or has zero area.
fn is_degenerate(positions: &[[f64; 3]], t: &[u32; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || face_normal(positions, t) == [0.0; 3]
}

/// Collects vertices, giving positions within [`WELD_EPS`] of an earlier one that
/// one's index. Positions are hashed by their cell in a grid of `WELD_EPS` cells;
/// a match can only lie in the same or a neighbouring cell.
#[derive(Default)]
struct Welder {
    positions: Vec<[f64; 3]>,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl Welder {
    fn index(&mut self, p: [f64; 3]) -> u32 {
        let cell = p.map(|c| (c / WELD_EPS).floor() as i64);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                    for &i in self.cells.get(&key).into_iter().flatten() {
                        let q = self.positions[i as usize];
                        if (0..3).all(|k| (p[k] - q[k]).abs() <= WELD_EPS) {
                            return i;
                        }
                    }
                }
            }
        }
        let i = self.positions.len() as u32;
        self.positions.push(p);
        self.cells.entry(cell).or_default().push(i);
        i
    }
}

/// Makes each edge-connected piece of the mesh consistently oriented, then turns
/// each piece to face away from `centre`.
///
/// Consistency spreads from a seed triangle to its neighbours across edges shared
/// by exactly two triangles: a neighbour that runs the shared edge in the same
/// direction is flipped. A piece then faces outward if the sum over its triangles
/// of `((b - a) x (c - a)) . (centroid - centre)` is positive; for a closed piece
/// this is six times its volume whatever `centre` is. The teapot's pieces (body
/// with rim and bottom, lid with knob, handle, spout) are open only at small holes
/// or at holes whose missing flux has the right sign for a centre inside the body.
fn orient_outward(positions: &[[f64; 3]], triangles: &mut [[u32; 3]], centre: [f64; 3]) {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut users: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for (a, b) in edges(tri) {
            users.entry(key(a, b)).or_default().push(t);
        }
    }

    let mut visited = vec![false; triangles.len()];
    let mut piece = Vec::new();
    for seed in 0..triangles.len() {
        if visited[seed] {
            continue;
        }
        visited[seed] = true;
        piece.clear();
        piece.push(seed);
        let mut next = 0;
        while let Some(&t) = piece.get(next) {
            next += 1;
            let tri = triangles[t];
            for (a, b) in edges(&tri) {
                let &[t0, t1] = users[&key(a, b)].as_slice() else {
                    continue; // boundary or non-manifold edge: no constraint
                };
                let other = if t0 == t { t1 } else { t0 };
                if !visited[other] {
                    visited[other] = true;
                    if edges(&triangles[other]).any(|e| e == (a, b)) {
                        flip(&mut triangles[other]);
                    }
                    piece.push(other);
                }
            }
        }

        let flux: f64 = piece
            .iter()
            .map(|&t| {
                let tri = &triangles[t];
                let centroid = tri
                    .iter()
                    .fold([0.0; 3], |s, &i| add(s, positions[i as usize]));
                dot(
                    face_normal(positions, tri),
                    sub(scale(centroid, 1.0 / 3.0), centre),
                )
            })
            .sum();
        if flux < 0.0 {
            for &t in &piece {
                flip(&mut triangles[t]);
            }
        }
    }
}

/// The three directed edges of a triangle.
fn edges(t: &[u32; 3]) -> impl Iterator<Item = (u32, u32)> + '_ {
    (0..3).map(move |k| (t[k], t[(k + 1) % 3]))
}

fn flip(t: &mut [u32; 3]) {
    t.swap(1, 2);
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::scene::mesh::tests::{assert_well_formed, edge_stats, signed_volume};

    /// `teapot.bpt` as shipped in the shared models folder, if it is there.
    fn read_bpt() -> Option<String> {
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
        [
            "../../shared/models/teapot.bpt",
            "../../../shared/models/teapot.bpt",
        ]
        .iter()
        .find_map(|rel| std::fs::read_to_string(manifest.join(rel)).ok())
    }

    #[test]
    fn const_data_matches_teapot_bpt() {
        let Some(text) = read_bpt() else {
            return;
        };
        let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
        let numbers = |line: &str| -> Vec<f64> {
            line.split_whitespace()
                .map(|t| t.parse().expect("number in teapot.bpt"))
                .collect()
        };
        assert_eq!(lines.next(), Some("32"));
        for (k, patch) in PATCHES.iter().enumerate() {
            assert_eq!(lines.next(), Some("3 3"), "patch {k} header");
            for (i, point) in patch.iter().enumerate() {
                let row = numbers(lines.next().expect("control point"));
                assert_eq!(row, point.to_vec(), "patch {k}, point {i}");
            }
        }
        assert_eq!(lines.next(), None);
    }

    #[test]
    fn triangle_counts() {
        // 32 patches * level^2 quads * 2, minus one triangle per quad along the
        // collapsed side of the 4 knob-top and 4 bottom patches.
        for (level, tris) in [(2, 240), (4, 992), (8, 4032), (16, 16256)] {
            let m = teapot(level as u32);
            assert_eq!(m.triangles.len(), tris, "level {level}");
            assert_eq!(tris, 64 * level * level - 8 * level);
            assert_eq!(m.positions.len(), 32 * level * level + 4 * level + 1);
        }
        // At level 1 the spout tip patches' corners are collinear: 4 more go.
        assert_eq!(teapot(1).triangles.len(), 52);
    }

    #[test]
    fn fits_the_unit_box_and_is_well_formed() {
        for level in [1, 3, 8] {
            let m = teapot(level);
            assert_well_formed(&m);
            for k in 0..3 {
                let lo = m
                    .positions
                    .iter()
                    .map(|p| p[k])
                    .fold(f64::INFINITY, f64::min);
                let hi = m
                    .positions
                    .iter()
                    .map(|p| p[k])
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!((lo + hi).abs() < 1e-12, "axis {k} centred: {lo} .. {hi}");
                assert!(hi <= 1.0 + 1e-12);
            }
            // Spout and handle lie along x, the widest axis.
            let x_max = m
                .positions
                .iter()
                .map(|p| p[0])
                .fold(f64::NEG_INFINITY, f64::max);
            assert!((x_max - 1.0).abs() < 1e-12);
            assert!(m.triangles.iter().all(|t| !is_degenerate(&m.positions, t)));
        }
    }

    #[test]
    fn seams_are_welded() {
        let level = 8;
        let m = teapot(level);
        // Without welding every patch would have its own (level + 1)^2 grid.
        assert!(m.positions.len() < 32 * (level as usize + 1).pow(2) * 9 / 10);
        // Each interior edge is used once in each direction; the boundary is the
        // rim's inner edge, the lid's lower edge and the two ends of the handle and
        // of the spout, each of two or four patch sides: 16 * level edges.
        let stats = edge_stats(&m.triangles);
        assert_eq!(stats.bad, 0, "{stats:?}");
        assert_eq!(stats.boundary, 16 * level as usize, "{stats:?}");
        assert_eq!(edge_stats(&teapot(4).triangles).boundary, 64);
    }

    #[test]
    fn faces_outward() {
        for level in [1, 4, 8] {
            let m = teapot(level);
            assert!(signed_volume(&m) > 0.0, "level {level}");
        }
        // Top of the knob points up, centre of the bottom points down; both are
        // single welded vertices.
        let m = teapot(8);
        let top =
            (0..m.positions.len()).max_by(|&a, &b| m.positions[a][1].total_cmp(&m.positions[b][1]));
        let bottom =
            (0..m.positions.len()).min_by(|&a, &b| m.positions[a][1].total_cmp(&m.positions[b][1]));
        assert!(m.normals[top.unwrap()][1] > 0.999);
        assert!(m.normals[bottom.unwrap()][1] < -0.999);
    }

    #[test]
    fn welder_merges_near_points_across_cell_borders() {
        let mut w = Welder::default();
        let a = w.index([1.0, 2.0, 3.0]);
        let b = w.index([1.0 + 1e-12, 2.0 - 1e-12, 3.0]);
        let c = w.index([1.0 + 1e-6, 2.0, 3.0]);
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(w.positions.len(), 2);
    }
}
