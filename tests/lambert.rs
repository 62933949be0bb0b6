//! The forward passes obey Lambert's law, and lights add exactly their own contribution.

mod common;

use glam::Vec3;
use umbra::scene::{primitives, Camera, Light, Scene};
use umbra::shadows::{Frame, Renderer, RendererDesc};

const ALBEDO: f32 = 0.8;

/// A large plane at y = 0 seen from straight above, no ambient, black background.
fn plane_scene(lights: Vec<Light>) -> Scene {
    let mut s = Scene::new("lambert plane");
    let id = s.add_mesh(primitives::plane(40.0));
    s.add_object(id, glam::Mat4::IDENTITY, Vec3::splat(ALBEDO));
    s.camera = Camera { up: -Vec3::Z, ..Camera::look_at(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO) };
    s.ambient = Vec3::ZERO;
    s.background = Vec3::ZERO;
    s.lights = lights;
    s
}

/// A directional light `degrees` away from the plane's normal (+Y), tilted towards +X.
fn light_at(degrees: f32, intensity: f32, color: Vec3) -> Light {
    let t = degrees.to_radians();
    let mut l = Light::directional(Vec3::new(t.sin(), t.cos(), 0.0), intensity);
    l.color = color;
    l
}

fn render(renderer: &mut Renderer, lights: Vec<Light>) -> Frame {
    renderer.render(&plane_scene(lights)).expect("render")
}

/// The largest per-channel difference from `expected` (in 0..1 units) over every pixel.
fn max_error(frame: &Frame, expected: Vec3) -> f32 {
    let want = expected.to_array().map(|v| v.clamp(0.0, 1.0) * 255.0);
    frame.rgba.chunks_exact(4).flat_map(|p| (0..3).map(move |c| (p[c] as f32 - want[c]).abs())).fold(0.0, f32::max)
        / 255.0
}

#[test]
fn pixel_values_follow_lamberts_law_within_2_of_255() {
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        for degrees in [0.0f32, 30.0, 60.0, 75.0, 100.0] {
            let frame = render(&mut r, vec![light_at(degrees, 1.0, Vec3::ONE)]);
            let expected = Vec3::splat(ALBEDO * degrees.to_radians().cos().max(0.0));
            let err = max_error(&frame, expected);
            println!(
                "light at {degrees:5.1} deg: expected {:.4}, max error {:.4} ({:.2}/255)",
                expected.x,
                err,
                err * 255.0
            );
            assert!(err <= 2.0 / 255.0, "light at {degrees} deg: max error {err} > 2/255");
            if degrees == 60.0 {
                frame.save_png(&common::output_dir("lambert").join("plane-60deg.png")).unwrap();
            }
        }
    });
}

#[test]
fn a_second_light_adds_exactly_its_own_contribution() {
    common::with_context(|ctx| {
        let mut r = Renderer::new(ctx, RendererDesc::new(common::SIZE.0, common::SIZE.1)).unwrap();
        let first = light_at(60.0, 1.0, Vec3::ONE);
        let second = light_at(-30.0, 0.5, Vec3::new(1.0, 0.5, 0.25));
        let one = render(&mut r, vec![first.clone()]);
        let only_second = render(&mut r, vec![second.clone()]);
        let both = render(&mut r, vec![first, second]);
        let c1 = Vec3::splat(ALBEDO * 0.5);
        let c2 = ALBEDO * 0.5 * 30f32.to_radians().cos() * Vec3::new(1.0, 0.5, 0.25);
        assert!(max_error(&one, c1) <= 2.0 / 255.0);
        assert!(max_error(&only_second, c2) <= 2.0 / 255.0);
        let err = max_error(&both, c1 + c2);
        println!("two lights: expected {:?}, max error {:.2}/255", c1 + c2, err * 255.0);
        assert!(err <= 2.0 / 255.0, "sum of two lights off by {err}");
        // Pixel by pixel, both = one + only_second (within the two 8-bit roundings).
        for ((b, o), s) in both.rgba.chunks_exact(4).zip(one.rgba.chunks_exact(4)).zip(only_second.rgba.chunks_exact(4))
        {
            for c in 0..3 {
                let diff = b[c] as i32 - (o[c] as i32 + s[c] as i32);
                assert!(diff.abs() <= 1, "channel {c}: {} != {} + {}", b[c], o[c], s[c]);
            }
        }
        assert_eq!(both.report.passes.iter().filter(|p| p.light.is_some()).count(), 2);
    });
}
