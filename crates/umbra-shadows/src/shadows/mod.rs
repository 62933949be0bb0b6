//! umbra's shadows recorded into an engine's own frame.
//!
//! An engine that owns its device, its depth buffer and its frame creates a [`Shadows`] from
//! its device ([`umbra_vk::Context::from_external`]), registers its meshes and instances once,
//! moves instances as they move, and each frame calls [`Shadows::record`] with its command
//! buffer, its depth, its matrices and its lights. umbra records every light's shadow passes
//! into that command buffer — no submission, no fence, no readback — and hands back, per
//! light, a visibility image to sample in the engine's own lighting (and the shadow map with
//! its matrices, for engines that sample maps themselves). `docs/embedding.md` lists what to
//! enable, what umbra reads and writes in which layouts and stages, and what it costs.
//!
//! The techniques, their plan and their passes are exactly those of [`crate::Renderer`]: over
//! a depth drawn the way umbra draws its own, the visibility images are the same, bit for bit
//! (`tests/embed.rs`).

mod inputs;
mod registry;

pub use inputs::{DepthTarget, FrameInputs, LightShadows, SampledImage, ShadowFrame, ShadowMapOutput};
pub use registry::{Instance, InstanceId, MeshId};

use crate::renderer::{EngineDepth, FrameSlot, Renderer, RendererDesc};
use crate::shadow_volume::FarPlane;
use crate::technique::needs;
use crate::view::View;
use crate::visibility::VISIBILITY_FORMAT;
use crate::{RenderError, RenderResult};
use glam::Mat4;
use inputs::{convention, depth_state};
use registry::{invalid, Registry};
use umbra_scene::{Mesh, Technique};
use umbra_vk::{vk, Context, Image, ImageDesc};

/// The most frames in flight a [`Shadows`] keeps resources for.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 8;

/// How a [`Shadows`] is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowsDesc {
    /// The techniques' settings and the frame size (`settings.width` × `settings.height`, the
    /// engine's depth extent). Diagnostics, the G-buffer, visibility readbacks, volume overdraw
    /// and the hybrid's blocker culling read results back mid-frame and are refused here.
    pub settings: RendererDesc,
    /// The engine's depth format: `D32_SFLOAT`, `D32_SFLOAT_S8_UINT` or `D24_UNORM_S8_UINT`
    /// (shadow volumes and the hybrid count in the stencil, so they need one of the last two).
    pub depth_format: vk::Format,
    /// How many frames the engine has in flight (1 to [`MAX_FRAMES_IN_FLIGHT`]): one set of
    /// host-written buffers, descriptor sets and query pools each.
    pub frames_in_flight: u32,
}

impl ShadowsDesc {
    /// A `width` × `height` frame with `depth_format` depth, default settings, two frames in
    /// flight.
    pub fn new(width: u32, height: u32, depth_format: vk::Format) -> Self {
        Self { settings: RendererDesc::new(width, height), depth_format, frames_in_flight: 2 }
    }

    /// A typed error for a setting an engine's frame cannot honour.
    fn validate(&self) -> RenderResult<()> {
        let s = &self.settings;
        let refused = [
            ("settings.diagnostics", s.diagnostics),
            ("settings.gbuffer", s.gbuffer),
            ("settings.read_visibility", s.read_visibility),
            ("settings.shadow_volume.overdraw", s.shadow_volume.overdraw),
            ("settings.hybrid.cull_blockers", s.hybrid.cull_blockers),
        ];
        if let Some((field, _)) = refused.iter().find(|(_, on)| *on) {
            return Err(RenderError::InvalidSetting {
                field,
                value: "true".into(),
                accepted:
                    "false: it reads results back in the middle of a frame, which an engine's frame does not wait for"
                        .into(),
            });
        }
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&self.frames_in_flight) {
            return Err(RenderError::InvalidSetting {
                field: "frames_in_flight",
                value: self.frames_in_flight.to_string(),
                accepted: format!("1 to {MAX_FRAMES_IN_FLIGHT}"),
            });
        }
        let formats = [vk::Format::D32_SFLOAT, vk::Format::D32_SFLOAT_S8_UINT, vk::Format::D24_UNORM_S8_UINT];
        if !formats.contains(&self.depth_format) {
            return Err(RenderError::InvalidSetting {
                field: "depth_format",
                value: format!("{:?}", self.depth_format),
                accepted: "D32_SFLOAT, D32_SFLOAT_S8_UINT or D24_UNORM_S8_UINT".into(),
            });
        }
        Ok(())
    }
}

/// umbra's shadows for an engine's frames: see the [module documentation](self).
pub struct Shadows {
    ctx: Context,
    desc: ShadowsDesc,
    renderer: Renderer,
    registry: Registry,
    slots: Vec<FrameSlot>,
}

impl Shadows {
    /// The pipelines for `desc`'s depth format and the resources of each frame in flight.
    pub fn new(ctx: &Context, desc: ShadowsDesc) -> RenderResult<Self> {
        desc.validate()?;
        let renderer = Renderer::for_engine(ctx, desc.settings, desc.depth_format)?;
        let slots = (0..desc.frames_in_flight as usize).map(|i| renderer.new_slot(i)).collect::<RenderResult<_>>()?;
        Ok(Self { ctx: ctx.clone(), desc, renderer, registry: Registry::default(), slots })
    }

    /// What it was made with.
    pub fn desc(&self) -> ShadowsDesc {
        self.desc
    }

    /// Registers a mesh (checked: [`Mesh::validate`]); its positions and indices are kept on
    /// the CPU (volumes and silhouettes are built from them) and uploaded with the next frame.
    pub fn add_mesh(&mut self, mesh: Mesh) -> RenderResult<MeshId> {
        self.registry.add_mesh(mesh)
    }

    /// Forgets a mesh no instance draws any more.
    pub fn remove_mesh(&mut self, mesh: MeshId) -> RenderResult<()> {
        self.registry.remove_mesh(mesh)
    }

    /// Places a registered mesh.
    pub fn add_instance(&mut self, instance: Instance) -> RenderResult<InstanceId> {
        self.registry.add_instance(instance)
    }

    /// Moves an instance: only its transform is written with the next frame.
    pub fn set_transform(&mut self, instance: InstanceId, transform: Mat4) -> RenderResult<()> {
        self.registry.set_transform(instance, transform)
    }

    /// Removes an instance.
    pub fn remove_instance(&mut self, instance: InstanceId) -> RenderResult<()> {
        self.registry.remove_instance(instance)
    }

    /// Records every light's shadows into `cmd`, a primary command buffer of the engine's in
    /// the recording state, outside any rendering pass: the shadow maps, volumes and the other
    /// passes of each light's technique, over `inputs.depth`, ending with each shadowed light's
    /// visibility image in `SHADER_READ_ONLY_OPTIMAL`, visible to fragment shaders, and the
    /// depth back in its layout. Nothing is submitted or waited for; the engine submits `cmd`
    /// and keeps what it recorded alive until it completed. A typed error, before anything is
    /// recorded, names the input umbra cannot use.
    pub fn record(&mut self, cmd: vk::CommandBuffer, inputs: &FrameInputs<'_>) -> RenderResult<ShadowFrame> {
        let allocations = self.ctx.memory_allocations();
        let state = self.check(inputs)?;
        let scene = &mut self.registry.scene;
        scene.lights.clear();
        scene.lights.extend_from_slice(inputs.lights);
        scene.validate_placement()?;
        let d = inputs.depth;
        let (width, height) = (self.desc.settings.width, self.desc.settings.height);
        let desc = ImageDesc::new_2d(d.format, width, height).usage(d.usage);
        let depth = Image::external(&self.ctx, d.image, d.view, desc);
        let k = (inputs.frame_index % self.slots.len() as u64) as usize;
        let slot = &mut self.slots[k];
        let earlier_passes = slot.pending.take().map(|p| slot.graph.earlier_times(p)).transpose()?;
        let view = View::of_matrices(inputs.view, inputs.proj);
        let engine_depth = EngineDepth { image: &depth, state };
        let recorded = self.renderer.record_into(slot, &self.registry.scene, view, engine_depth, cmd)?;
        slot.pending = Some(recorded.passes);
        let lights = recorded.lights.into_iter().map(|l| self.light_shadows(l)).collect::<RenderResult<Vec<_>>>()?;
        Ok(ShadowFrame {
            lights,
            slot: k,
            earlier_passes,
            geometry_uploaded_bytes: recorded.geometry_uploaded_bytes,
            memory_allocations: self.ctx.memory_allocations() - allocations,
        })
    }

    /// Checks `inputs` against what this `Shadows` was made for; returns the depth's state.
    fn check(&self, inputs: &FrameInputs<'_>) -> RenderResult<umbra_vk::ImageState> {
        let d = inputs.depth;
        let field = |f: &str| format!("FrameInputs::{f}");
        if d.format != self.desc.depth_format {
            let why = format!("{:?}, but this Shadows was made for {:?}", d.format, self.desc.depth_format);
            return Err(invalid(field("depth.format"), why));
        }
        let (width, height) = (self.desc.settings.width, self.desc.settings.height);
        if (d.extent.width, d.extent.height) != (width, height) {
            let why = format!("{}x{}, but this Shadows was made for {width}x{height}", d.extent.width, d.extent.height);
            return Err(invalid(field("depth.extent"), why));
        }
        if d.samples != vk::SampleCountFlags::TYPE_1 {
            let why = format!(
                "{:?}: umbra reads a single-sampled depth; resolve yours first (a depth resolve attachment, \
                 VK_KHR_depth_stencil_resolve, mode SAMPLE_ZERO) and hand over the resolved image",
                d.samples
            );
            return Err(invalid(field("depth.samples"), why));
        }
        let state = depth_state(d.layout)?;
        if !d.usage.contains(vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT) {
            return Err(invalid(
                field("depth.usage"),
                "needs DEPTH_STENCIL_ATTACHMENT: umbra's passes test against it".into(),
            ));
        }
        let hybrid = inputs.lights.iter().position(|l| matches!(l.technique, Technique::Hybrid | Technique::Auto));
        if let (Some(i), false) = (hybrid, d.usage.contains(vk::ImageUsageFlags::TRANSFER_SRC)) {
            let why = format!(
                "needs TRANSFER_SRC: light {i} uses {:?}, whose hybrid classification copies the depth",
                inputs.lights[i].technique
            );
            return Err(invalid(field("depth.usage"), why));
        }
        if !(inputs.view.is_finite() && inputs.view.determinant().abs() > 0.0) {
            return Err(invalid(field("view"), "must be finite and invertible".into()));
        }
        let c = convention(inputs.proj)?;
        if c.reversed {
            let why = "reversed depth is not supported yet: hand over a standard-depth (0 at the near plane) \
                       projection and depth";
            return Err(invalid(field("proj"), why.into()));
        }
        for (i, light) in inputs.lights.iter().enumerate() {
            if !needs(light.technique).infinite_camera {
                continue;
            }
            let clamp = self.desc.settings.shadow_volume.far_plane == FarPlane::DepthClamp;
            if !c.infinite && !clamp {
                let why = format!(
                    "has a finite far plane, but light {i} uses {:?}, whose volumes reach infinity: use an infinite \
                     far plane (glam's perspective_infinite_rh) or shadow_volume.far_plane = DepthClamp",
                    light.technique
                );
                return Err(invalid(field("proj"), why));
            }
            if !umbra_vk::format_aspect(d.format).contains(vk::ImageAspectFlags::STENCIL) {
                let why = format!(
                    "{:?} has no stencil, but light {i} uses {:?}, which counts in it: use D32_SFLOAT_S8_UINT",
                    d.format, light.technique
                );
                return Err(invalid(field("depth.format"), why));
            }
        }
        Ok(state)
    }

    /// What the engine gets of one recorded light.
    fn light_shadows(&self, l: crate::renderer::RecordedLight) -> RenderResult<LightShadows> {
        let light = l.plan.light;
        let sampled = |image: &Image, format| SampledImage {
            image: image.raw,
            view: image.view,
            format,
            layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            stages: vk::PipelineStageFlags2::FRAGMENT_SHADER,
        };
        let visibility = match l.shadowed {
            true => Some(sampled(self.renderer.visibility_image(light)?, VISIBILITY_FORMAT)),
            false => None,
        };
        let shadow_map = match (l.map, &l.plan.shadow_map) {
            (true, Some(report)) => {
                let image = self.renderer.shadow_map_image(light)?;
                Some(ShadowMapOutput {
                    image: sampled(image, image.desc.format),
                    view_proj: report.view_proj.clone(),
                    resolution: report.resolution,
                })
            }
            _ => None,
        };
        Ok(LightShadows { light, visibility, shadow_map, plan: l.plan })
    }
}
