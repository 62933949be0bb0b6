//! The silhouette map's geometry on the CPU: the reference the shaders mirror, and what the
//! tests check against (Sen, Cammarano, Hanrahan 2003, §3.1–3.2).
//!
//! Coordinates are **texel-local** on the silhouette map's dual grid: a silhouette texel is the
//! square whose corners are four depth samples, `(0, 0)` at the sample with the smallest map
//! coordinates and `(1, 1)` at the largest; x runs along the map's columns, y along its rows. A texel with no silhouette keeps the default point `(0.5, 0.5)`, which
//! makes it behave like a plain shadow map there.

use glam::Vec2;

/// How far outside the texel square an intersection still counts (§3.1: "the clipping square is
/// enlarged slightly"), so a line through a corner is stored in all four neighbours.
pub const CORNER_SLACK: f32 = 1e-3;

/// The default point of a texel without a silhouette edge.
pub const DEFAULT_POINT: Vec2 = Vec2::splat(0.5);

fn inside(p: Vec2, slack: f32) -> bool {
    p.cmpge(Vec2::splat(-slack)).all() && p.cmple(Vec2::splat(1.0 + slack)).all()
}

/// Where segment `a → b` crosses the segment `c → d`, with both parameters in `[−slack, 1 + slack]`
/// (the diagonal's parameter measured along the square), or `None` (parallel or apart).
fn cross(a: Vec2, b: Vec2, c: Vec2, d: Vec2, slack: f32) -> Option<Vec2> {
    let (r, s) = (b - a, d - c);
    let denom = r.perp_dot(s);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (c - a).perp_dot(s) / denom; // along a → b
    let u = (c - a).perp_dot(r) / denom; // along the diagonal
    let ok = |v: f32| (-slack..=1.0 + slack).contains(&v);
    (ok(t) && ok(u)).then(|| a + r * t)
}

/// The point a silhouette edge `a → b` (texel-local) stores in this texel (§3.1, Fig. 4):
/// an endpoint inside the texel; otherwise the one diagonal crossing, or the midpoint of both;
/// `None` when the segment misses the texel (the fragment is discarded). The result is clamped
/// into the texel. Degenerate input (zero-length or non-finite) gives `None` or a point inside.
pub fn pick_point(a: Vec2, b: Vec2) -> Option<Vec2> {
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let clamp = |p: Vec2| p.clamp(Vec2::ZERO, Vec2::ONE);
    if inside(a, CORNER_SLACK) {
        return Some(clamp(a));
    }
    if inside(b, CORNER_SLACK) {
        return Some(clamp(b));
    }
    let hits = [cross(a, b, Vec2::ZERO, Vec2::ONE, CORNER_SLACK), cross(a, b, Vec2::Y, Vec2::X, CORNER_SLACK)];
    match hits {
        [Some(p), Some(q)] => Some(clamp((p + q) * 0.5)),
        [Some(p), None] | [None, Some(p)] => Some(clamp(p)),
        [None, None] => None,
    }
}

/// The depth sample (texel corner) whose comparison shades a sample, named by its texel-local
/// coordinates (`C10` is `(1, 0)`). Mirrors the shader's `CORNER_*` constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corner {
    /// `(0, 0)`.
    C00,
    /// `(1, 0)`.
    C10,
    /// `(1, 1)`.
    C11,
    /// `(0, 1)`.
    C01,
}

/// The silhouette points of a texel and its four neighbours, each in **this** texel's frame
/// (the left neighbour's point has x in `[−1, 0]`, the upper one y in `[1, 2]`, …). "Down" and
/// "up" are −y and +y; in the map, y runs along the rows.
#[derive(Clone, Copy, Debug)]
pub struct Neighbourhood {
    /// This texel's point.
    pub centre: Vec2,
    /// The left (−x) neighbour's point.
    pub left: Vec2,
    /// The lower (−y) neighbour's point.
    pub down: Vec2,
    /// The right (+x) neighbour's point.
    pub right: Vec2,
    /// The upper (+y) neighbour's point.
    pub up: Vec2,
}

/// Whether `s` lies in the wedge swept counter-clockwise from ray `r1` to ray `r2`.
fn in_wedge(r1: Vec2, s: Vec2, r2: Vec2) -> bool {
    r1.perp_dot(s) >= 0.0 && s.perp_dot(r2) >= 0.0
}

/// Which skewed quadrant holds `sample` (§3.2, Fig. 5). The segments from the centre point to
/// the four neighbours' points and to the four corners cut the texel into eight wedges, two per
/// corner (each at most a half-plane: a neighbour's segment leaves the texel through the side
/// they share, between that side's corners); the first wedge holding the sample names the
/// corner. Exactly the shader's `quadrant` (`silhouette_map/geometry.glsl`).
pub fn quadrant(n: &Neighbourhood, sample: Vec2) -> Corner {
    let c = n.centre;
    let s = sample - c;
    let (l, d, r, u) = (n.left - c, n.down - c, n.right - c, n.up - c);
    let (c00, c10, c11, c01) = (-c, Vec2::X - c, Vec2::ONE - c, Vec2::Y - c);
    if in_wedge(l, s, c00) || in_wedge(c00, s, d) {
        Corner::C00
    } else if in_wedge(d, s, c10) || in_wedge(c10, s, r) {
        Corner::C10
    } else if in_wedge(r, s, c11) || in_wedge(c11, s, u) {
        Corner::C11
    } else if in_wedge(u, s, c01) || in_wedge(c01, s, l) {
        Corner::C01
    } else {
        // Only reachable through degenerate (zero-length) rays: the nearest corner.
        match (sample.x < 0.5, sample.y < 0.5) {
            (true, true) => Corner::C00,
            (true, false) => Corner::C01,
            (false, true) => Corner::C10,
            (false, false) => Corner::C11,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Vec2, b: Vec2) -> bool {
        a.abs_diff_eq(b, 1e-5)
    }

    #[test]
    fn an_endpoint_inside_the_texel_is_stored() {
        let p = pick_point(Vec2::new(0.3, 0.4), Vec2::new(2.0, 3.0)).unwrap();
        assert!(near(p, Vec2::new(0.3, 0.4)));
        let q = pick_point(Vec2::new(-2.0, 0.5), Vec2::new(0.6, 0.7)).unwrap();
        assert!(near(q, Vec2::new(0.6, 0.7)));
    }

    #[test]
    fn one_diagonal_hit_is_stored() {
        // A short segment crossing the main diagonal near a corner, missing the other one.
        let p = pick_point(Vec2::new(-0.05, 0.15), Vec2::new(0.15, -0.05)).unwrap();
        assert!(near(p, Vec2::new(0.05, 0.05)), "{p}");
    }

    #[test]
    fn two_diagonal_hits_store_their_midpoint() {
        // A horizontal line through the texel at y = 0.25 crosses both diagonals.
        let p = pick_point(Vec2::new(-1.0, 0.25), Vec2::new(2.0, 0.25)).unwrap();
        assert!(near(p, Vec2::new(0.5, 0.25)), "{p}");
    }

    #[test]
    fn a_segment_missing_the_texel_is_discarded() {
        assert_eq!(pick_point(Vec2::new(-1.0, 1.5), Vec2::new(2.0, 1.6)), None);
        assert_eq!(pick_point(Vec2::new(1.2, -1.0), Vec2::new(1.4, 2.0)), None);
        // The infinite line crosses the texel but the segment stops short of it.
        assert_eq!(pick_point(Vec2::new(-3.0, 0.5), Vec2::new(-1.0, 0.5)), None);
    }

    #[test]
    fn a_line_through_a_corner_is_stored_in_all_four_neighbours() {
        // The line x + y = 0 passes exactly through this texel's (0, 0) corner, which four
        // texels share. In the frame of the texel `offset` texels down-left of this one, the
        // line is shifted by `offset`: every one of the four must store a point.
        let (a, b) = (Vec2::new(-1.0, 1.0), Vec2::new(1.0, -1.0));
        for offset in [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0)] {
            let p = pick_point(a + offset, b + offset).unwrap_or_else(|| panic!("texel at {offset} missed the corner"));
            assert!(inside(p, 0.0), "{p} outside");
        }
    }

    #[test]
    fn an_edge_along_a_texel_border_is_kept_on_that_border() {
        let p = pick_point(Vec2::new(-1.0, 0.0), Vec2::new(2.0, 0.0)).unwrap();
        assert!(near(p, Vec2::new(0.5, 0.0)), "{p}");
        let q = pick_point(Vec2::new(1.0, -2.0), Vec2::new(1.0, 3.0)).unwrap();
        assert!(near(q, Vec2::new(1.0, 0.5)), "{q}");
    }

    #[test]
    fn degenerate_edges_give_no_nan_and_stay_inside() {
        // Zero length, outside and inside; an edge seen end-on (both endpoints the same point).
        assert_eq!(pick_point(Vec2::new(3.0, 3.0), Vec2::new(3.0, 3.0)), None);
        let p = pick_point(Vec2::new(0.4, 0.4), Vec2::new(0.4, 0.4)).unwrap();
        assert!(p.is_finite() && inside(p, 0.0));
        assert_eq!(pick_point(Vec2::new(f32::NAN, 0.0), Vec2::ONE * 0.5), None);
        // Collinear with a diagonal: the other diagonal gives the centre.
        let q = pick_point(Vec2::new(-1.0, -1.0), Vec2::new(2.0, 2.0)).unwrap();
        assert!(near(q, Vec2::splat(0.5)), "{q}");
    }

    #[test]
    fn a_straight_silhouette_splits_the_texel_into_its_two_sides() {
        // A vertical edge at x = 0.3 through this texel and its upper and lower neighbours; the
        // left and right neighbours have no silhouette (default points).
        let n = Neighbourhood {
            centre: Vec2::new(0.3, 0.5),
            up: Vec2::new(0.3, 1.5),
            down: Vec2::new(0.3, -0.5),
            left: Vec2::new(-0.5, 0.5),
            right: Vec2::new(1.5, 0.5),
        };
        for (s, left_side) in [
            (Vec2::new(0.2, 0.9), true),
            (Vec2::new(0.1, 0.1), true),
            (Vec2::new(0.4, 0.1), false),
            (Vec2::new(0.9, 0.8), false),
        ] {
            let c = quadrant(&n, s);
            let on_left = matches!(c, Corner::C00 | Corner::C01);
            assert_eq!(on_left, left_side, "{s} went to {c:?}");
        }
        // With every point at its default, the quadrants are the four texel quarters: a plain
        // shadow map's nearest sample.
        let plain = Neighbourhood {
            centre: DEFAULT_POINT,
            left: Vec2::new(-0.5, 0.5),
            down: Vec2::new(0.5, -0.5),
            right: Vec2::new(1.5, 0.5),
            up: Vec2::new(0.5, 1.5),
        };
        assert_eq!(quadrant(&plain, Vec2::new(0.1, 0.2)), Corner::C00);
        assert_eq!(quadrant(&plain, Vec2::new(0.8, 0.3)), Corner::C10);
        assert_eq!(quadrant(&plain, Vec2::new(0.7, 0.9)), Corner::C11);
        assert_eq!(quadrant(&plain, Vec2::new(0.2, 0.6)), Corner::C01);
    }

    #[test]
    fn a_skewed_contour_shades_each_side_from_a_corner_on_that_side() {
        // The line y = 0.3 + 0.6 x crosses this texel from its left to its right neighbour;
        // every point of it is stored where the line crosses each texel (the midpoint of the
        // two diagonal hits here). The lower and upper neighbours hold no silhouette.
        let line = |x: f32| 0.3 + 0.6 * x;
        let centre = pick_point(Vec2::new(-1.0, line(-1.0)), Vec2::new(2.0, line(2.0))).unwrap();
        let n = Neighbourhood {
            centre,
            left: Vec2::new(-0.5, line(-0.5)),
            right: Vec2::new(1.5, line(1.5)),
            down: Vec2::new(0.5, -0.5),
            up: Vec2::new(0.5, 1.5),
        };
        for i in 0..=20 {
            for j in 0..=20 {
                let s = Vec2::new(i as f32 / 20.0, j as f32 / 20.0);
                // Samples farther than 0.05 from the reconstructed polyline (which is this
                // straight line up to the points' placement).
                if (s.y - line(s.x)).abs() < 0.05 {
                    continue;
                }
                let below = s.y < line(s.x);
                let corner = quadrant(&n, s);
                let corner_below = matches!(corner, Corner::C00 | Corner::C10);
                assert_eq!(corner_below, below, "{s} went to {corner:?}");
            }
        }
    }
}
