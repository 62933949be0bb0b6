//! The two-level BVH against the exact reference (`umbra-reference`, f64 over world-space
//! triangles): the same answer for shadow rays from every scene's surfaces to its lights, a
//! watertight shared edge, and moves that rebuild only the top level.

use super::{BvhLayout, BvhNode, MeshBvh, RayScene, WideNode, MAX_STACK};
use glam::{Mat4, Vec3};
use umbra_reference::SceneBvh;
use umbra_scene::{procedural, Mesh, Scene};

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Every leaf range of `nodes` in leaf order: each primitive exactly once, and every child
/// inside its parent's box.
fn check_layout(nodes: &[BvhNode], primitives: usize) {
    let mut seen = vec![0u32; primitives];
    for n in nodes {
        if n.is_leaf() {
            (n.first..n.first + n.count).for_each(|i| seen[i as usize] += 1);
        } else {
            for child in [&nodes[n.first as usize], &nodes[n.first as usize + 1]] {
                let inside = (0..3).all(|k| child.min[k] >= n.min[k] && child.max[k] <= n.max[k]);
                assert!(inside, "{child:?} outside its parent {n:?}");
            }
        }
    }
    assert!(seen.iter().all(|&c| c == 1), "a primitive is in no leaf or in two");
}

/// Shadow rays from points on the scene's casters and receivers towards each light, and random
/// rays through the scene's box: the walk and the reference agree on all but rays whose f32
/// and f64 answers may differ (grazing an edge or ending on a surface).
fn agree(scene: &Scene, rays: usize) -> (usize, usize) {
    agree_in(scene, rays, BvhLayout::Binary)
}

/// [`agree`] with the meshes' BVHs in `layout`.
fn agree_in(scene: &Scene, rays: usize, layout: BvhLayout) -> (usize, usize) {
    let reference = SceneBvh::build(scene);
    let walk = RayScene::build_with(scene, layout);
    assert!(walk.stack_need() <= MAX_STACK, "depth {}, stack {}", walk.depth, walk.stack_need());
    check_layout(&walk.top, walk.instances.len());
    let bounds = scene.bounds();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let (mut disagree, mut blocked) = (0, 0);
    for _ in 0..rays {
        let pick = |r: &mut Rng| bounds.min + (bounds.max - bounds.min) * Vec3::new(r.unit(), r.unit(), r.unit());
        let (from, to) = (pick(&mut rng), pick(&mut rng));
        let (dir, len) = ((to - from).normalize_or_zero(), (to - from).length());
        if dir == Vec3::ZERO {
            continue;
        }
        let truth = reference.occluded(from, dir, len);
        blocked += usize::from(truth);
        if walk.occluded(from, dir, len).0 != truth {
            disagree += 1;
        }
    }
    // Rays that all pass (or all stop) would test nothing.
    assert!(blocked > rays / 20 && blocked < rays - rays / 20, "{blocked} of {rays} rays blocked");
    (disagree, rays)
}

#[test]
fn walks_agree_with_the_reference_on_every_procedural_scene() {
    for layout in [BvhLayout::Binary, BvhLayout::CompressedWide] {
        for name in procedural::NAMES {
            let scene = procedural::build(name).expect("procedural scene");
            let (disagree, rays) = agree_in(&scene, 4000, layout);
            println!("{} {name}: {disagree} of {rays} rays disagree with the reference", layout.name());
            // f32 against f64: only a ray ending within rounding of a surface may differ.
            assert!(disagree <= rays / 1000, "{name}: {disagree} of {rays}");
        }
    }
}

/// The two layouts walk to the same answer for every ray (the same triangle test; the wide
/// boxes are conservative), on every procedural scene.
#[test]
fn both_layouts_give_every_ray_the_same_answer() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    for name in procedural::NAMES {
        let scene = procedural::build(name).expect("procedural scene");
        let (binary, wide) = (RayScene::build(&scene), RayScene::build_with(&scene, BvhLayout::CompressedWide));
        let bounds = scene.bounds();
        let (mut nodes, mut wide_nodes) = (0u64, 0u64);
        for _ in 0..2000 {
            let pick = |r: &mut Rng| bounds.min + (bounds.max - bounds.min) * Vec3::new(r.unit(), r.unit(), r.unit());
            let (from, to) = (pick(&mut rng), pick(&mut rng));
            let (dir, len) = ((to - from).normalize_or_zero(), (to - from).length());
            if dir == Vec3::ZERO {
                continue;
            }
            let (a, sa) = binary.occluded(from, dir, len);
            let (b, sb) = wide.occluded(from, dir, len);
            assert_eq!(a, b, "{name}: a ray from {from} to {to}");
            (nodes, wide_nodes) = (nodes + u64::from(sa.nodes), wide_nodes + u64::from(sb.nodes));
        }
        println!("{name}: nodes fetched, binary {nodes}, wide {wide_nodes}");
        assert!(wide_nodes < nodes, "{name}: the wide walk fetches fewer nodes");
    }
}

/// Every triangle in exactly one wide leaf, and inside every box (as the walk decodes it) on
/// the path from the root to its leaf: a ray that hits it enters each of them.
fn check_wide_layout(bvh: &MeshBvh) {
    let mut seen = vec![0u32; bvh.triangles.len()];
    let nodes: &[WideNode] = &bvh.wide;
    // Each node with the intersection of the boxes above it.
    let mut stack = vec![(0u32, Vec3::NEG_INFINITY, Vec3::INFINITY)];
    while let Some((i, above_lo, above_hi)) = stack.pop() {
        let n = &nodes[i as usize];
        for slot in (0..8).filter(|&s| n.meta(s) != 0) {
            let (lo, hi) = n.child_box(slot);
            let (lo, hi) = (lo.max(above_lo), hi.min(above_hi));
            if n.is_inner(slot) {
                stack.push((n.child(slot), lo, hi));
                continue;
            }
            let (first, count) = n.triangles(slot);
            for t in first..first + count {
                seen[t as usize] += 1;
                let tri = &bvh.triangles[t as usize];
                let inside = |p: Vec3| p.cmpge(lo).all() && p.cmple(hi).all();
                assert!((0..3).all(|k| inside(tri.vertex(k))), "triangle {t} outside a box above it");
            }
        }
    }
    assert!(seen.iter().all(|&c| c == 1), "a triangle is in no leaf or in two");
}

#[test]
fn mesh_layouts_hold_every_triangle_once() {
    for name in ["cubes", "tree"] {
        let scene = procedural::build(name).expect("procedural scene");
        let walk = RayScene::build(&scene);
        let mut node = 0;
        for mesh in &scene.meshes {
            let bvh = MeshBvh::build(mesh, BvhLayout::Binary);
            check_layout(&bvh.nodes, bvh.triangles.len());
            let wide = MeshBvh::build(mesh, BvhLayout::CompressedWide);
            check_wide_layout(&wide);
            assert_eq!(wide.triangles.len(), bvh.triangles.len());
            assert!(
                wide.wide.len() <= bvh.nodes.len().div_ceil(4),
                "{} wide nodes for {} binary",
                wide.wide.len(),
                bvh.nodes.len()
            );
            assert_eq!(bvh.triangles.len(), mesh.indices.len() / 3);
            assert_eq!(&walk.nodes[node..node + bvh.nodes.len()], &bvh.nodes[..]);
            node += bvh.nodes.len();
        }
    }
}

#[test]
fn a_ray_through_a_shared_edge_always_hits() {
    let mut scene = Scene::new("quad");
    let positions =
        [Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, -1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(-1.0, 0.0, 1.0)];
    let mesh = scene.add_mesh(Mesh::with_flat_normals("quad", &positions, &[0, 2, 1, 0, 3, 2]).expect("quad"));
    // Rotated and moved, so the ray meets the diagonal in the mesh's space after a transform.
    let transform = Mat4::from_translation(Vec3::new(0.5, 1.0, -0.25)) * Mat4::from_rotation_y(0.3);
    scene.add_object(mesh, transform, Vec3::ONE);
    let walk = RayScene::build(&scene);
    for i in 1..400 {
        let s = -1.0 + 2.0 * i as f32 / 400.0;
        let on_diagonal = transform.transform_point3(Vec3::new(s, 0.0, s));
        let origin = on_diagonal + Vec3::new(0.0, 3.0, 0.0);
        assert!(walk.occluded(origin, -Vec3::Y, 10.0).0, "the ray at {s} passed between the triangles");
    }
    let beside = transform.transform_point3(Vec3::new(1.01, 0.0, 0.0)) + Vec3::Y;
    assert!(!walk.occluded(beside, -Vec3::Y, 10.0).0);
    let above = transform.transform_point3(Vec3::ZERO) + Vec3::new(0.0, 3.0, 0.0);
    assert!(!walk.occluded(above, -Vec3::Y, 2.9).0, "t_max must stop the ray");
}

#[test]
fn moving_an_object_rebuilds_the_top_level_only() {
    let mut scene = procedural::build("cubes").expect("cubes");
    let mut walk = RayScene::build(&scene);
    let meshes = walk.stats.mesh_builds;
    assert_eq!(meshes as usize, scene.meshes.len());
    for frame in 1..=10 {
        let o = &mut scene.objects[1];
        o.transform = Mat4::from_translation(Vec3::new(0.05 * frame as f32, 0.0, 0.0)) * o.transform;
        walk.update(&scene);
        assert_eq!(walk.stats.mesh_builds, meshes, "frame {frame} rebuilt a mesh");
        assert_eq!(walk.stats.top_builds, 1 + frame);
        let (disagree, rays) = agree(&scene, 500);
        assert!(disagree <= rays / 100, "frame {frame}: {disagree} of {rays}");
    }
    walk.update(&scene);
    assert_eq!(walk.stats.top_builds, 11, "nothing moved: nothing is built");
    let revision = walk.revision;
    scene.meshes[0].touch();
    walk.update(&scene);
    assert!(walk.revision > revision);
    assert_eq!(walk.stats.mesh_builds, meshes + 1, "a touched mesh is built again");
}

#[test]
fn non_casters_are_not_in_the_scene() {
    let mut scene = procedural::build("cubes").expect("cubes");
    let casters = scene.objects.iter().filter(|o| o.casts_shadows).count();
    assert_eq!(RayScene::build(&scene).instances.len(), casters);
    scene.objects.iter_mut().for_each(|o| o.casts_shadows = false);
    let walk = RayScene::build(&scene);
    assert!(walk.instances.is_empty() && walk.top.is_empty());
    assert!(!walk.occluded(Vec3::new(0.0, 10.0, 0.0), -Vec3::Y, 100.0).0);
}
