//! The passes of one hybrid light in the frame graph, in the paper's order (Chan–Durand §3):
//! step 2 `hybrid classify`, §4 `computation mask`, step 3 `hybrid volumes`, step 4
//! `hybrid visibility`, then the diagnostics asked for; a ray-traced hybrid light's
//! `hybrid ray list`, `hybrid classify` and `hybrid rays` (`hybrid::rays`). Each declares the images it uses. The
//! light's lighting pass (declared by the renderer) reads the visibility image they wrote.

use super::pass::{HybridLight, HybridPass};
use super::rays::{HybridRays, RaysLight};
use crate::diagnostics::ClassReadback;
use crate::frame::{PassId, QueryId, Stage, Use};
use umbra_vk::{BufferState, Image, ImageState};

/// The queries of one hybrid light: the mask pass's samples and, with `overdraw`, the volume
/// fragments the mask lets through.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HybridQueries {
    pub mask: QueryId,
    pub fragments: Option<QueryId>,
}

/// Declares light `h.light`'s passes after its depth bounds `bounds`;
/// `h.mask_query` is set here.
/// `fragments`: count the masked volume fragments (`overdraw`); `readback`: copy the classes
/// and the stencil out (diagnostics).
pub(crate) fn declare_light<'a>(
    stage: &mut Stage<'a>,
    pass: &'a HybridPass,
    mut h: HybridLight<'a>,
    bounds: &'a Image,
    fragments: bool,
    readback: Option<&'a ClassReadback>,
) -> HybridQueries {
    let Some(classes) = pass.classes() else {
        return HybridQueries { mask: QueryId(0), fragments: None };
    };
    use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};
    h.mask_query = stage.queries(1);
    let target = pass.count_target(h.mask, h.depth);
    let l = h.light;

    let classify = [Use::Image(h.visibility, Color), Use::Image(classes, Color), Use::Image(h.depth, Depth)];
    stage.pass(PassId::HybridClassify(l), &[&classify[..], &[Use::Image(bounds, Read)]].concat(), move |cx| {
        pass.record_classify(cx, &h);
        Ok(())
    });
    // With depth-bounds the frame's depth is first copied into the masked target.
    let mask_uses = match target.raw != h.depth.raw {
        true => vec![Use::Image(h.depth, ImageState::TransferSrc), Use::Image(target, ImageState::TransferDst)],
        false => vec![Use::Image(h.depth, Depth)],
    };
    stage.pass(PassId::ComputationMask(l), &[&mask_uses[..], &[Use::Image(classes, Read)]].concat(), move |cx| {
        pass.record_mask(cx, &h);
        Ok(())
    });
    let volume_uses = [vec![Use::Image(target, Depth)], h.source.reads()].concat();
    stage.pass(PassId::HybridVolumes(l), &volume_uses, move |cx| pass.record_volumes(cx, &h));
    let resolve = [Use::Image(h.visibility, Color), Use::Image(target, Depth), Use::Image(classes, Read)];
    stage.pass(PassId::HybridVisibility(l), &resolve, move |cx| {
        pass.record_visibility(cx, &h);
        Ok(())
    });
    let fragments = fragments.then(|| {
        let query = stage.queries(1);
        stage.pass(PassId::MaskedVolumeFragments(l), &[Use::Image(target, Depth)], move |cx| {
            pass.record_fragments(cx, &h, query)
        });
        query
    });
    if let Some(out) = readback {
        let mut uses = vec![
            Use::Image(classes, ImageState::TransferSrc),
            Use::Image(target, ImageState::TransferSrc),
            Use::Readback(&out.classes),
        ];
        uses.extend(out.stencil.as_ref().map(Use::Readback));
        stage.pass(PassId::HybridDiagnostics(l), &uses, move |cx| {
            pass.record_readback(cx, &h, out);
            Ok(())
        });
    }
    HybridQueries { mask: h.mask_query, fragments }
}

/// Declares a ray-traced hybrid light's passes (`hybrid::rays`) after its depth bounds
/// `bounds`: the list emptied, the classification appending the silhouette pixels' rays, the
/// rays; with `counted`, the list's count copied out for the report.
pub(crate) fn declare_rays_light<'a>(
    stage: &mut Stage<'a>,
    rays: &'a HybridRays,
    r: RaysLight<'a>,
    bounds: &'a Image,
    counted: bool,
) {
    let Some((header, entries, pixel_rays)) = rays.list() else { return };
    use BufferState::{ComputeRead, FragmentStorage, TransferDst, TransferSrc};
    use ImageState::{ColorAttachment as Color, DepthStencilAttachment as Depth, FragmentRead as Read};
    let l = r.light;
    stage.pass(PassId::HybridRayList(l), &[Use::Buffer(header, TransferDst)], move |cx| {
        rays.record_reset(cx);
        Ok(())
    });
    let classify = [
        Use::Image(r.visibility, Color),
        Use::Image(r.classes, Color),
        Use::Image(pixel_rays, Color),
        Use::Image(r.depth, Depth),
        Use::Image(bounds, Read),
        Use::Buffer(header, FragmentStorage),
        Use::Buffer(entries, FragmentStorage),
    ];
    stage.pass(PassId::HybridClassify(l), &classify, move |cx| {
        rays.record_classify(cx, &r);
        Ok(())
    });
    let cast = [
        Use::Image(r.visibility, ImageState::ComputeWrite),
        Use::Image(pixel_rays, ImageState::ComputeRead),
        Use::Buffer(header, ComputeRead),
        Use::Buffer(entries, ComputeRead),
    ];
    stage.pass(PassId::HybridRays(l), &cast, move |cx| {
        rays.record_rays(cx, &r);
        Ok(())
    });
    if let (true, Some(out)) = (counted, rays.count_readback(l)) {
        stage.pass(PassId::HybridRayCount(l), &[Use::Buffer(header, TransferSrc), Use::Readback(out)], move |cx| {
            rays.record_count(cx, l);
            Ok(())
        });
    }
}
