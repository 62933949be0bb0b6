//! The reference against shadows known in closed form: a square occluder over a plane, lit by
//! a directional light (the shadow is a parallelogram) and by a point light through a tilted
//! square (a general quadrilateral). Every pixel must agree, except those whose centre projects
//! within `EDGE_TOLERANCE` of the occluder's edge.

use glam::{Mat4, Quat, Vec3, Vec4};
use umbra_reference::{ray_cast_image, SceneBvh, ShadowMask, SurfaceImage};
use umbra_scene::{primitives, Camera, Light, Scene};

const EDGE_TOLERANCE: f32 = 1e-3;
const SIZE: (u32, u32) = (256, 192);

/// A 20 × 20 floor at y = 0, a 2 × 2 square occluder with `transform`, and `light`.
fn scene(transform: Mat4, light: Light) -> Scene {
    let mut scene = Scene::new("analytic");
    let floor = scene.add_mesh(primitives::plane(20.0));
    let square = scene.add_mesh(primitives::plane(2.0));
    scene.add_object(floor, Mat4::IDENTITY, Vec3::splat(0.8));
    scene.add_object(square, transform, Vec3::splat(0.8));
    scene.lights.push(light);
    scene.camera = Camera::look_at(Vec3::new(0.0, 9.0, 9.0), Vec3::ZERO);
    scene
}

/// Where the segment from `p` to the light crosses the square's plane, in the square's local
/// coordinates, if it does between them: shadowed when inside (-1, 1)², on the edge within the
/// tolerance.
fn analytic(transform: Mat4, light: Vec4, p: Vec3) -> Option<(f32, f32)> {
    let inv = transform.inverse();
    let local = inv.transform_point3(p);
    let towards = if light.w == 0.0 {
        inv.transform_vector3(light.truncate())
    } else {
        inv.transform_point3(light.truncate() / light.w) - local
    };
    let t = -local.y / towards.y;
    let limit = if light.w == 0.0 { f32::INFINITY } else { 1.0 };
    (t > 0.0 && t < limit).then(|| {
        let hit = local + towards * t;
        (hit.x, hit.z)
    })
}

fn check(transform: Mat4, light: Light) -> (u64, u64) {
    let position = light.position;
    let s = scene(transform, light);
    let bvh = SceneBvh::build(&s);
    let surfaces = SurfaceImage::ray_cast(&s, &bvh, SIZE.0, SIZE.1);
    let mask = ShadowMask::reference(&s, &bvh, 0, &surfaces).expect("light 0");
    let (mut agree, mut on_edge) = (0, 0);
    for (i, surface) in surfaces.pixels.iter().enumerate() {
        let Some(surface) = surface else { continue };
        if surface.object != 0 {
            continue; // the occluder itself
        }
        let got = mask.shadowed[i].expect("the floor faces the light and receives shadows");
        let expected = match analytic(transform, position, surface.position) {
            Some((u, v)) => {
                let outside = (u.abs() - 1.0).max(v.abs() - 1.0);
                if outside.abs() < EDGE_TOLERANCE {
                    on_edge += 1;
                    continue;
                }
                outside < 0.0
            }
            None => false,
        };
        assert_eq!(got, expected, "pixel {i} at {:?}", surface.position);
        agree += 1;
    }
    (agree, on_edge)
}

#[test]
fn directional_light_casts_the_exact_parallelogram() {
    let square = Mat4::from_translation(Vec3::new(0.5, 2.0, -0.5));
    let (agree, on_edge) = check(square, Light::directional(Vec3::new(0.6, 1.0, 0.3), 1.0));
    println!("directional: {agree} floor pixels agree, {on_edge} on the edge excepted");
    assert!(agree > 30_000, "{agree}");
    assert!(on_edge < 20, "{on_edge}");
}

#[test]
fn point_light_through_a_tilted_square() {
    let square = Mat4::from_rotation_translation(
        Quat::from_rotation_x(0.4) * Quat::from_rotation_y(0.3),
        Vec3::new(0.0, 1.5, 0.0),
    );
    let (agree, on_edge) = check(square, Light::point(Vec3::new(-1.0, 5.0, 1.0), 20.0));
    println!("point: {agree} floor pixels agree, {on_edge} on the edge excepted");
    assert!(agree > 30_000, "{agree}");
    assert!(on_edge < 20, "{on_edge}");
}

#[test]
fn gbuffer_and_ray_cast_surfaces_give_the_same_mask() {
    let s = scene(Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)), Light::directional(Vec3::new(0.3, 1.0, 0.2), 1.0));
    let bvh = SceneBvh::build(&s);
    let cast = SurfaceImage::ray_cast(&s, &bvh, SIZE.0, SIZE.1);
    // The same surfaces packed as the renderer's G-buffer packs them.
    let position: Vec<[f32; 4]> = cast
        .pixels
        .iter()
        .map(|p| p.map_or([0.0; 4], |p| [p.position.x, p.position.y, p.position.z, p.object as f32 + 1.0]))
        .collect();
    let normal: Vec<[f32; 4]> =
        cast.pixels.iter().map(|p| p.map_or([0.0; 4], |p| p.normal.extend(0.0).to_array())).collect();
    let read = SurfaceImage::from_gbuffer(SIZE.0, SIZE.1, &position, &normal).expect("sizes");
    assert_eq!(read.pixels, cast.pixels);
    let a = ShadowMask::reference(&s, &bvh, 0, &cast).expect("light");
    let b = ShadowMask::reference(&s, &bvh, 0, &read).expect("light");
    assert_eq!(a, b);
    assert!(SurfaceImage::from_gbuffer(SIZE.0, SIZE.1, &position[1..], &normal).is_err());
}

#[test]
fn ray_cast_render_is_lit_and_shadowed() {
    let s = scene(Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)), Light::directional(Vec3::new(0.0, 1.0, 0.0), 1.0));
    let bvh = SceneBvh::build(&s);
    let rgba = ray_cast_image(&s, &bvh, SIZE.0, SIZE.1);
    assert_eq!(rgba.len(), (SIZE.0 * SIZE.1 * 4) as usize);
    // Light straight down (N.L = 1 on the floor): a lit floor pixel is albedo * (1 + ambient),
    // a shadowed one albedo * ambient; the mask says which.
    let surfaces = SurfaceImage::ray_cast(&s, &bvh, SIZE.0, SIZE.1);
    let mask = ShadowMask::reference(&s, &bvh, 0, &surfaces).expect("light");
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let (lit, dark) = (byte(0.8 * (1.0 + s.ambient.x)), byte(0.8 * s.ambient.x));
    let (mut seen_lit, mut seen_dark) = (0, 0);
    for (i, surface) in surfaces.pixels.iter().enumerate() {
        if surface.is_some_and(|p| p.object == 0) {
            let expected = if mask.shadowed[i] == Some(true) { dark } else { lit };
            assert_eq!(rgba[4 * i], expected, "pixel {i}");
            seen_lit += usize::from(expected == lit);
            seen_dark += usize::from(expected == dark);
        }
    }
    assert!(seen_lit > 10_000 && seen_dark > 500, "{seen_lit} lit, {seen_dark} shadowed floor pixels");
}
