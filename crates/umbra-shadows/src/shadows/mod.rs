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
//! (`tests/embed.rs`). A depth umbra's passes cannot test as it is (multisampled, without
//! stencil, reversed-Z, or a finite far plane where volumes must reach infinity) is re-drawn
//! into an image of umbra's own first ([`RebuildReason`]).

mod inputs;
mod registry;

pub use crate::mesh_buffers::{IndexStream, MeshBuffers, VertexStream};
pub use inputs::{DepthTarget, FrameInputs, LightShadows, RebuildReason, SampledImage, ShadowFrame, ShadowMapOutput};
pub use registry::{Instance, InstanceId, MeshId};

use crate::renderer::{EngineDepth, FrameDepth, FrameSlot, Renderer, RendererDesc};
use crate::shadow_volume::FarPlane;
use crate::technique::needs;
use crate::view::View;
use crate::visibility::VISIBILITY_FORMAT;
use crate::{RenderError, RenderResult};
use glam::Mat4;
use inputs::{convention, depth_state, rebuild_reason, standard_infinite};
use registry::{invalid, Registry};
use umbra_scene::{Mesh, Technique};
use umbra_vk::{vk, Context, Image, ImageDesc, ImageState};

/// The most frames in flight a [`Shadows`] keeps resources for.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 8;

/// How a [`Shadows`] is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowsDesc {
    /// The techniques' settings and the frame size (`settings.width` × `settings.height`, the
    /// engine's depth extent). Diagnostics, the G-buffer, visibility readbacks, volume overdraw
    /// and the hybrid's blocker culling read results back mid-frame and are refused here.
    pub settings: RendererDesc,
    /// The engine's depth format: `D32_SFLOAT_S8_UINT`, `D24_UNORM_S8_UINT` or `D32_SFLOAT`.
    /// With a stencil, umbra's passes are built for it and test the engine's depth; without
    /// one, they are built for the device's depth/stencil format and umbra re-draws depth into
    /// an image of its own every frame ([`ShadowFrame::depth_rebuilt`]).
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
        let renderer = Renderer::for_engine(ctx, desc.settings, passes_format(ctx, desc.depth_format)?)?;
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

    /// Registers a mesh that stays in the engine's own buffers (checked against the sizes
    /// given: [`MeshBuffers`]). umbra never reads it on the CPU: the frame that uploads the
    /// meshes copies it into umbra's buffers on the GPU, and only its bounds are kept. Lights
    /// whose technique builds geometry on the CPU (shadow volumes, the hybrid, silhouette maps,
    /// `auto`) refuse instances of it that cast shadows: a typed error from [`Shadows::record`].
    /// The buffers must live, unchanged, while the mesh is registered (a mesh whose positions
    /// change on the GPU is registered with [`Shadows::add_deforming_mesh`]).
    pub fn add_mesh_buffers(&mut self, mesh: MeshBuffers) -> RenderResult<MeshId> {
        mesh.validate()?;
        let placeholder = mesh.placeholder(format!("engine mesh {}", self.registry.scene.meshes.len()))?;
        let id = self.registry.add_mesh(placeholder)?;
        let engine = &mut self.renderer.engine_meshes;
        engine.resize(self.registry.scene.meshes.len(), None);
        engine[id.0 as usize] = Some(mesh);
        Ok(id)
    }

    /// Registers a mesh the engine deforms on the GPU (skinned, displaced): drawn from its
    /// buffers as [`Shadows::add_mesh_buffers`] meshes are, and shadowed exactly by shadow
    /// volumes built on the GPU, which read `buffers.positions` anew every frame (the `volume
    /// positions` pass copies them on the GPU; the host does nothing per vertex or triangle).
    ///
    /// `rest` is the same mesh in its rest pose, on the CPU: its indices must be those of
    /// `buffers.indices` and its vertex count `buffers.vertex_count`. umbra welds it once for
    /// its connectivity, so vertices that share a position in the rest pose must share it in
    /// every pose (a skinned mesh's seams do). `buffers.positions.buffer` also needs
    /// `STORAGE_BUFFER` usage, and `buffers.bounds` must hold every pose (culling and map
    /// fitting read only it). Only [`Technique::ShadowMap`] and [`Technique::ShadowVolume`]
    /// with [`crate::VolumeBuild::Gpu`] shadow with such a mesh; other lights refuse it, with a
    /// typed error from [`Shadows::record`]. The engine writes the positions before the
    /// commands [`Shadows::record`] records run, in the same or an earlier submission: umbra's
    /// copy starts with a global barrier from every earlier command's writes to its compute
    /// read; its draws of the mesh, like the engine's own, need the writes made visible to
    /// `VERTEX_ATTRIBUTE_INPUT` by the engine. The buffers' handles and layout stay as given
    /// while the mesh is registered; only the positions' contents change.
    pub fn add_deforming_mesh(&mut self, buffers: MeshBuffers, rest: &Mesh) -> RenderResult<MeshId> {
        buffers.validate()?;
        rest.validate().map_err(|e| invalid("rest".into(), e.to_string()))?;
        if rest.positions.len() != buffers.vertex_count as usize {
            let why =
                format!("{} vertices, but buffers.vertex_count is {}", rest.positions.len(), buffers.vertex_count);
            return Err(invalid("rest.positions".into(), why));
        }
        if rest.indices.len() != buffers.indices.count as usize {
            let why = format!("{} indices, but buffers.indices.count is {}", rest.indices.len(), buffers.indices.count);
            return Err(invalid("rest.indices".into(), why));
        }
        let id = self.add_mesh_buffers(buffers)?;
        self.renderer.techniques.deforming.set(id.0 as usize, rest, buffers.positions);
        Ok(id)
    }

    /// Forgets a mesh no instance draws any more.
    pub fn remove_mesh(&mut self, mesh: MeshId) -> RenderResult<()> {
        self.registry.remove_mesh(mesh)?;
        if let Some(engine) = self.renderer.engine_meshes.get_mut(mesh.0 as usize) {
            *engine = None;
        }
        self.renderer.techniques.deforming.clear(mesh.0 as usize);
        Ok(())
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
        let (allocations, submissions) = (self.ctx.memory_allocations(), self.ctx.submissions());
        let (state, proj) = self.check(inputs)?;
        let scene = &mut self.registry.scene;
        scene.lights.clear();
        scene.lights.extend_from_slice(inputs.lights);
        scene.validate_placement_with(&mut self.renderer.checked)?;
        let d = inputs.depth;
        let (width, height) = (self.desc.settings.width, self.desc.settings.height);
        let desc = ImageDesc::new_2d(d.format, width, height).usage(d.usage).samples(d.samples);
        let depth = Image::external(&self.ctx, d.image, d.view, desc);
        let k = (inputs.frame_index % self.slots.len() as u64) as usize;
        let slot = &mut self.slots[k];
        let earlier_passes = slot.pending.take().map(|p| slot.graph.earlier_times(p)).transpose()?;
        let view = View::of_matrices(inputs.view, proj);
        let frame_depth = match state {
            Ok(state) => FrameDepth::Engine(EngineDepth { image: &depth, state }),
            Err(_) => FrameDepth::Rebuilt,
        };
        let recorded = self.renderer.record_into(slot, &self.registry.scene, view, frame_depth, cmd)?;
        slot.pending = Some(recorded.passes);
        let lights = recorded.lights.into_iter().map(|l| self.light_shadows(l)).collect::<RenderResult<Vec<_>>>()?;
        Ok(ShadowFrame {
            lights,
            slot: k,
            earlier_passes,
            geometry_uploaded_bytes: recorded.geometry_uploaded_bytes,
            memory_allocations: self.ctx.memory_allocations() - allocations,
            submissions: self.ctx.submissions() - submissions,
            depth_rebuilt: state.err(),
        })
    }

    /// Checks `inputs` against what this `Shadows` was made for. Returns the depth's state
    /// when umbra's passes use the engine's depth as it is (else why umbra re-draws its own,
    /// `crate::depth_rebuild`) and the projection umbra's passes use.
    fn check(&self, inputs: &FrameInputs<'_>) -> RenderResult<(Result<ImageState, RebuildReason>, Mat4)> {
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
        if !(inputs.view.is_finite() && inputs.view.determinant().abs() > 0.0) {
            return Err(invalid(field("view"), "must be finite and invertible".into()));
        }
        let c = convention(inputs.proj)?;
        let clamp = self.desc.settings.shadow_volume.far_plane == FarPlane::DepthClamp;
        let finite_allowed = clamp || !inputs.lights.iter().any(|l| needs(l.technique).infinite_camera);
        if let Some(reason) = rebuild_reason(d.samples, d.format, c, finite_allowed) {
            return Ok((Err(reason), standard_infinite(inputs.proj, c)));
        }
        let state = depth_state(d.layout)?;
        if !d.usage.contains(vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT) {
            return Err(invalid(
                field("depth.usage"),
                "needs DEPTH_STENCIL_ATTACHMENT: umbra's passes test against it".into(),
            ));
        }
        self.check_engine_meshes(inputs.lights)?;
        // `auto` picks the hybrid only where the map classifies first (`AutoPolicy`).
        let classify_first = self.renderer.auto_policy().classify_first;
        let hybrid = inputs
            .lights
            .iter()
            .position(|l| l.technique == Technique::Hybrid || (l.technique == Technique::Auto && classify_first));
        if let (Some(i), false) = (hybrid, d.usage.contains(vk::ImageUsageFlags::TRANSFER_SRC)) {
            let why = format!(
                "needs TRANSFER_SRC: light {i} uses {:?}, whose hybrid classification copies the depth",
                inputs.lights[i].technique
            );
            return Err(invalid(field("depth.usage"), why));
        }
        Ok((Ok(state), inputs.proj))
    }

    /// A typed error when a light whose technique builds geometry from the casters' triangles
    /// on the CPU would need a mesh only the engine's buffers hold (a deforming mesh's rest
    /// pose serves shadow volumes built on the GPU, and nothing else).
    fn check_engine_meshes(&self, lights: &[umbra_scene::Light]) -> RenderResult<()> {
        let engine = &self.renderer.engine_meshes;
        let scene = &self.registry.scene;
        let on_cpu =
            |t: Technique| t == Technique::Auto || needs(t).volumes.is_some() || needs(t).silhouette || needs(t).rays;
        let gpu_volumes = self.renderer.techniques.volumes_on_gpu();
        for o in scene.objects.iter().filter(|o| o.casts_shadows && engine.get(o.mesh).is_some_and(Option::is_some)) {
            let deforms = self.renderer.techniques.deforming.holds(o.mesh);
            let refused = |t: Technique| on_cpu(t) && !(deforms && gpu_volumes && t == Technique::ShadowVolume);
            let Some(i) = lights.iter().position(|l| refused(l.technique)) else { continue };
            let why = match deforms {
                true => format!(
                    "{:?} cannot shadow with {}, a mesh deformed on the GPU (add_deforming_mesh): only ShadowMap, \
                     and ShadowVolume with settings.shadow_volume.build = VolumeBuild::Gpu, read its pose",
                    lights[i].technique, o.name
                ),
                false => format!(
                    "{:?} builds shadows from the casters' triangles on the CPU, but {} casts shadows with a mesh \
                     registered by add_mesh_buffers, which umbra never reads on the CPU: register that mesh with \
                     add_mesh, or shadow this light with ShadowMap",
                    lights[i].technique, o.name
                ),
            };
            return Err(invalid(format!("FrameInputs::lights[{i}].technique"), why));
        }
        Ok(())
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

/// Whether `format` has a stencil aspect.
fn has_stencil(format: vk::Format) -> bool {
    umbra_vk::format_aspect(format).contains(vk::ImageAspectFlags::STENCIL)
}

/// The depth format umbra's passes are built for: the engine's when it has a stencil, else the
/// device's depth/stencil format (umbra then re-draws depth into its own image every frame).
fn passes_format(ctx: &Context, engine: vk::Format) -> RenderResult<vk::Format> {
    if has_stencil(engine) {
        return Ok(engine);
    }
    match ctx.capabilities().depth_stencil_format {
        vk::Format::UNDEFINED => Err(ctx.unsupported("any depth/stencil attachment format").into()),
        format => Ok(format),
    }
}
