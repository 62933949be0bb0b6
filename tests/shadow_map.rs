//! Shadow maps against exact geometry: the analytic boundary of a square's shadow, the six
//! faces of a point light's cube map, a spot light whose occluder runs past its frustum, the
//! out-of-frustum policy, depth-bias acne, and typed errors for bad resolutions.

mod common;

use common::raycast::{distance_to_boundary, hit_plane_y, inside_convex, pixel_ray, Box3};
use glam::{Mat4, Quat, Vec2, Vec3};
use umbra::scene::{primitives, Camera, Light, Scene, Technique};
use umbra::shadows::{DepthBias, Frame, RenderError, Renderer, RendererDesc, ShadowFilter, ShadowMapSettings};
use umbra::vk::{vk, Context, Image, ImageDesc, VkError};

fn renderer(ctx: &Context, size: (u32, u32), settings: ShadowMapSettings) -> Renderer {
    let mut desc = RendererDesc::new(size.0, size.1);
    desc.shadow_map = settings;
    Renderer::new(ctx, desc).expect("renderer")
}

fn settings(resolution: u32, filter: ShadowFilter) -> ShadowMapSettings {
    ShadowMapSettings { resolution: Some(resolution), filter, ..ShadowMapSettings::DEFAULT }
}

/// Red channel in 0..255.
fn red(frame: &Frame, x: u32, y: u32) -> u8 {
    frame.pixel(x, y)[0]
}

fn shadow_light(towards: Vec3) -> Light {
    let mut l = Light::directional(towards, 1.0);
    l.technique = Technique::ShadowMap;
    l
}

/// A receiving (non-casting) floor at y = 0 and an empty, black, unlit-by-ambient scene.
fn floor_scene(name: &str, size: f32) -> Scene {
    let mut s = Scene::new(name);
    let floor = s.add_mesh(primitives::plane(size));
    s.add_object(floor, Mat4::IDENTITY, Vec3::ONE).casts_shadows = false;
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    s
}

// ---------------------------------------------------------------------------------------------
// The analytic boundary: a square occluder above a plane under a directional light.

const SQUARE_HEIGHT: f32 = 1.0;
const SQUARE_TURN_DEG: f32 = 30.0;

fn square_transform() -> Mat4 {
    Mat4::from_rotation_translation(
        Quat::from_rotation_y(SQUARE_TURN_DEG.to_radians()),
        Vec3::new(0.0, SQUARE_HEIGHT, 0.0),
    )
}

/// Largest distance from the exact shadow edge among misclassified pixels, and how many
/// pixels were compared.
fn boundary_error(ctx: &Context, resolution: u32, size: u32) -> (f32, usize, usize) {
    let towards = Vec3::new(0.35, 1.0, 0.2).normalize();
    let mut s = floor_scene("square", 20.0);
    let quad = s.add_mesh(primitives::plane(2.0));
    let o = s.add_object(quad, square_transform(), Vec3::splat(0.3));
    o.receives_shadows = false;
    s.lights.push(shadow_light(towards));
    let centre = Vec3::new(-towards.x, 0.0, -towards.z) * (SQUARE_HEIGHT / towards.y);
    s.camera = Camera { up: -Vec3::Z, fov_y_deg: 50.0, ..Camera::look_at(centre + Vec3::Y * 4.0, centre) };

    let frame = renderer(ctx, (size, size), settings(resolution, ShadowFilter::Nearest)).render(&s).unwrap();
    frame.save_png(&common::output_dir("shadow_map").join(format!("square-{resolution}.png"))).unwrap();
    let corners: Vec<Vec3> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, z)| square_transform().transform_point3(Vec3::new(x, 0.0, z)))
        .collect();
    let square: Vec<Vec2> = corners.iter().map(|c| Vec2::new(c.x, c.z)).collect();
    let shadow: Vec<Vec2> =
        corners.iter().map(|&c| c - towards * (c.y / towards.y)).map(|p| Vec2::new(p.x, p.z)).collect();
    let lit = towards.y * 255.0;
    let view_proj = s.camera.view_proj(1.0);
    let (mut worst, mut compared, mut shadowed) = (0.0f32, 0, 0);
    for y in 0..size {
        for x in 0..size {
            let (o, d) = pixel_ray(view_proj, size, size, x, y);
            let on_square = hit_plane_y(o, d, SQUARE_HEIGHT).map(|p| Vec2::new(p.x, p.z));
            if on_square.is_some_and(|p| inside_convex(&square, p) || distance_to_boundary(&square, p) < 0.01) {
                continue; // the camera sees the occluder here (or its silhouette pixels)
            }
            let Some(q) = hit_plane_y(o, d, 0.0) else { continue };
            let q = Vec2::new(q.x, q.z);
            let expected = inside_convex(&shadow, q);
            let rendered = (red(&frame, x, y) as f32) < 0.5 * lit;
            compared += 1;
            shadowed += usize::from(expected);
            if expected != rendered {
                worst = worst.max(distance_to_boundary(&shadow, q));
            }
        }
    }
    (worst, compared, shadowed)
}

#[test]
fn misclassified_pixels_hug_the_exact_edge_and_the_band_halves_with_resolution() {
    common::with_context(|ctx| {
        let towards_y = Vec3::new(0.35, 1.0, 0.2).normalize().y;
        // The occluder's light-space footprint is at most its box diagonal (2.73 x 2.73 after a
        // 30 degree turn), plus the fit's 2% padding: an upper bound on the map's extent.
        let extent = Vec2::splat(2.0 * (30f32.to_radians().cos() + 30f32.to_radians().sin())).length() * 1.02;
        let mut worst = Vec::new();
        for resolution in [64, 128, 256] {
            let (w, compared, shadowed) = boundary_error(ctx, resolution, 768);
            let texel = extent / resolution as f32;
            // One texel's footprint on the floor: the texel square stretched by 1/cos along the
            // light's tilt; its diagonal.
            let band = texel * (1.0 + 1.0 / (towards_y * towards_y)).sqrt();
            println!("{resolution:4}^2: max misclassified distance {w:.4} (band {band:.4}), {shadowed} of {compared} pixels in shadow");
            assert!(shadowed > 5_000, "the shadow is in view");
            assert!(w <= band, "{resolution}^2: a pixel {w} from the edge is wrong (band {band})");
            worst.push(w);
        }
        for (pair, ratio) in [(0, worst[1] / worst[0]), (1, worst[2] / worst[1])] {
            println!("band ratio {pair}: {ratio:.3}");
            assert!((0.4..=0.6).contains(&ratio), "doubling resolution gave ratio {ratio}, not 0.5 +- 20%");
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Point light: one occluder per cube face, plus one on the seam between two faces.

#[test]
fn point_light_cube_faces_put_each_shadow_where_it_belongs_without_seam_leaks() {
    let light = Vec3::new(0.3, 0.2, -0.1);
    let room = Box3::around(Vec3::ZERO, Vec3::splat(4.0));
    let axes = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
    let mut occluders: Vec<Box3> = axes.iter().map(|&a| Box3::around(light + a * 1.4, Vec3::splat(0.3))).collect();
    let seam = Vec3::new(1.0, 0.0, 1.0).normalize();
    occluders.push(Box3::around(light + seam * 1.6, Vec3::splat(0.25)));

    let mut s = Scene::new("six occluders");
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    let room_mesh = s.add_mesh(primitives::cuboid(Vec3::splat(4.0)));
    s.add_object(room_mesh, Mat4::IDENTITY, Vec3::ONE).casts_shadows = false;
    for b in &occluders {
        let m = s.add_mesh(primitives::cuboid((b.max - b.min) * 0.5));
        s.add_object(m, Mat4::from_translation((b.min + b.max) * 0.5), Vec3::splat(0.5)).receives_shadows = false;
    }
    let mut l = Light::point(light, 30.0);
    l.technique = Technique::ShadowMap;
    s.lights.push(l);

    let size = common::SIZE;
    let band = 0.08;
    common::with_context(|ctx| {
        let mut r = renderer(ctx, size, settings(512, ShadowFilter::Pcf2x2));
        let views: Vec<(String, Vec3, Vec3)> = axes
            .iter()
            .map(|&a| {
                let side = a.any_orthonormal_vector() + a.cross(a.any_orthonormal_vector());
                (format!("face {a}"), light - a * 1.0 + side * 0.9, light + a * 4.0)
            })
            .chain([("seam +X/+Z".to_owned(), light + Vec3::new(-1.0, 0.9, -1.0), Vec3::new(4.0, 0.2, 4.0))])
            .collect();
        for (name, eye, target) in views {
            s.camera = Camera { fov_y_deg: 70.0, near: 0.05, ..Camera::look_at(eye, target) };
            let frame = r.render(&s).unwrap();
            assert!(frame.report.lights[0].shadow_map.as_ref().is_some_and(|m| m.cube), "a cube map was rendered");
            let vp = s.camera.view_proj(size.0 as f32 / size.1 as f32);
            let (mut wrong, mut in_shadow, mut compared) = (0, 0, 0);
            for y in 0..size.1 {
                for x in 0..size.0 {
                    let (o, d) = pixel_ray(vp, size.0, size.1, x, y);
                    let Some((_, exit)) = room.hit(o, d) else { continue };
                    // Skip rays that see an occluder, or pass within a hair of one (its silhouette
                    // pixels are covered by the rasterizer or not by rules finer than this test).
                    let grown = |b: &Box3| Box3 { min: b.min - 0.02, max: b.max + 0.02 };
                    if occluders.iter().any(|b| grown(b).hit(o, d).is_some_and(|(t0, _)| t0 < exit)) {
                        continue;
                    }
                    let q = o + d * exit;
                    let expected = occluders.iter().any(|b| b.blocks(light, q));
                    // Skip the band around the exact shadow edge (filtered, texel-quantised).
                    let gap = (q.abs() - Vec3::splat(4.0)).abs();
                    let axis = if gap.x <= gap.y && gap.x <= gap.z {
                        0
                    } else if gap.y <= gap.z {
                        1
                    } else {
                        2
                    };
                    let (t1, t2) = (Vec3::AXES[(axis + 1) % 3] * band, Vec3::AXES[(axis + 2) % 3] * band);
                    let near_edge = [q + t1, q - t1, q + t2, q - t2]
                        .iter()
                        .any(|&n| occluders.iter().any(|b| b.blocks(light, n)) != expected);
                    if near_edge {
                        continue;
                    }
                    compared += 1;
                    in_shadow += usize::from(expected);
                    let v = red(&frame, x, y);
                    let rendered_shadow = v < 20;
                    if rendered_shadow != expected {
                        wrong += 1;
                        println!("  wrong: pixel ({x},{y}) at {q:.3}: expected shadow {expected}, red {v}");
                    }
                }
            }
            let file = name.replace([' ', '/', '+', '(', ')', ','], "_");
            frame.save_png(&common::output_dir("shadow_map").join(format!("cube-{file}.png"))).unwrap();
            println!("{name}: {in_shadow} shadowed of {compared} compared pixels, {wrong} wrong");
            assert!(in_shadow > 300, "{name}: the occluder's shadow should be in view");
            assert_eq!(wrong, 0, "{name}: pixels lit or shadowed on the wrong side of the exact boundary");
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Spot light: an occluder that runs past the frustum's border shadows only what it should.

#[test]
fn spot_light_shadows_only_what_the_occluder_hides_even_past_the_frustum_border() {
    let light = Vec3::new(0.0, 4.0, 0.0);
    let occluder = Box3 { min: Vec3::new(0.2, 2.0, -2.0), max: Vec3::new(4.2, 2.0, 2.0) };
    let mut s = floor_scene("spot", 20.0);
    let quad = s.add_mesh(primitives::plane(4.0));
    s.add_object(quad, Mat4::from_translation(Vec3::new(2.2, 2.0, 0.0)), Vec3::splat(0.3)).receives_shadows = false;
    let mut l = Light::spot(light, -Vec3::Y, 30.0, 35.0, 12.0);
    l.technique = Technique::ShadowMap;
    s.lights.push(l);
    // Low and to the side, so the camera sees the floor under the occluder.
    s.camera = Camera { fov_y_deg: 70.0, ..Camera::look_at(Vec3::new(-3.5, 1.5, 4.0), Vec3::new(0.8, 0.0, 0.0)) };
    let size = common::SIZE;
    common::with_context(|ctx| {
        let mut r = renderer(ctx, size, settings(512, ShadowFilter::Pcf2x2));
        let shadowed = r.render(&s).unwrap();
        let mut unshadowed_scene = s.clone();
        unshadowed_scene.lights[0].technique = Technique::Unshadowed;
        let plain = r.render(&unshadowed_scene).unwrap();
        shadowed.save_png(&common::output_dir("shadow_map").join("spot.png")).unwrap();
        let vp = s.camera.view_proj(size.0 as f32 / size.1 as f32);
        let (mut lit_checked, mut shadow_checked) = (0, 0);
        for y in 0..size.1 {
            for x in 0..size.0 {
                let (o, d) = pixel_ray(vp, size.0, size.1, x, y);
                let Some(q) = hit_plane_y(o, d, 0.0) else { continue };
                let on_occluder = hit_plane_y(o, d, 2.0).is_some_and(|p| {
                    p.x >= occluder.min.x && p.x <= occluder.max.x && p.z.abs() <= 2.0 && p.distance(o) < q.distance(o)
                });
                if on_occluder {
                    continue;
                }
                // Where the ray from the light to q crosses the occluder's plane.
                let c = light + (q - light) * ((light.y - 2.0) / (light.y - q.y));
                let margin = 0.05;
                let inside = |m: f32| c.x > occluder.min.x + m && c.x < occluder.max.x - m && c.z.abs() < 2.0 - m;
                let (a, b) = (red(&shadowed, x, y), red(&plain, x, y));
                if inside(margin) {
                    if b > 10 {
                        shadow_checked += 1;
                        assert!(a <= 2, "pixel ({x},{y}) behind the occluder is lit: {a}");
                    }
                } else if !inside(-margin) {
                    lit_checked += 1;
                    assert!(a.abs_diff(b) <= 2, "pixel ({x},{y}) outside the exact shadow darkened: {a} vs {b}");
                }
            }
        }
        println!("spot: {lit_checked} lit and {shadow_checked} shadowed pixels match the exact shadow");
        assert!(lit_checked > 10_000 && shadow_checked > 1_000);
    });
}

// ---------------------------------------------------------------------------------------------
// Out-of-frustum policy (Arneson Fig. 1): a directional light's map is fitted to its casters,
// so casters touch its border; receivers beyond the border must not read the clamped texel.

fn beyond_border_darkened(ctx: &Context, outside_lit: bool) -> usize {
    let towards = Vec3::new(0.0, 1.0, 0.3).normalize();
    let mut s = floor_scene("border", 30.0);
    // A long bar crossing the whole view along x: it touches the fitted map's border in x.
    let bar = s.add_mesh(primitives::cuboid(Vec3::new(3.0, 0.05, 0.3)));
    s.add_object(bar, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)), Vec3::splat(0.3)).receives_shadows = false;
    s.lights.push(shadow_light(towards));
    s.camera = Camera { up: -Vec3::Z, fov_y_deg: 90.0, ..Camera::look_at(Vec3::new(0.0, 6.0, 0.0), Vec3::ZERO) };
    let mut st = settings(256, ShadowFilter::Pcf2x2);
    st.outside_lit = outside_lit;
    let frame = renderer(ctx, common::SIZE, st).render(&s).unwrap();
    let vp = s.camera.view_proj(common::SIZE.0 as f32 / common::SIZE.1 as f32);
    let lit = towards.y * 255.0;
    let mut darkened = 0;
    for y in 0..common::SIZE.1 {
        for x in 0..common::SIZE.0 {
            let (o, d) = pixel_ray(vp, common::SIZE.0, common::SIZE.1, x, y);
            if Box3::around(Vec3::new(0.0, 1.0, 0.0), Vec3::new(3.0, 0.05, 0.3)).hit(o, d).is_some() {
                continue; // the camera sees the bar
            }
            let Some(q) = hit_plane_y(o, d, 0.0) else { continue };
            // Beyond the bar's ends (|x| > 3.5): outside the map's frustum, never in shadow.
            if q.x.abs() > 3.5 && (red(&frame, x, y) as f32) < 0.5 * lit {
                darkened += 1;
            }
        }
    }
    darkened
}

#[test]
fn points_outside_the_frustum_are_explicitly_lit_not_clamped() {
    common::with_context(|ctx| {
        let lit_policy = beyond_border_darkened(ctx, true);
        let shadow_policy = beyond_border_darkened(ctx, false);
        println!("beyond the map's border: {lit_policy} pixels darkened when lit, {shadow_policy} when shadowed");
        assert_eq!(lit_policy, 0, "outside the frustum must be lit by default");
        assert!(shadow_policy > 1000, "the policy switch must change those pixels (so this test can fail)");
    });
}

// ---------------------------------------------------------------------------------------------
// Depth bias: a plane shadowing itself at steep incidence.

/// Pixels of a self-shadowing floor darker than the unshadowed render.
fn acne(ctx: &Context, degrees: f32, st: ShadowMapSettings) -> (usize, usize) {
    let t = degrees.to_radians();
    let mut s = Scene::new("acne");
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    let floor = s.add_mesh(primitives::cuboid(Vec3::new(5.0, 0.05, 5.0)));
    s.add_object(floor, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), Vec3::ONE);
    s.lights.push(shadow_light(Vec3::new(t.sin(), t.cos(), 0.0)));
    s.camera = Camera { up: -Vec3::Z, ..Camera::look_at(Vec3::new(0.0, 6.0, 0.0), Vec3::ZERO) };
    let mut r = renderer(ctx, common::SIZE, st);
    let shadowed = r.render(&s).unwrap();
    s.lights[0].technique = Technique::Unshadowed;
    let plain = r.render(&s).unwrap();
    let floor_pixels = plain.rgba.chunks_exact(4).filter(|p| p[0] > 0).count();
    let dark = shadowed
        .rgba
        .chunks_exact(4)
        .zip(plain.rgba.chunks_exact(4))
        .filter(|(a, b)| u16::from(a[0]) + 3 < u16::from(b[0]))
        .count();
    (dark, floor_pixels)
}

#[test]
fn default_bias_leaves_no_acne_and_zero_bias_shows_it() {
    common::with_context(|ctx| {
        for degrees in [60.0, 75.0] {
            for filter in ShadowFilter::ALL {
                let (dark, floor) = acne(ctx, degrees, settings(1024, filter));
                println!("{degrees} deg, {}: {dark} acne pixels of {floor}", filter.name());
                assert!(floor > 10_000);
                assert_eq!(dark, 0, "{degrees} deg, {}: acne with the default bias", filter.name());
            }
        }
        let zero = ShadowMapSettings {
            bias: DepthBias { constant: 0.0, slope: 0.0, clamp_texels: None },
            ..settings(1024, ShadowFilter::Nearest)
        };
        let (dark, floor) = acne(ctx, 75.0, zero);
        println!("75 deg, zero bias: {dark} acne pixels of {floor}");
        assert!(dark * 20 > floor, "zero bias must show acne on at least 5% of the floor (so the test can fail)");
        // Normal offset alone (no depth bias) moves the lookup off the surface: no acne either.
        let offset = ShadowMapSettings { normal_offset: 0.05, ..zero };
        let (dark, floor) = acne(ctx, 75.0, offset);
        println!("75 deg, zero bias, normal offset 0.05: {dark} acne pixels of {floor}");
        assert_eq!(dark, 0, "a normal offset of 0.05 should remove the acne");
    });
}

#[test]
fn surfaces_facing_a_point_or_spot_light_head_on_show_no_acne() {
    // A wall perpendicular to a cube face's axis (and to a spot's axis) has constant depth in
    // the map: no slope bias helps, only the receiver's relative shrink (lookup.glsl).
    common::with_context(|ctx| {
        // Whether the two depth paths round apart depends on near/far: several light positions.
        let lights = [Vec3::new(3.0, 14.0, -3.0), Vec3::new(3.0, 6.0, -3.0), Vec3::new(-2.0, 9.0, -4.5)];
        for (spot, light) in [false, true].into_iter().flat_map(|s| lights.map(|l| (s, l))) {
            let mut s = Scene::new("head-on wall");
            s.ambient = Vec3::ZERO;
            s.background = Vec3::ZERO;
            let wall = s.add_mesh(primitives::cuboid(Vec3::new(10.0, 5.0, 0.05)));
            s.add_object(wall, Mat4::from_translation(Vec3::new(0.0, 5.0, -10.05)), Vec3::ONE);
            let mut l = if spot { Light::spot(light, -Vec3::Z, 50.0, 60.0, 60.0) } else { Light::point(light, 60.0) };
            l.technique = Technique::ShadowMap;
            s.lights.push(l);
            s.camera = Camera::look_at(Vec3::new(4.0, 5.0, 15.0), Vec3::new(0.0, 3.5, 0.0));
            for resolution in [256, 2048] {
                let mut r = renderer(ctx, common::SIZE, settings(resolution, ShadowFilter::Pcf2x2));
                let shadowed = r.render(&s).unwrap();
                let mut plain_scene = s.clone();
                plain_scene.lights[0].technique = Technique::Unshadowed;
                let plain = r.render(&plain_scene).unwrap();
                let lit = plain.rgba.chunks_exact(4).filter(|p| p[0] > 10).count();
                let pairs = || shadowed.rgba.chunks_exact(4).zip(plain.rgba.chunks_exact(4));
                let darker = pairs().filter(|(a, b)| u16::from(a[0]) + 3 < u16::from(b[0])).count();
                let acne = pairs().filter(|(a, b)| 2 * u16::from(a[0]) < u16::from(b[0])).count();
                let kind = if spot { "spot" } else { "point" };
                println!("{kind} light at {light}, {resolution}^2: {acne} acne pixels, {darker} darker, of {lit} lit");
                assert!(lit > 5_000);
                assert_eq!(acne, 0, "{kind} light at {light}, {resolution}^2: acne (below half brightness)");
                // 2x2 PCF straddling a cube seam compares against the neighbouring face's
                // texels: a few pixels on a seam lose part of their light (docs: known limit).
                assert!(darker * 200 < lit, "{kind} light at {light}, {resolution}^2: {darker} pixels darkened");
            }
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Typed errors.

#[test]
fn bad_resolutions_and_cube_shapes_are_typed_errors() {
    common::with_context(|ctx| {
        let mut s = umbra::scene::load("ball").unwrap();
        s.lights[0].technique = Technique::ShadowMap;
        let max = ctx.capabilities().max_image_dimension_cube;
        for resolution in [0, 32, max + 1] {
            let err = renderer(ctx, common::SIZE, settings(resolution, ShadowFilter::Pcf2x2)).render(&s).unwrap_err();
            println!("{resolution}: {err}");
            assert!(matches!(err, RenderError::InvalidShadowMap { resolution: r, .. } if r == resolution), "{err}");
        }
        // A per-light size overrides the renderer's and is checked the same way.
        s.lights[0].shadow_map_size = Some(16);
        let err = renderer(ctx, common::SIZE, ShadowMapSettings::DEFAULT).render(&s).unwrap_err();
        assert!(matches!(err, RenderError::InvalidShadowMap { resolution: 16, .. }), "{err}");
        // Cube faces must be square.
        let mut cube = ImageDesc::new_cube(vk::Format::D32_SFLOAT, 64).usage(vk::ImageUsageFlags::SAMPLED);
        cube.height = 32;
        let err = Image::new(ctx, "non-square cube", cube).unwrap_err();
        assert!(matches!(err, VkError::InvalidDesc { .. }), "{err}");
    });
}
