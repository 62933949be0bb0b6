//! What a frame stopped using while the GPU may still read it for earlier frames: a light's
//! maps or visibility image once it no longer needs them, a target made again at another size,
//! a descriptor set over meshes uploaded again. umbra's own frames wait for the GPU, but an
//! engine keeps several frames in flight ([`crate::Shadows`]), so nothing is destroyed while
//! recording: it is handed to the frame slot being recorded, which drops it when the slot is
//! used again — after the engine waited for that slot's fence, and so (one queue, submission
//! order) for every frame recorded before it.

use std::any::Any;

/// Resources released while recording one frame slot's frame.
#[derive(Default)]
pub(crate) struct Retired(Vec<Box<dyn Any + Send>>);

impl Retired {
    /// Keeps `resource` alive until the slot's next frame.
    pub fn keep<T: Any + Send>(&mut self, resource: T) {
        self.0.push(Box::new(resource));
    }

    /// Keeps what `slot` held, leaving it empty.
    pub fn take<T: Any + Send>(&mut self, slot: &mut Option<T>) {
        if let Some(resource) = slot.take() {
            self.keep(resource);
        }
    }

    /// Destroys everything kept (the frames that could read it have completed).
    pub fn release(&mut self) {
        self.0.clear();
    }
}
