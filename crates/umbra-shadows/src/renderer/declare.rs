//! The frame's passes, each declared into the frame graph (`record.rs` puts them in order):
//! the mesh upload (when a mesh changed), an engine's depth rebuilt, and the lights' views (the
//! technique set's, `crate::techniques`); the renderer's own surfaces (`ambient`, the optional
//! `g-buffer`); every recorded light's shadows (its technique's visibility passes and
//! diagnostics, through the technique set; its visibility readback and classification here and
//! in `diagnostics.rs`); the renderer's own lights. Each pass names the images it uses; the
//! graph emits the barriers, labels and timestamps (`crate::frame`).

use super::Renderer;
use crate::frame::{PassId, Stage, Use};
use crate::light_surfaces::over_surfaces;
use crate::techniques::{FrameInputs, LightFrame, LightQueries};
use crate::RenderResult;
use umbra_vk::{ColorAttachment, DepthAttachment, ImageState, RenderTargets};

use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};

impl Renderer {
    /// The frame's first passes: the meshes' upload when they changed, an engine's depth re-drawn
    /// where umbra rebuilds it, then the lights' views: per recorded light its shadow map and
    /// silhouette points.
    pub(super) fn declare_views<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> RenderResult<()> {
        if let Some(upload) = &f.gpu.upload {
            stage.pass(PassId::MeshUpload, &[], move |cx| {
                upload.record(cx.rec, &f.gpu.geometry);
                Ok(())
            });
        }
        if let Some(rebuild) = f.rebuild {
            stage.pass(PassId::DepthRebuild, &[Use::Image(f.depth, Depth)], move |cx| {
                rebuild.record(cx.rec, &self.layout, f.gpu, f.scene, cx.log)
            });
        }
        self.techniques.declare_views(stage, f)
    }

    /// The renderer's own surfaces, before any light's shadows test them: `ambient` (its
    /// depth and the ambient term) and the optional `g-buffer`. An engine draws its own.
    pub(super) fn declare_surfaces<'a>(&'a self, stage: &mut Stage<'a>, f: FrameInputs<'a>) -> RenderResult<()> {
        let (color, depth) = (&self.own()?.color, f.depth);
        stage.pass(PassId::Ambient, &[Use::Image(color, Color), Use::Image(depth, Depth)], move |cx| {
            let bg = f.scene.background;
            let clear = [ColorAttachment { image: color, view: None, clear: Some([bg.x, bg.y, bg.z, 1.0]) }];
            let depth = DepthAttachment::cleared(depth, 1.0, 0);
            cx.rec.begin_rendering(&RenderTargets { color: &clear, depth: Some(depth) });
            self.forward.record_ambient(cx.rec, &self.layout, f.gpu, f.scene, cx.log);
            cx.rec.end_rendering();
            Ok(())
        });
        if let Some(g) = &self.gbuffer {
            stage.pass(PassId::GBuffer, &[&g.uses()[..], &[Use::Image(depth, Depth)]].concat(), move |cx| {
                g.record(cx, &self.layout, f.gpu, f.scene, depth);
                Ok(())
            });
        }
        Ok(())
    }

    /// The renderer's own lights, after every light's shadows (`queries`, from
    /// `declare_shadows`): the volume counts read back, every recorded light's lighting, then
    /// `readback`. Whether the volume counts are read back.
    pub(super) fn declare_lights<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        queries: &[LightQueries],
        overdraw: bool,
    ) -> RenderResult<bool> {
        let counted = self.techniques.declare_volume_counts(stage, f);
        for light in f.lights.iter().filter(|l| l.plan.recorded && f.bindings[l.light()].shadow_set.is_some()) {
            self.declare_light(stage, f, light, queries[light.light()].shadowed)?;
        }
        self.declare_readback(stage, overdraw)?;
        Ok(counted)
    }

    /// Every recorded light's shadows, before any light is lit: its visibility image (and its
    /// copy), then the diagnostics asked for. Returns each light's queries and whether the
    /// overdraw image was drawn.
    pub(super) fn declare_shadows<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
    ) -> RenderResult<(Vec<LightQueries>, bool)> {
        let mut queries = vec![LightQueries::default(); f.lights.len()];
        let mut overdraw = false;
        let shadows = self.techniques.begin_shadows(stage, f);
        for light in f.lights.iter().filter(|l| l.plan.recorded) {
            let l = light.light();
            let Some(shadow_set) = &f.bindings[l].shadow_set else { continue };
            let reads = self.techniques.light_reads(light)?;
            let shadowed = self.techniques.declare_visibility(stage, f, light, shadow_set, &reads, &mut queries[l])?;
            queries[l].shadowed = shadowed;
            if let (true, Some(out)) = (shadowed, f.bindings[l].visibility_readback) {
                let (image, src) = (&self.visibility.light(l)?.image, ImageState::TransferSrc);
                stage.pass(
                    PassId::VisibilityReadback(l),
                    &[Use::Image(image, src), Use::Readback(&out.buffer)],
                    |cx| {
                        cx.rec.copy_image_to_buffer(image, 0, &out.buffer);
                        Ok(())
                    },
                );
            }
            self.declare_light_diagnostics(stage, f, light, &reads);
            queries[l].volume_fragments =
                self.techniques.declare_light_extras(stage, f, shadows, light, &reads, !overdraw)?;
            overdraw |= queries[l].volume_fragments.is_some();
        }
        self.techniques.end_shadows(stage, shadows);
        Ok((queries, overdraw))
    }

    /// `light N (kind)`: the light's Lambert term times its visibility image (`shadowed`), or
    /// unshadowed.
    fn declare_light<'a>(
        &'a self,
        stage: &mut Stage<'a>,
        f: FrameInputs<'a>,
        light: &'a LightFrame,
        shadowed: bool,
    ) -> RenderResult<()> {
        let (l, depth) = (light.light(), f.depth);
        let color = &self.own()?.color;
        let mut uses = vec![Use::Image(color, Color), Use::Image(depth, Depth)];
        let set = match shadowed {
            true => {
                let own = self.visibility.light(l)?;
                uses.push(Use::Image(&own.image, Read));
                &own.set
            }
            false => &self.visibility.unshadowed_set,
        };
        let visibility = (set, shadowed);
        let surfaces = f.surfaces(light);
        stage.pass(PassId::Light(l, light.plan.kind), &uses, move |cx| {
            over_surfaces(cx.rec, color, None, depth);
            self.forward.record_light(cx, &self.layout, surfaces, visibility);
            cx.rec.end_rendering();
            Ok(())
        });
        Ok(())
    }
}
