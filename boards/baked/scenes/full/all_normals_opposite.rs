//! `all-normals-opposite` in the fixed-point formats of `fixshade`, baked by `cargo xtask bake-scenes (all-normals-opposite)`.
//! Generated: edit the source and bake again, not this file.
//!
//! Flash: 60 bytes of arrays.
//! object 0: 3 vertices, 1 triangles, 1 chunk(s) (largest 3 vertices, 3 vertices stored)

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
pub const MAX_CHUNK_VERTICES: usize = 3;
/// The chunks' vertex limit (`--chunk`; 0: one chunk per mesh).
pub const CHUNK_LIMIT: usize = 0;

/// Frame width of the scene.
pub const WIDTH: u32 = 48;
/// Frame height of the scene.
pub const HEIGHT: u32 = 48;
/// Background in the channel units of the scene's pixel format (rgb565le).
pub const BACKGROUND: [u32; 3] = [0, 0, 0];

/// The scene, each object with the mesh of its first chunk (replace it to draw
/// the others).
pub fn scene() -> Result<Scene<'static>, MeshError> {
    let mut s = Scene::new(Camera {
        eye: [q(0), q(0), q(196608)],
        target: [q(0), q(0), q(0)],
        up: [q(0), q(65536), q(0)],
        projection: Projection::Perspective { fovy: Angle::from_turns_bits(536870912), near: q(65536), far: q(1310720) },
    });
    let _ = s.add_light(Light { kind: LightKind::Directional { direction: [q(-32768), q(39322), q(52429)] }, ambient: [q(0), q(0), q(0)], diffuse: [q(65536), q(65536), q(65536)], specular: [q(65536), q(65536), q(65536)] });
    s.global_ambient = [q(13107), q(13107), q(13107)];
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
        material: Material { emission: [q(0), q(0), q(0)], ambient: [q(13107), q(13107), q(13107)], diffuse: [q(52429), q(32768), q(13107)], specular: [q(52429), q(52429), q(52429)], shininess: q(3276800) },
    });
    Ok(s)
}

static O0C0_P: [[Q16_16; 3]; 3] = [
    [q(-65536), q(-65536), q(0)],
    [q(65536), q(-65536), q(0)],
    [q(0), q(65536), q(0)],
];
static O0C0_N: [[Q2_14; 3]; 3] = [
    [n(16384), n(0), n(0)],
    [n(-16384), n(0), n(0)],
    [n(0), n(0), n(-16384)],
];
static O0C0_T: [[u16; 3]; 1] = [
    [0, 1, 2],
];
static OBJECT0: [Chunk; 1] = [
    (&O0C0_P, &O0C0_N, &O0C0_T),
];
