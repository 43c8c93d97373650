//! Wavefront OBJ loading, with MTL materials, through the `tobj` crate.
//!
//! # What is read
//!
//! - `v x y z [w]`: a position (a `w` divides x, y and z; the colours of
//!   `v x y z r g b` are dropped: not drawn). `vn x y z`: a normal. `vt`: read, not
//!   drawn. A `#` word and the rest of its line are a comment.
//! - `f`: a face of vertex references `i`, `i/t`, `i//n` or `i/t/n` (1-based; a
//!   negative index counts back from the last one defined so far). Faces of more
//!   than 3 vertices are cut into a fan around their first vertex (tobj's
//!   `triangulate`). An `f` of 1 or 2 vertices, `l` and `p` are points and lines,
//!   which are not drawn.
//! - `o` and `g` start a group, `usemtl` a run of faces with one material, `mtllib`
//!   names an MTL file (relative to the OBJ's directory). Consecutive groups with
//!   the same material become one [`MeshPart`], which the scene draws as an object
//!   of its own (same placement); a file without materials is one part.
//! - In an MTL file, `Kd`, `Ka`, `Ks`, `Ke` and `Ns` become the diffuse, ambient,
//!   specular and emission colours and the Blinn exponent of an OpenGL
//!   fixed-function material ([`MtlMaterial`]); colours must lie in 0..=1, `Ns` is
//!   clamped to the core's 1..=1000 (exporters write `Ns 0`). Keys the material does
//!   not set keep the scene's value. `d`, `illum` and texture maps are not used.
//!   A library that cannot be read, and a `usemtl` name no library read before it
//!   defines, leave their groups with the scene's material (as tobj and most
//!   viewers do: an OBJ often travels without its MTL file); a library that is
//!   read must be well-formed.
//!   Whether the MTL material or the scene's wins is
//!   [`ObjectDesc::part_material`](crate::scene::desc::ObjectDesc::part_material)'s
//!   rule: an `[object.material]` table in the scene file overrides the MTL
//!   materials; the scene-wide `[material]` only fills in what they leave out.
//!
//! # Normals and vertices
//!
//! When the faces reference `vn` normals, they are used (normalised), and a vertex
//! is one (position, normal) pair: a position used with two normals is two
//! vertices, so a cube with face normals keeps its hard edges. When no face
//! references a normal, normals are recomputed: area-weighted face normals summed
//! at each position of a group (the `v` index), and across groups at each equal
//! position, so a model split by materials stays smooth across the split. A file
//! whose faces mix both (some corners with a normal, some without) is drawn as if
//! it had no normals: they are recomputed for every face (tobj gives a corner
//! without a normal the previous corner's, so the mix cannot be kept).
//!
//! # tobj's options, and what is checked here
//!
//! Loaded with `triangulate`, `ignore_points`, `ignore_lines` and without
//! `single_index`: with it tobj splits vertices by (position, texture coordinate,
//! normal), which splits them needlessly at every texture seam (texture
//! coordinates are not drawn), and it pushes a normal only for corners that have
//! one, so arrays fall out of step when corners mix. Without it every group keeps
//! one vertex per `v` index with a normal index per corner, and the vertices are
//! split by (position, normal) here.
//!
//! tobj's errors name no line, so the line is found here: face references are
//! checked before tobj sees them (an index of 0, or past the vertices, texture
//! coordinates or normals defined so far; tobj 4.0.5 would also overflow on some of
//! those), and for tobj's other errors (a malformed `v`, `vn`, `vt`, ...) the line
//! is the last of the shortest prefix of the file that tobj rejects. MTL colours
//! with fewer than 3 numbers are rejected before tobj reads them (tobj 4.0.5 panics
//! on them). Positions are checked against the core's coordinate range. Before
//! tobj reads the file, comments after a statement and vertex colours are removed
//! (line for line): tobj takes a `#` only at the start of a line and rejects
//! files where only some vertices have colours.
//!
//! ```
//! use fixshade_sim::scene::mesh::{parse_obj, MtlFile};
//! let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nusemtl red\nf 1//1 2//1 3//1\n";
//! let mtl = |_: &std::path::Path| Ok(MtlFile { name: "m.mtl".into(), text: "newmtl red\nKd 1 0 0\n".into() });
//! let parts = parse_obj(obj, "tri.obj", &mtl).unwrap();
//! assert_eq!(parts[0].mesh.normals, vec![[0.0, 0.0, 1.0]; 3]);
//! assert_eq!(parts[0].material.unwrap().diffuse, Some([1.0, 0.0, 0.0]));
//!
//! let err = parse_obj("v 0 0 1e30\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "far.obj", &mtl).unwrap_err();
//! assert!(err.to_string().starts_with("far.obj:1: vertex coordinate `1e30` is out of range"));
//! ```

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::Path;

use super::error::MeshError;
use super::vector::{add, face_normal, normalize, sub};
use crate::scene::convert::q16;
use crate::scene::desc::{MeshData, MeshPart, MtlMaterial};
use fixshade::geometry::MAX_COORD;

/// Most vertices one part of an OBJ file may have: the core indexes vertices with
/// `u16`.
pub const MAX_OBJ_VERTICES: usize = u16::MAX as usize;

/// A material library as [`parse_obj`] gets it: the name its errors use, and its
/// text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MtlFile {
    /// How errors name the file.
    pub name: String,
    /// Its text.
    pub text: String,
}

/// What became of one `mtllib`.
enum Library {
    /// Read, colours checked.
    Read(MtlFile),
    /// Could not be read.
    Unreadable,
    /// A colour statement tobj cannot take.
    Bad(MeshError),
}

/// Reads a material library named by `mtllib`, or says why it cannot (a library
/// that cannot be read is not an error: see the module documentation).
pub type MtlReader<'a> = &'a dyn Fn(&Path) -> Result<MtlFile, String>;

/// Reads and parses an OBJ file and the MTL files it names (relative to its
/// directory); see [`parse_obj`]. Errors name the file as `path` displays; a file
/// that cannot be read gives an error without a line. Bytes that are not UTF-8 are
/// replaced (they can only matter in comments and names).
pub fn load_obj(path: &Path) -> Result<Vec<MeshPart>, MeshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MeshError::new(&name, None, format!("cannot read the file: {e}")))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let read_mtl = |lib: &Path| {
        let p = dir.join(lib);
        let bytes = std::fs::read(&p).map_err(|e| e.to_string())?;
        Ok(MtlFile {
            name: p.display().to_string(),
            text: String::from_utf8_lossy(&bytes).into_owned(),
        })
    };
    parse_obj(&String::from_utf8_lossy(&bytes), &name, &read_mtl)
}

/// Parses the text of an OBJ file into its parts (see the [module
/// documentation](self)); `name` is the file name used in errors and `read_mtl`
/// reads the libraries `mtllib` names.
///
/// Errors name the file (the OBJ's, or an MTL file's) and the line where one
/// applies: a malformed statement, a face reference out of range, a zero `vn`, a
/// coordinate outside the core's range (strictly between `-MAX_COORD` and
/// `MAX_COORD`, i.e. ±16384, after rounding to Q16.16), a malformed MTL file or an
/// MTL colour outside 0..=1, a part of more than
/// [`MAX_OBJ_VERTICES`] vertices, and a file without faces ("no triangles").
pub fn parse_obj(
    text: &str,
    name: &str,
    read_mtl: MtlReader<'_>,
) -> Result<Vec<MeshPart>, MeshError> {
    let at = |line: Option<usize>, message: String| MeshError::new(name, line, message);
    let text = &prepare(text);
    let corners = check_faces(text).map_err(|(line, m)| at(Some(line), m))?;

    // tobj calls the loader once per `mtllib`, in order; keep what it read.
    let libs: RefCell<Vec<Library>> = RefCell::new(Vec::new());
    let loader = |lib: &Path| {
        let (library, result) = match read_mtl(lib) {
            Err(_) => (Library::Unreadable, Err(tobj::LoadError::OpenFileFailed)),
            Ok(f) => match check_mtl_colours(&f) {
                Err(e) => (Library::Bad(e), Err(tobj::LoadError::MaterialParseError)),
                Ok(()) => {
                    let result = tobj::load_mtl_buf(&mut f.text.as_bytes());
                    (Library::Read(f), result)
                }
            },
        };
        libs.borrow_mut().push(library);
        result
    };
    let (models, _) =
        tobj::load_obj_buf(&mut text.as_bytes(), &options(), loader).map_err(|e| {
            match locate(text, e, obj_prefix_fails) {
                Some((line, message)) => at(Some(line), message),
                None => at(None, e.to_string()),
            }
        })?;
    let materials = materials(&libs.into_inner())?;

    let models: Vec<tobj::Model> = models
        .into_iter()
        .filter(|m| !m.mesh.indices.is_empty())
        .collect();
    if models.is_empty() {
        return Err(at(None, "no triangles".to_owned()));
    }
    let authored = corners.with_normal > 0 && corners.without_normal == 0;
    let normals = if authored {
        authored_normals(text, &models).map_err(|(l, m)| at(l, m))?
    } else {
        recomputed_normals(&models)
    };
    let mut parts = Vec::new();
    let mut start = 0;
    while start < models.len() {
        let id = models[start].mesh.material_id;
        let end = start
            + models[start..]
                .iter()
                .take_while(|m| m.mesh.material_id == id)
                .count();
        let part = part(&models[start..end], &normals[start..end], authored);
        if part.positions.len() > MAX_OBJ_VERTICES {
            return Err(at(
                None,
                format!(
                    "group `{}` has {} vertices; at most {MAX_OBJ_VERTICES} are supported \
                     (the renderer uses 16-bit indices)",
                    models[start].name,
                    part.positions.len()
                ),
            ));
        }
        check_positions(text, &part.positions).map_err(|(l, m)| at(l, m))?;
        parts.push(MeshPart {
            name: models[start].name.clone(),
            mesh: part,
            material: id.map(|i| materials[i]),
        });
        start = end;
    }
    Ok(parts)
}

/// The text tobj reads, line for line: comments (from a word that starts with
/// `#`) removed, and the colours of `v x y z r g b` (not drawn) dropped. tobj takes
/// a `#` only at the start of a line, and rejects a file where some vertices have
/// colours and others not.
fn prepare(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let words: Vec<&str> = line
            .split_whitespace()
            .take_while(|w| !w.starts_with('#'))
            .collect();
        let words = match words[..] {
            ["v", x, y, z, _, _, _] => vec!["v", x, y, z],
            _ => words,
        };
        out.push_str(&words.join(" "));
    }
    out
}

/// A result whose error is a message and the line it belongs to, if any.
type Located<T> = Result<T, (Option<usize>, String)>;

/// tobj's load options (see the module documentation for why).
fn options() -> tobj::LoadOptions {
    tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    }
}

/// The statements of `text`: 1-based line number, keyword, the rest of the line's
/// words. Lines split as tobj splits them (at `\n`, words at whitespace).
fn statements(text: &str) -> impl Iterator<Item = (usize, &str, std::str::SplitWhitespace<'_>)> {
    text.split('\n').enumerate().filter_map(|(i, line)| {
        let mut words = line.split_whitespace();
        words.next().map(|k| (i + 1, k, words))
    })
}

/// How many face corners (of faces of 3 or more vertices) reference a normal, and
/// how many do not.
struct Corners {
    with_normal: usize,
    without_normal: usize,
}

/// Checks every face reference against what is defined before it, and counts the
/// corners with and without a normal.
fn check_faces(text: &str) -> Result<Corners, (usize, String)> {
    // Statements defined so far: v, vt, vn.
    let mut defined = [0usize; 3];
    let mut corners = Corners {
        with_normal: 0,
        without_normal: 0,
    };
    for (line, keyword, words) in statements(text) {
        match keyword {
            "v" => defined[0] += 1,
            "vt" => defined[1] += 1,
            "vn" => defined[2] += 1,
            "f" => {
                let refs: Vec<&str> = words.collect();
                for r in &refs {
                    let parts: Vec<&str> = r.split('/').collect();
                    if parts.len() > 3 || parts[0].is_empty() {
                        return Err((
                            line,
                            format!("expected a vertex reference (i, i/t, i//n or i/t/n) after `f`, found `{r}`"),
                        ));
                    }
                    for (k, p) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
                        check_index(p, r, k, defined[k]).map_err(|m| (line, m))?;
                    }
                }
                if refs.len() >= 3 {
                    for r in &refs {
                        if r.split('/').nth(2).is_some_and(|n| !n.is_empty()) {
                            corners.with_normal += 1;
                        } else {
                            corners.without_normal += 1;
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(corners)
}

/// Checks one index of a face reference: `kind` 0, 1, 2 for a vertex, texture
/// coordinate or normal, of which `defined` are defined so far.
fn check_index(text: &str, reference: &str, kind: usize, defined: usize) -> Result<(), String> {
    let what = ["vertex", "texture coordinate", "normal"][kind];
    let statement = ["v", "vt", "vn"][kind];
    let index: i64 = text.parse().map_err(|_| {
        format!("expected an integer {what} index in `{reference}`, found `{text}`")
    })?;
    if index == 0 {
        return Err(format!(
            "{what} index 0 in `{reference}` is invalid (OBJ indices start at 1)"
        ));
    }
    // 1..=defined counts from the first, -1..=-defined back from the last.
    if index.unsigned_abs() <= defined as u64 {
        Ok(())
    } else {
        Err(format!(
            "{what} index {index} in `{reference}` is out of range: {defined} `{statement}` defined \
             before this line (1 is the first, -1 the last)"
        ))
    }
}

/// The line tobj's error `e` belongs to and a message naming it: the last line of
/// the shortest prefix of `text` that `fails`. `None` if no prefix fails.
fn locate(text: &str, e: tobj::LoadError, fails: fn(&str) -> bool) -> Option<(usize, String)> {
    let ends: Vec<usize> = text
        .match_indices('\n')
        .map(|(i, _)| i + 1)
        .chain(std::iter::once(text.len()))
        .collect();
    // Smallest k with prefix of k lines failing; lines are ends[k - 1].
    let (mut lo, mut hi) = (0, ends.len());
    if !fails(&text[..ends[hi - 1]]) {
        return None;
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if fails(&text[..ends[mid - 1]]) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let start = if hi == 1 { 0 } else { ends[hi - 2] };
    let line = text[start..ends[hi - 1]].trim();
    Some((hi, format!("{} in `{line}`", tobj_message(e))))
}

fn obj_prefix_fails(prefix: &str) -> bool {
    let no_mtl = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    tobj::load_obj_buf(&mut prefix.as_bytes(), &options(), no_mtl).is_err()
}

fn mtl_prefix_fails(prefix: &str) -> bool {
    tobj::load_mtl_buf(&mut prefix.as_bytes()).is_err()
}

/// tobj's error in words that say what was expected.
fn tobj_message(e: tobj::LoadError) -> String {
    use tobj::LoadError as E;
    match e {
        E::PositionParseError => "expected 3 numbers (x y z) after `v`".to_owned(),
        E::ScalingByZeroError => "the w of a `v` is 0".to_owned(),
        E::ColorParseError => "after x y z, `v` takes 1 number (w) or 3 (r g b)".to_owned(),
        E::NormalParseError => "expected 3 numbers after `vn`".to_owned(),
        E::TexcoordParseError => "expected 2 numbers after `vt`".to_owned(),
        E::MaterialParseError => {
            "malformed material statement (a name or numbers expected)".to_owned()
        }
        E::InvalidObjectName => "`newmtl` needs a name".to_owned(),
        E::FaceColorOutOfBounds => "a face uses a vertex without a colour while other `v` have \
                                    colours (`v x y z r g b`): give all or none"
            .to_owned(),
        other => other.to_string(),
    }
}

/// Rejects MTL colour statements with fewer than 3 numbers, which tobj 4.0.5
/// panics on; the error names the library and the line.
fn check_mtl_colours(f: &MtlFile) -> Result<(), MeshError> {
    for (line, keyword, words) in statements(&f.text) {
        let n = words.count();
        if matches!(keyword, "Ka" | "Kd" | "Ks" | "Ke") && n < 3 {
            return Err(MeshError::new(
                &f.name,
                Some(line),
                format!("expected 3 numbers (r g b) after `{keyword}`, found {n}"),
            ));
        }
    }
    Ok(())
}

/// The materials of the libraries tobj read, checked, in tobj's order (libraries
/// in `mtllib` order, each in file order; `material_id` indexes this). A library
/// that could not be read adds none (its groups keep the scene's material).
fn materials(libs: &[Library]) -> Result<Vec<MtlMaterial>, MeshError> {
    let mut out = Vec::new();
    for lib in libs {
        let f = match lib {
            Library::Read(f) => f,
            Library::Bad(e) => return Err(e.clone()),
            Library::Unreadable => continue,
        };
        let (mats, _) = tobj::load_mtl_buf(&mut f.text.as_bytes()).map_err(|e| {
            match locate(&f.text, e, mtl_prefix_fails) {
                Some((l, m)) => MeshError::new(&f.name, Some(l), m),
                None => MeshError::new(&f.name, None, e.to_string()),
            }
        })?;
        for m in &mats {
            out.push(mtl_material(f, m)?);
        }
    }
    Ok(out)
}

/// An MTL material as fixshade reads it, with its colours checked.
fn mtl_material(f: &MtlFile, m: &tobj::Material) -> Result<MtlMaterial, MeshError> {
    let colour = |key: &str, c: Option<[f64; 3]>| -> Result<Option<[f64; 3]>, MeshError> {
        match c {
            Some(c) if !c.iter().all(|x| (0.0..=1.0).contains(x)) => Err(MeshError::new(
                &f.name,
                mtl_key_line(&f.text, &m.name, key),
                format!(
                    "`{key}` of material `{}` must have components between 0 and 1, found {} {} {}",
                    m.name, c[0], c[1], c[2]
                ),
            )),
            c => Ok(c),
        }
    };
    let shininess = match m.shininess {
        Some(n) if n.is_nan() => {
            return Err(MeshError::new(
                &f.name,
                mtl_key_line(&f.text, &m.name, "Ns"),
                format!("`Ns` of material `{}` is not a number", m.name),
            ))
        }
        n => n.map(|n| n.clamp(1.0, 1000.0)),
    };
    Ok(MtlMaterial {
        emission: colour("Ke", m.emissive)?,
        ambient: colour("Ka", m.ambient)?,
        diffuse: colour("Kd", m.diffuse)?,
        specular: colour("Ks", m.specular)?,
        shininess,
    })
}

/// The line of `key` in material `material` of an MTL text (the last one, which
/// is the one tobj keeps).
fn mtl_key_line(text: &str, material: &str, key: &str) -> Option<usize> {
    let mut current = false;
    let mut found = None;
    for (line, keyword, words) in statements(text) {
        if keyword == "newmtl" {
            current = words.collect::<Vec<_>>().join(" ") == material;
        } else if current && keyword == key {
            found = Some(line);
        }
    }
    found
}

/// The unit `vn` normals of each model, in the model's normal order. A normal
/// without a direction is an error at its line.
fn authored_normals(text: &str, models: &[tobj::Model]) -> Located<Vec<Vec<[f64; 3]>>> {
    models
        .iter()
        .map(|m| {
            m.mesh
                .normals
                .chunks_exact(3)
                .map(|n| {
                    let n = [n[0], n[1], n[2]];
                    normalize(n).ok_or_else(|| {
                        let line = statements(text).find_map(|(l, k, w)| {
                            let v: Vec<f64> = w.take(3).filter_map(|x| x.parse().ok()).collect();
                            (k == "vn"
                                && v.len() == 3
                                && v.iter().zip(n).all(|(a, b)| a.to_bits() == b.to_bits()))
                            .then_some(l)
                        });
                        (
                            line,
                            format!(
                                "normal `vn {} {} {}` has no direction (zero or not finite)",
                                n[0], n[1], n[2]
                            ),
                        )
                    })
                })
                .collect()
        })
        .collect()
}

/// Area-weighted normals of each model's positions (one per tobj position): the
/// face normals summed at each position of the model, plus those at equal
/// positions of the other models.
fn recomputed_normals(models: &[tobj::Model]) -> Vec<Vec<[f64; 3]>> {
    let key = |p: [f64; 3]| p.map(f64::to_bits);
    let mut sums = Vec::new();
    let mut total: HashMap<[u64; 3], [f64; 3]> = HashMap::new();
    let mut own = Vec::new();
    for m in models {
        let positions = positions(m);
        let mut s = vec![[0.0; 3]; positions.len()];
        for t in m.mesh.indices.chunks_exact(3) {
            let n = face_normal(&positions, &[t[0], t[1], t[2]]);
            for &i in t {
                s[i as usize] = add(s[i as usize], n);
            }
        }
        let mut mine: HashMap<[u64; 3], [f64; 3]> = HashMap::new();
        for (p, n) in positions.iter().zip(&s) {
            let e = total.entry(key(*p)).or_default();
            *e = add(*e, *n);
            let e = mine.entry(key(*p)).or_default();
            *e = add(*e, *n);
        }
        sums.push((positions, s));
        own.push(mine);
    }
    sums.iter()
        .zip(&own)
        .map(|((positions, s), mine)| {
            positions
                .iter()
                .zip(s)
                .map(|(p, n)| {
                    // Only a group's own sums: exactly the old per-index normal.
                    let others = sub(total[&key(*p)], mine[&key(*p)]);
                    let sum = if others == [0.0; 3] {
                        *n
                    } else {
                        add(*n, others)
                    };
                    normalize(sum).unwrap_or([0.0, 1.0, 0.0])
                })
                .collect()
        })
        .collect()
}

fn positions(m: &tobj::Model) -> Vec<[f64; 3]> {
    m.mesh
        .positions
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// One part from consecutive models of one material: a vertex per (model,
/// position, normal) used, in order of first use. `normals[k]` holds model `k`'s
/// normals: per `vn` index when `authored`, else per position.
fn part(models: &[tobj::Model], normals: &[Vec<[f64; 3]>], authored: bool) -> MeshData {
    let mut out = MeshData::default();
    let mut index: HashMap<(usize, u32, u32), u32> = HashMap::new();
    for (k, (m, ns)) in models.iter().zip(normals).enumerate() {
        let positions = positions(m);
        let corners = m.mesh.indices.iter().enumerate().map(|(c, &p)| {
            let n = if authored {
                m.mesh.normal_indices[c]
            } else {
                p
            };
            (p, n)
        });
        let mut tri = Vec::with_capacity(3);
        for (p, n) in corners {
            let next = out.positions.len() as u32;
            let v = *index.entry((k, p, n)).or_insert_with(|| {
                out.positions.push(positions[p as usize]);
                out.normals.push(ns[n as usize]);
                next
            });
            tri.push(v);
            if tri.len() == 3 {
                out.triangles.push([tri[0], tri[1], tri[2]]);
                tri.clear();
            }
        }
    }
    out
}

/// Checks that every position is within the core's range; the error names the
/// first `v` line (in the file) of a position out of range, and its coordinate as
/// written.
fn check_positions(text: &str, positions: &[[f64; 3]]) -> Located<()> {
    let limit = i64::from(MAX_COORD) << 16;
    let in_range = |c: f64| c.is_finite() && i64::from(q16(c).to_bits()).abs() < limit;
    let key = |p: [f64; 3]| p.map(f64::to_bits);
    let bad: std::collections::HashSet<[u64; 3]> = positions
        .iter()
        .filter(|p| !p.iter().all(|c| in_range(*c)))
        .map(|p| key(*p))
        .collect();
    let Some(first) = positions.iter().find(|p| bad.contains(&key(**p))) else {
        return Ok(());
    };
    let range = format!(
        "model coordinates must lie strictly between -{MAX_COORD} and {MAX_COORD} \
         (the core's MAX_COORD, after rounding to Q16.16); scale the model in the scene file instead"
    );
    // The `v` statement that gave such a position (tobj divides by a `w`).
    let found = statements(text).find_map(|(line, keyword, words)| {
        if keyword != "v" {
            return None;
        }
        let words: Vec<&str> = words.collect();
        let v: Vec<f64> = words
            .iter()
            .map(|w| w.parse().unwrap_or(f64::NAN))
            .collect();
        let w = if v.len() == 4 { v[3] } else { 1.0 };
        let p = [v.first()?, v.get(1)?, v.get(2)?].map(|c| if w == 1.0 { *c } else { c / w });
        bad.contains(&key(p)).then(|| {
            let k = (0..3).find(|&k| !in_range(p[k])).unwrap_or(0);
            (line, words[k].to_owned())
        })
    });
    Err(match found {
        Some((line, word)) => (
            Some(line),
            format!("vertex coordinate `{word}` is out of range: {range}"),
        ),
        None => (None, format!("vertex {first:?} is out of range: {range}")),
    })
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

    fn no_mtl(_: &Path) -> Result<MtlFile, String> {
        Err("no material libraries in this test".to_owned())
    }

    /// The one part of a file without materials.
    fn one(text: &str) -> MeshData {
        let mut parts = parse_obj(text, "t.obj", &no_mtl).unwrap();
        assert_eq!(parts.len(), 1);
        parts.remove(0).mesh
    }

    /// Every file in `tests/data/obj/bad`, with the file its error must name (if
    /// not the OBJ), the line (if any) and a piece of the message.
    const BAD: &[(&str, Option<usize>, &str)] = &[
        ("missing_coordinate.obj", Some(4), "expected 3 numbers (x y z) after `v` in `v 0 1`"),
        ("not_a_number.obj", Some(3), "expected 3 numbers (x y z) after `v` in `v 1,5 0 0`"),
        ("index_out_of_range.obj", Some(6), "vertex index 4 in `4` is out of range: 3 `v` defined"),
        ("negative_index_out_of_range.obj", Some(5), "vertex index -4 in `-4` is out of range"),
        ("index_zero.obj", Some(5), "vertex index 0 in `0` is invalid"),
        ("forward_reference.obj", Some(3), "vertex index 2 in `2` is out of range: 1 `v` defined"),
        ("face_bad_reference.obj", Some(5), "expected an integer vertex index in `x/1`, found `x`"),
        ("nan.obj", Some(3), "vertex coordinate `nan` is out of range: model coordinates must lie strictly between -16384 and 16384"),
        ("infinity.obj", Some(4), "vertex coordinate `-inf` is out of range"),
        ("huge.obj", Some(3), "vertex coordinate `1e30` is out of range: model coordinates must lie strictly between -16384 and 16384"),
        ("normal_out_of_range.obj", Some(6), "normal index 2 in `3//2` is out of range: 1 `vn` defined"),
        ("zero_normal.obj", Some(4), "normal `vn 0 0 0` has no direction"),
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
            if !file.ends_with(".obj") {
                continue;
            }
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
    fn bad_mtl_files_are_named_with_their_lines() {
        let cases = [
            (
                "Kd 0.5\n",
                2,
                "expected 3 numbers (r g b) after `Kd`, found 1",
            ),
            (
                "Kd 1.5 0 0\n",
                2,
                "`Kd` of material `m` must have components between 0 and 1, found 1.5 0 0",
            ),
            ("Ks x y z\n", 2, "malformed material statement"),
        ];
        let obj = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
        for (body, line, fragment) in cases {
            let text = format!("newmtl m\n{body}");
            let read = |_: &Path| {
                Ok(MtlFile {
                    name: "lib.mtl".into(),
                    text: text.clone(),
                })
            };
            let err = parse_obj(obj, "t.obj", &read).unwrap_err();
            assert_eq!(
                (err.file.as_str(), err.line),
                ("lib.mtl", Some(line)),
                "{err}"
            );
            assert!(err.to_string().contains(fragment), "{err}");
        }
    }

    #[test]
    fn cube_loads_with_outward_faces() {
        let parts = load_obj(&data_dir().join("cube.obj")).unwrap();
        let m = &parts[0].mesh;
        assert_well_formed(m);
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.triangles.len(), 12);
        assert_eq!(edge_stats(&m.triangles).paired, 18);
        assert!((signed_volume(m) - 8.0).abs() < 1e-12);
        for t in &m.triangles {
            let centre = m.positions[t[0] as usize];
            assert!(dot(face_normal(&m.positions, t), centre) > 0.0);
        }
        // Area-weighted corner normals lean towards the faces whose fan puts two
        // triangles at that corner, but stay close to the diagonal (no `vn`).
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!(dot(*n, *p) / 3f64.sqrt() > 0.9, "{p:?} {n:?}");
        }
    }

    #[test]
    fn face_normals_split_vertices_and_keep_edges_hard() {
        let parts = load_obj(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/catalogue/meshes/cube-vn.obj"),
        )
        .unwrap();
        let m = &parts[0].mesh;
        assert_well_formed(m);
        // 8 positions, each on 3 faces: 24 (position, normal) vertices.
        assert_eq!((m.positions.len(), m.triangles.len()), (24, 12));
        for t in &m.triangles {
            let n = m.normals[t[0] as usize];
            assert!(t.iter().all(|&i| m.normals[i as usize] == n));
            let f = normalize(face_normal(&m.positions, t)).unwrap();
            assert!(dot(f, n) > 1.0 - 1e-12, "{f:?} {n:?}");
        }
    }

    #[test]
    fn groups_of_one_material_are_one_part_and_normals_are_smooth_across_parts() {
        // A square of two triangles in two groups: one part without materials.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\ng a\nf 1 2 3\ng b\nf 1 3 4\n";
        let m = one(text);
        assert_eq!((m.positions.len(), m.triangles.len()), (6, 2));
        // With two materials, two parts; the shared edge's normals agree.
        let mtl = "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n";
        let read = |_: &Path| {
            Ok(MtlFile {
                name: "m.mtl".into(),
                text: mtl.into(),
            })
        };
        let text = format!(
            "mtllib m.mtl\n{}",
            text.replace("g a", "usemtl a").replace("g b", "usemtl b")
        );
        let parts = parse_obj(&text, "t.obj", &read).unwrap();
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].material.unwrap().diffuse, Some([1.0, 0.0, 0.0]));
        assert_eq!(parts[1].material.unwrap().diffuse, Some([0.0, 1.0, 0.0]));
        let normal_at = |part: &MeshPart, p: [f64; 3]| {
            let i = part.mesh.positions.iter().position(|q| *q == p).unwrap();
            part.mesh.normals[i]
        };
        for p in [[0.0, 0.0, 0.0], [1.0, 1.0, 0.5]] {
            assert_eq!(normal_at(&parts[0], p), normal_at(&parts[1], p));
            assert_eq!(normal_at(&parts[0], p), normal_at(&parts[0], p));
        }
        // ... and equal the single part's.
        let whole = one("v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
        assert_eq!(normal_at(&parts[0], [0.0; 3]), whole.normals[0]);
    }

    #[test]
    fn polygons_are_fans_and_negative_indices_are_relative() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nvt 0 0\nf -5 -4 -3 2/1 4 5\n";
        let m = one(text);
        let tri = |t: &[u32; 3]| t.map(|i| m.positions[i as usize]);
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 1.5, 0.0],
        ];
        let want: Vec<[[f64; 3]; 3]> = [[0, 1, 2], [0, 2, 1], [0, 1, 3], [0, 3, 4]]
            .iter()
            .map(|t| t.map(|i| p[i]))
            .collect();
        assert_eq!(m.triangles.iter().map(tri).collect::<Vec<_>>(), want);
        // A `w` divides; vertex colours are read and not drawn; `\r\n` ends lines.
        let m = one("v 0 0 0\nv 2 0 0 2\r\nv 0 1 0\n# c\nf 1 2 3\n");
        assert_eq!(m.positions[..2], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        let m = one("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
        assert_eq!(m.positions.len(), 3);
        // An `f` of 2 vertices is a line, `l` too: not drawn.
        let m = one("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\nl 1 3\n");
        assert_eq!(m.triangles.len(), 1);
    }

    #[test]
    fn too_many_vertices() {
        let mut text = String::new();
        for i in 0..MAX_OBJ_VERTICES + 1 {
            text.push_str(&format!("v {} 0 {}\n", i % 256, i / 256));
        }
        for i in 2..=MAX_OBJ_VERTICES {
            text.push_str(&format!("f 1 {i} {}\n", i + 1));
        }
        let err = parse_obj(&text, "big.obj", &no_mtl).unwrap_err();
        assert_eq!(err.line, None);
        assert!(
            err.to_string()
                .starts_with("big.obj: group `unnamed_object` has 65536 vertices"),
            "{err}"
        );
    }

    #[test]
    fn missing_libraries_and_unknown_materials_keep_the_scene_material() {
        let obj = "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl blue\nf 1 2 3\n";
        let parts = parse_obj(obj, "t.obj", &no_mtl).unwrap();
        assert_eq!(parts[0].material, None);
        // Faces that mix corners with and without normals: all recomputed.
        let mixed = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 1 0 0\nf 1//1 2//1 3//1\nf 2 4 3\n";
        let m = one(mixed);
        assert!(
            m.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]),
            "{:?}",
            m.normals
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
