//! Meshes for the simulator: built-in models (UV sphere, Newell's teapot, a
//! procedural robot) and Wavefront OBJ files, all as f64 [`MeshData`].
//!
//! Every mesh this module returns has counter-clockwise triangles seen from
//! outside (`(b - a) x (c - a)` points outward) and one unit normal per vertex.
//!
//! ```
//! use fixshade_sim::desc::MeshSource;
//! use fixshade_sim::mesh;
//!
//! let ball = mesh::build(&MeshSource::Sphere { lon: 32, lat: 20 }, ".".as_ref()).unwrap();
//! assert_eq!(ball.triangles.len(), 1216);
//!
//! let err = mesh::build(&MeshSource::Sphere { lon: 2, lat: 20 }, ".".as_ref()).unwrap_err();
//! assert_eq!(err.to_string(), "<builtin sphere>: `lon` must be in 3..=1024, found 2");
//! ```

use std::fmt;
use std::ops::RangeInclusive;
use std::path::Path;

use crate::scene::desc::{MeshData, MeshSource};

mod obj;
mod robot;
mod sphere;
mod teapot;
mod teapot_data;

pub use obj::{load_obj, parse_obj};
pub use robot::robot;
pub use sphere::sphere;
pub use teapot::teapot;

/// Valid longitude segment counts of the built-in sphere.
pub const SPHERE_LON_RANGE: RangeInclusive<u32> = 3..=1024;
/// Valid latitude segment counts of the built-in sphere.
pub const SPHERE_LAT_RANGE: RangeInclusive<u32> = 2..=1024;
/// Valid subdivision levels of the built-in teapot.
pub const TEAPOT_LEVEL_RANGE: RangeInclusive<u32> = 1..=64;
/// Most vertices an OBJ file may have: the core indexes vertices with `u16`.
pub const MAX_OBJ_VERTICES: usize = u16::MAX as usize;

/// Why a mesh could not be built: which file (or built-in model), which line if
/// one applies, and what was wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshError {
    /// File name as given, or `<builtin sphere>` / `<builtin teapot>` for
    /// built-in models.
    pub file: String,
    /// 1-based line number, when the error belongs to one line.
    pub line: Option<usize>,
    /// What was expected or found, without the file and line.
    pub message: String,
}

impl MeshError {
    fn new(file: &str, line: Option<usize>, message: impl Into<String>) -> Self {
        MeshError {
            file: file.to_owned(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for MeshError {
    /// `file:line: message`, or `file: message` when no line applies.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file, line, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for MeshError {}

/// Builds the mesh a [`MeshSource`] names.
///
/// A relative OBJ path is resolved against `base_dir` (normally the directory of
/// the scene file); an absolute one is used as it is. Built-in models' arguments
/// are checked against [`SPHERE_LON_RANGE`], [`SPHERE_LAT_RANGE`] and
/// [`TEAPOT_LEVEL_RANGE`]; a value outside gives an error naming
/// `<builtin sphere>` or `<builtin teapot>`.
pub fn build(source: &MeshSource, base_dir: &Path) -> Result<MeshData, MeshError> {
    match *source {
        MeshSource::Sphere { lon, lat } => {
            const FILE: &str = "<builtin sphere>";
            check_range(FILE, "lon", lon, SPHERE_LON_RANGE)?;
            check_range(FILE, "lat", lat, SPHERE_LAT_RANGE)?;
            Ok(sphere(lon, lat))
        }
        MeshSource::Teapot { level } => {
            check_range("<builtin teapot>", "level", level, TEAPOT_LEVEL_RANGE)?;
            Ok(teapot(level))
        }
        MeshSource::Robot => Ok(robot()),
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

/// Area-weighted vertex normals: each vertex gets the normalised sum of the
/// unnormalised face normals `(b - a) x (c - a)` of the triangles that use it, so
/// large triangles count more than small ones. A vertex whose sum is zero (unused,
/// or only in degenerate triangles) gets `(0, 1, 0)`.
///
/// # Panics
///
/// If a triangle indexes past the end of `positions`.
pub fn area_weighted_normals(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    let mut sums = vec![[0.0; 3]; positions.len()];
    for tri in triangles {
        let n = face_normal(positions, tri);
        for &i in tri {
            sums[i as usize] = add(sums[i as usize], n);
        }
    }
    sums.into_iter()
        .map(|s| normalize(s).unwrap_or([0.0, 1.0, 0.0]))
        .collect()
}

// Small f64 vector helpers shared by the submodules.

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|`, or `None` if `a` is zero.
fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let len = dot(a, a).sqrt();
    if len > 0.0 && len.is_finite() {
        return Some(scale(a, 1.0 / len));
    }
    // The squared length overflowed or underflowed (huge or tiny finite
    // components): divide by the largest component first. Infinite or NaN
    // components have no direction.
    if !a.iter().all(|c| c.is_finite()) {
        return None;
    }
    let m = a.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if m == 0.0 {
        return None;
    }
    let b = a.map(|c| c / m);
    let len = dot(b, b).sqrt();
    Some(b.map(|c| c / len))
}

/// Unnormalised normal `(b - a) x (c - a)` of a triangle: twice its area in length.
fn face_normal(positions: &[[f64; 3]], tri: &[u32; 3]) -> [f64; 3] {
    let [a, b, c] = tri.map(|i| positions[i as usize]);
    cross(sub(b, a), sub(c, a))
}

/// Moves and scales `positions` in place so that their bounding box is centred at
/// the origin and its largest half-extent is 1.
fn fit_unit_box(positions: &mut [[f64; 3]]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let centre = scale(add(lo, hi), 0.5);
    let half = (0..3).map(|k| (hi[k] - lo[k]) * 0.5).fold(0.0, f64::max);
    if half > 0.0 {
        for p in positions.iter_mut() {
            *p = scale(sub(*p, centre), 1.0 / half);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use std::collections::HashMap;

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
        assert_eq!(
            build(&MeshSource::Sphere { lon: 3, lat: 2 }, dir)
                .unwrap()
                .triangles
                .len(),
            6
        );
        assert_eq!(
            build(&MeshSource::Teapot { level: 1 }, dir).unwrap(),
            teapot(1)
        );
        assert_eq!(build(&MeshSource::Robot, dir).unwrap(), robot());
    }

    #[test]
    fn build_resolves_obj_paths_against_base_dir() {
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let relative = MeshSource::Obj {
            path: "obj/cube.obj".into(),
        };
        let cube = build(&relative, &base).unwrap();
        assert_eq!(cube.triangles.len(), 12);
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
