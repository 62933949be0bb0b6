//! Device limits the frame depends on are checked before anything is created, with typed
//! errors that name the limit, its value and the device (issue #20): storage buffers against
//! `maxStorageBufferRange`, the target and shadow maps against `maxFramebuffer*`,
//! `maxViewportDimensions` and the format's `maxExtent` as well as `maxImageDimension*`,
//! allocations against `maxMemoryAllocationSize` and `maxBufferSize`, the frame's shadow maps
//! against the renderer's memory budget, and shadow-map settings that would make every shadow
//! vanish. The validation layer must stay silent throughout (`common::with_context`).

mod common;

use glam::{Mat4, Vec3};
use umbra::scene::{Light, Mesh, Object, Scene, Technique};
use umbra::shadows::{DepthBias, RenderError, Renderer, RendererDesc, ShadowMapSettings, DEFAULT_SHADOW_MAP_BUDGET};
use umbra::vk::{vk, Buffer, BufferDesc, Context, Image, ImageDesc, VkError};

/// Bytes per object in the object buffer (`shaders-glsl/common/scene.glsl`: two mat4, a vec4).
const OBJECT_BYTES: u64 = 144;

/// The most objects a test builds on the CPU (about 130 MB of scene): lavapipe's limit
/// (932,067 objects) is under it, SwiftShader's (7,456,540) is not.
const MAX_TEST_OBJECTS: u64 = 2_000_000;

fn is_llvmpipe(ctx: &Context) -> bool {
    ctx.capabilities().device_name.to_lowercase().contains("llvmpipe")
}

fn is_swiftshader(ctx: &Context) -> bool {
    ctx.capabilities().device_name.to_lowercase().contains("swiftshader")
}

fn renderer(ctx: &Context, edit: impl FnOnce(&mut RendererDesc)) -> Renderer {
    let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
    edit(&mut desc);
    Renderer::new(ctx, desc).expect("renderer")
}

/// `cubes` with every light casting shadow-map shadows.
fn cubes() -> Scene {
    let mut s = umbra::scene::load("cubes").expect("cubes");
    for l in &mut s.lights {
        l.technique = Technique::ShadowMap;
    }
    s
}

/// `cubes` whose point light is a spot aimed at the scene (one 2D map).
fn cubes_spot() -> Scene {
    let mut s = cubes();
    assert_eq!(s.point_lights_to_spots(80.0), vec![0]);
    s
}

/// `cubes` with silhouette maps: its point light's depth and silhouette maps are face
/// atlases, three faces (each with a two-texel border) across.
fn cubes_silhouette() -> Scene {
    let mut s = cubes();
    s.lights[0].technique = Technique::SilhouetteMap;
    s
}

#[test]
fn more_objects_than_max_storage_buffer_range_holds_are_a_typed_error_before_any_gpu_work() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        let range = u64::from(caps.max_storage_buffer_range);
        let fits = range / OBJECT_BYTES;
        println!("{}: maxStorageBufferRange {range} bytes holds {fits} objects", caps.device_name);
        if fits + 1 > MAX_TEST_OBJECTS {
            assert!(!is_llvmpipe(ctx), "llvmpipe must run this check (its limit is 932,067 objects)");
            println!(
                "NOT RUN on {}: {} objects would take about {} MB of scene on the CPU; the object-buffer \
                 check runs on llvmpipe (and in umbra-shadows' unit tests for any limit)",
                caps.device_name,
                fits + 1,
                (fits + 1) * 130 / 1_000_000
            );
            return;
        }
        let mut scene = Scene::new("too many objects");
        let triangle = [Vec3::ZERO, Vec3::X, Vec3::Z];
        scene.add_mesh(Mesh::new("", triangle.to_vec(), vec![Vec3::Y; 3], vec![0, 1, 2]).unwrap());
        let object = Object {
            name: String::new(),
            mesh: 0,
            transform: Mat4::IDENTITY,
            albedo: Vec3::ONE,
            casts_shadows: false,
            receives_shadows: false,
        };
        scene.objects = vec![object; fits as usize + 1];
        scene.lights.push(Light::point(Vec3::new(0.0, 3.0, 0.0), 1.0));
        let mut r = renderer(ctx, |_| {});
        let err = r.render(&scene).expect_err("one object over the limit");
        println!("{err}");
        let RenderError::DeviceLimit { limit, .. } = &err else { panic!("not a DeviceLimit: {err}") };
        assert_eq!((limit.name, limit.value), ("maxStorageBufferRange", range), "{err}");
        let text = err.to_string();
        assert!(text.contains(&format!("{} objects need", fits + 1)) && text.contains("of object buffer"), "{text}");
        assert!(text.contains(&caps.device_name), "{text}");
        assert_eq!(r.submissions(), 0, "nothing may reach the GPU");
    });
}

#[test]
fn target_sizes_over_the_framebuffer_viewport_and_image_limits_are_typed_errors() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        let [vw, vh] = caps.max_viewport_dimensions;
        let width = caps.max_image_dimension_2d.min(caps.max_framebuffer_width).min(vw);
        let height = caps.max_image_dimension_2d.min(caps.max_framebuffer_height).min(vh);
        let mut sizes = vec![(width + 1, 8), (8, height + 1)];
        if is_swiftshader(ctx) {
            // The fuzzing report's case: within maxImageDimension2D (16384), over
            // maxFramebufferWidth (8192).
            assert_eq!((caps.max_image_dimension_2d, caps.max_framebuffer_width), (16384, 8192));
            sizes.push((8200, 8));
        }
        for (w, h) in sizes {
            let err = Renderer::new(ctx, RendererDesc::new(w, h)).err().expect("refused");
            println!("{w}x{h}: {err}");
            let RenderError::InvalidSize { limit: Some(limit), .. } = &err else { panic!("{w}x{h}: {err}") };
            assert!(limit.value < u64::from(w.max(h)), "{err}");
            assert!(err.to_string().contains(limit.name) && err.to_string().contains(&caps.device_name), "{err}");
            if is_swiftshader(ctx) && w > h {
                assert_eq!(limit.name, "maxFramebufferWidth", "{err}");
            }
        }
    });
}

#[test]
fn shadow_maps_over_every_device_limit_are_typed_errors_before_any_allocation() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        // (scene, resolution, expected limit): a spot's 2D map and a point light's cube map
        // over the tightest limit; on lavapipe the cube case is the fuzzing report's
        // --sm-size 32768 (within maxImageDimensionCube, over the D32 format's maxExtent and
        // maxResourceSize), on SwiftShader a spot at 8256 (within maxImageDimension2D, over
        // maxFramebufferWidth).
        let mut cases: Vec<(Scene, u32, Option<&str>)> = Vec::new();
        if is_llvmpipe(ctx) {
            // Six 16384² D32 faces are 6 GiB, over the format's maxResourceSize (4 GiB - 1):
            // the largest cube is 13377², whatever maxExtent (16384) says.
            assert_eq!(caps.max_image_dimension_cube, 32768);
            let resource = Some("maxResourceSize (vkGetPhysicalDeviceImageFormatProperties)");
            cases.push((cubes(), 32768, resource));
            cases.push((cubes(), 16384, resource));
            cases.push((cubes_spot(), 16385, Some("maxImageDimension2D")));
            // Three faces of 5458 + 4 texels across are 16386, over the atlas's 16384.
            cases.push((cubes_silhouette(), 16384 / 3 - 4 + 1, Some("maxImageDimension2D")));
        } else if is_swiftshader(ctx) {
            cases.push((cubes_spot(), 8256, Some("maxFramebufferWidth")));
            cases.push((cubes(), 16385, Some("maxFramebufferWidth")));
            cases.push((cubes_silhouette(), 8192 / 3 - 4 + 1, Some("maxFramebufferWidth")));
        } else {
            panic!("this suite runs on llvmpipe or swiftshader; got {} (set UMBRA_DEVICE)", caps.device_name);
        }
        for (mut scene, size, expected) in cases {
            scene.lights[0].shadow_map_size = Some(size);
            let kind = scene.lights[0].kind();
            let mut r = renderer(ctx, |d| d.shadow_map_budget_bytes = u64::MAX);
            let err = r.render(&scene).expect_err("map over the limit");
            println!("{kind:?} at {size}: {err}");
            let RenderError::InvalidShadowMap { light: 0, resolution, limit: Some(limit), .. } = &err else {
                panic!("{kind:?} at {size}: {err}")
            };
            assert_eq!(*resolution, size);
            if let Some(name) = expected {
                assert_eq!(limit.name, name, "{err}");
            }
            assert!(err.to_string().contains(&caps.device_name), "{err}");
            assert_eq!(r.submissions(), 0);
        }
    });
}

#[test]
fn the_shadow_map_budget_is_checked_before_any_map_is_allocated() {
    common::with_context(|ctx| {
        // 40 shadowed point lights at 2048² took 4 GB: 40 × 96 MiB over the default 1 GiB.
        let mut scene = cubes();
        let first = scene.lights[0].clone();
        scene.lights = (0..40)
            .map(|i| {
                let mut l = first.clone();
                l.position += glam::Vec4::new(0.02 * i as f32, 0.0, 0.0, 0.0);
                l.intensity /= 40.0;
                l
            })
            .collect();
        // 2048² per face, as set (a map sized from the 256×192 frame would be 256²).
        let mut r = renderer(ctx, |d| d.shadow_map.resolution = Some(2048));
        let err = r.render(&scene).expect_err("over the default budget");
        println!("{err}");
        let RenderError::ShadowBudget { lights, bytes, budget } = &err else { panic!("{err}") };
        assert_eq!((lights.len(), *bytes, *budget), (40, 40 * (96 << 20), DEFAULT_SHADOW_MAP_BUDGET), "{err}");
        assert!(lights.iter().enumerate().all(|(i, l)| l.light == i && l.cube && l.resolution == 2048));
        let text = err.to_string();
        assert!(text.contains("light 39: 6 x 2048² = 96 MiB") && text.contains("shadow_map_budget_bytes = 1 GiB"));
        assert_eq!(r.submissions(), 0);

        // A spot's 1024² map is 4 MiB: one byte less is refused, exactly that renders.
        let spot = cubes_spot();
        let map = 4 * 1024 * 1024;
        let settings = ShadowMapSettings { resolution: Some(1024), ..ShadowMapSettings::DEFAULT };
        let mut tight = renderer(ctx, |d| (d.shadow_map, d.shadow_map_budget_bytes) = (settings, map - 1));
        let err = tight.render(&spot).expect_err("one byte short");
        assert!(matches!(&err, RenderError::ShadowBudget { bytes, .. } if *bytes == map), "{err}");
        let mut enough = renderer(ctx, |d| (d.shadow_map, d.shadow_map_budget_bytes) = (settings, map));
        let frame = enough.render(&spot).expect("within the budget");
        assert_eq!(frame.report.lights[0].shadow_map.as_ref().map(|m| m.resolution), Some(1024));

        // A hybrid light holds its depth bounds, two layers of the map's size, and its depth
        // map only with blocker culling (which queries it).
        let mut hybrid = spot.clone();
        hybrid.lights[0].technique = umbra::scene::Technique::Hybrid;
        for (cull, layers, text) in
            [(false, 2, "light 0: 1024² depth bounds = 8 MiB"), (true, 3, "light 0: 1024² + depth bounds = 12 MiB")]
        {
            let sized = |d: &mut RendererDesc, budget| {
                d.hybrid.resolution = Some(1024);
                d.hybrid.cull_blockers = cull;
                d.shadow_map_budget_bytes = budget;
            };
            let err = renderer(ctx, |d| sized(d, layers * map - 1)).render(&hybrid).expect_err("one byte short");
            assert!(matches!(&err, RenderError::ShadowBudget { bytes, .. } if *bytes == layers * map), "{err}");
            assert!(err.to_string().contains(text), "{err}");
            let frame = renderer(ctx, |d| sized(d, layers * map)).render(&hybrid).expect("within the budget");
            // The depth map is drawn only where something reads it.
            let drawn = frame.report.passes.iter().any(|p| p.name == "shadow_map 0");
            assert_eq!(drawn, cull, "{:?}", frame.report.passes.iter().map(|p| &p.name).collect::<Vec<_>>());
        }
    });
}

#[test]
fn non_finite_and_absurd_shadow_map_settings_are_refused_by_renderer_new() {
    common::with_context(|ctx| {
        let bias = |constant, slope| DepthBias { constant, slope, clamp_texels: None };
        let cases = [
            ("shadow_map.bias.constant", ShadowMapSettings { bias: bias(f32::NAN, f32::NAN), ..Default::default() }),
            (
                "shadow_map.bias.constant",
                ShadowMapSettings { bias: bias(f32::INFINITY, f32::NEG_INFINITY), ..Default::default() },
            ),
            ("shadow_map.bias.slope", ShadowMapSettings { bias: bias(2.0, 1e30), ..Default::default() }),
            ("shadow_map.normal_offset", ShadowMapSettings { normal_offset: f32::NAN, ..Default::default() }),
            ("shadow_map.normal_offset", ShadowMapSettings { normal_offset: 1e30, ..Default::default() }),
            ("shadow_map.normal_offset", ShadowMapSettings { normal_offset: -0.5, ..Default::default() }),
        ];
        for (field, settings) in cases {
            let mut desc = RendererDesc::new(common::SIZE.0, common::SIZE.1);
            desc.shadow_map = settings;
            let err = Renderer::new(ctx, desc).err().expect("refused");
            println!("{err}");
            assert!(matches!(&err, RenderError::InvalidSetting { field: f, .. } if *f == field), "{err}");
        }
    });
}

#[test]
fn allocations_over_device_limits_name_the_resource() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        println!(
            "{}: maxBufferSize {}, maxMemoryAllocationSize {}",
            caps.device_name, caps.max_buffer_size, caps.max_memory_allocation_size
        );
        // A buffer one byte over the tighter of the two: refused before its memory is asked for.
        let size = caps.max_buffer_size.min(caps.max_memory_allocation_size) + 1;
        let desc = BufferDesc::gpu_only(size, vk::BufferUsageFlags::STORAGE_BUFFER);
        let err = Buffer::new(ctx, "huge test buffer", desc).expect_err("over the limit");
        println!("{err}");
        let VkError::DeviceLimit { limit, what, .. } = &err else { panic!("{err}") };
        assert!(["maxBufferSize", "maxMemoryAllocationSize"].contains(&limit.name), "{err}");
        assert!(what.contains("huge test buffer"), "{err}");
        // A 16384² RGBA32F image is 4 GiB: over either driver's maxMemoryAllocationSize.
        let desc = ImageDesc::new_2d(vk::Format::R32G32B32A32_SFLOAT, 16384, 16384)
            .usage(vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST);
        let err = Image::new(ctx, "huge test image", desc).expect_err("over the limit");
        println!("{err}");
        assert!(matches!(&err, VkError::DeviceLimit { what, .. } if what.contains("huge test image")), "{err}");
    });
}
