//! `fixshade bake`: meshes (and whole scenes) as Rust source of `static` arrays in the
//! core's fixed-point formats, for firmware that keeps its models in flash.
//!
//! The input is a built-in scene (`sphere`, `teapot`, `robot`, `bench-sphere`), a
//! scene file (`.toml`) or a Wavefront OBJ file. A scene is baked with its camera,
//! lights, materials and placements as a `scene()` function, so the firmware renders
//! exactly the scene the host renders: both start from the same quantised numbers
//! ([`crate::scene::convert`]). An OBJ is baked as one mesh per material group, with
//! the vertices split by (position, normal) as the loader splits them
//! ([`crate::scene::mesh::obj`]), quantised the same way.
//!
//! Every bake has a `MATERIALS` array, one material per object: a scene's objects'
//! materials (the MTL material of an OBJ group where the scene lets it apply), or
//! for a bare OBJ each group's MTL material over OpenGL's default material.
//!
//! `--chunk N` splits each mesh into runs of consecutive triangles that use at most
//! `N` distinct vertices, each run with its own vertex arrays (shared vertices are
//! repeated). A board whose RAM cannot hold a vertex cache for the whole mesh runs
//! the vertex stage and the draw once per run: triangles are drawn in the mesh's
//! order and every vertex is transformed and lit by the same arithmetic, so the
//! frame has the same bytes as the whole-mesh render.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::scene::convert::{background_channels, core_scene, material, quantize_mesh, FixedMesh};
use crate::scene::desc::{MaterialDesc, MeshSource, Named, SceneDesc};
use crate::scene::load;
use crate::scene::{builtin, mesh};
use fixshade::fixed::{Q16_16, Q2_14};
use fixshade::light::{Light, LightKind, Material};
use fixshade::scene::{Projection, Scene};

/// Bytes of flash per vertex (Q16.16 position and Q2.14 normal) and per triangle.
const VERTEX_BYTES: usize = 12 + 6;
const TRIANGLE_BYTES: usize = 6;

/// A run of consecutive triangles with its own vertex arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chunk {
    /// Q16.16 positions.
    pub positions: Vec<[Q16_16; 3]>,
    /// Q2.14 normals.
    pub normals: Vec<[Q2_14; 3]>,
    /// Triangles, indices into this chunk's arrays.
    pub triangles: Vec<[u16; 3]>,
}

/// The baked `Chunk` type and its `const fn chunk` (every baked file that holds
/// chunks declares them so; needs `Q16_16`, `Q2_14` and `Mesh` in scope).
pub const CHUNK_SRC: &str =
    "/// A run of consecutive triangles with its own vertex arrays (Q16.16 positions,\n\
     /// Q2.14 normals, triangles), as the core's mesh with the whole mesh's bound.\n\
     pub type Chunk = Mesh<'static>;\n\n\
     /// The chunk of these arrays, transformed as the whole mesh is (`bound`, raw\n\
     /// Q16.16), checked when the firmware is compiled: a chunk that is not a valid\n\
     /// mesh does not compile, and a valid one costs no check at run time.\n\
     const fn chunk(\n    \
     positions: &'static [[Q16_16; 3]],\n    \
     normals: &'static [[Q2_14; 3]],\n    \
     triangles: &'static [[u16; 3]],\n    \
     bound: i32,\n\
     ) -> Chunk {\n    \
     match Mesh::new(positions, normals, triangles) {\n        \
     Ok(m) => m.with_bound(bound),\n        \
     Err(_) => panic!(\"a baked chunk is not a valid mesh\"),\n    \
     }\n\
     }\n\n";

/// The largest |coordinate| of a mesh's positions, raw Q16.16 (`Mesh::bound`).
pub fn mesh_bound(m: &FixedMesh) -> i32 {
    m.positions
        .iter()
        .flatten()
        .map(|c| c.to_bits().saturating_abs())
        .max()
        .unwrap_or(0)
}

/// Splits `m` into runs of consecutive triangles using at most `max_vertices`
/// distinct vertices each (`None`: one run, the mesh as it is). Errors if
/// `max_vertices < 3`.
pub fn chunks(m: &FixedMesh, max_vertices: Option<usize>) -> Result<Vec<Chunk>, String> {
    let Some(limit) = max_vertices else {
        return Ok(vec![Chunk {
            positions: m.positions.clone(),
            normals: m.normals.clone(),
            triangles: m.triangles.clone(),
        }]);
    };
    if limit < 3 {
        return Err(format!(
            "--chunk must be at least 3 vertices, found {limit}"
        ));
    }
    let mut out = Vec::new();
    let mut cur = Chunk::default();
    let mut local = vec![u16::MAX; m.positions.len()];
    let mut used: Vec<usize> = Vec::new();
    for t in &m.triangles {
        let new = t
            .iter()
            .enumerate()
            .filter(|(k, i)| local[**i as usize] == u16::MAX && !t[..*k].contains(i))
            .count();
        if used.len() + new > limit {
            for i in used.drain(..) {
                local[i] = u16::MAX;
            }
            out.push(std::mem::take(&mut cur));
        }
        let tri = t.map(|i| {
            let i = i as usize;
            if local[i] == u16::MAX {
                local[i] = used.len() as u16;
                used.push(i);
                cur.positions.push(m.positions[i]);
                cur.normals.push(m.normals[i]);
            }
            local[i]
        });
        cur.triangles.push(tri);
    }
    if !cur.triangles.is_empty() || out.is_empty() {
        out.push(cur);
    }
    Ok(out)
}

/// The result of a bake.
#[derive(Clone, Debug)]
pub struct Baked {
    /// The Rust source.
    pub source: String,
    /// Flash the arrays take, in bytes.
    pub flash_bytes: usize,
    /// One line per object: vertices, triangles, chunks, largest chunk.
    pub summary: String,
}

/// A Q16.16 value as baked source (`q(bits)`).
pub fn q(v: Q16_16) -> String {
    format!("q({})", v.to_bits())
}

/// Three Q16.16 values as baked source.
pub fn v3(v: &[Q16_16; 3]) -> String {
    format!("[{}, {}, {}]", q(v[0]), q(v[1]), q(v[2]))
}

fn light_src(l: &Light) -> String {
    let kind = match l.kind {
        LightKind::Directional { direction } => {
            format!("LightKind::Directional {{ direction: {} }}", v3(&direction))
        }
        LightKind::Point {
            position,
            attenuation,
        } => format!(
            "LightKind::Point {{ position: {}, attenuation: {} }}",
            v3(&position),
            v3(&attenuation)
        ),
    };
    format!(
        "Light {{ kind: {kind}, ambient: {}, diffuse: {}, specular: {} }}",
        v3(&l.ambient),
        v3(&l.diffuse),
        v3(&l.specular)
    )
}

/// A material as baked source.
pub fn material_src(m: &Material) -> String {
    format!(
        "Material {{ emission: {}, ambient: {}, diffuse: {}, specular: {}, shininess: {} }}",
        v3(&m.emission),
        v3(&m.ambient),
        v3(&m.diffuse),
        v3(&m.specular),
        q(m.shininess)
    )
}

fn scene_src(s: &Scene<'_>) -> String {
    let c = &s.camera;
    let projection = match c.projection {
        Projection::Perspective { fovy, near, far } => format!(
            "Projection::Perspective {{ fovy: Angle::from_turns_bits({}), near: {}, far: {} }}",
            fovy.to_turns_bits(),
            q(near),
            q(far)
        ),
        Projection::Orthographic { height, near, far } => format!(
            "Projection::Orthographic {{ height: {}, near: {}, far: {} }}",
            q(height),
            q(near),
            q(far)
        ),
    };
    let mut f = String::new();
    let _ = writeln!(
        f,
        "/// The scene, each object with the mesh of its first chunk (replace it to draw\n\
         /// the others).\npub fn scene() -> Result<Scene<'static>, MeshError> {{"
    );
    let _ = writeln!(
        f,
        "    let mut s = Scene::new(Camera {{\n        eye: {},\n        target: {},\n        up: {},\n        projection: {projection},\n    }});",
        v3(&c.eye),
        v3(&c.target),
        v3(&c.up)
    );
    for l in &s.lights {
        // At most 8 lights: the scene came from a core scene.
        let _ = writeln!(f, "    let _ = s.add_light({});", light_src(l));
    }
    let _ = writeln!(f, "    s.global_ambient = {};", v3(&s.global_ambient));
    let _ = writeln!(f, "    s.local_viewer = {};", s.local_viewer);
    let _ = writeln!(f, "    s.cull_back = {};", s.cull_back);
    let _ = writeln!(f, "    s.depth_test = {};", s.depth_test);
    // The variant's name is its `Debug` text.
    let _ = writeln!(f, "    s.shading = ShadingMode::{:?};", s.shading);
    for (i, o) in s.objects.iter().enumerate() {
        let p = &o.placement;
        let _ = writeln!(
            f,
            "    let _ = s.add_object(Object {{\n        mesh: OBJECTS[{i}][0],\n        placement: Placement {{\n            translate: {},\n            rotate: [{}],\n            scale: {},\n        }},\n        material: MATERIALS[{i}],\n        back_material: BACK_MATERIALS[{i}].as_ref(),\n    }});",
            v3(&p.translate),
            p.rotate
                .iter()
                .map(|a| format!("Angle::from_turns_bits({})", a.to_turns_bits()))
                .collect::<Vec<_>>()
                .join(", "),
            q(p.scale),
        );
    }
    f.push_str("    Ok(s)\n}\n");
    f
}

fn arrays_src(f: &mut String, name: &str, c: &Chunk) {
    let _ = writeln!(
        f,
        "static {name}_P: [[Q16_16; 3]; {}] = [",
        c.positions.len()
    );
    for p in &c.positions {
        let _ = writeln!(f, "    {},", v3(p));
    }
    f.push_str("];\n");
    let _ = writeln!(f, "static {name}_N: [[Q2_14; 3]; {}] = [", c.normals.len());
    for n in &c.normals {
        let _ = writeln!(
            f,
            "    [n({}), n({}), n({})],",
            n[0].to_bits(),
            n[1].to_bits(),
            n[2].to_bits()
        );
    }
    f.push_str("];\n");
    let _ = writeln!(f, "static {name}_T: [[u16; 3]; {}] = [", c.triangles.len());
    for t in &c.triangles {
        let _ = writeln!(f, "    [{}, {}, {}],", t[0], t[1], t[2]);
    }
    f.push_str("];\n");
}

/// What to bake.
enum Input {
    Scene(Box<SceneDesc>, PathBuf),
    Obj(PathBuf),
}

fn input(arg: &str) -> Result<Input, String> {
    if builtin::scene(arg).is_some() || arg.ends_with(".toml") {
        let (d, dir) = load::read_scene(arg)?;
        return Ok(Input::Scene(Box::new(d), dir));
    }
    let p = Path::new(arg);
    if !p.exists() {
        return Err(format!(
            "{arg}: no such OBJ or scene file, and not a built-in scene (built-ins: {})",
            builtin::SCENES.join(", ")
        ));
    }
    Ok(Input::Obj(p.to_path_buf()))
}

/// Bakes `arg` (built-in scene, scene file or OBJ); `command` is the command line
/// written into the file's header.
pub fn bake(arg: &str, chunk: Option<usize>, command: &str) -> Result<Baked, String> {
    match input(arg)? {
        Input::Scene(d, dir) => {
            let ls = load::load(arg, &d, &dir)?;
            bake_loaded(arg, Some(&ls.desc), &ls.fixed, chunk, command)
        }
        Input::Obj(p) => {
            let parts = mesh::build(&MeshSource::Obj { path: p }, Path::new(""))
                .map_err(|e| e.to_string())?;
            let fixed = parts
                .iter()
                .map(|part| FixedMesh::from_mesh(&quantize_mesh(&part.mesh)))
                .collect::<Result<Vec<_>, _>>()?;
            let gl = MaterialDesc::default();
            let materials: Vec<MaterialDesc> = parts
                .iter()
                .map(|part| part.material.map_or(gl, |m| m.over(&gl)))
                .collect();
            bake_meshes(arg, None, &fixed, &materials, chunk, command)
        }
    }
}

/// Bakes meshes already in the core's formats, with the scene `desc` that places
/// them (`None`: the meshes alone); `arg` names the source in the file's header.
/// What [`bake`] does after loading its input, for scenes built in code (the
/// hard-case catalogue replaces meshes of its scene files).
pub fn bake_loaded(
    arg: &str,
    desc: Option<&SceneDesc>,
    fixed: &[FixedMesh],
    chunk: Option<usize>,
    command: &str,
) -> Result<Baked, String> {
    let materials: Vec<MaterialDesc> = match desc {
        Some(d) => d.objects.iter().map(|o| o.material).collect(),
        None => vec![MaterialDesc::default(); fixed.len()],
    };
    bake_meshes(arg, desc, fixed, &materials, chunk, command)
}

/// [`bake_loaded`] with the objects' materials (one per mesh) given.
fn bake_meshes(
    arg: &str,
    desc: Option<&SceneDesc>,
    fixed: &[FixedMesh],
    materials: &[MaterialDesc],
    chunk: Option<usize>,
    command: &str,
) -> Result<Baked, String> {
    let mut f = String::new();
    let _ = writeln!(
        f,
        "//! `{arg}` in the fixed-point formats of `fixshade`, baked by `{command}`.\n\
         //! Generated: edit the source and bake again, not this file."
    );
    let mut flash = 0;
    let mut summary = String::new();
    let mut body = String::new();
    let mut objects = Vec::new();
    for (i, m) in fixed.iter().enumerate() {
        let cs = chunks(m, chunk)?;
        let bound = mesh_bound(m);
        let mut names = Vec::new();
        for (k, c) in cs.iter().enumerate() {
            let name = format!("O{i}C{k}");
            arrays_src(&mut body, &name, c);
            flash += c.positions.len() * VERTEX_BYTES + c.triangles.len() * TRIANGLE_BYTES;
            names.push(format!("chunk(&{name}_P, &{name}_N, &{name}_T, {bound})"));
        }
        let largest = cs.iter().map(|c| c.positions.len()).max().unwrap_or(0);
        let repeated: usize = cs.iter().map(|c| c.positions.len()).sum::<usize>();
        let _ = writeln!(
            summary,
            "object {i}: {} vertices, {} triangles, {} chunk(s) (largest {largest} vertices, {} vertices stored)",
            m.positions.len(),
            m.triangles.len(),
            cs.len(),
            repeated
        );
        let _ = writeln!(
            body,
            "static OBJECT{i}: [Chunk; {}] = [\n    {},\n];",
            cs.len(),
            names.join(",\n    ")
        );
        objects.push(format!("&OBJECT{i}"));
    }
    let _ = writeln!(f, "//!\n//! Flash: {flash} bytes of arrays.");
    for l in summary.lines() {
        let _ = writeln!(f, "//! {l}");
    }
    f.push_str(
        "\n#![allow(dead_code, clippy::all)]\n\n\
         use fixshade::fixed::{Q16_16, Q2_14};\n\
         use fixshade::geometry::{Mesh, MeshError};\n\
         use fixshade::light::Material;\n",
    );
    if desc.is_some() {
        f.push_str(
            "use fixshade::fixed::Angle;\n\
             use fixshade::light::{Light, LightKind};\n\
             use fixshade::scene::{Camera, Object, Placement, Projection, Scene, ShadingMode};\n",
        );
    }
    f.push('\n');
    f.push_str(CHUNK_SRC);
    f.push_str(
        "const fn q(bits: i32) -> Q16_16 {\n    Q16_16::from_bits(bits)\n}\n\n\
         const fn n(bits: i16) -> Q2_14 {\n    Q2_14::from_bits(bits)\n}\n\n",
    );
    let _ = writeln!(
        f,
        "/// Every object's chunks, in the scene's object order.\npub static OBJECTS: [&[Chunk]; {}] = [{}];\n",
        objects.len(),
        objects.join(", ")
    );
    let _ = writeln!(
        f,
        "/// Every object's material, in the scene's object order.\npub static MATERIALS: [Material; {}] = [\n{}];\n",
        materials.len(),
        materials
            .iter()
            .map(|m| format!("    {},\n", material_src(&material(m))))
            .collect::<String>()
    );
    let cut = fixed
        .iter()
        .map(|m| chunks(m, chunk))
        .collect::<Result<Vec<_>, _>>()?;
    let largest = cut
        .iter()
        .flat_map(|cs| cs.iter().map(|c| c.positions.len()))
        .max()
        .unwrap_or(0);
    let most = cut.iter().map(Vec::len).max().unwrap_or(0);
    let _ = writeln!(
        f,
        "/// Vertices in the largest chunk: the vertex cache a draw of one chunk needs.\npub const MAX_CHUNK_VERTICES: usize = {largest};\n\
         /// The chunks' vertex limit (`--chunk`; 0: one chunk per mesh).\npub const CHUNK_LIMIT: usize = {};\n\
         /// Chunks of the object cut into the most.\npub const MAX_CHUNKS: usize = {most};\n",
        chunk.unwrap_or(0)
    );
    if let Some(d) = desc {
        let s = core_scene(d, fixed)?;
        // Two-sided lighting's back materials (a static: the objects borrow them).
        let _ = writeln!(
            f,
            "/// Every object's back material (two-sided lighting), in the scene's object order.\npub static BACK_MATERIALS: [Option<Material>; {}] = [\n{}];\n",
            s.objects.len(),
            s.objects
                .iter()
                .map(|o| match o.back_material {
                    Some(m) => format!("    Some({}),\n", material_src(m)),
                    None => "    None,\n".to_string(),
                })
                .collect::<String>()
        );
        let bg = background_channels(d.format, d.background);
        let _ = writeln!(
            f,
            "/// Frame width of the scene.\npub const WIDTH: u32 = {};\n/// Frame height of the scene.\npub const HEIGHT: u32 = {};\n\
             /// Background in the channel units of the scene's pixel format ({}).\npub const BACKGROUND: [u32; 3] = [{}, {}, {}];\n",
            d.width,
            d.height,
            d.format.name(),
            bg[0],
            bg[1],
            bg[2]
        );
        let _ = writeln!(
            f,
            "/// The depth buffer's cell (`depth_bits` of the scene file).\npub type Depth = u{};\n",
            if d.depth_bits == 32 { 32 } else { 16 }
        );
        f.push_str(&scene_src(&s));
        f.push('\n');
    }
    f.push_str(&body);
    Ok(Baked {
        source: f,
        flash_bytes: flash,
        summary,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> FixedMesh {
        // A 4 x 4 vertex grid, 18 triangles.
        let mut m = FixedMesh::default();
        for y in 0..4 {
            for x in 0..4 {
                m.positions
                    .push([Q16_16::from_int(x), Q16_16::from_int(y), Q16_16::ZERO]);
                m.normals
                    .push([Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]);
            }
        }
        for y in 0..3u16 {
            for x in 0..3u16 {
                let i = y * 4 + x;
                m.triangles.push([i, i + 1, i + 5]);
                m.triangles.push([i, i + 5, i + 4]);
            }
        }
        m
    }

    #[test]
    fn chunks_keep_triangle_order_and_vertices() {
        let m = grid();
        for limit in [3, 4, 5, 7, 16, 100] {
            let cs = chunks(&m, Some(limit)).unwrap();
            assert!(cs.iter().all(|c| c.positions.len() <= limit), "{limit}");
            // Concatenated, the chunks' triangles resolve to the mesh's triangles.
            let flat: Vec<[[Q16_16; 3]; 3]> = cs
                .iter()
                .flat_map(|c| {
                    c.triangles
                        .iter()
                        .map(|t| t.map(|i| c.positions[i as usize]))
                })
                .collect();
            let want: Vec<[[Q16_16; 3]; 3]> = m
                .triangles
                .iter()
                .map(|t| t.map(|i| m.positions[i as usize]))
                .collect();
            assert_eq!(flat, want, "{limit}");
        }
        assert_eq!(chunks(&m, Some(16)).unwrap().len(), 1);
        assert!(chunks(&m, Some(2)).is_err());
    }
}
