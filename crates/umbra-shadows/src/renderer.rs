//! The renderer: records a frame's passes into a headless target and reads the colour back.
//!
//! A frame, top to bottom:
//! 1. plan: per light, decide what to record and which casters enter its shadow passes
//!    (`plan::plan_frame`: nothing that cannot change the image), and fit the shadow-map
//!    views of the lights that use shadow maps (`shadow_map::frustum`);
//! 2. upload: the scene's meshes, objects, lights, shadow views and camera (`gpu_scene`);
//! 3. `ambient`: depth plus ambient term for every object;
//! 4. per planned light: its technique's passes (`shadow_map N`: depth from the light;
//!    `silhouette_map N`: the silhouette points on the dual grid; `shadow_volume N`: stencil
//!    counts), then `light N (kind)`, its additive lighting with the shadow test (map or
//!    silhouette-map lookup, or stencil == 0). Diagnostic passes follow when asked for:
//!    `volume overdraw N` (volumes into the overdraw image), `silhouette diagnostics N` (the
//!    classification and silhouette-point views), `light diagnostics N` (the classification of
//!    shadow-map and shadow-volume lights), `hybrid diagnostics N`; and after `ambient`, with
//!    `gbuffer`, the `g-buffer` pass (positions and normals for the exact reference);
//! 5. `readback`: copy the colour target into a host-visible buffer.
//!
//! Every pass is a debug label with timestamps around it; the [`FrameReport`] lists them.

use crate::budget::{self, ShadowStorage, DEFAULT_SHADOW_MAP_BUDGET};
use crate::diagnostics::SilhouetteMapImage;
use crate::diagnostics::{self, ClassReadback, DiagnosticTargets, GBuffer, LightDiagnostics, PixelClass};
use crate::forward::{Forward, PassBounds};
use crate::gbuffer::{self, GBufferPass};
use crate::gpu_scene::{self, GpuScene, GpuShadow, SceneCounts};
use crate::hybrid::cull;
use crate::hybrid::pass::{self as hybrid_pass, HybridLight, HybridPass};
use crate::hybrid::{HybridSettings, MaskKind, DEPTH_BOUNDS_EPSILON};
use crate::mesh_cache::MeshCache;
use crate::plan::{plan_frame, tally, CullReason, FramePlan, HybridReport, LightPlan, PlanInput, ShadowMapReport};
use crate::plan::{CasterMode, ShadowVolumeReport, SilhouetteMapReport, SILHOUETTE_CUBE_UNSUPPORTED};
use crate::report::{FrameReport, SceneSummary};
use crate::shadow_map::frustum::{self, LightViews, MapKind};
use crate::shadow_map::pass::{self, ShadowMapPass};
use crate::shadow_map::{DepthBias, ShadowMapSettings};
use crate::shadow_volume::build::{self as volumes, Counting, LightVolumes};
use crate::shadow_volume::pass::{ShadowVolumePass, VolumeBindings};
use crate::shadow_volume::VolumeMode;
use crate::shadow_volume::{FarPlane, ShadowVolumeSettings};
use crate::silhouette_map::edges::{self, EdgeInstance, LightEdges};
use crate::silhouette_map::pass::SilhouetteMapPass;
use crate::streams::Streams;
use crate::timing::{PassLog, PassTimer};
use crate::{RenderError, RenderResult};
use std::path::Path;
use std::time::Instant;
use umbra_scene::{Scene, Technique};
use umbra_vk::{
    vk, Buffer, BufferDesc, ColorAttachment, Context, DepthAttachment, DescriptorSetLayout, Image, ImageDesc,
    ImageState, PipelineLayout, QueryKind, QueryPool, RenderTargets,
};

/// The colour target format: linear 8-bit RGBA (values are written as computed, no sRGB curve).
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

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
    /// Render the diagnostic views of every light ([`Frame::diagnostics`]: its per-pixel
    /// classification, hence its shadow mask; silhouette points and map for silhouette-map
    /// lights, the stencil for hybrid and shadow-volume lights) and count silhouette-map
    /// lights' silhouette pixels: one more pass and readback per light, reported as a
    /// diagnostic pass. Off by default.
    pub diagnostics: bool,
    /// Render the G-buffer ([`Frame::gbuffer`]): world position and geometric normal per
    /// pixel, for the exact reference. One diagnostic pass. Off by default.
    pub gbuffer: bool,
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
            diagnostics: false,
            gbuffer: false,
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
    /// Tightly packed RGBA8, `width * height * 4` bytes.
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
}

impl Frame {
    /// The RGBA value at `(x, y)`, `y = 0` being the top row.
    ///
    /// # Panics
    /// When `(x, y)` lies outside the frame, like slice indexing.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        let mut p = [0; 4];
        p.copy_from_slice(&self.rgba[i..i + 4]);
        p
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

/// Renders scenes into a headless target of a fixed size.
pub struct Renderer {
    ctx: Context,
    desc: RendererDesc,
    color: Image,
    depth: Image,
    readback: Buffer,
    scene_set_layout: DescriptorSetLayout,
    shadow_set_layout: DescriptorSetLayout,
    layout: PipelineLayout,
    forward: Forward,
    shadow_map: ShadowMapPass,
    shadow_volume: ShadowVolumePass,
    silhouette_map: SilhouetteMapPass,
    hybrid: HybridPass,
    /// The computation mask of hybrid lights (`desc.hybrid.mask`, or the device's best).
    mask: MaskKind,
    /// Classification and silhouette-point targets (with `diagnostics`).
    diagnostic_targets: Option<DiagnosticTargets>,
    /// Welded connectivity per mesh, kept while the mesh keeps its revision.
    meshes: MeshCache,
    /// The scene on the GPU from the frame before: its meshes, reused while every mesh keeps
    /// its revision, and its per-frame buffers, rewritten in place.
    gpu: Option<GpuScene>,
    /// Per-frame vertex data (edges, volumes, blocker boxes), kept between frames.
    streams: Streams,
    /// The pass timer (its timestamp pool), kept between frames.
    timer: Option<PassTimer>,
    /// Volume overdraw target and its readback (with `shadow_volume.overdraw`).
    overdraw: Option<(Image, Buffer)>,
    /// The G-buffer pass (with `gbuffer`).
    gbuffer: Option<GBufferPass>,
    /// Command buffers submitted so far.
    submissions: u64,
}

impl Renderer {
    /// Creates the targets and pipelines, after checking `desc`: the shadow-map settings
    /// ([`ShadowMapSettings::validate`]) and the target size against every device limit of the
    /// frame-sized images ([`RenderError::InvalidSize`] naming the limit).
    pub fn new(ctx: &Context, desc: RendererDesc) -> RenderResult<Self> {
        let caps = ctx.capabilities();
        desc.shadow_map.validate()?;
        let depth_format = caps.depth_stencil_format;
        if depth_format == vk::Format::UNDEFINED {
            return Err(ctx.unsupported("any depth/stencil attachment format").into());
        }
        let mask = desc.hybrid.mask.unwrap_or(MaskKind::best_for(caps.depth_bounds));
        if mask == MaskKind::DepthBounds && !caps.depth_bounds {
            return Err(ctx.unsupported("the hybrid's depth-bounds computation mask (depthBounds)").into());
        }
        check_frame_size(ctx, &desc, depth_format, mask)?;
        let color = frame_target(ctx, "colour target", desc.width, desc.height)?;
        let depth = Image::new(ctx, "depth/stencil target", depth_desc(depth_format, desc.width, desc.height))?;
        let readback =
            Buffer::new(ctx, "colour readback", BufferDesc::readback(4 * desc.width as u64 * desc.height as u64))?;
        let scene_set_layout = gpu_scene::scene_set_layout(ctx)?;
        let shadow_set_layout = pass::shadow_set_layout(ctx)?;
        let push = std::mem::size_of::<gpu_scene::DrawPush>() as u32;
        let layout = PipelineLayout::new(ctx, "scene layout", &[&scene_set_layout, &shadow_set_layout], push)?;
        // Bounded lights' depth bounds need the test in their pipelines.
        let bounds = desc.cull && caps.depth_bounds;
        let forward =
            Forward::new(ctx, &layout, COLOR_FORMAT, depth_format, &desc.shadow_map, desc.diagnostics, bounds)?;
        let shadow_map = ShadowMapPass::new(ctx, &layout, desc.shadow_map)?;
        if desc.shadow_volume.far_plane == FarPlane::DepthClamp && !caps.depth_clamp {
            return Err(ctx.unsupported("shadow volumes with FarPlane::DepthClamp (depthClamp)").into());
        }
        let shadow_volume = ShadowVolumePass::new(ctx, &layout, depth_format, &desc.shadow_volume, bounds)?;
        let silhouette_map = SilhouetteMapPass::new(ctx, &layout, COLOR_FORMAT, depth_format, &desc.shadow_map)?;
        let clamp = desc.shadow_volume.far_plane == FarPlane::DepthClamp;
        let hybrid = HybridPass::new(ctx, &layout, COLOR_FORMAT, depth_format, &desc.shadow_map, clamp)?;
        let diagnostic_targets = if desc.diagnostics {
            Some(DiagnosticTargets {
                classification: frame_target(ctx, "diagnostics: classification", desc.width, desc.height)?,
                points: frame_target(ctx, "diagnostics: silhouette points", desc.width, desc.height)?,
            })
        } else {
            None
        };
        let overdraw = if desc.shadow_volume.overdraw {
            let image = frame_target(ctx, "volume overdraw", desc.width, desc.height)?;
            let readback = Buffer::new(
                ctx,
                "overdraw readback",
                BufferDesc::readback(4 * desc.width as u64 * desc.height as u64),
            )?;
            Some((image, readback))
        } else {
            None
        };
        let gbuffer = match desc.gbuffer {
            true => Some(GBufferPass::new(ctx, &layout, depth_format, desc.width, desc.height)?),
            false => None,
        };
        Ok(Self {
            ctx: ctx.clone(),
            desc,
            color,
            depth,
            readback,
            scene_set_layout,
            shadow_set_layout,
            layout,
            forward,
            shadow_map,
            shadow_volume,
            silhouette_map,
            hybrid,
            mask,
            diagnostic_targets,
            meshes: MeshCache::default(),
            gpu: None,
            streams: Streams::default(),
            timer: None,
            overdraw,
            gbuffer,
            submissions: 0,
        })
    }

    /// Command buffers this renderer has submitted to the GPU so far (a frame whose scene is
    /// rejected by validation submits none).
    pub fn submissions(&self) -> u64 {
        self.submissions
    }

    /// The target size and settings it was created with.
    pub fn desc(&self) -> RendererDesc {
        self.desc
    }

    /// The computation mask hybrid lights use on this device.
    pub fn mask(&self) -> MaskKind {
        self.mask
    }

    /// Renders one frame of `scene` and reads it back.
    pub fn render(&mut self, scene: &Scene) -> RenderResult<Frame> {
        let started = Instant::now();
        let allocations_before = self.ctx.memory_allocations();
        // A typed error, before any GPU work, for non-finite or out-of-range input, and for
        // more objects or lights than the device's buffers can bind.
        scene.validate()?;
        gpu_scene::check_limits(self.ctx.capabilities(), SceneCounts::of(scene, 0))?;
        let aspect = self.desc.width as f32 / self.desc.height as f32;
        let volume_settings = self.desc.shadow_volume;
        // Shadow volumes reach infinity: the frame uses P_inf unless depth clamp does the job.
        // Decided from what the scene asks for (`auto` may pick the hybrid), not from the plan,
        // so that culling never changes the depth buffer.
        let asks_volumes = scene
            .lights
            .iter()
            .any(|l| matches!(l.technique, Technique::ShadowVolume | Technique::Hybrid | Technique::Auto));
        let camera_used = if asks_volumes {
            volumes::volume_camera(&scene.camera, volume_settings.far_plane == FarPlane::Infinite)
        } else {
            scene.camera
        };
        let camera = camera_used.view_proj(aspect);
        // Each object's world bounds, once per frame, for planning, fitting and mode choice.
        let boxes = scene.object_bounds();
        let settings = *self.shadow_map.settings();
        let mut lights = plan_frame(
            scene,
            &PlanInput {
                boxes: &boxes,
                camera: &camera_used,
                size: (self.desc.width, self.desc.height),
                cull: self.desc.cull,
                depth_bounds: self.desc.cull && self.ctx.capabilities().depth_bounds,
                map_resolution: settings.resolution,
            },
        )?;
        let uses = |l: &LightPlan, t: Technique| l.recorded && l.technique == t;
        let shadows = |l: &LightPlan, t: Technique| uses(l, t) && l.shadowed;
        // Welded connectivity of every mesh (cached): volumes and silhouette maps use it, and
        // the report lists every mesh's topology.
        let adjacency = self.meshes.adjacency(scene)?;
        // The vertex streams, back in `self` once the frame's work is done.
        let mut streams = std::mem::take(&mut self.streams);

        // Shadow maps (also the depth maps of silhouette maps): fit each light's views, size
        // its map, and note what the GPU reads.
        let mut gpu_shadows = vec![GpuShadow::default(); scene.lights.len()];
        let mut shadow_views = Vec::new();
        let mut fitted: Vec<Option<LightViews>> = vec![None; scene.lights.len()];
        let mut silhouettes: Vec<Option<LightEdges>> = vec![None; scene.lights.len()];
        // Depth-bias clamp per light, in map depth units (0: none, or no `depthBiasClamp`).
        let mut bias_clamps = vec![0.0f32; scene.lights.len()];
        let mut edge_instances: Vec<EdgeInstance> = Vec::new();
        let hybrid_resolution = HybridSettings::default_resolution(self.desc.width, self.desc.height);
        let map_techniques = [Technique::ShadowMap, Technique::SilhouetteMap, Technique::Hybrid];
        // First every light's views and map size, each checked against the device, and what
        // they all take together against the budget; only then is anything allocated.
        let mut resolutions = vec![0u32; scene.lights.len()];
        let mut storage = Vec::new();
        for plan in lights.iter_mut().filter(|l| map_techniques.iter().any(|&t| shadows(l, t))) {
            let light = &scene.lights[plan.light];
            let Some(mut views) = frustum::fit(light, scene, &boxes, camera) else {
                plan.note = Some("no caster can shadow a visible receiver: no shadow map rendered".into());
                continue;
            };
            if self.desc.cull {
                // The fit saw every caster (so the map's frustum is the same either way); only
                // the planned ones are drawn, each into the views it may touch.
                views.casters.retain(|c| plan.map_casters.contains(c));
                let out = views.cull_per_view(&boxes);
                tally(&mut plan.culled, CullReason::OutsideMapView, out);
            }
            let silhouette = plan.technique == Technique::SilhouetteMap;
            if silhouette && views.kind == MapKind::Cube {
                return Err(RenderError::UnsupportedLight {
                    light: plan.light,
                    technique: plan.technique,
                    why: SILHOUETTE_CUBE_UNSUPPORTED.into(),
                });
            }
            let resolution = light.shadow_map_size.unwrap_or(match plan.technique {
                Technique::Hybrid => self.desc.hybrid.resolution.unwrap_or(hybrid_resolution),
                _ => settings.resolution,
            });
            let mut bytes = self.shadow_map.check(&self.ctx, plan.light, resolution, views.kind)?;
            if silhouette {
                let map = self.silhouette_map.check(&self.ctx, plan.light, resolution)?;
                // With diagnostics the map is also read back, as many bytes again.
                bytes += if self.diagnostic_targets.is_some() { 2 * map } else { map };
            }
            let cube = views.kind == MapKind::Cube;
            storage.push(ShadowStorage { light: plan.light, resolution, cube, silhouette, bytes });
            resolutions[plan.light] = resolution;
            fitted[plan.light] = Some(views);
        }
        budget::check(&storage, self.desc.shadow_map_budget_bytes)?;
        let has_map: Vec<bool> = fitted.iter().map(Option::is_some).collect();
        self.shadow_map.keep_only(&has_map);
        let mut has_silhouette = vec![false; scene.lights.len()];
        for s in &storage {
            has_silhouette[s.light] = s.silhouette;
        }
        self.silhouette_map.keep_only(&has_silhouette);
        for plan in lights.iter_mut() {
            let Some(views) = &fitted[plan.light] else { continue };
            let light = &scene.lights[plan.light];
            let silhouette = has_silhouette[plan.light];
            let resolution = resolutions[plan.light];
            self.shadow_map.prepare(&self.ctx, plan.light, resolution, views.kind)?;
            gpu_shadows[plan.light] = GpuShadow {
                kind: match (views.kind, silhouette) {
                    (MapKind::Cube, _) => 2,
                    (MapKind::Single, false) => 1,
                    (MapKind::Single, true) => 3,
                },
                first_view: shadow_views.len() as u32,
                normal_offset: settings.normal_offset,
                texel: 1.0 / resolution as f32,
                near: views.near,
                far: views.far,
            };
            plan.shadow_map = Some(ShadowMapReport {
                resolution,
                cube: views.kind == MapKind::Cube,
                near: views.near,
                far: views.far,
                casters: views.casters.len(),
                texel_size: (light.position.w == 0.0).then(|| frustum::texel_size(views.views[0], resolution)),
                view_proj: views.views.clone(),
            });
            if silhouette {
                self.silhouette_map.prepare(&self.ctx, plan.light, resolution)?;
                let e = edges::extract(scene, &adjacency, &views.casters, light, &mut edge_instances);
                plan.silhouette_map = Some(SilhouetteMapReport {
                    resolution,
                    silhouette_edges: e.count as usize,
                    cpu_extract_ms: e.cpu_ms,
                    silhouette_pixels: None,
                    silhouette_fraction: None,
                });
                silhouettes[plan.light] = Some(e);
            }
            let clamp_texels = match (settings.bias.clamp_texels, silhouette) {
                (Some(t), _) => Some(t),
                (None, true) => Some(DepthBias::SILHOUETTE_CLAMP_TEXELS),
                (None, false) => None,
            };
            if let (Some(texels), true) = (clamp_texels, self.ctx.capabilities().depth_bias_clamp) {
                bias_clamps[plan.light] = frustum::bias_clamp(views.views[0], resolution, texels);
            }
            shadow_views.extend_from_slice(&views.views);
        }
        let edge_buffer = streams.edges.fill(&self.ctx, &edge_instances)?;
        // Shadow volumes: every caster's volume per light, built on the CPU (z-fail only for
        // hybrid lights, Chan–Durand §3 step 3; none for a hybrid light without a map).
        let mut built: Vec<Option<LightVolumes>> = vec![None; scene.lights.len()];
        let mut volume_vertices = Vec::new();
        let volume_lights = lights.iter_mut().filter(|l| {
            shadows(l, Technique::ShadowVolume) || (shadows(l, Technique::Hybrid) && fitted[l.light].is_some())
        });
        for plan in volume_lights {
            let light = &scene.lights[plan.light];
            let mode = if plan.technique == Technique::Hybrid { VolumeMode::ZFail } else { volume_settings.mode };
            let v = volumes::build_light(
                scene,
                &plan.volume_casters,
                &adjacency,
                &boxes,
                light,
                &camera_used,
                aspect,
                mode,
                &mut volume_vertices,
            );
            built[plan.light] = Some(v);
        }
        let volume_buffer = streams.volumes.fill(&self.ctx, &volume_vertices)?;
        // Hybrid lights: their queries (mask samples, masked volume fragments) and, with
        // blocker culling, one box per caster of a 2D map.
        let hybrids: Vec<usize> = lights
            .iter()
            .filter(|l| l.technique == Technique::Hybrid && built[l.light].is_some() && fitted[l.light].is_some())
            .map(|l| l.light)
            .collect();
        let mut culling = CullingPlan::default();
        if self.desc.hybrid.cull_blockers && self.desc.cull {
            for &l in &hybrids {
                let (Some(v), Some(views)) = (&built[l], &fitted[l]) else { continue };
                if views.kind != MapKind::Single {
                    continue;
                }
                for (i, c) in v.casters.iter().enumerate() {
                    if let Some(b) = boxes.get(c.object).copied().flatten() {
                        if cull::queryable(&scene.lights[l], &b) {
                            cull::box_triangles(&b, &mut culling.vertices);
                            culling.boxes.push((l, i));
                        }
                    }
                }
            }
        }
        let culling_buffer = streams.blockers.fill(&self.ctx, &culling.vertices)?;
        let culling_queries = match culling.boxes.len() as u32 {
            0 => None,
            n => Some(QueryPool::new(&self.ctx, "blocker culling", QueryKind::Occlusion, n)?),
        };
        // Per hybrid light h: query h counts the mask pass's samples and, with `overdraw`,
        // query n + h the volume fragments through the mask.
        let counts_fragments = self.overdraw.is_some();
        let hybrid_queries = match hybrids.len() as u32 {
            0 => None,
            n => {
                let count = if counts_fragments { 2 * n } else { n };
                Some(QueryPool::new(&self.ctx, "hybrid samples", QueryKind::Occlusion, count)?)
            }
        };
        if !hybrids.is_empty() {
            self.hybrid.prepare(&self.ctx, self.desc.width, self.desc.height, self.mask == MaskKind::DepthBounds)?;
        }

        let gpu = GpuScene::upload(
            &self.ctx,
            &self.scene_set_layout,
            scene,
            &camera_used,
            aspect,
            &gpu_shadows,
            &shadow_views,
            self.gpu.take(),
        )?;
        let geometry_uploaded_bytes = gpu.geometry_uploaded;
        let shadow_sets = lights
            .iter()
            .filter(|l| l.recorded)
            .map(|l| {
                let has_map = fitted[l.light].is_some().then_some(l.light);
                let hybrid = hybrids.contains(&l.light);
                let technique_image = match (hybrid, self.hybrid.classes()) {
                    (true, Some(classes)) => classes,
                    _ => self.silhouette_map.image(silhouettes[l.light].map(|_| l.light)),
                };
                self.shadow_map.descriptor_set(&self.ctx, &self.shadow_set_layout, has_map, hybrid, technique_image)
            })
            .collect::<RenderResult<Vec<_>>>()?;
        // Pass 2 reads the depth map raw while it writes the silhouette map, which its set
        // must not bind: the placeholder stands in.
        let depth_sets = (0..scene.lights.len())
            .map(|l| match silhouettes[l] {
                Some(_) => self
                    .shadow_map
                    .descriptor_set(&self.ctx, &self.shadow_set_layout, Some(l), false, self.silhouette_map.image(None))
                    .map(Some),
                None => Ok(None),
            })
            .collect::<RenderResult<Vec<_>>>()?;
        let diagnosed: Vec<usize> = match self.diagnostic_targets {
            Some(_) => (0..scene.lights.len()).filter(|&l| silhouettes[l].is_some()).collect(),
            None => Vec::new(),
        };
        let diagnostic_buffers = diagnosed
            .iter()
            .map(|&l| {
                DiagnosticReadback::new(
                    &self.ctx,
                    self.desc.width,
                    self.desc.height,
                    self.silhouette_map.image(Some(l)),
                )
            })
            .collect::<RenderResult<Vec<_>>>()?;
        let hybrid_readbacks = match self.desc.diagnostics {
            true => hybrids
                .iter()
                .map(|_| ClassReadback::new(&self.ctx, self.desc.width, self.desc.height, true))
                .collect::<RenderResult<Vec<_>>>()?,
            false => Vec::new(),
        };
        // Shadow-map and shadow-volume lights: the classification alone (and the stencil that
        // decides a shadow-volume light's pixels).
        let classified: Vec<(usize, ClassReadback)> = match self.desc.diagnostics {
            true => lights
                .iter()
                .filter(|l| uses(l, Technique::ShadowMap) || uses(l, Technique::ShadowVolume))
                .map(|l| {
                    let stencil = built[l.light].is_some();
                    Ok((l.light, ClassReadback::new(&self.ctx, self.desc.width, self.desc.height, stencil)?))
                })
                .collect::<RenderResult<Vec<_>>>()?,
            false => Vec::new(),
        };
        // Poison the readback so a copy that never happened cannot pass for a frame.
        let poison = vec![0xCD; self.readback.desc.size as usize];
        self.readback.write(0, &poison)?;

        let planned = lights.iter().filter(|l| l.recorded).count();
        let passes = 2
            + planned
            + fitted.iter().flatten().count()
            + silhouettes.iter().flatten().count()
            + diagnosed.len()
            + 2 * built.iter().flatten().count()
            + 7 * hybrids.len()
            + classified.len()
            + usize::from(self.gbuffer.is_some())
            + usize::from(culling_queries.is_some());
        // One overdraw query per light with volumes, when any volume has vertices to draw.
        let volume_lights = match volume_buffer {
            Some(_) => built.iter().flatten().count() as u32,
            None => 0,
        };
        let fragment_queries = match (&self.overdraw, volume_lights) {
            (Some(_), n) if n > 0 => Some(QueryPool::new(&self.ctx, "volume fragments", QueryKind::Occlusion, n)?),
            _ => None,
        };
        let timer = PassTimer::new(&self.ctx, passes, self.timer.take())?;
        let mut log = PassLog::default();
        let mut rec = self.ctx.begin_commands("frame")?;
        timer.reset(&mut rec);
        for pool in [&culling_queries, &hybrid_queries, &fragment_queries].into_iter().flatten() {
            rec.reset_queries(pool);
        }

        // The lights' views first: shadow maps, silhouette points, blocker culling.
        for plan in lights.iter().filter(|l| l.recorded) {
            if let Some(views) = &fitted[plan.light] {
                timer.begin(&mut rec, &mut log, format!("shadow_map {}", plan.light), Some(plan.light));
                let first_view = gpu_shadows[plan.light].first_view;
                let clamp = bias_clamps[plan.light];
                self.shadow_map.record(
                    &mut rec,
                    &self.layout,
                    &gpu,
                    scene,
                    plan.light,
                    views,
                    first_view,
                    clamp,
                    &mut log,
                )?;
                timer.end(&mut rec, &log);
            }
            if let (Some(e), Some(depth_set)) = (silhouettes[plan.light], &depth_sets[plan.light]) {
                timer.begin(&mut rec, &mut log, format!("silhouette_map {}", plan.light), Some(plan.light));
                self.silhouette_map.record_points(
                    &mut rec,
                    &self.layout,
                    &gpu,
                    depth_set,
                    plan.light,
                    edge_buffer,
                    e,
                    &mut log,
                )?;
                timer.end(&mut rec, &log);
            }
        }
        let mut rec = match (&culling_buffer, &culling_queries) {
            (Some(vertices), Some(queries)) => {
                timer.begin(&mut rec, &mut log, "blocker culling".into(), None);
                let mut first = 0;
                for &l in &hybrids {
                    let n = culling.boxes.iter().filter(|(light, _)| *light == l).count() as u32;
                    if n == 0 {
                        continue;
                    }
                    let map = self.shadow_map.image(l)?;
                    let view = gpu_shadows[l].first_view;
                    self.hybrid.record_culling(
                        &mut rec,
                        &self.layout,
                        &gpu,
                        map,
                        vertices,
                        first..first + n,
                        view,
                        queries,
                        first,
                        &mut log,
                    );
                    first += n;
                }
                timer.end(&mut rec, &log);
                // The volumes to draw depend on the answers: read them before going on.
                self.submissions += 1;
                self.ctx.submit_and_wait(rec)?;
                let visible = queries.results()?;
                culling.apply(&visible, &mut built);
                self.ctx.begin_commands("frame (after blocker culling)")?
            }
            _ => rec,
        };
        for plan in lights.iter_mut().filter(|l| built[l.light].is_some()) {
            if let Some(v) = &built[plan.light] {
                plan.shadow_volume = Some(volume_report(scene, v));
            }
            if let Some(n) = culling.culled(plan.light) {
                tally(&mut plan.culled, CullReason::HiddenBlocker, n);
            }
        }

        rec.transition(&[
            (&self.color, ImageState::Undefined, ImageState::ColorAttachment),
            (&self.depth, ImageState::Undefined, ImageState::DepthStencilAttachment),
        ]);
        let bg = scene.background;
        timer.begin(&mut rec, &mut log, "ambient".into(), None);
        let clear_color = [ColorAttachment { image: &self.color, clear: Some([bg.x, bg.y, bg.z, 1.0]) }];
        rec.begin_rendering(&RenderTargets {
            color: &clear_color,
            depth: Some(DepthAttachment {
                image: &self.depth,
                view: None,
                clear: Some((1.0, 0)),
                clear_stencil: None,
                read_only: false,
            }),
        });
        self.forward.record_ambient(&mut rec, &self.layout, &gpu, scene, &mut log);
        rec.end_rendering();
        timer.end(&mut rec, &log);
        if let Some(g) = &self.gbuffer {
            g.record(&mut rec, &timer, &mut log, &self.layout, &gpu, scene, &self.depth);
        }

        let load_color = [ColorAttachment { image: &self.color, clear: None }];
        let keep_depth = |clear_stencil| DepthAttachment {
            image: &self.depth,
            view: None,
            clear: None,
            clear_stencil,
            read_only: false,
        };
        let mut overdraw_query = 0;
        let mut diagnosed_so_far = 0;
        // Whether the classification target was used this frame (it is then in TransferSrc).
        let mut classification_used = false;
        for (plan, shadow_set) in lights.iter().filter(|l| l.recorded).zip(&shadow_sets) {
            let volumes = built[plan.light].as_ref().zip(volume_buffer);
            if let Some(h) = hybrids.iter().position(|&l| l == plan.light) {
                let (Some(v), Some(queries)) = (&built[plan.light], &hybrid_queries) else { continue };
                let light = HybridLight {
                    light: plan.light,
                    mask: self.mask,
                    first_in_frame: h == 0,
                    layout: &self.layout,
                    gpu: &gpu,
                    scene,
                    shadow_set,
                    color: &self.color,
                    depth: &self.depth,
                    volumes: v,
                    vertices: volume_buffer,
                    zfail: self.shadow_volume.zfail(),
                    queries,
                    first_query: h as u32,
                    fragment_query: counts_fragments.then_some((hybrids.len() + h) as u32),
                    readback: hybrid_readbacks.get(h),
                };
                self.hybrid.record_light(&mut rec, &timer, &mut log, light);
            } else {
                let bounds = PassBounds { scissor: plan.scissor, depth: plan.depth_bounds };
                if let Some((v, buffer)) = volumes {
                    timer.begin(&mut rec, &mut log, format!("shadow_volume {}", plan.light), Some(plan.light));
                    rec.begin_rendering(&RenderTargets { color: &[], depth: Some(keep_depth(Some(0))) });
                    self.shadow_volume.record_stencil(
                        &mut rec,
                        VolumeBindings { layout: &self.layout, gpu: &gpu, vertices: buffer },
                        v,
                        plan.light as u32,
                        bounds,
                        &mut log,
                    );
                    rec.end_rendering();
                    timer.end(&mut rec, &log);
                }
                timer.begin(
                    &mut rec,
                    &mut log,
                    format!("light {} ({:?})", plan.light, plan.kind).to_lowercase(),
                    Some(plan.light),
                );
                rec.begin_rendering(&RenderTargets { color: &load_color, depth: Some(keep_depth(None)) });
                // Test the stencil only after this light's own stencil pass (which cleared it).
                let stenciled = volumes.is_some();
                self.forward.record_light(
                    &mut rec,
                    &self.layout,
                    &gpu,
                    shadow_set,
                    scene,
                    plan.light as u32,
                    stenciled,
                    bounds,
                    &mut log,
                );
                rec.end_rendering();
                timer.end(&mut rec, &log);
            }
            let readback = classified.iter().find(|(l, _)| *l == plan.light).map(|(_, r)| r);
            if let (Some(targets), Some(out)) = (&self.diagnostic_targets, readback) {
                timer.begin_diagnostic(
                    &mut rec,
                    &mut log,
                    format!("light diagnostics {}", plan.light),
                    Some(plan.light),
                );
                let class = &targets.classification;
                let was = if classification_used { ImageState::TransferSrc } else { ImageState::Undefined };
                rec.transition(&[(class, was, ImageState::ColorAttachment)]);
                let color = [ColorAttachment { image: class, clear: Some([0.0; 4]) }];
                rec.begin_rendering(&RenderTargets { color: &color, depth: Some(keep_depth(None)) });
                let light = plan.light as u32;
                self.forward.record_classes(&mut rec, &self.layout, &gpu, shadow_set, scene, light, &mut log);
                rec.end_rendering();
                rec.transition(&[(class, ImageState::ColorAttachment, ImageState::TransferSrc)]);
                rec.copy_image_to_buffer(class, 0, &out.classes);
                if let Some(stencil) = &out.stencil {
                    let attachment = ImageState::DepthStencilAttachment;
                    rec.transition(&[(&self.depth, attachment, ImageState::TransferSrc)]);
                    rec.copy_stencil_to_buffer(&self.depth, stencil);
                    rec.transition(&[(&self.depth, ImageState::TransferSrc, attachment)]);
                }
                timer.end(&mut rec, &log);
                classification_used = true;
            }
            if let (Some((v, buffer)), Some((image, _)), Some(q)) = (volumes, &self.overdraw, &fragment_queries) {
                timer.begin_diagnostic(&mut rec, &mut log, format!("volume overdraw {}", plan.light), Some(plan.light));
                if overdraw_query == 0 {
                    rec.transition(&[(image, ImageState::Undefined, ImageState::ColorAttachment)]);
                }
                let clear = (overdraw_query == 0).then_some([0.0; 4]);
                rec.begin_rendering(&RenderTargets { color: &[ColorAttachment { image, clear }], depth: None });
                rec.begin_query(q, overdraw_query);
                self.shadow_volume.record_overdraw(
                    &mut rec,
                    VolumeBindings { layout: &self.layout, gpu: &gpu, vertices: buffer },
                    v,
                    plan.light as u32,
                    &mut log,
                );
                rec.end_query(q, overdraw_query);
                rec.end_rendering();
                timer.end(&mut rec, &log);
                overdraw_query += 1;
            }
            if let (Some(targets), true) = (&self.diagnostic_targets, diagnosed.contains(&plan.light)) {
                timer.begin_diagnostic(
                    &mut rec,
                    &mut log,
                    format!("silhouette diagnostics {}", plan.light),
                    Some(plan.light),
                );
                let was = if classification_used { ImageState::TransferSrc } else { ImageState::Undefined };
                let (class, points) = (&targets.classification, &targets.points);
                rec.transition(&[
                    (class, was, ImageState::ColorAttachment),
                    (points, was, ImageState::ColorAttachment),
                ]);
                let color = [
                    ColorAttachment { image: class, clear: Some(diagnostics::BACKGROUND) },
                    ColorAttachment { image: points, clear: Some([0.0; 4]) },
                ];
                rec.begin_rendering(&RenderTargets { color: &color, depth: Some(keep_depth(None)) });
                self.silhouette_map.record_diagnostics(
                    &mut rec,
                    &self.layout,
                    &gpu,
                    shadow_set,
                    scene,
                    plan.light as u32,
                    &mut log,
                );
                rec.end_rendering();
                let silmap = self.silhouette_map.image(Some(plan.light));
                rec.transition(&[
                    (class, ImageState::ColorAttachment, ImageState::TransferSrc),
                    (points, ImageState::ColorAttachment, ImageState::TransferSrc),
                    (silmap, ImageState::FragmentRead, ImageState::TransferSrc),
                ]);
                let out = &diagnostic_buffers[diagnosed_so_far];
                rec.copy_image_to_buffer(class, 0, &out.classification);
                rec.copy_image_to_buffer(points, 0, &out.points);
                rec.copy_image_to_buffer(silmap, 0, &out.silhouette_map);
                timer.end(&mut rec, &log);
                diagnosed_so_far += 1;
                classification_used = true;
            }
        }
        if let (Some((image, readback)), true) = (&self.overdraw, overdraw_query > 0) {
            rec.transition(&[(image, ImageState::ColorAttachment, ImageState::TransferSrc)]);
            rec.copy_image_to_buffer(image, 0, readback);
        }

        timer.begin(&mut rec, &mut log, "readback".into(), None);
        rec.transition(&[(&self.color, ImageState::ColorAttachment, ImageState::TransferSrc)]);
        rec.copy_image_to_buffer(&self.color, 0, &self.readback);
        timer.end(&mut rec, &log);
        self.submissions += 1;
        self.ctx.submit_and_wait(rec)?;
        // Kept for the next frame: its meshes, per-frame buffers and vertex streams are reused.
        self.gpu = Some(gpu);
        self.streams = streams;

        let passes = timer.finish(log)?;
        self.timer = Some(timer);
        let rgba = self.readback.read()?;
        let overdraw = match (&self.overdraw, overdraw_query > 0) {
            (Some((_, readback)), true) => Some(readback.read()?),
            _ => None,
        };
        let counts = match (&fragment_queries, &self.overdraw) {
            (Some(q), _) => Some(q.results()?),
            // Volumes built, none with a triangle: nothing was rasterized.
            (None, Some(_)) => Some(vec![0; built.iter().flatten().count()]),
            (None, None) => None,
        };
        if let Some(counts) = counts {
            let with_volumes = lights.iter_mut().filter(|l| l.shadow_volume.is_some());
            for (plan, count) in with_volumes.zip(counts) {
                if let Some(r) = plan.shadow_volume.as_mut() {
                    r.volume_fragments = Some(count);
                }
            }
        }
        let image_pixels = u64::from(self.desc.width) * u64::from(self.desc.height);
        let mut diagnostics = Vec::with_capacity(diagnosed.len() + hybrid_readbacks.len());
        for (&light, out) in diagnosed.iter().zip(&diagnostic_buffers) {
            let d = out.read(light)?;
            if let Some(r) = lights[light].silhouette_map.as_mut() {
                let n = d.silhouette_pixels();
                r.silhouette_pixels = Some(n);
                r.silhouette_fraction = Some(n as f64 / image_pixels as f64);
            }
            diagnostics.push(d);
        }
        if let Some(q) = &hybrid_queries {
            let samples = q.results()?;
            for (h, &l) in hybrids.iter().enumerate() {
                let kept = samples[h];
                // The depth-bounds mask pass keeps the other pixels; the others keep silhouettes.
                let silhouette_pixels = match self.mask {
                    MaskKind::DepthBounds => image_pixels.saturating_sub(kept),
                    _ => kept,
                };
                let plan = &mut lights[l];
                let volume_fragments = plan.shadow_volume.as_ref().and_then(|r| r.volume_fragments);
                plan.hybrid = Some(HybridReport {
                    mask: self.mask,
                    depth_bounds_epsilon: (self.mask == MaskKind::DepthBounds).then_some(DEPTH_BOUNDS_EPSILON),
                    silhouette_pixels,
                    silhouette_fraction: silhouette_pixels as f64 / image_pixels as f64,
                    volume_casters: built[l].as_ref().map_or(0, |v| v.casters.len()),
                    culled_casters: culling.culled(l),
                    volume_fragments,
                    masked_volume_fragments: match self.mask {
                        MaskKind::None => volume_fragments,
                        _ => counts_fragments.then(|| samples[hybrids.len() + h]),
                    },
                    stencil_gpu_ms: passes
                        .iter()
                        .find(|p| p.light == Some(l) && p.name.starts_with("hybrid volumes"))
                        .and_then(|p| p.gpu_ms),
                });
            }
            for (&l, out) in hybrids.iter().zip(&hybrid_readbacks) {
                diagnostics.push(out.read(l, Some((PixelClass::SilhouetteLit, self.mask.count_bits())))?);
            }
        }
        for (l, out) in &classified {
            // A shadow-volume light's shader saw no shadow: its stencil decides every lit pixel.
            diagnostics.push(out.read(*l, out.stencil.as_ref().map(|_| (PixelClass::MapLit, 0xff)))?);
        }
        diagnostics.sort_by_key(|d| d.light);
        let gbuffer = self.gbuffer.as_ref().map(GBufferPass::read).transpose()?;
        let caps = self.ctx.capabilities();
        let sum = |diagnostic: bool| {
            passes.iter().filter(|p| p.diagnostic == diagnostic).map(|p| p.gpu_ms).sum::<Option<f64>>()
        };
        for plan in &mut lights {
            plan.passes = passes.iter().filter(|p| p.light == Some(plan.light)).map(|p| p.name.clone()).collect();
        }
        let report = FrameReport {
            device: caps.device_name.clone(),
            driver: caps.driver(),
            capabilities: caps.clone(),
            scene: SceneSummary::of(scene, &adjacency),
            width: self.desc.width,
            height: self.desc.height,
            shadow_map_settings: settings,
            shadow_volume_settings: volume_settings,
            plan: FramePlan::of(self.desc.cull, &lights),
            lights,
            total_gpu_ms: sum(false),
            diagnostic_gpu_ms: sum(true),
            passes,
            cpu_frame_ms: started.elapsed().as_secs_f64() * 1e3,
            geometry_uploaded_bytes,
            memory_allocations: self.ctx.memory_allocations() - allocations_before,
        };
        Ok(Frame { width: self.desc.width, height: self.desc.height, rgba, report, overdraw, diagnostics, gbuffer })
    }
}

/// A frame-sized RGBA8 image rendered to and copied out (colour, overdraw, diagnostic views).
fn frame_target(ctx: &Context, name: &str, width: u32, height: u32) -> RenderResult<Image> {
    Ok(Image::new(ctx, name, frame_target_desc(width, height))?)
}

/// The description of [`frame_target`]'s images.
fn frame_target_desc(width: u32, height: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    ImageDesc::new_2d(COLOR_FORMAT, width, height).usage(usage)
}

/// The frame's depth/stencil target, copied out for stencil diagnostics.
fn depth_desc(format: vk::Format, width: u32, height: u32) -> ImageDesc {
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    ImageDesc::new_2d(format, width, height).usage(usage)
}

/// Checks `desc`'s size against every limit of the frame-sized images the renderer may create
/// (colour and depth targets, the hybrid's classes and masked depth, the G-buffer): a typed
/// [`RenderError::InvalidSize`] naming the first limit broken, before anything is created.
fn check_frame_size(ctx: &Context, desc: &RendererDesc, depth_format: vk::Format, mask: MaskKind) -> RenderResult<()> {
    let (width, height) = (desc.width, desc.height);
    if width == 0 || height == 0 {
        return Err(RenderError::InvalidSize {
            width,
            height,
            why: "each side must be at least 1".into(),
            limit: None,
        });
    }
    let (classes, masked_depth) = hybrid_pass::target_descs(depth_format, width, height);
    let mut images = vec![
        ("colour target", frame_target_desc(width, height)),
        ("depth/stencil target", depth_desc(depth_format, width, height)),
        ("hybrid silhouette classes", classes),
    ];
    if mask == MaskKind::DepthBounds {
        images.push(("hybrid masked depth", masked_depth));
    }
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

/// Blocker culling's queries in one frame: a box per (hybrid light, caster index).
#[derive(Default)]
struct CullingPlan {
    boxes: Vec<(usize, usize)>,
    vertices: Vec<glam::Vec4>,
    /// Casters dropped per light, once the answers are in.
    culled: Vec<(usize, usize)>,
}

impl CullingPlan {
    /// Drops from `built` every queried caster whose box had no visible sample.
    fn apply(&mut self, visible: &[u64], built: &mut [Option<LightVolumes>]) {
        let mut dropped: Vec<(usize, usize)> =
            self.boxes.iter().zip(visible).filter(|(_, &n)| n == 0).map(|(&b, _)| b).collect();
        // Highest caster index first, so earlier indices stay valid.
        dropped.sort_by(|a, b| b.cmp(a));
        for &(light, caster) in &dropped {
            if let Some(v) = built[light].as_mut() {
                v.casters.remove(caster);
            }
        }
        for &(light, _) in &self.boxes {
            if !self.culled.iter().any(|&(l, _)| l == light) {
                let n = dropped.iter().filter(|&&(l, _)| l == light).count();
                self.culled.push((light, n));
            }
        }
    }

    /// Casters culled for `light`, when its boxes were queried.
    fn culled(&self, light: usize) -> Option<usize> {
        self.culled.iter().find(|&&(l, _)| l == light).map(|&(_, n)| n)
    }
}

/// The report of one light's volumes.
fn volume_report(scene: &Scene, v: &LightVolumes) -> ShadowVolumeReport {
    let mode = |c: Counting| if c == Counting::ZPass { "zpass" } else { "zfail" };
    ShadowVolumeReport {
        casters: v.casters.len(),
        zpass_casters: v.casters.iter().filter(|c| c.counting == Counting::ZPass).count(),
        zfail_casters: v.casters.iter().filter(|c| c.counting == Counting::ZFail).count(),
        silhouette_edges: v.casters.iter().map(|c| c.stats.silhouette_edges).sum(),
        volume_triangles: v.casters.iter().map(|c| c.count as usize / 3).sum(),
        cpu_build_ms: v.cpu_ms,
        volume_fragments: None,
        caster_modes: v
            .casters
            .iter()
            .map(|c| CasterMode {
                object: c.object,
                name: scene.objects.get(c.object).map(|o| o.name.clone()).unwrap_or_default(),
                mode: mode(c.counting),
                triangles: c.count as usize / 3,
            })
            .collect(),
    }
}

/// Host-visible copies of one light's diagnostic views and silhouette map.
struct DiagnosticReadback {
    classification: Buffer,
    points: Buffer,
    silhouette_map: Buffer,
    resolution: u32,
}

impl DiagnosticReadback {
    fn new(ctx: &Context, width: u32, height: u32, silhouette_map: &Image) -> RenderResult<Self> {
        let frame = BufferDesc::readback(4 * u64::from(width) * u64::from(height));
        let resolution = silhouette_map.desc.width;
        let points = BufferDesc::readback(8 * u64::from(resolution) * u64::from(resolution));
        Ok(Self {
            classification: Buffer::new(ctx, "diagnostics readback: classification", frame)?,
            points: Buffer::new(ctx, "diagnostics readback: silhouette points", frame)?,
            silhouette_map: Buffer::new(ctx, "diagnostics readback: silhouette map", points)?,
            resolution,
        })
    }

    fn read(&self, light: usize) -> RenderResult<LightDiagnostics> {
        let raw = self.silhouette_map.read()?;
        let points = raw
            .chunks_exact(8)
            .map(|c| {
                let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                [f(&c[..4]), f(&c[4..])]
            })
            .collect();
        Ok(LightDiagnostics {
            light,
            classification: self.classification.read()?,
            points: Some(self.points.read()?),
            silhouette_map: Some(SilhouetteMapImage { resolution: self.resolution, points }),
            stencil: None,
        })
    }
}
