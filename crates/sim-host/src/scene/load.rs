//! A scene ready for both renderers: read (a file or a built-in), its meshes built,
//! everything quantised to the core's grid.

use std::path::{Path, PathBuf};

use super::convert::{quantize_mesh, quantize_scene, FixedMesh};
use super::desc::{MeshData, ObjectDesc, SceneDesc};
use super::{builtin, file, mesh};

/// A scene with its meshes built and quantised, ready for both renderers.
///
/// Its objects are the parts to draw: a scene object whose OBJ file has several
/// material groups becomes one object per group, each with the same placement and
/// its own material ([`ObjectDesc::part_material`]), in the file's order.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// Where the scene came from (file path or built-in name).
    pub name: String,
    /// The description, quantised to the core's grid.
    pub desc: SceneDesc,
    /// The meshes in f64, quantised (for the reference).
    pub meshes: Vec<MeshData>,
    /// The meshes in the core's formats.
    pub fixed: Vec<FixedMesh>,
}

/// Reads a scene: `arg` is a built-in scene name or a scene file path. Returns the
/// description and the directory OBJ paths are relative to.
pub fn read_scene(arg: &str) -> Result<(SceneDesc, PathBuf), String> {
    if let Some(d) = builtin::scene(arg) {
        return Ok((d, PathBuf::from(".")));
    }
    let path = Path::new(arg);
    if !path.exists() {
        return Err(format!(
            "{arg}: no such scene file, and not a built-in scene (built-ins: {})",
            builtin::SCENES.join(", ")
        ));
    }
    let d = file::load_scene(path).map_err(|e| e.to_string())?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok((d, dir))
}

/// Builds the meshes of `desc` (OBJ paths relative to `base_dir`), one object per
/// mesh part (see [`LoadedScene`]), and quantises everything. Errors if the parts
/// are more than the core's [`MAX_OBJECTS`](fixshade::scene::MAX_OBJECTS).
pub fn load(name: &str, desc: &SceneDesc, base_dir: &Path) -> Result<LoadedScene, String> {
    let mut objects = Vec::new();
    let mut meshes = Vec::new();
    let mut fixed = Vec::new();
    for o in &desc.objects {
        for part in mesh::build(&o.mesh, base_dir).map_err(|e| e.to_string())? {
            objects.push(ObjectDesc {
                material: o.part_material(&part),
                ..o.clone()
            });
            let q = quantize_mesh(&part.mesh);
            fixed.push(FixedMesh::from_mesh(&q)?);
            meshes.push(q);
        }
    }
    let max = fixshade::scene::MAX_OBJECTS;
    if objects.len() > max {
        return Err(format!(
            "{name}: {} objects to draw (an OBJ file draws one per material group), \
             the core draws at most {max}",
            objects.len()
        ));
    }
    let mut desc = desc.clone();
    desc.objects = objects;
    Ok(LoadedScene {
        name: name.to_string(),
        desc: quantize_scene(&desc),
        meshes,
        fixed,
    })
}

/// [`read_scene`] then [`load`].
pub fn load_arg(arg: &str) -> Result<LoadedScene, String> {
    let (d, dir) = read_scene(arg)?;
    load(arg, &d, &dir)
}
