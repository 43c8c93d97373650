//! Scene descriptions in f64: what a scene file or a built-in scene says, before
//! anything is converted to the core's fixed-point formats.
//!
//! Both the fixed-point renderer (through `convert`) and the f64 reference renderer
//! (`reference`) start from these types, so they see the same scene.

use std::path::PathBuf;

pub use super::names::{DivideName, FormatName, Named, ShadingName, SpanName, SpecularName};

/// A triangle mesh in f64: positions, one unit normal per vertex, and
/// counter-clockwise (front-facing) triangles as indices into both arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions in model space.
    pub positions: Vec<[f64; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// One drawable piece of a mesh source: the whole mesh of a built-in model, or one
/// material group of an OBJ file ([`super::mesh::obj`]), each drawn as an object of
/// its own with the same placement.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshPart {
    /// The OBJ group's name (`o`/`g`, as tobj reports it), or the built-in model's.
    pub name: String,
    /// The triangles of the piece, with their own vertex arrays.
    pub mesh: MeshData,
    /// The material an MTL file gives the piece (`usemtl`), if any: the keys the
    /// file sets, applied over the scene's material ([`MtlMaterial::over`]).
    pub material: Option<MtlMaterial>,
}

/// A material of an MTL file as fixshade reads it: each key it sets, the others
/// left to the scene's material. Colours are checked to lie in 0..=1; `Ns` is
/// clamped to the core's 1..=1000.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MtlMaterial {
    /// `Ke`: emission.
    pub emission: Option<[f64; 3]>,
    /// `Ka`: ambient reflectance.
    pub ambient: Option<[f64; 3]>,
    /// `Kd`: diffuse reflectance.
    pub diffuse: Option<[f64; 3]>,
    /// `Ks`: specular reflectance.
    pub specular: Option<[f64; 3]>,
    /// `Ns`: Blinn exponent.
    pub shininess: Option<f64>,
}

impl MtlMaterial {
    /// `base` with every key this material sets replaced.
    ///
    /// ```
    /// use fixshade_sim::scene::desc::{MaterialDesc, MtlMaterial};
    /// let red = MtlMaterial { diffuse: Some([0.8, 0.1, 0.1]), ..Default::default() };
    /// let m = red.over(&MaterialDesc::default());
    /// assert_eq!((m.diffuse, m.ambient), ([0.8, 0.1, 0.1], [0.2, 0.2, 0.2]));
    /// ```
    pub fn over(&self, base: &MaterialDesc) -> MaterialDesc {
        MaterialDesc {
            emission: self.emission.unwrap_or(base.emission),
            ambient: self.ambient.unwrap_or(base.ambient),
            diffuse: self.diffuse.unwrap_or(base.diffuse),
            specular: self.specular.unwrap_or(base.specular),
            shininess: self.shininess.unwrap_or(base.shininess),
        }
    }
}

/// Where an object's material comes from, which decides whether the materials of
/// an OBJ's MTL file apply to it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MaterialFrom {
    /// The scene's `[material]` table (or OpenGL's defaults): an OBJ group with a
    /// `usemtl` material draws with that material's keys over it.
    #[default]
    Scene,
    /// The object's own `[object.material]` table: it overrides the MTL materials,
    /// every group of the OBJ draws with it (as a `glMaterial` call after loading).
    Object,
}

/// Where a mesh comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshSource {
    /// UV sphere of radius 1 centred at the origin, normals = positions.
    Sphere {
        /// Longitude segments (around the y axis), at least 3.
        lon: u32,
        /// Latitude segments (pole to pole), at least 2.
        lat: u32,
    },
    /// Newell's teapot: 32 bicubic Bézier patches, each tessellated into
    /// `level` x `level` quads.
    Teapot {
        /// Subdivisions per patch side, at least 1.
        level: u32,
    },
    /// A procedural robot of boxes, cylinders and spheres (flat faces, sharp edges).
    Robot,
    /// A Wavefront OBJ file.
    Obj {
        /// Path of the file.
        path: PathBuf,
    },
}

/// One mesh placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDesc {
    /// The mesh.
    pub mesh: MeshSource,
    /// Translation in world units.
    pub translate: [f64; 3],
    /// Rotation in degrees about x, y and z; the model matrix is
    /// `T * Rz * Ry * Rx * S` (x applied first).
    pub rotate_deg: [f64; 3],
    /// Uniform scale.
    pub scale: f64,
    /// The object's material.
    pub material: MaterialDesc,
    /// Where [`ObjectDesc::material`] comes from (whether an OBJ's MTL materials
    /// apply).
    pub material_from: MaterialFrom,
    /// The material of the object's back faces under two-sided lighting
    /// (`[object.back_material]`); `None`: the front material on both sides.
    pub back_material: Option<MaterialDesc>,
}

impl ObjectDesc {
    /// The material `part` of this object's mesh draws with: the object's own
    /// material when the scene file gives one (`[object.material]`), else the MTL
    /// material of the part over the scene's material, else the scene's material.
    pub fn part_material(&self, part: &MeshPart) -> MaterialDesc {
        match (self.material_from, &part.material) {
            (MaterialFrom::Scene, Some(mtl)) => mtl.over(&self.material),
            _ => self.material,
        }
    }
}

/// Camera projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// `gluPerspective(fovy, width/height, near, far)`.
    Perspective {
        /// Vertical field of view in degrees, in (0, 180).
        fovy_deg: f64,
        /// Near plane distance, > 0.
        near: f64,
        /// Far plane distance, > near.
        far: f64,
    },
    /// `glOrtho(-h*aspect/2, h*aspect/2, -h/2, h/2, near, far)`.
    Orthographic {
        /// Height of the view volume in world units.
        height: f64,
        /// Near plane distance.
        near: f64,
        /// Far plane distance, > near.
        far: f64,
    },
}

/// `gluLookAt` camera plus projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position.
    pub eye: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// Up direction.
    pub up: [f64; 3],
    /// Projection.
    pub projection: Projection,
}

/// Light kind; positions and directions are in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light at infinity; `direction` points from the surface towards the light
    /// (OpenGL position with w = 0).
    Directional {
        /// Direction towards the light (need not be unit length).
        direction: [f64; 3],
    },
    /// Point light with OpenGL attenuation `1 / (c + l*d + q*d^2)`.
    Point {
        /// Position in world space.
        position: [f64; 3],
        /// Constant, linear and quadratic attenuation.
        attenuation: [f64; 3],
    },
}

/// An OpenGL fixed-function light. Colours are linear, 0..1 per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightDesc {
    /// Directional or point.
    pub kind: LightKind,
    /// Ambient colour.
    pub ambient: [f64; 3],
    /// Diffuse colour.
    pub diffuse: [f64; 3],
    /// Specular colour.
    pub specular: [f64; 3],
}

/// An OpenGL fixed-function material. Colours 0..1 per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialDesc {
    /// Emission.
    pub emission: [f64; 3],
    /// Ambient reflectance.
    pub ambient: [f64; 3],
    /// Diffuse reflectance.
    pub diffuse: [f64; 3],
    /// Specular reflectance.
    pub specular: [f64; 3],
    /// Blinn exponent n, 1..=1000.
    pub shininess: f64,
}

impl Default for MaterialDesc {
    fn default() -> Self {
        MaterialDesc {
            emission: [0.0; 3],
            ambient: [0.2, 0.2, 0.2],
            diffuse: [0.8, 0.8, 0.8],
            specular: [0.0; 3],
            shininess: 1.0,
        }
    }
}

/// Default pixels per perspective division ([`SceneDesc::perspective_span`]).
pub const DEFAULT_PERSPECTIVE_SPAN: u32 = 16;

/// A whole scene as a scene file or a built-in scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    /// Image width in pixels, 1..=4096.
    pub width: u32,
    /// Image height in pixels, 1..=4096.
    pub height: u32,
    /// Output pixel format.
    pub format: FormatName,
    /// Background colour, 8 bits per channel.
    pub background: [u8; 3],
    /// Camera.
    pub camera: CameraDesc,
    /// Up to 8 lights.
    pub lights: Vec<LightDesc>,
    /// Global ambient light (OpenGL `GL_LIGHT_MODEL_AMBIENT`).
    pub global_ambient: [f64; 3],
    /// Local viewer (`GL_LIGHT_MODEL_LOCAL_VIEWER`).
    pub local_viewer: bool,
    /// Two-sided lighting (`GL_LIGHT_MODEL_TWO_SIDE`): back faces lit with the
    /// negated normal and the back material.
    pub two_sided: bool,
    /// Objects.
    pub objects: Vec<ObjectDesc>,
    /// Shading mode.
    pub shading: ShadingName,
    /// Span method.
    pub span: SpanName,
    /// Cull back faces (counter-clockwise triangles are front faces).
    pub cull_back: bool,
    /// Test and write a depth buffer.
    pub depth_test: bool,
    /// Bits per depth cell: 16 (`u16`) or 32 (`u32`, for near/far ratios a 16-bit
    /// buffer cannot resolve; see `fixshade::target::DepthFormat`).
    pub depth_bits: u32,
    /// Perspective-correct instead of screen-affine interpolation of Gouraud colours
    /// and Phong normals and eye positions, in the fixed-point renderer and in the
    /// reference.
    pub perspective_correct: bool,
    /// Pixels per perspective division of the fixed-point renderer: 1 (every pixel)
    /// or a power of two up to 64 (sub-spans interpolated linearly).
    pub perspective_span: u32,
    /// Specular model of the fixed-point renderer (the reference is always exact).
    pub specular: SpecularName,
    /// Divider of the fixed-point renderer's divisions (setup reciprocal, classic
    /// span, Schlick's denominator).
    pub divide: DivideName,
    /// Ray-casting settings and analytic primitives (`shading = "raycast"`).
    pub raycast: RaycastDesc,
    /// Effects forced on or off (`[render] effects`, `--effects`; [`super::effects`]).
    pub effects: Overrides,
}

// ---------------------------------------------------------------------------------
// Ray casting (`shading = "raycast"`, [`crate::render::raycast`]).

/// Default segment length L (see `docs/raycast.md` for the measurements behind it).
pub const DEFAULT_SEGMENT: u32 = 8;
/// Default threshold K in 8-bit levels, the seed's 2.3 (see `docs/raycast.md`).
pub const DEFAULT_THRESHOLD: f64 = 2.3;
/// Largest segment length accepted from scene files and the CLI.
pub const MAX_SEGMENT: u32 = 256;
/// Largest threshold accepted (any larger value never subdivides an 8-bit channel).
pub const MAX_THRESHOLD: f64 = 256.0;

/// An analytic sphere of a scene file (`[[sphere]]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereDesc {
    /// Centre, world space.
    pub centre: [f64; 3],
    /// Radius, > 0.
    pub radius: f64,
    /// Material.
    pub material: MaterialDesc,
}

/// An infinite plane of a scene file (`[[plane]]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneDesc {
    /// A point of the plane, world space.
    pub point: [f64; 3],
    /// Normal, non-zero.
    pub normal: [f64; 3],
    /// Material.
    pub material: MaterialDesc,
}

/// The ray-casting settings of a scene: sampler parameters and analytic
/// primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct RaycastDesc {
    /// Segment length L, 1..=[`MAX_SEGMENT`].
    pub segment: u32,
    /// Threshold K in 8-bit levels, 0..=[`MAX_THRESHOLD`] (rounded to 1/256).
    pub threshold: f64,
    /// Two-dimensional blocks instead of row segments.
    pub block: bool,
    /// The sampler also applies to `shading = "phong"`: set when the segment or the
    /// threshold is given explicitly (scene file or command line). Ray casting always
    /// samples.
    pub sampled: bool,
    /// Hard shadows from the first light.
    pub shadows: bool,
    /// Analytic spheres (at most 8).
    pub spheres: Vec<SphereDesc>,
    /// Planes (at most 4).
    pub planes: Vec<PlaneDesc>,
}

impl Default for RaycastDesc {
    fn default() -> Self {
        RaycastDesc {
            segment: DEFAULT_SEGMENT,
            threshold: DEFAULT_THRESHOLD,
            block: false,
            sampled: false,
            shadows: true,
            spheres: Vec::new(),
            planes: Vec::new(),
        }
    }
}

// ---------------------------------------------------------------------------------
// Effects forced on or off ([`super::effects`]).

/// An effect that `--effects` and the scene file's `effects` key can force.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Effect {
    /// The depth test.
    Depth,
    /// Back-face culling.
    Cull,
    /// The specular term.
    Specular,
    /// Lighting at all (`-lighting`: unlit).
    Lighting,
    /// The local viewer.
    LocalViewer,
    /// Perspective-correct interpolation of Gouraud colours and Phong normals.
    Perspective,
}

impl Named for Effect {
    const WHAT: &'static str = "effect";
    const ALL: &'static [(Self, &'static str)] = &[
        (Effect::Depth, "depth"),
        (Effect::Cull, "cull"),
        (Effect::Specular, "specular"),
        (Effect::Lighting, "lighting"),
        (Effect::LocalViewer, "local-viewer"),
        (Effect::Perspective, "perspective"),
    ];
}

/// Where a forced setting comes from.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// The scene file's `[render] effects` key.
    SceneFile,
    /// `--effects` on the command line.
    CommandLine,
}

impl Source {
    /// The rule, in words, for `--explain`.
    pub fn why(self) -> &'static str {
        match self {
            Source::SceneFile => "forced by the scene file (effects = ...)",
            Source::CommandLine => "forced by --effects",
        }
    }
}

/// Forced settings, in order (a later one wins).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Overrides(pub Vec<(Effect, bool, Source)>);

impl Overrides {
    /// Parses `+name,-name,...` (a bare `name` means `+name`). The error is one
    /// sentence naming the bad item and the valid names.
    pub fn parse(list: &str, source: Source) -> Result<Overrides, String> {
        let mut out = Vec::new();
        for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (on, name) = match item.as_bytes()[0] {
                b'+' => (true, &item[1..]),
                b'-' => (false, &item[1..]),
                _ => (true, item),
            };
            let effect = Effect::parse(name.trim()).map_err(|e| {
                format!("effects: `{item}`: {e} (each item is +NAME or -NAME, comma-separated)")
            })?;
            out.push((effect, on, source));
        }
        Ok(Overrides(out))
    }

    /// The last forced value of `e`, with its source.
    pub fn get(&self, e: Effect) -> Option<(bool, Source)> {
        self.0
            .iter()
            .rev()
            .find(|(x, _, _)| *x == e)
            .map(|(_, on, s)| (*on, *s))
    }

    /// Appends `other` (its settings win).
    pub fn extend(&mut self, other: &Overrides) {
        self.0.extend(other.0.iter().copied());
    }
}
