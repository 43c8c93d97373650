//! OpenGL-style matrices in f64 (column vectors) and small vector helpers.
//!
//! A [`Mat4`] is stored row-major, `m[row][col]`, and applies to column vectors:
//! `v' = m * v`, `v'[i] = Σ_j m[i][j] * v[j]`. (This is the transpose of OpenGL's
//! column-major memory layout, but the same mathematical matrix.)

use crate::scene::desc::{CameraDesc, ObjectDesc, Projection};

/// A 4x4 matrix, row-major (`m[row][col]`), acting on column vectors.
pub type Mat4 = [[f64; 4]; 4];

/// The 4x4 identity matrix.
pub const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// Matrix product `a * b` (apply `b` first, then `a`).
pub fn mat_mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut r = [[0.0; 4]; 4];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

/// `m * v` for a homogeneous column vector `v`.
pub fn mat_vec(m: &Mat4, v: [f64; 4]) -> [f64; 4] {
    let mut r = [0.0; 4];
    for (i, out) in r.iter_mut().enumerate() {
        *out = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] + m[i][3] * v[3];
    }
    r
}

/// Transforms a point (w = 1) by an affine matrix and drops w.
pub fn transform_point(m: &Mat4, p: [f64; 3]) -> [f64; 3] {
    let r = mat_vec(m, [p[0], p[1], p[2], 1.0]);
    [r[0], r[1], r[2]]
}

/// Transforms a direction by the upper-left 3x3 part of `m`.
pub fn transform_dir(m: &Mat4, d: [f64; 3]) -> [f64; 3] {
    let r = mat_vec(m, [d[0], d[1], d[2], 0.0]);
    [r[0], r[1], r[2]]
}

/// The normal matrix of `m`: the inverse-transpose of its upper-left 3x3 part, as a
/// [`Mat4`] with zero translation. For a singular 3x3 part the cofactor matrix is
/// returned instead (same directions wherever they are defined; normals are
/// renormalised afterwards anyway).
pub fn normal_matrix(m: &Mat4) -> Mat4 {
    let a = |i: usize, j: usize| m[i][j];
    // Cofactor matrix C; inverse-transpose = C / det.
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            // Cyclic index order gives the signed cofactor directly.
            *cell = a(i1, j1) * a(i2, j2) - a(i1, j2) * a(i2, j1);
        }
    }
    let det = a(0, 0) * c[0][0] + a(0, 1) * c[0][1] + a(0, 2) * c[0][2];
    let s = if det != 0.0 { 1.0 / det } else { 1.0 };
    let mut r = IDENTITY;
    for (r_row, c_row) in r.iter_mut().zip(&c) {
        for (x, y) in r_row.iter_mut().zip(c_row) {
            *x = y * s;
        }
    }
    r
}

/// `glTranslate(t)`.
pub fn translation(t: [f64; 3]) -> Mat4 {
    let mut m = IDENTITY;
    m[0][3] = t[0];
    m[1][3] = t[1];
    m[2][3] = t[2];
    m
}

/// `glScale(s, s, s)`.
pub fn uniform_scale(s: f64) -> Mat4 {
    let mut m = IDENTITY;
    m[0][0] = s;
    m[1][1] = s;
    m[2][2] = s;
    m
}

/// `glRotate(deg, axis)` for an arbitrary axis (normalised here), right-handed:
/// counter-clockwise when looking down the axis towards the origin.
pub fn rotation(deg: f64, axis: [f64; 3]) -> Mat4 {
    let [x, y, z] = normalize(axis);
    let (s, c) = deg.to_radians().sin_cos();
    let t = 1.0 - c;
    [
        [x * x * t + c, x * y * t - z * s, x * z * t + y * s, 0.0],
        [y * x * t + z * s, y * y * t + c, y * z * t - x * s, 0.0],
        [x * z * t - y * s, y * z * t + x * s, z * z * t + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// The model matrix of an object: `T * Rz * Ry * Rx * S` (scale first, then the
/// rotation about x, y, z, then the translation), rotations in degrees as
/// `glRotate`.
pub fn model_matrix(obj: &ObjectDesc) -> Mat4 {
    let [rx, ry, rz] = obj.rotate_deg;
    let mut m = translation(obj.translate);
    m = mat_mul(&m, &rotation(rz, [0.0, 0.0, 1.0]));
    m = mat_mul(&m, &rotation(ry, [0.0, 1.0, 0.0]));
    m = mat_mul(&m, &rotation(rx, [1.0, 0.0, 0.0]));
    mat_mul(&m, &uniform_scale(obj.scale))
}

/// The view matrix `gluLookAt(eye, target, up)`: `f = normalize(target - eye)`,
/// `s = normalize(f × up)`, `u = s × f`, rows `s`, `u`, `-f`, then translation by
/// `-eye`.
pub fn view_matrix(cam: &CameraDesc) -> Mat4 {
    let f = normalize(sub(cam.target, cam.eye));
    let s = normalize(cross(f, cam.up));
    let u = cross(s, f);
    let e = cam.eye;
    [
        [s[0], s[1], s[2], -dot(s, e)],
        [u[0], u[1], u[2], -dot(u, e)],
        [-f[0], -f[1], -f[2], dot(f, e)],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// The projection matrix: `gluPerspective(fovy, aspect, near, far)`, or for
/// [`Projection::Orthographic`] with height `h`
/// `glOrtho(-h*aspect/2, h*aspect/2, -h/2, h/2, near, far)`. `aspect` is
/// width / height of the image.
pub fn projection_matrix(cam: &CameraDesc, aspect: f64) -> Mat4 {
    match cam.projection {
        Projection::Perspective {
            fovy_deg,
            near,
            far,
        } => {
            let f = 1.0 / (fovy_deg.to_radians() / 2.0).tan();
            [
                [f / aspect, 0.0, 0.0, 0.0],
                [0.0, f, 0.0, 0.0],
                [
                    0.0,
                    0.0,
                    (far + near) / (near - far),
                    2.0 * far * near / (near - far),
                ],
                [0.0, 0.0, -1.0, 0.0],
            ]
        }
        Projection::Orthographic { height, near, far } => {
            let (r, t) = (height * aspect / 2.0, height / 2.0);
            let (l, b) = (-r, -t);
            [
                [2.0 / (r - l), 0.0, 0.0, -(r + l) / (r - l)],
                [0.0, 2.0 / (t - b), 0.0, -(t + b) / (t - b)],
                [0.0, 0.0, -2.0 / (far - near), -(far + near) / (far - near)],
                [0.0, 0.0, 0.0, 1.0],
            ]
        }
    }
}

pub(crate) use crate::scene::mesh::vector::{add, cross, dot, sub};

/// Euclidean length.
pub(crate) fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or the zero vector when `a` is zero.
pub(crate) fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = length(a);
    if l > 0.0 {
        [a[0] / l, a[1] / l, a[2] / l]
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::desc::{MaterialDesc, MeshSource};

    fn assert_mat_close(a: &Mat4, b: &Mat4) {
        for i in 0..4 {
            for j in 0..4 {
                assert!(
                    (a[i][j] - b[i][j]).abs() < 1e-12,
                    "[{i}][{j}]: {} vs {}\n{a:?}\n{b:?}",
                    a[i][j],
                    b[i][j]
                );
            }
        }
    }

    fn cam(projection: Projection) -> CameraDesc {
        CameraDesc {
            eye: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            projection,
        }
    }

    #[test]
    fn look_at_from_positive_z_is_a_translation() {
        let c = cam(Projection::Orthographic {
            height: 2.0,
            near: 1.0,
            far: 10.0,
        });
        let mut want = IDENTITY;
        want[2][3] = -5.0;
        assert_mat_close(&view_matrix(&c), &want);
    }

    #[test]
    fn look_at_from_positive_x() {
        let c = CameraDesc {
            eye: [3.0, 0.0, 0.0],
            target: [0.0; 3],
            up: [0.0, 2.0, 0.0],
            projection: Projection::Orthographic {
                height: 2.0,
                near: 1.0,
                far: 10.0,
            },
        };
        // f = -x, s = f × y = -z, u = y.
        let want = [
            [0.0, 0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, -3.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        assert_mat_close(&view_matrix(&c), &want);
    }

    #[test]
    fn perspective_90_degrees() {
        let c = cam(Projection::Perspective {
            fovy_deg: 90.0,
            near: 1.0,
            far: 3.0,
        });
        let want = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, -2.0, -3.0],
            [0.0, 0.0, -1.0, 0.0],
        ];
        assert_mat_close(&projection_matrix(&c, 1.0), &want);
        // Aspect 2 halves the x scale.
        assert!((projection_matrix(&c, 2.0)[0][0] - 0.5).abs() < 1e-15);
        // The near plane maps to z_ndc = -1 and the far plane to +1.
        let p = projection_matrix(&c, 1.0);
        let n = mat_vec(&p, [0.0, 0.0, -1.0, 1.0]);
        let f = mat_vec(&p, [0.0, 0.0, -3.0, 1.0]);
        assert!((n[2] / n[3] + 1.0).abs() < 1e-15);
        assert!((f[2] / f[3] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn orthographic() {
        let c = cam(Projection::Orthographic {
            height: 4.0,
            near: 1.0,
            far: 9.0,
        });
        let want = [
            [0.25, 0.0, 0.0, 0.0],
            [0.0, 0.5, 0.0, 0.0],
            [0.0, 0.0, -0.25, -1.25],
            [0.0, 0.0, 0.0, 1.0],
        ];
        assert_mat_close(&projection_matrix(&c, 2.0), &want);
    }

    #[test]
    fn model_matrix_order_is_t_rz_ry_rx_s() {
        let obj = ObjectDesc {
            mesh: MeshSource::Robot,
            translate: [10.0, 20.0, 30.0],
            rotate_deg: [90.0, 0.0, 90.0],
            scale: 2.0,
            material: MaterialDesc::default(),
            material_from: Default::default(),
            back_material: None,
        };
        let m = model_matrix(&obj);
        // x: scale → (2,0,0); Rx keeps it; Rz(90) → (0,2,0); translate.
        let p = transform_point(&m, [1.0, 0.0, 0.0]);
        for (a, b) in p.iter().zip([10.0, 22.0, 30.0]) {
            assert!((a - b).abs() < 1e-12, "{p:?}");
        }
        // y: scale → (0,2,0); Rx(90) → (0,0,2); Rz keeps it.
        let p = transform_point(&m, [0.0, 1.0, 0.0]);
        for (a, b) in p.iter().zip([10.0, 20.0, 32.0]) {
            assert!((a - b).abs() < 1e-12, "{p:?}");
        }
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn normal_matrix_is_inverse_transpose() {
        let m = mat_mul(
            &rotation(30.0, [1.0, 2.0, 3.0]),
            &[
                [2.0, 0.0, 0.0, 5.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, -0.5, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ],
        );
        let n = normal_matrix(&m);
        // (N^T * M) restricted to 3x3 = I  <=>  N = M^-T.
        for i in 0..3 {
            for j in 0..3 {
                let v: f64 = (0..3).map(|k| n[k][i] * m[k][j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-12, "{i},{j}: {v}");
            }
        }
    }
}
