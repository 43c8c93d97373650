//! The frame both images draw: a lit tetrahedron into a 64×64 RGB565 framebuffer.
//! Only the effects differ, chosen by type in each binary (`src/bin/`).
#![no_std]

use fixshade::fixed::{Angle, Q16_16, Q2_14};
use fixshade::geometry::Mesh;
use fixshade::light::{Light, Material};
use fixshade::scene::{Camera, Object, Placement, Projection, Scene};

/// Frame width and height.
pub const SIZE: u32 = 64;

const fn q(v: i32) -> Q16_16 {
    Q16_16::from_int(v)
}
const fn n(v: i16) -> Q2_14 {
    Q2_14::from_bits(v)
}

static POS: [[Q16_16; 3]; 4] = [
    [q(1), q(1), q(1)],
    [q(-1), q(-1), q(1)],
    [q(-1), q(1), q(-1)],
    [q(1), q(-1), q(-1)],
];
// Unit vertex normals (±1/√3 in Q2.14 = ±9459).
static NRM: [[Q2_14; 3]; 4] = [
    [n(9459), n(9459), n(9459)],
    [n(-9459), n(-9459), n(9459)],
    [n(-9459), n(9459), n(-9459)],
    [n(9459), n(-9459), n(-9459)],
];
static TRI: [[u16; 3]; 4] = [[0, 1, 3], [0, 2, 1], [0, 3, 2], [1, 2, 3]];

/// The scene: one directional light with a specular colour, a shiny material.
pub fn scene(spin: i32) -> Scene<'static> {
    let camera = Camera {
        eye: [Q16_16::ZERO, Q16_16::ZERO, q(5)],
        target: [Q16_16::ZERO; 3],
        up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
        projection: Projection::Perspective {
            fovy: Angle::from_degrees(45),
            near: Q16_16::ONE,
            far: q(10),
        },
    };
    let mut s = Scene::new(camera);
    let white = [Q16_16::ONE; 3];
    let _ = s.add_light(Light::directional([q(-1), q(1), q(2)], white, white));
    let mesh = match Mesh::new(&POS, &NRM, &TRI) {
        Ok(m) => m,
        Err(_) => return s,
    };
    let material = Material {
        specular: [Q16_16::from_ratio(1, 2); 3],
        shininess: q(30),
        ..Material::default()
    };
    let placement = Placement {
        rotate: [
            Angle::from_degrees(spin),
            Angle::from_degrees(2 * spin),
            Angle::default(),
        ],
        ..Placement::default()
    };
    let _ = s.add_object(Object {
        mesh,
        placement,
        material,
        back_material: None,
    });
    s
}
