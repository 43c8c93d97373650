//! `crates/sim-host/scenes/effects/ground-plane.toml` in the fixed-point formats of `fixshade`, baked by `fixshade bake crates/sim-host/scenes/effects/ground-plane.toml`.
//! Generated: edit the source and bake again, not this file.
//!
//! Flash: 84 bytes of arrays.
//! object 0: 4 vertices, 2 triangles, 1 chunk(s) (largest 4 vertices, 4 vertices stored)

#![allow(dead_code, clippy::all)]

use fixshade::fixed::{Q16_16, Q2_14};
use fixshade::geometry::{Mesh, MeshError};
use fixshade::fixed::Angle;
use fixshade::light::{Light, LightKind, Material};
use fixshade::scene::{Camera, Object, Placement, Projection, Scene, ShadingMode};

/// A run of consecutive triangles with its own vertex arrays: Q16.16 positions,
/// Q2.14 normals, triangles.
pub type Chunk = (&'static [[Q16_16; 3]], &'static [[Q2_14; 3]], &'static [[u16; 3]]);

const fn q(bits: i32) -> Q16_16 {
    Q16_16::from_bits(bits)
}

const fn n(bits: i16) -> Q2_14 {
    Q2_14::from_bits(bits)
}

/// The core's view of a chunk.
pub fn chunk_mesh(c: &Chunk) -> Result<Mesh<'static>, MeshError> {
    Mesh::new(c.0, c.1, c.2)
}

/// Every object's chunks, in the scene's object order.
pub static OBJECTS: [&[Chunk]; 1] = [&OBJECT0];

/// Vertices in the largest chunk: the vertex cache a draw of one chunk needs.
pub const MAX_CHUNK_VERTICES: usize = 4;
/// The chunks' vertex limit (`--chunk`; 0: one chunk per mesh).
pub const CHUNK_LIMIT: usize = 0;

/// Frame width of the scene.
pub const WIDTH: u32 = 320;
/// Frame height of the scene.
pub const HEIGHT: u32 = 240;
/// Background in the channel units of the scene's pixel format (rgb565le).
pub const BACKGROUND: [u32; 3] = [2, 5, 4];

/// The scene, each object with the mesh of its first chunk (replace it to draw
/// the others).
pub fn scene() -> Result<Scene<'static>, MeshError> {
    let mut s = Scene::new(Camera {
        eye: [q(0), q(65536), q(393216)],
        target: [q(0), q(39322), q(0)],
        up: [q(0), q(65536), q(0)],
        projection: Projection::Perspective { fovy: Angle::from_turns_bits(715827883), near: q(32768), far: q(3932160) },
    });
    let _ = s.add_light(Light { kind: LightKind::Point { position: [q(-1179648), q(131072), q(-1179648)], attenuation: [q(65536), q(0), q(131)] }, ambient: [q(0), q(0), q(0)], diffuse: [q(65536), q(62259), q(55706)], specular: [q(0), q(0), q(0)] });
    s.global_ambient = [q(6554), q(6554), q(6554)];
    s.local_viewer = false;
    s.cull_back = true;
    s.depth_test = true;
    s.shading = ShadingMode::Gouraud;
    let _ = s.add_object(Object {
        mesh: chunk_mesh(&OBJECTS[0][0])?,
        placement: Placement {
            translate: [q(0), q(0), q(0)],
            rotate: [Angle::from_turns_bits(0), Angle::from_turns_bits(0), Angle::from_turns_bits(0)],
            scale: q(65536),
        },
        material: Material { emission: [q(0), q(0), q(0)], ambient: [q(13107), q(16384), q(13107)], diffuse: [q(32768), q(52429), q(32768)], specular: [q(0), q(0), q(0)], shininess: q(65536) },
    });
    Ok(s)
}

static O0C0_P: [[Q16_16; 3]; 4] = [
    [q(-1310720), q(0), q(-1310720)],
    [q(1310720), q(0), q(-1310720)],
    [q(-1310720), q(0), q(1310720)],
    [q(1310720), q(0), q(1310720)],
];
static O0C0_N: [[Q2_14; 3]; 4] = [
    [n(0), n(16384), n(0)],
    [n(0), n(16384), n(0)],
    [n(0), n(16384), n(0)],
    [n(0), n(16384), n(0)],
];
static O0C0_T: [[u16; 3]; 2] = [
    [0, 2, 3],
    [0, 3, 1],
];
static OBJECT0: [Chunk; 1] = [
    (&O0C0_P, &O0C0_N, &O0C0_T),
];
