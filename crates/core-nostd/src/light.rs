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

use crate::fixed::{Q16_16, Q2_14};
use crate::math::{dot_q30, mul_wide, normalize_to_q30, Mat4, Vec3, ONE_Q30};
pub use crate::specular::{BlinnExact, Specular};

/// An RGB colour, Q16.16 per channel, 0..=1 for inputs.
///
/// ```
/// use fixshade::light::Color;
/// use fixshade::prelude::rgb;
/// let orange: Color = rgb(255, 128, 0);
/// assert_eq!(orange[0].to_bits(), 1 << 16); // 255 is 1.0
/// ```
pub type Color = [Q16_16; 3];

/// An RGB colour from 8-bit channels (`v / 255` in Q16.16, rounded to nearest).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::rgb;
/// assert_eq!(rgb(255, 0, 51), [Q16_16::ONE, Q16_16::ZERO, Q16_16::from_ratio(1, 5)]);
/// ```
pub const fn rgb(r: u8, g: u8, b: u8) -> Color {
    [
        Q16_16::from_ratio(r as i32, 255),
        Q16_16::from_ratio(g as i32, 255),
        Q16_16::from_ratio(b as i32, 255),
    ]
}

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
    /// la·ka, ld·kd, ls·ks per channel, Q16.16 (saturated to `i32`).
    amb: [i32; 3],
    dif: [i32; 3],
    spec: [i32; 3],
    /// The light adds a specular term: `spec` is not zero and `S::enabled()`.
    has_spec: bool,
}

/// Maximum number of lights.
pub const MAX_LIGHTS: usize = 8;

/// Everything the per-vertex lighting needs for one object in one frame.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::light::{Light, LightingSetup, Material};
/// use fixshade::specular::BlinnExact;
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
    /// The directional lights first, then the point lights (see [`Self::shade`]).
    lights: heapless::Vec<EyeLight, MAX_LIGHTS>,
    /// How many of `lights` are directional.
    directional: usize,
    /// emission + global_ambient·ka, Q16.16.
    base: [i64; 3],
    /// A local viewer for a specular term (false without one: `S::enabled()`).
    local_viewer: bool,
    spec: S::Params,
    /// Directional lights only, every colour product in [0, 1) and the base in
    /// [0, 16] (Q16.16): [`Self::shade`] sums in `i32` with 32-bit products
    /// ([`Self::shade_directional`]).
    unit: bool,
}

/// The three sums of a lit colour (Q16.16 before the clamp): `i32` where the
/// setup's bounds allow ([`LightingSetup::unit`]: below 2²⁶), `i64` otherwise.
/// The directional-light loop ([`LightingSetup::shade_directional`]) is written
/// once over both.
trait Sums: Copy {
    /// The sums of the base (emission + global ambient, Q16.16).
    fn base(b: &[i64; 3]) -> Self;
    /// Adds the ambient parts `c` (Q16.16).
    fn add(&mut self, c: &[i32; 3]);
    /// Adds `⌊c·f/2¹⁶⌋` to each sum for the colour products `c` and a factor `f`
    /// in [0, 2³¹).
    fn add_terms(&mut self, c: &[i32; 3], f: i32);
    /// The channels clamped to [0, 1].
    fn clamped(self) -> [i32; 3];
}

impl Sums for [i64; 3] {
    #[inline(always)]
    fn base(b: &[i64; 3]) -> Self {
        *b
    }
    #[inline(always)]
    fn add(&mut self, c: &[i32; 3]) {
        for (a, c) in self.iter_mut().zip(c) {
            *a += *c as i64;
        }
    }
    /// `|c|` < 2³¹ and `f` < 2³¹: `mul_wide` below 2⁶², each term below 2⁴⁶.
    #[inline(always)]
    fn add_terms(&mut self, c: &[i32; 3], f: i32) {
        for (a, c) in self.iter_mut().zip(c) {
            *a += mul_wide(*c, f) >> 16;
        }
    }
    #[inline(always)]
    fn clamped(self) -> [i32; 3] {
        self.map(|c| c.clamp(0, 1 << 16) as i32)
    }
}

impl Sums for [i32; 3] {
    /// A base in [0, 2²⁰] (the `unit` condition).
    #[inline(always)]
    fn base(b: &[i64; 3]) -> Self {
        b.map(|b| b as i32)
    }
    #[inline(always)]
    fn add(&mut self, c: &[i32; 3]) {
        for (a, c) in self.iter_mut().zip(c) {
            *a += *c;
        }
    }
    /// For the colour products `c` in [0, 2¹⁶): [`mul_wide`]'s values, from one
    /// 32-bit multiply each for the usual factor, at most 2¹⁶ (a diffuse factor of
    /// unit vectors, which lie within 4 units of Q2.30, so `N·L` ≤ 2³⁰ + 14; a
    /// specular model up to 1), where `c·f` < 2³² as `u32`; a larger factor takes
    /// `mul_wide` (on ARMv6-M four 16×16-bit products each).
    #[inline(always)]
    fn add_terms(&mut self, c: &[i32; 3], f: i32) {
        if f <= 1 << 16 {
            for (a, c) in self.iter_mut().zip(c) {
                *a += ((*c as u32).wrapping_mul(f as u32) >> 16) as i32;
            }
        } else {
            for (a, c) in self.iter_mut().zip(c) {
                *a += (mul_wide(*c, f) >> 16) as i32;
            }
        }
    }
    #[inline(always)]
    fn clamped(self) -> [i32; 3] {
        self.map(|c| c.clamp(0, 1 << 16))
    }
}

fn mul_q16(a: Q16_16, b: Q16_16) -> i32 {
    (a * b).to_bits()
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
        // Directional lights first: `shade` walks them in a loop of their own. The
        // order of the lights does not change a colour (exact integer sums).
        let lights = lights.iter().take(MAX_LIGHTS);
        let directional = lights
            .clone()
            .filter(|l| matches!(l.kind, LightKind::Directional { .. }))
            .count();
        let (dirs, points) = (lights.clone(), lights);
        let ordered = dirs
            .filter(|l| matches!(l.kind, LightKind::Directional { .. }))
            .chain(points.filter(|l| matches!(l.kind, LightKind::Point { .. })));
        for light in ordered {
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
                // Folded once here: the per-pixel tests read this flag and the
                // constant `S::ENABLED`, never `S::enabled()`.
                has_spec: S::enabled() && spec.iter().any(|v| *v != 0),
                spec,
            });
        }
        let base = core::array::from_fn(|i| {
            material.emission[i].to_bits() as i64
                + mul_q16(global_ambient[i], material.ambient[i]) as i64
        });
        let n = material
            .shininess
            .clamp(Q16_16::ONE, Q16_16::from_int(1000));
        let below_one = |c: &[i32; 3]| c.iter().all(|v| (0..1 << 16).contains(v));
        let unit = directional == out.len()
            && base.iter().all(|b| (0..=1 << 20).contains(b))
            && out
                .iter()
                .all(|l| below_one(&l.amb) && below_one(&l.dif) && below_one(&l.spec));
        LightingSetup {
            lights: out,
            directional,
            base,
            unit,
            // Without a specular term the viewer is never needed.
            local_viewer: local_viewer && S::enabled(),
            spec: S::prepare(n),
        }
    }

    /// Whether [`Self::shade`] reads the eye-space position: for point lights, and
    /// for a local viewer's half vector. Without either, the vertex stage skips
    /// computing it.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::light::{Light, LightingSetup, Material};
    /// use fixshade::specular::BlinnExact;
    /// use fixshade::math::Mat4;
    /// let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], [Q16_16::ONE; 3], [Q16_16::ONE; 3]);
    /// let at = |local| LightingSetup::<BlinnExact>::new(&[sun], &Mat4::IDENTITY, &Material::default(), [Q16_16::ZERO; 3], local);
    /// assert!(!at(false).needs_position() && at(true).needs_position());
    /// ```
    pub fn needs_position(&self) -> bool {
        self.directional < self.lights.len() || (S::ENABLED && self.local_viewer)
    }

    /// The lit colour of a vertex: eye-space position `p` (Q16.16) and unit normal
    /// `n` (Q2.30). Returns Q16.16 channels clamped to [0, 1].
    ///
    /// Bounds: every term is a product of factors ≤ 1 (dot products, colours) and
    /// an attenuation ≤ 2¹⁵, so each is below 2³¹ in Q16.16 and the i64 sums of at
    /// most 8 lights cannot overflow.
    #[inline]
    pub fn shade(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        // Not in the smallest images (`small-flash`: the micro:bit's 256 KiB),
        // which keep one copy: the same bits either way.
        if !cfg!(feature = "small-flash") && self.unit {
            return self.shade_directional::<[i32; 3]>(p, n);
        }
        // Inlined into the caller, so a diffuse-only directional scene makes one
        // call, as a hand-written loop does.
        if !S::enabled() && self.directional >= self.lights.len() {
            return self.diffuse_directional(n);
        }
        self.shade_any(p, n)
    }

    /// [`Self::shade_any`] for directional lights only, summed in `A`: `i32` for
    /// lights whose colour products lie in [0, 1) and a base in [0, 16] (Q16.16;
    /// `unit`), `i64` for any. In `i32` a factor is below 2²² (specular: `s` ≤
    /// 2³⁶; diffuse: `N·L` saturates at 2³¹, so `N·L >> 14` < 2¹⁷), so the sum of
    /// the base and at most 8 lights' three terms (ambient below 2¹⁶, diffuse
    /// below 2¹⁷, specular below 2²²) stays below 2²⁶.
    #[inline(always)]
    fn shade_directional<A: Sums>(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        let mut acc = A::base(&self.base);
        let view = self.view(p);
        for light in &self.lights {
            let EyeKind::Directional { l, h } = light.kind else {
                continue;
            };
            acc.add(&light.amb);
            let nl = dot_q30(n, l);
            if nl <= 0 {
                continue;
            }
            // As in `add_light` with attenuation exactly 1.
            acc.add_terms(&light.dif, nl >> 14);
            if !S::ENABLED || !light.has_spec {
                continue;
            }
            let h = if self.local_viewer { half(l, view) } else { h };
            let Some(h) = h else { continue };
            let nh = dot_q30(n, h);
            if nh <= 0 {
                continue;
            }
            // s ≤ 2^36: f < 2^22.
            acc.add_terms(
                &light.spec,
                (S::eval_wide(&self.spec, nh.min(ONE_Q30)) >> 14) as i32,
            );
        }
        acc.clamped()
    }

    /// The unit vector towards the viewer at eye-space `p` for the half vector:
    /// from `p` with a local viewer and a specular term, else +z.
    #[inline(always)]
    fn view(&self, p: [i32; 3]) -> [i32; 3] {
        if S::ENABLED && self.local_viewer {
            normalize_to_q30([-(p[0] as i64), -(p[1] as i64), -(p[2] as i64)])
                .unwrap_or([0, 0, ONE_Q30])
        } else {
            [0, 0, ONE_Q30]
        }
    }

    /// [`Self::shade`] for any lights and specular term.
    fn shade_any(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        let mut acc = self.base;
        // The viewer direction enters the half vector only: without a specular term
        // it is never needed.
        let view = self.view(p);
        let (dirs, points) = self
            .lights
            .split_at(self.directional.min(self.lights.len()));
        // Directional lights in a loop of their own: no distance, no attenuation.
        for light in dirs {
            let EyeKind::Directional { l, h } = light.kind else {
                continue;
            };
            let h = || if self.local_viewer { half(l, view) } else { h };
            self.add_light(&mut acc, light, n, l, None, h);
        }
        for light in points {
            let EyeKind::Point { pos, att } = light.kind else {
                continue;
            };
            let d = [
                pos[0] as i64 - p[0] as i64,
                pos[1] as i64 - p[1] as i64,
                pos[2] as i64 - p[2] as i64,
            ];
            let Some(l) = normalize_to_q30(d) else {
                continue;
            };
            let a = attenuation(d, att);
            self.add_light(&mut acc, light, n, l, Some(a), || half(l, view));
        }
        acc.map(|c| c.clamp(0, 1 << 16) as i32)
    }

    /// [`Self::shade`] without a specular term and with directional lights only
    /// (the same sums in the same order, in `i64`): out of line, a loop with no
    /// call and no register to save, what a hand-written diffuse path does.
    #[inline(never)]
    fn diffuse_directional(&self, n: [i32; 3]) -> [i32; 3] {
        self.shade_directional::<[i64; 3]>([0; 3], n)
    }

    /// Adds one light's ambient, diffuse and specular terms to `acc`: unit normal
    /// `n` and direction to the light `l` (Q2.30), attenuation `att` (Q16.16;
    /// `None` for a directional light, exactly 1), the half vector computed only
    /// when the specular term is needed.
    #[inline(always)]
    fn add_light(
        &self,
        acc: &mut [i64; 3],
        light: &EyeLight,
        n: [i32; 3],
        l: [i32; 3],
        att: Option<i32>,
        h: impl FnOnce() -> Option<[i32; 3]>,
    ) {
        // `att` None: attenuation exactly 1 (2¹⁶ in Q16.16); its products are
        // skipped, with the same values ((x·2¹⁶) >> 16 = x, (2¹⁶·y) >> 30 = y >> 14).
        // Otherwise att < 2³¹ (Q16.16), so every product below is a `mul_wide`.
        match att {
            None => {
                for (c, amb) in acc.iter_mut().zip(light.amb.iter()) {
                    *c += *amb as i64;
                }
            }
            Some(a) => {
                for (c, amb) in acc.iter_mut().zip(light.amb.iter()) {
                    *c += mul_wide(*amb, a) >> 16;
                }
            }
        }
        let nl = dot_q30(n, l);
        if nl <= 0 {
            return;
        }
        // att·(N·L): Q16.16 · Q2.30 → Q16.16, below 2³¹.
        let f = match att {
            None => nl >> 14,
            Some(a) => (mul_wide(a, nl) >> 30) as i32,
        };
        for (c, dif) in acc.iter_mut().zip(light.dif.iter()) {
            *c += mul_wide(*dif, f) >> 16;
        }
        if !S::ENABLED || !light.has_spec {
            return;
        }
        let Some(h) = h() else { return };
        let nh = dot_q30(n, h);
        if nh <= 0 {
            return;
        }
        let s = S::eval_wide(&self.spec, nh.min(ONE_Q30));
        // s ≤ 2^36 (Q.30): for a directional light (att exactly 2^16) s >> 14 < 2^22;
        // for a point light att·s/2^30 = att·⌊s/2^30⌋ + att·(s mod 2^30)/2^30, each
        // part a `mul_wide`, the sum below 2^37.
        let f = match att {
            None => s >> 14,
            Some(a) => {
                let (hi, lo) = ((s >> 30) as i32, (s & ((1 << 30) - 1)) as i32);
                ((mul_wide(a, hi) << 30) + mul_wide(a, lo)) as u64 >> 30
            }
        };
        // A factor above 2^31 (only the energy-conserving model under a strong point
        // light) is split the same way.
        for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
            *c += if f < 1 << 31 {
                mul_wide(*sp, f as i32) >> 16
            } else {
                (mul_wide(*sp, (f >> 16) as i32)) + (mul_wide(*sp, (f & 0xFFFF) as i32) >> 16)
            };
        }
    }
}

/// `⌊c·f/2¹⁵⌋` for any `c` and `0 ≤ f ≤ 2¹⁵` (the result fits `i32`): one `SMULL`
/// on ARMv7-M; on ARMv6-M two 16×16-bit products, `c = ch·2¹⁶ + cl` with `ch`
/// signed and `cl` unsigned: `2·ch·f + ⌊cl·f/2¹⁵⌋` (|2·ch·f| ≤ 2³¹ … exactly
/// `−2³¹` at the extreme, `cl·f` < 2³¹). Both give the same bits (tested).
#[inline(always)]
fn scale_q15(c: i32, f: i32) -> i32 {
    debug_assert!((0..=1 << 15).contains(&f));
    #[cfg(fixshade_v6m)]
    {
        scale_q15_split(c, f)
    }
    #[cfg(not(fixshade_v6m))]
    {
        ((c as i64 * f as i64) >> 15) as i32
    }
}

/// [`scale_q15`] from two 16×16-bit products.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
fn scale_q15_split(c: i32, f: i32) -> i32 {
    2 * ((c >> 16) * f) + (((c & 0xFFFF) * f) >> 15)
}

/// A Q2.30 unit vector rounded to Q1.15 (components within ±2¹⁵).
fn to_q15(v: [i32; 3]) -> [i32; 3] {
    v.map(|c| (c + (1 << 14)) >> 15)
}

/// Transforms an eye-space direction back to the object's space by the transpose
/// of the model-view's linear part (a rotation times the uniform scale, whose sign
/// it keeps): Q2.30 unit vector, `None` for the zero vector.
fn to_object(mv: &Mat4, d: [i32; 3]) -> Option<[i32; 3]> {
    // Q32.32 · Q2.30 = Q62, three terms < 2^126 in i128; shifted together into i64.
    let v: [i128; 3] =
        core::array::from_fn(|c| (0..3).map(|r| mv.m[r][c] as i128 * d[r] as i128).sum());
    let max = v.iter().fold(0u128, |m, c| m | c.unsigned_abs());
    let shift = (128 - max.leading_zeros() as i32 - 62).max(0);
    normalize_to_q30(v.map(|c| (c >> shift) as i64))
}

/// The unit normal for lighting from a Q2.14 mesh normal: the normal itself (Q2.14
/// in `i32`) and `e = |n|² − 2²⁸` (Q28), which [`ndot`] corrects the dot products
/// by; a normal whose length is off by 2⁻⁸ or more is normalised first (exactly,
/// [`normalize_to_q30`], rounded to Q2.14), a zero normal replaced by `zero`.
///
/// Bounds: |components| ≤ 2¹⁵, so each square ≤ 2³⁰ and their sum ≤ 3·2³⁰ fits
/// `u32`.
#[inline(always)]
fn unit_normal(n: &[Q2_14; 3], zero: ([i32; 3], i32)) -> ([i32; 3], i32) {
    let v = n.map(|c| c.to_bits() as i32);
    let sq = (v[0] * v[0]) as u32 + (v[1] * v[1]) as u32 + (v[2] * v[2]) as u32;
    let e = sq.wrapping_sub(1 << 28) as i32;
    if e.unsigned_abs() < 1 << 20 {
        return (v, e);
    }
    match normalize_to_q30(v.map(|c| c as i64)) {
        Some(u) => {
            let r = u.map(|c| (c + (1 << 15)) >> 16);
            let sq = (r[0] * r[0]) as u32 + (r[1] * r[1]) as u32 + (r[2] * r[2]) as u32;
            (r, sq.wrapping_sub(1 << 28) as i32)
        }
        None => zero,
    }
}

/// `n·l/|n|` for a normal from [`unit_normal`] (Q2.14, `|n|² = 2²⁸ + e` with
/// |e| < 2²⁰) and a Q1.15 unit vector: Q29. The dot product (each term ≤ 2³⁰, the
/// sum below |n|·|l| ≤ 2²⁹·1.002) times `1 − e/2²⁹`, the first-order inverse
/// length (its error (3/8)·(e/2²⁸)² is below 2⁻¹⁷; for a rounded unit normal,
/// |e/2²⁸| ≲ 2⁻¹², below 2⁻²⁶): the correction from `(dot >> 17)·(e >> 5)` <
/// 2¹⁴·2¹⁵.
#[inline(always)]
fn ndot(n: &[i32; 3], e: i32, l: &[i32; 3]) -> i32 {
    let d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    d - (((d >> 17) * (e >> 5)) >> 7)
}

/// One light of an [`ObjectLighting`], in the object's space.
#[derive(Copy, Clone, Debug)]
struct ObjectLight {
    kind: ObjectKind,
    /// la·ka, ld·kd, ls·ks per channel, Q16.16 (as in the eye-space setup).
    amb: [i32; 3],
    dif: [i32; 3],
    spec: [i32; 3],
    /// As the eye-space light's (`S::enabled()` folded in).
    has_spec: bool,
}

#[derive(Copy, Clone, Debug)]
enum ObjectKind {
    Directional {
        /// Unit direction to the light, Q1.15.
        l: [i32; 3],
        /// Half vector for the infinite viewer, Q1.15 (None: L + V = 0).
        h: Option<[i32; 3]>,
    },
    Point {
        /// Position in the object's Q16.16 units.
        pos: [i64; 3],
        /// Attenuation factors, Q16.16.
        att: [Q16_16; 3],
    },
}

/// The vertex stage's lighting of one object: [`LightingSetup::shade`]'s sums, in
/// the object's own space. The model-view is a similarity (a rigid view, a rotation
/// and a uniform scale), so `N·L` in eye space is `n·L'` with `n` the mesh's unit
/// normal and `L' = Rᵀ·L` turned back once per frame (likewise the half vectors,
/// the point lights' positions, the eye): no normal matrix, no eye-space position
/// per vertex, and the normal's length is 1 to the Q2.14 rounding, corrected to
/// first order (`ndot`) without a square root. Directions are Q1.15 and dot
/// products Q29: 15 bits, the precision of the mesh's normals. Distances to point
/// lights are scaled back to eye space by the model's scale.
///
/// ```
/// use fixshade::fixed::{Q16_16, Q2_14};
/// use fixshade::light::{Light, LightingSetup, Material};
/// use fixshade::specular::BlinnExact;
/// use fixshade::math::Mat4;
/// let white = [Q16_16::ONE; 3];
/// let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
/// let setup: LightingSetup<BlinnExact> =
///     LightingSetup::new(&[sun], &Mat4::IDENTITY, &Material::default(), [Q16_16::ZERO; 3], false);
/// let lit = setup.for_object(&Mat4::IDENTITY);
/// let up = [Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE];
/// // Facing the light: the default diffuse 0.8 (Q16.16), as the eye-space setup.
/// assert!((lit.shade(&[Q16_16::ZERO; 3], &up)[0] - 52_429).abs() <= 2);
/// ```
#[derive(Clone, Debug)]
pub struct ObjectLighting<S: Specular> {
    lights: heapless::Vec<ObjectLight, MAX_LIGHTS>,
    directional: usize,
    /// emission + global ambient + the directional lights' ambient, Q16.16.
    base: [i64; 3],
    /// The viewer (0, 0, 1) in object space, Q1.15.
    view: [i32; 3],
    /// The eye's position in object units (a local viewer).
    eye: Option<[i64; 3]>,
    /// The model's scale as a Q16.16 factor from object to eye distances.
    scale: i64,
    /// A zero normal's replacement (eye-space +z), as [`unit_normal`] returns it.
    zero: ([i32; 3], i32),
    spec: S::Params,
    /// Directional lights only, every colour product in [0, 1] and the base in
    /// [0, 16]: [`ObjectLighting::shade`] sums in `i32` with 32-bit products.
    unit: bool,
}

impl<S: Specular> LightingSetup<S> {
    /// This setup turned into the space of an object with model-view `mv` (a
    /// similarity: see [`ObjectLighting`]).
    pub fn for_object(&self, mv: &Mat4) -> ObjectLighting<S> {
        // s² from the first column of the linear part (Q64), |s| in Q16.16.
        let s2: u128 = (0..3)
            .map(|r| (mv.m[r][0] as i128 * mv.m[r][0] as i128) as u128)
            .sum();
        let s = crate::math::isqrt_u128(s2) as i64 >> 16; // Q32 → Q16.16
                                                          // Object-space point: Rᵀ·(P − t)/s = linᵀ·(P − t)/s², Q16.16.
        let to_obj_point = |p: [i64; 3]| -> [i64; 3] {
            core::array::from_fn(|c| {
                let v: i128 = (0..3)
                    .map(|r| mv.m[r][c] as i128 * (p[r] - mv.m[r][3]) as i128)
                    .sum();
                if s2 == 0 {
                    0
                } else {
                    // Q32.32·Q32.32 = Q64 over Q64: the ratio, in Q16.16.
                    let q = (v << 16) / s2 as i128;
                    q.clamp(i64::MIN as i128, i64::MAX as i128) as i64
                }
            })
        };
        let unit15 = |d: [i32; 3]| to_object(mv, d).map(to_q15);
        let view = unit15([0, 0, ONE_Q30]).unwrap_or([0, 0, 1 << 15]);
        let zero = to_object(mv, [0, 0, ONE_Q30]).unwrap_or([0, 0, ONE_Q30]);
        let zero = unit_normal(
            &zero.map(|c| Q2_14::from_bits(((c + (1 << 15)) >> 16) as i16)),
            ([0, 0, 1 << 14], 0),
        );
        let mut base = self.base;
        let mut lights = heapless::Vec::new();
        for light in &self.lights {
            let kind = match light.kind {
                EyeKind::Directional { l, h } => {
                    for (b, a) in base.iter_mut().zip(light.amb.iter()) {
                        *b += *a as i64;
                    }
                    ObjectKind::Directional {
                        l: unit15(l).unwrap_or([0, 0, 1 << 15]),
                        h: h.and_then(unit15),
                    }
                }
                EyeKind::Point { pos, att } => ObjectKind::Point {
                    pos: to_obj_point(pos.map(|c| (c as i64) << 16)),
                    att,
                },
            };
            // Cannot overflow: both have MAX_LIGHTS entries.
            let _ = lights.push(ObjectLight {
                kind,
                amb: light.amb,
                dif: light.dif,
                spec: light.spec,
                has_spec: light.has_spec,
            });
        }
        let directional = self.directional.min(self.lights.len());
        let in_unit = |c: &[i32; 3]| c.iter().all(|v| (0..=1 << 16).contains(v));
        let unit = directional == lights.len()
            && base.iter().all(|b| (0..=1 << 20).contains(b))
            && lights.iter().all(|l| in_unit(&l.dif) && in_unit(&l.spec));
        ObjectLighting {
            lights,
            directional,
            base,
            view,
            eye: if self.local_viewer {
                Some(to_obj_point([0; 3]))
            } else {
                None
            },
            scale: s,
            zero,
            spec: self.spec,
            unit,
        }
    }
}

impl<S: Specular> ObjectLighting<S> {
    /// Whether [`Self::shade`] reads the position (point lights, a local viewer).
    pub fn needs_position(&self) -> bool {
        self.directional < self.lights.len() || (S::ENABLED && self.eye.is_some())
    }

    /// The lit colour of a mesh vertex: position `p` and normal `n` as the mesh
    /// holds them. Q16.16 channels clamped to [0, 1], as [`LightingSetup::shade`].
    ///
    /// Bounds: as [`LightingSetup::shade`]'s; each term is added to an `i64` sum.
    #[inline]
    pub fn shade(&self, p: &Vec3, n: &[Q2_14; 3]) -> [i32; 3] {
        if self.unit {
            self.shade_unit(p, n)
        } else {
            self.shade_wide(p, n)
        }
    }

    /// [`Self::shade`] for directional lights whose colour products lie in [0, 1]
    /// and a base in [0, 16] (Q16.16): the same terms as [`Self::shade_wide`] in
    /// 32 bits. Each product of a colour (≤ 2¹⁶) and a factor (≤ 2¹⁵, Q15) is at
    /// most 2³¹ as `u32`; the sum of the base and at most 8 lights' two terms stays
    /// below 2²⁵.
    #[inline(always)]
    fn shade_unit(&self, p: &Vec3, n: &[Q2_14; 3]) -> [i32; 3] {
        let (n, e) = unit_normal(n, self.zero);
        let mut acc = self.base.map(|b| b as i32);
        let view = match (&self.eye, S::ENABLED) {
            (Some(eye), true) => {
                let d = core::array::from_fn(|k| eye[k] - p[k].to_bits() as i64);
                normalize_to_q30(d).map(to_q15).unwrap_or(self.view)
            }
            _ => self.view,
        };
        let term = |c: i32, f: u32| ((c as u32 * f) >> 15) as i32;
        for light in &self.lights {
            let ObjectKind::Directional { l, h } = light.kind else {
                continue;
            };
            let nl = ndot(&n, e, &l);
            if nl <= 0 {
                continue;
            }
            let f = ((nl >> 14) as u32).min(1 << 15);
            for (c, dif) in acc.iter_mut().zip(light.dif.iter()) {
                *c += term(*dif, f);
            }
            if !S::ENABLED || !light.has_spec {
                continue;
            }
            let h = if self.eye.is_some() {
                half15(l, view)
            } else {
                h
            };
            let Some(h) = h else { continue };
            let nh = ndot(&n, e, &h);
            if nh <= 0 {
                continue;
            }
            let s = S::eval_wide(&self.spec, (nh << 1).min(ONE_Q30));
            if s <= 1 << 30 {
                let f = (s >> 15) as u32;
                for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
                    *c += term(*sp, f);
                }
            } else {
                // A model above 1 (at most 2^36, Q.30): the colour (≤ 2^16) times
                // s >> 14 (< 2^22), in 64 bits; saturated, the sum stays in i32.
                for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
                    let t = (*sp as i64 * (s >> 14) as i64) >> 16;
                    *c = (*c as i64 + t).min(1 << 30) as i32;
                }
            }
        }
        acc.map(|c| c.clamp(0, 1 << 16))
    }

    /// [`Self::shade`] for any lights and colours, summed in `i64`.
    fn shade_wide(&self, p: &Vec3, n: &[Q2_14; 3]) -> [i32; 3] {
        let (n, e) = unit_normal(n, self.zero);
        let mut acc = self.base;
        // The viewer direction at this vertex (Q1.15): only a local viewer's varies.
        let view = match (&self.eye, S::ENABLED) {
            (Some(eye), true) => {
                let d = core::array::from_fn(|k| eye[k] - p[k].to_bits() as i64);
                normalize_to_q30(d).map(to_q15).unwrap_or(self.view)
            }
            _ => self.view,
        };
        let (dirs, points) = self.lights.split_at(self.directional);
        for light in dirs {
            let ObjectKind::Directional { l, h } = light.kind else {
                continue;
            };
            let nl = ndot(&n, e, &l);
            if nl <= 0 {
                continue;
            }
            // Q29 → Q15, at most 1.
            let f = (nl >> 14).min(1 << 15);
            for (c, dif) in acc.iter_mut().zip(light.dif.iter()) {
                *c += scale_q15(*dif, f) as i64;
            }
            if !S::ENABLED || !light.has_spec {
                continue;
            }
            let h = if self.eye.is_some() {
                half15(l, view)
            } else {
                h
            };
            if let Some(h) = h {
                self.add_specular(&mut acc, light, &n, e, &h, None);
            }
        }
        for light in points {
            let ObjectKind::Point { pos, att } = light.kind else {
                continue;
            };
            let d: [i64; 3] = core::array::from_fn(|k| pos[k] - p[k].to_bits() as i64);
            let Some(l30) = normalize_to_q30(d) else {
                continue;
            };
            let l = to_q15(l30);
            // Eye-space distance: the object's scale times the object-space one.
            let dist = crate::math::mul_q16_u64(crate::math::length(d), self.scale);
            let a = attenuation_at(dist, att);
            for (c, amb) in acc.iter_mut().zip(light.amb.iter()) {
                *c += mul_wide(*amb, a) >> 16;
            }
            let nl = ndot(&n, e, &l);
            if nl <= 0 {
                continue;
            }
            // att·(N·L): Q16.16 · Q29 → Q16.16, below 2³¹.
            let f = (mul_wide(a, nl) >> 29) as i32;
            for (c, dif) in acc.iter_mut().zip(light.dif.iter()) {
                *c += mul_wide(*dif, f) >> 16;
            }
            if !S::ENABLED || !light.has_spec {
                continue;
            }
            if let Some(h) = half15(l, view) {
                self.add_specular(&mut acc, light, &n, e, &h, Some(a));
            }
        }
        acc.map(|c| c.clamp(0, 1 << 16) as i32)
    }

    /// The specular term of one light for the half vector `h` (Q1.15), as
    /// [`LightingSetup::shade`] adds it: `cⁿ` from the [`Specular`] model of
    /// `c = N·H`, times the attenuation (`None`: exactly 1).
    #[inline(always)]
    fn add_specular(
        &self,
        acc: &mut [i64; 3],
        light: &ObjectLight,
        n: &[i32; 3],
        e: i32,
        h: &[i32; 3],
        att: Option<i32>,
    ) {
        let nh = ndot(n, e, h);
        if nh <= 0 {
            return;
        }
        // Q29 → Q30 (below 2^31), at most 1.
        let s = S::eval_wide(&self.spec, (nh << 1).min(ONE_Q30));
        if att.is_none() && s <= 1 << 30 {
            // The usual case: a factor in [0, 1], Q15.
            let f = (s >> 15) as i32;
            for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
                *c += scale_q15(*sp, f) as i64;
            }
            return;
        }
        // As in `add_light`: s ≤ 2^36 (Q.30), att < 2^31 (Q16.16).
        let f = match att {
            None => s >> 14,
            Some(a) => {
                let (hi, lo) = ((s >> 30) as i32, (s & ((1 << 30) - 1)) as i32);
                ((mul_wide(a, hi) << 30) + mul_wide(a, lo)) as u64 >> 30
            }
        };
        for (c, sp) in acc.iter_mut().zip(light.spec.iter()) {
            *c += if f < 1 << 31 {
                mul_wide(*sp, f as i32) >> 16
            } else {
                (mul_wide(*sp, (f >> 16) as i32)) + (mul_wide(*sp, (f & 0xFFFF) as i32) >> 16)
            };
        }
    }
}

/// The half vector of two Q1.15 unit vectors, Q1.15 (`None` if they are opposite).
fn half15(l: [i32; 3], v: [i32; 3]) -> Option<[i32; 3]> {
    normalize_to_q30(core::array::from_fn(|k| (l[k] + v[k]) as i64)).map(to_q15)
}

impl<S: Specular> crate::raster::phong::PixelLight for LightingSetup<S> {
    #[inline]
    fn light(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        self.shade(p, n)
    }
}

/// A cone of unit vectors: its axis and the cosine and sine of its half-angle, all
/// Q2.30. The half-angle is below 90° (`cos > 0`).
#[derive(Copy, Clone, Debug)]
struct Cone {
    axis: [i32; 3],
    cos: i64,
    sin: i64,
}

/// Slack added to every bound (Q2.30, about 4e-6): covers the rounding of the dot
/// products, normalisations and square roots below and of the per-pixel
/// interpolation of normals and positions.
const SLACK: i64 = 1 << 12;

/// `sqrt(1 − c²)` for `c` in Q2.30, |c| ≤ 1.
fn sine_of(c: i64) -> i64 {
    let c = c.clamp(-(ONE_Q30 as i64), ONE_Q30 as i64);
    // c² ≤ 2^60: fits; the difference is in [0, 2^60].
    crate::math::isqrt_u64(((1i64 << 60) - c * c) as u64) as i64
}

impl Cone {
    /// The cone of one direction (half-angle 0).
    fn point(axis: [i32; 3]) -> Cone {
        Cone {
            axis,
            cos: ONE_Q30 as i64,
            sin: 0,
        }
    }

    /// A cone holding the three unit vectors `v` and so (the half-angle being below
    /// 90°, a spherical cap is convex) every normalised positive combination of
    /// them. `None` if no such cone with a half-angle below 90° is found.
    fn around(v: &[[i32; 3]; 3]) -> Option<Cone> {
        let sum: [i64; 3] = core::array::from_fn(|k| v.iter().map(|u| u[k] as i64).sum());
        let axis = normalize_to_q30(sum)?;
        let cos = v.iter().map(|u| dot_q30(axis, *u) as i64).min()? - SLACK;
        if cos <= 0 {
            return None;
        }
        Some(Cone {
            axis,
            cos,
            sin: sine_of(cos),
        })
    }

    /// `(cos, sin)` of the angle between the axes and of the sum of the half-angles.
    fn angles(&self, o: &Cone) -> (i64, i64, i64, i64) {
        let c_ab = dot_q30(self.axis, o.axis) as i64;
        let s_ab = sine_of(c_ab);
        // Products of Q2.30 values ≤ 1: < 2^61.
        let c_t = (self.cos * o.cos - self.sin * o.sin) >> 30;
        let s_t = (self.sin * o.cos + self.cos * o.sin) >> 30;
        (c_ab, s_ab, c_t, s_t)
    }

    /// An upper bound of `x·y` for `x` in `self`, `y` in `o` (Q2.30): the angle
    /// between them is at least the axes' angle minus both half-angles.
    fn max_dot(&self, o: &Cone) -> i64 {
        let c_ab = dot_q30(self.axis, o.axis) as i64;
        // Products of Q2.30 values ≤ 1: < 2^61.
        let c_t = (self.cos * o.cos - self.sin * o.sin) >> 30;
        if c_ab >= c_t {
            return ONE_Q30 as i64;
        }
        let s_ab = sine_of(c_ab);
        let s_t = (self.sin * o.cos + self.cos * o.sin) >> 30;
        (((c_ab * c_t + s_ab * s_t) >> 30) + SLACK).min(ONE_Q30 as i64)
    }

    /// A lower bound of `x·y` (Q2.30): the angle is at most the axes' angle plus both
    /// half-angles.
    fn min_dot(&self, o: &Cone) -> i64 {
        let (c_ab, s_ab, c_t, s_t) = self.angles(o);
        let cos_sum = (c_ab * c_t - s_ab * s_t) >> 30;
        let sin_sum = (s_ab * c_t + c_ab * s_t) >> 30;
        if sin_sum < 0 || (sin_sum == 0 && cos_sum < 0) {
            return -(ONE_Q30 as i64);
        }
        (cos_sum - SLACK).max(-(ONE_Q30 as i64))
    }
}

impl<S: Specular> LightingSetup<S> {
    /// An upper bound, over a whole triangle, of the specular part of
    /// [`LightingSetup::shade`] (Q16.16, the largest channel, summed over the
    /// lights), for a triangle with eye-space unit vertex normals `n` (Q2.30) and
    /// vertex positions `p` (Q16.16), whatever point inside it is lit with whatever
    /// normalised positive combination of its vertex normals (what Phong shading
    /// does). `i64::MAX` when no finite bound is found (normals more than 90° apart,
    /// a light or the eye on the triangle).
    ///
    /// For each light: the normals lie in a cone around their normalised sum, the
    /// directions to a point light and to a local viewer in cones around theirs (they
    /// are positive combinations of the vertex directions); `N·H = N·(L + V)/|L + V|`
    /// is bounded by `(max N·L + max N·V) / sqrt(2 + 2·min L·V)` (for a directional
    /// light and an infinite viewer `H` is fixed and `max N·H` is bounded directly),
    /// and a light with `max N·L ≤ 0` adds nothing (the specular term needs
    /// `N·L > 0`). The bound on `cⁿ` is the model's value at the bound of `c`, which
    /// assumes the model is non-decreasing in `c` (every model of
    /// [`crate::specular`] is). The attenuation of a point light is bounded by its
    /// value at the least distance any point of the triangle can have (the nearest
    /// vertex's distance minus the longest edge).
    pub fn specular_bound(&self, n: &[[i32; 3]; 3], p: &[[i32; 3]; 3]) -> i64 {
        if !self.any_specular() {
            return 0;
        }
        match Cone::around(n) {
            Some(nc) => self.specular_in(&nc, p),
            None => i64::MAX,
        }
    }

    /// Whether some light adds a specular term.
    fn any_specular(&self) -> bool {
        S::ENABLED && self.lights.iter().any(|l| l.has_spec)
    }

    /// Whether both bounds of a triangle are below their limits (Q16.16):
    /// [`LightingSetup::specular_bound`] below `spec_limit` and
    /// [`LightingSetup::diffuse_bound`] below `diffuse_limit`, with the cone of
    /// normals computed once for both. False where no finite bound is found.
    pub(crate) fn within_bounds(
        &self,
        n: &[[i32; 3]; 3],
        p: &[[i32; 3]; 3],
        spec_limit: i64,
        diffuse_limit: i64,
    ) -> bool {
        let Some(nc) = Cone::around(n) else {
            return false;
        };
        // The diffuse bound first: for directional lights it needs no square root.
        self.diffuse_in(&nc, n, p) < diffuse_limit
            && (!self.any_specular() || self.specular_in(&nc, p) < spec_limit)
    }

    /// [`LightingSetup::specular_bound`] for the cone `nc` of the vertex normals.
    fn specular_in(&self, nc: &Cone, p: &[[i32; 3]; 3]) -> i64 {
        let v_cone = if self.local_viewer {
            let mut v = [[0; 3]; 3];
            for (o, q) in v.iter_mut().zip(p.iter()) {
                match normalize_to_q30([-(q[0] as i64), -(q[1] as i64), -(q[2] as i64)]) {
                    Some(u) => *o = u,
                    None => return i64::MAX,
                }
            }
            match Cone::around(&v) {
                Some(c) => c,
                None => return i64::MAX,
            }
        } else {
            Cone::point([0, 0, ONE_Q30])
        };
        let one = ONE_Q30 as i64;
        let mut total: i64 = 0;
        for light in self.lights.iter().filter(|l| l.has_spec) {
            let (l_cone, att, fixed_h) = match light.kind {
                EyeKind::Directional { l, h } => {
                    let fixed = if self.local_viewer { None } else { Some(h) };
                    (Cone::point(l), 1i64 << 16, fixed)
                }
                EyeKind::Point { pos, att } => {
                    let mut ls = [[0; 3]; 3];
                    let mut near = i64::MAX;
                    for (o, q) in ls.iter_mut().zip(p.iter()) {
                        let d: [i64; 3] = core::array::from_fn(|k| pos[k] as i64 - q[k] as i64);
                        match normalize_to_q30(d) {
                            Some(u) => *o = u,
                            None => return i64::MAX,
                        }
                        near = near.min(length_q16(d));
                    }
                    let edge = (0..3)
                        .map(|k| {
                            let (a, b) = (p[k], p[(k + 1) % 3]);
                            length_q16(core::array::from_fn(|j| a[j] as i64 - b[j] as i64))
                        })
                        .max()
                        .unwrap_or(0);
                    let Some(cone) = Cone::around(&ls) else {
                        return i64::MAX;
                    };
                    let dmin = (near - edge).max(0);
                    (cone, attenuation([dmin, 0, 0], att) as i64, None)
                }
            };
            let max_nl = nc.max_dot(&l_cone);
            if max_nl <= 0 {
                continue;
            }
            let max_nh = match fixed_h {
                Some(None) => continue,
                Some(Some(h)) => nc.max_dot(&Cone::point(h)),
                None => {
                    let num = max_nl + nc.max_dot(&v_cone);
                    if num <= 0 {
                        continue;
                    }
                    // |L + V|² = 2 + 2·L·V, Q2.30.
                    let den2 = 2 * one + 2 * l_cone.min_dot(&v_cone);
                    if den2 <= one >> 8 {
                        one
                    } else {
                        // den2 < 2^32: den2·2^30 < 2^62.
                        let den = crate::math::isqrt_u64((den2 << 30) as u64) as i64;
                        // num ≤ 2^31: num·2^30 < 2^62.
                        ((num << 30) / den.max(1) + SLACK).min(one)
                    }
                }
            };
            if max_nh <= 0 {
                continue;
            }
            let s = S::eval_wide(&self.spec, max_nh as i32);
            // As in `shade`: att ≤ 2^31 (Q16.16), s ≤ 2^36 (Q.30).
            let f = ((att as i128 * s as i128) >> 30) as i64;
            let top = light
                .spec
                .iter()
                .map(|sp| (*sp as i64 * f) >> 16)
                .max()
                .unwrap_or(0);
            total = total.saturating_add(top + 1);
        }
        total
    }
}

impl<S: Specular> LightingSetup<S> {
    /// An upper bound (Q16.16, the largest channel, summed over the lights) of how
    /// far the ambient and diffuse part of a Gouraud-shaded triangle can be from the
    /// same part lit per pixel (Phong), for eye-space unit vertex normals `n` and
    /// positions `p` as in [`LightingSetup::specular_bound`]; `i64::MAX` when no
    /// finite bound is found.
    ///
    /// For a directional light, with `dᵢ = nᵢ·L` at the vertices: no `dᵢ` above 0
    /// gives 0 on both sides; otherwise the difference is at most
    /// `ld·kd·(neg + 1 − cos)`, `neg` being how far the lowest vertex lies behind the
    /// terminator (`max(−dᵢ, 0)`) and `cos` the cosine of the normals' cone's
    /// half-angle (the interpolated normal is at least that long), and at most
    /// `ld·kd·max dᵢ / cos` (neither side exceeds it). For a point light both lie
    /// between the least and the greatest value the term takes over the triangle
    /// (bounded from the cones of normals and of light directions and the
    /// attenuation at the nearest and farthest distance), and differ by at most the
    /// span between them.
    pub fn diffuse_bound(&self, n: &[[i32; 3]; 3], p: &[[i32; 3]; 3]) -> i64 {
        match Cone::around(n) {
            Some(nc) => self.diffuse_in(&nc, n, p),
            None => i64::MAX,
        }
    }

    /// [`LightingSetup::diffuse_bound`] for the cone `nc` of the vertex normals `n`.
    fn diffuse_in(&self, nc: &Cone, n: &[[i32; 3]; 3], p: &[[i32; 3]; 3]) -> i64 {
        let one = ONE_Q30 as i64;
        let mut total: i64 = 0;
        for light in &self.lights {
            let top =
                |v: &[i32; 3], f: i64| v.iter().map(|c| (*c as i64 * f) >> 16).max().unwrap_or(0);
            match light.kind {
                EyeKind::Directional { l, .. } => {
                    // With weights wᵢ (Σ wᵢ = 1) and dᵢ = nᵢ·L, Gouraud interpolates
                    // g = Σ wᵢ·max(dᵢ, 0) and Phong lights max(s, 0)/len with
                    // s = Σ wᵢ·dᵢ and len = |Σ wᵢ·nᵢ| ≥ cos (the cone's). No dᵢ
                    // above 0: s ≤ 0 and both are 0. Otherwise g − s ≤ neg =
                    // max(−dᵢ, 0), and s/len ≤ 1, so the difference is at most
                    // neg + (1 − cos); and both are at most max dᵢ / cos.
                    let d = n.map(|v| dot_q30(v, l) as i64);
                    let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
                    // SLACK covers the per-pixel normal's rounding.
                    if hi + SLACK <= 0 {
                        continue;
                    }
                    let neg = (-lo).max(0);
                    let shorter = neg + (one - nc.cos) + SLACK;
                    // hi < 2^31, cos in (0, 2^30]: hi·2^30 < 2^61.
                    let crossing = ((hi + SLACK) << 30) / nc.cos + SLACK;
                    // Q2.30 → Q16.16, rounded up.
                    let f = (shorter.min(crossing) >> 14) + 1;
                    total = total.saturating_add(top(&light.dif, f) + 1);
                }
                EyeKind::Point { pos, att } => {
                    let mut ls = [[0; 3]; 3];
                    let (mut near, mut far) = (i64::MAX, 0);
                    for (o, q) in ls.iter_mut().zip(p.iter()) {
                        let d: [i64; 3] = core::array::from_fn(|k| pos[k] as i64 - q[k] as i64);
                        match normalize_to_q30(d) {
                            Some(u) => *o = u,
                            None => return i64::MAX,
                        }
                        let len = length_q16(d);
                        near = near.min(len);
                        far = far.max(len);
                    }
                    let edge = (0..3)
                        .map(|k| {
                            let (a, b) = (p[k], p[(k + 1) % 3]);
                            length_q16(core::array::from_fn(|j| a[j] as i64 - b[j] as i64))
                        })
                        .max()
                        .unwrap_or(0);
                    let Some(lc) = Cone::around(&ls) else {
                        return i64::MAX;
                    };
                    // The distance is convex: its maximum is at a vertex.
                    let att_max = attenuation([(near - edge).max(0), 0, 0], att) as i64;
                    let att_min = attenuation([far, 0, 0], att) as i64;
                    let max_nl = nc.max_dot(&lc).max(0);
                    let inv = Cone {
                        axis: [-lc.axis[0], -lc.axis[1], -lc.axis[2]],
                        ..lc
                    };
                    let min_nl = (-inv.max_dot(nc)).max(0);
                    // Q16.16 · Q2.30 → Q16.16.
                    let hi = (att_max * max_nl) >> 30;
                    let lo = (att_min * min_nl) >> 30;
                    let span =
                        top(&light.dif, hi - lo + 1) + top(&light.amb, att_max - att_min + 1);
                    total = total.saturating_add(span + 1);
                }
            }
        }
        total
    }
}

/// Length of a Q16.16 offset, Q16.16 (components < 2^32 raw: squares summed in u128).
fn length_q16(d: [i64; 3]) -> i64 {
    crate::math::length(d).min(i64::MAX as u64) as i64
}

fn half(l: [i32; 3], v: [i32; 3]) -> Option<[i32; 3]> {
    normalize_to_q30([
        l[0] as i64 + v[0] as i64,
        l[1] as i64 + v[1] as i64,
        l[2] as i64 + v[2] as i64,
    ])
}

/// `1 / (c + l·d + q·d²)` in Q16.16 for the Q16.16 offset `d` (saturating just
/// below 2¹⁵): [`attenuation_at`] of its length ([`crate::math::length`]).
fn attenuation(d: [i64; 3], att: [Q16_16; 3]) -> i32 {
    attenuation_at(crate::math::length(d), att)
}

/// `1 / (c + l·dist + q·dist²)` in Q16.16 for a Q16.16 distance (taken as at most
/// 65536 units), saturating at `i32::MAX` (just below 2¹⁵): no `i128`, no division.
/// The denominator in Q.32 from 32×32-bit products (`u64`, saturating: `l·dist` <
/// 2⁶³, `q·dist²/2¹⁶` from the two words of `dist²`), its reciprocal by
/// [`crate::math::recip_q61`] of its top 31 bits: within 2⁻²⁸ of `2⁴⁸/den`,
/// relatively, and one unit (tested against the exact value).
fn attenuation_at(dist: u64, att: [Q16_16; 3]) -> i32 {
    use crate::math::{leading_zeros, mul_wide_u, recip_q61};
    let [c, l, q] = att.map(|v| v.to_bits().max(0) as u32);
    let d = dist.min(u32::MAX as u64) as u32;
    let d2 = mul_wide_u(d, d); // dist², Q32.32
    let t2_hi = mul_wide_u(q, (d2 >> 32) as u32);
    let t2 = if t2_hi >= 1 << 48 {
        u64::MAX
    } else {
        (t2_hi << 16) + (mul_wide_u(q, d2 as u32) >> 16)
    };
    let den = ((c as u64) << 16)
        .saturating_add(mul_wide_u(l, d))
        .saturating_add(t2);
    if den == 0 {
        return i32::MAX;
    }
    // den = m·2^(33 − k) with m its top 31 bits in [2^30, 2^31), k its leading zeros.
    let (hi, lo) = ((den >> 32) as u32, den as u32);
    let (k, top) = if hi != 0 {
        let z = leading_zeros(hi);
        (
            z,
            if z == 0 {
                hi
            } else {
                (hi << z) | (lo >> (32 - z))
            },
        )
    } else {
        let z = leading_zeros(lo);
        (32 + z, lo << z)
    };
    let r = recip_q61(top >> 1); // 2^61/m, in (2^30, 2^31)
                                 // 2^48/den = 2^(15 + k)/m = r·2^(k − 46): above 2^31 for k > 46.
    match k {
        47.. => i32::MAX,
        15..=46 => (r >> (46 - k)).min(i32::MAX as u32) as i32,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(v: i32, d: i32) -> Q16_16 {
        Q16_16::from_ratio(v, d)
    }

    /// Random directional lights and materials with colour products below 1: the
    /// 32-bit sums ([`LightingSetup::shade_directional`]) give the `i64` sums' bits
    /// ([`LightingSetup::shade_any`]) for every specular model (the
    /// energy-conserving one reaches factors above 2¹⁶, as do normals longer than
    /// 1), with and without a local viewer; a product of exactly 1 keeps the `i64`
    /// sums.
    #[test]
    fn shade_unit_equals_shade_any() {
        fn next(seed: &mut u64, m: u64) -> u64 {
            *seed ^= *seed << 13;
            *seed ^= *seed >> 7;
            *seed ^= *seed << 17;
            *seed % m
        }
        fn colour(seed: &mut u64, max: u64) -> [Q16_16; 3] {
            let v = next(seed, max) as i32;
            [v, (v * 3 + 7) % max as i32, (v * 5 + 11) % max as i32].map(Q16_16::from_bits)
        }
        fn check<S: Specular>(seed: &mut u64) -> usize {
            let mut checked = 0;
            for round in 0..24 {
                let lights: heapless::Vec<Light, 3> = (0..1 + round % 3)
                    .map(|_| {
                        let d = [0; 3]
                            .map(|_| Q16_16::from_bits(next(seed, 1 << 18) as i32 - (1 << 17)));
                        let mut l =
                            Light::directional(d, colour(seed, 1 << 16), colour(seed, 1 << 16));
                        l.ambient = colour(seed, 1 << 13);
                        l
                    })
                    .collect();
                let mat = Material {
                    emission: colour(seed, 1 << 15),
                    ambient: colour(seed, 1 << 16),
                    diffuse: colour(seed, 1 << 16),
                    specular: colour(seed, 1 << 16),
                    shininess: Q16_16::from_bits(next(seed, 200 << 16) as i32),
                };
                let setup = LightingSetup::<S>::new(
                    &lights,
                    &Mat4::IDENTITY,
                    &mat,
                    colour(seed, 1 << 15),
                    round % 2 == 0,
                );
                assert!(setup.unit);
                for _ in 0..400 {
                    let v = [0; 3].map(|_| next(seed, 1 << 20) as i64 - (1 << 19));
                    let Some(n) = normalize_to_q30(v) else {
                        continue;
                    };
                    let p = [0; 3].map(|_| next(seed, 1 << 22) as i32 - (1 << 21));
                    assert_eq!(
                        setup.shade_directional::<[i32; 3]>(p, n),
                        setup.shade_any(p, n),
                        "{n:?} {p:?}"
                    );
                    // A normal 1.5 long: diffuse factors above 2^16 as well.
                    let long = n.map(|c| c + c / 2);
                    assert_eq!(
                        setup.shade_directional::<[i32; 3]>(p, long),
                        setup.shade_any(p, long),
                        "{long:?}"
                    );
                    checked += 1;
                }
            }
            checked
        }
        let mut seed = 0x2545_F491_4F6C_DD1D;
        assert!(check::<BlinnExact>(&mut seed) > 9000);
        assert!(check::<crate::specular::CosQuadratic>(&mut seed) > 9000);
        assert!(check::<crate::specular::CosQuadraticEnergy>(&mut seed) > 9000);
        assert!(check::<crate::specular::Schlick>(&mut seed) > 9000);
        let white = [Q16_16::ONE; 3];
        let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
        let mat = Material {
            diffuse: white,
            ..Material::default()
        };
        let setup = LightingSetup::<BlinnExact>::new(
            &[sun],
            &Mat4::IDENTITY,
            &mat,
            [Q16_16::ZERO; 3],
            false,
        );
        assert!(!setup.unit);
    }

    /// The colour products give `mul_wide`'s bits: every colour at the ends of its
    /// range and around the powers of two, against factors around 2¹⁶ (where the
    /// two forms meet) and across [0, 2³¹).
    #[test]
    fn colour_terms_equal_wide() {
        let mut cs: heapless::Vec<i32, 64> = heapless::Vec::new();
        let mut fs: heapless::Vec<i32, 1024> = heapless::Vec::new();
        cs.extend([0, 1, (1 << 16) - 1]);
        fs.extend([0, 1, i32::MAX, (1 << 22) - 1]);
        for k in 0..31 {
            for d in [-1, 0, 1] {
                if k < 16 {
                    cs.push((1 << k) + d).unwrap();
                }
                fs.push((1i32 << k).saturating_add(d).max(0)).unwrap();
            }
        }
        for d in -300..300 {
            fs.push((1 << 16) + d).unwrap();
        }
        for &c in cs.iter().filter(|c| (0..1 << 16).contains(*c)) {
            for &f in &fs {
                let mut acc = [7, 0, -3];
                acc.add_terms(&[c, c, c], f);
                let t = (mul_wide(c, f) >> 16) as i32;
                assert_eq!(acc, [7 + t, t, t - 3], "{c} {f}");
            }
        }
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
    fn mixed_lights_sum_in_any_order() {
        // Point lights interleaved with directional ones: the setup walks the
        // directional lights first, which must not change a colour. Without
        // ambient parts or global ambient the lights' terms simply add (as long as
        // no channel saturates), so each pair is also checked against the two
        // lights alone.
        let white = [q(1, 4); 3];
        let sun = |x: i32| Light::directional([q(x, 4), Q16_16::ONE, Q16_16::ONE], white, white);
        let lamp = |x: i32| Light {
            kind: LightKind::Point {
                position: [q(x, 2), Q16_16::ONE, Q16_16::from_int(2)],
                attenuation: [Q16_16::ONE, q(1, 4), Q16_16::ZERO],
            },
            ambient: [Q16_16::ZERO; 3],
            diffuse: white,
            specular: white,
        };
        let mat = Material {
            emission: [Q16_16::ZERO; 3],
            ambient: [Q16_16::ZERO; 3],
            specular: [q(1, 2); 3],
            ..Material::default()
        };
        let setup = |ls: &[Light], local: bool| {
            LightingSetup::<BlinnExact>::new(ls, &Mat4::IDENTITY, &mat, [Q16_16::ZERO; 3], local)
        };
        let lights = [lamp(1), sun(-1), lamp(-3), sun(2)];
        let p = [1 << 14, -(1 << 15), -(3 << 16)];
        let mut lit = 0;
        for local in [false, true] {
            let all = setup(&lights, local);
            let rev = {
                let mut r = lights;
                r.reverse();
                setup(&r, local)
            };
            for k in 0..64 {
                let n = normalize_to_q30([(k % 8 - 4) as i64, (k / 8 - 4) as i64, 6])
                    .expect("non-zero");
                let c = all.shade(p, n);
                assert_eq!(c, rev.shade(p, n), "normal {n:?}");
                let parts: [i32; 3] = core::array::from_fn(|ch| {
                    lights
                        .iter()
                        .map(|l| setup(&[*l], local).shade(p, n)[ch])
                        .sum()
                });
                if parts.iter().all(|v| *v < 1 << 16) {
                    assert_eq!(c, parts, "normal {n:?}");
                    lit += 1;
                }
            }
        }
        assert!(lit > 64, "{lit} unsaturated samples");
    }

    #[test]
    fn diffuse_directional_path_gives_the_general_sums() {
        // Without a specular term and with directional lights only, `shade` takes
        // the directional loop (in i32 sums where the colour products are below 1,
        // in i64 otherwise); the general loop (reached here through `BlinnExact`
        // with no specular colour) must give the same colours, with and without
        // ambient parts, facing and turned away from the lights, with colour
        // products below and above 1.
        let sun = |x: i32, a: i32, d: i32| Light {
            ambient: [q(a, 10); 3],
            ..Light::directional(
                [q(x, 4), Q16_16::ONE, Q16_16::ONE],
                [q(3 * d, 4), q(d, 2), q(d, 4)],
                [Q16_16::ZERO; 3],
            )
        };
        let mat = Material {
            emission: [q(1, 20); 3],
            ..Material::default()
        };
        for (lights, unit) in [
            (&[sun(-1, 0, 1)][..], true),
            (&[sun(-1, 1, 1), sun(3, 2, 1), sun(0, 0, 1)][..], true),
            (&[][..], true),
            (&[sun(-1, 1, 3), sun(3, 2, 1)][..], false),
            (&[sun(2, 60, 1)][..], false),
        ] {
            let d = LightingSetup::<crate::effects::NoSpecular>::new(
                lights,
                &Mat4::IDENTITY,
                &mat,
                [q(1, 5); 3],
                true,
            );
            assert_eq!(d.unit, unit);
            let g =
                LightingSetup::<BlinnExact>::new(lights, &Mat4::IDENTITY, &mat, [q(1, 5); 3], true);
            for k in 0..64 {
                let n =
                    normalize_to_q30([(k % 8 - 4) as i64, (k / 8 - 4) as i64, 3 - k as i64 % 5])
                        .expect("non-zero");
                let p = [1 << 14, -(1 << 15), -(3 << 16)];
                let want = g.shade_any(p, n);
                assert_eq!(d.shade(p, n), want, "normal {n:?}");
                assert_eq!(d.diffuse_directional(n), want, "normal {n:?}");
                if unit {
                    assert_eq!(d.shade_directional::<[i32; 3]>(p, n), want, "normal {n:?}");
                }
            }
        }
    }

    #[test]
    fn terminator_bound_follows_the_vertices_behind_it() {
        // A small triangle crossing a directional light's terminator, its vertices
        // at most 0.05 behind it (N·L ≥ −0.05): Gouraud and Phong differ by at most
        // about 0.05 of the diffuse term (plus the normals' spread), far below the
        // term itself.
        let light = Light::directional(
            [Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO],
            [Q16_16::ONE; 3],
            [Q16_16::ZERO; 3],
        );
        let setup = LightingSetup::<BlinnExact>::new(
            &[light],
            &Mat4::IDENTITY,
            &Material::default(),
            [Q16_16::ZERO; 3],
            false,
        );
        let unit = |x: i64, y: i64| normalize_to_q30([x, y, 1 << 20]).expect("non-zero");
        let k = 1 << 20;
        let n = [
            unit(k / 20, 0),
            unit(-k / 20, k / 20),
            unit(-k / 20, -k / 20),
        ];
        let p = [
            [0, 0, -(4 << 16)],
            [1 << 12, 0, -(4 << 16)],
            [0, 1 << 12, -(4 << 16)],
        ];
        let bound = setup.diffuse_bound(&n, &p);
        // Diffuse 0.8: its full term is 52 429; 0.05 of it is 2 621.
        assert!(bound > 2_000 && bound < 3_300, "{bound}");
        assert_eq!(setup.specular_bound(&n, &p), 0);
        // The same triangle facing the light: only the normals' spread is left.
        let lit = n.map(|v| {
            normalize_to_q30([v[0] as i64 + (ONE_Q30 as i64), v[1] as i64, v[2] as i64])
                .expect("non-zero")
        });
        assert!(setup.diffuse_bound(&lit, &p) < 600);
    }

    /// Both forms of the colour product give the same bits, over every sign and
    /// the whole range of the factor.
    #[test]
    fn scale_q15_split_equals_native() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for k in 0..1_000_000u32 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let c = match k {
                0 => i32::MIN,
                1 => i32::MAX,
                _ => (seed as i32) >> (seed >> 59),
            };
            let f = ((seed >> 32) % ((1 << 15) + 1)) as i32;
            assert_eq!(
                scale_q15_split(c, f),
                ((c as i64 * f as i64) >> 15) as i32,
                "{c} {f}"
            );
        }
    }

    /// The attenuation without `i128` or division against `2⁴⁸/den` for the exact
    /// Q.32 denominator `c·2¹⁶ + l·d + ⌊q·d²/2¹⁶⌋`: within 2⁻²⁸ relatively, one unit.
    #[test]
    fn attenuation_matches_exact() {
        let mut seed = 0x1111_2222_3333_4444u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for k in 0..200_000u32 {
            let r = next();
            let att = [
                Q16_16::from_bits((r % (4 << 16)) as i32 * (k % 2) as i32),
                Q16_16::from_bits(((r >> 20) % (1 << 16)) as i32),
                Q16_16::from_bits(((r >> 40) % (1 << 14)) as i32 * (k % 3 / 2) as i32),
            ];
            let d = (next() >> (28 + k % 30)).min(u32::MAX as u64);
            let (c, l, q) = (
                att[0].to_bits() as i128,
                att[1].to_bits() as i128,
                att[2].to_bits() as i128,
            );
            let d128 = d as i128;
            let den = (c << 16) + l * d128 + ((q * d128 * d128) >> 16);
            let want = if den <= 0 {
                i32::MAX as f64
            } else {
                ((1i128 << 48) as f64 / den as f64).min(i32::MAX as f64)
            };
            let got = attenuation_at(d, att) as f64;
            assert!(
                (got - want).abs() <= want * 2f64.powi(-28) + 1.0,
                "{att:?} d {d}: {got} vs {want}"
            );
        }
    }

    /// The 32-bit sums of directional lights in unit colours give the 64-bit
    /// sums' colours, with and without a local viewer.
    #[test]
    fn unit_sums_equal_wide_sums() {
        use crate::fixed::Angle;
        let mut seed = 0x4242_1717_abab_cdcdu64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for round in 0..40 {
            let c = |r: u64| Q16_16::from_bits((r % (1 << 16)) as i32);
            let sun = |r: u64, d: [i32; 3]| Light {
                ambient: [c(r >> 3); 3],
                ..Light::directional(
                    d.map(|v| Q16_16::from_bits(v << 12)),
                    [c(r), c(r >> 7), c(r >> 11)],
                    [c(r >> 17); 3],
                )
            };
            let lights = [sun(next(), [1, 2, 3]), sun(next(), [-3, 1, 1])];
            let mat = Material {
                specular: [c(next()); 3],
                shininess: Q16_16::from_int(1 + (next() % 60) as i32),
                ..Material::default()
            };
            let setup = LightingSetup::<BlinnExact>::new(
                &lights,
                &Mat4::IDENTITY,
                &mat,
                [c(next() >> 2); 3],
                round % 2 == 0,
            );
            let mv = Mat4::translate([Q16_16::ONE, Q16_16::ZERO, Q16_16::from_int(-4)])
                .mul(&Mat4::rotate_y(Angle::from_degrees(round * 17)))
                .mul(&Mat4::rotate_x(Angle::from_degrees(round * 7)));
            let lit = setup.for_object(&mv);
            assert!(lit.unit);
            for _ in 0..500 {
                let n = [0, 0, 0]
                    .map(|_: i32| Q2_14::from_bits(((next() % 32768) as i32 - 16384) as i16));
                let p = [0, 0, 0]
                    .map(|_: i32| Q16_16::from_bits(((next() % (1 << 18)) as i32) - (1 << 17)));
                assert_eq!(
                    lit.shade_unit(&p, &n),
                    lit.shade_wide(&p, &n),
                    "{n:?} {p:?}"
                );
            }
        }
    }

    #[test]
    fn point_light_attenuates() {
        let d = [0i64, 0, 2 << 16]; // distance 2
        let a = attenuation(d, [Q16_16::ONE, Q16_16::ZERO, Q16_16::ONE]); // 1/(1+4)
        assert!((a - 65536 / 5).abs() <= 1, "{a}");
    }
}
