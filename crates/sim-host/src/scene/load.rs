//! A scene ready for both renderers: read (a file or a built-in), its meshes built,
//! everything quantised to the core's grid.

use std::path::{Path, PathBuf};

use super::convert::{quantize_mesh, quantize_scene, FixedMesh};
use super::desc::{MeshData, SceneDesc};
use super::{builtin, file, mesh};

/// A scene with its meshes built and quantised, ready for both renderers.
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

/// Builds the meshes of `desc` (OBJ paths relative to `base_dir`) and quantises
/// everything.
pub fn load(name: &str, desc: &SceneDesc, base_dir: &Path) -> Result<LoadedScene, String> {
    let mut meshes = Vec::new();
    let mut fixed = Vec::new();
    for o in &desc.objects {
        let m = mesh::build(&o.mesh, base_dir).map_err(|e| e.to_string())?;
        let q = quantize_mesh(&m);
        fixed.push(FixedMesh::from_mesh(&q)?);
        meshes.push(q);
    }
    Ok(LoadedScene {
        name: name.to_string(),
        desc: quantize_scene(desc),
        meshes,
        fixed,
    })
}

/// [`read_scene`] then [`load`].
pub fn load_arg(arg: &str) -> Result<LoadedScene, String> {
    let (d, dir) = read_scene(arg)?;
    load(arg, &d, &dir)
}
