//! The frame graph (see `docs/architecture.md`): passes declared in order with the images and
//! buffers they use; barriers, debug labels, timestamps and query pools come from here.

mod graph;
mod pass_id;
mod states;
pub(crate) mod timing;

pub(crate) use graph::{FrameGraph, PassRecorder, QueryId, Stage, StageResults, Use};
pub use pass_id::PassId;
