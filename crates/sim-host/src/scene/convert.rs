//! From f64 scene descriptions to the core's fixed-point scene, and the matching
//! quantisation of the description for the reference renderer.
//!
//! Every number the core receives is rounded to its fixed-point grid: coordinates,
//! colours and factors to Q16.16, normals to Q2.14, angles to 2⁻³² of a turn.
//! [`quantize_scene`] and [`quantize_mesh`] round the f64 description to exactly the
//! same values, so the reference renderer sees the scene the core sees and the
//! accuracy figures measure only the core's arithmetic, not input rounding.

use super::desc::{
    CameraDesc, FormatName, LightDesc, LightKind, MaterialDesc, MeshData, Projection, SceneDesc,
};
use fixshade::fixed::{Angle, Q16_16, Q2_14};
use fixshade::geometry::Mesh;
use fixshade::light::{Light, LightKind as CoreLightKind, Material};
use fixshade::scene::{
    Camera, Object, Placement, Projection as CoreProjection, Scene, ShadingMode,
};

/// The smallest positive Q16.16 number, 2⁻¹⁶: the core's smallest perspective
/// near plane (`Mat4::perspective` takes `near > 0` after rounding).
pub const Q16_MIN_POSITIVE: f64 = 1.0 / 65536.0;
/// The largest Q16.16 number, 32767.99998…: larger values saturate.
pub const Q16_MAX: f64 = i32::MAX as f64 / 65536.0;

/// Rounds to Q16.16, saturating.
pub fn q16(v: f64) -> Q16_16 {
    let r = (v * 65536.0).round();
    Q16_16::from_bits(r.clamp(i32::MIN as f64, i32::MAX as f64) as i32)
}

/// The f64 value of a Q16.16 number.
pub fn f16(v: Q16_16) -> f64 {
    v.to_bits() as f64 / 65536.0
}

/// Rounds degrees to a binary angle (2⁻³² turn).
pub fn angle(deg: f64) -> Angle {
    let turns = deg.rem_euclid(360.0) / 360.0;
    Angle::from_turns_bits(((turns * 4294967296.0).round() as u64 & 0xFFFF_FFFF) as u32)
}

/// Degrees of a binary angle, exactly.
pub fn angle_deg(a: Angle) -> f64 {
    a.to_turns_bits() as f64 * 360.0 / 4294967296.0
}

fn qv(v: [f64; 3]) -> [f64; 3] {
    v.map(|c| f16(q16(c)))
}

fn qa(deg: f64) -> f64 {
    angle_deg(angle(deg))
}

/// Rounds a Q2.14 normal component.
pub fn q14(v: f64) -> Q2_14 {
    Q2_14::from_bits((v * 16384.0).round().clamp(-32768.0, 32767.0) as i16)
}

/// The description rounded to the values the core works with.
pub fn quantize_scene(d: &SceneDesc) -> SceneDesc {
    let mut q = d.clone();
    let cam = &mut q.camera;
    cam.eye = qv(cam.eye);
    cam.target = qv(cam.target);
    cam.up = qv(cam.up);
    cam.projection = match cam.projection {
        Projection::Perspective {
            fovy_deg,
            near,
            far,
        } => Projection::Perspective {
            fovy_deg: qa(fovy_deg),
            near: f16(q16(near)),
            far: f16(q16(far)),
        },
        Projection::Orthographic { height, near, far } => Projection::Orthographic {
            height: f16(q16(height)),
            near: f16(q16(near)),
            far: f16(q16(far)),
        },
    };
    for l in &mut q.lights {
        l.ambient = qv(l.ambient);
        l.diffuse = qv(l.diffuse);
        l.specular = qv(l.specular);
        l.kind = match l.kind {
            LightKind::Directional { direction } => LightKind::Directional {
                direction: qv(direction),
            },
            LightKind::Point {
                position,
                attenuation,
            } => LightKind::Point {
                position: qv(position),
                attenuation: qv(attenuation),
            },
        };
    }
    q.global_ambient = qv(q.global_ambient);
    for o in &mut q.objects {
        o.translate = qv(o.translate);
        o.rotate_deg = o.rotate_deg.map(qa);
        o.scale = f16(q16(o.scale));
        o.material = quantize_material(&o.material);
        o.back_material = o.back_material.as_ref().map(quantize_material);
    }
    q
}

fn quantize_material(m: &MaterialDesc) -> MaterialDesc {
    MaterialDesc {
        emission: qv(m.emission),
        ambient: qv(m.ambient),
        diffuse: qv(m.diffuse),
        specular: qv(m.specular),
        shininess: f16(q16(m.shininess)),
    }
}

/// The mesh rounded to Q16.16 positions and Q2.14 normals.
pub fn quantize_mesh(m: &MeshData) -> MeshData {
    MeshData {
        positions: m.positions.iter().map(|p| qv(*p)).collect(),
        normals: m
            .normals
            .iter()
            .map(|n| n.map(|c| q14(c).to_bits() as f64 / 16384.0))
            .collect(),
        triangles: m.triangles.clone(),
    }
}

/// A mesh in the core's formats, owned by the host.
#[derive(Clone, Debug, Default)]
pub struct FixedMesh {
    /// Q16.16 positions.
    pub positions: Vec<[Q16_16; 3]>,
    /// Q2.14 normals.
    pub normals: Vec<[Q2_14; 3]>,
    /// Triangles.
    pub triangles: Vec<[u16; 3]>,
}

impl FixedMesh {
    /// Converts an f64 mesh; errors if it has more than 65535 vertices or
    /// coordinates beyond ±16384.
    pub fn from_mesh(m: &MeshData) -> Result<FixedMesh, String> {
        if m.positions.len() > 65535 {
            return Err(format!(
                "mesh has {} vertices; the core indexes at most 65535 (u16)",
                m.positions.len()
            ));
        }
        let fm = FixedMesh {
            positions: m.positions.iter().map(|p| p.map(q16)).collect(),
            normals: m.normals.iter().map(|n| n.map(q14)).collect(),
            triangles: m.triangles.iter().map(|t| t.map(|i| i as u16)).collect(),
        };
        fm.mesh()
            .map_err(|e| format!("mesh rejected by the core: {e}"))?;
        Ok(fm)
    }

    /// The core's view of this mesh.
    pub fn mesh(&self) -> Result<Mesh<'_>, fixshade::geometry::MeshError> {
        Mesh::new(&self.positions, &self.normals, &self.triangles)
    }
}

fn color(c: [f64; 3]) -> [Q16_16; 3] {
    c.map(q16)
}

fn camera(c: &CameraDesc) -> Camera {
    Camera {
        eye: color(c.eye),
        target: color(c.target),
        up: color(c.up),
        projection: match c.projection {
            Projection::Perspective {
                fovy_deg,
                near,
                far,
            } => CoreProjection::Perspective {
                fovy: angle(fovy_deg),
                near: q16(near),
                far: q16(far),
            },
            Projection::Orthographic { height, near, far } => CoreProjection::Orthographic {
                height: q16(height),
                near: q16(near),
                far: q16(far),
            },
        },
    }
}

fn light(l: &LightDesc) -> Light {
    Light {
        kind: match l.kind {
            LightKind::Directional { direction } => CoreLightKind::Directional {
                direction: color(direction),
            },
            LightKind::Point {
                position,
                attenuation,
            } => CoreLightKind::Point {
                position: color(position),
                attenuation: color(attenuation),
            },
        },
        ambient: color(l.ambient),
        diffuse: color(l.diffuse),
        specular: color(l.specular),
    }
}

/// A material in the core's formats.
pub fn material(m: &MaterialDesc) -> Material {
    Material {
        emission: color(m.emission),
        ambient: color(m.ambient),
        diffuse: color(m.diffuse),
        specular: color(m.specular),
        shininess: q16(m.shininess),
    }
}

/// `m` with the static lifetime a core object's back material borrows with: each
/// distinct material is kept once for the life of the process (a scene's back
/// materials are few; a scene converted again finds its materials kept).
fn interned(m: Material) -> &'static Material {
    use std::sync::Mutex;
    static KEPT: Mutex<Vec<&'static Material>> = Mutex::new(Vec::new());
    let mut kept = KEPT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(k) = kept.iter().find(|k| ***k == m) {
        return k;
    }
    let k: &'static Material = Box::leak(Box::new(m));
    kept.push(k);
    k
}

/// Builds the core scene of `d` over `meshes` (one per object, in order).
pub fn core_scene<'a>(d: &SceneDesc, meshes: &'a [FixedMesh]) -> Result<Scene<'a>, String> {
    let mut s = Scene::new(camera(&d.camera));
    for l in &d.lights {
        s.add_light(light(l))
            .map_err(|_| "more than 8 lights".to_string())?;
    }
    s.global_ambient = color(d.global_ambient);
    s.local_viewer = d.local_viewer;
    s.cull_back = d.cull_back;
    s.depth_test = d.depth_test;
    // The ray caster does not use the rasterizer's shading mode.
    s.shading = d.shading.core().unwrap_or(ShadingMode::Gouraud);
    for (o, m) in d.objects.iter().zip(meshes) {
        let mesh = m
            .mesh()
            .map_err(|e| format!("mesh rejected by the core: {e}"))?;
        s.add_object(Object {
            mesh,
            placement: Placement {
                translate: color(o.translate),
                rotate: o.rotate_deg.map(angle),
                scale: q16(o.scale),
            },
            material: material(&o.material),
            back_material: o.back_material.as_ref().map(|m| interned(material(m))),
        })
        .map_err(|_| "more than 16 objects".to_string())?;
    }
    Ok(s)
}

/// K in Q8 (1/256 of an 8-bit level), rounded; negative or non-finite values give 0.
pub fn threshold_q8(k: f64) -> u32 {
    if k.is_finite() && k > 0.0 {
        (k * 256.0).round().min(super::desc::MAX_THRESHOLD * 256.0) as u32
    } else {
        0
    }
}

/// Channel integers of the background in `format` (rounded to nearest).
pub fn background_channels(format: FormatName, bg: [u8; 3]) -> [u32; 3] {
    let m = format.channel_max();
    if format.is_gray() {
        let y = (77 * bg[0] as u32 + 150 * bg[1] as u32 + 29 * bg[2] as u32 + 128) / 256;
        return [y; 3];
    }
    [0, 1, 2].map(|i| (bg[i] as u32 * m[i] + 127) / 255)
}

/// The background as it appears in the image: quantised to the format, expanded.
pub fn background8(desc: &SceneDesc) -> [u8; 3] {
    desc.format
        .expand(background_channels(desc.format, desc.background))
}
