//! The hard-case catalogue (`tests/catalogue/`): screen-space triangle cases
//! (`triangles.toml`) and scene cases (`scenes.toml`, scene files under
//! `scenes/`). The file headers describe the formats and what each `holds` entry
//! means; `tests/tests/hard_cases.rs` runs them, and the fuzz seed corpora are
//! written from them.

use fixshade::raster::ScreenVertex;
use serde::Deserialize;

/// One triangle case.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriCase {
    /// Unique name.
    pub name: String,
    /// What makes it hard.
    pub what: String,
    /// Frame width and height in pixels.
    pub frame: [u32; 2],
    /// First row and row count of the strip drawn into (default: whole frame).
    #[serde(default)]
    pub strip: Option<[u32; 2]>,
    /// What must hold.
    pub holds: Vec<String>,
    /// Triangles: vertices `[x, y, z, r, g, b]` (Q12.4, u16 depth, 8-bit colour).
    pub tri: Vec<[[i64; 6]; 3]>,
}

impl TriCase {
    /// True if the case lists `what` in `holds`.
    pub fn holds(&self, what: &str) -> bool {
        self.holds.iter().any(|h| h == what)
    }

    /// The strip `(y0, rows)`.
    pub fn strip(&self) -> (u32, u32) {
        let [y0, h] = self.strip.unwrap_or([0, self.frame[1]]);
        (y0, h)
    }

    /// The triangles as the rasterizer takes them (depth and colours scaled by
    /// 2¹⁶; coordinates outside `i32` saturate).
    pub fn triangles(&self) -> Vec<[ScreenVertex; 3]> {
        self.tri
            .iter()
            .map(|t| {
                t.map(|v| ScreenVertex {
                    x: v[0].clamp(i32::MIN as i64, i32::MAX as i64) as i32,
                    y: v[1].clamp(i32::MIN as i64, i32::MAX as i64) as i32,
                    z: (v[2].clamp(0, 65534) as u32) << 16,
                    c: [v[3], v[4], v[5]].map(|c| (c.clamp(0, 255) as i32) << 16),
                })
            })
            .collect()
    }
}

/// The known `holds` words of triangle cases.
pub const TRI_HOLDS: [&str; 8] = [
    "coverage",
    "colour",
    "depth",
    "watertight",
    "nonempty",
    "empty",
    "first-wins",
    "strip",
];

#[derive(Deserialize)]
struct TriFile {
    case: Vec<TriCase>,
}

/// One scene case: a scene file, optionally with explicit mesh data for its first
/// object (positions, normals and triangles given as they are, so normals can be
/// anything the core accepts).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneCase {
    /// Unique name.
    pub name: String,
    /// What makes it hard.
    pub what: String,
    /// Scene file, relative to `tests/catalogue/`.
    pub scene: String,
    /// Explicit positions of object 0's mesh (replacing the scene's mesh).
    #[serde(default)]
    pub positions: Vec<[f64; 3]>,
    /// Explicit unit normals, one per position.
    #[serde(default)]
    pub normals: Vec<[f64; 3]>,
    /// Explicit triangles.
    #[serde(default)]
    pub triangles: Vec<[u32; 3]>,
    /// What must hold.
    pub holds: Vec<String>,
    /// Upper bound of the NMSE against the f64 reference (`reference` in `holds`).
    #[serde(default)]
    pub nmse_max: Option<f64>,
}

impl SceneCase {
    /// True if the case lists `what` in `holds`.
    pub fn holds(&self, what: &str) -> bool {
        self.holds.iter().any(|h| h == what)
    }
}

impl SceneCase {
    /// The case as the renderer takes it: its scene file loaded, and object 0's
    /// mesh replaced by the explicit `positions`, `normals` and `triangles` when the
    /// case gives them.
    pub fn load(&self) -> Result<fixshade_sim::scene::load::LoadedScene, String> {
        use fixshade_sim::scene::convert::{quantize_mesh, FixedMesh};
        use fixshade_sim::scene::desc::MeshData;
        use fixshade_sim::scene::load::{load, read_scene};
        let path = path(&self.scene);
        let (desc, dir) = read_scene(&path.display().to_string())?;
        let mut ls = load(&self.name, &desc, &dir).map_err(|e| format!("{}: {e}", self.name))?;
        if !self.positions.is_empty() {
            let m = quantize_mesh(&MeshData {
                positions: self.positions.clone(),
                normals: self.normals.clone(),
                triangles: self.triangles.clone(),
            });
            ls.fixed[0] = FixedMesh::from_mesh(&m).map_err(|e| format!("{}: {e}", self.name))?;
            ls.meshes[0] = m;
        }
        Ok(ls)
    }
}

/// The known `holds` words of scene cases.
pub const SCENE_HOLDS: [&str; 6] = [
    "renders",
    "nonempty",
    "empty",
    "strip",
    "reference",
    "coverage",
];

#[derive(Deserialize)]
struct SceneFile {
    case: Vec<SceneCase>,
}

/// Path of a catalogue file.
pub fn path(rel: &str) -> std::path::PathBuf {
    crate::package_path("catalogue").join(rel)
}

/// The triangle cases.
pub fn triangle_cases() -> Vec<TriCase> {
    let p = path("triangles.toml");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let f: TriFile = toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    f.case
}

/// The scene cases.
pub fn scene_cases() -> Vec<SceneCase> {
    let p = path("scenes.toml");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let f: SceneFile = toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    f.case
}

/// The fuzz target `raster`'s input for triangles `tris` (see
/// `fuzz/fuzz_targets/raster.rs` for the layout): span method `method`, `flags`,
/// frame `w` × `h` (1..=24), strip `(y0, rows)`.
pub fn raster_seed(
    method: u8,
    flags: u8,
    w: u32,
    h: u32,
    strip: (u32, u32),
    tris: &[[ScreenVertex; 3]],
) -> Vec<u8> {
    let mut out = vec![
        method,
        flags,
        (w - 1) as u8,
        (h - 1) as u8,
        strip.0 as u8,
        (strip.1 - 1) as u8,
    ];
    for t in tris.iter().take(4) {
        for v in t {
            for word in [v.x, v.y, v.z as i32, v.c[0], v.c[1], v.c[2]] {
                out.extend(word.to_le_bytes());
            }
        }
        // Edge-midpoint colours: the mean of the edge's vertex colours (the
        // quadratic surface is then the Gouraud plane).
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            for ch in 0..3 {
                out.extend(((a.c[ch] + b.c[ch]) / 2).to_le_bytes());
            }
        }
    }
    out
}
