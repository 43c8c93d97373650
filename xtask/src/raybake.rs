//! Ray-cast scenes baked for the Cortex-M4 image (`boards/baked/ray/`): the scene as
//! `fixshade bake` writes it, plus the ray caster's analytic spheres and planes and
//! the scene's sampling (segment L, threshold K in Q8, shadows). `cargo xtask bake`
//! writes them.

use fixshade_sim::render::bake;
use fixshade_sim::scene::convert::{self, q16, threshold_q8};
use fixshade_sim::scene::desc::MaterialDesc;
use fixshade_sim::scene::load;

/// (file under boards/baked/ray, built-in scene).
pub const RAY_SCENES: &[(&str, &str)] = &[
    ("spheres_plane.rs", "spheres-plane"),
    ("sphere.rs", "sphere"),
];

fn v3(v: &[f64; 3]) -> String {
    bake::v3(&v.map(q16))
}

fn material(m: &MaterialDesc) -> String {
    bake::material_src(&convert::material(m))
}

/// The source of one baked ray scene.
pub fn bake_ray(scene: &str) -> Result<String, String> {
    let command = format!("cargo xtask bake ({scene})");
    let mut s = fixshade_sim::render::bake::bake(scene, None, &command)?.source;
    let ls = load::load_arg(scene)?;
    let r = &ls.desc.raycast;
    s.push_str(&format!(
        "\n// The ray caster's part of the scene (added by `cargo xtask bake`).\n\n\
         use fixshade::raycast::{{Plane, Sphere}};\n\n\
         /// Segment length L of the scene's sampling.\n\
         pub const SEGMENT: u32 = {};\n\
         /// Threshold K of the scene's sampling, Q8 8-bit levels ({}).\n\
         pub const K_Q8: u32 = {};\n\
         /// Hard shadows from the first light.\n\
         pub const SHADOWS: bool = {};\n\
         /// Analytic spheres.\n\
         pub const SPHERES: [Sphere; {}] = [\n",
        r.segment,
        r.threshold,
        threshold_q8(r.threshold),
        r.shadows,
        r.spheres.len()
    ));
    for sp in &r.spheres {
        s.push_str(&format!(
            "    Sphere {{ centre: {}, radius: {}, material: {} }},\n",
            v3(&sp.centre),
            bake::q(q16(sp.radius)),
            material(&sp.material)
        ));
    }
    s.push_str(&format!(
        "];\n/// Planes.\npub const PLANES: [Plane; {}] = [\n",
        r.planes.len()
    ));
    for p in &r.planes {
        s.push_str(&format!(
            "    Plane {{ point: {}, normal: {}, material: {} }},\n",
            v3(&p.point),
            v3(&p.normal),
            material(&p.material)
        ));
    }
    s.push_str("];\n");
    Ok(s)
}
