//! The built-in scenes: the figures, the benchmark sphere and the ray-casting
//! example, whose TOML text is in `crates/sim-host/scenes/`.

use super::desc::SceneDesc;
use super::file::parse_scene;

/// Names of the built-in scenes, for [`scene`] and [`text`].
pub const SCENES: &[&str] = &["sphere", "teapot", "robot", "bench-sphere", "spheres-plane"];

/// The TOML text of a built-in scene (`crates/sim-host/scenes/NAME.toml`), or `None`
/// if there is no built-in scene of that name.
pub fn text(name: &str) -> Option<&'static str> {
    match name {
        "sphere" => Some(include_str!("../../scenes/sphere.toml")),
        "teapot" => Some(include_str!("../../scenes/teapot.toml")),
        "robot" => Some(include_str!("../../scenes/robot.toml")),
        "bench-sphere" => Some(include_str!("../../scenes/bench-sphere.toml")),
        "spheres-plane" => Some(include_str!("../../scenes/spheres-plane.toml")),
        _ => None,
    }
}

/// A built-in scene, parsed, or `None` if there is no built-in scene of that name.
pub fn scene(name: &str) -> Option<SceneDesc> {
    let text = text(name)?;
    parse_scene(text, &format!("scenes/{name}.toml")).ok()
}
