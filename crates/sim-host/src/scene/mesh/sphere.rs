//! UV sphere.

use std::f64::consts::PI;

use crate::scene::desc::MeshData;

/// UV sphere of radius 1 centred at the origin, with normals equal to positions.
///
/// Latitude rings `i = 1..lat` sit at polar angle `theta = pi * i / lat` from +y
/// (`y = cos theta`); ring vertex `j` is at longitude `phi = 2 * pi * j / lon`,
/// `x = sin theta * sin phi`, `z = sin theta * cos phi`, so `j = 0` lies towards
/// +z. Each pole is a single vertex closed by a fan of cap triangles (no
/// degenerate quads) and the seam has no duplicated vertices, which gives
/// `lon * (lat - 1) + 2` vertices and `2 * lon * (lat - 1)` triangles, all
/// counter-clockwise seen from outside.
///
/// # Panics
///
/// If `lon < 3` or `lat < 2`; [`build`](super::build) checks its arguments first.
pub fn sphere(lon: u32, lat: u32) -> MeshData {
    assert!(
        lon >= 3 && lat >= 2,
        "sphere needs lon >= 3 and lat >= 2, got {lon} x {lat}"
    );
    let ring_count = (lat - 1) as usize;
    let mut positions = Vec::with_capacity(lon as usize * ring_count + 2);
    positions.push([0.0, 1.0, 0.0]);
    for i in 1..lat {
        let (sin_t, cos_t) = (PI * f64::from(i) / f64::from(lat)).sin_cos();
        for j in 0..lon {
            let (sin_p, cos_p) = (2.0 * PI * f64::from(j) / f64::from(lon)).sin_cos();
            positions.push([sin_t * sin_p, cos_t, sin_t * cos_p]);
        }
    }
    positions.push([0.0, -1.0, 0.0]);

    let north = 0;
    let south = positions.len() as u32 - 1;
    // Vertex j (wrapping around) of ring i (1..lat).
    let ring = |i: u32, j: u32| 1 + (i - 1) * lon + j % lon;
    let mut triangles = Vec::with_capacity(2 * lon as usize * ring_count);
    for j in 0..lon {
        triangles.push([north, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..lat - 1 {
        for j in 0..lon {
            let (a, b) = (ring(i, j), ring(i, j + 1));
            let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    for j in 0..lon {
        triangles.push([ring(lat - 1, j), south, ring(lat - 1, j + 1)]);
    }

    MeshData {
        normals: positions.clone(),
        positions,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::tests::{assert_well_formed, edge_stats, signed_volume, EdgeStats};
    use crate::scene::mesh::vector::{add, dot, face_normal, scale};

    #[test]
    fn triangle_and_vertex_counts() {
        for (lon, lat, tris) in [(32, 20, 1216), (64, 40, 4992), (128, 80, 20224), (3, 2, 6)] {
            let m = sphere(lon, lat);
            assert_eq!(m.triangles.len(), tris, "{lon} x {lat}");
            assert_eq!(m.positions.len(), (lon * (lat - 1) + 2) as usize);
        }
    }

    #[test]
    fn vertices_on_unit_sphere_with_normals_equal_to_positions() {
        let m = sphere(32, 20);
        assert_well_formed(&m);
        assert_eq!(m.positions, m.normals);
        assert_eq!(m.positions[0], [0.0, 1.0, 0.0]);
        assert_eq!(*m.positions.last().unwrap(), [0.0, -1.0, 0.0]);
        // Ring 1, j = 0 lies towards +z; j = lon/4 towards +x.
        let [x, _, z] = m.positions[1];
        assert!(x.abs() < 1e-12 && z > 0.0);
        let [x, _, z] = m.positions[1 + 8];
        assert!(x > 0.0 && z.abs() < 1e-12);
    }

    #[test]
    fn triangles_counter_clockwise_from_outside_and_closed() {
        for (lon, lat) in [(3, 2), (5, 3), (32, 20), (64, 40)] {
            let m = sphere(lon, lat);
            for t in &m.triangles {
                let centroid = t
                    .iter()
                    .fold([0.0; 3], |s, &i| add(s, m.positions[i as usize]));
                let n = face_normal(&m.positions, t);
                assert!(dot(n, scale(centroid, 1.0 / 3.0)) > 0.0, "{t:?}");
            }
            let expected = EdgeStats {
                boundary: 0,
                paired: m.triangles.len() * 3 / 2,
                bad: 0,
            };
            assert_eq!(edge_stats(&m.triangles), expected);
            assert!(signed_volume(&m) > 0.0);
        }
    }
}
