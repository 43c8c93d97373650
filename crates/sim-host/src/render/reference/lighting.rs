//! OpenGL 1.x fixed-function lighting in eye space, in f64.

use super::matrix::{add, dot, length, normalize, sub, transform_dir, transform_point, Mat4};
use crate::scene::desc::{LightKind, MaterialDesc, SceneDesc};

/// Where a light is, in eye space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EyeLightKind {
    /// Light at infinity.
    Directional {
        /// Unit vector from the surface towards the light, eye space (zero if the
        /// scene gave a zero direction).
        direction: [f64; 3],
    },
    /// Point light.
    Point {
        /// Position in eye space.
        position: [f64; 3],
        /// Constant, linear and quadratic attenuation.
        attenuation: [f64; 3],
    },
}

/// A light transformed to eye space, with its colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeLight {
    /// Directional or point, in eye space.
    pub kind: EyeLightKind,
    /// Ambient colour.
    pub ambient: [f64; 3],
    /// Diffuse colour.
    pub diffuse: [f64; 3],
    /// Specular colour.
    pub specular: [f64; 3],
}

/// Everything [`light_vertex`] needs besides the vertex and the material: the
/// lights in eye space, the global ambient light and the viewer model.
#[derive(Clone, Debug, PartialEq)]
pub struct LightingContext {
    /// The scene's lights, transformed to eye space.
    pub lights: Vec<EyeLight>,
    /// Global ambient light (`GL_LIGHT_MODEL_AMBIENT`).
    pub global_ambient: [f64; 3],
    /// Local viewer (`GL_LIGHT_MODEL_LOCAL_VIEWER`): `V = normalize(-P)` instead of
    /// `(0, 0, 1)`.
    pub local_viewer: bool,
}

impl LightingContext {
    /// Transforms the scene's world-space lights by `view` (positions by the full
    /// matrix, directions by its 3x3 part, then normalised) and copies the light
    /// model settings.
    pub fn new(scene: &SceneDesc, view: &Mat4) -> LightingContext {
        let lights = scene
            .lights
            .iter()
            .map(|l| EyeLight {
                kind: match l.kind {
                    LightKind::Directional { direction } => EyeLightKind::Directional {
                        direction: normalize(transform_dir(view, direction)),
                    },
                    LightKind::Point {
                        position,
                        attenuation,
                    } => EyeLightKind::Point {
                        position: transform_point(view, position),
                        attenuation,
                    },
                },
                ambient: l.ambient,
                diffuse: l.diffuse,
                specular: l.specular,
            })
            .collect();
        LightingContext {
            lights,
            global_ambient: scene.global_ambient,
            local_viewer: scene.local_viewer,
        }
    }
}

/// Lights one point: OpenGL 1.x fixed function (Blinn–Phong) in eye space.
///
/// `eye_pos` is the eye-space position P, `eye_normal` the eye-space normal N (it
/// need not be unit length: it is normalised here, as with `GL_NORMALIZE`). Per
/// channel the colour is
///
/// `emission + global_ambient*ka + Σ att * (la*ka + max(N·L,0)*ld*kd + spec*ls*ks)`
///
/// with `spec = max(N·H, 0)^shininess` when `N·L > 0` (else 0), `H = normalize(L + V)`
/// (no specular when `L + V` is zero), `V = normalize(-P)` for a local viewer and
/// `(0, 0, 1)` otherwise. Directional lights have `att = 1`; point lights
/// `L = normalize(Pl - P)` and `att = 1 / (c + l*d + q*d²)`, `d = |Pl - P|` (a
/// non-positive denominator makes the light contribute nothing). The result is
/// clamped to `[0, 1]` per channel.
pub fn light_vertex(
    ctx: &LightingContext,
    eye_pos: [f64; 3],
    eye_normal: [f64; 3],
    material: &MaterialDesc,
) -> [f64; 3] {
    let n = normalize(eye_normal);
    let v = if ctx.local_viewer {
        normalize([-eye_pos[0], -eye_pos[1], -eye_pos[2]])
    } else {
        [0.0, 0.0, 1.0]
    };
    let mut c: [f64; 3] =
        std::array::from_fn(|i| material.emission[i] + ctx.global_ambient[i] * material.ambient[i]);
    for light in &ctx.lights {
        let (l, att) = match light.kind {
            EyeLightKind::Directional { direction } => (direction, 1.0),
            EyeLightKind::Point {
                position,
                attenuation: [kc, kl, kq],
            } => {
                let to_light = sub(position, eye_pos);
                let d = length(to_light);
                let denom = kc + kl * d + kq * d * d;
                if denom <= 0.0 || denom.is_nan() {
                    continue;
                }
                (normalize(to_light), 1.0 / denom)
            }
        };
        let n_dot_l = dot(n, l);
        let diffuse = n_dot_l.max(0.0);
        let spec = if n_dot_l > 0.0 {
            let lv = add(l, v);
            if length(lv) == 0.0 {
                0.0
            } else {
                dot(n, normalize(lv)).max(0.0).powf(material.shininess)
            }
        } else {
            0.0
        };
        for (i, ci) in c.iter_mut().enumerate() {
            *ci += att
                * (light.ambient[i] * material.ambient[i]
                    + diffuse * light.diffuse[i] * material.diffuse[i]
                    + spec * light.specular[i] * material.specular[i]);
        }
    }
    c.map(|x| x.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directional(direction: [f64; 3], a: f64, d: f64, s: f64) -> EyeLight {
        EyeLight {
            kind: EyeLightKind::Directional {
                direction: normalize(direction),
            },
            ambient: [a; 3],
            diffuse: [d; 3],
            specular: [s; 3],
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    #[test]
    fn head_on_directional_light_sums_all_terms() {
        let ctx = LightingContext {
            lights: vec![EyeLight {
                kind: EyeLightKind::Directional {
                    direction: [0.0, 0.0, 1.0],
                },
                ambient: [0.1, 0.2, 0.3],
                diffuse: [0.5, 0.6, 0.7],
                specular: [0.9, 0.8, 0.7],
            }],
            global_ambient: [0.2, 0.2, 0.2],
            local_viewer: false,
        };
        let m = MaterialDesc {
            emission: [0.05, 0.0, 0.01],
            ambient: [0.5, 0.4, 0.3],
            diffuse: [0.6, 0.5, 0.4],
            specular: [0.3, 0.2, 0.9],
            shininess: 37.0,
        };
        // N = L = V = +z: N·L = N·H = 1.
        let c = light_vertex(&ctx, [0.0, 0.0, -4.0], [0.0, 0.0, 3.0], &m);
        let r = 0.05 + 0.2 * 0.5 + 0.1 * 0.5 + 0.5 * 0.6 + 0.9 * 0.3;
        let g = 0.0 + 0.2 * 0.4 + 0.2 * 0.4 + 0.6 * 0.5 + 0.8 * 0.2;
        let b = 0.01 + 0.2 * 0.3 + 0.3 * 0.3 + 0.7 * 0.4 + 0.7 * 0.9; // 1.07 → 1
        assert!(b > 1.0);
        assert!(close(c, [r, g, 1.0]), "{c:?}");
    }

    #[test]
    fn light_from_behind_gives_ambient_only() {
        let ctx = LightingContext {
            lights: vec![directional([0.0, 0.0, -1.0], 0.25, 1.0, 1.0)],
            global_ambient: [0.0; 3],
            local_viewer: false,
        };
        let m = MaterialDesc {
            specular: [1.0; 3],
            ..MaterialDesc::default()
        };
        let c = light_vertex(&ctx, [0.0; 3], [0.0, 0.0, 1.0], &m);
        assert!(close(c, [0.05; 3]), "{c:?}");
    }

    #[test]
    fn point_light_attenuation_and_local_viewer() {
        let ctx = LightingContext {
            lights: vec![EyeLight {
                kind: EyeLightKind::Point {
                    position: [0.0, 2.0, -2.0],
                    attenuation: [1.0, 0.5, 0.25],
                },
                ambient: [0.0; 3],
                diffuse: [1.0; 3],
                specular: [1.0; 3],
            }],
            global_ambient: [0.0; 3],
            local_viewer: true,
        };
        let m = MaterialDesc {
            emission: [0.0; 3],
            ambient: [0.0; 3],
            diffuse: [0.9; 3],
            specular: [0.6; 3],
            shininess: 1.0,
        };
        // P = (0,0,-2), N = +y: L = +y, d = 2, att = 1/3; V = +z;
        // H = normalize(0,1,1), N·H = 1/√2.
        let c = light_vertex(&ctx, [0.0, 0.0, -2.0], [0.0, 1.0, 0.0], &m);
        let want = (0.9 + 0.6 * std::f64::consts::FRAC_1_SQRT_2) / 3.0;
        assert!(close(c, [want; 3]), "{c:?} vs {want}");
    }

    #[test]
    fn context_transforms_lights_to_eye_space() {
        use crate::scene::desc::*;
        let scene = SceneDesc {
            width: 4,
            height: 4,
            format: FormatName::RGB888,
            background: [0; 3],
            camera: CameraDesc {
                eye: [0.0, 0.0, 5.0],
                target: [0.0; 3],
                up: [0.0, 1.0, 0.0],
                projection: Projection::Orthographic {
                    height: 2.0,
                    near: 1.0,
                    far: 10.0,
                },
            },
            lights: vec![
                LightDesc {
                    kind: LightKind::Directional {
                        direction: [0.0, 0.0, 7.0],
                    },
                    ambient: [0.0; 3],
                    diffuse: [1.0; 3],
                    specular: [0.0; 3],
                },
                LightDesc {
                    kind: LightKind::Point {
                        position: [1.0, 2.0, 3.0],
                        attenuation: [1.0, 0.0, 0.0],
                    },
                    ambient: [0.0; 3],
                    diffuse: [1.0; 3],
                    specular: [0.0; 3],
                },
            ],
            global_ambient: [0.2; 3],
            local_viewer: false,
            two_sided: false,
            objects: vec![],
            shading: ShadingName::GOURAUD,
            span: SpanName::CLASSIC,
            cull_back: false,
            depth_test: true,
            depth_bits: 16,
            perspective_correct: false,
            perspective_span: crate::scene::desc::DEFAULT_PERSPECTIVE_SPAN,
            specular: crate::scene::desc::SpecularName::EXACT,
            divide: crate::scene::desc::DivideName::EXACT,
            raycast: Default::default(),
            effects: Default::default(),
        };
        let view = super::super::matrix::view_matrix(&scene.camera);
        let ctx = LightingContext::new(&scene, &view);
        assert_eq!(
            ctx.lights[0].kind,
            EyeLightKind::Directional {
                direction: [0.0, 0.0, 1.0]
            }
        );
        assert_eq!(
            ctx.lights[1].kind,
            EyeLightKind::Point {
                position: [1.0, 2.0, -2.0],
                attenuation: [1.0, 0.0, 0.0]
            }
        );
    }
}
