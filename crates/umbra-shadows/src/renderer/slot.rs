//! What one frame in flight owns: everything the host writes for it or resets while recording
//! it. The renderer waits for each frame and keeps one slot; an engine's frames in flight
//! ([`crate::Shadows`]) get one each, so that recording frame `n + 1` never touches what the
//! GPU may still read for frame `n`. Images are shared: they are written on the GPU only, and
//! the frame graph orders each first use after all earlier work.

use crate::frame::FrameGraph;
use crate::gpu_scene::{FrameBuffers, GpuScene, MeshUpload, SceneGeometry};
use crate::retired::Retired;
use crate::streams::Streams;
use crate::techniques::TechniqueSlot;
use crate::RenderResult;
use std::sync::Arc;
use umbra_vk::{Context, DescriptorArena, DescriptorSetLayout};

/// One frame in flight's host-written buffers, descriptor sets and query pools.
pub(crate) struct FrameSlot {
    /// Camera, objects, lights and shadow views, with their set (none before the first frame).
    pub frame: Option<FrameBuffers>,
    /// Silhouette edges, volume vertices and blocker boxes.
    pub streams: Streams,
    /// The lights' shadow sets, made afresh each frame from one pool that is reset.
    pub sets: DescriptorArena,
    /// The frame graph: its query pools and the images' states.
    pub graph: FrameGraph,
    /// The passes recorded into an engine's last frame of this slot, GPU times unread.
    pub pending: Option<Vec<crate::frame::timing::PassReport>>,
    /// The meshes the slot's last frame drew, kept alive while the GPU may read them (a later
    /// frame may have uploaded others), and the staging buffers its upload copied from.
    geometry: Option<Arc<SceneGeometry>>,
    upload: Option<MeshUpload>,
    /// What the slot's last frame stopped using, destroyed when the slot is used again.
    pub retired: Retired,
    /// The techniques' sets over what this slot's frames wrote (the BVH, GPU-built volumes).
    pub techniques: TechniqueSlot,
}

impl FrameSlot {
    /// An empty slot whose sets are of `shadow_set_layout`; `name` tells slots apart in debug
    /// names.
    pub fn new(ctx: &Context, name: &str, shadow_set_layout: &DescriptorSetLayout) -> RenderResult<Self> {
        Ok(Self {
            frame: None,
            streams: Streams::default(),
            sets: DescriptorArena::new(ctx, name, shadow_set_layout, 8)?,
            graph: FrameGraph::default(),
            pending: None,
            geometry: None,
            upload: None,
            retired: Retired::default(),
            techniques: TechniqueSlot::default(),
        })
    }

    /// Starts recording the slot's next frame: its last one has completed (the renderer waited
    /// for it; an engine waited for the slot's fence), so what that frame retired goes.
    pub fn begin(&mut self) {
        self.retired.release();
    }

    /// Keeps what the frame just recorded reads from the host side until the slot's next use
    /// (when the frame has completed); returns the meshes, for the frames after.
    pub fn keep(&mut self, gpu: GpuScene) -> Arc<SceneGeometry> {
        self.frame = Some(gpu.frame);
        self.upload = gpu.upload;
        self.geometry = Some(gpu.geometry.clone());
        gpu.geometry
    }
}
