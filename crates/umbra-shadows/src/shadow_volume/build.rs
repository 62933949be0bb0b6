//! Per light, on the CPU: every caster's volume (in parallel) and the counting mode each one
//! uses (§3.4).

use super::settings::VolumeMode;
use super::{CasterMode, ShadowVolumeReport};
use crate::view::View;
use glam::{Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;
use std::sync::Arc;
use umbra_scene::{Aabb, Adjacency, Camera, Light, Scene, Volume, VolumeStats};

/// Counting mode chosen for one caster.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Counting {
    ZPass,
    ZFail,
}

/// One caster's volume, as a range of the frame's volume vertices.
#[derive(Clone, Debug)]
pub(crate) struct CasterVolume {
    pub object: usize,
    /// `None`: decided per frame on the GPU (`gpu.rs`, [`VolumeMode::Auto`]).
    pub counting: Option<Counting>,
    pub first: u32,
    pub count: u32,
    /// The last `cut_caps` of the `count` vertices are front-cap triangles cut on the host
    /// (`clip.rs`), drawn with [`super::pass::CUT_CAP_COMPARE`]; 0 unless host-clipped.
    pub cut_caps: u32,
    /// The most this volume can add to a pixel's count: 1 for a convex solid
    /// (`Adjacency::convex`), else its cap triangles (each adds at most 1).
    pub count_bound: u32,
    pub stats: VolumeStats,
    /// Built on the GPU: its job (`gpu.rs`), and `first`/`count` are 0.
    pub job: Option<u32>,
}

/// What one caster's volume counted, for the report.
#[derive(Clone, Copy, Debug)]
struct Counted {
    edges: usize,
    triangles: usize,
    /// `None`: decided on the GPU, not read back.
    mode: Option<Counting>,
}

/// Every caster's volume for one light.
#[derive(Clone, Debug, Default)]
pub(crate) struct LightVolumes {
    pub casters: Vec<CasterVolume>,
    pub cpu_ms: f64,
    /// The casters' ranges are in the host-clipped vertices (`clip.rs`).
    pub host_clipped: bool,
    /// The batches the casters are counted in, as ranges of `casters` (`batches.rs`): all at
    /// once until [`Self::plan_batches`] runs on the final casters.
    pub batches: Vec<std::ops::Range<usize>>,
    /// Built on the GPU (`gpu_frame.rs`): the frame's index of its first job, and its jobs.
    pub gpu: Option<(usize, Vec<super::gpu::VolumeJob>)>,
    /// The camera's depth precision where it is coarser than measured exact
    /// (`View::depth_precision`), for the report.
    pub depth_precision: Option<crate::view::DepthPrecision>,
}

impl LightVolumes {
    /// Plans the batches of the casters as they will be drawn (after blocker culling), for the
    /// stencil layout `bits`.
    pub fn plan_batches(&mut self, bits: super::batches::CountBits) {
        self.batches = super::batches::count_batches(&self.casters, bits);
    }

    /// The report of these volumes (`volume_fragments` is filled in once counted; built on the
    /// GPU, the counts are 0 and modes decided there `gpu` until [`Self::counted_report`]).
    pub fn report(&self, scene: &Scene) -> ShadowVolumeReport {
        self.report_with(scene, |c| {
            Some(Counted { edges: c.stats.silhouette_edges, triangles: c.count as usize / 3, mode: c.counting })
        })
    }

    /// The report of volumes built on the GPU, with their counts and modes from the draws
    /// buffer's `words` as read back (`gpu::JobCounts`): as the CPU path reports them, casters
    /// whose volume is empty left out.
    pub fn counted_report(&self, scene: &Scene, words: &[u32]) -> ShadowVolumeReport {
        let Some((first, jobs)) = &self.gpu else { return self.report(scene) };
        self.report_with(scene, |c| {
            let job = c.job?;
            let counts =
                super::gpu::JobCounts::read(words, jobs.get((job as usize).wrapping_sub(*first))?, job as usize);
            let triangles = (2 * counts.silhouette_edges + counts.cap_triangles) as usize;
            let edges = counts.silhouette_edges as usize;
            (triangles > 0).then_some(Counted { edges, triangles, mode: counts.mode })
        })
    }

    /// The report, with each caster's silhouette edges, volume triangles and mode from
    /// `counts` (`None`: an empty volume, left out; a mode `None`: decided on the GPU, not
    /// read back).
    fn report_with(&self, scene: &Scene, counts: impl Fn(&CasterVolume) -> Option<Counted>) -> ShadowVolumeReport {
        let name = |c: Option<Counting>| match c {
            Some(Counting::ZPass) => "zpass",
            Some(Counting::ZFail) => "zfail",
            None => "gpu",
        };
        let casters: Vec<(&CasterVolume, Counted)> =
            self.casters.iter().filter_map(|c| Some((c, counts(c)?))).collect();
        let with = |mode: Counting| casters.iter().filter(|(_, n)| n.mode == Some(mode)).count();
        ShadowVolumeReport {
            casters: casters.len(),
            zpass_casters: with(Counting::ZPass),
            zfail_casters: with(Counting::ZFail),
            silhouette_edges: casters.iter().map(|(_, n)| n.edges).sum(),
            volume_triangles: casters.iter().map(|(_, n)| n.triangles).sum(),
            host_clipped: self.host_clipped,
            count_batches: self.batches.len(),
            cpu_build_ms: self.cpu_ms,
            volume_fragments: None,
            caster_modes: casters
                .iter()
                .map(|(c, n)| CasterMode {
                    object: c.object,
                    name: scene.objects.get(c.object).map(|o| o.name.clone()).unwrap_or_default(),
                    mode: name(n.mode),
                    triangles: n.triangles,
                })
                .collect(),
            gpu_built: self.gpu.is_some(),
            depth_precision: self.depth_precision,
        }
    }
}

/// One light's shadow-volume casters, as both paths read them.
#[derive(Clone, Copy)]
pub(crate) struct LightCasters<'a> {
    pub scene: &'a Scene,
    /// The objects that cast (the plan's, `LightPlan::volume_casters`).
    pub casters: &'a [usize],
    /// Mesh `i`'s welded connectivity at `i`.
    pub adjacency: &'a [Arc<Adjacency>],
    /// Each object's world bounds (`Scene::object_bounds`).
    pub boxes: &'a [Option<Aabb>],
    pub light: &'a Light,
    /// The camera the volumes are drawn from (its near plane decides z-pass or z-fail).
    pub view: &'a View,
    pub mode: VolumeMode,
}

/// Builds the volumes of `c.light` for its casters, appending their vertices to `vertices`.
pub(crate) fn build_light(c: LightCasters<'_>, vertices: &mut Vec<Vec4>) -> LightVolumes {
    let LightCasters { scene, casters, adjacency, boxes, light, view, mode } = c;
    let started = std::time::Instant::now();
    let near_region = NearRegion::new(view, light.position);
    let built: Vec<(usize, Counting, Vec<Vec4>, VolumeStats, u32)> = casters
        .par_iter()
        .filter_map(|&i| {
            let o = scene.objects.get(i)?;
            let adj = adjacency.get(o.mesh)?;
            let bounds = boxes.get(i).copied().flatten()?;
            // The light in the caster's object space: facing is decided there.
            let local = o.transform.inverse() * light.position;
            let volume = Volume::build(adj, local);
            let counting = match mode {
                VolumeMode::ZPass => Counting::ZPass,
                VolumeMode::ZFail => Counting::ZFail,
                VolumeMode::Auto => {
                    if near_region.may_touch(&bounds) {
                        Counting::ZFail
                    } else {
                        Counting::ZPass
                    }
                }
            };
            let verts = volume.vertices(adj, counting == Counting::ZFail);
            let bound = if adj.convex { 1 } else { volume.stats.cap_triangles as u32 };
            Some((i, counting, verts, volume.stats, bound))
        })
        .collect();
    let mut casters = Vec::with_capacity(built.len());
    for (object, counting, verts, stats, count_bound) in built {
        if verts.is_empty() {
            continue;
        }
        casters.push(CasterVolume {
            object,
            counting: Some(counting),
            first: vertices.len() as u32,
            count: verts.len() as u32,
            cut_caps: 0,
            count_bound,
            stats,
            job: None,
        });
        vertices.extend(verts);
    }
    let batches = std::iter::once(0..casters.len()).collect();
    LightVolumes {
        casters,
        cpu_ms: started.elapsed().as_secs_f64() * 1e3,
        host_clipped: false,
        batches,
        gpu: None,
        depth_precision: None,
    }
}

/// Names the volumes of `c.light` for its casters as jobs of the GPU path (`gpu.rs`),
/// appended to `jobs` over `arrays` (every mesh's adjacency, in mesh order), with their facing
/// and list entries after `next` (advanced). Nothing per triangle, and in [`VolumeMode::Auto`]
/// nothing per caster but its box: the GPU decides each caster's counting mode from the
/// light's near-plane clip region, made here once.
pub(crate) fn jobs_for_light(
    c: LightCasters<'_>,
    arrays: &super::gpu::MeshRanges,
    jobs: &mut Vec<super::gpu::VolumeJob>,
    next: &mut (u32, u32),
) -> LightVolumes {
    let LightCasters { scene, casters, adjacency, boxes, light, view, mode } = c;
    use super::gpu::{MODE_AUTO, MODE_ZFAIL, MODE_ZPASS, NEAR_PLANES};
    let started = std::time::Instant::now();
    let (counting, job_mode) = match mode {
        VolumeMode::ZPass => (Some(Counting::ZPass), MODE_ZPASS),
        VolumeMode::ZFail => (Some(Counting::ZFail), MODE_ZFAIL),
        VolumeMode::Auto => (None, MODE_AUTO),
    };
    let mut near = [[0.0; 4]; NEAR_PLANES];
    let near_region = NearRegion::new(view, light.position);
    for (to, plane) in near.iter_mut().zip(&near_region.planes) {
        *to = plane.to_array();
    }
    let near_count = near_region.planes.len().min(NEAR_PLANES) as u32;
    let first = jobs.len();
    let mut out = Vec::with_capacity(casters.len());
    for &i in casters {
        let (Some(o), Some(bounds)) = (scene.objects.get(i), boxes.get(i).copied().flatten()) else { continue };
        let (Some(adj), Some(range)) = (adjacency.get(o.mesh), arrays.get(o.mesh)) else { continue };
        let local = o.transform.inverse() * light.position;
        let job = super::gpu::VolumeJob {
            box_min: bounds.min.extend(0.0).to_array(),
            box_max: bounds.max.extend(0.0).to_array(),
            near,
            near_count,
            mode: job_mode,
            ..range.job(local, next.0, next.1)
        };
        next.0 += job.triangle_count;
        next.1 += range.list_bound;
        // Caps a ray may cross: a closed caster's triangles, an open one's twice (edge-on ones,
        // which make none, are not known on the host).
        let faces = (adj.report.triangles - adj.report.degenerate_triangles) as u32;
        let count_bound = match (adj.convex, adj.report.closed) {
            (true, _) => 1,
            (false, true) => faces,
            (false, false) => 2 * faces,
        };
        out.push(CasterVolume {
            object: i,
            counting,
            first: 0,
            count: 0,
            cut_caps: 0,
            count_bound,
            stats: VolumeStats::default(),
            job: Some(jobs.len() as u32),
        });
        jobs.push(job);
    }
    let batches = std::iter::once(0..out.len()).collect();
    // No job, nothing to build: the light is drawn as one with no volumes.
    let gpu = (jobs.len() > first).then(|| (first, jobs[first..].to_vec()));
    LightVolumes {
        casters: out,
        cpu_ms: started.elapsed().as_secs_f64() * 1e3,
        host_clipped: false,
        batches,
        gpu,
        depth_precision: None,
    }
}

/// The near-plane clip region of §3.4: the convex hull of the camera's near rectangle and the
/// light (a point light), or the near rectangle swept towards a directional light. A caster
/// whose volume can reach the near rectangle must lie in it; a caster outside it may use
/// z-pass. The test is conservative (face planes of the region only): when unsure, z-fail.
/// `classify.comp` runs the same test for volumes built on the GPU.
struct NearRegion {
    /// Outward planes (normal, offset): a point p is outside when n·p + d > 0.
    planes: Vec<Vec4>,
}

impl NearRegion {
    fn new(view: &View, light: Vec4) -> Self {
        let inv = view.view_proj.inverse();
        let corners: Vec<Vec3> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(x, y)| inv.project_point3(Vec3::new(x, y, 0.0)))
            .collect();
        let centre = corners.iter().sum::<Vec3>() / 4.0;
        // A point well inside the region, to orient the planes outward.
        let inside = if light.w == 0.0 {
            centre + light.xyz().normalize() * 0.5
        } else {
            centre * 0.75 + light.xyz() / light.w * 0.25
        };
        let mut planes = Vec::new();
        let mut add = |n: Vec3, p: Vec3| {
            if n.length_squared() < 1e-12 {
                return false;
            }
            let n = n.normalize();
            let mut pl = n.extend(-n.dot(p));
            if pl.xyz().dot(inside) + pl.w > 0.0 {
                pl = -pl;
            }
            planes.push(pl);
            true
        };
        let ok = add((corners[1] - corners[0]).cross(corners[3] - corners[0]), corners[0])
            && (0..4).all(|k| {
                let (a, b) = (corners[k], corners[(k + 1) % 4]);
                let towards = if light.w == 0.0 { light.xyz() } else { light.xyz() / light.w - a };
                add((b - a).cross(towards), a)
            });
        if !ok {
            planes.clear(); // degenerate (light on the near plane): no separating plane known
        }
        Self { planes }
    }

    /// Whether the box may intersect the region (false: certainly not).
    fn may_touch(&self, b: &Aabb) -> bool {
        if self.planes.is_empty() {
            return true;
        }
        !self.planes.iter().any(|pl| {
            // The box corner farthest against the outward normal: if even it is outside, the
            // whole box is.
            let n = pl.xyz();
            let nearest = Vec3::select(n.cmpge(Vec3::ZERO), b.min, b.max);
            n.dot(nearest) + pl.w > 0.0
        })
    }
}

/// The camera a frame with shadow volumes renders with: the scene's, with the far plane at
/// infinity unless depth clamp is used.
pub(crate) fn volume_camera(camera: &Camera, infinite: bool) -> Camera {
    if infinite {
        Camera { far: None, ..*camera }
    } else {
        *camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn touches_near_region(camera: &Camera, aspect: f32, light: Vec4, bounds: &Aabb, transform: Mat4) -> bool {
        NearRegion::new(&View::of_camera(camera, aspect), light).may_touch(&bounds.transformed(&transform))
    }

    #[test]
    fn casters_between_the_eye_and_the_light_need_z_fail() {
        let cam = Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO);
        let light = Vec4::new(0.0, 1.0, 15.0, 1.0); // behind the eye
        let unit = Aabb { min: Vec3::splat(-0.5), max: Vec3::splat(0.5) };
        // Right between the near plane and the light: its volume covers the eye.
        assert!(touches_near_region(&cam, 1.0, light, &unit, Mat4::from_translation(Vec3::new(0.0, 1.0, 10.0))));
        // In front of the camera, away from the light: its volume goes away from the eye.
        assert!(!touches_near_region(&cam, 1.0, light, &unit, Mat4::IDENTITY));
        // Off to the side, far from the eye–light segment.
        assert!(!touches_near_region(&cam, 1.0, light, &unit, Mat4::from_translation(Vec3::new(8.0, 1.0, 10.0))));
        // Directional light from behind the eye: anything behind the eye may shadow it.
        let dir = Vec4::new(0.0, 0.0, 1.0, 0.0);
        assert!(touches_near_region(&cam, 1.0, dir, &unit, Mat4::from_translation(Vec3::new(0.0, 1.0, 30.0))));
        assert!(!touches_near_region(&cam, 1.0, dir, &unit, Mat4::IDENTITY));
    }
}
