//! # vorang-tcl — VoRANG's script language and windows
//!
//! The thesis's script language (thesis 4.2 and appendix A) is real Tcl 8.6 extended by the
//! VoRANG commands ([`script`]); its windows — the `online` display and the interactive viewer —
//! are Tk ([`display`]), over the bindings of the Tcl and Tk C libraries ([`tcl`], [`tk`]).
//! Modules import downwards only: `script` → `display` → `tcl`, `tk`, `report`. Everything here is a thin caller of the core library `vorang`: the
//! commands parse their words and call the session's setters, the windows show what the session
//! renders. This crate is the only one that links libtcl.

// Edit distances and pixel rows index several arrays by the same position (`d[j]`, `prev[j]`),
// which reads like the recurrences they implement.
#![allow(clippy::needless_range_loop)]

pub mod display;
pub mod report;
pub mod script;
pub mod tcl;
pub mod tk;
