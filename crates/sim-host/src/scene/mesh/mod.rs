//! Meshes for the simulator: built-in models (UV sphere, Newell's teapot, a
//! procedural robot) and Wavefront OBJ files with their MTL materials ([`obj`]),
//! all as f64 [`MeshPart`]s: one for a built-in model, one per material group of
//! an OBJ file.
//!
//! Every mesh this module returns has counter-clockwise triangles seen from
//! outside (`(b - a) x (c - a)` points outward) and one unit normal per vertex.
//!
//! ```
//! use fixshade_sim::scene::desc::MeshSource;
//! use fixshade_sim::scene::mesh;
//!
//! let ball = mesh::build(&MeshSource::Sphere { lon: 32, lat: 20 }, ".".as_ref()).unwrap();
//! assert_eq!(ball[0].mesh.triangles.len(), 1216);
//!
//! let err = mesh::build(&MeshSource::Sphere { lon: 2, lat: 20 }, ".".as_ref()).unwrap_err();
//! assert_eq!(err.to_string(), "<builtin sphere>: `lon` must be in 3..=1024, found 2");
//! ```

use std::ops::RangeInclusive;
use std::path::Path;

use crate::scene::desc::{MeshData, MeshPart, MeshSource};

mod error;
pub mod obj;
mod robot;
mod sphere;
mod teapot;
mod teapot_data;
pub(crate) mod vector;

pub use error::MeshError;
pub use obj::{load_obj, parse_obj, MtlFile, MtlReader, MAX_OBJ_VERTICES};
pub use robot::robot;
pub use sphere::sphere;
pub use teapot::teapot;
pub use vector::area_weighted_normals;

/// Valid longitude segment counts of the built-in sphere.
pub const SPHERE_LON_RANGE: RangeInclusive<u32> = 3..=1024;
/// Valid latitude segment counts of the built-in sphere.
pub const SPHERE_LAT_RANGE: RangeInclusive<u32> = 2..=1024;
/// Valid subdivision levels of the built-in teapot.
pub const TEAPOT_LEVEL_RANGE: RangeInclusive<u32> = 1..=64;

/// Builds the mesh a [`MeshSource`] names: one part for a built-in model (without
/// a material of its own), one per material group for an OBJ file ([`load_obj`]).
///
/// A relative OBJ path is resolved against `base_dir` (normally the directory of
/// the scene file); an absolute one is used as it is. Built-in models' arguments
/// are checked against [`SPHERE_LON_RANGE`], [`SPHERE_LAT_RANGE`] and
/// [`TEAPOT_LEVEL_RANGE`]; a value outside gives an error naming
/// `<builtin sphere>` or `<builtin teapot>`.
pub fn build(source: &MeshSource, base_dir: &Path) -> Result<Vec<MeshPart>, MeshError> {
    let builtin = |name: &str, mesh: MeshData| {
        Ok(vec![MeshPart {
            name: name.to_owned(),
            mesh,
            material: None,
        }])
    };
    match *source {
        MeshSource::Sphere { lon, lat } => {
            const FILE: &str = "<builtin sphere>";
            check_range(FILE, "lon", lon, SPHERE_LON_RANGE)?;
            check_range(FILE, "lat", lat, SPHERE_LAT_RANGE)?;
            builtin("sphere", sphere(lon, lat))
        }
        MeshSource::Teapot { level } => {
            check_range("<builtin teapot>", "level", level, TEAPOT_LEVEL_RANGE)?;
            builtin("teapot", teapot(level))
        }
        MeshSource::Robot => builtin("robot", robot()),
        MeshSource::Obj { ref path } => load_obj(&base_dir.join(path)),
    }
}

fn check_range(
    file: &str,
    what: &str,
    value: u32,
    range: RangeInclusive<u32>,
) -> Result<(), MeshError> {
    if range.contains(&value) {
        Ok(())
    } else {
        let message = format!(
            "`{what}` must be in {}..={}, found {value}",
            range.start(),
            range.end()
        );
        Err(MeshError::new(file, None, message))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use std::collections::HashMap;

    use super::vector::{cross, dot, fit_unit_box, sub};
    use super::*;

    /// Checks what every mesh must satisfy: matching lengths, indices in range,
    /// finite positions, unit normals.
    pub(crate) fn assert_well_formed(mesh: &MeshData) {
        assert_eq!(mesh.positions.len(), mesh.normals.len());
        let n = mesh.positions.len() as u32;
        for tri in &mesh.triangles {
            assert!(tri.iter().all(|&i| i < n), "index out of range in {tri:?}");
        }
        for p in &mesh.positions {
            assert!(p.iter().all(|c| c.is_finite()), "position {p:?}");
        }
        for nrm in &mesh.normals {
            assert!((dot(*nrm, *nrm) - 1.0).abs() < 1e-9, "normal {nrm:?}");
        }
    }

    /// How the directed edges of a mesh pair up.
    #[derive(Debug, Default, PartialEq)]
    pub(crate) struct EdgeStats {
        /// Edges used by one triangle only.
        pub boundary: usize,
        /// Edges used once in each direction.
        pub paired: usize,
        /// Edges used twice in the same direction, or by more than two triangles.
        pub bad: usize,
    }

    /// Counts boundary, correctly paired and badly paired edges, identifying
    /// vertices by index.
    pub(crate) fn edge_stats(triangles: &[[u32; 3]]) -> EdgeStats {
        // (lo, hi) -> (uses as lo->hi, uses as hi->lo)
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let entry = uses.entry((a.min(b), a.max(b))).or_default();
                if a < b {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
        }
        let mut stats = EdgeStats::default();
        for (fwd, back) in uses.into_values() {
            match (fwd, back) {
                (1, 0) | (0, 1) => stats.boundary += 1,
                (1, 1) => stats.paired += 1,
                _ => stats.bad += 1,
            }
        }
        stats
    }

    /// Signed volume enclosed by the triangles, relative to the origin.
    pub(crate) fn signed_volume(mesh: &MeshData) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                dot(a, cross(b, c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn normals_of_a_tetrahedron_point_outward() {
        let positions = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let triangles = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let normals = area_weighted_normals(&positions, &triangles);
        let centre = [0.25; 3];
        for (p, n) in positions.iter().zip(&normals) {
            assert!(dot(*n, sub(*p, centre)) > 0.0);
            assert!((dot(*n, *n) - 1.0).abs() < 1e-12);
        }
        // The origin corner sees three equal right triangles: normal along -(1,1,1).
        let k = -(1.0f64 / 3.0).sqrt();
        for c in normals[0] {
            assert!((c - k).abs() < 1e-12);
        }
    }

    #[test]
    fn unused_or_degenerate_vertices_get_up_normal() {
        let positions = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [5.0, 5.0, 5.0]];
        let normals = area_weighted_normals(&positions, &[[0, 1, 2]]);
        assert!(normals.iter().all(|n| *n == [0.0, 1.0, 0.0]));
    }

    #[test]
    fn fit_unit_box_centres_and_scales() {
        let mut p = [[1.0, 2.0, 3.0], [5.0, 3.0, 4.0]];
        fit_unit_box(&mut p);
        assert_eq!(p, [[-1.0, -0.25, -0.25], [1.0, 0.25, 0.25]]);
    }

    #[test]
    fn build_checks_builtin_arguments() {
        let dir = Path::new(".");
        let cases = [
            (
                MeshSource::Sphere { lon: 2, lat: 20 },
                "<builtin sphere>: `lon` must be in 3..=1024, found 2",
            ),
            (
                MeshSource::Sphere { lon: 8, lat: 1 },
                "<builtin sphere>: `lat` must be in 2..=1024, found 1",
            ),
            (
                MeshSource::Sphere { lon: 1025, lat: 8 },
                "<builtin sphere>: `lon` must be in 3..=1024, found 1025",
            ),
            (
                MeshSource::Teapot { level: 0 },
                "<builtin teapot>: `level` must be in 1..=64, found 0",
            ),
            (
                MeshSource::Teapot { level: 65 },
                "<builtin teapot>: `level` must be in 1..=64, found 65",
            ),
        ];
        for (source, expected) in cases {
            assert_eq!(build(&source, dir).unwrap_err().to_string(), expected);
        }
        let mesh = |source: MeshSource| build(&source, dir).unwrap().remove(0).mesh;
        assert_eq!(
            mesh(MeshSource::Sphere { lon: 3, lat: 2 }).triangles.len(),
            6
        );
        assert_eq!(mesh(MeshSource::Teapot { level: 1 }), teapot(1));
        assert_eq!(mesh(MeshSource::Robot), robot());
    }

    #[test]
    fn build_resolves_obj_paths_against_base_dir() {
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let relative = MeshSource::Obj {
            path: "obj/cube.obj".into(),
        };
        let cube = build(&relative, &base).unwrap();
        assert_eq!(cube[0].mesh.triangles.len(), 12);
        let absolute = MeshSource::Obj {
            path: base.join("obj/cube.obj"),
        };
        assert_eq!(build(&absolute, Path::new("/nonexistent")).unwrap(), cube);
        let missing = MeshSource::Obj {
            path: "obj/missing.obj".into(),
        };
        let err = build(&missing, &base).unwrap_err();
        assert!(err.to_string().contains("missing.obj"), "{err}");
        assert_eq!(err.line, None);
    }

    #[test]
    fn error_display_names_file_and_line() {
        let e = MeshError::new(
            "teapot.obj",
            Some(12),
            "expected 3 numbers after `v`, found 2",
        );
        assert_eq!(
            e.to_string(),
            "teapot.obj:12: expected 3 numbers after `v`, found 2"
        );
        let e = MeshError::new("model.obj", None, "no triangles");
        assert_eq!(e.to_string(), "model.obj: no triangles");
    }
}
