//! The sweep: every (scene, technique, option) configuration rendered for warm-up plus N
//! frames, timed per pass, and its last frame scored against the exact reference.

use crate::record::{Accuracy, Config, Fill, NoCull, PassTime, Rays, Record, Skipped, Spread};
use crate::{BenchError, BenchResult};
use std::collections::BTreeMap;
use std::path::Path;
use umbra_reference::{error_image, Comparison, SceneBvh, ShadowMask, SurfaceImage, WrongPixels};
use umbra_scene::{Scene, Technique};
use umbra_shadows::ray_traced::BvhLayout;
use umbra_shadows::{Frame, HybridSettings, MaskKind, RenderError, Renderer, RendererDesc, ShadowFilter};
use umbra_vk::{Context, VkError};

/// What to sweep.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Scenes (procedural names, .toml, .glb/.gltf).
    pub scenes: Vec<String>,
    /// Short technique names.
    pub techniques: Vec<&'static str>,
    /// Shadow-map sizes (`None`: the renderer's default).
    pub sm_sizes: Vec<Option<u32>>,
    /// Shadow-map filters.
    pub filters: Vec<ShadowFilter>,
    /// Hybrid computation masks.
    pub masks: Vec<MaskKind>,
    /// The meshes' BVH layouts (rt, hybrid-rt).
    pub bvhs: Vec<BvhLayout>,
}

/// The techniques a sweep measures, by their short names ([`Technique::short`]).
pub const TECHNIQUES: &[Technique] = &Technique::SHADOWING;

/// The short names of [`TECHNIQUES`], in order: the sweep's and frame cost's default.
pub fn short_names() -> Vec<String> {
    TECHNIQUES.iter().map(|t| t.short().to_owned()).collect()
}

/// The swept technique of a short name.
pub fn technique(short: &str) -> Option<Technique> {
    TECHNIQUES.iter().copied().find(|t| t.short() == short)
}

impl Plan {
    /// Every configuration of one scene: shadow maps per size and filter, silhouette maps and
    /// the ray-traced hybrid per size, shadow volumes and ray-traced shadows once, the hybrid per
    /// size and mask.
    pub fn configs(&self, scene: &str) -> Vec<Config> {
        let mut out = Vec::new();
        let base = |technique| Config {
            scene: scene.to_owned(),
            technique,
            sm_size: None,
            filter: None,
            mask: None,
            bvh: None,
        };
        // The ray-casting techniques once per BVH layout, the binary one unnamed.
        let bvhs = || self.bvhs.iter().map(|&b| (b != BvhLayout::Binary).then_some(b.name()));
        for &t in &self.techniques {
            match t {
                "sm" => {
                    for &sm_size in &self.sm_sizes {
                        for f in &self.filters {
                            out.push(Config { sm_size, filter: Some(f.name()), ..base(t) });
                        }
                    }
                }
                "silmap" => out.extend(self.sm_sizes.iter().map(|&sm_size| Config { sm_size, ..base(t) })),
                "hybrid-rt" => {
                    for bvh in bvhs() {
                        out.extend(self.sm_sizes.iter().map(|&sm_size| Config { sm_size, bvh, ..base(t) }));
                    }
                }
                "rt" => out.extend(bvhs().map(|bvh| Config { bvh, ..base(t) })),
                "hybrid" => {
                    for &sm_size in &self.sm_sizes {
                        for m in &self.masks {
                            out.push(Config { sm_size, mask: Some(m.name()), ..base(t) });
                        }
                    }
                }
                _ => out.push(base(t)),
            }
        }
        out
    }
}

/// Why the device cannot run `config`, if it cannot.
pub fn unsupported(ctx: &Context, config: &Config) -> Option<String> {
    let caps = ctx.capabilities();
    if config.technique == Technique::HybridRt.short()
        && !(caps.fragment_stores_and_atomics && caps.storage_image_extended_formats && caps.compute_queue)
    {
        return Some(format!(
            "{} lacks fragmentStoresAndAtomics, shaderStorageImageExtendedFormats or compute on its graphics queue",
            caps.device_name
        ));
    }
    if config.mask == Some(MaskKind::DepthBounds.name()) && !caps.depth_bounds {
        return Some(format!("{} has no depthBounds feature", caps.device_name));
    }
    match config.sm_size {
        Some(s) if s > caps.max_image_dimension_2d => {
            Some(format!("{s}² exceeds maxImageDimension2D {} on {}", caps.max_image_dimension_2d, caps.device_name))
        }
        _ => None,
    }
}

/// The renderer settings of `config`: diagnostics (classification), G-buffer, the visibility
/// images' readback and volume overdraw on, all as diagnostic passes outside the technique's
/// timed total.
pub fn renderer_desc(config: &Config, width: u32, height: u32) -> BenchResult<RendererDesc> {
    let mut desc = RendererDesc::new(width, height);
    if let Some(s) = config.sm_size {
        desc.shadow_map.resolution = Some(s);
    }
    if let Some(f) = config.filter {
        desc.shadow_map.filter = f.parse().map_err(BenchError::Usage)?;
    }
    let mask = config.mask.map(str::parse::<MaskKind>).transpose().map_err(BenchError::Usage)?;
    desc.hybrid = HybridSettings { resolution: config.sm_size, mask, cull_blockers: false };
    if let Some(b) = config.bvh {
        desc.bvh = b.parse().map_err(BenchError::Usage)?;
    }
    desc.shadow_volume.overdraw = true;
    desc.diagnostics = true;
    desc.gbuffer = true;
    desc.read_visibility = true;
    Ok(desc)
}

/// One configuration measured: its record, plus the last frame's image and first light's error
/// image (both RGBA8, row 0 at the top) for pictures.
#[derive(Clone, Debug)]
pub struct Measured {
    /// What was measured.
    pub record: Record,
    /// The last timed frame.
    pub image: Vec<u8>,
    /// The first light's error image against the reference ([`umbra_reference::error_image`]).
    pub error_image: Vec<u8>,
}

/// Measures one configuration of `scene` (whose lights all get the configuration's technique)
/// and writes its error image to `<out>/images/<id>-error.png`; `Ok(Err(reason))` when the
/// device turns it down with a typed "unsupported".
#[allow(clippy::too_many_arguments)]
pub fn measure(
    ctx: &Context,
    scene: &Scene,
    bvh: &SceneBvh,
    config: &Config,
    size: (u32, u32),
    warmup: usize,
    frames: usize,
    no_cull: bool,
    out: &Path,
) -> BenchResult<Result<Measured, String>> {
    let Some(technique) = technique(config.technique) else {
        return Err(BenchError::Usage(format!("unknown technique {:?}", config.technique)));
    };
    let mut scene = scene.clone();
    for light in &mut scene.lights {
        light.technique = technique;
    }
    let desc = renderer_desc(config, size.0, size.1)?;
    let Rendered { timed, first_bvh } = match run_frames(ctx, desc, &scene, warmup, frames)? {
        Ok(t) => t,
        Err(reason) => return Ok(Err(reason)),
    };
    let Some(last) = timed.last() else { return Err(BenchError::Usage("no frame rendered".into())) };
    let no_cull = if no_cull {
        let unplanned = match run_frames(ctx, RendererDesc { cull: false, ..desc }, &scene, warmup, frames)? {
            Ok(t) => t,
            Err(reason) => return Ok(Err(reason)),
        };
        let Some(other) = unplanned.timed.last() else { return Err(BenchError::Usage("no frame rendered".into())) };
        Some(NoCull {
            gpu_ms: total_gpu(&unplanned.timed),
            recorded_passes: other.report.passes.len(),
            identical: other.rgba == last.rgba,
        })
    } else {
        None
    };
    let (accuracy, error_image) = score(&scene, bvh, last, &out.join("images"), &config.id())?;
    let r = &last.report;
    let record = Record {
        config: config.clone(),
        device: r.device.clone(),
        driver: r.driver.clone(),
        width: size.0,
        height: size.1,
        triangles: r.scene.triangles,
        frames: timed.len(),
        gpu_ms: total_gpu(&timed),
        passes: pass_times(&timed),
        cpu_silhouette_ms: Spread::of(&timed.iter().filter_map(cpu_silhouette_ms).collect::<Vec<_>>()),
        fill: fill(last),
        rays: rays(last, first_bvh),
        accuracy,
        error_image: format!("images/{}-error.png", config.id()),
        recorded_passes: r.passes.len(),
        no_cull,
        map_resolution: r.lights.iter().find_map(|l| l.shadow_map.as_ref()).map(|m| m.resolution),
    };
    Ok(Ok(Measured { record, image: last.rgba.clone(), error_image }))
}

/// A configuration's frames.
struct Rendered {
    /// The frames after the warm-up.
    timed: Vec<Frame>,
    /// The first frame's BVH build milliseconds (meshes, top level), where it cast rays.
    first_bvh: Option<(f64, f64)>,
}

/// Renders `warmup` discarded frames, then `frames` kept ones (at least one).
fn run_frames(
    ctx: &Context,
    desc: RendererDesc,
    scene: &Scene,
    warmup: usize,
    frames: usize,
) -> BenchResult<Result<Rendered, String>> {
    let mut renderer = match Renderer::new(ctx, desc) {
        Ok(r) => r,
        Err(e) => return unsupported_or(e),
    };
    let mut timed: Vec<Frame> = Vec::with_capacity(frames);
    let mut first_bvh = None;
    for i in 0..warmup + frames.max(1) {
        let frame = match renderer.render(scene) {
            Ok(f) => f,
            Err(e) => return unsupported_or(e),
        };
        if i == 0 {
            let built = frame.report.lights.iter().find_map(|l| l.ray_traced);
            first_bvh = built.map(|r| (r.mesh_build_ms, r.top_build_ms));
        }
        if i >= warmup {
            timed.push(frame);
        }
    }
    Ok(Ok(Rendered { timed, first_bvh }))
}

/// The spread of the frames' total GPU times.
fn total_gpu(frames: &[Frame]) -> Option<Spread> {
    Spread::of(&frames.iter().filter_map(|f| f.report.total_gpu_ms).collect::<Vec<_>>())
}

/// A typed "unsupported" or "over a device limit or the shadow-map budget" becomes a skip
/// reason; anything else stops the sweep.
fn unsupported_or<T>(e: RenderError) -> BenchResult<Result<T, String>> {
    match e {
        RenderError::Vk(VkError::Unsupported { .. } | VkError::DeviceLimit { .. })
        | RenderError::UnsupportedLight { .. }
        | RenderError::InvalidShadowMap { .. }
        | RenderError::InvalidSize { limit: Some(_), .. }
        | RenderError::DeviceLimit { .. }
        | RenderError::ShadowBudget { .. } => Ok(Err(e.to_string())),
        e => Err(e.into()),
    }
}

/// Median GPU time of every technique pass, in the order the frame recorded them.
fn pass_times(frames: &[Frame]) -> Vec<PassTime> {
    let mut order: Vec<String> = Vec::new();
    let mut samples: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for f in frames {
        for p in f.report.passes.iter().filter(|p| !p.diagnostic) {
            if !samples.contains_key(&p.name) {
                order.push(p.name.clone());
            }
            let entry = samples.entry(p.name.clone()).or_default();
            entry.extend(p.gpu_ms);
        }
    }
    order
        .into_iter()
        .filter_map(|name| {
            let gpu_ms = Spread::of(samples.get(&name)?)?;
            Some(PassTime { name, gpu_ms })
        })
        .collect()
}

/// CPU time spent finding silhouettes in one frame: silhouette-map edge extraction plus
/// shadow-volume construction, over every light; `None` when no light does either.
fn cpu_silhouette_ms(frame: &Frame) -> Option<f64> {
    let times: Vec<f64> = frame
        .report
        .lights
        .iter()
        .flat_map(|l| {
            let edges = l.silhouette_map.as_ref().map(|s| s.cpu_extract_ms);
            edges.into_iter().chain(l.shadow_volume.as_ref().map(|v| v.cpu_build_ms))
        })
        .collect();
    (!times.is_empty()).then(|| times.iter().sum())
}

fn fill(frame: &Frame) -> Fill {
    let pixels = f64::from(frame.width) * f64::from(frame.height);
    let lights = &frame.report.lights;
    let sum = |v: Vec<Option<u64>>| -> Option<u64> {
        if v.is_empty() {
            None
        } else {
            v.into_iter().sum()
        }
    };
    let volume_fragments =
        sum(lights.iter().filter_map(|l| l.shadow_volume.as_ref()).map(|v| v.volume_fragments).collect());
    let masked = sum(lights.iter().filter_map(|l| l.hybrid.as_ref()).map(|h| h.masked_volume_fragments).collect());
    let fractions: Vec<f64> = lights
        .iter()
        .filter_map(|l| {
            l.hybrid
                .as_ref()
                .map(|h| h.silhouette_fraction)
                .or(l.silhouette_map.as_ref().and_then(|s| s.silhouette_fraction))
        })
        .collect();
    Fill {
        volume_overdraw: volume_fragments.map(|n| n as f64 / pixels),
        volume_fragments,
        masked_volume_fragments: masked,
        silhouette_fraction: (!fractions.is_empty()).then(|| fractions.iter().sum()),
    }
}

/// The shadow rays of every ray-casting light (with their traversal counted) and the BVH's
/// first build (`built`, meshes and top level), `None` without.
fn rays(frame: &Frame, built: Option<(f64, f64)>) -> Option<Rays> {
    let lights: Vec<_> = frame.report.lights.iter().filter_map(|l| l.ray_traced).collect();
    let first = lights.first()?;
    let walks: Vec<_> = lights.iter().filter_map(|r| r.traversal).collect();
    let rays: u64 = walks.iter().map(|t| t.rays).sum();
    let mean = |f: fn(&umbra_shadows::TraversalReport) -> f64| {
        walks.iter().map(|t| f(t) * t.rays as f64).sum::<f64>() / rays.max(1) as f64
    };
    Some(Rays {
        rays,
        ray_fraction: rays as f64 / (f64::from(frame.width) * f64::from(frame.height)),
        nodes_mean: mean(|t| t.nodes_mean),
        nodes_p95: walks.iter().map(|t| t.nodes_p95).max().unwrap_or(0),
        triangles_mean: mean(|t| t.triangles_mean),
        triangles_p95: walks.iter().map(|t| t.triangles_p95).max().unwrap_or(0),
        bvh_bytes: first.bvh_bytes,
        mesh_build_ms: built.map_or(0.0, |b| b.0),
        top_build_ms: built.map_or(0.0, |b| b.1),
    })
}

/// Every light's visibility image against the reference from the frame's own G-buffer; writes the first
/// light's error image as `<dir>/<id>-error.png` and returns it (empty without a light).
fn score(scene: &Scene, bvh: &SceneBvh, frame: &Frame, dir: &Path, id: &str) -> BenchResult<(Accuracy, Vec<u8>)> {
    let gbuffer =
        frame.gbuffer.as_ref().ok_or_else(|| BenchError::Usage("the renderer returned no G-buffer".into()))?;
    let surfaces = SurfaceImage::from_gbuffer(frame.width, frame.height, &gbuffer.position, &gbuffer.normal)?;
    std::fs::create_dir_all(dir).map_err(|e| BenchError::output(dir, e))?;
    let (mut all, mut band) = (WrongPixels::default(), WrongPixels::default());
    let (mut max_distance, mut undecided, mut band_px) = (None::<f32>, 0, umbra_reference::EDGE_BAND_PX);
    let mut first_error = Vec::new();
    for (i, (light, mask)) in frame.shadow_masks().enumerate() {
        let technique = ShadowMask::new(frame.width, frame.height, mask)?;
        let truth = ShadowMask::reference(scene, bvh, light, &surfaces)?;
        let c = Comparison::new(&technique, &truth)?;
        all += c.all;
        band += c.edge_band;
        if let Some(d) = c.max_wrong_distance_px {
            max_distance = Some(max_distance.map_or(d, |m| m.max(d)));
        }
        undecided += c.undecided;
        band_px = c.edge_band_px;
        if i == 0 {
            first_error = error_image(&technique, &truth);
            let path = dir.join(format!("{id}-error.png"));
            image::save_buffer(&path, &first_error, frame.width, frame.height, image::ColorType::Rgba8)
                .map_err(|e| BenchError::output(&path, e))?;
        }
    }
    let accuracy = Accuracy {
        all,
        edge_band: band,
        edge_band_px: band_px,
        wrong_fraction: all.fraction(),
        false_shadow_fraction: all.false_shadow_fraction(),
        false_lit_fraction: all.false_lit_fraction(),
        edge_band_wrong_fraction: band.fraction(),
        max_wrong_distance_px: max_distance,
        undecided,
    };
    Ok((accuracy, first_error))
}

/// A skipped configuration, logged.
pub fn skip(config: &Config, reason: String) -> Skipped {
    log::warn!("skipped {} on {}: {reason}", config.label(), config.scene);
    Skipped { config: config.clone(), reason }
}
