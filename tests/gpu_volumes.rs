//! Shadow volumes built on the GPU (issue #26) against the CPU reference implementation: the
//! GPU's silhouette edges equal the CPU's, edge for edge and with multiplicity, for every
//! caster and light of every hard case and for the repository's scanned and modelled meshes
//! under lights all around them (directional and point, one in the plane of a face); and the
//! renderer's frames with volumes built on the GPU equal the CPU path's: images, overdraw, and
//! the report's counts and counting modes (decided on the GPU in auto mode), caster for caster.

mod common;

use glam::{Vec3, Vec4};
use std::sync::Arc;
use umbra::scene::{facing, silhouette_edges, Adjacency, Scene, Technique};
use umbra::shadows::shadow_volume::GpuSilhouettes;
use umbra::shadows::{Frame, HostClip, MaskKind, PassId, Renderer, RendererDesc, VolumeBuild, VolumeMode};

/// `edges` sorted, so that two lists of directed edges with multiplicity compare as multisets.
fn sorted(mut edges: Vec<[u32; 2]>) -> Vec<[u32; 2]> {
    edges.sort_unstable();
    edges
}

/// Every job's GPU edges against the CPU's; returns the jobs and edges compared.
fn compare(ctx: &umbra::vk::Context, meshes: &[Arc<Adjacency>], jobs: &[(usize, Vec4)], what: &str) -> (usize, usize) {
    let gpu = GpuSilhouettes::new(ctx).expect("pipelines");
    let found = gpu.find(ctx, meshes, jobs).expect("GPU silhouettes");
    assert_eq!(found.len(), jobs.len());
    let mut edges = 0;
    for (k, (&(mesh, light), gpu_edges)) in jobs.iter().zip(found).enumerate() {
        let adj = &meshes[mesh];
        let cpu = silhouette_edges(adj, &facing(adj, light));
        edges += cpu.len();
        assert_eq!(sorted(gpu_edges), sorted(cpu), "{what}: job {k} (mesh {mesh}, light {light})");
    }
    (jobs.len(), edges)
}

/// Every (caster, light) pair of `scene`, with the light in the caster's object space as the
/// CPU builder computes it.
fn scene_jobs(scene: &Scene) -> (Vec<Arc<Adjacency>>, Vec<(usize, Vec4)>) {
    let meshes: Vec<Arc<Adjacency>> = scene.meshes.iter().map(|m| Arc::new(Adjacency::build(m))).collect();
    let mut jobs = Vec::new();
    for o in scene.objects.iter().filter(|o| o.casts_shadows) {
        for l in &scene.lights {
            jobs.push((o.mesh, o.transform.inverse() * l.position));
        }
    }
    (meshes, jobs)
}

#[test]
fn gpu_silhouettes_equal_the_cpu_ones_in_every_hard_case() {
    common::with_context(|ctx| {
        let (mut cases, mut jobs_total, mut edges_total) = (0, 0, 0);
        for (name, scene) in hard_case_scenes() {
            let (meshes, jobs) = scene_jobs(&scene);
            let (j, e) = compare(ctx, &meshes, &jobs, &name);
            cases += 1;
            jobs_total += j;
            edges_total += e;
        }
        println!("{cases} hard cases: {jobs_total} caster-light pairs, {edges_total} silhouette edges, GPU = CPU");
        assert!(cases >= 25 && edges_total > 0, "{cases} cases, {edges_total} edges");
    });
}

#[test]
fn gpu_silhouettes_equal_the_cpu_ones_on_the_assets_under_lights_all_around() {
    common::with_context(|ctx| {
        let mut meshes = Vec::new();
        for file in ["stanford-bunny.glb", "suzanne.glb", "teapot.glb", "spot.glb", "fandisk.glb"] {
            let imported = umbra::scene::import_gltf(&common::assets().join(file)).expect("asset");
            meshes.extend(imported.meshes.iter().map(|m| Arc::new(Adjacency::build(m))));
        }
        let mut jobs = Vec::new();
        for (i, adj) in meshes.iter().enumerate() {
            let (lo, hi) = adj.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
            let (centre, radius) = ((lo + hi) * 0.5, (hi - lo).length());
            for k in 0..12 {
                let angle = k as f32 * 0.55;
                let dir = Vec3::new(angle.cos(), 0.6 - 0.1 * k as f32, angle.sin()).normalize();
                jobs.push((i, (centre + dir * 2.0 * radius).extend(1.0)));
                jobs.push((i, dir.extend(0.0)));
            }
            // A light in the plane of the mesh's first face (hard case 06's situation).
            if let Some(t) = adj.triangles.iter().find(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
                let [a, b, _] = t.map(|v| adj.positions[v as usize]);
                jobs.push((i, (a + (b - a) * 4.0).extend(1.0)));
            }
        }
        let (j, e) = compare(ctx, &meshes, &jobs, "assets");
        let triangles: usize = meshes.iter().map(|m| m.triangles.len()).sum();
        println!(
            "{} meshes ({triangles} triangles), {j} mesh-light pairs: {e} silhouette edges, GPU = CPU",
            meshes.len()
        );
    });
}

/// What the image test renders each scene with: shadow volumes in a counting mode, or the
/// hybrid (z-fail volumes behind its computation mask) with a mask (`None`: the device's best)
/// and blocker culling on or off.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Variant {
    Volumes(VolumeMode),
    Hybrid { mask: Option<MaskKind>, cull_blockers: bool },
}

/// Every variant the image test renders.
const VARIANTS: [Variant; 4] = [
    Variant::Volumes(VolumeMode::Auto),
    Variant::Volumes(VolumeMode::ZFail),
    Variant::Hybrid { mask: None, cull_blockers: false },
    Variant::Hybrid { mask: Some(MaskKind::Stencil), cull_blockers: true },
];

/// `scene` with every light's technique that of `variant`, rendered with volumes built on
/// `build` (host clipping off on both paths: the GPU path draws unclipped, and so must the path
/// it is compared with), with the overdraw diagnostic.
fn render(ctx: &umbra::vk::Context, scene: &Scene, build: VolumeBuild, variant: Variant) -> Frame {
    let mut desc = RendererDesc::new(256, 192);
    desc.read_visibility = true;
    desc.shadow_volume.overdraw = true;
    desc.shadow_volume.build = build;
    desc.shadow_volume.host_clip = HostClip::Never;
    let technique = match variant {
        Variant::Volumes(mode) => {
            desc.shadow_volume.mode = mode;
            Technique::ShadowVolume
        }
        Variant::Hybrid { mask, cull_blockers } => {
            desc.hybrid.mask = mask;
            desc.hybrid.cull_blockers = cull_blockers;
            Technique::Hybrid
        }
    };
    let mut r = Renderer::new(ctx, desc).expect("renderer");
    let mut s = scene.clone();
    for l in &mut s.lights {
        l.technique = technique;
    }
    r.render(&s).expect("frame")
}

/// The hard cases the loader takes, by file name, sorted (a case whose mesh it refuses, 21:
/// non-finite positions, has no volume).
fn hard_case_scenes() -> Vec<(String, Scene)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hard-cases");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/hard-cases")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .filter_map(|f| Some((f.file_name()?.to_string_lossy().into_owned(), umbra::scene::load_scene_file(f).ok()?)))
        .collect()
}

/// The hard cases and the suite's procedural scenes, by name.
fn image_scenes() -> Vec<(String, Scene)> {
    let mut out = hard_case_scenes();
    for name in ["cubes", "cage", "tree", "pins"] {
        out.push((name.into(), umbra::scene::load(name).expect("procedural scene")));
    }
    out
}

#[test]
fn volumes_built_on_the_gpu_give_the_cpu_paths_images_bit_for_bit() {
    common::with_context(|ctx| {
        let (mut scenes, mut lights, mut counted, mut modes, mut fragment_lights) = (0, 0, 0, [0; 2], 0);
        for (name, scene) in image_scenes() {
            for variant in VARIANTS {
                let cpu = render(ctx, &scene, VolumeBuild::Cpu, variant);
                let gpu = render(ctx, &scene, VolumeBuild::Gpu, variant);
                assert_eq!(cpu.visibility.len(), gpu.visibility.len(), "{name}");
                for (c, g) in cpu.visibility.iter().zip(&gpu.visibility) {
                    let differ = c
                        .texels
                        .iter()
                        .zip(&g.texels)
                        .filter(|(a, b)| a[0].to_bits() != b[0].to_bits() || a[1].to_bits() != b[1].to_bits())
                        .count();
                    assert_eq!(differ, 0, "{name} {variant:?}: light {}: {differ} visibility texels differ", c.light);
                }
                assert!(cpu.rgba == gpu.rgba, "{name} {variant:?}: the colour images differ");
                assert!(cpu.overdraw == gpu.overdraw, "{name} {variant:?}: the overdraw images differ");
                // The counts read back from the GPU are the CPU path's, caster for caster, and
                // so are the volume fragments the overdraw diagnostic counts.
                for (c, g) in cpu.report.lights.iter().zip(&gpu.report.lights) {
                    let fragments = |h: &Option<umbra::shadows::HybridReport>| {
                        h.as_ref().map(|h| (h.volume_fragments, h.masked_volume_fragments))
                    };
                    assert_eq!(fragments(&c.hybrid), fragments(&g.hybrid), "{name} {variant:?}: hybrid fragments");
                    fragment_lights +=
                        usize::from(g.shadow_volume.as_ref().is_some_and(|v| v.volume_fragments > Some(0)));
                    let (Some(c), Some(g)) = (&c.shadow_volume, &g.shadow_volume) else {
                        assert_eq!(c.shadow_volume.is_some(), g.shadow_volume.is_some(), "{name} {variant:?}");
                        continue;
                    };
                    let figures = |v: &umbra::shadows::ShadowVolumeReport| {
                        let modes: Vec<_> = v.caster_modes.iter().map(|m| (m.object, m.mode, m.triangles)).collect();
                        let counts = (v.casters, v.zpass_casters, v.zfail_casters, v.silhouette_edges);
                        (counts, v.volume_triangles, v.volume_fragments, modes)
                    };
                    assert_eq!(figures(c), figures(g), "{name} {variant:?}: the reports' counts differ");
                    counted += g.volume_triangles;
                    if variant == Variant::Volumes(VolumeMode::Auto) {
                        modes[0] += g.zpass_casters;
                        modes[1] += g.zfail_casters;
                    }
                }
                // The GPU path ran its stages, and reports that it built the volumes.
                let ran = |id: fn(usize) -> PassId| gpu.report.passes.iter().any(|p| (0..8).any(|l| p.id == id(l)));
                let volumes =
                    gpu.report.lights.iter().filter_map(|l| l.shadow_volume.as_ref()).filter(|v| v.casters > 0);
                if volumes.clone().next().is_some() {
                    assert!(ran(PassId::VolumeClassify) && ran(PassId::VolumeSilhouettes), "{name}");
                    assert!(volumes.clone().all(|v| v.gpu_built), "{name}");
                }
            }
            scenes += 1;
            lights += scene.lights.len();
        }
        println!(
            "{scenes} scenes ({lights} lights), shadow volumes in auto and z-fail and the hybrid (the device's \
             mask; the stencil mask with blocker culling): volumes built on the GPU, images identical; \
             {counted} volume triangles counted on the GPU, as on the CPU; in auto mode the GPU chose \
             z-pass for {} casters and z-fail for {}, as the CPU path did; overdraw images and volume \
             fragments equal ({fragment_lights} lights with fragments)",
            modes[0], modes[1]
        );
        assert!(fragment_lights > 0, "no volume fragment counted");
        assert!(counted > 0, "no volume triangle counted");
        assert!(modes.iter().all(|&m| m > 0), "auto mode should meet both modes: {modes:?}");
    });
}
