//! Procedural meshes: planes, boxes, spheres, cylinders and lathes (surfaces of revolution).
//! Every mesh is closed unless its name says otherwise, and winds counter-clockwise outward.
//! Segment and ring counts are clamped to `3..=`[`MAX_SEGMENTS`] (rings `2..=`); scene files
//! refuse values outside those ranges instead.

pub use crate::limits::MAX_SEGMENTS;
use crate::mesh::Mesh;
use glam::{Mat4, Quat, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Builds a mesh from generated parts; generators only produce valid indices.
fn assemble(name: &str, positions: Vec<Vec3>, normals: Vec<Vec3>, indices: Vec<u32>) -> Mesh {
    Mesh::from_parts(name.to_owned(), positions, normals, indices)
}

/// A square in the XZ plane at y = 0, `size` wide, facing +Y (open: one-sided).
pub fn plane(size: f32) -> Mesh {
    let h = size * 0.5;
    let positions = vec![Vec3::new(-h, 0.0, -h), Vec3::new(-h, 0.0, h), Vec3::new(h, 0.0, h), Vec3::new(h, 0.0, -h)];
    assemble("plane", positions, vec![Vec3::Y; 4], vec![0, 1, 2, 0, 2, 3])
}

/// An axis-aligned box centred on the origin with the given half extents (24 vertices,
/// 12 triangles, flat normals).
pub fn cuboid(half: Vec3) -> Mesh {
    let mut m = assemble("box", vec![], vec![], vec![]);
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let mut u = Vec3::ZERO;
            u[(axis + 1) % 3] = 1.0;
            let v = n.cross(u);
            let (hu, hv) = (u * half.dot(u.abs()), v * half.dot(v.abs()));
            let c = n * half[axis];
            let base = m.positions.len() as u32;
            m.positions.extend([c - hu - hv, c + hu - hv, c + hu + hv, c - hu + hv]);
            m.normals.extend([n; 4]);
            m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    m
}

/// A UV sphere of `radius` with `segments` around and `rings` from pole to pole.
pub fn sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
    displaced_sphere(radius, segments, rings, |_, _| 1.0)
}

/// A UV sphere whose radius is scaled by `scale(theta, phi)`; smooth normals. Closed: one
/// vertex per pole and the seam column shared, so welding by position finds no boundary.
pub fn displaced_sphere(radius: f32, segments: u32, rings: u32, scale: impl Fn(f32, f32) -> f32) -> Mesh {
    let (segments, rings) = (segments.clamp(3, MAX_SEGMENTS), rings.clamp(2, MAX_SEGMENTS));
    let mut positions = vec![Vec3::Y * radius * scale(0.0, 0.0)];
    for i in 1..rings {
        let phi = PI * i as f32 / rings as f32;
        for j in 0..segments {
            let theta = TAU * j as f32 / segments as f32;
            let dir = Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin());
            positions.push(dir * radius * scale(theta, phi));
        }
    }
    positions.push(-Vec3::Y * radius * scale(0.0, PI));
    let south = positions.len() as u32 - 1;
    let at = |i: u32, j: u32| match i {
        0 => 0,
        i if i == rings => south,
        i => 1 + (i - 1) * segments + j % segments,
    };
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if i != 0 {
                indices.extend([a, d, b]);
            }
            if i != rings - 1 {
                indices.extend([d, c, b]);
            }
        }
    }
    let mut m = Mesh::with_smooth_normals("sphere", positions, indices).unwrap_or_default();
    m.name = "sphere".into();
    m
}

/// A closed cylinder of `radius` from y = 0 to y = `height`, with flat caps.
pub fn cylinder(radius: f32, height: f32, segments: u32) -> Mesh {
    lathe(
        &[Vec2::new(0.0, 0.0), Vec2::new(radius, 0.0), Vec2::new(radius, height), Vec2::new(0.0, height)],
        segments,
        true,
    )
}

/// A closed cylinder of `radius` from `a` to `b` (branches, bars).
pub fn cylinder_between(a: Vec3, b: Vec3, radius: f32, segments: u32) -> Mesh {
    let axis = b - a;
    let len = axis.length();
    let rotation = Quat::from_rotation_arc(Vec3::Y, axis / len.max(1e-12));
    cylinder(radius, len, segments).transformed(Mat4::from_rotation_translation(rotation, a))
}

/// A surface of revolution about +Y of `profile` points `(radius, y)` listed bottom to top,
/// `segments` around. Profile ends at radius 0 close the surface with a fan. With `creased`,
/// every profile segment gets its own vertices (flat-shaded bands, for caps and cylinders);
/// otherwise normals are smooth.
pub fn lathe(profile: &[Vec2], segments: u32, creased: bool) -> Mesh {
    let segments = segments.clamp(3, MAX_SEGMENTS);
    let bands: Vec<[Vec2; 2]> = profile.windows(2).map(|w| [w[0], w[1]]).collect();
    let mut m = Mesh { name: "lathe".into(), ..Default::default() };
    let ring = |p: Vec2, j: u32| {
        let t = TAU * (j % segments) as f32 / segments as f32;
        Vec3::new(p.x * t.cos(), p.y, p.x * t.sin())
    };
    if creased {
        for [lo, hi] in bands {
            let mut band = Mesh::default();
            band_triangles(&mut band, lo, hi, segments, ring);
            m.append(&Mesh::with_flat_normals("", &band.positions, &band.indices).unwrap_or_default());
        }
        return m;
    }
    let mut positions = Vec::new();
    for p in profile {
        for j in 0..=segments {
            positions.push(ring(*p, j));
        }
    }
    let stride = segments + 1;
    let mut indices = Vec::new();
    for k in 0..profile.len().saturating_sub(1) as u32 {
        for j in 0..segments {
            let (a, b, c, d) = (k * stride + j, k * stride + j + 1, (k + 1) * stride + j + 1, (k + 1) * stride + j);
            if profile[k as usize].x > 0.0 {
                indices.extend([a, d, b]);
            }
            if profile[k as usize + 1].x > 0.0 {
                indices.extend([d, c, b]);
            }
        }
    }
    Mesh::with_smooth_normals("lathe", positions, indices).unwrap_or_default()
}

/// Triangles of one profile band `lo → hi` (positions unshared), skipping degenerate ones.
fn band_triangles(out: &mut Mesh, lo: Vec2, hi: Vec2, segments: u32, ring: impl Fn(Vec2, u32) -> Vec3) {
    for j in 0..segments {
        let (a, b, c, d) = (ring(lo, j), ring(lo, j + 1), ring(hi, j + 1), ring(hi, j));
        let base = out.positions.len() as u32;
        out.positions.extend([a, b, c, d]);
        if lo.x > 0.0 {
            out.indices.extend([base, base + 3, base + 1]);
        }
        if hi.x > 0.0 {
            out.indices.extend([base + 3, base + 2, base + 1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume by the divergence theorem: positive when faces wind outward.
    fn volume(m: &Mesh) -> f32 {
        m.indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn closed_primitives_have_their_analytic_volume() {
        let b = cuboid(Vec3::new(1.0, 2.0, 3.0));
        assert!((volume(&b) - 48.0).abs() < 1e-3, "box {}", volume(&b));
        let s = sphere(1.0, 64, 32);
        assert!((volume(&s) - 4.0 / 3.0 * PI).abs() < 0.05, "sphere {}", volume(&s));
        let c = cylinder(1.0, 2.0, 64);
        assert!((volume(&c) - 2.0 * PI).abs() < 0.05, "cylinder {}", volume(&c));
        let c = cylinder_between(Vec3::ONE, Vec3::new(1.0, 1.0, 3.0), 1.0, 64);
        assert!((volume(&c) - 2.0 * PI).abs() < 0.05, "oriented cylinder {}", volume(&c));
    }

    #[test]
    fn normals_point_outward() {
        for m in [cuboid(Vec3::ONE), sphere(1.0, 16, 8), cylinder(1.0, 1.0, 12)] {
            let centre = m.bounds().center();
            for tri in m.indices.chunks_exact(3) {
                let i = tri[0] as usize;
                assert!(m.normals[i].dot(m.positions[i] - centre) > -1e-4, "{}: inward normal", m.name);
            }
        }
    }
}
