//! Per-pass GPU timing: a timestamp before and after each pass, and a debug label around it.

use serde::Serialize;
use umbra_vk::{QueryKind, QueryPool, Recorder};

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
}

/// The passes recorded so far in a frame.
#[derive(Default)]
pub(crate) struct PassLog {
    passes: Vec<PassReport>,
}

impl PassLog {
    /// Counts a draw of `triangles` in the open pass.
    pub fn count_draw(&mut self, triangles: u64) {
        if let Some(p) = self.passes.last_mut() {
            p.draws += 1;
            p.triangles += triangles;
        }
    }
}

/// Timestamps and labels passes in one command buffer.
pub(crate) struct PassTimer {
    pool: Option<QueryPool>,
}

impl PassTimer {
    /// A timer for at most `max_passes` passes, reusing `previous`'s query pool when it holds
    /// enough timestamps (a frame's timer is kept for the next); without timestamps it only
    /// labels.
    pub fn new(ctx: &umbra_vk::Context, max_passes: usize, previous: Option<Self>) -> umbra_vk::VkResult<Self> {
        if !ctx.capabilities().timestamps {
            return Ok(Self { pool: None });
        }
        let needed = 2 * max_passes.max(1) as u32;
        match previous.and_then(|p| p.pool).filter(|p| p.count >= needed) {
            Some(pool) => Ok(Self { pool: Some(pool) }),
            None => Ok(Self { pool: Some(QueryPool::new(ctx, "pass timestamps", QueryKind::Timestamp, needed)?) }),
        }
    }

    /// Resets the queries; record once before the first pass.
    pub fn reset<'a>(&'a self, rec: &mut Recorder<'a>) {
        if let Some(p) = &self.pool {
            rec.reset_queries(p);
        }
    }

    /// Opens a pass: label plus start timestamp.
    pub fn begin<'a>(&'a self, rec: &mut Recorder<'a>, log: &mut PassLog, name: String, light: Option<usize>) {
        self.open(rec, log, PassReport { name, light, draws: 0, triangles: 0, gpu_ms: None, diagnostic: false });
    }

    /// Opens a diagnostic pass (see [`PassReport::diagnostic`]).
    pub fn begin_diagnostic<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        log: &mut PassLog,
        name: String,
        light: Option<usize>,
    ) {
        let pass = PassReport { name, light, draws: 0, triangles: 0, gpu_ms: None, diagnostic: true };
        self.open(rec, log, pass);
    }

    fn open<'a>(&'a self, rec: &mut Recorder<'a>, log: &mut PassLog, pass: PassReport) {
        rec.begin_label(&pass.name);
        let index = 2 * log.passes.len() as u32;
        log.passes.push(pass);
        if let Some(p) = &self.pool {
            rec.write_timestamp(p, index);
        }
    }

    /// Closes the last pass opened: end timestamp plus end of label.
    pub fn end<'a>(&'a self, rec: &mut Recorder<'a>, log: &PassLog) {
        if let Some(p) = &self.pool {
            rec.write_timestamp(p, 2 * log.passes.len() as u32 - 1);
        }
        rec.end_label();
    }

    /// After the submission completed: the passes with their GPU times.
    pub fn finish(&self, log: PassLog) -> umbra_vk::VkResult<Vec<PassReport>> {
        let mut passes = log.passes;
        if let (Some(pool), false) = (&self.pool, passes.is_empty()) {
            let stamps = pool.first_results(2 * passes.len() as u32)?;
            for (i, p) in passes.iter_mut().enumerate() {
                p.gpu_ms = Some(pool.elapsed_ns(&stamps, 2 * i, 2 * i + 1) / 1e6);
            }
        }
        Ok(passes)
    }
}
