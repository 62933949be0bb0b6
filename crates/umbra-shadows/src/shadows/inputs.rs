//! What an engine hands umbra each frame, checked (a typed error naming the field, before
//! anything is recorded), and what umbra hands back.

use super::registry::invalid;
use crate::frame::timing::PassReport;
use crate::plan::LightPlan;
use crate::RenderResult;
use glam::Mat4;
use umbra_scene::Light;
use umbra_vk::{vk, ImageState};

/// The engine's depth buffer for a frame.
#[derive(Clone, Copy, Debug)]
pub struct DepthTarget {
    /// The image, one layer. umbra's passes test it as it is when it is single-sampled, has
    /// a stencil and was drawn in umbra's depth convention ([`FrameInputs::proj`]); otherwise
    /// umbra re-draws depth into an image of its own and does not touch this one
    /// ([`ShadowFrame::depth_rebuilt`]).
    pub image: vk::Image,
    /// A view of it with every aspect it has (depth, and stencil for D32S8 / D24S8).
    pub view: vk::ImageView,
    /// Its format; the one [`crate::ShadowsDesc::depth_format`] named.
    pub format: vk::Format,
    /// Its extent; the size [`crate::ShadowsDesc`] was made for.
    pub extent: vk::Extent2D,
    /// The usage it was created with: where umbra tests it, `DEPTH_STENCIL_ATTACHMENT`, and
    /// `TRANSFER_SRC` where a light uses the hybrid (its classification copies the depth).
    pub usage: vk::ImageUsageFlags,
    /// Its sample count (multisampled: umbra re-draws depth single-sampled).
    pub samples: vk::SampleCountFlags,
    /// The layout it is in when umbra's commands begin, written by earlier commands of the
    /// engine's (a depth pre-pass); umbra leaves it in the same layout.
    /// `DEPTH_STENCIL_ATTACHMENT_OPTIMAL` or `DEPTH_STENCIL_READ_ONLY_OPTIMAL`.
    pub layout: vk::ImageLayout,
}

/// What [`crate::Shadows::record`] needs each frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameInputs<'a> {
    /// The engine's depth of this frame, drawn with `proj * view` (see `docs/embedding.md`
    /// for the vertex transform that keeps umbra's EQUAL tests exact).
    pub depth: DepthTarget,
    /// World to view, right-handed (the camera looks down -Z), as the engine built it.
    pub view: Mat4,
    /// View to clip, as the engine built it: a right-handed perspective (`w_clip = -z_view`)
    /// with Vulkan's 0..1 depth, standard or reversed-Z, finite or infinite far plane. umbra's
    /// own convention — standard depth, and the far plane at infinity wherever a light's
    /// volumes must reach it (shadow volumes, the hybrid, unless `shadow_volume.far_plane` is
    /// `DepthClamp`) — lets it test the engine's depth; any other makes it re-draw its own.
    /// umbra's viewport is y-up (row 0 is clip-space y = +1), as `glam`'s `perspective_rh`
    /// expects.
    pub proj: Mat4,
    /// This frame's lights, each with its technique.
    pub lights: &'a [Light],
    /// The engine's frame counter: frame slot `frame_index % frames_in_flight` is used, and
    /// must no longer be in use on the GPU (the engine waited for that slot's fence).
    pub frame_index: u64,
}

/// An image umbra hands the engine, ready to sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampledImage {
    /// The image.
    pub image: vk::Image,
    /// A view of every layer (`2D`, `2D_ARRAY` or `CUBE`).
    pub view: vk::ImageView,
    /// Its format.
    pub format: vk::Format,
    /// The layout umbra left it in: `SHADER_READ_ONLY_OPTIMAL`.
    pub layout: vk::ImageLayout,
    /// The stages umbra's last barrier made its writes visible to: `FRAGMENT_SHADER`.
    pub stages: vk::PipelineStageFlags2,
}

/// A light's shadow map, for engines that sample maps themselves.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMapOutput {
    /// The depth map (D32, six layers for a cube).
    pub image: SampledImage,
    /// World to clip of each layer, as the map was drawn.
    pub view_proj: Vec<Mat4>,
    /// Texels per side.
    pub resolution: u32,
}

/// What one light got this frame.
#[derive(Clone, Debug)]
pub struct LightShadows {
    /// Index of the light in [`FrameInputs::lights`].
    pub light: usize,
    /// Its visibility image (`crate::VISIBILITY_FORMAT`: R visibility, G 1 where its shadow is
    /// in question), or `None` when nothing shadows it this frame: light it unshadowed.
    pub visibility: Option<SampledImage>,
    /// Its shadow map, when its technique drew one.
    pub shadow_map: Option<ShadowMapOutput>,
    /// What umbra planned for it (technique, culling, reports).
    pub plan: LightPlan,
}

/// What [`crate::Shadows::record`] recorded.
#[derive(Clone, Debug)]
pub struct ShadowFrame {
    /// Per light, in order.
    pub lights: Vec<LightShadows>,
    /// The frame slot used.
    pub slot: usize,
    /// The passes this slot recorded the last time it was used, with their GPU times where the
    /// GPU had written them (read without waiting); `None` on the slot's first frame.
    pub earlier_passes: Option<Vec<PassReport>>,
    /// Bytes of mesh data uploaded for this frame (0 when no mesh was added or removed),
    /// copied from staging buffers by the frame's first pass (`mesh upload`).
    pub geometry_uploaded_bytes: u64,
    /// Vulkan memory allocations made while recording it (0 once warm).
    pub memory_allocations: u64,
    /// Queue submissions made through the context while recording it (`Context::submissions`;
    /// nothing else should submit through it meanwhile): 0, `record` never submits (a mesh
    /// upload too is recorded into the engine's command buffer, the `mesh upload` pass).
    pub submissions: u64,
    /// Why umbra re-drew the scene's depth into an image of its own this frame (a depth-only
    /// pass, `depth rebuild`), or `None` when its passes tested the engine's depth as it was.
    pub depth_rebuilt: Option<RebuildReason>,
}

/// The state `layout` stands for, or a typed error naming the field.
pub(crate) fn depth_state(layout: vk::ImageLayout) -> RenderResult<ImageState> {
    match layout {
        vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL => Ok(ImageState::DepthStencilAttachment),
        vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL => Ok(ImageState::DepthStencilReadOnly),
        other => Err(invalid(
            "FrameInputs::depth.layout".into(),
            format!(
                "{other:?}: hand the depth over in DEPTH_STENCIL_ATTACHMENT_OPTIMAL or DEPTH_STENCIL_READ_ONLY_OPTIMAL"
            ),
        )),
    }
}

/// How a projection stores depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Convention {
    /// Depth 1 at the near plane, falling with distance.
    pub reversed: bool,
    /// The far plane at infinity.
    pub infinite: bool,
}

/// `proj`'s depth convention, or a typed error when it is no right-handed perspective.
pub(crate) fn convention(proj: Mat4) -> RenderResult<Convention> {
    let perspective = proj.x_axis.w == 0.0 && proj.y_axis.w == 0.0 && proj.z_axis.w == -1.0 && proj.w_axis.w == 0.0;
    if !(proj.is_finite() && perspective && proj.y_axis.y != 0.0) {
        return Err(invalid(
            "FrameInputs::proj".into(),
            "must be a finite right-handed perspective (w_clip = -z_view), as glam's perspective_rh builds".into(),
        ));
    }
    let depth = |z: f32| {
        let clip = proj * glam::Vec4::new(0.0, 0.0, z, 1.0);
        clip.z / clip.w
    };
    let reversed = depth(-2.0) < depth(-1.0);
    // Far at infinity: depth tends to 1 (standard) or 0 (reversed) as z → -∞.
    let at_infinity = proj.z_axis.z / proj.z_axis.w;
    let infinite = if reversed { at_infinity == 0.0 } else { at_infinity == 1.0 };
    Ok(Convention { reversed, infinite })
}

/// Why umbra re-drew its own depth for a frame instead of testing the engine's
/// ([`ShadowFrame::depth_rebuilt`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RebuildReason {
    /// The engine's depth is multisampled; umbra's passes are single-sampled.
    Multisampled,
    /// The engine's depth has no stencil: umbra's passes are built for a depth/stencil format
    /// (shadow volumes count in the stencil), so they cannot use it as an attachment.
    NoStencil,
    /// The engine's projection is reversed-Z; umbra's passes test standard depth.
    ReversedZ,
    /// The engine's far plane is finite, and a light's volumes reach infinity (no depth clamp).
    FiniteFar,
}

impl std::fmt::Display for RebuildReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Multisampled => "the depth is multisampled",
            Self::NoStencil => "the depth has no stencil",
            Self::ReversedZ => "the projection is reversed-Z",
            Self::FiniteFar => "the far plane is finite and a light's volumes reach infinity",
        })
    }
}

/// Why umbra's passes cannot test against a depth of `samples` and `format` drawn with
/// convention `c`, or `None` when they can. `finite_allowed`: no light needs volumes reaching
/// infinity without depth clamp.
pub(crate) fn rebuild_reason(
    samples: vk::SampleCountFlags,
    format: vk::Format,
    c: Convention,
    finite_allowed: bool,
) -> Option<RebuildReason> {
    let stencil = umbra_vk::format_aspect(format).contains(vk::ImageAspectFlags::STENCIL);
    if samples != vk::SampleCountFlags::TYPE_1 {
        Some(RebuildReason::Multisampled)
    } else if !stencil {
        Some(RebuildReason::NoStencil)
    } else if c.reversed {
        Some(RebuildReason::ReversedZ)
    } else if !(c.infinite || finite_allowed) {
        Some(RebuildReason::FiniteFar)
    } else {
        None
    }
}

/// `proj` (of convention `c`) in umbra's own: the same x, y and w rows, so that every pixel
/// covers what it covered, and standard depth with the far plane at infinity (glam's
/// `perspective_infinite_rh` for the same near plane).
pub(crate) fn standard_infinite(proj: Mat4, c: Convention) -> Mat4 {
    // z_clip = a·z + b and w = -z: depth 0 (standard) or 1 (reversed) at z = -near. In f64, so
    // that the near plane comes back as the engine gave it wherever f32 allows.
    let (a, b) = (f64::from(proj.z_axis.z), f64::from(proj.w_axis.z));
    let near = if c.reversed { b / (1.0 + a) } else { b / a };
    let mut out = proj;
    out.z_axis.z = -1.0;
    out.w_axis.z = -near as f32;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conventions_are_read_off_the_projection() {
        let (fov, aspect) = (1.0, 4.0 / 3.0);
        let c = |p| convention(p).unwrap();
        assert_eq!(c(Mat4::perspective_rh(fov, aspect, 0.1, 100.0)), Convention { reversed: false, infinite: false });
        assert_eq!(c(Mat4::perspective_infinite_rh(fov, aspect, 0.1)), Convention { reversed: false, infinite: true });
        assert_eq!(c(Mat4::perspective_rh(fov, aspect, 100.0, 0.1)), Convention { reversed: true, infinite: false });
        let reversed_infinite = Mat4::perspective_infinite_reverse_rh(fov, aspect, 0.1);
        assert_eq!(c(reversed_infinite), Convention { reversed: true, infinite: true });
        let orthographic = Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0);
        assert!(convention(orthographic).unwrap_err().to_string().starts_with("FrameInputs::proj: must be"));
        for p in [Mat4::perspective_rh(fov, aspect, 0.1, 100.0), reversed_infinite] {
            let standard = standard_infinite(p, c(p));
            // x and y rows are kept as given (glam rounds them one ulp apart between builders).
            assert!(standard.abs_diff_eq(Mat4::perspective_infinite_rh(fov, aspect, 0.1), 1e-6), "{p}");
            assert_eq!(standard.z_axis.z, -1.0);
        }
        let reversed_finite = standard_infinite(
            Mat4::perspective_rh(fov, aspect, 100.0, 0.1),
            c(Mat4::perspective_rh(fov, aspect, 100.0, 0.1)),
        );
        assert!((reversed_finite.w_axis.z + 0.1).abs() < 1e-7, "{reversed_finite}");
        let standard = Convention { reversed: false, infinite: true };
        let (one, d32s8, d32) = (vk::SampleCountFlags::TYPE_1, vk::Format::D32_SFLOAT_S8_UINT, vk::Format::D32_SFLOAT);
        assert_eq!(rebuild_reason(one, d32s8, standard, false), None);
        assert_eq!(
            rebuild_reason(vk::SampleCountFlags::TYPE_4, d32s8, standard, false),
            Some(RebuildReason::Multisampled)
        );
        assert_eq!(rebuild_reason(one, d32, standard, true), Some(RebuildReason::NoStencil));
        assert_eq!(
            rebuild_reason(one, d32s8, Convention { reversed: true, infinite: true }, true),
            Some(RebuildReason::ReversedZ)
        );
        let finite = Convention { reversed: false, infinite: false };
        assert_eq!(rebuild_reason(one, d32s8, finite, false), Some(RebuildReason::FiniteFar));
        assert_eq!(rebuild_reason(one, d32s8, finite, true), None);
        assert!(depth_state(vk::ImageLayout::GENERAL).unwrap_err().to_string().contains("FrameInputs::depth.layout"));
    }
}
