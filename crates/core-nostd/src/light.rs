//! Lighting: OpenGL 1.x fixed-function Blinn lighting in eye space, evaluated per
//! vertex (Gouraud, flat) in fixed point.
//!
//! For each vertex with eye-space position `P` and unit normal `N`:
//!
//! ```text
//! colour = emission + global_ambient·ka
//!        + Σ att · ( la·ka + max(N·L, 0)·ld·kd + [N·L > 0]·max(N·H, 0)ⁿ·ls·ks )
//! ```
//!
//! clamped to [0, 1] per channel, with `H = normalize(L + V)`, `V = (0, 0, 1)` for an
//! infinite viewer or `normalize(-P)` for a local one, and `att = 1 / (c + l·d + q·d²)`
//! for point lights (1 for directional lights). Unit vectors are Q2.30, colours
//! Q16.16; the specular power goes through the [`Specular`] seam.
//!
//! ```
//! use fixshade::fixed::Q16_16;
//! use fixshade::light::{Light, Material};
//! let white = [Q16_16::ONE; 3];
//! let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
//! let mat = Material::default();
//! assert_eq!(mat.shininess, Q16_16::ONE);
//! # let _ = sun;
//! ```

use crate::fixed::Q16_16;
use crate::math::{dot_q30, normalize_to_q30, pow_q30, Mat4, Vec3, ONE_Q30};

/// An RGB colour, Q16.16 per channel, 0..=1 for inputs.
///
/// ```
/// use fixshade::light::Color;
/// use fixshade::prelude::rgb;
/// let orange: Color = rgb(255, 128, 0);
/// assert_eq!(orange[0].to_bits(), 1 << 16); // 255 is 1.0
/// ```
pub type Color = [Q16_16; 3];

/// The kind of a light; positions and directions are given in world space and
/// transformed to eye space by the view matrix once per frame.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{Light, LightKind};
/// let q = Q16_16::from_int;
/// let mut lamp = Light::directional([q(0), q(1), q(0)], [Q16_16::ONE; 3], [Q16_16::ONE; 3]);
/// // A bulb at (0, 2, 0) whose light halves at distance 1: 1 / (1 + d).
/// lamp.kind = LightKind::Point {
///     position: [q(0), q(2), q(0)],
///     attenuation: [Q16_16::ONE, Q16_16::ONE, Q16_16::ZERO],
/// };
/// assert!(matches!(lamp.kind, LightKind::Point { .. }));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum LightKind {
    /// At infinity; `direction` points from the surface towards the light.
    Directional {
        /// Direction towards the light (any non-zero length).
        direction: Vec3,
    },
    /// A point light with attenuation `1 / (c + l·d + q·d²)`.
    Point {
        /// Position in world space.
        position: Vec3,
        /// `[c, l, q]`, all ≥ 0 and not all zero.
        attenuation: [Q16_16; 3],
    },
}

/// An OpenGL fixed-function light.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::Light;
/// use fixshade::prelude::rgb;
/// // A warm sun from the upper right, no specular part, a little ambient.
/// let mut sun = Light::directional(
///     [Q16_16::ONE, Q16_16::ONE, Q16_16::ZERO],
///     rgb(255, 240, 220),
///     rgb(0, 0, 0),
/// );
/// sun.ambient = rgb(20, 20, 20);
/// assert_eq!(sun.specular, [Q16_16::ZERO; 3]);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Light {
    /// Directional or point.
    pub kind: LightKind,
    /// Ambient colour.
    pub ambient: Color,
    /// Diffuse colour.
    pub diffuse: Color,
    /// Specular colour.
    pub specular: Color,
}

impl Light {
    /// A directional light with no ambient part.
    pub fn directional(direction: Vec3, diffuse: Color, specular: Color) -> Light {
        Light {
            kind: LightKind::Directional { direction },
            ambient: [Q16_16::ZERO; 3],
            diffuse,
            specular,
        }
    }
}

/// An OpenGL fixed-function material.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::Material;
/// use fixshade::prelude::rgb;
/// let gold = Material {
///     diffuse: rgb(200, 160, 60),
///     specular: rgb(255, 240, 200),
///     shininess: Q16_16::from_int(40),
///     ..Material::default()
/// };
/// assert_eq!(gold.ambient, Material::default().ambient);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Material {
    /// Emission.
    pub emission: Color,
    /// Ambient reflectance.
    pub ambient: Color,
    /// Diffuse reflectance.
    pub diffuse: Color,
    /// Specular reflectance.
    pub specular: Color,
    /// Blinn exponent n, 1..=1000 (values outside are clamped when lighting).
    pub shininess: Q16_16,
}

impl Default for Material {
    /// OpenGL's defaults: ambient 0.2, diffuse 0.8, no specular, n = 1.
    fn default() -> Self {
        let g = |n: i32| [Q16_16::from_ratio(n, 10); 3];
        Material {
            emission: [Q16_16::ZERO; 3],
            ambient: g(2),
            diffuse: g(8),
            specular: [Q16_16::ZERO; 3],
            shininess: Q16_16::ONE,
        }
    }
}

/// The specular seam: how `cⁿ` (c = N·H) is evaluated.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{BlinnExact, Specular};
/// use fixshade::specular::Schlick;
/// let c = 0x3800_0000; // N·H = 0.875 in Q2.30
/// let n = Q16_16::from_int(8);
/// let exact = BlinnExact::eval(&BlinnExact::prepare(n), c); // 0.875⁸ ≈ 0.344
/// let approx = <Schlick>::eval(&<Schlick>::prepare(n), c); // c / (n − n·c + c) ≈ 0.467
/// assert!((exact - 368947264).abs() < 1 << 8);
/// assert!(approx > exact);
/// ```
pub trait Specular {
    /// Per-material data derived from n once per frame (a table lookup, a reciprocal).
    type Params: Copy;
    /// Prepares the parameters for exponent `n` (already clamped to 1..=1000).
    fn prepare(n: Q16_16) -> Self::Params;
    /// `cⁿ` or its approximation for `c` in Q2.30 (0 < c ≤ 1), result Q2.30 in [0, 1].
    fn eval(p: &Self::Params, c: i32) -> i32;
    /// The value lighting uses, in Q.30 as `u64`: [`Specular::eval`] for every model
    /// whose result stays in [0, 1]; a model that may exceed 1 (the energy-conserving
    /// form peaks near 41) overrides it with its unsaturated value, at most 2³⁶.
    #[inline]
    fn eval_wide(p: &Self::Params, c: i32) -> u64 {
        Self::eval(p, c).max(0) as u64
    }
}

/// Exact `cⁿ` (see [`pow_q30`]).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{BlinnExact, Specular};
/// let p = BlinnExact::prepare(Q16_16::from_int(2));
/// assert_eq!(BlinnExact::eval(&p, 1 << 29), 1 << 28); // 0.5² = 0.25
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct BlinnExact;

impl Specular for BlinnExact {
    type Params = Q16_16;
    fn prepare(n: Q16_16) -> Q16_16 {
        n
    }
    #[inline]
    fn eval(n: &Q16_16, c: i32) -> i32 {
        pow_q30(c, *n)
    }
}

/// A light transformed to eye space with the material's products folded in.
#[derive(Copy, Clone, Debug)]
enum EyeKind {
    Directional {
        /// Unit direction towards the light, Q2.30.
        l: [i32; 3],
        /// Half vector for the infinite viewer, Q2.30 (None: L + V = 0).
        h: Option<[i32; 3]>,
    },
    Point {
        /// Eye-space position, Q16.16.
        pos: [i32; 3],
        /// Attenuation factors, Q16.16.
        att: [Q16_16; 3],
    },
}

#[derive(Copy, Clone, Debug)]
struct EyeLight {
    kind: EyeKind,
    /// la·ka, ld·kd, ls·ks per channel, Q16.16.
    amb: [i64; 3],
    dif: [i64; 3],
    spec: [i64; 3],
    has_spec: bool,
}

/// Maximum number of lights.
pub const MAX_LIGHTS: usize = 8;

/// Everything the per-vertex lighting needs for one object in one frame.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{BlinnExact, Light, LightingSetup, Material};
/// use fixshade::math::{Mat4, ONE_Q30};
/// let white = [Q16_16::ONE; 3];
/// let light = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
/// let setup: LightingSetup<BlinnExact> =
///     LightingSetup::new(&[light], &Mat4::IDENTITY, &Material::default(), [Q16_16::ZERO; 3], false);
/// // A surface facing the light gets the default diffuse 0.8 (Q16.16) per channel.
/// let c = setup.shade([0, 0, 0], [0, 0, ONE_Q30]);
/// assert!((c[0] - 52_429).abs() <= 2);
/// // Facing away: nothing (no ambient in this light or scene).
/// assert_eq!(setup.shade([0, 0, 0], [0, 0, -ONE_Q30]), [0, 0, 0]);
/// ```
#[derive(Clone, Debug)]
pub struct LightingSetup<S: Specular> {
    lights: heapless::Vec<EyeLight, MAX_LIGHTS>,
    /// emission + global_ambient·ka, Q16.16.
    base: [i64; 3],
    local_viewer: bool,
    spec: S::Params,
}

fn mul_q16(a: Q16_16, b: Q16_16) -> i64 {
    (a.to_bits() as i64 * b.to_bits() as i64 + (1 << 15)) >> 16
}

impl<S: Specular> LightingSetup<S> {
    /// Transforms `lights` by `view` and folds in `material`.
    pub fn new(
        lights: &[Light],
        view: &Mat4,
        material: &Material,
        global_ambient: Color,
        local_viewer: bool,
    ) -> LightingSetup<S> {
        let mut out = heapless::Vec::new();
        for light in lights.iter().take(MAX_LIGHTS) {
            let kind = match light.kind {
                LightKind::Directional { direction } => {
                    let d = view.transform_dir(direction);
                    let l = normalize_to_q30(d).unwrap_or([0, 0, ONE_Q30]);
                    let h =
                        normalize_to_q30([l[0] as i64, l[1] as i64, l[2] as i64 + ONE_Q30 as i64]);
                    EyeKind::Directional { l, h }
                }
                LightKind::Point {
                    position,
                    attenuation,
                } => {
                    let p = view.transform_point(position);
                    let pos = p.map(|v| crate::fixed::sat_i64_to_i32((v + (1 << 15)) >> 16));
                    EyeKind::Point {
                        pos,
                        att: attenuation,
                    }
                }
            };
            let prod = |a: &Color, b: &Color| {
                [
                    mul_q16(a[0], b[0]),
                    mul_q16(a[1], b[1]),
                    mul_q16(a[2], b[2]),
                ]
            };
            let spec = prod(&light.specular, &material.specular);
            // Cannot overflow: MAX_LIGHTS entries and `out` has that capacity.
            let _ = out.push(EyeLight {
                kind,
                amb: prod(&light.ambient, &material.ambient),
                dif: prod(&light.diffuse, &material.diffuse),
                has_spec: spec.iter().any(|v| *v != 0),
                spec,
            });
        }
        let base = core::array::from_fn(|i| {
            material.emission[i].to_bits() as i64 + mul_q16(global_ambient[i], material.ambient[i])
        });
        let n = material
            .shininess
            .clamp(Q16_16::ONE, Q16_16::from_int(1000));
        LightingSetup {
            lights: out,
            base,
            local_viewer,
            spec: S::prepare(n),
        }
    }

    /// The lit colour of a vertex: eye-space position `p` (Q16.16) and unit normal
    /// `n` (Q2.30). Returns Q16.16 channels clamped to [0, 1].
    ///
    /// Bounds: every term is a product of factors ≤ 1 (dot products, colours) and
    /// an attenuation ≤ 2¹⁵, so each is below 2³¹ in Q16.16 and the i64 sums of at
    /// most 8 lights cannot overflow.
    pub fn shade(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        let mut acc = self.base;
        let view = if self.local_viewer {
            normalize_to_q30([-(p[0] as i64), -(p[1] as i64), -(p[2] as i64)])
                .unwrap_or([0, 0, ONE_Q30])
        } else {
            [0, 0, ONE_Q30]
        };
        for light in &self.lights {
            let (l, att, h) = match light.kind {
                EyeKind::Directional { l, h } => {
                    let h = if self.local_viewer { half(l, view) } else { h };
                    (l, 1i64 << 16, h)
                }
                EyeKind::Point { pos, att } => {
                    let d = [
                        pos[0] as i64 - p[0] as i64,
                        pos[1] as i64 - p[1] as i64,
                        pos[2] as i64 - p[2] as i64,
                    ];
                    let Some(l) = normalize_to_q30(d) else {
                        continue;
                    };
                    let a = attenuation(d, att);
                    (l, a, half(l, view))
                }
            };
            for (c, amb) in acc.iter_mut().zip(light.amb.iter()) {
                *c += (amb * att) >> 16;
            }
            let nl = dot_q30(n, l);
            if nl <= 0 {
                continue;
            }
            // att·(N·L): Q16.16 · Q2.30 → Q16.16.
            let f = (att * nl as i64) >> 30;
            for (c, dif) in acc.iter_mut().zip(light.dif.iter()) {
                *c += (dif * f) >> 16;
            }
            if !light.has_spec {
                continue;
            }
            let Some(h) = h else { continue };
            let nh = dot_q30(n, h);
            if nh <= 0 {
                continue;
            }
            let s = S::eval_wide(&self.spec, nh.min(ONE_Q30));
            // att ≤ 2^31 (Q16.16) and s ≤ 2^36 (Q.30): the product needs i128 only
            // for a point light; a directional light's att is exactly 2^16.
            let f = if att == 1 << 16 {
                (s >> 14) as i64
            } else {
                ((att as i128 * s as i128) >> 30) as i64
            };
            for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
                *c += (sp * f) >> 16;
            }
        }
        acc.map(|c| c.clamp(0, 1 << 16) as i32)
    }
}

impl<S: Specular> crate::raster::phong::PixelLight for LightingSetup<S> {
    #[inline]
    fn light(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        self.shade(p, n)
    }
}

fn half(l: [i32; 3], v: [i32; 3]) -> Option<[i32; 3]> {
    normalize_to_q30([
        l[0] as i64 + v[0] as i64,
        l[1] as i64 + v[1] as i64,
        l[2] as i64 + v[2] as i64,
    ])
}

/// `1 / (c + l·d + q·d²)` in Q16.16 for the Q16.16 offset `d` (saturating at 2¹⁵).
fn attenuation(d: [i64; 3], att: [Q16_16; 3]) -> i64 {
    // |d| components < 2^32 raw: squares < 2^64, so sum in u128.
    let sq: u128 = d.iter().map(|c| (*c as i128 * *c as i128) as u128).sum();
    let dist = crate::math::isqrt_u128(sq) as i128; // Q16.16
    let (c, l, q) = (
        att[0].to_bits() as i128,
        att[1].to_bits() as i128,
        att[2].to_bits() as i128,
    );
    // Denominator in Q.32: c·2^16 + l·d + q·d²/2^16.
    let den = (c << 16) + l * dist + ((q * dist * dist) >> 16);
    if den <= 0 {
        return 1 << 31;
    }
    ((1i128 << 48) / den).min(1 << 31) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(v: i32, d: i32) -> Q16_16 {
        Q16_16::from_ratio(v, d)
    }

    #[test]
    fn head_on_light_sums_all_terms() {
        let white = [Q16_16::ONE; 3];
        let light = Light {
            kind: LightKind::Directional {
                direction: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE],
            },
            ambient: [q(1, 10); 3],
            diffuse: white,
            specular: white,
        };
        let mat = Material {
            emission: [q(1, 20); 3],
            ambient: [q(1, 5); 3],
            diffuse: [q(1, 2); 3],
            specular: [q(1, 4); 3],
            shininess: Q16_16::from_int(50),
        };
        let setup =
            LightingSetup::<BlinnExact>::new(&[light], &Mat4::IDENTITY, &mat, [q(1, 5); 3], false);
        let c = setup.shade([0, 0, 0], [0, 0, ONE_Q30]);
        // 0.05 + 0.2·0.2 + 0.1·0.2 + 0.5 + 0.25 = 0.86
        let want = 0.86 * 65536.0;
        for ch in c {
            assert!((ch as f64 - want).abs() < 3.0, "{ch} vs {want}");
        }
    }

    #[test]
    fn light_behind_surface_gives_ambient_only() {
        let white = [Q16_16::ONE; 3];
        let light = Light::directional([Q16_16::ZERO, Q16_16::ZERO, -Q16_16::ONE], white, white);
        let mat = Material {
            specular: white,
            ..Material::default()
        };
        let setup = LightingSetup::<BlinnExact>::new(
            &[light],
            &Mat4::IDENTITY,
            &mat,
            [Q16_16::ZERO; 3],
            true,
        );
        assert_eq!(setup.shade([0, 0, -(3 << 16)], [0, 0, ONE_Q30]), [0, 0, 0]);
    }

    #[test]
    fn point_light_attenuates() {
        let d = [0i64, 0, 2 << 16]; // distance 2
        let a = attenuation(d, [Q16_16::ONE, Q16_16::ZERO, Q16_16::ONE]); // 1/(1+4)
        assert!((a - 65536 / 5).abs() <= 1, "{a}");
    }
}
