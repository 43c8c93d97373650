//! Effects: what a scene calls for, derived from its content by named rules,
//! overridable in the scene file (`[render] effects = "-depth,+specular"`) and on the
//! command line (`--effects LIST`), and applied so that a frame pays for the effects
//! it uses and nothing else.
//!
//! The rules ([`derive()`]) only switch off work whose result the scene cannot show,
//! so a derived frame has the pixels of the frame the scene file describes (the
//! tests check this); a forced setting may change the pixels (`-specular` drops the
//! highlights). The run-time choice becomes a type of the core's pipeline: depth test
//! [`fixshade::raster::span::DepthTest`] or `NoDepth`, lighting with a specular model
//! or [`fixshade::effects::NoSpecular`], the shading mode; see
//! [`crate::render::specular_pipeline`].

use super::desc::{Effect, LightKind, MeshData, Projection, SceneDesc, ShadingName, SpecularName};
use super::desc::{Overrides, Source};
use super::load::LoadedScene;

/// How much lighting a frame computes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Lighting {
    /// No lights: every colour is emission + global ambient · k_a.
    Unlit,
    /// Ambient and diffuse terms, no specular term.
    Diffuse,
    /// Ambient, diffuse and specular terms.
    Specular,
}

impl Lighting {
    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Lighting::Unlit => "none",
            Lighting::Diffuse => "diffuse",
            Lighting::Specular => "diffuse+specular",
        }
    }
}

/// One chosen setting and the rule that chose it.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting<T> {
    /// The value.
    pub value: T,
    /// The rule, in words.
    pub why: String,
}

fn set<T>(value: T, why: impl Into<String>) -> Setting<T> {
    Setting {
        value,
        why: why.into(),
    }
}

/// The effects of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Effects {
    /// Depth test.
    pub depth: Setting<bool>,
    /// Back-face culling.
    pub cull: Setting<bool>,
    /// Lighting.
    pub lighting: Setting<Lighting>,
    /// Shading mode.
    pub shading: Setting<ShadingName>,
    /// Directional and point lights in use.
    pub lights: Setting<(usize, usize)>,
    /// Local viewer.
    pub local_viewer: Setting<bool>,
    /// Perspective-correct interpolation of Gouraud colours and Phong normals.
    pub perspective: Setting<bool>,
    /// Two-sided lighting (back faces lit with the negated normal and the back
    /// material: [`fixshade::effects::TwoSided`]).
    pub two_sided: Setting<bool>,
}

fn nonzero(c: &[f64; 3]) -> bool {
    c.iter().any(|v| *v > 0.0)
}

/// True if some light and some material (front, or back under two-sided
/// lighting) both have a specular colour, so the specular term can light a pixel.
pub fn has_specular(d: &SceneDesc) -> bool {
    let back = |o: &super::desc::ObjectDesc| {
        d.two_sided && o.back_material.is_some_and(|b| nonzero(&b.specular))
    };
    d.lights.iter().any(|l| nonzero(&l.specular))
        && d.objects
            .iter()
            .any(|o| nonzero(&o.material.specular) || back(o))
}

/// True if `+specular` is forced (scene file or command line): the frame runs the
/// specular term even when nothing in the scene has one.
pub fn forced_specular(d: &SceneDesc) -> bool {
    matches!(d.effects.get(Effect::Specular), Some((true, _)))
}

/// True if every triangle of `m` has every vertex on or behind its plane (within
/// 1e-6 of the mesh's size, and at least four Q16.16 units): a convex surface, whose front faces never overlap on
/// screen from any viewpoint.
pub fn is_convex(m: &MeshData) -> bool {
    let size = m
        .positions
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(1e-12);
    // The meshes are quantised to Q16.16: a flat pair of triangles may bend by a
    // few units of 2^-16, which is not a concavity.
    let eps = (1e-6 * size).max(4.0 / 65536.0);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let (u, v) = (sub(b, a), sub(c, a));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len == 0.0 {
            continue;
        }
        for p in &m.positions {
            let d = sub(*p, a);
            if (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / len > eps {
                return false;
            }
        }
    }
    true
}

/// Derives the effects of `ls` by the rules, then applies the overrides of
/// `ls.desc.effects` (scene file and command line). Errors for an override that
/// cannot be honoured (`+lighting` or `+specular` without lights).
pub fn derive(ls: &LoadedScene) -> Result<Effects, String> {
    let d = &ls.desc;
    let forced = |e: Effect| d.effects.get(e);

    // Lighting.
    let mut lighting = if d.lights.is_empty() {
        set(
            Lighting::Unlit,
            "no lights: every colour is emission + global ambient·k_a",
        )
    } else if has_specular(d) {
        set(
            Lighting::Specular,
            "a light and a material both have a specular colour",
        )
    } else if !d.lights.iter().any(|l| nonzero(&l.specular)) {
        set(Lighting::Diffuse, "no light has a specular colour")
    } else {
        set(Lighting::Diffuse, "k_s = 0 on every material")
    };
    if let Some((on, src)) = forced(Effect::Lighting) {
        if on && d.lights.is_empty() {
            return Err("effects: +lighting: the scene has no lights".into());
        }
        if !on {
            lighting = set(Lighting::Unlit, src.why());
        }
    }
    if let Some((on, src)) = forced(Effect::Specular) {
        if on && d.lights.is_empty() {
            return Err("effects: +specular: the scene has no lights".into());
        }
        if on {
            lighting = set(Lighting::Specular, src.why());
        } else if lighting.value == Lighting::Specular {
            lighting = set(Lighting::Diffuse, src.why());
        }
    }

    // Shading.
    let shading = match (lighting.value, d.shading) {
        (_, ShadingName::RAYCAST) => set(d.shading, "as set (the ray caster has its own pipeline)"),
        (Lighting::Unlit, s) if s != ShadingName::FLAT => set(
            ShadingName::FLAT,
            "unlit: the colour is constant over each object",
        ),
        (Lighting::Diffuse, ShadingName::ADAPTIVE) => set(
            ShadingName::GOURAUD,
            "adaptive without a specular term: no triangle can hold a highlight",
        ),
        (_, s) => set(s, "as set by the scene file or --shading"),
    };

    // Lights.
    let lights = if lighting.value == Lighting::Unlit {
        set((0, 0), "unlit")
    } else {
        let dir = d
            .lights
            .iter()
            .filter(|l| matches!(l.kind, LightKind::Directional { .. }))
            .count();
        set((dir, d.lights.len() - dir), "the scene's [[light]] tables")
    };

    // Local viewer.
    let mut local_viewer = if !d.local_viewer {
        set(
            false,
            "the scene sets local_viewer = false (or leaves it out)",
        )
    } else if lighting.value != Lighting::Specular {
        set(
            false,
            "no specular term: the direction to the viewer is unused",
        )
    } else {
        set(true, "the scene sets local_viewer = true")
    };
    if let Some((on, src)) = forced(Effect::LocalViewer) {
        local_viewer = set(on, src.why());
    }

    // Culling.
    let mut cull = set(
        d.cull_back,
        if d.cull_back {
            "the scene sets cull = \"back\" (or leaves it out)"
        } else {
            "the scene sets cull = \"none\""
        },
    );
    if let Some((on, src)) = forced(Effect::Cull) {
        cull = set(on, src.why());
    }

    // Depth test.
    let mut depth = if !d.depth_test {
        set(false, "the scene sets depth_test = false")
    } else if !cull.value {
        set(
            true,
            "back faces are drawn (no culling): surfaces may overlap",
        )
    } else if ls.meshes.len() != 1 {
        set(true, "several objects may overlap")
    } else if !is_convex(&ls.meshes[0]) {
        set(true, "the mesh is not convex: its front faces may overlap")
    } else {
        set(
            false,
            "one convex mesh with back-face culling: front faces never overlap",
        )
    };
    if let Some((on, src)) = forced(Effect::Depth) {
        depth = set(on, src.why());
    }

    // Perspective correction.
    let mut perspective = match d.camera.projection {
        Projection::Orthographic { .. } => set(
            false,
            "orthographic camera: screen-space interpolation is exact",
        ),
        Projection::Perspective { .. } if d.perspective_correct => set(
            true,
            "asked for by the scene (perspective_correct = true)",
        ),
        Projection::Perspective { .. } => set(
            false,
            "the scene interpolates in screen space (perspective_correct = false, the seeds' Gouraud)",
        ),
    };
    if let Some((on, src)) = forced(Effect::Perspective) {
        perspective = set(on, src.why());
    }
    // Gouraud colours and Phong normals and positions are corrected.
    let corrected = match shading.value {
        ShadingName::GOURAUD | ShadingName::PHONG_EVEN_ODD | ShadingName::ADAPTIVE => Ok(()),
        ShadingName::PHONG if !d.raycast.sampled => Ok(()),
        ShadingName::PHONG => Err(
            "sampled Phong lighting (the segment sampler): its attributes interpolate in \
             screen space",
        ),
        ShadingName::FLAT => Err("flat shading: one colour per triangle, nothing to correct"),
        ShadingName::QUADRATIC => {
            Err("the quadratic surface interpolates in screen space (not corrected)")
        }
        _ => Err("ray casting: each pixel is cast, nothing to correct"),
    };
    if let (true, Err(why)) = (perspective.value, corrected) {
        perspective = set(false, why);
    }

    // Two-sided lighting.
    let back_material = d.objects.iter().any(|o| o.back_material.is_some());
    let two_sided = if !d.two_sided {
        set(false, "the scene sets two_sided = false (or leaves it out)")
    } else if cull.value {
        set(
            false,
            "back faces are culled: no back face is drawn to show it",
        )
    } else if lighting.value == Lighting::Unlit && !back_material {
        set(
            false,
            "unlit and no back material: both sides have the same colour",
        )
    } else {
        set(true, "the scene sets two_sided = true and draws back faces")
    };

    Ok(Effects {
        depth,
        cull,
        lighting,
        shading,
        lights,
        local_viewer,
        perspective,
        two_sided,
    })
}

/// `ls` with its description set to the effects `e`: depth test, culling, shading,
/// local viewer; unlit drops the lights; diffuse zeroes every specular colour (so
/// the pipeline runs without the specular term); `+specular` is kept in the
/// overrides so [`crate::render::specular_pipeline`] runs the specular term even
/// when nothing in the scene has one.
pub fn apply(ls: &LoadedScene, e: &Effects) -> LoadedScene {
    let mut out = ls.clone();
    let d = &mut out.desc;
    d.depth_test = e.depth.value;
    d.cull_back = e.cull.value;
    d.shading = e.shading.value;
    d.local_viewer = e.local_viewer.value;
    d.perspective_correct = e.perspective.value;
    d.two_sided = e.two_sided.value;
    match e.lighting.value {
        Lighting::Unlit => d.lights.clear(),
        Lighting::Diffuse => {
            for l in &mut d.lights {
                l.specular = [0.0; 3];
            }
            for o in &mut d.objects {
                o.material.specular = [0.0; 3];
                if let Some(b) = &mut o.back_material {
                    b.specular = [0.0; 3];
                }
            }
        }
        Lighting::Specular => {}
    }
    let mut keep = Overrides::default();
    if e.lighting.value == Lighting::Specular {
        keep.0.push((Effect::Specular, true, Source::CommandLine));
    }
    d.effects = keep;
    out
}

/// The scene with every effect on: depth test, the specular term with the exact
/// model, Phong shading; culling, lights and local viewer as the scene sets.
pub fn everything_on(ls: &LoadedScene) -> LoadedScene {
    let mut out = ls.clone();
    let d = &mut out.desc;
    d.depth_test = true;
    d.shading = ShadingName::PHONG;
    d.specular = SpecularName::EXACT;
    d.effects = Overrides(vec![(Effect::Specular, true, Source::CommandLine)]);
    out
}
