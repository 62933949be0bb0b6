//! Shadow volumes built on the GPU (issue #26) against the CPU reference implementation: the
//! GPU's silhouette edges equal the CPU's, edge for edge and with multiplicity, for every
//! caster and light of every hard case and for the repository's scanned and modelled meshes
//! under lights all around them (directional and point, one in the plane of a face).

mod common;

use glam::{Vec3, Vec4};
use std::sync::Arc;
use umbra::scene::{facing, silhouette_edges, Adjacency, Scene};
use umbra::shadows::shadow_volume::GpuSilhouettes;

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
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hard-cases");
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .expect("tests/hard-cases")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        files.sort();
        let (mut cases, mut jobs_total, mut edges_total) = (0, 0, 0);
        for file in &files {
            let name = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            // A case whose mesh the loader refuses (21: non-finite positions) has no volume.
            let Ok(scene) = umbra::scene::load_scene_file(file) else { continue };
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
