//! The face atlas: a point light's six cube faces side by side in one 2D map (three columns,
//! two rows), each face widened by [`FACE_BORDER`] texels beyond its 90° on every side. It is
//! the depth map and the silhouette map of a silhouette-map light that needs a cube (a point
//! light, a spot wider than 80°).
//!
//! Why a border: the lookup (Sen et al. §3.2) reads a silhouette texel, its four neighbours and
//! the four depth samples at its corners. Chosen by the direction's major axis, the face holds
//! the point within its 90° interior, so every texel read lies at most two texels beyond it: in
//! the border, which the face's own (widened) frustum rendered. Edges crossing a seam are
//! rasterized into both faces; each face reconstructs them from its own samples, so no lookup
//! needs a neighbour from another face, and none reads a texel of the face beside it in the
//! atlas. `shaders-glsl/shadow_map/atlas.glsl` mirrors these numbers.

use glam::{Mat4, Vec3};

/// Texels each face holds beyond its 90° interior, on every side: the lookup's cell may lie one
/// texel past the interior and reads one neighbour further.
pub(crate) const FACE_BORDER: u32 = 2;

/// Faces of a cube, in layer order +X, −X, +Y, −Y, +Z, −Z.
pub(crate) const FACES: u32 = 6;
/// Faces per atlas row.
pub(crate) const COLUMNS: u32 = 3;
/// Rows of faces.
pub(crate) const ROWS: u32 = 2;

/// Texels per side of one face whose 90° interior is `resolution` texels wide.
pub(crate) fn face_side(resolution: u32) -> u32 {
    resolution.saturating_add(2 * FACE_BORDER)
}

/// The atlas's width and height for faces of `resolution` interior texels.
pub(crate) fn extent(resolution: u32) -> (u32, u32) {
    let side = face_side(resolution);
    (COLUMNS.saturating_mul(side), ROWS.saturating_mul(side))
}

/// Face `face`'s rectangle in the atlas: x, y (rows down), width, height, in texels.
pub(crate) fn face_rect(face: u32, resolution: u32) -> [u32; 4] {
    let side = face_side(resolution);
    [(face % COLUMNS) * side, (face / COLUMNS) * side, side, side]
}

/// Widens 90° cube-face view-projections so that `resolution` texels of a
/// [`face_side`]-texel face span the 90° interior: x and y in clip space shrink by
/// resolution / side (depth is unchanged, so the faces' depths are the cube's).
pub(crate) fn widen(views: &mut [Mat4], resolution: u32) {
    let scale = resolution as f32 / face_side(resolution) as f32;
    let shrink = Mat4::from_scale(Vec3::new(scale, scale, 1.0));
    for view in views {
        *view = shrink * *view;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4Swizzles;

    #[test]
    fn faces_tile_the_atlas_without_overlap() {
        let (w, h) = extent(100);
        assert_eq!((w, h), (312, 208));
        let rects: Vec<[u32; 4]> = (0..6).map(|f| face_rect(f, 100)).collect();
        for (i, a) in rects.iter().enumerate() {
            assert!(a[0] + a[2] <= w && a[1] + a[3] <= h, "face {i} inside the atlas");
            for b in &rects[i + 1..] {
                let apart = a[0] + a[2] <= b[0] || b[0] + b[2] <= a[0] || a[1] + a[3] <= b[1] || b[1] + b[3] <= a[1];
                assert!(apart, "faces {a:?} and {b:?} overlap");
            }
        }
    }

    #[test]
    fn the_interior_spans_ninety_degrees() {
        // A direction at 45° off the face axis (a seam) lands FACE_BORDER texels inside the
        // face's edge; the axis lands in the middle.
        let resolution = 64;
        let side = face_side(resolution) as f32;
        let mut views = [Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 10.0)];
        widen(&mut views, resolution);
        let texel_x = |p: Vec3| {
            let clip = views[0] * p.extend(1.0);
            (0.5 + 0.5 * clip.x / clip.w) * side
        };
        assert!((texel_x(Vec3::new(1.0, 0.0, -1.0)) - (side - FACE_BORDER as f32)).abs() < 1e-3);
        assert!((texel_x(Vec3::new(-1.0, 0.0, -1.0)) - FACE_BORDER as f32).abs() < 1e-3);
        assert!((texel_x(Vec3::new(0.0, 0.0, -3.0)) - side / 2.0).abs() < 1e-3);
        let clip = views[0] * Vec3::new(0.3, 0.2, -2.0).extend(1.0);
        let plain =
            Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 10.0) * Vec3::new(0.3, 0.2, -2.0).extend(1.0);
        assert_eq!(clip.zw(), plain.zw(), "depth is the cube's");
    }
}
