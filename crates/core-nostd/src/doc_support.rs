//! Fixtures shared by the documentation's examples: one lit triangle facing the
//! camera. Not part of the API (hidden from the docs); examples start from it so
//! each shows only the item it documents.

use crate::fixed::{Angle, Q16_16, Q2_14};
use crate::geometry::{Mesh, MeshError};
use crate::light::rgb;
use crate::light::{Light, Material};
use crate::math::Vec3;
use crate::scene::{Camera, Object, Scene};

/// Vertices of a triangle in the z = 0 plane, counter-clockwise seen from +z.
pub static POSITIONS: [Vec3; 3] = [
    [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
    [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
    [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
];
/// Normals: all +z.
pub static NORMALS: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
/// The one triangle.
pub static TRIANGLES: [[u16; 3]; 1] = [[0, 1, 2]];

/// The eye of [`scene`]: on the +z axis, 3 units from the triangle.
pub const EYE: Vec3 = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)];

/// The triangle as a mesh (always `Ok`).
pub fn triangle() -> Result<Mesh<'static>, MeshError> {
    Mesh::new(&POSITIONS, &NORMALS, &TRIANGLES)
}

/// The triangle, orange with a white highlight, seen through a 60° camera at
/// [`EYE`] and lit by a white light from the eye's direction.
pub fn scene() -> Scene<'static> {
    let white = rgb(255, 255, 255);
    let mut s = Scene::new(Camera::perspective(
        EYE,
        [Q16_16::ZERO; 3],
        Angle::from_degrees(60),
    ));
    let mat = Material::default()
        .with_diffuse(rgb(230, 120, 40))
        .with_specular(white, 32);
    // Capacity is 8 lights and 16 objects: one of each always fits.
    let _ = s.add_light(Light::directional(EYE, white, white));
    if let Ok(mesh) = triangle() {
        let _ = s.add_object(Object::new(mesh).with_material(mat));
    }
    s
}
