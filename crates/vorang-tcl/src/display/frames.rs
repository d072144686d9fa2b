//! The viewer's render thread: renders the frames the Tcl thread asks for, one at a time, and
//! hands back each frame (or why there is none) and, for refined frames, each tile as it
//! finishes. The Tcl thread cancels a job through its flag when the view moves on.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::{Receiver, Sender};
use std::time::Instant;

use super::rgba8;
use vorang::framebuffer::{Background, Framebuffer};
use vorang::mapping::Mapping;
use vorang::render::{Rect, Settings, TileSink, Watch};
use vorang::scene::View;
use vorang::session::Backend;
use vorang::volume::Volume;

/// A frame to render: `refined` with the chosen method, else a preview.
pub struct Job {
    pub generation: u64,
    pub refined: bool,
    pub view: View,
    pub settings: Settings,
    pub cancel: Arc<AtomicBool>,
}

/// A rendered frame (or why there is none).
pub struct Done {
    pub generation: u64,
    pub refined: bool,
    pub frame: Result<Framebuffer, String>,
    pub seconds: f64,
}

/// A finished tile of a refined frame: its generation, where it lies, its 8-bit RGBA pixels.
pub type Tile = (u64, Rect, Vec<u8>);

/// Renders the jobs from `jobs` with the session's backend (`vorang view --gpu`: previews and
/// refined frames on the GPU) until that channel closes (or nobody listens any more).
pub fn render(
    backend: &Backend,
    vol: &Arc<Volume>,
    mapping: &Mapping,
    jobs: Receiver<Job>,
    done_send: Sender<Done>,
    tile_send: Sender<Tile>,
) {
    for job in jobs {
        let started = Instant::now();
        let transparent = matches!(job.settings.background, Background::None);
        let generation = job.generation;
        let sink = |rect: Rect, pixels: &[[f32; 4]]| {
            let _ = tile_send.send((generation, rect, rgba8(pixels, transparent)));
        };
        let watch = Watch {
            progress: None,
            tile: job.refined.then_some(&sink as TileSink),
            cancel: &job.cancel,
        };
        let frame = backend
            .render(vol, mapping, &job.view, &job.settings, &watch)
            .map(|(fb, _)| fb)
            .map_err(|e| e.to_string());
        let done = Done {
            generation: job.generation,
            refined: job.refined,
            frame,
            seconds: started.elapsed().as_secs_f64(),
        };
        if done_send.send(done).is_err() {
            break;
        }
    }
}
