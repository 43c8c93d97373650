//! Measurements written as documents: the accuracy-versus-time report
//! ([`report`]), the specular models ([`specular`]), the effects ([`effects`]) and
//! pixel-segment ray casting ([`raycast`]).

pub mod effects;
pub mod raycast;
pub mod report;
pub mod specular;
