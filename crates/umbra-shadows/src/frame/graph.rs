//! The frame graph: a frame is a list of passes, each declared with its id, the images it uses
//! (and the state it uses them in) and the function that records it. Running a [`Stage`] (one
//! command buffer, one submission) records, around every pass and from one place, the batched
//! barrier from each image's last state, the debug label and the two timestamps, with the
//! timestamp and occlusion query pools sized from what was declared and kept between frames.
//! No reordering, no aliasing, no compile step: passes run in the order declared.

use super::states::ImageStates;
use super::timing::{PassLog, PassReport};
use super::PassId;
use crate::RenderResult;
use umbra_vk::{Buffer, BufferState, Context, Image, ImageState, QueryKind, QueryPool, Recorder};

/// What a pass uses: an image in a state, a buffer the GPU writes in a state, or a buffer it
/// copies into for the host to read.
#[derive(Clone, Copy)]
pub(crate) enum Use<'a> {
    /// The image, moved into the state before the pass begins.
    Image(&'a Image, ImageState),
    /// A buffer the GPU writes (a compacted list), with a barrier from its last use before the
    /// pass begins.
    Buffer(&'a Buffer, BufferState),
    /// A host-visible buffer written by a copy, read by the host once the stage completed.
    Readback(&'a Buffer),
}

/// An occlusion query of a stage, reserved with [`Stage::queries`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct QueryId(pub u32);

/// The function that records a pass's commands.
type RecordFn<'a> = Box<dyn FnOnce(&mut PassRecorder<'_, 'a>) -> RenderResult<()> + 'a>;

struct DeclaredPass<'a> {
    id: PassId,
    uses: Vec<Use<'a>>,
    record: RecordFn<'a>,
}

/// The passes of one submission, in order, and the occlusion queries they use.
pub(crate) struct Stage<'a> {
    name: &'static str,
    slot: usize,
    passes: Vec<DeclaredPass<'a>>,
    queries: u32,
}

impl<'a> Stage<'a> {
    /// Reserves `count` occlusion queries; returns the first (the others follow it).
    pub fn queries(&mut self, count: u32) -> QueryId {
        let first = QueryId(self.queries);
        self.queries += count;
        first
    }

    /// Declares the next pass: `id`, the images and buffers it uses, and how it records.
    pub fn pass(
        &mut self,
        id: PassId,
        uses: &[Use<'a>],
        record: impl FnOnce(&mut PassRecorder<'_, 'a>) -> RenderResult<()> + 'a,
    ) {
        self.passes.push(DeclaredPass { id, uses: uses.to_vec(), record: Box::new(record) });
    }
}

/// What a pass records with: the command buffer, its draw counter, the frame's image states
/// (for a state change inside the pass) and the stage's occlusion queries.
pub(crate) struct PassRecorder<'r, 'a> {
    /// The stage's command buffer.
    pub rec: &'r mut Recorder<'a>,
    /// Counts the pass's draws and triangles.
    pub log: &'r mut PassLog,
    states: &'r mut ImageStates,
    queries: Option<&'a QueryPool>,
}

impl<'a> PassRecorder<'_, 'a> {
    /// Moves images into new states inside the pass (one batched barrier from their last states).
    pub fn enter(&mut self, uses: &[(&'a Image, ImageState)]) {
        self.states.enter(self.rec, uses);
    }

    /// Begins occlusion query `query` (reserved in this pass's stage).
    pub fn begin_query(&mut self, query: QueryId) {
        if let Some(pool) = self.queries {
            self.rec.begin_query(pool, query.0);
        }
    }

    /// Ends occlusion query `query`.
    pub fn end_query(&mut self, query: QueryId) {
        if let Some(pool) = self.queries {
            self.rec.end_query(pool, query.0);
        }
    }
}

/// What a stage's submission returned: its passes' reports and its occlusion queries' samples.
pub(crate) struct StageResults {
    /// One per pass, in order, with GPU times where the device has timestamps.
    pub passes: Vec<PassReport>,
    /// The samples of every query reserved, by [`QueryId`].
    pub samples: Vec<u64>,
    /// Host time spent submitting its commands and waiting for them (ms).
    pub submit_wait_ms: f64,
}

impl StageResults {
    /// The samples of query `query`.
    pub fn samples(&self, query: QueryId) -> u64 {
        self.samples.get(query.0 as usize).copied().unwrap_or(0)
    }
}

/// The query pools of every stage slot, kept between frames, and the frame's image states.
#[derive(Default)]
pub(crate) struct FrameGraph {
    timestamps: Vec<Option<QueryPool>>,
    occlusion: Vec<Option<QueryPool>>,
    states: ImageStates,
    stages: usize,
    submissions: u64,
}

impl FrameGraph {
    /// Starts a frame: every image's state is forgotten (its content is discarded at first use).
    pub fn begin_frame(&mut self) {
        self.states.clear();
        self.stages = 0;
    }

    /// A new, empty stage named `name` (its command buffer's debug name).
    pub fn stage<'a>(&mut self, name: &'static str) -> Stage<'a> {
        self.stages += 1;
        Stage { name, slot: self.stages - 1, passes: Vec::new(), queries: 0 }
    }

    /// Sets `image`'s state for this frame without a barrier: an image the engine hands over
    /// in `state`, whose content umbra's passes keep.
    pub fn import(&mut self, image: &Image, state: ImageState) {
        self.states.import(image, state);
    }

    /// `passes`, the reports of this graph's last single-stage frame recorded into a command
    /// buffer umbra does not wait for ([`RecordedStage::into_passes`]), with their GPU times
    /// where the GPU has written them: read before the graph records again, never waiting.
    pub fn earlier_times(&self, mut passes: Vec<PassReport>) -> RenderResult<Vec<PassReport>> {
        if let (Some(t), false) = (pool(&self.timestamps, 0), passes.is_empty()) {
            if let Some(stamps) = t.available_results(2 * passes.len() as u32)? {
                for (i, p) in passes.iter_mut().enumerate() {
                    p.gpu_ms = Some(t.elapsed_ns(&stamps, 2 * i, 2 * i + 1) / 1e6);
                }
            }
        }
        Ok(passes)
    }

    /// Command buffers submitted so far.
    pub fn submissions(&self) -> u64 {
        self.submissions
    }

    /// Records `stage` into a command buffer of its own, submits it and waits for it; returns
    /// its passes' reports and queries.
    pub fn run<'a>(&'a mut self, ctx: &Context, stage: Stage<'a>) -> RenderResult<StageResults> {
        self.submissions += 1;
        let mut rec = ctx.begin_commands(stage.name)?;
        let recorded = self.record(ctx, &mut rec, stage)?;
        rec.transfer_to_host(&recorded.readbacks);
        let waiting = std::time::Instant::now();
        ctx.submit_and_wait(rec)?;
        let submit_wait_ms = waiting.elapsed().as_secs_f64() * 1e3;
        let mut results = recorded.results()?;
        results.submit_wait_ms = submit_wait_ms;
        Ok(results)
    }

    /// Records `stage` into `rec` (a command buffer umbra or the engine began): around every
    /// pass the barrier into the states it declared, its debug label and two timestamps, with
    /// the stage's query pools reset first. Read the results with [`RecordedStage::results`] once
    /// the commands completed.
    pub fn record<'a>(
        &'a mut self,
        ctx: &Context,
        rec: &mut Recorder<'a>,
        stage: Stage<'a>,
    ) -> RenderResult<RecordedStage<'a>> {
        let timestamps = 2 * stage.passes.len() as u32;
        if ctx.capabilities().timestamps {
            reserve(ctx, &mut self.timestamps, stage.slot, "pass timestamps", QueryKind::Timestamp, timestamps)?;
        }
        reserve(ctx, &mut self.occlusion, stage.slot, "occlusion queries", QueryKind::Occlusion, stage.queries)?;
        let (timer, queries) = (pool(&self.timestamps, stage.slot), pool(&self.occlusion, stage.slot));
        let states = &mut self.states;
        for p in [timer, queries].into_iter().flatten() {
            rec.reset_queries(p);
        }
        let mut passes = Vec::with_capacity(stage.passes.len());
        let mut readbacks = Vec::new();
        for (i, pass) in stage.passes.into_iter().enumerate() {
            let images: Vec<_> = pass
                .uses
                .iter()
                .filter_map(|u| match *u {
                    Use::Image(image, state) => Some((image, state)),
                    _ => None,
                })
                .collect();
            let buffers: Vec<_> = pass
                .uses
                .iter()
                .filter_map(|u| match *u {
                    Use::Buffer(buffer, state) => Some((buffer, state)),
                    _ => None,
                })
                .collect();
            readbacks.extend(pass.uses.iter().filter_map(|u| match *u {
                Use::Readback(buffer) => Some(buffer),
                _ => None,
            }));
            states.enter(rec, &images);
            states.enter_buffers(rec, &buffers);
            rec.begin_label(&pass.id.name());
            if let Some(t) = timer {
                rec.write_timestamp(t, 2 * i as u32);
            }
            let mut log = PassLog::default();
            (pass.record)(&mut PassRecorder { rec, log: &mut log, states, queries })?;
            if let Some(t) = timer {
                rec.write_timestamp(t, 2 * i as u32 + 1);
            }
            rec.end_label();
            passes.push(log.report(pass.id));
        }
        Ok(RecordedStage {
            passes,
            timer,
            queries: queries.filter(|_| stage.queries > 0),
            count: stage.queries,
            readbacks,
        })
    }
}

/// A stage recorded into a command buffer, its results not read yet.
pub(crate) struct RecordedStage<'a> {
    passes: Vec<PassReport>,
    timer: Option<&'a QueryPool>,
    queries: Option<&'a QueryPool>,
    count: u32,
    /// The readbacks its passes copied into, for the host to read once it completed.
    pub readbacks: Vec<&'a Buffer>,
}

impl RecordedStage<'_> {
    /// Its passes' reports, their GPU times not read (for [`FrameGraph::earlier_times`]).
    pub fn into_passes(self) -> Vec<PassReport> {
        self.passes
    }

    /// A recorded stage's passes' reports with their GPU times, and its occlusion queries'
    /// samples, once its commands completed.
    pub fn results(self) -> RenderResult<StageResults> {
        let RecordedStage { mut passes, timer, queries, count, .. } = self;
        if let (Some(t), false) = (timer, passes.is_empty()) {
            let stamps = t.first_results(2 * passes.len() as u32)?;
            for (i, p) in passes.iter_mut().enumerate() {
                p.gpu_ms = Some(t.elapsed_ns(&stamps, 2 * i, 2 * i + 1) / 1e6);
            }
        }
        let samples = match queries {
            Some(q) => q.first_results(count)?,
            None => Vec::new(),
        };
        Ok(StageResults { passes, samples, submit_wait_ms: 0.0 })
    }
}

/// Makes sure `pools[slot]` holds at least `count` queries (a new pool only when it does not).
fn reserve(
    ctx: &Context,
    pools: &mut Vec<Option<QueryPool>>,
    slot: usize,
    name: &str,
    kind: QueryKind,
    count: u32,
) -> RenderResult<()> {
    if pools.len() <= slot {
        pools.resize_with(slot + 1, || None);
    }
    if count > 0 && pools[slot].as_ref().is_none_or(|p| p.count < count) {
        pools[slot] = Some(QueryPool::new(ctx, &format!("{name} (stage {slot})"), kind, count)?);
    }
    Ok(())
}

fn pool(pools: &[Option<QueryPool>], slot: usize) -> Option<&QueryPool> {
    pools.get(slot).and_then(Option::as_ref)
}
