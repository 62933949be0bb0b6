//! What each pass of a frame did: its draws, triangles and GPU time (the timestamps around it
//! come from the frame graph, `crate::frame`).

use super::PassId;
use serde::Serialize;

/// What one recorded pass did and how long the GPU spent on it.
#[derive(Clone, Debug, Serialize)]
pub struct PassReport {
    /// Pass name, as in the debug label (`ambient`, `light 0 (point)`, `readback`).
    pub name: String,
    /// The light the pass serves, if any.
    pub light: Option<usize>,
    /// Draw calls recorded.
    pub draws: u32,
    /// Triangles submitted.
    pub triangles: u64,
    /// GPU time between the timestamps around the pass (`None` without timestamp support).
    pub gpu_ms: Option<f64>,
    /// A diagnostic pass (overdraw, classification views): not part of the technique's cost,
    /// and left out of `FrameReport::total_gpu_ms`.
    pub diagnostic: bool,
    /// Which pass it was (not serialised: `name` says the same in the JSON report).
    #[serde(skip)]
    pub id: PassId,
}

/// The draws one pass recorded so far.
#[derive(Default)]
pub(crate) struct PassLog {
    draws: u32,
    triangles: u64,
}

impl PassLog {
    /// Counts a draw of `triangles` in the pass.
    pub fn count_draw(&mut self, triangles: u64) {
        self.draws += 1;
        self.triangles += triangles;
    }

    /// The report of pass `id` (its GPU time is filled in once the submission completed).
    pub fn report(&self, id: PassId) -> PassReport {
        PassReport {
            name: id.name(),
            light: id.light(),
            draws: self.draws,
            triangles: self.triangles,
            gpu_ms: None,
            diagnostic: id.diagnostic(),
            id,
        }
    }
}
