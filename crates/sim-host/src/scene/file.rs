//! TOML scene files: parsing and validation.
//!
//! A scene file describes one image: its size and pixel format, how triangles are
//! rasterized, a `gluLookAt` camera, OpenGL fixed-function lights and materials, and
//! the objects to draw. [`parse_scene`] turns the text into a [`SceneDesc`];
//! [`load_scene`] reads a file first. Every error is a [`SceneError`] that names the
//! file and, where the problem belongs to a key, value or table header, its 1-based
//! line: `scenes/x.toml:12: `fovy` must be between 0 and 180 degrees (exclusive),
//! found 200`. Nothing in here panics, whatever the input.
//!
//! # Format
//!
//! All tables are optional except `[camera]` (for its `eye`) and at least one
//! `[[object]]`. Unknown tables and unknown keys are errors, so typos do not pass
//! silently. Numbers must be finite (`nan` and `inf` are rejected); an integer is
//! accepted wherever a float is expected, but not the other way round. A "vector" is
//! an array of exactly 3 numbers; a "colour" is a vector whose components lie in
//! `[0, 1]` (linear RGB). Names (formats, modes, meshes, ...) are matched without
//! regard to ASCII case.
//!
//! ## `[image]`
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `width` | integer | 320 | 1..=4096 |
//! | `height` | integer | 240 | 1..=4096 |
//! | `format` | string | `"rgb565le"` | `rgb565le`, `rgb565be`, `rgb888`, `gray8` ([`FormatName`]) |
//! | `background` | array of 3 integers | `[0, 0, 0]` | each 0..=255 (8-bit RGB) |
//!
//! ## `[render]`
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `shading` | string | `"gouraud"` | `flat`, `gouraud`, `quadratic`, `phong`, `phong-even-odd`, `adaptive`, `raycast` ([`ShadingName`]) |
//! | `specular` | string | `"exact"` | `exact`, `schlick`, `schlick-mod`, `quadratic`, `cos-quad`, `cos-quad-energy` ([`SpecularName`]; the reference is always exact) |
//! | `span` | string | `"gradient"` | `classic`, `gradient`, `even-odd`, `kway2`, `kway3`, `kway4`, `counter`, `segment2`, `segment4`, `segment8`, `segment16`, `segment32`, `segment64`, `sierpinski`, `sierpinski-exact` ([`SpanName`]) |
//! | `divide` | string | `"exact"` | `exact`, `table`, `shift-add-N`, `shift-add-rounded-N` (N = 4..=16) ([`DivideName`]; the divider of the classic span division, the setup reciprocal (of every shading: Gouraud, quadratic, Phong, adaptive), the perspective division and Schlick's denominator; `exact` keeps the full-precision divisions) |
//! | `cull` | string | `"back"` | `back` (cull clockwise triangles), `none` |
//! | `depth_test` | boolean | `true` | |
//! | `depth_bits` | integer | 16 | 16 or 32: bits per depth cell (`u16` or `u32`); 16 suffice while far/near stays below about 2¹⁶ times the smallest depth gap the scene must resolve relative to the far distance (see `fixshade::target::DepthFormat`), 32 take twice the memory |
//! | `perspective_correct` | boolean | `false` | perspective-correct Gouraud colours and Phong normals and eye positions, adaptive both (the fixed-point renderer and the reference; flat needs none, the quadratic surface and sampled Phong interpolate affinely); see docs/effects.md |
//! | `perspective_span` | integer | 16 | 1, 2, 4, …, 64: pixels per perspective division of the fixed-point renderer (1: every pixel; otherwise linear in between) |
//! | `segment` | integer | 8 | 1..=256; `raycast`, and `phong` when given: segment length L of the pixel-segment sampler (1: every pixel; Phong samples within pieces of 64 pixels of a span) |
//! | `threshold` | number | 2.3 | 0..=256; `raycast`, and `phong` when given: K, the largest channel difference (8-bit levels) of two segment ends that still interpolates |
//! | `block` | boolean | `false` | `raycast` only: sample L × L blocks instead of row segments |
//! | `shadows` | boolean | `true` | `raycast` only: hard shadows from the first light |
//! | `effects` | string | `""` | effects forced on or off, e.g. `"-depth,+specular"`: comma-separated `+NAME`/`-NAME` with NAME one of `depth`, `cull`, `specular`, `lighting`, `local-viewer`, `perspective`; see docs/effects.md |
//!
//! ## `[camera]` (required)
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `eye` | vector | required | |
//! | `target` | vector | `[0, 0, 0]` | must differ from `eye` |
//! | `up` | vector | `[0, 1, 0]` | non-zero, not parallel to `target - eye` |
//! | `projection` | string | `"perspective"` | `perspective`, `orthographic` |
//! | `fovy` | number | 45 | degrees, strictly between 0 and 180; perspective only |
//! | `height` | number | 2 | view-volume height in world units, > 0; orthographic only |
//! | `near` | number | 1 | perspective: 2⁻¹⁶ (0.0000152587890625, the smallest positive Q16.16 number the core takes) up to `far`; orthographic: any value from −32768 up to `far` |
//! | `far` | number | 100 | > `near` (also after rounding both to Q16.16), at most 32767.99998 (the largest Q16.16 number) |
//!
//! ## `[lighting]`
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `global_ambient` | colour | `[0.2, 0.2, 0.2]` | OpenGL's `GL_LIGHT_MODEL_AMBIENT` |
//! | `local_viewer` | boolean | `false` | OpenGL's `GL_LIGHT_MODEL_LOCAL_VIEWER` |
//! | `two_sided` | boolean | `false` | OpenGL's `GL_LIGHT_MODEL_TWO_SIDE`: a back face (clockwise on screen) is lit with its normals negated and its object's `back_material`; only shows with `cull = "none"`; not with `adaptive` or `raycast` shading (an error), nor with a divider other than `exact` (an error); see docs/effects.md |
//!
//! ## `[[light]]` (0 to 8 of them)
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `type` | string | required | `directional`, `point` |
//! | `direction` | vector | required for `directional` | from the surface towards the light, non-zero; directional only |
//! | `position` | vector | required for `point` | world space; point only |
//! | `attenuation` | vector | `[1, 0, 0]` | constant, linear, quadratic; each >= 0, not all 0; point only |
//! | `ambient` | colour | `[0, 0, 0]` | |
//! | `diffuse` | colour | `[1, 1, 1]` | |
//! | `specular` | colour | `[1, 1, 1]` | |
//!
//! ## `[material]`
//!
//! The default material of every object; the defaults are OpenGL's.
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `emission` | colour | `[0, 0, 0]` | |
//! | `ambient` | colour | `[0.2, 0.2, 0.2]` | |
//! | `diffuse` | colour | `[0.8, 0.8, 0.8]` | |
//! | `specular` | colour | `[0, 0, 0]` | |
//! | `shininess` | number | 1 | 1..=1000 (Blinn exponent) |
//!
//! ## `[[object]]` (1 to 16 of them)
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `mesh` | string | required | `sphere`, `teapot`, `robot`, `obj` |
//! | `lon` | integer | 32 | 3..=1024; sphere only (longitude segments) |
//! | `lat` | integer | 20 | 2..=1024; sphere only (latitude segments) |
//! | `level` | integer | 8 | 1..=64; teapot only (subdivisions per patch side) |
//! | `path` | string | required for `obj` | non-empty; obj only. A relative path is kept relative: the caller resolves it against the scene file's directory. The file's `vn` normals are used when its faces give them (hard edges stay hard), else normals are recomputed; each material group (`usemtl` of an `mtllib` file) is drawn as an object of its own with this object's placement (all objects together at most 16) |
//! | `translate` | vector | `[0, 0, 0]` | world units |
//! | `rotate` | vector | `[0, 0, 0]` | degrees about x, y and z (x applied first) |
//! | `scale` | number | 1 | > 0 (uniform) |
//! | `material` | table | the `[material]` table | written `[object.material]` after the `[[object]]` header; the keys given override `[material]` for this object, with the same types and ranges. For an OBJ with MTL materials: without this table each group draws with its MTL material (`Kd`, `Ka`, `Ks`, `Ke`, `Ns`), keys the MTL file leaves out taken from `[material]`; with it, this material replaces the MTL materials for every group |
//! | `back_material` | table | the object's material | written `[object.back_material]` after the `[[object]]` header: the material of the object's back faces under `two_sided = true`; the keys given override the object's material (`[object.material]` over `[material]`; not an OBJ's MTL materials), with the same types and ranges |
//!
//! ## `[[sphere]]` and `[[plane]]` (0 to 8 spheres, 0 to 4 planes)
//!
//! Analytic primitives drawn by `shading = "raycast"` only (the rasterizer draws
//! the `[[object]]` meshes alone); a scene still needs at least one `[[object]]`.
//!
//! | key | type | default | range |
//! |-----|------|---------|-------|
//! | `centre` | vector | `[0, 0, 0]` | sphere only; world space |
//! | `radius` | number | 1 | sphere only; > 0 |
//! | `point` | vector | `[0, 0, 0]` | plane only; a point of the plane, world space |
//! | `normal` | vector | `[0, 1, 0]` | plane only; non-zero (both sides are lit) |
//! | `material` | table | the `[material]` table | written `[sphere.material]` / `[plane.material]`; overrides like `[object.material]` |
//!
//! # Example
//!
//! Every table and most keys, with their defaults where the comment says so:
//!
//! ```toml
//! [image]
//! width = 320                  # default 320
//! height = 240                 # default 240
//! format = "rgb565le"          # default
//! background = [16, 20, 32]    # default [0, 0, 0]
//!
//! [render]
//! shading = "gouraud"          # default
//! span = "gradient"            # default
//! divide = "exact"             # default
//! cull = "back"                # default
//! depth_test = true            # default
//! depth_bits = 16              # default; 32 for u32 depth cells
//! perspective_correct = false  # default
//!
//! [camera]
//! eye = [0.0, 1.0, 4.0]        # required
//! target = [0.0, 0.0, 0.0]     # default
//! up = [0.0, 1.0, 0.0]         # default
//! projection = "perspective"   # default
//! fovy = 45.0                  # default
//! near = 1.0                   # default
//! far = 10.0                   # default 100
//!
//! [lighting]
//! global_ambient = [0.2, 0.2, 0.2]  # default
//! local_viewer = false              # default
//! two_sided = false                 # default
//!
//! [[light]]
//! type = "directional"
//! direction = [-0.5, 0.7, 0.8]
//! ambient = [0.0, 0.0, 0.0]    # default
//! diffuse = [1.0, 1.0, 1.0]    # default
//! specular = [1.0, 1.0, 1.0]   # default
//!
//! [[light]]
//! type = "point"
//! position = [2.0, 3.0, 2.0]
//! attenuation = [1.0, 0.05, 0.01]   # default [1, 0, 0]
//! diffuse = [0.4, 0.4, 0.5]
//! specular = [0.0, 0.0, 0.0]
//!
//! [material]
//! emission = [0.0, 0.0, 0.0]   # default
//! ambient = [0.2, 0.2, 0.2]    # default
//! diffuse = [0.8, 0.8, 0.8]    # default
//! specular = [0.5, 0.5, 0.5]   # default [0, 0, 0]
//! shininess = 32               # default 1
//!
//! [[object]]
//! mesh = "sphere"
//! lon = 32                     # default
//! lat = 20                     # default
//! translate = [-1.2, 0.0, 0.0]
//! scale = 0.8
//!
//! [object.material]            # overrides [material] for this object only
//! diffuse = [0.9, 0.45, 0.12]
//!
//! [object.back_material]       # its back faces under two_sided = true
//! diffuse = [0.2, 0.3, 0.8]
//!
//! [[object]]
//! mesh = "teapot"
//! level = 8                    # default
//! translate = [1.2, 0.0, 0.0]
//! rotate = [15.0, -30.0, 0.0]
//!
//! [[object]]
//! mesh = "obj"
//! path = "models/bunny.obj"    # relative to this file's directory
//! translate = [0.0, 0.0, -2.0]
//! ```
//!
//! The built-in scenes (`fixshade list` names them; text in `crates/sim-host/scenes/`) are
//! further examples.

use super::convert::{q16, Q16_MAX, Q16_MIN_POSITIVE};
use super::desc::{
    CameraDesc, DivideName, FormatName, LightDesc, LightKind, MaterialDesc, MaterialFrom,
    MeshSource, Named, ObjectDesc, Projection, SceneDesc, ShadingName, SpanName, SpecularName,
};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// A scene file that could not be read, parsed or validated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The file name as given to [`parse_scene`] or [`load_scene`].
    pub file: String,
    /// The 1-based line of the offending key, value or table header; `None` for
    /// errors about the whole file (read errors, a missing `[camera]` or `[[object]]`).
    pub line: Option<usize>,
    /// What is wrong, in one sentence.
    pub message: String,
}

impl fmt::Display for SceneError {
    /// `file:line: message`, or `file: message` without a line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file, line, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// Reads and parses a scene file. The error's `file` is `path` as given; read errors
/// (missing file, not UTF-8, ...) become a [`SceneError`] without a line. Relative OBJ
/// paths in the scene stay relative: resolve them against `path`'s directory.
pub fn load_scene(path: &Path) -> Result<SceneDesc, SceneError> {
    let file = path.display().to_string();
    match std::fs::read_to_string(path) {
        Ok(text) => parse_scene(&text, &file),
        Err(e) => Err(SceneError {
            file,
            line: None,
            message: format!("cannot read scene file: {e}"),
        }),
    }
}

/// Parses and validates the text of a scene file; `file_name` only appears in errors.
/// The format is described in the [module documentation](self).
pub fn parse_scene(text: &str, file_name: &str) -> Result<SceneDesc, SceneError> {
    let to_error = |fail: Fail| SceneError {
        file: file_name.to_string(),
        line: fail.span.map(|s| line_of(text, s.start)),
        message: fail.message,
    };
    let doc = DeTable::parse(text).map_err(|e| {
        to_error(Fail {
            span: e.span(),
            message: format!("TOML syntax error: {}", one_line(e.message())),
        })
    })?;
    scene(doc.get_ref()).map_err(to_error)
}

/// 1-based line of byte offset `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    1 + text.as_bytes()[..end]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
}

/// Collapses a possibly multi-line message into one line.
fn one_line(message: &str) -> String {
    let parts: Vec<&str> = message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    parts.join("; ")
}

type Span = Range<usize>;
type Val<'i> = Spanned<DeValue<'i>>;

/// An error before the file name and line are attached.
struct Fail {
    span: Option<Span>,
    message: String,
}

type R<T> = Result<T, Fail>;

fn fail<T>(span: Span, message: impl Into<String>) -> R<T> {
    Err(Fail {
        span: Some(span),
        message: message.into(),
    })
}

fn fail_file<T>(message: impl Into<String>) -> R<T> {
    Err(Fail {
        span: None,
        message: message.into(),
    })
}

// ---------------------------------------------------------------------------------
// Key names of every table, in documentation order (used in "expected one of").

const TOP_KEYS: &[&str] = &[
    "image", "render", "camera", "lighting", "light", "material", "object", "sphere", "plane",
];
const TOP_TITLES: &str =
    "[image], [render], [camera], [lighting], [[light]], [material], [[object]], [[sphere]], [[plane]]";
const IMAGE_KEYS: &[&str] = &["width", "height", "format", "background"];
const RENDER_KEYS: &[&str] = &[
    "shading",
    "specular",
    "span",
    "divide",
    "cull",
    "depth_test",
    "depth_bits",
    "perspective_correct",
    "perspective_span",
    "segment",
    "threshold",
    "block",
    "shadows",
    "effects",
];
const CAMERA_KEYS: &[&str] = &[
    "eye",
    "target",
    "up",
    "projection",
    "fovy",
    "height",
    "near",
    "far",
];
const LIGHTING_KEYS: &[&str] = &["global_ambient", "local_viewer", "two_sided"];
const LIGHT_KEYS: &[&str] = &[
    "type",
    "direction",
    "position",
    "attenuation",
    "ambient",
    "diffuse",
    "specular",
];
const MATERIAL_KEYS: &[&str] = &["emission", "ambient", "diffuse", "specular", "shininess"];
const OBJECT_KEYS: &[&str] = &[
    "mesh",
    "lon",
    "lat",
    "level",
    "path",
    "translate",
    "rotate",
    "scale",
    "material",
    "back_material",
];

/// Most lights a scene may have.
const MAX_LIGHTS: usize = 8;
/// Most objects a scene may have.
const MAX_OBJECTS: usize = 16;
/// Largest image side.
const MAX_SIDE: i64 = 4096;

// ---------------------------------------------------------------------------------
// A table being read.

/// The entries of one table, sorted by position in the file, with unknown keys
/// already rejected.
struct Section<'t, 'i> {
    /// How error messages name the table: `[camera]`, `[[light]]`, ...
    title: &'static str,
    /// Span of the table's header (or inline table, or dotted key).
    span: Span,
    /// Key, span of the key, value.
    entries: Vec<(&'t str, Span, &'t Val<'i>)>,
}

impl<'t, 'i> Section<'t, 'i> {
    /// Reads table `table` (spanning `span`), rejecting keys not in `allowed`.
    fn new(
        title: &'static str,
        span: Span,
        table: &'t DeTable<'i>,
        allowed: &[&str],
    ) -> R<Section<'t, 'i>> {
        let mut entries: Vec<(&'t str, Span, &'t Val<'i>)> = table
            .iter()
            .map(|(k, v)| (k.get_ref().as_ref(), k.span(), v))
            .collect();
        entries.sort_by_key(|(_, s, _)| s.start);
        for (key, key_span, _) in &entries {
            if !allowed.contains(key) {
                return fail(
                    key_span.clone(),
                    format!(
                        "unknown key `{key}` in {title}; expected one of: {}",
                        allowed.join(", ")
                    ),
                );
            }
        }
        Ok(Section {
            title,
            span,
            entries,
        })
    }

    /// Reads the table value `value` of key `key`.
    fn from_value(
        title: &'static str,
        key: &str,
        value: &'t Val<'i>,
        allowed: &[&str],
    ) -> R<Section<'t, 'i>> {
        match value.get_ref() {
            DeValue::Table(t) => Section::new(title, value.span(), t, allowed),
            other => fail(
                value.span(),
                format!("`{key}` must be a table, found {}", other.type_str()),
            ),
        }
    }

    /// The value of `key`, if present.
    fn get(&self, key: &str) -> Option<&'t Val<'i>> {
        self.entries
            .iter()
            .find(|(k, _, _)| *k == key)
            .map(|(_, _, v)| *v)
    }

    /// Span of the line to blame for `key`: its value if present, else the header.
    fn span_of(&self, key: &str) -> Span {
        self.get(key).map_or(self.span.clone(), |v| v.span())
    }

    /// Error for a required key that is missing.
    fn missing<T>(&self, key: &str, extra: &str) -> R<T> {
        fail(
            self.span.clone(),
            format!("missing key `{key}` in {}{extra}", self.title),
        )
    }

    /// Error if `key` is present: it does not apply here.
    fn forbid(&self, key: &str, why: &str) -> R<()> {
        match self.entries.iter().find(|(k, _, _)| *k == key) {
            Some((_, key_span, _)) => fail(key_span.clone(), format!("`{key}` {why}")),
            None => Ok(()),
        }
    }

    fn number(&self, key: &str, default: f64) -> R<f64> {
        self.get(key).map_or(Ok(default), |v| number(key, v))
    }

    fn vector(&self, key: &str, default: [f64; 3]) -> R<[f64; 3]> {
        self.get(key).map_or(Ok(default), |v| vector(key, v))
    }

    fn colour(&self, key: &str, default: [f64; 3]) -> R<[f64; 3]> {
        self.get(key).map_or(Ok(default), |v| colour(key, v))
    }

    fn boolean(&self, key: &str, default: bool) -> R<bool> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => match v.get_ref() {
                DeValue::Boolean(b) => Ok(*b),
                other => fail(
                    v.span(),
                    format!("`{key}` must be a boolean, found {}", other.type_str()),
                ),
            },
        }
    }

    /// An integer in `lo..=hi`.
    fn int_in(&self, key: &str, default: u32, lo: i64, hi: i64) -> R<u32> {
        let Some(v) = self.get(key) else {
            return Ok(default);
        };
        let (n, text) = integer(key, v)?;
        match n {
            Some(n) if (lo..=hi).contains(&n) => u32::try_from(n)
                .or_else(|_| fail(v.span(), format!("`{key}` is out of range, found {text}"))),
            _ => fail(
                v.span(),
                format!("`{key}` must be between {lo} and {hi}, found {text}"),
            ),
        }
    }

    /// A name from `names`, as its index; `what` names the kind in errors.
    fn choice(&self, key: &str, default: usize, what: &str, names: &[&str]) -> R<usize> {
        let Some(v) = self.get(key) else {
            return Ok(default);
        };
        let s = string(key, v)?;
        names
            .iter()
            .position(|n| n.eq_ignore_ascii_case(s))
            .ok_or_else(|| Fail {
                span: Some(v.span()),
                message: format!(
                    "unknown {what} `{s}`; expected one of: {}",
                    names.join(", ")
                ),
            })
    }

    /// A [`Named`] enum value.
    fn named<T: Named>(&self, key: &str, default: T) -> R<T> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => T::parse(string(key, v)?).or_else(|msg| fail(v.span(), msg)),
        }
    }
}

// ---------------------------------------------------------------------------------
// Values.

/// A string value.
fn string<'t>(key: &str, v: &'t Val<'_>) -> R<&'t str> {
    match v.get_ref() {
        DeValue::String(s) => Ok(s.as_ref()),
        other => fail(
            v.span(),
            format!("`{key}` must be a string, found {}", other.type_str()),
        ),
    }
}

/// An integer value: `Some(n)` if it fits in i64, and its text.
fn integer(key: &str, v: &Val<'_>) -> R<(Option<i64>, String)> {
    match v.get_ref() {
        DeValue::Integer(i) => {
            let n = i64::from_str_radix(i.as_str(), i.radix()).ok();
            let text = match n {
                Some(n) => n.to_string(),
                None => i.as_str().to_string(),
            };
            Ok((n, text))
        }
        other => fail(
            v.span(),
            format!("`{key}` must be an integer, found {}", other.type_str()),
        ),
    }
}

/// A finite number (integer or float).
fn number(key: &str, v: &Val<'_>) -> R<f64> {
    let (n, text) = match v.get_ref() {
        DeValue::Integer(i) => {
            let n = i64::from_str_radix(i.as_str(), i.radix())
                .map(|n| n as f64)
                .ok();
            (n, i.as_str())
        }
        DeValue::Float(f) => (f.as_str().parse::<f64>().ok(), f.as_str()),
        other => {
            return fail(
                v.span(),
                format!("`{key}` must be a number, found {}", other.type_str()),
            )
        }
    };
    match n {
        Some(n) if n.is_finite() => Ok(n),
        _ => fail(
            v.span(),
            format!("`{key}` must be a finite number, found {text}"),
        ),
    }
}

/// An array of 3 finite numbers.
fn vector(key: &str, v: &Val<'_>) -> R<[f64; 3]> {
    let items = match v.get_ref() {
        DeValue::Array(a) if a.len() == 3 => a,
        DeValue::Array(a) => {
            return fail(
                v.span(),
                format!(
                    "`{key}` must be an array of 3 numbers, found an array of {}",
                    a.len()
                ),
            )
        }
        other => {
            return fail(
                v.span(),
                format!(
                    "`{key}` must be an array of 3 numbers, found {}",
                    other.type_str()
                ),
            )
        }
    };
    let mut out = [0.0; 3];
    for (o, item) in out.iter_mut().zip(items.iter()) {
        *o = number(key, item).map_err(|f| Fail {
            message: f.message.replacen(
                &format!("`{key}` must be"),
                &format!("`{key}` components must each be"),
                1,
            ),
            ..f
        })?;
    }
    Ok(out)
}

/// A colour: 3 numbers in [0, 1].
fn colour(key: &str, v: &Val<'_>) -> R<[f64; 3]> {
    let c = vector(key, v)?;
    if let DeValue::Array(items) = v.get_ref() {
        for (x, item) in c.iter().zip(items.iter()) {
            if !(0.0..=1.0).contains(x) {
                return fail(
                    item.span(),
                    format!("`{key}` components must be between 0 and 1, found {x}"),
                );
            }
        }
    }
    Ok(c)
}

/// Formats a vector for messages: `[0, 1, 0]`.
fn fmt_v3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm2(a: [f64; 3]) -> f64 {
    a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
}

// ---------------------------------------------------------------------------------
// Tables.

/// The whole document.
fn scene(doc: &DeTable<'_>) -> R<SceneDesc> {
    let mut top: Vec<(&str, Span, &Val<'_>)> = doc
        .iter()
        .map(|(k, v)| (k.get_ref().as_ref(), k.span(), v))
        .collect();
    top.sort_by_key(|(_, s, _)| s.start);
    for (key, key_span, value) in &top {
        if !TOP_KEYS.contains(key) {
            let what = if value.get_ref().is_table() {
                format!("unknown table [{key}]")
            } else {
                format!("unknown key `{key}` at the top level")
            };
            return fail(
                key_span.clone(),
                format!("{what}; expected one of: {TOP_TITLES}"),
            );
        }
    }
    let get = |key: &str| top.iter().find(|(k, _, _)| *k == key).map(|(_, _, v)| *v);

    let Some(objects_value) = get("object") else {
        return fail_file("no [[object]]: a scene needs at least one [[object]] table");
    };
    let Some(camera_value) = get("camera") else {
        return fail_file("no [camera]: a scene needs a [camera] table with at least `eye`");
    };

    let mut desc = SceneDesc {
        width: 320,
        height: 240,
        format: FormatName::RGB565LE,
        background: [0, 0, 0],
        camera: CameraDesc {
            eye: [0.0; 3],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            projection: Projection::Perspective {
                fovy_deg: 45.0,
                near: 1.0,
                far: 100.0,
            },
        },
        lights: Vec::new(),
        global_ambient: [0.2, 0.2, 0.2],
        local_viewer: false,
        two_sided: false,
        objects: Vec::new(),
        shading: ShadingName::GOURAUD,
        span: SpanName::GRADIENT,
        cull_back: true,
        depth_test: true,
        depth_bits: 16,
        perspective_correct: false,
        perspective_span: super::desc::DEFAULT_PERSPECTIVE_SPAN,
        specular: SpecularName::EXACT,
        divide: DivideName::EXACT,
        raycast: super::desc::RaycastDesc::default(),
        effects: Default::default(),
    };

    if let Some(v) = get("image") {
        image(
            &Section::from_value("[image]", "image", v, IMAGE_KEYS)?,
            &mut desc,
        )?;
    }
    if let Some(v) = get("render") {
        render(
            &Section::from_value("[render]", "render", v, RENDER_KEYS)?,
            &mut desc,
        )?;
    }
    desc.camera = camera(&Section::from_value(
        "[camera]",
        "camera",
        camera_value,
        CAMERA_KEYS,
    )?)?;
    if let Some(v) = get("lighting") {
        let s = Section::from_value("[lighting]", "lighting", v, LIGHTING_KEYS)?;
        desc.global_ambient = s.colour("global_ambient", desc.global_ambient)?;
        desc.local_viewer = s.boolean("local_viewer", desc.local_viewer)?;
        desc.two_sided = s.boolean("two_sided", desc.two_sided)?;
    }
    if let Some(v) = get("light") {
        for item in array_of_tables("light", v, MAX_LIGHTS, "lights")? {
            let s = Section::from_value("[[light]]", "light", item, LIGHT_KEYS)?;
            desc.lights.push(light(&s)?);
        }
    }
    let material = match get("material") {
        Some(v) => material(
            &Section::from_value("[material]", "material", v, MATERIAL_KEYS)?,
            MaterialDesc::default(),
        )?,
        None => MaterialDesc::default(),
    };
    let items = array_of_tables("object", objects_value, MAX_OBJECTS, "objects")?;
    if items.is_empty() {
        return fail(
            objects_value.span(),
            "no [[object]]: a scene needs at least one [[object]] table",
        );
    }
    for item in items {
        let s = Section::from_value("[[object]]", "object", item, OBJECT_KEYS)?;
        desc.objects.push(object(&s, material)?);
    }
    raycast_primitives(&get, material, &mut desc)?;
    Ok(desc)
}

/// The items of an array of tables (`[[key]]`), at most `max` of them.
fn array_of_tables<'t, 'i>(
    key: &str,
    v: &'t Val<'i>,
    max: usize,
    plural: &str,
) -> R<&'t [Val<'i>]> {
    let items: &[Val<'i>] = match v.get_ref() {
        DeValue::Array(a) => a,
        DeValue::Table(_) => {
            return fail(
                v.span(),
                format!("`{key}` must be an array of tables: write [[{key}]], not [{key}]"),
            )
        }
        other => {
            return fail(
                v.span(),
                format!(
                    "`{key}` must be an array of tables ([[{key}]]), found {}",
                    other.type_str()
                ),
            )
        }
    };
    if let Some(extra) = items.get(max) {
        return fail(
            extra.span(),
            format!("too many {plural}: at most {max} [[{key}]] tables are allowed"),
        );
    }
    Ok(items)
}

fn image(s: &Section<'_, '_>, desc: &mut SceneDesc) -> R<()> {
    desc.width = s.int_in("width", desc.width, 1, MAX_SIDE)?;
    desc.height = s.int_in("height", desc.height, 1, MAX_SIDE)?;
    desc.format = s.named("format", desc.format)?;
    if let Some(v) = s.get("background") {
        let items = match v.get_ref() {
            DeValue::Array(a) if a.len() == 3 => a,
            other => {
                let found = match other {
                    DeValue::Array(a) => format!("an array of {}", a.len()),
                    other => other.type_str().to_string(),
                };
                return fail(
                    v.span(),
                    format!(
                        "`background` must be an array of 3 integers (8-bit RGB), found {found}"
                    ),
                );
            }
        };
        for (c, item) in desc.background.iter_mut().zip(items.iter()) {
            let (n, text) = integer("background", item).map_err(|f| Fail {
                message: f
                    .message
                    .replacen("must be an integer", "components must be integers", 1),
                ..f
            })?;
            *c = match n.and_then(|n| u8::try_from(n).ok()) {
                Some(n) => n,
                None => {
                    return fail(
                        item.span(),
                        format!("`background` components must be between 0 and 255, found {text}"),
                    )
                }
            };
        }
    }
    Ok(())
}

fn render(s: &Section<'_, '_>, desc: &mut SceneDesc) -> R<()> {
    desc.shading = s.named("shading", desc.shading)?;
    desc.specular = s.named("specular", desc.specular)?;
    desc.divide = s.named("divide", desc.divide)?;
    desc.span = s.named("span", desc.span)?;
    desc.cull_back = s.choice("cull", 0, "cull mode", &["back", "none"])? == 0;
    desc.depth_test = s.boolean("depth_test", desc.depth_test)?;
    desc.depth_bits = s.int_in("depth_bits", desc.depth_bits, 0, u32::MAX as i64)?;
    if desc.depth_bits != 16 && desc.depth_bits != 32 {
        return fail(
            s.span_of("depth_bits"),
            format!("`depth_bits` must be 16 or 32, found {}", desc.depth_bits),
        );
    }
    desc.perspective_correct = s.boolean("perspective_correct", desc.perspective_correct)?;
    desc.perspective_span = s.int_in("perspective_span", desc.perspective_span, 1, 64)?;
    if !desc.perspective_span.is_power_of_two() {
        return fail(
            s.span_of("perspective_span"),
            format!(
                "`perspective_span` must be 1, 2, 4, 8, 16, 32 or 64, found {}",
                desc.perspective_span
            ),
        );
    }
    if let Some(v) = s.get("effects") {
        let list = string("effects", v)?;
        desc.effects = super::desc::Overrides::parse(list, super::desc::Source::SceneFile)
            .or_else(|m| fail(v.span(), m))?;
    }
    raycast_render_keys(s, &mut desc.raycast)
}

fn camera(s: &Section<'_, '_>) -> R<CameraDesc> {
    let Some(eye_value) = s.get("eye") else {
        return s.missing("eye", ", the camera position");
    };
    let eye = vector("eye", eye_value)?;
    let target = s.vector("target", [0.0; 3])?;
    let up = s.vector("up", [0.0, 1.0, 0.0])?;
    let dir = sub(target, eye);
    // Blame `target` if given, else `eye`.
    let target_span = s.get("target").unwrap_or(eye_value).span();
    if norm2(dir) == 0.0 {
        return fail(
            target_span,
            format!("`target` must differ from `eye`, both are {}", fmt_v3(eye)),
        );
    }
    if norm2(up) == 0.0 {
        return fail(s.span_of("up"), "`up` must not be the zero vector");
    }
    // sin² of the angle between up and the view direction.
    let sin2 = norm2(cross(up, dir)) / (norm2(up) * norm2(dir));
    // (NaN when the vectors are so large that the products overflow.)
    if sin2.is_nan() || sin2 <= 1e-12 {
        let (span, which) = match s.get("up") {
            Some(v) => (v.span(), format!("`up` {}", fmt_v3(up))),
            None => (target_span, format!("`up` (default {})", fmt_v3(up))),
        };
        return fail(
            span,
            format!(
                "{which} is parallel to the view direction `target - eye` = {}",
                fmt_v3(dir)
            ),
        );
    }

    let ortho = s.choice(
        "projection",
        0,
        "projection",
        &["perspective", "orthographic"],
    )? == 1;
    let near = s.number("near", 1.0)?;
    let far = s.number("far", 100.0)?;
    let projection = if ortho {
        s.forbid("fovy", "is only valid for a perspective projection")?;
        let height = s.number("height", 2.0)?;
        if height <= 0.0 {
            return fail(
                s.span_of("height"),
                format!("`height` must be greater than 0, found {height}"),
            );
        }
        Projection::Orthographic { height, near, far }
    } else {
        s.forbid(
            "height",
            "is only valid for an orthographic projection (use `fovy` for perspective)",
        )?;
        let fovy = s.number("fovy", 45.0)?;
        if !(fovy > 0.0 && fovy < 180.0) {
            return fail(
                s.span_of("fovy"),
                format!("`fovy` must be between 0 and 180 degrees (exclusive), found {fovy}"),
            );
        }
        if near < Q16_MIN_POSITIVE {
            return fail(
                s.span_of("near"),
                format!(
                    "`near` must be at least {Q16_MIN_POSITIVE} (2^-16, the smallest positive \
                     Q16.16 number the core takes) for a perspective projection, found {near}"
                ),
            );
        }
        Projection::Perspective {
            fovy_deg: fovy,
            near,
            far,
        }
    };
    // The core compares the planes after rounding to Q16.16 (`Mat4::perspective`,
    // `Mat4::orthographic`: `far > near`), and larger values would saturate.
    for (key, value) in [("near", near), ("far", far)] {
        if !(-32768.0..=Q16_MAX).contains(&value) {
            return fail(
                s.span_of(key),
                format!("`{key}` must be between -32768 and {Q16_MAX} (the Q16.16 range), found {value}"),
            );
        }
    }
    if q16(far) <= q16(near) {
        return match s.get("far") {
            Some(v) => fail(
                v.span(),
                format!("`far` must be greater than `near` ({near}), found {far}"),
            ),
            None => fail(
                s.span_of("near"),
                format!("`near` must be less than `far` ({far}, the default), found {near}"),
            ),
        };
    }
    Ok(CameraDesc {
        eye,
        target,
        up,
        projection,
    })
}

fn light(s: &Section<'_, '_>) -> R<LightDesc> {
    if s.get("type").is_none() {
        return s.missing("type", "; it must be \"directional\" or \"point\"");
    }
    let point = s.choice("type", 0, "light type", &["directional", "point"])? == 1;
    let kind = if point {
        s.forbid(
            "direction",
            "is only valid for directional lights (a point light has a `position`)",
        )?;
        let Some(p) = s.get("position") else {
            return s.missing("position", ", which a point light needs");
        };
        let position = vector("position", p)?;
        let attenuation = s.vector("attenuation", [1.0, 0.0, 0.0])?;
        if let Some(v) = s.get("attenuation") {
            if let DeValue::Array(items) = v.get_ref() {
                for (x, item) in attenuation.iter().zip(items.iter()) {
                    if *x < 0.0 {
                        return fail(
                            item.span(),
                            format!("`attenuation` components must not be negative, found {x}"),
                        );
                    }
                }
            }
            if attenuation == [0.0; 3] {
                return fail(v.span(), "`attenuation` must not be all zero");
            }
        }
        LightKind::Point {
            position,
            attenuation,
        }
    } else {
        s.forbid(
            "position",
            "is only valid for point lights (a directional light has a `direction`)",
        )?;
        s.forbid("attenuation", "is only valid for point lights")?;
        let Some(d) = s.get("direction") else {
            return s.missing("direction", ", which a directional light needs");
        };
        let direction = vector("direction", d)?;
        if norm2(direction) == 0.0 {
            return fail(d.span(), "`direction` must not be the zero vector");
        }
        LightKind::Directional { direction }
    };
    Ok(LightDesc {
        kind,
        ambient: s.colour("ambient", [0.0; 3])?,
        diffuse: s.colour("diffuse", [1.0; 3])?,
        specular: s.colour("specular", [1.0; 3])?,
    })
}

/// A material table: the keys present override `base`.
fn material(s: &Section<'_, '_>, base: MaterialDesc) -> R<MaterialDesc> {
    let m = MaterialDesc {
        emission: s.colour("emission", base.emission)?,
        ambient: s.colour("ambient", base.ambient)?,
        diffuse: s.colour("diffuse", base.diffuse)?,
        specular: s.colour("specular", base.specular)?,
        shininess: s.number("shininess", base.shininess)?,
    };
    if !(1.0..=1000.0).contains(&m.shininess) {
        return fail(
            s.span_of("shininess"),
            format!(
                "`shininess` must be between 1 and 1000, found {}",
                m.shininess
            ),
        );
    }
    Ok(m)
}

fn object(s: &Section<'_, '_>, base: MaterialDesc) -> R<ObjectDesc> {
    const MESHES: &[&str] = &["sphere", "teapot", "robot", "obj"];
    if s.get("mesh").is_none() {
        return s.missing("mesh", "; it must be one of: sphere, teapot, robot, obj");
    }
    let kind = s.choice("mesh", 0, "mesh", MESHES)?;
    // Keys that belong to one mesh kind only.
    for (key, owner) in [("lon", 0), ("lat", 0), ("level", 1), ("path", 3)] {
        if kind != owner {
            s.forbid(
                key,
                &format!(
                    "is only valid for {} meshes (this object's mesh is {})",
                    MESHES[owner], MESHES[kind]
                ),
            )?;
        }
    }
    let mesh = match kind {
        0 => MeshSource::Sphere {
            lon: s.int_in("lon", 32, 3, 1024)?,
            lat: s.int_in("lat", 20, 2, 1024)?,
        },
        1 => MeshSource::Teapot {
            level: s.int_in("level", 8, 1, 64)?,
        },
        2 => MeshSource::Robot,
        _ => {
            let Some(p) = s.get("path") else {
                return s.missing("path", ", which an obj mesh needs");
            };
            let path = string("path", p)?;
            if path.is_empty() {
                return fail(p.span(), "`path` must not be empty");
            }
            MeshSource::Obj {
                path: PathBuf::from(path),
            }
        }
    };
    let scale = s.number("scale", 1.0)?;
    if scale <= 0.0 {
        return fail(
            s.span_of("scale"),
            format!("`scale` must be greater than 0, found {scale}"),
        );
    }
    let (material, material_from) = match s.get("material") {
        Some(v) => (
            material(
                &Section::from_value("[object.material]", "material", v, MATERIAL_KEYS)?,
                base,
            )?,
            MaterialFrom::Object,
        ),
        None => (base, MaterialFrom::Scene),
    };
    // The back material's keys override the object's (front) material.
    let back_material = match s.get("back_material") {
        Some(v) => Some(self::material(
            &Section::from_value("[object.back_material]", "back_material", v, MATERIAL_KEYS)?,
            material,
        )?),
        None => None,
    };
    Ok(ObjectDesc {
        mesh,
        translate: s.vector("translate", [0.0; 3])?,
        rotate_deg: s.vector("rotate", [0.0; 3])?,
        scale,
        material,
        material_from,
        back_material,
    })
}

// ---------------------------------------------------------------------------------
// Ray casting (`crate::render::raycast`): sampler keys of [render], [[sphere]], [[plane]].

fn raycast_render_keys(s: &Section<'_, '_>, r: &mut super::desc::RaycastDesc) -> R<()> {
    use super::desc::{MAX_SEGMENT, MAX_THRESHOLD};
    r.segment = s.int_in("segment", r.segment, 1, MAX_SEGMENT as i64)?;
    r.threshold = s.number("threshold", r.threshold)?;
    if !(0.0..=MAX_THRESHOLD).contains(&r.threshold) {
        return fail(
            s.span_of("threshold"),
            format!(
                "`threshold` must be between 0 and {MAX_THRESHOLD} (8-bit levels), found {}",
                r.threshold
            ),
        );
    }
    r.block = s.boolean("block", r.block)?;
    r.sampled |= s.get("segment").is_some() || s.get("threshold").is_some();
    r.shadows = s.boolean("shadows", r.shadows)?;
    Ok(())
}

const SPHERE_KEYS: &[&str] = &["centre", "radius", "material"];
const PLANE_KEYS: &[&str] = &["point", "normal", "material"];

fn primitive_material(
    s: &Section<'_, '_>,
    title: &'static str,
    base: MaterialDesc,
) -> R<MaterialDesc> {
    match s.get("material") {
        Some(v) => material(
            &Section::from_value(title, "material", v, MATERIAL_KEYS)?,
            base,
        ),
        None => Ok(base),
    }
}

fn raycast_primitives<'t, 'i>(
    get: &dyn Fn(&str) -> Option<&'t Val<'i>>,
    base: MaterialDesc,
    desc: &mut SceneDesc,
) -> R<()>
where
    'i: 't,
{
    use super::desc::{PlaneDesc, SphereDesc};
    if let Some(v) = get("sphere") {
        for item in array_of_tables("sphere", v, fixshade::raycast::MAX_SPHERES, "spheres")? {
            let s = Section::from_value("[[sphere]]", "sphere", item, SPHERE_KEYS)?;
            let radius = s.number("radius", 1.0)?;
            if radius <= 0.0 {
                return fail(
                    s.span_of("radius"),
                    format!("`radius` must be greater than 0, found {radius}"),
                );
            }
            desc.raycast.spheres.push(SphereDesc {
                centre: s.vector("centre", [0.0; 3])?,
                radius,
                material: primitive_material(&s, "[sphere.material]", base)?,
            });
        }
    }
    if let Some(v) = get("plane") {
        for item in array_of_tables("plane", v, fixshade::raycast::MAX_PLANES, "planes")? {
            let s = Section::from_value("[[plane]]", "plane", item, PLANE_KEYS)?;
            let normal = s.vector("normal", [0.0, 1.0, 0.0])?;
            if norm2(normal) == 0.0 {
                return fail(s.span_of("normal"), "`normal` must not be the zero vector");
            }
            desc.raycast.planes.push(PlaneDesc {
                point: s.vector("point", [0.0; 3])?,
                normal,
                material: primitive_material(&s, "[plane.material]", base)?,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data_dir(sub: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/scenes")
            .join(sub)
    }

    fn toml_files(dir: &Path) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        files.sort();
        files
    }

    const MINIMAL: &str = "[camera]\neye = [0, 0, 5]\n[[object]]\nmesh = \"sphere\"\n";

    fn err(text: &str) -> SceneError {
        parse_scene(text, "t.toml").expect_err("expected an error")
    }

    #[test]
    fn scene_file_bad_corpus_gives_errors_with_lines() {
        let files = toml_files(&data_dir("bad"));
        assert!(files.len() >= 12, "only {} bad scenes", files.len());
        for path in files {
            let text = std::fs::read_to_string(&path).unwrap();
            let first = text.lines().next().unwrap_or("");
            let expect = first
                .strip_prefix("# expect-line:")
                .unwrap_or_else(|| panic!("{}: no `# expect-line:` header", path.display()))
                .trim();
            let expect: Option<usize> = match expect {
                "none" => None,
                n => Some(n.parse().unwrap()),
            };
            let e = load_scene(&path).expect_err(&path.display().to_string());
            let shown = e.to_string();
            let name = path.display().to_string();
            assert!(shown.starts_with(&name), "{shown}");
            assert_eq!(e.line, expect, "{shown}");
            if let Some(line) = expect {
                assert!(shown.starts_with(&format!("{name}:{line}: ")), "{shown}");
            }
            assert!(!e.message.contains('\n'), "{shown}");
        }
    }

    #[test]
    fn scene_file_good_corpus_parses() {
        for path in toml_files(&data_dir("good")) {
            if let Err(e) = load_scene(&path) {
                panic!("{e}");
            }
        }
    }

    #[test]
    fn scene_file_builtins_parse() {
        for name in crate::scene::builtin::SCENES {
            let text = crate::scene::builtin::text(name).unwrap();
            if let Err(e) = parse_scene(text, name) {
                panic!("{e}");
            }
            let s = crate::scene::builtin::scene(name).unwrap();
            assert_eq!((s.width, s.height), (320, 240));
            assert_eq!(s.format, FormatName::RGB565LE);
            let shading = if *name == "spheres-plane" {
                ShadingName::RAYCAST
            } else {
                ShadingName::GOURAUD
            };
            assert_eq!(s.shading, shading);
            assert_eq!(s.span, SpanName::GRADIENT);
            assert!(s.cull_back && s.depth_test);
        }
        assert!(crate::scene::builtin::scene("nope").is_none());
        assert!(crate::scene::builtin::text("nope").is_none());
    }

    #[test]
    fn scene_file_bench_sphere_is_exact() {
        let s = crate::scene::builtin::scene("bench-sphere").unwrap();
        assert_eq!(s.objects.len(), 1);
        let o = &s.objects[0];
        assert_eq!(o.mesh, MeshSource::Sphere { lon: 32, lat: 20 });
        assert_eq!(o.translate, [0.0, 0.0, -3.0]);
        assert_eq!(o.rotate_deg, [0.0; 3]);
        assert_eq!(o.scale, 1.0);
        assert_eq!(o.material.diffuse, [0.7, 0.5, 0.3]);
        assert_eq!(o.material.specular, [0.5, 0.5, 0.5]);
        assert_eq!(o.material.shininess, 32.0);
        assert_eq!(
            s.camera,
            CameraDesc {
                eye: [0.0; 3],
                target: [0.0, 0.0, -1.0],
                up: [0.0, 1.0, 0.0],
                projection: Projection::Perspective {
                    fovy_deg: 45.0,
                    near: 1.0,
                    far: 10.0
                },
            }
        );
        assert_eq!(s.lights.len(), 1);
        assert_eq!(
            s.lights[0].kind,
            LightKind::Directional {
                direction: [0.5, 0.6, 1.0]
            }
        );
        assert_eq!(s.lights[0].diffuse, [1.0; 3]);
        assert_eq!(s.lights[0].specular, [1.0; 3]);
    }

    #[test]
    fn scene_file_defaults_are_the_documented_ones() {
        let s = parse_scene(MINIMAL, "min.toml").unwrap();
        assert_eq!((s.width, s.height), (320, 240));
        assert_eq!(s.format, FormatName::RGB565LE);
        assert_eq!(s.background, [0, 0, 0]);
        assert_eq!(s.shading, ShadingName::GOURAUD);
        assert_eq!(s.span, SpanName::GRADIENT);
        assert!(s.cull_back);
        assert!(s.depth_test);
        assert!(!s.perspective_correct);
        assert_eq!(
            s.camera,
            CameraDesc {
                eye: [0.0, 0.0, 5.0],
                target: [0.0; 3],
                up: [0.0, 1.0, 0.0],
                projection: Projection::Perspective {
                    fovy_deg: 45.0,
                    near: 1.0,
                    far: 100.0
                },
            }
        );
        assert_eq!(s.global_ambient, [0.2, 0.2, 0.2]);
        assert!(!s.local_viewer);
        assert!(s.lights.is_empty());
        assert_eq!(
            s.objects,
            vec![ObjectDesc {
                mesh: MeshSource::Sphere { lon: 32, lat: 20 },
                translate: [0.0; 3],
                rotate_deg: [0.0; 3],
                scale: 1.0,
                material: MaterialDesc::default(),
                material_from: MaterialFrom::Scene,
                back_material: None,
            }]
        );
        assert_eq!(
            MaterialDesc::default(),
            MaterialDesc {
                emission: [0.0; 3],
                ambient: [0.2; 3],
                diffuse: [0.8; 3],
                specular: [0.0; 3],
                shininess: 1.0,
            }
        );

        // Light, teapot, orthographic defaults.
        let s = parse_scene(
            "[camera]\neye = [0, 0, 5]\nprojection = \"orthographic\"\n\
             [[light]]\ntype = \"point\"\nposition = [1, 2, 3]\n\
             [[light]]\ntype = \"directional\"\ndirection = [0, 0, 1]\n\
             [[object]]\nmesh = \"teapot\"\n[[object]]\nmesh = \"robot\"\n",
            "d.toml",
        )
        .unwrap();
        assert_eq!(
            s.camera.projection,
            Projection::Orthographic {
                height: 2.0,
                near: 1.0,
                far: 100.0
            }
        );
        assert_eq!(
            s.lights[0],
            LightDesc {
                kind: LightKind::Point {
                    position: [1.0, 2.0, 3.0],
                    attenuation: [1.0, 0.0, 0.0]
                },
                ambient: [0.0; 3],
                diffuse: [1.0; 3],
                specular: [1.0; 3],
            }
        );
        assert_eq!(s.objects[0].mesh, MeshSource::Teapot { level: 8 });
        assert_eq!(s.objects[1].mesh, MeshSource::Robot);
    }

    #[test]
    fn scene_file_object_material_overrides_default_material() {
        let s = parse_scene(
            "[camera]\neye = [0, 0, 5]\n[material]\nspecular = [0.5, 0.5, 0.5]\nshininess = 20\n\
             [[object]]\nmesh = \"sphere\"\n[object.material]\ndiffuse = [1, 0, 0]\n\
             [[object]]\nmesh = \"obj\"\npath = \"models/a.obj\"\n",
            "m.toml",
        )
        .unwrap();
        let m0 = s.objects[0].material;
        assert_eq!(m0.diffuse, [1.0, 0.0, 0.0]);
        assert_eq!(m0.specular, [0.5; 3]);
        assert_eq!(m0.shininess, 20.0);
        let m1 = s.objects[1].material;
        assert_eq!(m1.diffuse, [0.8; 3]);
        assert_eq!(m1.specular, [0.5; 3]);
        assert_eq!(
            s.objects[1].mesh,
            MeshSource::Obj {
                path: PathBuf::from("models/a.obj")
            }
        );
    }

    #[test]
    fn scene_file_doc_example_parses() {
        let src = include_str!("file.rs");
        let mut lines = src.lines().skip_while(|l| l.trim() != "//! ```toml");
        lines.next();
        let example: String = lines
            .take_while(|l| l.trim() != "//! ```")
            .map(|l| {
                format!(
                    "{}\n",
                    l.trim_start_matches("//!").strip_prefix(' ').unwrap_or("")
                )
            })
            .collect();
        assert!(example.contains("[[object]]"));
        let s = match parse_scene(&example, "doc-example.toml") {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(s.lights.len(), 2);
        assert_eq!(s.objects.len(), 3);
        assert_eq!(s.objects[0].material.diffuse, [0.9, 0.45, 0.12]);
        assert_eq!(s.objects[1].material.diffuse, [0.8; 3]);
        assert_eq!(s.objects[1].material.shininess, 32.0);
    }

    #[test]
    fn scene_file_messages_and_lines() {
        let e = err("[camera]\neye = [0, 0, 5]\nfovy = 200\n[[object]]\nmesh = \"sphere\"\n");
        assert_eq!(
            e.to_string(),
            "t.toml:3: `fovy` must be between 0 and 180 degrees (exclusive), found 200"
        );
        let e = err("[camera]\neye = [0, 0, 5]\nfovx = 20\n[[object]]\nmesh = \"sphere\"\n");
        assert_eq!(
            e.to_string(),
            "t.toml:3: unknown key `fovx` in [camera]; expected one of: \
             eye, target, up, projection, fovy, height, near, far"
        );
        let e = err("");
        assert_eq!(e.line, None);
        assert!(e.to_string().starts_with("t.toml: no [[object]]"), "{e}");
        let e = err("[[object]]\nmesh = \"sphere\"\n");
        assert_eq!(e.line, None);
        // Syntax error: one line, with toml's message.
        let e = err("[camera]\neye = [0, 0,\n\n[[object]]\nmesh = \"sphere\"\n");
        assert!(e.message.starts_with("TOML syntax error: "), "{e}");
        assert!(e.line.is_some(), "{e}");
        // Integers where floats are expected, underscores, hex.
        let s = parse_scene(
            "[image]\nwidth = 0x40\nheight = 1_000\n[camera]\neye = [0, 0, 1_0.5]\n\
             [[object]]\nmesh = \"sphere\"\n",
            "t.toml",
        )
        .unwrap();
        assert_eq!((s.width, s.height), (64, 1000));
        assert_eq!(s.camera.eye, [0.0, 0.0, 10.5]);
        // Case-insensitive names.
        let s = parse_scene(
            "[render]\nspan = \"Classic\"\n[camera]\neye = [0, 0, 5]\n[[object]]\nmesh = \"SPHERE\"\n",
            "t.toml",
        )
        .unwrap();
        assert_eq!(s.span, SpanName::CLASSIC);
        // inf, -nan, float for an integer, huge integers.
        for (text, line) in [
            ("[camera]\neye = [0, 0, inf]\n", 2),
            ("[camera]\neye = [0, 0, -nan]\n", 2),
            ("[image]\nwidth = 320.0\n", 2),
            ("[image]\n\nwidth = 99999999999999999999999\n", 3),
            ("[image]\nbackground = [0, 256, 0]\n", 2),
            ("[image]\nbackground = [0, -1, 0]\n", 2),
            ("[material]\nshininess = 0.5\n", 2),
            ("[camera]\neye = [0, 0, 0]\n", 2),
            ("[camera]\neye = [0, 0, 5]\nup = [0, 0, 0]\n", 3),
            ("[camera]\neye = [0, 5, 0]\n", 2),
            (
                "[camera]\neye = [0, 0, 5]\nprojection = \"orthographic\"\nfovy = 30\n",
                4,
            ),
            ("[camera]\neye = [0, 0, 5]\nheight = 3\n", 3),
            ("[camera]\neye = [0, 0, 5]\nnear = 200\n", 3),
            ("light = 3\n", 1),
            ("[light]\ntype = \"point\"\n", 1),
            ("[[light]]\ntype = \"point\"\n", 1),
            (
                "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\nattenuation = [0, 0, 0]\n",
                4,
            ),
            (
                "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\ndirection = [0, 0, 1]\n",
                4,
            ),
            ("[[light]]\ntype = \"spot\"\n", 2),
            ("[[light]]\ndirection = [0, 0, 1]\n", 1),
            ("[foo]\nx = 1\n", 1),
            ("width = 1\n", 1),
            ("image = 1\n", 1),
        ] {
            let full = format!("{text}[[object]]\nmesh = \"sphere\"\n");
            let full = if text.contains("[camera]") {
                full
            } else {
                format!("{full}[camera]\neye = [0, 0, 5]\n")
            };
            let e = err(&full);
            assert_eq!(e.line, Some(line), "{text:?}: {e}");
        }
        for (text, line) in [
            ("[[object]]\nmesh = \"teapot\"\nlon = 3\n", 3),
            ("[[object]]\nmesh = \"sphere\"\nlat = 1\n", 3),
            ("[[object]]\nmesh = \"obj\"\npath = \"\"\n", 3),
            ("[[object]]\nmesh = \"sphere\"\nscale = 0\n", 3),
            (
                "[[object]]\nmesh = \"sphere\"\n[object.material]\nglow = 1\n",
                4,
            ),
            ("[[object]]\nlon = 4\n", 1),
        ] {
            let e = err(&format!("[camera]\neye = [0, 0, 5]\n{text}"));
            assert_eq!(e.line, Some(line + 2), "{text:?}: {e}");
        }
        let e = err("object = []\n[camera]\neye = [0, 0, 5]\n");
        assert_eq!(e.line, Some(1), "{e}");
        let many: String = (0..17).map(|_| "[[object]]\nmesh = \"robot\"\n").collect();
        let e = err(&format!("[camera]\neye = [0, 0, 5]\n{many}"));
        assert_eq!(e.line, Some(2 + 2 * 16 + 1), "{e}");
    }

    #[test]
    fn scene_file_tiny_near_plane_names_file_line_and_range() {
        let text = "[camera]\neye = [0.0, 0.0, 4.0]\nnear = 1e-6\n[[object]]\nmesh = \"sphere\"\n";
        assert_eq!(
            parse_scene(text, "tiny.toml").unwrap_err().to_string(),
            "tiny.toml:3: `near` must be at least 0.0000152587890625 (2^-16, the smallest \
             positive Q16.16 number the core takes) for a perspective projection, found 0.000001"
        );
        // The smallest accepted near plane is one the core takes.
        let ok = text.replace("1e-6", "0.0000152587890625");
        let d = parse_scene(&ok, "ok.toml").unwrap();
        let c = &crate::scene::convert::quantize_scene(&d).camera;
        assert!(
            matches!(c.projection, Projection::Perspective { near, .. } if near == Q16_MIN_POSITIVE)
        );
        // Planes that collapse on the Q16.16 grid, or leave it, name the range too.
        let e = err("[camera]\neye = [0.0, 0.0, 4.0]\nprojection = \"orthographic\"\nnear = 0.0\nfar = 0.000001\n[[object]]\nmesh = \"sphere\"\n");
        assert_eq!(e.line, Some(5), "{e}");
        let e = err("[camera]\neye = [0.0, 0.0, 4.0]\nfar = 1e6\n[[object]]\nmesh = \"sphere\"\n");
        assert!(
            e.to_string()
                .contains(":3: `far` must be between -32768 and 32767.99998"),
            "{e}"
        );
    }

    #[test]
    fn scene_file_load_errors_name_the_file() {
        let e = load_scene(Path::new("/nonexistent/dir/x.toml")).unwrap_err();
        assert_eq!(e.line, None);
        assert!(e
            .to_string()
            .starts_with("/nonexistent/dir/x.toml: cannot read"));
    }

    #[test]
    fn scene_file_never_panics_on_mangled_input() {
        // Every prefix and a byte-flipped variant of every built-in scene.
        let mut inputs: Vec<String> = Vec::new();
        for name in crate::scene::builtin::SCENES {
            let text = crate::scene::builtin::text(name).unwrap();
            for (i, _) in text.char_indices() {
                inputs.push(text[..i].to_string());
                let mut b = text.as_bytes().to_vec();
                b[i] = match b[i] {
                    b'[' => b']',
                    b'=' => b'[',
                    b'"' => b'.',
                    b'0'..=b'9' => b'-',
                    _ => b'"',
                };
                inputs.push(String::from_utf8_lossy(&b).into_owned());
            }
        }
        for text in inputs {
            let _ = parse_scene(&text, "fuzz.toml").map_err(|e| e.to_string());
        }
    }

    #[test]
    fn raycast_keys_and_primitives() {
        let d = crate::scene::builtin::scene("spheres-plane").unwrap();
        assert_eq!(d.shading, ShadingName::RAYCAST);
        assert_eq!((d.raycast.segment, d.raycast.threshold), (8, 2.3));
        assert_eq!((d.raycast.spheres.len(), d.raycast.planes.len()), (2, 1));
        assert_eq!(d.raycast.spheres[1].radius, 0.45);
        assert_eq!(d.raycast.spheres[0].material.shininess, 60.0);
        // The plane inherits [material] except what [plane.material] overrides.
        assert_eq!(d.raycast.planes[0].material.shininess, 1.0);

        let base = "[camera]\neye = [0, 0, 5]\n[[object]]\nmesh = \"sphere\"\n";
        let e = err(&format!("[render]\nsegment = 0\n{base}"));
        assert_eq!(e.line, Some(2), "{e}");
        let e = err(&format!("[render]\nthreshold = -1\n{base}"));
        assert!(e.message.contains("`threshold`"), "{e}");
        let e = err(&format!("{base}[[sphere]]\nradius = 0\n"));
        assert!(e.message.contains("`radius`"), "{e}");
        let e = err(&format!("{base}[[plane]]\nnormal = [0, 0, 0]\n"));
        assert!(e.message.contains("`normal`"), "{e}");
        let e = err(&format!("{base}[[plane]]\nradius = 1\n"));
        assert!(e.message.contains("radius"), "{e}");
        let many = "[[plane]]\n".repeat(5);
        let e = err(&format!("{base}{many}"));
        assert!(e.message.contains("at most 4"), "{e}");
    }
}
