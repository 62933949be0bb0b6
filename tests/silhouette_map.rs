//! Silhouette maps against exact geometry: a straight occluder edge at 30° to the map's grid
//! (the silhouette map keeps misclassified pixels within a quarter texel of the true edge, the
//! shadow map at the same resolution does not), a hidden silhouette that must not be stored,
//! degenerate edges that must not store NaNs or points outside their texel, the same straight
//! edge under a point light across a seam of its cube (face atlas), and agreement with shadow
//! volumes on spot-lit and on point-lit scenes.

mod common;

use common::raycast::{distance_to_boundary, hit_plane_y, inside_convex, pixel_ray};
use glam::{Mat4, Quat, Vec2, Vec3};
use umbra::scene::{primitives, Camera, Light, Mesh, Scene, Technique};
use umbra::shadows::{Frame, PixelClass, Renderer, RendererDesc, ShadowFilter, ShadowMapSettings};
use umbra::vk::Context;

const SIZE: u32 = 256;

fn render(ctx: &Context, scene: &Scene, resolution: u32, diagnostics: bool) -> Frame {
    let mut desc = RendererDesc::new(SIZE, SIZE);
    desc.shadow_map =
        ShadowMapSettings { resolution: Some(resolution), filter: ShadowFilter::Nearest, ..ShadowMapSettings::DEFAULT };
    desc.diagnostics = diagnostics;
    Renderer::new(ctx, desc).expect("renderer").render(scene).expect("frame")
}

/// A receiving, non-casting floor at y = 0; no ambient, black background; a directional
/// light straight down (its map's grid runs along world x and z).
fn floor_scene(name: &str, technique: Technique) -> Scene {
    let mut s = Scene::new(name);
    let floor = s.add_mesh(primitives::plane(20.0));
    s.add_object(floor, Mat4::IDENTITY, Vec3::ONE).casts_shadows = false;
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    let mut l = Light::directional(Vec3::Y, 1.0);
    l.technique = technique;
    s.lights.push(l);
    s
}

/// A square caster of half-side `half` centred at `at`, turned `turn_deg` about y, seen by
/// nobody but the light; its corners (x, z).
fn add_square(s: &mut Scene, at: Vec3, turn_deg: f32, half: f32) -> Vec<Vec2> {
    let quad = s.add_mesh(primitives::plane(2.0 * half));
    let t = Mat4::from_rotation_translation(Quat::from_rotation_y(turn_deg.to_radians()), at);
    s.add_object(quad, t, Vec3::splat(0.3)).receives_shadows = false;
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, z)| t.transform_point3(Vec3::new(x * half, 0.0, z * half)))
        .map(|c| Vec2::new(c.x, c.z))
        .collect()
}

/// A camera between the caster and the floor, looking straight down at `centre` (x, z) and
/// seeing `half_width` around it: only the floor is in view.
fn camera_below(centre: Vec2, half_width: f32) -> Camera {
    let eye = Vec3::new(centre.x, 0.5, centre.y);
    let fov = 2.0 * (half_width / eye.y).atan().to_degrees();
    Camera { up: Vec3::Z, fov_y_deg: fov, near: 0.05, far: Some(2.0), ..Camera::look_at(eye, eye - Vec3::Y) }
}

/// Saves `frame` as `{prefix}-{technique}.png` and its classification, where it has one, as
/// `{prefix}-classes.png` in the test's output folder.
fn save_views(frame: &Frame, prefix: &str, technique: &str) {
    let dir = common::output_dir("silhouette_map");
    frame.save_png(&dir.join(format!("{prefix}-{technique}.png"))).unwrap();
    for d in &frame.diagnostics {
        let path = dir.join(format!("{prefix}-classes.png"));
        image::save_buffer(path, &d.classification, SIZE, SIZE, image::ColorType::Rgba8).unwrap();
    }
}

/// World units per texel of the frame's only light (asserting square texels).
fn texel(frame: &Frame) -> f32 {
    let [tx, ty] = frame.report.lights[0].shadow_map.as_ref().and_then(|m| m.texel_size).expect("orthographic map");
    assert!((tx / ty - 1.0).abs() < 0.01, "texels are not square: {tx} x {ty}");
    0.5 * (tx + ty)
}

/// The largest distance, in texels (`texel` gives a texel's world size on the floor at a
/// point), of a misclassified floor pixel from the boundary of the `shadow` polygon, and the
/// numbers of compared and shadowed pixels.
fn worst_misclassified(
    frame: &Frame,
    camera: &Camera,
    shadow: &[Vec2],
    texel: impl Fn(Vec2) -> f32,
) -> (f32, usize, usize) {
    let view_proj = camera.view_proj(1.0);
    let (mut worst, mut compared, mut shadowed) = (0.0f32, 0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (o, d) = pixel_ray(view_proj, SIZE, SIZE, x, y);
            let Some(q) = hit_plane_y(o, d, 0.0) else { continue };
            let q = Vec2::new(q.x, q.z);
            let expected = inside_convex(shadow, q);
            let rendered = frame.pixel(x, y)[0] < 128;
            compared += 1;
            shadowed += usize::from(expected);
            if expected != rendered {
                worst = worst.max(distance_to_boundary(shadow, q) / texel(q));
            }
        }
    }
    (worst, compared, shadowed)
}

#[test]
fn a_straight_edge_at_30_degrees_is_reconstructed_within_a_quarter_texel() {
    common::with_context(|ctx| {
        let resolution = 64;
        let mut errors = Vec::new();
        for technique in [Technique::ShadowMap, Technique::SilhouetteMap] {
            let mut s = floor_scene("edge at 30 degrees", technique);
            let square = add_square(&mut s, Vec3::Y, 30.0, 1.0);
            // The middle of one edge, away from the corners; about 20 texels in view.
            let centre = (square[0] + square[1]) * 0.5;
            s.camera = camera_below(centre, 0.45);
            let frame = render(ctx, &s, resolution, technique == Technique::SilhouetteMap);
            let name = technique.name();
            save_views(&frame, "edge-30", name);
            let texel = texel(&frame);
            let (worst, compared, shadowed) = worst_misclassified(&frame, &s.camera, &square, |_| texel);
            let corner_distance = square.iter().map(|c| c.distance(centre)).fold(f32::INFINITY, f32::min) / texel;
            println!(
                "{name:>14}, {resolution}² map: worst misclassified pixel {worst:.3} texel from the edge \
                 ({shadowed} of {compared} pixels in shadow; nearest corner {corner_distance:.1} texels away)"
            );
            assert!(shadowed > compared / 4 && shadowed < 3 * compared / 4, "the edge crosses the view");
            errors.push(worst);
        }
        let (map, silhouette) = (errors[0], errors[1]);
        assert!((0.35..=1.5).contains(&map), "the shadow map's staircase should reach about a texel, got {map}");
        assert!(silhouette <= 0.25, "silhouette map: a pixel {silhouette} texel from the edge is wrong");
    });
}

/// The 30° edge under a point light, crossing the seam between the cube's −y face (the floor
/// below the light) and its +x face: the face atlas must reconstruct it on both sides of the
/// seam as the 2D map does, without a crack or a doubled edge where the faces meet.
#[test]
fn a_straight_edge_across_a_cube_seam_is_reconstructed_within_a_quarter_texel() {
    common::with_context(|ctx| {
        let (resolution, light_height, caster_height) = (64, 2.0, 1.0);
        let mut errors = Vec::new();
        for technique in [Technique::ShadowMap, Technique::SilhouetteMap] {
            let mut s = floor_scene("edge across a cube seam", technique);
            let mut light = Light::point(Vec3::Y * light_height, 40.0);
            light.technique = technique;
            s.lights = vec![light];
            // The square's shadow is the square scaled by H / (H - h) about the light's foot;
            // place it so its first edge's middle lies on the seam (x = H on the floor).
            let scale = light_height / (light_height - caster_height);
            let edge_middle = Quat::from_rotation_y(30f32.to_radians()) * Vec3::new(0.0, 0.0, -1.0);
            let at = Vec3::new(light_height, 0.0, 0.3) / scale - edge_middle;
            let caster = add_square(&mut s, Vec3::new(at.x, caster_height, at.z), 30.0, 1.0);
            let shadow: Vec<Vec2> = caster.iter().map(|c| *c * scale).collect();
            let seam = (shadow[0] + shadow[1]) * 0.5;
            assert!((seam.x - light_height).abs() < 1e-4, "the edge crosses the seam at {seam}");
            s.camera = camera_below(seam, 0.45);
            let frame = render(ctx, &s, resolution, technique == Technique::SilhouetteMap);
            let name = technique.name();
            save_views(&frame, "edge-seam", name);
            // A texel's smaller side on the floor: 2H / N in the −y face, whose image plane is
            // parallel to the floor; 2m / N at horizontal distance m > H, in a side face.
            let texel = |q: Vec2| 2.0 * q.abs().max_element().max(light_height) / resolution as f32;
            let (worst, compared, shadowed) = worst_misclassified(&frame, &s.camera, &shadow, texel);
            let corner_distance = shadow.iter().map(|c| c.distance(seam)).fold(f32::INFINITY, f32::min) / texel(seam);
            println!(
                "{name:>14}, 6 × {resolution}² cube: worst misclassified pixel {worst:.3} texel from an edge crossing \
                 the −y/+x seam ({shadowed} of {compared} pixels in shadow; nearest corner {corner_distance:.1} texels away)"
            );
            assert!(shadowed > compared / 4 && shadowed < 3 * compared / 4, "the edge crosses the view");
            errors.push(worst);
        }
        let (map, silhouette) = (errors[0], errors[1]);
        assert!((0.35..=1.5).contains(&map), "the shadow map's staircase should reach about a texel, got {map}");
        assert!(silhouette <= 0.25, "silhouette map: a pixel {silhouette} texel from the edge is wrong");
    });
}

#[test]
fn a_hidden_silhouette_is_not_stored_and_does_not_change_the_shadow() {
    common::with_context(|ctx| {
        // A big square at y = 2 hides a smaller turned square at y = 1.2 from the light; the
        // hidden square's edges cross texels whose corners all see the big square.
        let build = |with_hidden: bool| {
            let mut s = floor_scene("hidden silhouette", Technique::SilhouetteMap);
            let big = add_square(&mut s, Vec3::Y * 2.0, 10.0, 1.0);
            if with_hidden {
                add_square(&mut s, Vec3::Y * 1.2, 37.0, 0.55);
            }
            // The big shadow's edge and, inside it, where the hidden square's edges project.
            s.camera = camera_below((big[0] + big[1]) * 0.5 * 0.6, 0.6);
            s
        };
        let without = render(ctx, &build(false), 64, true);
        let with = render(ctx, &build(true), 64, true);
        let texels = |f: &Frame| f.diagnostics[0].silhouette_map.as_ref().expect("read back").silhouette_texels();
        let edges = |f: &Frame| f.report.lights[0].silhouette_map.as_ref().expect("report").silhouette_edges;
        println!(
            "silhouette edges drawn: {} without, {} with the hidden caster; texels holding a point: {} and {}",
            edges(&without),
            edges(&with),
            texels(&without),
            texels(&with)
        );
        with.save_png(&common::output_dir("silhouette_map").join("hidden.png")).unwrap();
        assert!(edges(&with) > edges(&without), "the hidden caster's edges were drawn");
        assert!(texels(&without) > 0);
        assert_eq!(texels(&with), texels(&without), "a hidden silhouette stored points");
        let differing = with.rgba.iter().zip(&without.rgba).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "the hidden caster changed the image");
    });
}

/// A vertical wall and a vertical needle under a light straight down: their edges along the
/// light project to single points, their faces to lines.
fn degenerate_casters(s: &mut Scene) {
    let wall = Mesh::with_flat_normals(
        "wall",
        &[Vec3::new(-0.6, 0.5, 0.2), Vec3::new(0.7, 0.5, -0.1), Vec3::new(0.7, 1.5, -0.1), Vec3::new(-0.6, 1.5, 0.2)],
        &[0, 1, 2, 0, 2, 3],
    )
    .unwrap();
    // A needle, plus a zero-area triangle (a repeated corner) the welding drops.
    let needle = Mesh::with_flat_normals(
        "needle",
        &[Vec3::new(0.3, 0.4, 0.5), Vec3::new(0.3, 1.4, 0.5), Vec3::new(0.3001, 0.9, 0.5)],
        &[0, 1, 2, 0, 0, 1],
    )
    .unwrap();
    for m in [wall, needle] {
        let id = s.add_mesh(m);
        s.add_object(id, Mat4::IDENTITY, Vec3::splat(0.4)).receives_shadows = false;
    }
}

#[test]
fn degenerate_edges_store_no_nan_and_no_point_outside_its_texel() {
    common::with_context(|ctx| {
        let mut s = floor_scene("degenerate edges", Technique::SilhouetteMap);
        degenerate_casters(&mut s);
        add_square(&mut s, Vec3::Y * 2.0, 0.0, 0.1); // keeps the map's extent sane around the needle
        s.camera = camera_below(Vec2::ZERO, 1.0);
        let frame = render(ctx, &s, 128, true);
        let map = frame.diagnostics[0].silhouette_map.as_ref().expect("read back");
        let bad: Vec<_> = map
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| !p.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)))
            .take(5)
            .collect();
        let edges = frame.report.lights[0].silhouette_map.as_ref().map(|m| m.silhouette_edges).unwrap_or(0);
        println!("{edges} edges drawn, {} texels hold a point, bad points: {bad:?}", map.silhouette_texels());
        assert!(map.silhouette_texels() > 0, "the casters' outlines were stored");
        assert!(bad.is_empty(), "points outside [0, 1]² or not finite: {bad:?}");
        assert!(frame.rgba.chunks_exact(4).all(|p| p[3] == 255), "every pixel was written");
    });
}

/// Pixels of shadow receivers (`classes`, a classification view) whose colour differs by more
/// than `tolerance` in any channel.
fn differing(a: &Frame, b: &Frame, classes: &[u8], tolerance: u8) -> usize {
    let receiver = |c: &[u8]| {
        !matches!(PixelClass::decode([c[0], c[1], c[2], c[3]]), PixelClass::NotReceiver | PixelClass::Background)
    };
    a.rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .zip(classes.chunks_exact(4))
        .filter(|((p, q), c)| receiver(c) && p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > tolerance))
        .count()
}

#[test]
fn on_spot_lit_scenes_silhouette_maps_agree_with_shadow_volumes_better_than_shadow_maps() {
    // The largest ratio of the silhouette map's disagreement to the shadow map's: the pins'
    // outlines cross each other in the map (two silhouettes in one texel, Sen Fig. 7).
    agree_with_shadow_volumes(true, &[("cylinder", 0.5), ("pins", 0.8)]);
}

#[test]
fn on_point_lit_scenes_cube_silhouette_maps_agree_with_shadow_volumes_better_than_shadow_maps() {
    // The same scenes with their point lights kept: each light's six faces share one atlas.
    agree_with_shadow_volumes(false, &[("cylinder", 0.5), ("pins", 0.8)]);
}

/// Renders each scene with shadow volumes, a shadow map and a silhouette map (512² per face)
/// and asserts that the silhouette map disagrees with the volumes on fewer than `ratio` times
/// the shadow map's pixels; `spots` turns the scenes' point lights into 80° spots first.
fn agree_with_shadow_volumes(spots: bool, cases: &[(&str, f64)]) {
    common::with_context(|ctx| {
        for &(name, ratio) in cases {
            let mut frames = Vec::new();
            for technique in [Technique::ShadowVolume, Technique::ShadowMap, Technique::SilhouetteMap] {
                let mut s = umbra::scene::procedural::build(name).unwrap();
                if spots {
                    assert_eq!(s.point_lights_to_spots(80.0), vec![0]);
                }
                s.lights[0].technique = technique;
                // Shadows compared on the floor only (the classification view's receivers): on
                // the casters' curved sides, shadow volumes show the mesh's polygonal
                // terminator, which no map-based technique reproduces.
                for o in s.objects.iter_mut().filter(|o| o.name != "floor") {
                    o.receives_shadows = false;
                }
                let frame = render(ctx, &s, 512, technique == Technique::SilhouetteMap);
                let file = format!("{name}-{}{}.png", technique.name(), if spots { "-spot" } else { "-point" });
                frame.save_png(&common::output_dir("silhouette_map").join(file)).unwrap();
                frames.push(frame);
            }
            let classes = &frames[2].diagnostics[0].classification;
            let map = differing(&frames[0], &frames[1], classes, 24);
            let silhouette = differing(&frames[0], &frames[2], classes, 24);
            let fraction = frames[2].report.lights[0].silhouette_map.as_ref().and_then(|m| m.silhouette_fraction);
            println!(
                "{name} (spots {spots}): pixels differing from shadow volumes: shadow map {map}, silhouette map {silhouette} (of {}); \
                 silhouette pixels {:.2}%",
                SIZE * SIZE,
                100.0 * fraction.unwrap_or(0.0)
            );
            assert!(fraction.is_some_and(|f| f > 0.0 && f < 0.2), "{name}: silhouette pixel fraction {fraction:?}");
            assert!(
                (silhouette as f64) < ratio * map as f64,
                "{name}: the silhouette map should disagree less than {ratio} x the shadow map"
            );
            assert!((silhouette as f64) < 0.01 * f64::from(SIZE * SIZE), "{name}: more than 1% of pixels disagree");
        }
    });
}
