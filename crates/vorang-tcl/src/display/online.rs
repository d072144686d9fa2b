//! `render_btf online` (thesis A.1): the render runs on a thread of its
//! own while the Tcl thread puts each finished tile into the window and keeps Tk's events
//! flowing, so the picture grows as it renders and the window stays responsive.

use std::sync::mpsc;
use std::time::{Duration, Instant};

use super::{Window, rgba8};
use vorang::render::{Rect, TileSink};

/// How often the Tcl thread lets Tk handle events while a render runs.
const EVENT_INTERVAL: Duration = Duration::from_millis(30);

/// Runs `render` on a new thread, handing it a sink for finished tiles; meanwhile shows those
/// tiles in `window` (converted as an 8-bit file of a framebuffer that is `transparent` or not
/// would hold them) and processes Tk events. Returns what `render` returns; an error if it
/// panicked.
pub fn show_while_rendering<T: Send>(
    window: &Window,
    transparent: bool,
    render: impl FnOnce(TileSink) -> T + Send,
) -> Result<T, String> {
    let (send, receive) = mpsc::channel::<(Rect, Vec<u8>)>();
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            let sink = move |rect: Rect, pixels: &[[f32; 4]]| {
                // The window may be gone (the script ended): nothing to show then.
                let _ = send.send((rect, rgba8(pixels, transparent)));
            };
            render(&sink)
        });
        let mut last_update = Instant::now();
        loop {
            match receive.recv_timeout(EVENT_INTERVAL) {
                // Fails only if the script deleted the photo image: nothing to show then.
                Ok((rect, rgba)) => {
                    let _ = window.put(rect, &rgba);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                // The sink is dropped when the render returns.
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if last_update.elapsed() >= EVENT_INTERVAL {
                window.update();
                last_update = Instant::now();
            }
        }
        worker
            .join()
            .map_err(|_| "internal error: the render thread panicked; please report this".into())
    })
}
