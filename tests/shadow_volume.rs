//! Robust stenciled shadow volumes against an exact CPU reference (ray casting the scene's
//! triangles), on closed meshes and in the hard cases of Everitt–Kilgard.

mod common;

use common::exact::Reference;
use glam::{Mat4, Vec3, Vec4};
use umbra::scene::{primitives, Camera, Light, Scene, Technique};
use umbra::shadows::{FarPlane, Frame, PassId, Renderer, RendererDesc, ShadowVolumeSettings, VolumeMode};
use umbra::vk::Context;

fn render(ctx: &Context, scene: &Scene, mode: VolumeMode, far_plane: FarPlane) -> (Frame, Frame) {
    let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
    desc.shadow_volume = ShadowVolumeSettings { mode, far_plane, ..ShadowVolumeSettings::default() };
    let mut r = Renderer::new(ctx, desc).unwrap();
    let mut s = scene.clone();
    for l in &mut s.lights {
        l.technique = Technique::ShadowVolume;
    }
    let shadowed = r.render(&s).unwrap();
    for l in &mut s.lights {
        l.technique = Technique::Unshadowed;
    }
    let plain = r.render(&s).unwrap();
    (shadowed, plain)
}

/// (pixels compared, of which shadowed, wrong) for a frame against the reference.
fn compare(scene: &Scene, reference: &Reference, shadowed: &Frame, plain: &Frame) -> (usize, usize, usize) {
    let (compared, in_shadow, wrong) = compare_pixels(scene, reference, shadowed, plain);
    (compared, in_shadow, wrong.len())
}

/// (pixels compared, of which shadowed, the wrong pixels).
fn compare_pixels(
    scene: &Scene,
    reference: &Reference,
    shadowed: &Frame,
    plain: &Frame,
) -> (usize, usize, Vec<(u32, u32)>) {
    let (w, h) = common::SIZE;
    // The renderer used P_inf, but the rays are the same for any far plane.
    let vp = scene.camera.view_proj(w as f32 / h as f32);
    let (mut compared, mut in_shadow, mut wrong) = (0, 0, Vec::new());
    for y in 0..h {
        for x in 0..w {
            let Some(expected) = reference.pixel(vp, w, h, x, y) else { continue };
            let lit_value = plain.pixel(x, y).iter().take(3).copied().max().unwrap_or(0);
            if lit_value < 8 {
                continue; // too dim to tell lit from shadowed
            }
            let value = shadowed.pixel(x, y).iter().take(3).copied().max().unwrap_or(0);
            let rendered = u16::from(value) + 3 < u16::from(lit_value);
            compared += 1;
            in_shadow += usize::from(expected);
            if rendered != expected {
                wrong.push((x, y));
                if wrong.len() <= 5 {
                    println!("  wrong pixel ({x},{y}): expected shadowed={expected}, value {value} of lit {lit_value}");
                }
            }
        }
    }
    (compared, in_shadow, wrong)
}

fn no_ambient(mut s: Scene) -> Scene {
    s.ambient = Vec3::ZERO;
    s
}

/// A shared asset standing on a floor under a point light.
fn asset_scene(file: &str) -> Scene {
    let imported = umbra::scene::import_gltf(&common::assets().join(file)).unwrap();
    let mut s = Scene::new(file);
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(5.0, 0.05, 5.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let mesh = imported.meshes[0].clone();
    let b = mesh.bounds();
    let scale = 2.0 / (b.max - b.min).max_element();
    let lift = Vec3::new(-b.center().x * scale, -b.min.y * scale + 0.3, -b.center().z * scale);
    let id = s.add_mesh(mesh);
    s.add_object(id, Mat4::from_translation(lift) * Mat4::from_scale(Vec3::splat(scale)), Vec3::new(0.8, 0.6, 0.4));
    s.lights.push(Light::point(Vec3::new(2.0, 5.0, 1.5), 30.0));
    s.camera = Camera::look_at(Vec3::new(-3.0, 3.0, 4.0), Vec3::new(0.0, 0.8, 0.0));
    s
}

#[test]
fn closed_meshes_match_the_exact_reference_outside_the_half_pixel_band() {
    let scenes = [
        no_ambient(umbra::scene::load("cubes").unwrap()),
        no_ambient(asset_scene("spot.glb")),
        no_ambient(asset_scene("fandisk.glb")),
    ];
    common::with_context(|ctx| {
        let mut failures = Vec::new();
        for scene in &scenes {
            let reference = Reference::new(scene);
            let clamp = ctx.capabilities().depth_clamp;
            let variants = [
                (VolumeMode::ZFail, FarPlane::Infinite),
                (VolumeMode::Auto, FarPlane::Infinite),
                (VolumeMode::ZFail, FarPlane::DepthClamp),
            ];
            for (mode, far_plane) in variants.into_iter().filter(|v| clamp || v.1 == FarPlane::Infinite) {
                let (shadowed, plain) = render(ctx, scene, mode, far_plane);
                let (compared, in_shadow, wrong) = compare(scene, &reference, &shadowed, &plain);
                let v = shadowed.report.lights[0].shadow_volume.as_ref().unwrap();
                println!(
                    "{} {} {far_plane:?}: {compared} pixels compared, {in_shadow} in shadow, {wrong} wrong ({} z-pass / {} z-fail casters, {} silhouette edges)",
                    scene.name,
                    mode.name(),
                    v.zpass_casters,
                    v.zfail_casters,
                    v.silhouette_edges
                );
                let file = format!("{}-{}-{far_plane:?}.png", scene.name.replace('.', "_"), mode.name());
                shadowed.save_png(&common::output_dir("shadow_volume").join(file)).unwrap();
                assert!(compared > 5_000 && in_shadow > 300, "{}: too little to compare", scene.name);
                if wrong != 0 {
                    failures.push(format!(
                        "{} ({} {far_plane:?}): {wrong} pixels disagree with the exact reference",
                        scene.name,
                        mode.name()
                    ));
                }
            }
        }
        assert!(failures.is_empty(), "{failures:?}");
    });
}

/// A slab above the floor under a point light, and the eye under the slab, inside its shadow
/// volume, looking out at the floor.
fn eye_in_shadow_scene() -> Scene {
    let mut s = Scene::new("eye in shadow");
    s.ambient = Vec3::ZERO;
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(8.0, 0.05, 8.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let slab = s.add_mesh(primitives::cuboid(Vec3::new(1.5, 0.1, 1.5)));
    s.add_object(slab, Mat4::from_translation(Vec3::new(0.0, 2.5, 0.0)), Vec3::splat(0.5));
    s.lights.push(Light::point(Vec3::new(0.0, 6.0, 0.0), 40.0));
    s.camera = Camera { near: 0.05, ..Camera::look_at(Vec3::new(0.2, 1.0, 0.1), Vec3::new(4.0, 0.0, 3.0)) };
    s
}

#[test]
fn eye_inside_a_volume_is_exact_with_z_fail_and_auto_and_wrong_with_z_pass() {
    let scene = eye_in_shadow_scene();
    let reference = Reference::new(&scene);
    common::with_context(|ctx| {
        for (mode, exact) in [(VolumeMode::ZFail, true), (VolumeMode::Auto, true), (VolumeMode::ZPass, false)] {
            let (shadowed, plain) = render(ctx, &scene, mode, FarPlane::Infinite);
            let (compared, in_shadow, wrong) = compare(&scene, &reference, &shadowed, &plain);
            println!("eye in shadow, {}: {compared} compared, {in_shadow} in shadow, {wrong} wrong", mode.name());
            shadowed
                .save_png(&common::output_dir("shadow_volume").join(format!("eye-in-shadow-{}.png", mode.name())))
                .unwrap();
            assert!(compared > 5_000 && in_shadow > 1_000, "the view must hold shadow and light");
            if exact {
                assert_eq!(wrong, 0, "{}: the eye inside a volume must not break the count", mode.name());
            } else {
                assert!(wrong > 1_000, "z-pass should invert the shadow here (this case must exercise the problem)");
            }
        }
    });
}

#[test]
fn depth_clamp_gives_the_same_shadows_as_the_far_plane_at_infinity() {
    let scene = eye_in_shadow_scene();
    let reference = Reference::new(&scene);
    common::with_context(|ctx| {
        if !ctx.capabilities().depth_clamp {
            println!("SKIPPED on {}: no depthClamp", ctx.capabilities().device_name);
            return;
        }
        let (shadowed, plain) = render(ctx, &scene, VolumeMode::ZFail, FarPlane::DepthClamp);
        let (compared, in_shadow, wrong) = compare(&scene, &reference, &shadowed, &plain);
        println!("depth clamp, z-fail: {compared} compared, {in_shadow} in shadow, {wrong} wrong");
        assert!(compared > 5_000 && in_shadow > 1_000);
        assert_eq!(wrong, 0);
    });
}

/// Renders `scene` in z-fail and auto and checks both against the exact reference.
fn exact_in_zfail_and_auto(ctx: &Context, scene: &Scene, min_shadow: usize) {
    let reference = Reference::new(scene);
    for mode in [VolumeMode::ZFail, VolumeMode::Auto] {
        let (shadowed, plain) = render(ctx, scene, mode, FarPlane::Infinite);
        let (compared, in_shadow, wrong) = compare(scene, &reference, &shadowed, &plain);
        let v = shadowed.report.lights[0].shadow_volume.as_ref().unwrap();
        println!(
            "{} {}: {compared} compared, {in_shadow} in shadow, {wrong} wrong ({} z-pass / {} z-fail casters)",
            scene.name,
            mode.name(),
            v.zpass_casters,
            v.zfail_casters
        );
        let file = format!("{}-{}.png", scene.name.replace([' ', '.'], "_"), mode.name());
        shadowed.save_png(&common::output_dir("shadow_volume").join(file)).unwrap();
        assert!(compared > 3_000 && in_shadow >= min_shadow, "{}: too little to compare", scene.name);
        assert_eq!(wrong, 0, "{} ({}): pixels disagree with the exact reference", scene.name, mode.name());
    }
}

#[test]
fn open_and_non_manifold_meshes_render_without_cracks_or_leaks() {
    common::with_context(|ctx| {
        for file in ["teapot.glb", "stanford-bunny.glb", "suzanne.glb"] {
            let scene = no_ambient(asset_scene(file));
            let adj = umbra::scene::Adjacency::build(&scene.meshes[1]);
            println!("{file}: {:?}", adj.report);
            assert!(!adj.report.closed);
            exact_in_zfail_and_auto(ctx, &scene, 300);
        }
    });
}

#[test]
fn hard_cases_near_plane_open_box_directional_light_and_a_light_touching_a_surface() {
    common::with_context(|ctx| {
        // The near plane cuts a volume's side: the eye sits on the slab's shadow boundary.
        let mut near_cut = eye_in_shadow_scene();
        near_cut.name = "near plane cuts a volume".into();
        let side_x = 1.5 * (6.0 - 1.0) / (6.0 - 2.4);
        near_cut.camera =
            Camera { near: 0.05, ..Camera::look_at(Vec3::new(side_x, 1.0, 0.0), Vec3::new(side_x + 0.5, 0.0, 4.0)) };
        exact_in_zfail_and_auto(ctx, &near_cut, 1_000);

        // Everitt–Kilgard Fig. 2: a point light inside an open box (no lid), a cube inside.
        let mut open_box = Scene::new("light inside an open box");
        open_box.ambient = Vec3::ZERO;
        let floor = open_box.add_mesh(primitives::cuboid(Vec3::new(6.0, 0.05, 6.0)));
        open_box.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
        let mut walls = primitives::cuboid(Vec3::new(1.5, 1.0, 1.5));
        let lid: Vec<u32> = walls
            .indices
            .chunks_exact(3)
            .filter(|t| walls.normals[t[0] as usize].y < 0.5)
            .flat_map(|t| t.to_vec())
            .collect();
        walls.indices = lid;
        let walls = open_box.add_mesh(walls);
        open_box.add_object(walls, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)), Vec3::splat(0.7));
        let cube = open_box.add_mesh(primitives::cuboid(Vec3::splat(0.3)));
        open_box.add_object(cube, Mat4::from_translation(Vec3::new(0.6, 0.3, 0.4)), Vec3::new(0.8, 0.4, 0.3));
        open_box.lights.push(Light::point(Vec3::new(-0.3, 1.2, -0.2), 20.0));
        open_box.camera = Camera::look_at(Vec3::new(2.5, 4.5, 3.5), Vec3::new(0.0, 0.5, 0.0));
        exact_in_zfail_and_auto(ctx, &open_box, 1_000);

        // A directional light (w = 0: every far vertex is the same point at infinity).
        let mut directional = eye_in_shadow_scene();
        directional.name = "directional light".into();
        directional.lights = vec![Light::directional(Vec3::new(0.4, 1.0, 0.3), 1.0)];
        directional.camera = Camera::look_at(Vec3::new(-4.0, 4.0, 5.0), Vec3::new(0.0, 0.5, 0.0));
        exact_in_zfail_and_auto(ctx, &directional, 1_000);

        // A point light 1e-4 above the slab's top face (y = 2.6).
        let mut touching = eye_in_shadow_scene();
        touching.name = "light touching a surface".into();
        touching.lights = vec![Light::point(Vec3::new(0.3, 2.6 + 1e-4, 0.2), 20.0)];
        touching.camera = Camera::look_at(Vec3::new(-4.0, 4.5, 5.0), Vec3::new(0.0, 1.0, 0.0));
        exact_in_zfail_and_auto(ctx, &touching, 1_000);
    });
}

#[test]
fn three_hundred_overlapping_volumes_count_past_255() {
    // 300 thin slabs stacked under a directional light from straight above: their shadows
    // coincide, so a floor pixel in shadow lies in all 300 volumes, past the 8-bit stencil.
    // Their bounds (1 each, convex) sum past 255, so they are counted in batches of 127 folded
    // into the stencil's top bit (docs/techniques/shadow-volumes.md; hard cases 24 and 25 take
    // exactly 256 and 512, which 8-bit wrap ops alone would read as lit).
    let mut s = Scene::new("300 volumes");
    s.ambient = Vec3::ZERO;
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(6.0, 0.05, 6.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::splat(0.8));
    let slab = s.add_mesh(primitives::cuboid(Vec3::new(1.0, 0.002, 1.0)));
    for i in 0..300 {
        let y = 1.0 + i as f32 * 0.005;
        s.add_object(slab, Mat4::from_translation(Vec3::new(0.0, y, 0.0)), Vec3::splat(0.5));
    }
    s.lights.push(Light::directional(Vec3::Y, 1.0));
    s.camera = Camera::look_at(Vec3::new(-2.5, 0.6, 3.5), Vec3::new(0.3, 0.0, 0.0));
    common::with_context(|ctx| {
        exact_in_zfail_and_auto(ctx, &s, 1_000);
    });
}

/// Clip-space triangles (`vec4` positions, passed through) drawn into the device's
/// depth/stencil format, both faces.
fn clip_triangles_desc(ctx: &Context, name: &'static str) -> umbra::vk::GraphicsPipelineDesc<'static> {
    use umbra::vk::{vk, GraphicsPipelineDesc, VertexAttribute};
    const ATTRIBUTES: [VertexAttribute; 1] =
        [VertexAttribute { location: 0, format: vk::Format::R32G32B32A32_SFLOAT, offset: 0 }];
    let mut desc = GraphicsPipelineDesc::new(name, umbra::shaders::debug::CLIP_PASSTHROUGH_VERT);
    desc.vertex_stride = 16;
    desc.vertex_attributes = &ATTRIBUTES;
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth_format = ctx.capabilities().depth_stencil_format;
    desc
}

/// Rasterizes `triangles` (clip-space) with two-sided stencil counting (+1 front, −1 back,
/// wrap) and no depth test, and returns how many pixels end at a nonzero count. A closed
/// surface must leave every pixel at 0.
fn nonzero_after_counting(ctx: &Context, triangles: &[Vec4], w: u32, h: u32) -> u64 {
    use umbra::vk::{vk, Buffer, DepthState, GraphicsPipeline, PipelineLayout, StencilFace};
    let target = common::depth_target(ctx, "count", w, h, vk::ImageUsageFlags::empty());
    let layout = PipelineLayout::new(ctx, "empty", &[], 0).unwrap();
    let mut desc = clip_triangles_desc(ctx, "count");
    desc.depth = DepthState::NONE;
    let op = |o: vk::StencilOp| StencilFace { pass: o, ..StencilFace::KEEP };
    desc.stencil = Some((op(vk::StencilOp::INCREMENT_AND_WRAP), op(vk::StencilOp::DECREMENT_AND_WRAP)));
    let count = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
    let probe = common::StencilProbe::new(ctx, &layout, vk::CompareOp::NOT_EQUAL);
    let bytes: &[u8] = umbra::vk::bytemuck::cast_slice(triangles);
    let vertices = Buffer::with_data(ctx, "clip triangles", vk::BufferUsageFlags::VERTEX_BUFFER, bytes).unwrap();
    let mut rec = ctx.begin_commands("watertight").unwrap();
    probe.reset(&mut rec);
    common::begin_depth_pass(&mut rec, &target);
    rec.bind_pipeline(&count);
    rec.set_stencil_reference(0);
    rec.bind_vertex_buffer(&vertices);
    rec.draw(triangles.len() as u32);
    probe.record(&mut rec);
    rec.end_rendering();
    ctx.submit_and_wait(rec).unwrap();
    probe.pixels()
}

/// The closed-mesh scenes the watertightness tests use: cubes, the cow, the fandisk.
fn watertight_scenes() -> [Scene; 3] {
    [umbra::scene::load("cubes").unwrap(), asset_scene("spot.glb"), asset_scene("fandisk.glb")]
}

/// Every caster's volume in `scene`, extruded on the CPU (the vertex shader's formula) and seen
/// by the scene's camera with P_inf: clip-space triangles.
fn volume_clip_triangles(scene: &Scene, (w, h): (u32, u32)) -> Vec<Vec4> {
    let camera = Camera { far: None, ..scene.camera };
    let vp = camera.view_proj(w as f32 / h as f32);
    let light = scene.lights[0].position;
    let mut clip = Vec::new();
    for o in scene.objects.iter().filter(|o| o.casts_shadows) {
        let adj = umbra::scene::Adjacency::build(&scene.meshes[o.mesh]);
        let local = o.transform.inverse() * light;
        let volume = umbra::scene::Volume::build(&adj, local);
        for v in volume.vertices(&adj, true) {
            let world = o.transform * v.truncate().extend(1.0);
            let world = if v.w == 0.0 { umbra::scene::extrude(world.truncate(), light) } else { world };
            clip.push(vp * world);
        }
    }
    clip
}

#[test]
fn closed_volumes_rasterize_watertight() {
    // Every pixel must count 0 where the driver's clipper is watertight. The volumes are drawn
    // as built, not clipped on the host: on SwiftShader (`Capabilities::watertight_clipping`
    // false) this measures its clipper, which leaves a few lone pixels counted an odd way
    // (at most 0.05 % of the image here) — what `HostClip` works around.
    common::with_context(|ctx| {
        let (w, h) = common::SIZE;
        for scene in &watertight_scenes() {
            let camera = Camera { far: None, ..scene.camera };
            let vp = camera.view_proj(w as f32 / h as f32);
            let clip = volume_clip_triangles(scene, (w, h));
            let nonzero = nonzero_after_counting(ctx, &clip, w, h) as usize;
            println!("{}: {} volume triangles, {nonzero} pixels with a nonzero count", scene.name, clip.len() / 3);
            // The casters' own closed meshes (small triangles in view, nothing to clip): the
            // same counting must be exact on every driver.
            let mesh_clip: Vec<Vec4> = scene
                .objects
                .iter()
                .filter(|o| o.casts_shadows)
                .flat_map(|o| {
                    let m = &scene.meshes[o.mesh];
                    m.indices.iter().map(move |&i| vp * (o.transform * m.positions[i as usize].extend(1.0)))
                })
                .collect();
            let mesh_nonzero = nonzero_after_counting(ctx, &mesh_clip, w, h);
            println!("{}: the casters' meshes alone, {mesh_nonzero} pixels with a nonzero count", scene.name);
            assert_eq!(mesh_nonzero, 0, "{}: closed meshes in view must rasterize watertight", scene.name);
            if !ctx.capabilities().watertight_clipping && nonzero <= (w * h) as usize / 2_000 {
                // The z-fail sparkles' cause, isolated: the same closed clip-space triangles, no
                // depth test, and the driver leaves a few pixels counted an odd way.
                println!("  KNOWN SWIFTSHADER ISSUE: closed geometry does not rasterize watertight here");
            } else {
                assert_eq!(nonzero, 0, "{}: the closed volumes must rasterize watertight", scene.name);
            }
        }
    });
}

/// Per triangle of `triangles`, how many samples of pixel (x, y) it covers front-facing and
/// back-facing: an occlusion query per triangle and face, under a one-pixel scissor.
fn coverage_at(ctx: &Context, triangles: &[Vec4], (w, h): (u32, u32), (x, y): (u32, u32)) -> Vec<(u64, u64)> {
    use umbra::vk::{vk, Buffer, DepthState, GraphicsPipeline, PipelineLayout, QueryKind, QueryPool};
    let target = common::depth_target(ctx, "coverage", w, h, vk::ImageUsageFlags::empty());
    let layout = PipelineLayout::new(ctx, "empty", &[], 0).unwrap();
    let mut desc = clip_triangles_desc(ctx, "front faces");
    desc.cull = vk::CullModeFlags::BACK;
    // A depth test that always passes: SwiftShader counts no samples without one.
    desc.depth = DepthState { test: true, write: false, compare: vk::CompareOp::ALWAYS, ..DepthState::NONE };
    let front = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
    desc.name = "back faces";
    desc.cull = vk::CullModeFlags::FRONT;
    let back = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
    let n = triangles.len() as u32 / 3;
    let pool = QueryPool::new(ctx, "coverage", QueryKind::Occlusion, 2 * n).unwrap();
    let bytes: &[u8] = umbra::vk::bytemuck::cast_slice(triangles);
    let vertices = Buffer::with_data(ctx, "clip triangles", vk::BufferUsageFlags::VERTEX_BUFFER, bytes).unwrap();
    let mut rec = ctx.begin_commands("coverage").unwrap();
    rec.reset_queries(&pool);
    common::begin_depth_pass(&mut rec, &target);
    rec.bind_vertex_buffer(&vertices);
    for (face, pipeline) in [&front, &back].into_iter().enumerate() {
        rec.bind_pipeline(pipeline);
        rec.set_scissor([x, y, 1, 1]);
        for t in 0..n {
            rec.begin_query(&pool, 2 * t + face as u32);
            rec.draw_range(3, 3 * t);
            rec.end_query(&pool, 2 * t + face as u32);
        }
    }
    rec.end_rendering();
    ctx.submit_and_wait(rec).unwrap();
    let r = pool.results().unwrap();
    (0..n as usize).map(|t| (r[2 * t], r[2 * t + 1])).collect()
}

fn is_swiftshader(ctx: &Context) -> bool {
    ctx.capabilities().device_name.to_lowercase().contains("swiftshader")
}

#[test]
fn swiftshaders_clipper_leaves_a_hole_that_clipping_inside_the_view_closes() {
    // The minimal reproduction (#22): three side triangles of the cubes scene's volumes at
    // 256x192, literally. The pixel (207, 161) lies inside the first, a sliver 0.04 px wide
    // there, between its long edges shared with the other two; the far vertex (shared) lies
    // below and right of the view, so the driver clips all three against two planes.
    let a = Vec4::new(9.284529, 0.4366727, 17.502316, 17.552317);
    let b = Vec4::new(9.060701, 0.044448853, 16.995693, 17.045694);
    let far = Vec4::new(3.1552231, -22.80692, 0.3432004, 0.3432004);
    let left = Vec4::new(3.3790512, -22.414696, 0.84982216, 0.84982216);
    let right = Vec4::new(2.9190092, -21.699677, 0.19714546, 0.19714546);
    let three = [a, b, far, a, far, left, b, right, far];
    let pixel = (207, 161);
    common::with_context(|ctx| {
        let covered = |tris: &[Vec4]| -> (u64, u64) {
            coverage_at(ctx, tris, common::SIZE, pixel).iter().fold((0, 0), |s, c| (s.0 + c.0, s.1 + c.1))
        };
        let as_drawn = covered(&three);
        let clipped = covered(&common::clip::clip_inside_view(&three, 0.9999));
        println!("pixel {pixel:?}: (front, back) samples as drawn {as_drawn:?}, clipped inside the view {clipped:?}");
        // Clipped on the host to just inside the view, the driver clips nothing: exactly one
        // front-facing triangle covers the pixel, on every driver.
        assert_eq!(clipped, (1, 0));
        if is_swiftshader(ctx) {
            // SwiftShader's own clipping of the three leaves the pixel to none of them: a hole
            // in a closed surface, which a stencil count reads as a shadow edge.
            println!("KNOWN SWIFTSHADER ISSUE: its frustum clipper leaves a hole between shared edges");
            assert_eq!(as_drawn, (0, 0), "SwiftShader covers the pixel now: the workaround may be unnecessary");
        } else {
            assert_eq!(as_drawn, (1, 0));
        }
    });
}

#[test]
fn volumes_clipped_inside_the_view_rasterize_watertight_on_every_driver() {
    // The formulation #22 asks for, measured at the Vulkan level: the volumes of the watertight
    // scenes clipped on the host to 0 <= z, |x|, |y| <= g·w. With g < 1 the driver clips
    // nothing and every pixel counts 0 on both drivers; with g > 1 (the driver clips what is
    // left) SwiftShader miscounts again, more than unclipped.
    common::with_context(|ctx| {
        let (w, h) = common::SIZE;
        for scene in &watertight_scenes() {
            let clip = volume_clip_triangles(scene, (w, h));
            for g in [0.9999, 1.01, 2.0] {
                let clipped = common::clip::clip_inside_view(&clip, g);
                let nonzero = nonzero_after_counting(ctx, &clipped, w, h);
                println!(
                    "{} g = {g}: {} -> {} triangles, {nonzero} pixels nonzero",
                    scene.name,
                    clip.len() / 3,
                    clipped.len() / 3
                );
                if g < 1.0 || !is_swiftshader(ctx) {
                    assert_eq!(nonzero, 0, "{} clipped to |x|, |y| <= {g} w", scene.name);
                } else if nonzero > 0 {
                    println!("  KNOWN SWIFTSHADER ISSUE: its clipper is not watertight");
                }
            }
        }
    });
}

#[test]
fn several_lights_accumulate_each_with_its_own_stencil_count() {
    // Two point lights on the slab scene: the stencil is cleared per light, so the two-light
    // frame is the sum of the one-light frames, pixel by pixel.
    let mut scene = eye_in_shadow_scene();
    // No ambient and a black background: each frame holds only its lights' terms.
    assert_eq!(scene.ambient, Vec3::ZERO);
    scene.background = Vec3::ZERO;
    scene.camera = Camera::look_at(Vec3::new(-4.0, 4.5, 5.0), Vec3::new(0.0, 1.0, 0.0));
    scene.lights = vec![Light::point(Vec3::new(0.0, 6.0, 0.0), 20.0), Light::point(Vec3::new(3.0, 5.0, -2.0), 20.0)];
    for l in &mut scene.lights {
        l.technique = Technique::ShadowVolume;
    }
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        let both = r.render(&scene).unwrap();
        let mut single = |i: usize| {
            let mut s = scene.clone();
            s.lights = vec![scene.lights[i].clone()];
            r.render(&s).unwrap()
        };
        let (a, b) = (single(0), single(1));
        let mut worst = 0;
        for ((p, x), y) in both.rgba.chunks_exact(4).zip(a.rgba.chunks_exact(4)).zip(b.rgba.chunks_exact(4)) {
            for c in 0..3 {
                let sum = (i32::from(x[c]) + i32::from(y[c])).min(255);
                worst = worst.max((i32::from(p[c]) - sum).abs());
            }
        }
        let volume_passes = both.report.passes.iter().filter(|p| matches!(p.id, PassId::ShadowVolume(_))).count();
        println!("two shadow-volume lights: {volume_passes} stencil passes, worst difference from the sum {worst}/255");
        assert_eq!(volume_passes, 2);
        // One 8-bit rounding per addend.
        assert!(worst <= 2, "two lights differ from the sum of one-light frames by {worst}");
    });
}

#[test]
fn an_empty_scene_renders_its_background() {
    let mut s = Scene::new("empty");
    s.lights.push(Light::point(Vec3::ONE, 1.0));
    s.lights[0].technique = Technique::ShadowVolume;
    common::with_context(|ctx| {
        let frame = Renderer::new(ctx, RendererDesc::new(64, 48)).unwrap().render(&s).unwrap();
        let bg = (s.background * 255.0).to_array().map(|v| v.round() as u8);
        assert!(frame.rgba.chunks_exact(4).all(|p| p[..3].iter().zip(bg).all(|(a, b)| a.abs_diff(b) <= 1)));
        assert_eq!(frame.report.lights[0].skipped_because.as_deref(), Some("no objects to light"));
    });
}

#[test]
fn host_clipping_changes_nothing_where_the_driver_clips_watertight() {
    // `HostClip::Always` against `Never` on the watertight scenes (z-fail, P_inf): on a driver
    // whose clipping is watertight the two give the same image, pixel for pixel, so the
    // workaround costs only host time there; on SwiftShader (`Auto` = `Always`) it changes the
    // pixels its clipper got wrong.
    common::with_context(|ctx| {
        for scene in watertight_scenes() {
            let mut scene = scene;
            for l in &mut scene.lights {
                l.technique = Technique::ShadowVolume;
            }
            let frames: Vec<Frame> = [umbra::shadows::HostClip::Never, umbra::shadows::HostClip::Always]
                .into_iter()
                .map(|host_clip| {
                    let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
                    desc.shadow_volume =
                        ShadowVolumeSettings { mode: VolumeMode::ZFail, host_clip, ..Default::default() };
                    Renderer::new(ctx, desc).unwrap().render(&scene).unwrap()
                })
                .collect();
            let differ = frames[0].rgba.chunks(4).zip(frames[1].rgba.chunks(4)).filter(|(a, b)| a != b).count();
            let clipped =
                frames[1].report.lights.iter().filter_map(|l| l.shadow_volume.as_ref()).all(|v| v.host_clipped);
            println!("{}: {differ} pixels differ between host clipping off and on", scene.name);
            assert!(clipped, "{}: the report says whether the volumes were clipped", scene.name);
            if ctx.capabilities().watertight_clipping {
                assert_eq!(differ, 0, "{}", scene.name);
            }
        }
    });
}

#[test]
fn swiftshader_misses_a_volume_face_a_few_depth_ulps_behind_a_grazing_surface() {
    // Hard case 11's residual on SwiftShader, reduced to two adjacent triangles of the scanned
    // bunny (world space, an open mesh, hard case 11's camera and light). Pixel (157, 107)
    // lies on their shared edge, lit at grazing incidence (n·l = 0.024 and 0.138): nothing
    // blocks it, so the exact count is 0. The eye ray enters the two triangles' volume there
    // and leaves it through a side 3.2e-4 world units behind, 18 f32 depth ulps at z = 0.98:
    // that side must fail the depth test to close the count. lavapipe counts 0; SwiftShader's
    // interpolated depth of the side (a triangle reaching the image border) lands in front of
    // the surface, the exit is lost and the pixel counts -1 (stencil 255): shadowed.
    let triangles = [
        [
            Vec3::new(0.746796, 0.351395, 0.141255),
            Vec3::new(0.749388, 0.351152, 0.149967),
            Vec3::new(0.749064, 0.363833, 0.140517),
        ],
        [
            Vec3::new(0.749388, 0.351152, 0.149967),
            Vec3::new(0.750783, 0.363626, 0.149850),
            Vec3::new(0.749064, 0.363833, 0.140517),
        ],
    ];
    let positions: Vec<Vec3> = triangles.iter().flatten().copied().collect();
    let mut scene = Scene::new("two grazing bunny triangles");
    scene.camera = Camera {
        position: Vec3::new(-1.0, 3.0, 4.5),
        target: Vec3::new(0.0, 0.7, 0.0),
        fov_y_deg: 50.0,
        near: 0.1,
        up: Vec3::Y,
        far: None,
    };
    let mesh = scene.add_mesh(umbra::scene::Mesh::with_flat_normals("pair", &positions, &[0, 1, 2, 3, 4, 5]).unwrap());
    scene.add_object(mesh, Mat4::IDENTITY, Vec3::splat(0.7));
    scene.lights.push(Light { technique: Technique::ShadowVolume, ..Light::point(Vec3::new(1.5, 5.0, 2.0), 30.0) });
    common::with_context(|ctx| {
        let (w, h) = common::SIZE;
        let mut desc = RendererDesc::new(w, h);
        desc.diagnostics = true;
        let frame = Renderer::new(ctx, desc).unwrap().render(&scene).unwrap();
        let stencil = frame.diagnostics[0].stencil.as_ref().expect("a shadow-volume light's stencil view");
        let count = stencil[(107 * w + 157) as usize];
        println!("pixel (157, 107): stencil count {count}");
        if is_swiftshader(ctx) {
            println!("KNOWN SWIFTSHADER ISSUE: a volume side 18 depth ulps behind the surface passes the depth test");
            assert_eq!(count, 255, "SwiftShader counts this pixel otherwise now: revisit hard case 11's tolerance");
        } else {
            assert_eq!(count, 0);
        }
    });
}
