//! # umbra-shadows — the renderer and the shadow technique modules
//!
//! [`Renderer`] renders a [`umbra_scene::Scene`] into a headless target: a depth + ambient
//! pass, then per light the passes of the [`umbra_scene::Technique`] the scene asked for, which
//! write the light's [`visibility`] image, and an additive Lambert pass that multiplies by it,
//! then a readback. Each frame returns its pixels and a
//! [`FrameReport`] (device, capabilities, scene, per-light plan, per-pass GPU times) that
//! serialises to JSON.
//!
//! Techniques: [`shadow_map`], [`shadow_volume`], [`silhouette_map`] and [`hybrid`], each a
//! module that reads top to bottom as its paper's passes.

#![warn(missing_docs)]

mod budget;
mod depth_rebuild;
pub mod diagnostics;
mod error;
mod forward;
mod frame;
mod gbuffer;
mod gpu_scene;
pub mod hybrid;
mod light_surfaces;
mod mesh_buffers;
mod mesh_cache;
pub mod plan;
pub mod ray_traced;
mod reach;
mod renderer;
mod report;
mod retired;
pub mod shadow_map;
pub mod shadow_volume;
pub mod shadows;
pub mod silhouette_map;
mod streams;
mod targets;
mod technique;
mod techniques;
mod view;
pub mod visibility;

pub use budget::DEFAULT_SHADOW_MAP_BUDGET;
pub use diagnostics::{GBuffer, LightDiagnostics, PixelClass, SilhouetteMapImage};
pub use error::{RenderError, RenderResult, ShadowStorage};
pub use frame::timing::PassReport;
pub use frame::PassId;
pub use hybrid::{HybridSettings, MaskKind};
pub use mesh_buffers::{IndexStream, MeshBuffers, VertexStream};
pub use plan::auto::{AutoAccuracy, AutoPolicy};
pub use plan::{
    CullReason, Culled, FramePlan, HybridReport, HybridRtReport, LightPlan, RayTracedReport, ShadowMapReport,
    SilhouetteMapReport,
};
pub use ray_traced::TraversalReport;
pub use renderer::{Frame, Renderer, RendererDesc};
pub use report::{FrameReport, MeshTopology, SceneSummary, TopologySource, VolumeConstruction};
pub use shadow_map::{DepthBias, ShadowFilter, ShadowMapSettings};
pub use shadow_volume::{
    CasterMode, FarPlane, HostClip, ShadowVolumeReport, ShadowVolumeSettings, VolumeBuild, VolumeMode,
};
pub use shadows::{
    DepthTarget, FrameInputs, Instance, InstanceId, LightShadows, MeshId, RebuildReason, SampledImage, ShadowFrame,
    ShadowMapOutput, Shadows, ShadowsDesc,
};
pub use targets::COLOR_FORMAT;
pub use view::DepthPrecision;
pub use visibility::{VisibilityImage, VISIBILITY_FORMAT};
