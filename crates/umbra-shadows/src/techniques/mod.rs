//! The technique set: every technique's pipelines and caches, and each step of a frame that
//! depends on a light's technique, behind one seam. The renderer reaches the techniques only
//! through it (and names no technique's submodule): it plans, then asks the set to prepare
//! every light ([`Techniques::prepare`]), bind its maps, declare its views and its visibility
//! passes, and read its results back.
//!
//! What a technique asks of a frame is its `crate::technique::needs` row (a map and its size,
//! volumes, rays, the hybrid's lighting); each step here reads those rows and what a light
//! prepared this frame ([`LightFrame`]):
//! - `prepare.rs`: check and size the maps against the device and the budget, extract
//!   silhouette edges, build volumes (or name them as GPU jobs), prepare the BVH, list blocker
//!   boxes, make the hybrid's targets;
//! - `bind.rs`: a light's set (its maps as the lighting passes sample them) and readbacks;
//! - `views.rs`: a light's views (its map, the hybrid's depth bounds, silhouette points) and
//!   blocker culling;
//! - `declare.rs`: the one dispatch of a light's visibility passes, and the techniques'
//!   diagnostics; `ray_stats.rs`, the rays' counters;
//! - `results.rs`: what its queries and readbacks say, into its plan's report.

mod bind;
mod declare;
mod inputs;
mod light;
mod prepare;
mod ray_stats;
mod results;
mod views;

pub(crate) use crate::hybrid::cull::CullingPlan;
pub(crate) use bind::Binding;
pub(crate) use inputs::FrameInputs;
pub(crate) use light::{FrameView, LightBindings, LightFrame, LightQueries, LightReadbacks, LightSets};
pub(crate) use prepare::PrepareInputs;
pub(crate) use results::FrameCounts;

use crate::hybrid::pass::HybridPass;
use crate::hybrid::rays::HybridRays;
use crate::hybrid::{HybridSettings, MaskKind};
use crate::ray_traced::pass::{RayPass, SlotRays};
use crate::ray_traced::stats::RayStats;
use crate::ray_traced::BvhLayout;
use crate::shadow_map::fits::Fits;
use crate::shadow_map::pass::ShadowMapPass;
use crate::shadow_map::samples::GridSamples;
use crate::shadow_map::ShadowMapSettings;
use crate::shadow_volume::deform::Deforming;
use crate::shadow_volume::gpu_frame::{GpuVolumes, SlotVolumes};
use crate::shadow_volume::pass::{ShadowVolumePass, VolumeInput};
use crate::shadow_volume::{FarPlane, ShadowVolumeSettings, VolumeBuild};
use crate::silhouette_map::pass::SilhouetteMapPass;
use crate::targets::COLOR_FORMAT;
use crate::{RenderError, RenderResult};
use umbra_vk::{vk, Context, DescriptorSetLayout, Image, ImageDesc, PipelineLayout};

/// What the techniques are set up with: the renderer's settings they read.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Setup {
    /// The frame's size in pixels.
    pub width: u32,
    pub height: u32,
    pub shadow_map: ShadowMapSettings,
    pub shadow_volume: ShadowVolumeSettings,
    pub hybrid: HybridSettings,
    pub bvh: BvhLayout,
    /// Whether frames are planned (culling, bounds).
    pub cull: bool,
    /// Whether the diagnostic views are rendered (and silhouette maps read back).
    pub diagnostics: bool,
    /// Whether every shadowed light's visibility image is read back.
    pub read_visibility: bool,
    /// The most bytes one frame's shadow storage may take.
    pub budget_bytes: u64,
    /// umbra's own frames, whose counts are read back (an engine's frames read none).
    pub own: bool,
    /// The depth (and stencil) format the passes test.
    pub depth_format: vk::Format,
}

/// Every technique's pipelines, the caches kept between frames, and the choices made for the
/// device (the hybrid's mask, how volume vertices reach the GPU).
pub(crate) struct Techniques {
    setup: Setup,
    shadow_map: ShadowMapPass,
    shadow_volume: ShadowVolumePass,
    silhouette_map: SilhouetteMapPass,
    hybrid: HybridPass,
    /// Ray-traced lights' BVH and shadow rays.
    rays: RayPass,
    /// The ray-traced hybrid's pipelines and ray list (`None` where the device cannot run it:
    /// [`crate::visibility::storage_supported`]).
    hybrid_rays: Option<HybridRays>,
    /// The shadow rays' counted twins and counters (with `diagnostics`, in umbra's own frames).
    ray_stats: Option<RayStats>,
    /// Each light's receiver grid samples, kept while their inputs do not change.
    grid_samples: GridSamples,
    /// Every map light's fitted views, kept while their inputs are the same bits.
    fits: Fits,
    /// How volume vertices reach the GPU: as built, or clipped to the view on the host.
    volume_input: VolumeInput,
    /// Shadow volumes built on the GPU (`shadow_volume.build`: `VolumeBuild::Gpu`).
    gpu_volumes: Option<GpuVolumes>,
    /// The computation mask of hybrid lights (`hybrid.mask`, or the device's best).
    mask: MaskKind,
    /// The engine's meshes that deform on the GPU (`Shadows::add_deforming_mesh`).
    pub deforming: Deforming,
}

/// What one frame in flight keeps of the techniques: the sets over what it wrote.
#[derive(Default)]
pub(crate) struct TechniqueSlot {
    /// The ray-tracing BVH's set over this slot's top level (with ray-traced lights).
    rays: Option<SlotRays>,
    /// The set of the shadow volumes built on the GPU over this slot's jobs.
    volumes: Option<SlotVolumes>,
}

/// The computation mask hybrid lights use on this device: `settings.mask`, or the device's
/// best; refused (naming the feature) where the device lacks the depth-bounds test it asks for.
pub(crate) fn mask_for(ctx: &Context, settings: &HybridSettings) -> RenderResult<MaskKind> {
    let caps = ctx.capabilities();
    let mask = settings.mask.unwrap_or(MaskKind::best_for(caps.depth_bounds));
    if mask == MaskKind::DepthBounds && !caps.depth_bounds {
        return Err(ctx.unsupported("the hybrid's depth-bounds computation mask (depthBounds)").into());
    }
    Ok(mask)
}

/// The frame-sized images the techniques may create, named, for a frame of `width` × `height`
/// over `depth_format` with the hybrid's `mask`: the hybrid's classes, then its masked depth.
pub(crate) fn frame_images(
    depth_format: vk::Format,
    width: u32,
    height: u32,
    mask: MaskKind,
) -> Vec<(&'static str, ImageDesc)> {
    let (classes, masked_depth) = crate::hybrid::pass::target_descs(depth_format, width, height);
    let mut images = vec![("hybrid silhouette classes", classes)];
    if mask == MaskKind::DepthBounds {
        images.push(("hybrid masked depth", masked_depth));
    }
    images
}

/// The layout of set 1 of the lighting passes: a light's maps as they are sampled.
pub(crate) fn shadow_set_layout(ctx: &Context) -> RenderResult<DescriptorSetLayout> {
    crate::shadow_map::pass::shadow_set_layout(ctx)
}

impl Techniques {
    /// Every technique's pipelines over `layout` (sets 0 to 2: `scene_set_layout`,
    /// `shadow_set_layout`, the visibility set) for `setup`, with the hybrid's `mask`
    /// ([`mask_for`]); `bounds` when bounded lights' pipelines test depth bounds. Refused,
    /// naming the setting, where the device cannot run what `setup` asks for.
    pub fn new(
        ctx: &Context,
        setup: Setup,
        layouts: [&DescriptorSetLayout; 2],
        layout: &PipelineLayout,
        mask: MaskKind,
        bounds: bool,
    ) -> RenderResult<Self> {
        let [scene_set_layout, shadow_set_layout] = layouts;
        let (caps, depth_format) = (ctx.capabilities(), setup.depth_format);
        let shadow_map = ShadowMapPass::new(ctx, layout, setup.shadow_map)?;
        if setup.shadow_volume.far_plane == FarPlane::DepthClamp && !caps.depth_clamp {
            return Err(ctx.unsupported("shadow volumes with FarPlane::DepthClamp (depthClamp)").into());
        }
        let volume_input = match setup.shadow_volume.host_clip.applies(caps.watertight_clipping) {
            true => VolumeInput::HostClipped,
            false => VolumeInput::Built,
        };
        let shadow_volume =
            ShadowVolumePass::new(ctx, layout, depth_format, &setup.shadow_volume, bounds, volume_input)?;
        let gpu_volumes = gpu_volumes(ctx, &setup, scene_set_layout, volume_input, bounds)?;
        let silhouette_map = SilhouetteMapPass::new(ctx, layout, COLOR_FORMAT, depth_format, &setup.shadow_map)?;
        let clamp = setup.shadow_volume.far_plane == FarPlane::DepthClamp;
        let hybrid =
            HybridPass::new(ctx, layout, depth_format, scene_set_layout, &setup.shadow_map, clamp, volume_input)?;
        let hybrid = match &gpu_volumes {
            Some(g) => hybrid.with_gpu_volumes(ctx, g, clamp, setup.shadow_volume.overdraw)?,
            None => hybrid,
        };
        let rays = RayPass::new(ctx, scene_set_layout, depth_format, bounds, setup.bvh)?;
        let hybrid_rays = match crate::hybrid::rays::supported(caps) {
            true => Some(HybridRays::new(
                ctx,
                scene_set_layout,
                shadow_set_layout,
                rays.set_layout(),
                depth_format,
                &setup.shadow_map,
                setup.bvh,
            )?),
            false => None,
        };
        let ray_stats = match setup.diagnostics && setup.own {
            true => {
                let listed = hybrid_rays.as_ref().map(|h| {
                    let [list, output] = h.set_layouts();
                    [rays.set_layout(), list, output]
                });
                let bvh = (rays.set_layout(), setup.bvh);
                Some(RayStats::new(ctx, scene_set_layout, bvh, listed, depth_format, bounds)?)
            }
            false => None,
        };
        Ok(Self {
            setup,
            shadow_map,
            shadow_volume,
            silhouette_map,
            hybrid,
            rays,
            hybrid_rays,
            ray_stats,
            grid_samples: Default::default(),
            fits: Default::default(),
            volume_input,
            gpu_volumes,
            mask,
            deforming: Default::default(),
        })
    }

    /// The computation mask hybrid lights use.
    pub fn mask(&self) -> MaskKind {
        self.mask
    }

    /// The shadow-map settings, as validated.
    pub fn shadow_map_settings(&self) -> &ShadowMapSettings {
        self.shadow_map.settings()
    }

    /// Whether shadow volumes are built on the GPU (`shadow_volume.build`, `Auto` resolved for
    /// the device).
    pub fn volumes_on_gpu(&self) -> bool {
        self.gpu_volumes.is_some()
    }

    /// Light `light`'s shadow map (while it has one).
    pub fn shadow_map_image(&self, light: usize) -> RenderResult<&Image> {
        self.shadow_map.image(light)
    }
}

/// The GPU path of shadow volumes, when `setup` asks for it: refused (naming the setting) where
/// the device needs volumes clipped on the host, or on a graphics queue that runs no compute;
/// `VolumeBuild::Auto` then builds them on the host instead. In umbra's own frames the counts
/// are read back for the report.
fn gpu_volumes(
    ctx: &Context,
    setup: &Setup,
    scene_set_layout: &DescriptorSetLayout,
    input: VolumeInput,
    bounds: bool,
) -> RenderResult<Option<GpuVolumes>> {
    let settings = &setup.shadow_volume;
    let asked = match settings.build {
        VolumeBuild::Cpu => return Ok(None),
        VolumeBuild::Gpu => true,
        VolumeBuild::Auto => false,
    };
    let refuse = |why: &str| match asked {
        true => {
            let why = format!("VolumeBuild::Gpu {why}");
            Err(RenderError::InvalidInput { field: "shadow_volume.build".into(), why })
        }
        false => Ok(None),
    };
    if input == VolumeInput::HostClipped {
        return refuse(
            "cannot clip volumes on the host, which this device needs (set host_clip to Never to draw them unclipped)",
        );
    }
    if !ctx.capabilities().compute_queue {
        return refuse(&format!("needs compute on the graphics queue, which {} lacks", ctx.capabilities().device_name));
    }
    let clamp = settings.far_plane == FarPlane::DepthClamp;
    let (depth_format, own, overdraw) = (setup.depth_format, setup.own, settings.overdraw);
    let volumes = GpuVolumes::new(ctx, scene_set_layout, depth_format, clamp, bounds, own, overdraw)?;
    Ok(Some(volumes))
}
