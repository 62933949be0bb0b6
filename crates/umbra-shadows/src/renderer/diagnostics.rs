//! The diagnostic passes of a frame the renderer declares beside its lights' shadows when asked
//! for: a light's classification (and the stencil that decides a shadow-volume light's pixels),
//! and the final `readback` of the colour target and the overdraw image. A technique's own
//! diagnostics (volume overdraw, a silhouette map's points) are the technique set's.

use super::Renderer;
use crate::frame::{PassId, Stage, Use};
use crate::light_surfaces::over_surfaces;
use crate::techniques::{FrameInputs, LightFrame};
use crate::RenderResult;
use umbra_vk::ImageState;
use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth};

impl Renderer {
    /// With diagnostics, a shadow-map or shadow-volume light's classification (and the
    /// stencil that decides a shadow-volume light's pixels), copied out.
    pub(super) fn declare_light_diagnostics<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        reads: &[Use<'a>],
    ) {
        let l = light.light();
        let (Some(targets), Some(out), false) =
            (&self.diagnostic_targets, &f.bindings[l].class_readback, light.hybrid())
        else {
            return;
        };
        let Some(shadow_set) = &f.bindings[l].shadow_set else { return };
        let (class, depth) = (&targets.classification, f.depth);
        let mut uses = vec![Use::Image(class, Color), Use::Image(depth, Depth), Use::Readback(&out.classes)];
        uses.extend(out.stencil.as_ref().map(Use::Readback));
        uses.extend_from_slice(reads);
        let surfaces = f.surfaces(light);
        stage.pass(PassId::LightDiagnostics(l), &uses, move |cx| {
            over_surfaces(cx.rec, class, Some([0.0; 4]), depth);
            self.forward.record_classes(cx, &self.layout, surfaces, shadow_set);
            cx.rec.end_rendering();
            cx.enter(&[(class, ImageState::TransferSrc)]);
            cx.rec.copy_image_to_buffer(class, 0, &out.classes);
            if let Some(stencil) = &out.stencil {
                cx.enter(&[(depth, ImageState::TransferSrc)]);
                cx.rec.copy_stencil_to_buffer(depth, stencil);
            }
            Ok(())
        });
    }

    /// `readback`: the colour target (with `read_color`) and the overdraw image (when drawn)
    /// copied out; the colour target is left ready for transfers either way
    /// ([`Renderer::color_image`]).
    pub(super) fn declare_readback<'a>(&'a self, stage: &mut Stage<'a>, overdraw: bool) -> RenderResult<()> {
        let src = ImageState::TransferSrc;
        let own = self.own()?;
        let mut uses = vec![Use::Image(&own.color, src)];
        if let Some(readback) = &own.readback {
            uses.push(Use::Readback(readback));
        }
        let overdraw = self.overdraw.as_ref().filter(|_| overdraw);
        if let Some((image, readback)) = overdraw {
            uses.extend([Use::Image(image, src), Use::Readback(readback)]);
        }
        stage.pass(PassId::Readback, &uses, move |cx| {
            if let Some(readback) = &own.readback {
                cx.rec.copy_image_to_buffer(&own.color, 0, readback);
            }
            if let Some((image, readback)) = overdraw {
                cx.rec.copy_image_to_buffer(image, 0, readback);
            }
            Ok(())
        });
        Ok(())
    }
}
