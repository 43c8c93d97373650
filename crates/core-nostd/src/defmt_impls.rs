//! `defmt::Format` for the public value types (feature `defmt`): fixed-point numbers,
//! errors, statistics, scene settings and vertices, for firmware that logs with
//! `defmt`. Written by hand here, so the types' own modules carry no feature gates.
//! Fixed-point numbers print their raw bits with the format's name
//! (`Q16_16(65536)` is 1.0): defmt has no fixed-point display hint.

use defmt::{write, Format, Formatter};

use crate::fixed::{Angle, NumError, Q16_16, Q2_14};
use crate::geometry::{MeshError, Viewport};
use crate::light::{Light, LightKind, Material};
use crate::raster::perspective::Perspective;
use crate::raster::ScreenVertex;
use crate::render::{RenderError, Stats, XfVertex};
use crate::scene::{Camera, CapacityError, Placement, Projection, ShadingMode};
use crate::target::TargetError;

impl Format for Q16_16 {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "Q16_16({=i32})", self.to_bits())
    }
}

impl Format for Q2_14 {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "Q2_14({=i16})", self.to_bits())
    }
}

impl Format for Angle {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "Angle({=u32} / 2^32 turn)", self.to_turns_bits())
    }
}

impl Format for NumError {
    fn format(&self, f: Formatter<'_>) {
        match self {
            NumError::NotFinite => write!(f, "NotFinite"),
            NumError::OutOfRange => write!(f, "OutOfRange"),
        }
    }
}

impl Format for MeshError {
    fn format(&self, f: Formatter<'_>) {
        match self {
            MeshError::NormalCount => write!(f, "NormalCount"),
            MeshError::TooManyVertices => write!(f, "TooManyVertices"),
            MeshError::IndexOutOfRange(t) => write!(f, "IndexOutOfRange({=usize})", t),
            MeshError::CoordinateOutOfRange(v) => {
                write!(f, "CoordinateOutOfRange({=usize})", v)
            }
        }
    }
}

impl Format for Viewport {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Viewport {{ width: {=u32}, height: {=u32} }}",
            self.width, self.height
        )
    }
}

impl Format for ScreenVertex {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "ScreenVertex {{ x: {=i32}, y: {=i32}, z: {=u32}, c: {} }}",
            self.x, self.y, self.z, self.c
        )
    }
}

impl Format for Perspective {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "Perspective(every {=u32} px)", self.span())
    }
}

impl Format for XfVertex {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "XfVertex {{ s: {}, flags: {=u8} }}", self.s, self.flags)
    }
}

impl Format for Stats {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Stats {{ triangles: {=u32}, culled: {=u32}, degenerate: {=u32}, outside: {=u32}, clipped: {=u32}, drawn: {=u32}, pixels: {=u32}, fallback: {=u32}, per_pixel: {=u32}, evaluations: {=u32} }}",
            self.triangles,
            self.culled,
            self.degenerate,
            self.outside,
            self.clipped,
            self.drawn,
            self.pixels,
            self.fallback,
            self.per_pixel,
            self.evaluations
        )
    }
}

impl Format for RenderError {
    fn format(&self, f: Formatter<'_>) {
        match self {
            RenderError::CacheTooSmall { needed } => {
                write!(f, "CacheTooSmall {{ needed: {=usize} }}", needed)
            }
            RenderError::BadSize => write!(f, "BadSize"),
            RenderError::BadView => write!(f, "BadView"),
            RenderError::BadProjection => write!(f, "BadProjection"),
            RenderError::SingularModel { object } => {
                write!(f, "SingularModel {{ object: {=usize} }}", object)
            }
            RenderError::TargetSizeMismatch => write!(f, "TargetSizeMismatch"),
            RenderError::TwoSidedUnsupported => write!(f, "TwoSidedUnsupported"),
            RenderError::NoDepthBuffer => write!(f, "NoDepthBuffer"),
            RenderError::SetupMismatch => write!(f, "SetupMismatch"),
            RenderError::CacheNotPrepared => write!(f, "CacheNotPrepared"),
        }
    }
}

impl Format for TargetError {
    fn format(&self, f: Formatter<'_>) {
        match self {
            TargetError::BadSize => write!(f, "BadSize"),
            TargetError::ColorBufferTooSmall => write!(f, "ColorBufferTooSmall"),
            TargetError::DepthBufferTooSmall => write!(f, "DepthBufferTooSmall"),
            TargetError::StripOutsideFrame => write!(f, "StripOutsideFrame"),
        }
    }
}

impl Format for CapacityError {
    fn format(&self, f: Formatter<'_>) {
        write!(f, "CapacityError")
    }
}

impl Format for ShadingMode {
    fn format(&self, f: Formatter<'_>) {
        match self {
            ShadingMode::Flat => write!(f, "Flat"),
            ShadingMode::Gouraud => write!(f, "Gouraud"),
            ShadingMode::QuadraticSurface => write!(f, "QuadraticSurface"),
            ShadingMode::Phong => write!(f, "Phong"),
            ShadingMode::PhongEvenOdd => write!(f, "PhongEvenOdd"),
            ShadingMode::Adaptive => write!(f, "Adaptive"),
        }
    }
}

impl Format for Projection {
    fn format(&self, f: Formatter<'_>) {
        match self {
            Projection::Perspective { fovy, near, far } => write!(
                f,
                "Perspective {{ fovy: {}, near: {}, far: {} }}",
                fovy, near, far
            ),
            Projection::Orthographic { height, near, far } => write!(
                f,
                "Orthographic {{ height: {}, near: {}, far: {} }}",
                height, near, far
            ),
        }
    }
}

impl Format for Camera {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Camera {{ eye: {}, target: {}, up: {}, projection: {} }}",
            self.eye, self.target, self.up, self.projection
        )
    }
}

impl Format for Placement {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Placement {{ translate: {}, rotate: {}, scale: {} }}",
            self.translate, self.rotate, self.scale
        )
    }
}

impl Format for LightKind {
    fn format(&self, f: Formatter<'_>) {
        match self {
            LightKind::Directional { direction } => {
                write!(f, "Directional {{ direction: {} }}", direction)
            }
            LightKind::Point {
                position,
                attenuation,
            } => write!(
                f,
                "Point {{ position: {}, attenuation: {} }}",
                position, attenuation
            ),
        }
    }
}

impl Format for Light {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Light {{ kind: {}, ambient: {}, diffuse: {}, specular: {} }}",
            self.kind, self.ambient, self.diffuse, self.specular
        )
    }
}

impl Format for Material {
    fn format(&self, f: Formatter<'_>) {
        write!(
            f,
            "Material {{ emission: {}, ambient: {}, diffuse: {}, specular: {}, shininess: {} }}",
            self.emission, self.ambient, self.diffuse, self.specular, self.shininess
        )
    }
}
