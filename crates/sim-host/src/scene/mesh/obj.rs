//! Wavefront OBJ loading.
//!
//! This is a small parser of its own rather than `tobj`, because `tobj`'s errors
//! carry no line numbers and errors here must name the file, the line and what was
//! expected.

use std::path::Path;

use super::error::MeshError;
use super::vector::area_weighted_normals;
use crate::scene::desc::MeshData;

/// Most vertices an OBJ file may have: the core indexes vertices with `u16`.
pub const MAX_OBJ_VERTICES: usize = u16::MAX as usize;

/// Reads and parses an OBJ file; see [`parse_obj`]. Errors name the file as
/// `path` displays; a file that cannot be read gives an error without a line.
/// Bytes that are not UTF-8 are replaced (they can only matter in comments and
/// names, which are ignored).
pub fn load_obj(path: &Path) -> Result<MeshData, MeshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MeshError::new(&name, None, format!("cannot read the file: {e}")))?;
    parse_obj(&String::from_utf8_lossy(&bytes), &name)
}

/// Parses the text of an OBJ file; `name` is the file name used in errors.
///
/// Only two statements matter:
/// - `v x y z` adds a vertex. It needs at least 3 numbers, all finite; further
///   numbers (a `w`, or vertex colours) are allowed and ignored.
/// - `f i j k ...` adds a face of at least 3 vertex references, each `i`, `i/t`,
///   `i//n` or `i/t/n`. Indices start at 1; a negative index counts back from the
///   last vertex defined so far (`-1` is the last). Only the vertex index is used.
///   Faces with more than 3 vertices are cut into a fan around their first vertex.
///
/// Every other statement (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, ...)
/// is accepted and ignored, and so is everything after a `#`. In particular `vn`
/// normals are ignored: normals are always computed with
/// [`area_weighted_normals`], so vertices are shared by position only.
///
/// Errors: a malformed `v` or `f` line, an index that is 0 or refers to a vertex
/// not yet defined, more than [`MAX_OBJ_VERTICES`] vertices (the core indexes
/// vertices with `u16`), and a file without any face ("no triangles").
pub fn parse_obj(text: &str, name: &str) -> Result<MeshData, MeshError> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let at_line = |message: String| MeshError::new(name, Some(number + 1), message);
        let statement = raw.split('#').next().unwrap_or("");
        let mut tokens = statement.split_whitespace();
        match tokens.next() {
            Some("v") => {
                if positions.len() == MAX_OBJ_VERTICES {
                    return Err(at_line(format!(
                        "too many vertices: at most {MAX_OBJ_VERTICES} are supported \
                         (the renderer uses 16-bit indices)"
                    )));
                }
                positions.push(parse_vertex(tokens).map_err(at_line)?);
            }
            Some("f") => {
                let refs = tokens
                    .map(|t| parse_index(t, positions.len()))
                    .collect::<Result<Vec<u32>, String>>()
                    .map_err(at_line)?;
                if refs.len() < 3 {
                    return Err(at_line(format!(
                        "expected at least 3 vertices after `f`, found {}",
                        refs.len()
                    )));
                }
                triangles.extend(refs.windows(2).skip(1).map(|w| [refs[0], w[0], w[1]]));
            }
            _ => {}
        }
    }
    if triangles.is_empty() {
        return Err(MeshError::new(name, None, "no triangles"));
    }
    let normals = area_weighted_normals(&positions, &triangles);
    Ok(MeshData {
        positions,
        normals,
        triangles,
    })
}

/// The numbers after `v`: at least 3, all finite.
fn parse_vertex<'a>(tokens: impl Iterator<Item = &'a str>) -> Result<[f64; 3], String> {
    let mut numbers = Vec::with_capacity(4);
    for token in tokens {
        let value: f64 = token
            .parse()
            .map_err(|_| format!("expected a number after `v`, found `{token}`"))?;
        if !value.is_finite() {
            return Err(format!(
                "vertex coordinate `{token}` is not a finite number"
            ));
        }
        numbers.push(value);
    }
    match numbers[..] {
        [x, y, z, ..] => Ok([x, y, z]),
        _ => Err(format!(
            "expected 3 numbers after `v`, found {}",
            numbers.len()
        )),
    }
}

/// The 0-based vertex index of one `f` reference, given how many vertices have
/// been defined so far.
fn parse_index(token: &str, defined: usize) -> Result<u32, String> {
    let vertex = token.split('/').next().unwrap_or("");
    let index: i64 = vertex
        .parse()
        .map_err(|_| format!("expected a vertex index after `f`, found `{token}`"))?;
    let resolved = match index {
        0 => return Err("vertex index 0 is invalid (OBJ indices start at 1)".to_owned()),
        i if i > 0 => usize::try_from(i - 1).ok(),
        i => usize::try_from(i.unsigned_abs())
            .ok()
            .and_then(|back| defined.checked_sub(back)),
    };
    match resolved {
        Some(i) if i < defined => Ok(i as u32),
        _ => {
            let noun = if defined == 1 { "vertex" } else { "vertices" };
            Err(format!(
                "vertex index {index} is out of range: {defined} {noun} defined so far"
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::scene::mesh::tests::{assert_well_formed, edge_stats, signed_volume};
    use crate::scene::mesh::vector::{dot, face_normal};

    fn data_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/obj")
    }

    /// Every file in `tests/data/obj/bad`, with the line its error must name (if
    /// any) and a piece of the message.
    const BAD: &[(&str, Option<usize>, &str)] = &[
        (
            "missing_coordinate.obj",
            Some(4),
            "expected 3 numbers after `v`, found 2",
        ),
        (
            "not_a_number.obj",
            Some(3),
            "expected a number after `v`, found `1,5`",
        ),
        (
            "index_out_of_range.obj",
            Some(6),
            "vertex index 4 is out of range: 3 vertices",
        ),
        (
            "negative_index_out_of_range.obj",
            Some(5),
            "vertex index -4 is out of range",
        ),
        ("index_zero.obj", Some(5), "vertex index 0 is invalid"),
        (
            "forward_reference.obj",
            Some(3),
            "vertex index 2 is out of range: 1 vertex defined",
        ),
        (
            "face_two_vertices.obj",
            Some(6),
            "expected at least 3 vertices after `f`, found 2",
        ),
        (
            "face_bad_reference.obj",
            Some(5),
            "expected a vertex index after `f`, found `x/1`",
        ),
        (
            "nan.obj",
            Some(3),
            "vertex coordinate `nan` is not a finite number",
        ),
        (
            "infinity.obj",
            Some(4),
            "vertex coordinate `-inf` is not a finite number",
        ),
        ("empty.obj", None, "no triangles"),
        ("no_faces.obj", None, "no triangles"),
        ("only_comments.obj", None, "no triangles"),
    ];

    #[test]
    fn bad_corpus_gives_errors_naming_file_and_line() {
        let dir = data_dir().join("bad");
        let mut seen = Vec::new();
        for entry in std::fs::read_dir(&dir).expect("bad corpus directory") {
            let path = entry.unwrap().path();
            let file = path.file_name().unwrap().to_str().unwrap().to_owned();
            let &(_, line, fragment) = BAD
                .iter()
                .find(|(name, ..)| *name == file)
                .unwrap_or_else(|| panic!("{file} is not listed in BAD"));
            let err = load_obj(&path).expect_err(&file);
            let shown = err.to_string();
            assert!(shown.contains(&file), "{shown}");
            assert!(shown.contains(fragment), "{shown}");
            assert_eq!(err.line, line, "{shown}");
            if let Some(line) = line {
                assert!(shown.contains(&format!("{file}:{line}: ")), "{shown}");
            }
            seen.push(file);
        }
        assert_eq!(
            seen.len(),
            BAD.len(),
            "files listed in BAD but missing: {seen:?}"
        );
    }

    #[test]
    fn cube_loads_with_outward_faces() {
        let m = load_obj(&data_dir().join("cube.obj")).unwrap();
        assert_well_formed(&m);
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.triangles.len(), 12);
        assert_eq!(edge_stats(&m.triangles).paired, 18);
        assert!((signed_volume(&m) - 8.0).abs() < 1e-12);
        for t in &m.triangles {
            let centre = m.positions[t[0] as usize];
            assert!(dot(face_normal(&m.positions, t), centre) > 0.0);
        }
        // Area-weighted corner normals lean towards the faces whose fan puts two
        // triangles at that corner, but stay close to the diagonal (`vn` ignored).
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!(dot(*n, *p) / 3f64.sqrt() > 0.9, "{p:?} {n:?}");
        }
    }

    #[test]
    fn polygons_are_fans_and_negative_indices_are_relative() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nf -5 -4 -3 2/7/1 4//3 5\n";
        let m = parse_obj(text, "fan.obj").unwrap();
        assert_eq!(
            m.triangles,
            vec![[0, 1, 2], [0, 2, 1], [0, 1, 3], [0, 3, 4]]
        );
        let m = parse_obj(
            "v 0 0 0 1 0.5 0.5 0.5\nv 1 0 0\r\nv 0 1 0 # c\nf 1 2 3\n",
            "x.obj",
        );
        assert_eq!(m.unwrap().positions[0], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn too_many_vertices() {
        let mut text = "v 0 0 0\n".repeat(MAX_OBJ_VERTICES);
        text.push_str("f 1 2 3\n");
        assert_eq!(
            parse_obj(&text, "big.obj").unwrap().positions.len(),
            MAX_OBJ_VERTICES
        );
        text.push_str("v 1 1 1\n");
        let err = parse_obj(&text, "big.obj").unwrap_err();
        assert_eq!(err.line, Some(MAX_OBJ_VERTICES + 2));
        assert!(
            err.to_string()
                .starts_with("big.obj:65537: too many vertices"),
            "{err}"
        );
    }

    #[test]
    fn unreadable_file() {
        let err = load_obj(&data_dir().join("no_such_file.obj")).unwrap_err();
        assert!(
            err.to_string()
                .contains("no_such_file.obj: cannot read the file"),
            "{err}"
        );
        assert_eq!(err.line, None);
    }
}
