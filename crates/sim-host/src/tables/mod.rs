//! Measurements written as documents: the accuracy-versus-time report
//! ([`report`]) with the seed claims ([`claims`]), the specular models
//! ([`specular`]), the effects ([`effects`]) and pixel-segment ray casting
//! ([`raycast`]); [`provenance`] stamps each with its commit.

pub mod claims;
pub mod effects;
pub mod provenance;
pub mod raycast;
pub mod report;
pub mod specular;
