//! What a renderer is created with ([`RendererDesc`]), what a frame returns ([`Frame`]), and the
//! frame-sized targets checked against the device before anything is made.

use crate::budget::DEFAULT_SHADOW_MAP_BUDGET;
use crate::diagnostics::{GBuffer, LightDiagnostics};
use crate::gbuffer;
use crate::hybrid::{HybridSettings, MaskKind};
use crate::plan::auto::AutoPolicy;
use crate::ray_traced::BvhLayout;
use crate::report::FrameReport;
use crate::shadow_map::ShadowMapSettings;
use crate::shadow_volume::ShadowVolumeSettings;
use crate::targets::{depth_desc, COLOR_FORMAT};
use crate::techniques;
use crate::visibility::VisibilityImage;
use crate::{RenderError, RenderResult};
use std::path::Path;
use umbra_vk::{vk, Context, Image, ImageDesc};

/// What a renderer renders into, and how its techniques are set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererDesc {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Shadow-map settings for lights whose technique is `shadow_map`.
    pub shadow_map: ShadowMapSettings,
    /// Shadow-volume settings for lights whose technique is `shadow_volume` (`hybrid` lights
    /// use its far-plane choice and `overdraw`).
    pub shadow_volume: ShadowVolumeSettings,
    /// Settings of lights whose technique is `hybrid`.
    pub hybrid: HybridSettings,
    /// How the ray-casting techniques (`ray_traced`, `hybrid_rt`) lay out each mesh's BVH:
    /// binary (the default) or compressed wide (CWBVH). Both give the same images; which
    /// walks faster is measured in `docs/techniques/ray-traced.md`.
    pub bvh: BvhLayout,
    /// How lights whose technique is `auto` choose theirs (`crate::plan::auto`): `None` (the
    /// default), [`AutoPolicy::for_device`] of the renderer's device.
    pub auto: Option<AutoPolicy>,
    /// Render the diagnostic views of every light ([`Frame::diagnostics`]: its per-pixel
    /// classification, hence its shadow mask; silhouette points and map for silhouette-map
    /// lights, the stencil for hybrid and shadow-volume lights), count silhouette-map lights'
    /// silhouette pixels, and count how far ray-casting lights' rays walk the BVH
    /// (`RayTracedReport::traversal`, the `ray stats` passes): one more pass and readback per
    /// light, reported as a diagnostic pass. Off by default.
    pub diagnostics: bool,
    /// Render the G-buffer ([`Frame::gbuffer`]): world position and geometric normal per
    /// pixel, for the exact reference. One diagnostic pass. Off by default.
    pub gbuffer: bool,
    /// Read every shadowed light's visibility image back ([`Frame::visibility`]): what its
    /// technique decided per pixel, the input of the accuracy measurements. One copy per
    /// light (8 bytes a pixel), reported as a diagnostic pass. Off by default.
    pub read_visibility: bool,
    /// Read the colour target back into [`Frame::rgba`]. On by default; off, the frame's
    /// pixels stay on the GPU ([`crate::Renderer::color_image`], to present with
    /// `umbra_vk::Swapchain::present_image`) and `rgba` is empty.
    pub read_color: bool,
    /// Plan each frame so that nothing that cannot change the image is recorded (lights out of
    /// view, casters whose shadows cannot be seen, scissor and depth bounds of bounded lights;
    /// see [`crate::plan`]). On by default; off records every pass of every light over every
    /// caster, the same image, for comparison (`--no-cull`).
    pub cull: bool,
    /// The most bytes the shadow storage of one frame may take: every light's depth map (4
    /// bytes a texel, six faces for a cube), silhouette map (8 bytes a texel) and, with
    /// `diagnostics`, its readback. A frame whose lights need more is refused with
    /// [`RenderError::ShadowBudget`] before any map is allocated (no fallback: lower the
    /// resolutions or shadow fewer lights). Default [`DEFAULT_SHADOW_MAP_BUDGET`] (1 GiB: ten
    /// point lights' 2048² cube maps); `u64::MAX` is unlimited.
    pub shadow_map_budget_bytes: u64,
}

impl RendererDesc {
    /// A `width` × `height` target with default technique settings.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            shadow_map: ShadowMapSettings::DEFAULT,
            shadow_volume: ShadowVolumeSettings::default(),
            hybrid: HybridSettings::default(),
            bvh: BvhLayout::Binary,
            auto: None,
            diagnostics: false,
            gbuffer: false,
            read_visibility: false,
            read_color: true,
            cull: true,
            shadow_map_budget_bytes: DEFAULT_SHADOW_MAP_BUDGET,
        }
    }
}

/// A rendered frame: RGBA8 pixels (row 0 at the top) and its report.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Tightly packed RGBA8, `width * height * 4` bytes; empty without
    /// [`RendererDesc::read_color`].
    pub rgba: Vec<u8>,
    /// What the frame did.
    pub report: FrameReport,
    /// Volume overdraw (RGBA8, red = volume fragments per pixel, saturating at 255), when the
    /// renderer was built with `shadow_volume.overdraw` and a light used shadow volumes.
    pub overdraw: Option<Vec<u8>>,
    /// Per recorded light, its diagnostic views (with `RendererDesc::diagnostics`), in light
    /// order.
    pub diagnostics: Vec<LightDiagnostics>,
    /// What every pixel shows (with `RendererDesc::gbuffer`).
    pub gbuffer: Option<GBuffer>,
    /// Per light whose technique wrote one this frame, its visibility image (with
    /// `RendererDesc::read_visibility`), in light order.
    pub visibility: Vec<VisibilityImage>,
}

impl Frame {
    /// The RGBA value at `(x, y)`, `y = 0` being the top row.
    ///
    /// # Panics
    /// When `(x, y)` lies outside the frame, like slice indexing, and for every pixel of a
    /// frame not read back (`RendererDesc::read_color` off: `rgba` is empty).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        let mut p = [0; 4];
        p.copy_from_slice(&self.rgba[i..i + 4]);
        p
    }

    /// Light `light`'s shadow mask (per pixel `Some(true)` shadowed, `Some(false)` lit, `None`
    /// not in question): from its visibility image ([`VisibilityImage::shadow_mask`]), or, for a
    /// light nothing shadowed this frame, from its classification. `None` without either (render
    /// with `read_visibility` and `diagnostics`).
    pub fn shadow_mask(&self, light: usize) -> Option<Vec<Option<bool>>> {
        match self.visibility.iter().find(|v| v.light == light) {
            Some(v) => Some(v.shadow_mask()),
            None => self.diagnostics.iter().find(|d| d.light == light).map(LightDiagnostics::shadow_mask),
        }
    }

    /// Every light that has a shadow mask ([`Frame::shadow_mask`]), in light order, with it:
    /// what an accuracy measurement compares with the reference. Ray-traced lights have a
    /// visibility image but no classification.
    pub fn shadow_masks(&self) -> impl Iterator<Item = (usize, Vec<Option<bool>>)> + '_ {
        (0..self.report.lights.len()).filter_map(|l| self.shadow_mask(l).map(|m| (l, m)))
    }

    /// Writes the pixels as a PNG.
    pub fn save_png(&self, path: &Path) -> RenderResult<()> {
        image::save_buffer(path, &self.rgba, self.width, self.height, image::ColorType::Rgba8)
            .map_err(|e| RenderError::Output { path: path.to_owned(), message: e.to_string() })
    }

    /// Writes the report as pretty JSON.
    pub fn save_report(&self, path: &Path) -> RenderResult<()> {
        std::fs::write(path, self.report.to_json())
            .map_err(|e| RenderError::Output { path: path.to_owned(), message: e.to_string() })
    }
}

/// A frame-sized RGBA8 image rendered to and copied out (colour, overdraw, diagnostic views).
pub(crate) fn frame_target(ctx: &Context, name: &str, width: u32, height: u32) -> RenderResult<Image> {
    Ok(Image::new(ctx, name, frame_target_desc(width, height))?)
}

/// The description of [`frame_target`]'s images.
pub(crate) fn frame_target_desc(width: u32, height: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    ImageDesc::new_2d(COLOR_FORMAT, width, height).usage(usage)
}

/// Checks `desc`'s size against every limit of the frame-sized images the renderer may create
/// (colour and depth targets, the hybrid's classes and masked depth, the visibility image, the
/// G-buffer): a typed
/// [`RenderError::InvalidSize`] naming the first limit broken, before anything is created.
pub(crate) fn check_frame_size(
    ctx: &Context,
    desc: &RendererDesc,
    depth_format: vk::Format,
    mask: MaskKind,
) -> RenderResult<()> {
    let (width, height) = (desc.width, desc.height);
    if width == 0 || height == 0 {
        return Err(RenderError::InvalidSize {
            width,
            height,
            why: "each side must be at least 1".into(),
            limit: None,
        });
    }
    let mut images = vec![
        ("colour target", frame_target_desc(width, height)),
        ("depth/stencil target", depth_desc(depth_format, width, height)),
    ];
    // The techniques' first (the hybrid's classes) before the visibility image, as always: the
    // first image over a limit is the one the error names.
    let mut technique_images = techniques::frame_images(depth_format, width, height, mask).into_iter();
    images.extend(technique_images.next());
    images.push(("visibility image", crate::visibility::image_desc(width, height, false)));
    images.extend(technique_images);
    if desc.gbuffer {
        images.push(("g-buffer", gbuffer::target_desc(width, height)));
    }
    for (name, image) in images {
        if let Some((what, limit)) = ctx.image_limits(&image)?.broken_by(&image) {
            let device = &ctx.capabilities().device_name;
            return Err(RenderError::InvalidSize {
                width,
                height,
                why: format!("the {name}'s {what} is over a device limit: {limit} on {device}"),
                limit: Some(limit),
            });
        }
    }
    Ok(())
}
