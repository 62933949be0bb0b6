//! Counts that never alias. An 8-bit stencil count wraps, so a pixel inside 256·k volumes
//! would read 0, lit (Everitt–Kilgard accept it). Each volume adds at most its `count_bound`
//! to a pixel (`build.rs`: 1 for a convex solid). When a light's bounds fit the count's bits
//! its casters are counted at once, as in the paper. Otherwise they are counted in batches
//! whose bounds fit a narrower count, and after each batch a full-screen draw keeps "this
//! batch's count ≠ 0" in a fold bit and clears the count: the count bits together are then
//! non-zero exactly where some volume holds the pixel, which is all the visibility passes read.

use super::build::{CasterVolume, LightVolumes};
use crate::frame::timing::PassLog;
use std::ops::Range;
use umbra_vk::{vk, DepthState, GraphicsPipeline, GraphicsPipelineDesc, Recorder, StencilFace};

/// A stencil count's layout: `all` counts when the casters go at once; in batches `batch`
/// counts and `fold` keeps "an earlier batch's count was non-zero".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CountBits {
    pub all: u8,
    pub batch: u8,
    pub fold: u8,
}

/// The whole 8-bit stencil (shadow volumes; the hybrid with the depth-bounds mask or none).
pub(crate) const FULL_STENCIL: CountBits = CountBits { all: 0xff, batch: 0x7f, fold: 0x80 };

/// The batches `casters` are counted in, as ranges of it: one when their bounds sum to at
/// most `bits.all`, else greedy runs whose bounds sum to at most `bits.batch` (a caster whose
/// own bound is larger is a batch alone: its count aliases only where one ray crosses
/// `bits.batch + 1` of its caps).
pub(crate) fn count_batches(casters: &[CasterVolume], bits: CountBits) -> Vec<Range<usize>> {
    let total: u64 = casters.iter().map(|c| u64::from(c.count_bound)).sum();
    if total <= u64::from(bits.all) {
        return std::iter::once(0..casters.len()).collect();
    }
    let limit = u64::from(bits.batch);
    let mut batches = Vec::new();
    let (mut start, mut sum) = (0, 0u64);
    for (i, c) in casters.iter().enumerate() {
        let bound = u64::from(c.count_bound);
        if i > start && sum + bound > limit {
            batches.push(start..i);
            (start, sum) = (i, 0);
        }
        sum += bound;
    }
    batches.push(start..casters.len());
    batches
}

/// `desc` (a counting pipeline) writing only `bits.batch`, named `name`.
pub(crate) fn counting_in_batch<'d>(
    desc: &GraphicsPipelineDesc<'d>,
    name: &'d str,
    bits: CountBits,
) -> GraphicsPipelineDesc<'d> {
    let mut twin = *desc;
    twin.name = name;
    twin.stencil = twin.stencil.map(|(f, b)| {
        let masked = |s: StencilFace| StencilFace { write_mask: u32::from(bits.batch), ..s };
        (masked(f), masked(b))
    });
    twin
}

/// The fold between batches: full screen, no depth test; where `stencil & bits.batch != 0`
/// the reference `bits.fold` (whose batch bits are 0) replaces `bits.batch | bits.fold`,
/// leaving any other bit (the hybrid's silhouette bit) as it is.
pub(crate) fn fold_desc(
    name: &'static str,
    depth_format: vk::Format,
    bits: CountBits,
) -> GraphicsPipelineDesc<'static> {
    let mut desc = GraphicsPipelineDesc::new(name, umbra_shaders::fullscreen::TRIANGLE_VERT);
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth_format = depth_format;
    desc.depth = DepthState::NONE;
    let face = StencilFace {
        pass: vk::StencilOp::REPLACE,
        compare: vk::CompareOp::NOT_EQUAL,
        compare_mask: u32::from(bits.batch),
        write_mask: u32::from(bits.batch | bits.fold),
        ..StencilFace::KEEP
    };
    desc.stencil = Some((face, face));
    desc
}

/// Records `volumes` batch by batch (their planned `batches`, for the layout `bits`):
/// `batch(rec, log, casters, batched)` draws one (with the batch pipelines when `batched`),
/// and `fold` runs between two.
pub(crate) fn record_in_batches<'a, 'c>(
    rec: &mut Recorder<'a>,
    log: &mut PassLog,
    volumes: &'c LightVolumes,
    bits: CountBits,
    fold: &'a GraphicsPipeline,
    mut batch: impl FnMut(&mut Recorder<'a>, &mut PassLog, &'c [CasterVolume], bool),
) {
    let batched = volumes.batches.len() > 1;
    for (k, range) in volumes.batches.iter().enumerate() {
        if k > 0 {
            rec.bind_pipeline(fold);
            rec.set_stencil_reference(u32::from(bits.fold));
            rec.draw(3);
            log.count_draw(1);
        }
        batch(rec, log, volumes.casters.get(range.clone()).unwrap_or_default(), batched);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow_volume::build::Counting;

    fn casters(bounds: &[u32]) -> Vec<CasterVolume> {
        bounds
            .iter()
            .map(|&count_bound| CasterVolume {
                object: 0,
                counting: Some(Counting::ZFail),
                first: 0,
                count: 3,
                cut_caps: 0,
                count_bound,
                stats: Default::default(),
                job: None,
            })
            .collect()
    }

    #[test]
    fn casters_are_counted_at_once_below_256_and_in_batches_of_127_above() {
        let at_once = |c: &[CasterVolume]| {
            let b = count_batches(c, FULL_STENCIL);
            b.len() == 1 && b[0] == (0..c.len())
        };
        assert!(at_once(&casters(&[1; 255])) && at_once(&casters(&[])) && at_once(&casters(&[200, 55])));
        // 256 convex slabs (hard case 24): 127 + 127 + 2.
        assert_eq!(count_batches(&casters(&[1; 256]), FULL_STENCIL), vec![0..127, 127..254, 254..256]);
        // A mesh whose own bound passes 127 is a batch alone; the others fill batches around it.
        assert_eq!(count_batches(&casters(&[1, 40_000, 1, 1]), FULL_STENCIL), vec![0..1, 1..2, 2..4]);
        for bounds in [vec![3; 500], vec![100, 27, 1, 126, 2, 127, 0, 5]] {
            let c = casters(&bounds);
            let batches = count_batches(&c, FULL_STENCIL);
            assert_eq!(batches.first().map(|b| b.start), Some(0));
            assert_eq!(batches.last().map(|b| b.end), Some(c.len()));
            for pair in batches.windows(2) {
                assert_eq!(pair[0].end, pair[1].start);
            }
            for b in &batches {
                let sum: u32 = c[b.clone()].iter().map(|c| c.count_bound).sum();
                assert!(sum <= 127 || b.len() == 1, "{bounds:?}: {b:?} sums {sum}");
            }
        }
    }
}
