//! Clipping clip-space triangles on the host, to the region 0 ≤ z and |x|, |y| ≤ g·w, so that
//! the driver's own clipper never runs when g < 1. Every cut point of an original edge is
//! computed from that edge's endpoints in one canonical order (by their bit patterns), so two
//! triangles sharing the edge get the same point; the pieces are fanned back into triangles.
//! It works on host clip-space positions with a bound `g` of the test's choosing, so the tests
//! can measure the formulation at the Vulkan level, apart from the renderer's own
//! (`umbra_shadows` `shadow_volume/clip.rs`, which keeps the GPU's vertices and a fixed bound).

use glam::Vec4;

type P = [f64; 4];

/// The clip planes as distances (inside where ≥ 0) for the bound `g`.
const PLANES: [fn(&P, f64) -> f64; 5] =
    [|p, _| p[2], |p, g| g * p[3] - p[0], |p, g| g * p[3] + p[0], |p, g| g * p[3] - p[1], |p, g| g * p[3] + p[1]];

#[derive(Clone, Copy)]
struct V {
    p: P,
    f: Vec4,
}

fn key(v: Vec4) -> [u32; 4] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits(), v.w.to_bits()]
}

/// `triangles` (three clip-space vertices each) clipped to 0 ≤ z, |x| ≤ g·w, |y| ≤ g·w.
pub fn clip_inside_view(triangles: &[Vec4], g: f64) -> Vec<Vec4> {
    let wide = |v: Vec4| V { p: [v.x as f64, v.y as f64, v.z as f64, v.w as f64], f: v };
    let inside = |v: &V| PLANES.iter().all(|d| d(&v.p, g) >= 0.0);
    let mut out = Vec::new();
    for t in triangles.chunks_exact(3) {
        let mut poly: Vec<V> = t.iter().map(|&v| wide(v)).collect();
        if poly.iter().all(inside) {
            out.extend_from_slice(t);
            continue;
        }
        for plane in PLANES {
            let mut next = Vec::new();
            for i in 0..poly.len() {
                let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                let (da, db) = (plane(&a.p, g), plane(&b.p, g));
                if da >= 0.0 {
                    next.push(a);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    let (u, v, du, dv) = if key(a.f) <= key(b.f) { (a, b, da, db) } else { (b, a, db, da) };
                    let s = du / (du - dv);
                    let p: P = std::array::from_fn(|k| u.p[k] + s * (v.p[k] - u.p[k]));
                    next.push(V { p, f: Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32) });
                }
            }
            poly = next;
        }
        for i in 1..poly.len().saturating_sub(1) {
            out.extend([poly[0].f, poly[i].f, poly[i + 1].f]);
        }
    }
    out
}
