//! Procedural stand-ins for the papers' scenes, with their triangle counts and shadow
//! complexity: `cylinder` and `ball` on a plane (Chan–Durand Fig. 1), `cubes` (~12k triangles
//! of cubes above a floor and walls), `cage` (bars around a blob, ~12k), `tree` (~40k
//! triangles of thin branches) and `pins` (ten bowling pins of 450 triangles, Sen's STRIKE).
//! Each is lit by one point light and seen by a camera facing the light, as in the papers.
//! `plaza` is the frame planner's scene (issue #9): eight groups of pillars in a ring, each
//! under its own bounded light (every technique and `auto` among them), seen by a camera that
//! frames two of the groups, so only two lights can change the image.

use crate::error::{SceneError, SceneResult};
use crate::primitives::{cuboid, cylinder, cylinder_between, displaced_sphere, lathe, sphere};
use crate::{Camera, Light, Mesh, Scene};
use glam::{Mat4, Quat, Vec2, Vec3};
use std::f32::consts::TAU;

/// Names accepted by [`build`].
pub const NAMES: &[&str] = &["cylinder", "ball", "cubes", "cage", "tree", "pins", "plaza"];

/// Builds the procedural scene `name`.
pub fn build(name: &str) -> SceneResult<Scene> {
    let scene = match name {
        "cylinder" => cylinder_scene(),
        "ball" => ball_scene(),
        "cubes" => cubes_scene(),
        "cage" => cage_scene(),
        "tree" => tree_scene(),
        "pins" => pins_scene(),
        "plaza" => plaza_scene(),
        _ => return Err(SceneError::UnknownScene(name.to_owned())),
    };
    scene.validate()?;
    Ok(scene)
}

/// A tiny deterministic generator (xorshift) so scenes are identical on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
}

const FLOOR: Vec3 = Vec3::new(0.75, 0.75, 0.72);

/// A closed floor slab whose top face is y = 0.
fn add_floor(scene: &mut Scene, half: f32) {
    let mut m = cuboid(Vec3::new(half, 0.05, half));
    m.name = "floor".into();
    let id = scene.add_mesh(m);
    scene.add_object(id, Mat4::from_translation(Vec3::new(0.0, -0.05, 0.0)), FLOOR).name = "floor".into();
}

/// A point light whose radiance at `reference` (at normal incidence) is about 1.
fn point_light(scene: &mut Scene, position: Vec3, reference: Vec3) {
    let mut l = Light::point(position, position.distance_squared(reference));
    l.name = "key".into();
    scene.lights.push(l);
}

fn add(scene: &mut Scene, mut mesh: Mesh, name: &str, transform: Mat4, albedo: Vec3) {
    mesh.name = name.into();
    let id = scene.add_mesh(mesh);
    scene.add_object(id, transform, albedo).name = name.into();
}

/// Eight pillar groups on a ring of radius 14, each under a light of range 5 three units
/// above it; the camera frames groups 1 and 2 (at 45° and 90°).
fn plaza_scene() -> Scene {
    use crate::Technique;
    let mut s = Scene::new("plaza");
    add_floor(&mut s, 20.0);
    let techniques = [
        Technique::ShadowMap,
        Technique::ShadowVolume,
        Technique::Hybrid,
        Technique::SilhouetteMap,
        Technique::Auto,
        Technique::ShadowVolume,
        Technique::ShadowMap,
        Technique::Hybrid,
    ];
    let pillar = cuboid(Vec3::new(0.25, 1.0, 0.25));
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    for (k, &technique) in techniques.iter().enumerate() {
        let angle = k as f32 * TAU / 8.0;
        let centre = Vec3::new(angle.cos(), 0.0, angle.sin()) * 14.0;
        let mut group = Mesh::default();
        for _ in 0..5 {
            let at = centre + Vec3::new(rng.range(-1.8, 1.8), 1.0, rng.range(-1.8, 1.8));
            let turn = Mat4::from_rotation_translation(Quat::from_rotation_y(rng.range(0.0, TAU)), at);
            group.append(&pillar.clone().transformed(turn));
        }
        group.append(&sphere(0.5, 24, 12).transformed(Mat4::from_translation(centre + Vec3::new(0.0, 2.6, 0.0))));
        add(&mut s, group, &format!("group {k}"), Mat4::IDENTITY, Vec3::new(0.8, 0.6, 0.35));
        let position = centre + Vec3::new(1.0, 4.0, 0.5);
        // Odd groups get spots, even ones point lights.
        let mut l = if k % 2 == 1 {
            Light::spot(position, centre - position, 40.0, 55.0, 16.0)
        } else {
            Light::point(position, 16.0)
        };
        l.range = Some(7.0);
        l.technique = technique;
        l.name = format!("lamp {k}");
        s.lights.push(l);
    }
    s.ambient = Vec3::splat(0.08);
    s.camera = Camera::look_at(Vec3::new(2.0, 9.0, 2.0), Vec3::new(6.0, 0.0, 11.0));
    s
}

fn cylinder_scene() -> Scene {
    let mut s = Scene::new("cylinder");
    add_floor(&mut s, 5.0);
    add(&mut s, cylinder(0.6, 2.0, 64), "cylinder", Mat4::IDENTITY, Vec3::new(0.8, 0.35, 0.25));
    point_light(&mut s, Vec3::new(2.5, 5.0, 1.5), Vec3::ZERO);
    s.camera = Camera::look_at(Vec3::new(-3.5, 3.2, -4.5), Vec3::new(0.0, 0.6, 0.0));
    s
}

fn ball_scene() -> Scene {
    let mut s = Scene::new("ball");
    add_floor(&mut s, 5.0);
    add(
        &mut s,
        sphere(1.0, 48, 24),
        "ball",
        Mat4::from_translation(Vec3::new(0.0, 1.4, 0.0)),
        Vec3::new(0.3, 0.5, 0.8),
    );
    point_light(&mut s, Vec3::new(1.5, 6.0, 1.0), Vec3::ZERO);
    s.camera = Camera::look_at(Vec3::new(-2.5, 4.0, -5.5), Vec3::new(0.0, 0.7, 0.0));
    s
}

fn cubes_scene() -> Scene {
    let mut s = Scene::new("cubes");
    add_floor(&mut s, 10.0);
    let wall = Vec3::new(0.7, 0.72, 0.75);
    add(
        &mut s,
        cuboid(Vec3::new(10.0, 5.0, 0.05)),
        "back wall",
        Mat4::from_translation(Vec3::new(0.0, 5.0, -10.05)),
        wall,
    );
    add(
        &mut s,
        cuboid(Vec3::new(0.05, 5.0, 10.0)),
        "left wall",
        Mat4::from_translation(Vec3::new(-10.05, 5.0, 0.0)),
        wall,
    );
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut cubes = Mesh::default();
    for i in 0..9 {
        for j in 0..12 {
            for k in 0..9 {
                let centre = Vec3::new(-6.0 + 1.5 * i as f32, 1.0 + 0.55 * j as f32, -6.0 + 1.5 * k as f32)
                    + Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.1, 0.1), rng.range(-0.3, 0.3));
                let size = rng.range(0.12, 0.3);
                let rotation = Quat::from_euler(glam::EulerRot::XYZ, rng.range(0.0, TAU), rng.range(0.0, TAU), 0.0);
                cubes.append(&cuboid(Vec3::splat(size)).transformed(Mat4::from_rotation_translation(rotation, centre)));
            }
        }
    }
    add(&mut s, cubes, "cubes", Mat4::IDENTITY, Vec3::new(0.85, 0.55, 0.3));
    point_light(&mut s, Vec3::new(3.0, 14.0, -3.0), Vec3::ZERO);
    s.camera = Camera::look_at(Vec3::new(4.0, 5.0, 15.0), Vec3::new(0.0, 3.5, 0.0));
    s
}

fn cage_scene() -> Scene {
    let mut s = Scene::new("cage");
    add_floor(&mut s, 6.0);
    let blob = displaced_sphere(1.0, 64, 72, |theta, phi| 1.0 + 0.18 * (3.0 * theta).sin() * (4.0 * phi).sin());
    add(&mut s, blob, "blob", Mat4::from_translation(Vec3::new(0.0, 1.6, 0.0)), Vec3::new(0.55, 0.75, 0.35));
    let (radius, bars, bar) = (1.8, 24, 0.045);
    let mut cage = Mesh::default();
    let at = |i: u32, y: f32| {
        let t = TAU * i as f32 / bars as f32;
        Vec3::new(radius * t.cos(), y, radius * t.sin())
    };
    for i in 0..bars {
        cage.append(&cylinder_between(at(i, 0.0), at(i, 3.4), bar, 8));
        for y in [0.9, 2.1, 3.3] {
            cage.append(&cylinder_between(at(i, y), at(i + 1, y), bar, 8));
        }
    }
    add(&mut s, cage, "cage", Mat4::IDENTITY, Vec3::new(0.5, 0.5, 0.55));
    point_light(&mut s, Vec3::new(-1.0, 6.5, -2.0), Vec3::ZERO);
    s.camera = Camera::look_at(Vec3::new(2.5, 3.0, 5.5), Vec3::new(0.0, 1.4, 0.0));
    s
}

fn tree_scene() -> Scene {
    let mut s = Scene::new("tree");
    add_floor(&mut s, 8.0);
    add(&mut s, tree(TREE_SEED, 7), "tree", Mat4::IDENTITY, Vec3::new(0.45, 0.33, 0.2));
    point_light(&mut s, Vec3::new(2.0, 9.0, -3.0), Vec3::ZERO);
    s.camera = Camera::look_at(Vec3::new(-3.0, 3.0, 7.5), Vec3::new(0.0, 2.3, 0.0));
    s
}

/// The seed of the `tree` scene's tree.
pub const TREE_SEED: u64 = 0xD1B5_4A32_D192_ED03;

/// A branching tree of closed triangular prisms standing at the origin, 1.6 high at the
/// trunk, `depth` levels of three children each (3^depth twigs: thin, many-edged geometry),
/// shaped by `seed` (non-zero).
pub fn tree(seed: u64, depth: u32) -> Mesh {
    let mut rng = Rng(seed.max(1));
    let mut tree = Mesh::default();
    grow(&mut tree, &mut rng, Vec3::ZERO, Vec3::Y, 1.6, 0.12, depth);
    tree.name = "tree".into();
    tree
}

/// One branch (a closed triangular prism) and, below `depth`, three children.
fn grow(out: &mut Mesh, rng: &mut Rng, from: Vec3, dir: Vec3, len: f32, radius: f32, depth: u32) {
    let to = from + dir * len;
    out.append(&cylinder_between(from, to, radius, 3));
    if depth == 0 {
        return;
    }
    let side = dir.any_orthonormal_vector();
    let spin = rng.range(0.0, TAU);
    for k in 0..3 {
        let azimuth = Quat::from_axis_angle(dir, spin + TAU * k as f32 / 3.0);
        let tilt = Quat::from_axis_angle(azimuth * side, rng.range(0.45, 0.75));
        let child = (tilt * dir + Vec3::Y * 0.15).normalize();
        let child_len = len * rng.range(0.66, 0.78);
        grow(out, rng, to, child, child_len, radius * 0.62, depth - 1);
    }
}

/// A bowling pin: a 17-point profile turned with 15 segments = 450 triangles.
fn pin() -> Mesh {
    const PROFILE: [(f32, f32); 17] = [
        (0.0, 0.0),
        (0.13, 0.0),
        (0.17, 0.1),
        (0.2, 0.3),
        (0.21, 0.45),
        (0.19, 0.6),
        (0.14, 0.75),
        (0.09, 0.88),
        (0.075, 0.98),
        (0.08, 1.08),
        (0.1, 1.18),
        (0.11, 1.27),
        (0.105, 1.35),
        (0.09, 1.42),
        (0.065, 1.47),
        (0.035, 1.5),
        (0.0, 1.51),
    ];
    let profile: Vec<Vec2> = PROFILE.iter().map(|&(r, y)| Vec2::new(r, y)).collect();
    lathe(&profile, 15, false)
}

fn pins_scene() -> Scene {
    let mut s = Scene::new("pins");
    add_floor(&mut s, 4.0);
    let mut p = pin();
    p.name = "pin".into();
    let id = s.add_mesh(p);
    let mut n = 0;
    for row in 0..4 {
        for i in 0..=row {
            let x = (i as f32 - row as f32 * 0.5) * 0.6;
            let z = -(row as f32) * 0.52;
            n += 1;
            s.add_object(id, Mat4::from_translation(Vec3::new(x, 0.0, z)), Vec3::new(0.92, 0.9, 0.86)).name =
                format!("pin {n}");
        }
    }
    point_light(&mut s, Vec3::new(-1.8, 4.0, 1.5), Vec3::new(0.0, 0.0, -0.8));
    s.camera = Camera::look_at(Vec3::new(0.8, 1.6, 3.0), Vec3::new(0.0, 0.6, -0.8));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_counts_match_the_papers_scenes() {
        let count = |n: &str| build(n).unwrap().triangle_count();
        let cubes = count("cubes");
        assert!((11_000..13_500).contains(&cubes), "cubes {cubes}");
        let cage = count("cage");
        assert!((11_000..13_500).contains(&cage), "cage {cage}");
        let tree = count("tree");
        assert!((37_000..43_000).contains(&tree), "tree {tree}");
        assert_eq!(build("pins").unwrap().meshes[1].triangle_count(), 450);
    }

    #[test]
    fn every_procedural_scene_builds_and_has_a_light() {
        for name in NAMES {
            let s = build(name).unwrap();
            assert!(!s.lights.is_empty() && !s.objects.is_empty(), "{name}");
        }
        assert!(matches!(build("nope"), Err(SceneError::UnknownScene(_))));
    }
}
