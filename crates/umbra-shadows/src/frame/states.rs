//! The state every image and GPU-written buffer of a frame was last left in, so that each
//! barrier is emitted from the resource's real last state and never from a hand-kept guess.

use umbra_vk::{vk, Buffer, BufferState, Image, ImageState, Recorder};

/// The last state of every image used so far this frame; an image not seen yet is
/// [`ImageState::Undefined`] (its content from an earlier frame is discarded). Likewise the
/// buffers the GPU writes, an unseen one [`BufferState::Unknown`].
#[derive(Default)]
pub(crate) struct ImageStates {
    last: Vec<(vk::Image, ImageState)>,
    buffers: Vec<(vk::Buffer, BufferState)>,
}

impl ImageStates {
    /// Forgets every image (at the start of a frame).
    pub fn clear(&mut self) {
        self.last.clear();
        self.buffers.clear();
    }

    /// Records one batched barrier moving every buffer of `uses` into its state: a new state (an
    /// earlier write made visible to the new stages) or a write before or after. Reads after
    /// reads in one state need none.
    pub fn enter_buffers<'a>(&mut self, rec: &mut Recorder<'a>, uses: &[(&'a Buffer, BufferState)]) {
        let mut barriers = Vec::with_capacity(uses.len());
        for &(buffer, state) in uses {
            let entry = match self.buffers.iter().position(|(raw, _)| *raw == buffer.raw) {
                Some(i) => &mut self.buffers[i],
                None => {
                    self.buffers.push((buffer.raw, BufferState::Unknown));
                    self.buffers.last_mut().expect("just pushed")
                }
            };
            if entry.1 != state || entry.1.writes() || state.writes() {
                barriers.push((buffer, entry.1, state));
            }
            entry.1 = state;
        }
        rec.buffer_transition(&barriers);
    }

    /// The state `image` was last left in.
    pub fn of(&self, image: &Image) -> ImageState {
        self.last.iter().find(|(raw, _)| *raw == image.raw).map_or(ImageState::Undefined, |&(_, s)| s)
    }

    /// Sets `image`'s state without a barrier: an image handed over in `state` (an engine's
    /// depth), whose content is kept.
    pub fn import(&mut self, image: &Image, state: ImageState) {
        match self.last.iter_mut().find(|(raw, _)| *raw == image.raw) {
            Some(entry) => entry.1 = state,
            None => self.last.push((image.raw, state)),
        }
    }

    /// Records one batched barrier moving every image of `uses` into its state: a layout
    /// change, or a write before or after (write-after-write and read-after-write in one
    /// layout still need the memory dependency). Reads after reads in one state need none.
    pub fn enter<'a>(&mut self, rec: &mut Recorder<'a>, uses: &[(&'a Image, ImageState)]) {
        let mut barriers = Vec::with_capacity(uses.len());
        for &(image, state) in uses {
            let was = self.of(image);
            if was != state || writes(was) || writes(state) {
                barriers.push((image, was, state));
            }
            match self.last.iter_mut().find(|(raw, _)| *raw == image.raw) {
                Some(entry) => entry.1 = state,
                None => self.last.push((image.raw, state)),
            }
        }
        rec.transition(&barriers);
    }
}

/// Whether an image in `state` may be written.
fn writes(state: ImageState) -> bool {
    matches!(
        state,
        ImageState::ColorAttachment
            | ImageState::DepthStencilAttachment
            | ImageState::TransferDst
            | ImageState::ComputeWrite
    )
}
