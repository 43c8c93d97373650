//! Scene descriptions in f64: what a scene file or a built-in scene says, before
//! anything is converted to the core's fixed-point formats.
//!
//! Both the fixed-point renderer (through `convert`) and the f64 reference renderer
//! (`reference`) start from these types, so they see the same scene.

use std::path::PathBuf;

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

/// Output pixel format by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormatName {
    /// RGB 5-6-5, little-endian bytes.
    Rgb565Le,
    /// RGB 5-6-5, big-endian bytes (what ST7789/ILI9341 take over SPI).
    Rgb565Be,
    /// RGB 8-8-8.
    Rgb888,
    /// 8-bit grey, `(77 R + 150 G + 29 B) / 256`.
    Gray8,
}

/// Shading mode by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadingName {
    /// One colour per triangle: its last (provoking) vertex's, as OpenGL does.
    Flat,
    /// Vertex colours interpolated linearly in screen space.
    Gouraud,
    /// Quadratic intensity surface through the vertex and edge-midpoint colours
    /// (seed 003); its reference is the exact Phong render.
    Quadratic,
    /// Per-pixel lighting from interpolated normals.
    Phong,
    /// Phong with the even/odd fill of seed 003 (the same pixels).
    PhongEvenOdd,
    /// Phong where a highlight can reach inside a triangle, Gouraud elsewhere
    /// (`fixshade::shade::Adaptive`); its reference is the exact Phong render.
    Adaptive,
    /// Per-pixel ray casting sampled by pixel segments (seed 002 §2.6,
    /// [`crate::raycast`]); its reference is the exact Phong render.
    Raycast,
}

impl ShadingName {
    /// True if the matching f64 reference is the per-pixel (Phong) render.
    pub fn phong_reference(self) -> bool {
        matches!(
            self,
            ShadingName::Quadratic
                | ShadingName::Phong
                | ShadingName::PhongEvenOdd
                | ShadingName::Adaptive
                | ShadingName::Raycast
        )
    }
}

/// Specular model by name (the `Specular` implementations of the core).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecularName {
    /// Exact `cⁿ`.
    Exact,
    /// Schlick's `c / (n − n·c + c)`.
    Schlick,
    /// The seed's modified Schlick.
    SchlickMod,
    /// `a·c² + (1 − a)·c` with the tabulated `a(n)`.
    Quadratic,
    /// `(σ(c − 1) + 1)²`, σ = (n + 1)/3.
    CosQuad,
    /// The energy-conserving cosine-quadratic form.
    CosQuadEnergy,
}

/// Divider by name (the `Divide` implementations of the core, `fixshade::divide`):
/// used by the classic span division, the triangle setup's reciprocal and
/// Schlick's denominator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DivideName {
    /// Full-precision integer division (bit-identical to the pipeline before the seam).
    #[default]
    Exact,
    /// The 16 KiB reciprocal table of `k = 1..=4096`.
    Table,
    /// Shift-and-add with `N` terms of the truncated expansion of `1/k`, `N` in 4..=16.
    ShiftAdd(u8),
    /// Shift-and-add with the expansion rounded at bit `N`, `N` in 4..=16.
    ShiftAddRounded(u8),
}

/// Every divider with its name, from the core's `NAME`s.
const DIVIDE_ALL: [(DivideName, &str); 28] = {
    use fixshade::divide::{Divide, Exact, ShiftAdd, ShiftAddRounded, Table};
    macro_rules! sa {
        ($($n:literal)*) => {
            [
                (DivideName::Exact, Exact::NAME),
                (DivideName::Table, Table::NAME),
                $((DivideName::ShiftAdd($n), ShiftAdd::<$n>::NAME),)*
                $((DivideName::ShiftAddRounded($n), ShiftAddRounded::<$n>::NAME),)*
            ]
        };
    }
    sa!(4 5 6 7 8 9 10 11 12 13 14 15 16)
};

impl Named for DivideName {
    const WHAT: &'static str = "divider";
    const ALL: &'static [(Self, &'static str)] = &DIVIDE_ALL;
}

/// Span method by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpanName {
    /// Per-span division of the end values (the idx3d way).
    Classic,
    /// Constant per-triangle increment (seed 000 §2.1).
    Gradient,
    /// Two accumulators over even and odd pixels (seed 000 §3.1).
    EvenOdd,
    /// Two accumulators stepping 2·ΔI.
    KWay2,
    /// Three accumulators stepping 3·ΔI.
    KWay3,
    /// Four accumulators stepping 4·ΔI.
    KWay4,
    /// Two interpolators from both ends towards the middle (seed 000 §3.2).
    Counter,
    /// 2 units filling segments of 2 pixels.
    Segment2,
    /// 4 units filling segments of 4 pixels.
    Segment4,
    /// 8 units filling segments of 8 pixels.
    Segment8,
    /// 16 units filling segments of 14 pixels.
    Segment16,
    /// 32 units filling segments of 22 pixels.
    Segment32,
    /// 64 units filling segments of 32 pixels.
    Segment64,
    /// Sierpinski subdivision with vertices snapped to even pixels (seed 000 §3.3).
    Sierpinski,
    /// Sierpinski subdivision only where it is exact (even vertex deltas).
    SierpinskiExact,
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
    /// Objects.
    pub objects: Vec<ObjectDesc>,
    /// Shading mode.
    pub shading: ShadingName,
    /// Span method.
    pub span: SpanName,
    /// Cull back faces (counter-clockwise triangles are front faces).
    pub cull_back: bool,
    /// Use the u16 depth buffer.
    pub depth_test: bool,
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
    pub raycast: crate::raycast::RaycastDesc,
    /// Effects forced on or off (`[render] effects`, `--effects`; [`crate::effects`]).
    pub effects: crate::effects::Overrides,
}

/// Names of the variants of an enum selectable by name in scene files and on the
/// command line.
pub trait Named: Sized + Copy + 'static {
    /// What the names denote, for error messages ("span method").
    const WHAT: &'static str;
    /// Every variant with its name.
    const ALL: &'static [(Self, &'static str)];

    /// The variant's name.
    fn name(self) -> &'static str
    where
        Self: PartialEq,
    {
        Self::ALL
            .iter()
            .find(|(v, _)| *v == self)
            .map(|(_, n)| *n)
            .unwrap_or("?")
    }

    /// Parses a name; the error lists the valid names.
    fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(v, _)| *v)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(_, n)| *n).collect();
                format!(
                    "unknown {} `{}`; expected one of: {}",
                    Self::WHAT,
                    name,
                    names.join(", ")
                )
            })
    }
}

impl Named for FormatName {
    const WHAT: &'static str = "pixel format";
    const ALL: &'static [(Self, &'static str)] = &[
        (FormatName::Rgb565Le, "rgb565le"),
        (FormatName::Rgb565Be, "rgb565be"),
        (FormatName::Rgb888, "rgb888"),
        (FormatName::Gray8, "gray8"),
    ];
}

impl Named for ShadingName {
    const WHAT: &'static str = "shading mode";
    const ALL: &'static [(Self, &'static str)] = &[
        (ShadingName::Flat, "flat"),
        (ShadingName::Gouraud, "gouraud"),
        (ShadingName::Quadratic, "quadratic"),
        (ShadingName::Phong, "phong"),
        (ShadingName::PhongEvenOdd, "phong-even-odd"),
        (ShadingName::Adaptive, "adaptive"),
        (ShadingName::Raycast, "raycast"),
    ];
}

impl Named for SpecularName {
    const WHAT: &'static str = "specular model";
    const ALL: &'static [(Self, &'static str)] = &[
        (SpecularName::Exact, "exact"),
        (SpecularName::Schlick, "schlick"),
        (SpecularName::SchlickMod, "schlick-mod"),
        (SpecularName::Quadratic, "quadratic"),
        (SpecularName::CosQuad, "cos-quad"),
        (SpecularName::CosQuadEnergy, "cos-quad-energy"),
    ];
}

impl Named for SpanName {
    const WHAT: &'static str = "span method";
    const ALL: &'static [(Self, &'static str)] = &[
        (SpanName::Classic, "classic"),
        (SpanName::Gradient, "gradient"),
        (SpanName::EvenOdd, "even-odd"),
        (SpanName::KWay2, "kway2"),
        (SpanName::KWay3, "kway3"),
        (SpanName::KWay4, "kway4"),
        (SpanName::Counter, "counter"),
        (SpanName::Segment2, "segment2"),
        (SpanName::Segment4, "segment4"),
        (SpanName::Segment8, "segment8"),
        (SpanName::Segment16, "segment16"),
        (SpanName::Segment32, "segment32"),
        (SpanName::Segment64, "segment64"),
        (SpanName::Sierpinski, "sierpinski"),
        (SpanName::SierpinskiExact, "sierpinski-exact"),
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trips<T: Named + PartialEq + std::fmt::Debug>(variants: &[T]) {
        for v in variants {
            assert_eq!(T::parse(v.name()), Ok(*v), "{v:?}");
        }
        assert_eq!(T::ALL.len(), variants.len(), "{} names missing", T::WHAT);
    }

    #[test]
    fn every_variant_has_a_name() {
        use SpanName::*;
        round_trips(&[
            Classic,
            Gradient,
            EvenOdd,
            KWay2,
            KWay3,
            KWay4,
            Counter,
            Segment2,
            Segment4,
            Segment8,
            Segment16,
            Segment32,
            Segment64,
            Sierpinski,
            SierpinskiExact,
        ]);
        round_trips(&[
            ShadingName::Flat,
            ShadingName::Gouraud,
            ShadingName::Quadratic,
            ShadingName::Phong,
            ShadingName::PhongEvenOdd,
            ShadingName::Adaptive,
            ShadingName::Raycast,
        ]);
        use SpecularName as Sp;
        round_trips(&[
            Sp::Exact,
            Sp::Schlick,
            Sp::SchlickMod,
            Sp::Quadratic,
            Sp::CosQuad,
            Sp::CosQuadEnergy,
        ]);
        let mut dividers = vec![DivideName::Exact, DivideName::Table];
        dividers.extend((4..=16).map(DivideName::ShiftAdd));
        dividers.extend((4..=16).map(DivideName::ShiftAddRounded));
        round_trips(&dividers);
        assert_eq!(
            DivideName::parse("shift-add-8"),
            Ok(DivideName::ShiftAdd(8))
        );
        assert!(DivideName::parse("shift-add-17").is_err());
        // The names are the core's.
        let names: Vec<&str> = Sp::ALL.iter().map(|(_, n)| *n).collect();
        assert_eq!(names, fixshade::specular::NAMES);
        round_trips(&[
            FormatName::Rgb565Le,
            FormatName::Rgb565Be,
            FormatName::Rgb888,
            FormatName::Gray8,
        ]);
    }
}
