//! fixshade host simulator.
pub mod bake;
pub mod cli;
pub mod compare;
pub mod convert;
pub mod demo;
pub mod desc;
pub mod effects;
pub mod host_divide;
pub mod image;
pub mod mesh;
pub mod pipeline;
pub mod raycast;
pub mod reference;
pub mod report;
pub mod scene_file;
pub mod specular_table;
