//! Alpha shading methods (thesis C.2 "Parameter für die Alpha Shading Methoden").

pub mod bary_shading;
pub mod const_cell;
pub mod constant;
pub mod simple_absorber;
