//! Ctrl-C at the prompt: during a render it cancels that render (the
//! command fails with "the render was cancelled" and the session goes on); anywhere else it
//! ends the program as usual, so that a runaway Tcl loop can still be stopped.
//!
//! The program's SIGINT handler ([`on_interrupt`]) reads [`RENDERING`]: the render commands
//! set it while they run and pass [`CANCEL`] to the renderer, whose tiles check it.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set while a render command runs.
pub static RENDERING: AtomicBool = AtomicBool::new(false);
/// Set by Ctrl-C during a render; cleared when the next render starts.
pub static CANCEL: AtomicBool = AtomicBool::new(false);

/// What the SIGINT handler does: `true` when a render was running and is now asked to stop,
/// `false` when the program should end. Only atomics: safe in a signal handler.
pub fn on_interrupt() -> bool {
    if RENDERING.load(Ordering::SeqCst) {
        CANCEL.store(true, Ordering::SeqCst);
        true
    } else {
        false
    }
}

/// Marks a render as running for as long as the guard lives.
pub struct Rendering;

impl Rendering {
    pub fn start() -> Rendering {
        CANCEL.store(false, Ordering::SeqCst);
        RENDERING.store(true, Ordering::SeqCst);
        Rendering
    }
}

impl Drop for Rendering {
    fn drop(&mut self) {
        RENDERING.store(false, Ordering::SeqCst);
    }
}
