//! Diagnostics (with `RendererDesc::diagnostics`, in umbra's own frames): how far each shadow
//! ray walks the BVH. After a ray-traced or hybrid-RT light's visibility, `ray stats N` casts its
//! rays again with counters on (`shaders-glsl/visibility/ray_stats.frag`,
//! `shaders-glsl/hybrid/rays_stats.comp`, `shaders-glsl/ray/stats.glsl`): per light, the rays
//! cast and the nodes and triangles each visited, summed and binned, in one storage buffer
//! emptied once a frame (`ray stats reset`) and copied out once (`ray stats readback`). The
//! counted passes are diagnostics: the technique's own passes, and so its timings, run without
//! counters. The result is [`TraversalReport`] in the light's [`crate::RayTracedReport`].

use super::BvhLayout;
use crate::forward::{self, Bounded};
use crate::frame::PassRecorder;
use crate::gpu_scene::DrawPush;
use crate::light_surfaces::LightSurfaces;
use crate::retired::Retired;
use crate::visibility::VISIBILITY_FORMAT;
use crate::RenderResult;
use serde::Serialize;
use umbra_vk::{
    vk, Binding, Buffer, BufferDesc, ColorTarget, ComputePipeline, Context, DescriptorSet, DescriptorSetLayout,
    PipelineLayout, Recorder, Resource,
};

/// Bins of each histogram (`STATS_BINS` in `ray/stats.glsl`): one per count below 64, then
/// eight per power of two up to 2³².
pub(crate) const BINS: usize = 272;

/// Words before the histograms: rays, nodes (low, high), triangles (low, high), three unused.
const HEADER_WORDS: usize = 8;

/// Words per light (`STATS_WORDS`).
const WORDS: usize = HEADER_WORDS + 2 * BINS;

/// How far a light's shadow rays walked the BVH in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TraversalReport {
    /// Shadow rays cast (ray-traced: one per receiver fragment that passed the depth test;
    /// hybrid-RT: one per silhouette pixel, i.e. its `HybridRtReport::rays` less the entries of
    /// a pixel that a later fragment listed again).
    pub rays: u64,
    /// BVH nodes (top level and meshes') whose box a ray tested, per ray.
    pub nodes_mean: f64,
    /// The 95th percentile of nodes per ray: exact below 64, else the upper end of its bin (an
    /// eighth of a power of two wide, so at most 12.5 % above the exact figure).
    pub nodes_p95: u64,
    /// Triangles a ray tested, per ray.
    pub triangles_mean: f64,
    /// The 95th percentile of triangles per ray (binned as `nodes_p95`).
    pub triangles_p95: u64,
}

/// The histogram bin of count `n` (`stats_bin` in `ray/stats.glsl`, mirrored here to test the
/// decoding against it).
#[cfg(test)]
pub(crate) fn bin(n: u32) -> usize {
    if n < 64 {
        return n as usize;
    }
    let e = 31 - n.leading_zeros();
    64 + 8 * (e as usize - 6) + ((n >> (e - 3)) & 7) as usize
}

/// The largest count in bin `b`.
pub(crate) fn bin_top(b: usize) -> u64 {
    if b < 64 {
        return b as u64;
    }
    let (e, m) = (6 + (b - 64) / 8, (b - 64) % 8);
    (((8 + m as u64 + 1) << (e - 3)) - 1).min(u64::from(u32::MAX))
}

/// The smallest count `p` such that at least 95 % of the histogram's rays are at or below `p`.
fn p95(bins: &[u32], rays: u64) -> u64 {
    let need = (rays * 95).div_ceil(100).max(1);
    let mut seen = 0u64;
    for (b, &n) in bins.iter().enumerate() {
        seen += u64::from(n);
        if seen >= need {
            return bin_top(b);
        }
    }
    bin_top(bins.len().saturating_sub(1))
}

/// One light's words decoded; `None` when it cast no ray.
pub(crate) fn decode(words: &[u32]) -> Option<TraversalReport> {
    if words.len() < WORDS || words[0] == 0 {
        return None;
    }
    let rays = u64::from(words[0]);
    let wide = |at: usize| u64::from(words[at]) | (u64::from(words[at + 1]) << 32);
    let (nodes, triangles) = (&words[HEADER_WORDS..HEADER_WORDS + BINS], &words[HEADER_WORDS + BINS..WORDS]);
    Some(TraversalReport {
        rays,
        nodes_mean: wide(1) as f64 / rays as f64,
        nodes_p95: p95(nodes, rays),
        triangles_mean: wide(3) as f64 / rays as f64,
        triangles_p95: p95(triangles, rays),
    })
}

/// The counters on the GPU and their readback, for `lights` lights.
struct Counters {
    lights: usize,
    buffer: Buffer,
    readback: Buffer,
    set: DescriptorSet,
}

/// The counted twins of the ray-traced pass and of the hybrid-RT rays, and the counters.
pub(crate) struct RayStats {
    set_layout: DescriptorSetLayout,
    surfaces: Bounded,
    surfaces_layout: PipelineLayout,
    /// The hybrid-RT rays' twin (where the device runs the ray-traced hybrid).
    listed: Option<(ComputePipeline, PipelineLayout)>,
    counters: Option<Counters>,
}

/// The set layouts of the hybrid-RT rays (`crate::hybrid::rays`): the BVH's, the list's and
/// the output's.
pub(crate) type ListedLayouts<'a> = [&'a DescriptorSetLayout; 3];

impl RayStats {
    /// The counted pipelines, walking the BVH in layout `bvh`: over the frame's surfaces with
    /// sets 0 (scene), 1 (BVH) and 2 (counters); and, with `listed`, over the hybrid's ray list
    /// with its sets and the counters at set 3.
    pub fn new(
        ctx: &Context,
        scene_set_layout: &DescriptorSetLayout,
        (bvh_layout, bvh): (&DescriptorSetLayout, BvhLayout),
        listed: Option<ListedLayouts<'_>>,
        depth_format: vk::Format,
        depth_bounds: bool,
    ) -> RenderResult<Self> {
        let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let binding = [Binding { binding: 0, ty: vk::DescriptorType::STORAGE_BUFFER, stages }];
        let set_layout = DescriptorSetLayout::new(ctx, "ray stats layout", &binding)?;
        let push = std::mem::size_of::<DrawPush>() as u32;
        let sets = [scene_set_layout, bvh_layout, &set_layout];
        let surfaces_layout = PipelineLayout::new(ctx, "ray stats (surfaces) layout", &sets, push)?;
        let target = [ColorTarget::opaque(VISIBILITY_FORMAT)];
        let frag = umbra_shaders::visibility::RAY_STATS_FRAG;
        let mut desc = forward::surface_pass_desc("ray stats (surfaces)", frag, depth_format, &[]);
        desc.color_targets = &target;
        let specialization = bvh.specialization();
        desc.specialization = &specialization;
        let surfaces = Bounded::new(ctx, &surfaces_layout, &desc, depth_bounds)?;
        let listed = match listed {
            Some([bvh, list, output]) => {
                let sets = [bvh, list, output, &set_layout];
                let layout = PipelineLayout::new(ctx, "ray stats (list) layout", &sets, 4)?;
                let comp = umbra_shaders::hybrid::RAYS_STATS_COMP;
                Some((ComputePipeline::new(ctx, &layout, "ray stats (list)", comp, &specialization)?, layout))
            }
            None => None,
        };
        Ok(Self { set_layout, surfaces, surfaces_layout, listed, counters: None })
    }

    /// Makes sure the counters hold `lights` lights (made again, the old ones retired, when
    /// they do not).
    pub fn prepare(&mut self, ctx: &Context, lights: usize, retired: &mut Retired) -> RenderResult<()> {
        if self.counters.as_ref().is_some_and(|c| c.lights >= lights) {
            return Ok(());
        }
        retired.take(&mut self.counters);
        let bytes = (lights.max(1) * WORDS * 4) as u64;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let buffer = Buffer::new(ctx, "ray stats", BufferDesc::gpu_only(bytes, usage))?;
        let readback = Buffer::new(ctx, "ray stats readback", BufferDesc::readback(bytes))?;
        let set = DescriptorSet::new(ctx, "ray stats", &self.set_layout, &[Resource::Buffer(&buffer)])?;
        self.counters = Some(Counters { lights, buffer, readback, set });
        Ok(())
    }

    /// The counters and their readback (after [`Self::prepare`]), for the passes' declarations.
    pub fn buffers(&self) -> Option<(&Buffer, &Buffer)> {
        self.counters.as_ref().map(|c| (&c.buffer, &c.readback))
    }

    /// `ray stats reset` (the counters in TransferDst).
    pub fn record_reset<'a>(&'a self, rec: &mut Recorder<'a>) {
        if let Some(c) = &self.counters {
            rec.fill_buffer(&c.buffer, 0);
        }
    }

    /// `ray stats N` of a ray-traced light, inside a pass over the frame's surfaces (its
    /// visibility image kept as the one colour target): its rays through the slot's `bvh`.
    pub fn record_surfaces<'a>(
        &'a self,
        cx: &mut PassRecorder<'_, 'a>,
        bvh: &'a DescriptorSet,
        s: LightSurfaces<'a, '_>,
    ) {
        let Some(c) = &self.counters else { return };
        self.surfaces.bind(cx.rec, s.bounds);
        cx.rec.bind_descriptor_set(&self.surfaces_layout, 1, bvh);
        cx.rec.bind_descriptor_set(&self.surfaces_layout, 2, &c.set);
        s.draw(cx, &self.surfaces_layout);
    }

    /// `ray stats N` of a hybrid-RT light: its listed rays, dispatched with the workgroups its
    /// classification counted in `header`, through `sets` (the BVH, the list, its output).
    pub fn record_listed<'a>(
        &'a self,
        rec: &mut Recorder<'a>,
        sets: [&'a DescriptorSet; 3],
        header: &'a Buffer,
        light: u32,
    ) {
        let (Some(c), Some((pipeline, layout))) = (&self.counters, &self.listed) else { return };
        rec.bind_compute_pipeline(pipeline);
        for (i, set) in sets.into_iter().chain([&c.set]).enumerate() {
            rec.bind_compute_set(layout, i as u32, set);
        }
        rec.push_constants(layout, &light);
        rec.dispatch_indirect(header, 0);
    }

    /// `ray stats readback` (the counters in TransferSrc).
    pub fn record_readback<'a>(&'a self, rec: &mut Recorder<'a>) {
        if let Some(c) = &self.counters {
            rec.copy_buffer(&c.buffer, &c.readback, c.buffer.desc.size);
        }
    }

    /// Light `light`'s counts, read back once its frame completed; `None` when it cast no ray.
    pub fn read(&self, light: usize) -> RenderResult<Option<TraversalReport>> {
        let Some(c) = self.counters.as_ref().filter(|c| light < c.lights) else { return Ok(None) };
        let bytes = c.readback.read()?;
        let words: Vec<u32> = bytes.chunks_exact(4).map(|b| u32::from_ne_bytes([b[0], b[1], b[2], b[3]])).collect();
        Ok(words.get(light * WORDS..(light + 1) * WORDS).and_then(decode))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_are_exact_below_64_and_an_eighth_of_an_octave_above() {
        for n in 0..64 {
            assert_eq!(bin(n), n as usize);
            assert_eq!(bin_top(n as usize), u64::from(n));
        }
        assert_eq!(bin(64), 64);
        assert_eq!(bin(71), 64);
        assert_eq!(bin(72), 65);
        assert_eq!(bin(u32::MAX), BINS - 1);
        for n in [64u32, 100, 1000, 4095, 4096, 123_456, 1 << 31, u32::MAX] {
            let top = bin_top(bin(n));
            assert!(top >= u64::from(n) && (top as f64) <= f64::from(n) * 1.125 + 1.0, "{n}: {top}");
            assert!(bin(n) == BINS - 1 || bin((top + 1) as u32) == bin(n) + 1, "{n}");
        }
    }

    #[test]
    fn decode_gives_means_and_p95() {
        let mut words = vec![0u32; WORDS];
        // 100 rays: 90 visit 10 nodes and 1 triangle, 10 visit 200 nodes and 30 triangles.
        words[0] = 100;
        let nodes = 90 * 10 + 10 * 200u64;
        words[1] = nodes as u32;
        words[3] = 90 + 300;
        words[HEADER_WORDS + bin(10)] = 90;
        words[HEADER_WORDS + bin(200)] = 10;
        words[HEADER_WORDS + BINS + bin(1)] = 90;
        words[HEADER_WORDS + BINS + bin(30)] = 10;
        let r = decode(&words).unwrap();
        assert_eq!(r.rays, 100);
        assert!((r.nodes_mean - 29.0).abs() < 1e-9);
        assert_eq!(r.nodes_p95, bin_top(bin(200)));
        assert!((200..=207).contains(&r.nodes_p95));
        assert!((r.triangles_mean - 3.9).abs() < 1e-9);
        assert_eq!(r.triangles_p95, 30);
        words[2] = 1;
        assert!((decode(&words).unwrap().nodes_mean - (nodes as f64 + 4_294_967_296.0) / 100.0).abs() < 1e-6);
        words[0] = 0;
        assert_eq!(decode(&words), None);
    }
}
