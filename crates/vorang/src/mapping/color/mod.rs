//! Colour shading methods (thesis C.2 "Parameter für die Color Shading Methoden").

pub mod absorption_weighted;
pub mod const_cell;
pub mod constant;
pub mod identity;
pub mod lit_emitter;
pub mod simple_emitter;
