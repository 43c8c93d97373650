//! Scenes: the plain description types ([`desc`], [`names`]), scene files
//! ([`mod@file`]), the built-in scenes ([`builtin`]), meshes ([`mesh`]), the conversion
//! to the core's fixed-point scene ([`convert`]), the effect rules ([`effects`]) and
//! loading ([`load`]). Imports nothing of the simulator above it.

pub mod builtin;
pub mod convert;
pub mod desc;
pub mod effects;
pub mod file;
pub mod load;
pub mod mesh;
pub mod names;
