//! The diagnostic passes of a frame, declared beside its lights' shadows when asked for: a
//! light's classification (and the stencil that decides a shadow-volume light's pixels), the
//! volumes' overdraw, a silhouette-map light's classification and points, and the final
//! `readback` of the colour target and the overdraw image.

use super::declare::FrameInputs;
use super::lights::LightFrame;
use super::Renderer;
use crate::frame::{PassId, QueryId, Stage, Use};
use crate::light_surfaces::over_surfaces;
use crate::shadow_volume::frame::{self as volume_frame, VolumeLight, VolumeSource};
use crate::RenderResult;
use umbra_vk::{ColorAttachment, DepthAttachment, ImageState, RenderTargets};
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

    /// With `overdraw`, a light's volumes into the overdraw image (cleared by the `first`),
    /// counted by the returned query.
    pub(super) fn declare_overdraw<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        first: bool,
    ) -> Option<QueryId> {
        let ((image, _), volumes) = (self.overdraw.as_ref()?, light.volumes.as_ref()?);
        // Built on the CPU: the frame's vertices; on the GPU: the stages' draws and set.
        let source = match volumes.gpu {
            Some(_) => VolumeSource::Gpu(self.gpu_volumes.as_ref()?, self.slot.volumes.as_ref()?),
            None => VolumeSource::Host(Some(f.volumes?)),
        };
        let v = VolumeLight { surfaces: f.surfaces(light), layout: &self.layout, volumes, source };
        Some(volume_frame::declare_overdraw(stage, &self.shadow_volume, v, image, first))
    }

    /// With diagnostics, a silhouette-map light's classification and silhouette points over
    /// the frame's depth, copied out with its silhouette map.
    pub(super) fn declare_silhouette_diagnostics<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        reads: &[Use<'a>],
    ) {
        let l = light.light();
        let (Some(targets), Some(out), Some(shadow_set)) =
            (&self.diagnostic_targets, &f.bindings[l].silhouette_readback, &f.bindings[l].shadow_set)
        else {
            return;
        };
        let (class, points, depth) = (&targets.classification, &targets.points, f.depth);
        let silmap = self.silhouette_map.image(Some(l));
        let mut uses = vec![Use::Image(class, Color), Use::Image(points, Color), Use::Image(depth, Depth)];
        uses.extend_from_slice(reads);
        uses.extend([
            Use::Readback(&out.classification),
            Use::Readback(&out.points),
            Use::Readback(&out.silhouette_map),
        ]);
        let surfaces = f.surfaces(light);
        stage.pass(PassId::SilhouetteDiagnostics(l), &uses, move |cx| {
            let color = [
                ColorAttachment { image: class, clear: Some(crate::diagnostics::BACKGROUND) },
                ColorAttachment { image: points, clear: Some([0.0; 4]) },
            ];
            cx.rec.begin_rendering(&RenderTargets { color: &color, depth: Some(DepthAttachment::keep(depth)) });
            self.silhouette_map.record_diagnostics(cx, &self.layout, surfaces, shadow_set);
            cx.rec.end_rendering();
            let src = ImageState::TransferSrc;
            cx.enter(&[(class, src), (points, src), (silmap, src)]);
            cx.rec.copy_image_to_buffer(class, 0, &out.classification);
            cx.rec.copy_image_to_buffer(points, 0, &out.points);
            cx.rec.copy_image_to_buffer(silmap, 0, &out.silhouette_map);
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
