//! Pictures: the one PNG writer, a pixel font and a chart canvas. Imports nothing
//! else of the simulator.

pub mod font;
pub mod plot;
pub mod png;
