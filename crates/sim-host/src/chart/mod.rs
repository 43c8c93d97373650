//! Pictures: the one PNG writer, a pixel font, a chart canvas and overlap-free
//! label placement. Imports nothing else of the simulator.

pub mod font;
pub mod labels;
pub mod plot;
pub mod png;
