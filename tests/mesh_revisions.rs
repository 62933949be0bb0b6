//! Meshes edited in place: the renderer keys what it derives from a mesh (welded adjacency,
//! which shadow volumes extrude) by `Mesh::revision`, so an edit followed by `Mesh::touch`
//! is drawn exactly as a fresh renderer draws it — even a vertex in the middle of the mesh,
//! which the old cache key (counts, first and last position) did not see — and an edit that
//! changes a mesh's size without `touch` is a typed error, not a stale shadow.

mod common;

use glam::{Mat4, Vec3};
use umbra::scene::{primitives, Light, Scene, Technique};
use umbra::shadows::{RenderError, Renderer, RendererDesc};

/// A ball over a floor, lit from above by shadow volumes.
fn scene() -> Scene {
    let mut s = Scene::new("deformed ball");
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(4.0, 0.05, 4.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let ball = s.add_mesh(primitives::sphere(0.6, 24, 12));
    s.add_object(ball, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)), Vec3::splat(0.8));
    let mut light = Light::directional(Vec3::new(0.3, 1.0, 0.2), 1.0);
    light.technique = Technique::ShadowVolume;
    s.lights.push(light);
    s.camera = umbra::scene::Camera::look_at(Vec3::new(0.0, 5.0, 4.0), Vec3::ZERO);
    s
}

/// Pulls a vertex from the middle of the ball's vertex list far out: a spike in its shadow.
fn deform(s: &mut Scene) {
    let ball = &mut s.meshes[1];
    let middle = ball.positions.len() / 2;
    assert!(middle > 0 && middle + 1 < ball.positions.len());
    ball.positions[middle] *= 2.5;
}

#[test]
fn a_touched_mesh_is_drawn_as_a_fresh_renderer_draws_it() {
    common::with_context(|ctx| {
        let desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
        let mut warm = Renderer::new(ctx, desc).expect("renderer");
        let mut s = scene();
        let before = warm.render(&s).expect("frame").rgba;
        deform(&mut s);
        s.meshes[1].touch();
        let after = warm.render(&s).expect("frame").rgba;
        let mut fresh = Renderer::new(ctx, desc).expect("renderer");
        let expected = fresh.render(&s).expect("frame").rgba;
        let changed = before.chunks_exact(4).zip(expected.chunks_exact(4)).filter(|(a, b)| a != b).count();
        println!("the spike changes {changed} pixels");
        assert!(changed > 50, "the deformation must show in the shadow ({changed} pixels)");
        assert!(after == expected, "the warm renderer drew the edited mesh with stale adjacency");
    });
}

#[test]
fn a_mesh_resized_without_touch_is_a_typed_error() {
    common::with_context(|ctx| {
        let mut renderer = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).expect("renderer");
        let mut s = scene();
        renderer.render(&s).expect("frame");
        let ball = &mut s.meshes[1];
        let last = *ball.positions.last().unwrap();
        ball.positions.push(last);
        ball.normals.push(Vec3::Y);
        match renderer.render(&s) {
            Err(e @ RenderError::StaleMesh { mesh: 1, .. }) => println!("{e}"),
            other => panic!("expected StaleMesh, got {:?}", other.map(|_| "a frame")),
        }
        s.meshes[1].touch();
        renderer.render(&s).expect("after touch() the mesh renders");
    });
}

/// The meshes are uploaded once and reused while every mesh keeps its revision: the second
/// frame of an unchanged scene uploads no geometry and is the same image; a touched mesh is
/// uploaded again.
#[test]
fn unchanged_meshes_are_not_uploaded_again() {
    common::with_context(|ctx| {
        let mut renderer = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).expect("renderer");
        let mut s = scene();
        let first = renderer.render(&s).expect("frame");
        let second = renderer.render(&s).expect("frame");
        println!(
            "geometry uploaded: first frame {} bytes, second {} bytes",
            first.report.geometry_uploaded_bytes, second.report.geometry_uploaded_bytes
        );
        assert!(first.report.geometry_uploaded_bytes > 0);
        assert_eq!(second.report.geometry_uploaded_bytes, 0, "unchanged meshes were uploaded again");
        assert!(first.rgba == second.rgba, "reused geometry draws the same image");
        s.objects[1].transform = Mat4::from_translation(Vec3::new(0.3, 1.0, 0.0));
        assert_eq!(
            renderer.render(&s).expect("frame").report.geometry_uploaded_bytes,
            0,
            "a moved object is no mesh edit"
        );
        deform(&mut s);
        s.meshes[1].touch();
        let edited = renderer.render(&s).expect("frame");
        assert_eq!(edited.report.geometry_uploaded_bytes, first.report.geometry_uploaded_bytes);
        let mut fresh = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).expect("renderer");
        assert!(
            edited.rgba == fresh.render(&s).expect("frame").rgba,
            "the re-uploaded mesh is drawn as uploaded fresh"
        );
    });
}

/// `FrameReport::memory_allocations` counts the buffers and images a frame allocated: the
/// first frame allocates its maps and targets, a warm frame of the same scene fewer (the
/// geometry is reused); the figures are printed for `docs/results.md`'s before/after of the
/// GPU-resident scene.
#[test]
fn the_report_counts_the_memory_allocations_of_a_frame() {
    common::with_context(|ctx| {
        let before = ctx.memory_allocations();
        let probe = umbra::vk::Buffer::new(ctx, "counted", umbra::vk::BufferDesc::readback(64)).expect("buffer");
        assert_eq!(ctx.memory_allocations(), before + 1, "one buffer, one allocation");
        drop(probe);
        let mut renderer = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).expect("renderer");
        let s = scene();
        let frames: Vec<u64> = (0..4).map(|_| renderer.render(&s).expect("frame").report.memory_allocations).collect();
        println!("memory allocations per frame: {frames:?}");
        assert!(frames[0] > frames[3], "a warm frame allocates less than the first: {frames:?}");
        assert_eq!(frames[3], 0, "a warm frame of an unchanged scene allocates nothing: {frames:?}");
        assert!(frames[1..].windows(2).all(|w| w[0] == w[1]), "warm frames allocate alike: {frames:?}");
    });
}
