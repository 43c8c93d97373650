//! fixshade host simulator.
pub mod compare;
pub mod desc;
pub mod image;
pub mod mesh;
pub mod reference;
pub mod scene_file;
