//! What each pixel sees: a world position, the geometric normal on the camera's side and the
//! object. Either read from the renderer's G-buffer (the raster pass's own positions, so the
//! reference judges exactly the points the technique shaded) or ray cast from the camera (the
//! pure ray-cast render, for sanity checks).

use crate::bvh::SceneBvh;
use crate::{ReferenceError, ReferenceResult};
use glam::{Mat4, Vec3};
use rayon::prelude::*;
use umbra_scene::Scene;

/// The surface seen through one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// World position.
    pub position: Vec3,
    /// Unit geometric normal, turned towards the camera (surfaces are lit on both sides).
    /// Zero where the raster pass could not tell (a triangle seen exactly edge-on).
    pub normal: Vec3,
    /// Index of the object in `scene.objects`.
    pub object: usize,
}

/// A frame's worth of [`Surface`]s, row 0 at the top.
#[derive(Clone, Debug)]
pub struct SurfaceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` entries, `None` where no surface covers the pixel centre.
    pub pixels: Vec<Option<Surface>>,
}

impl SurfaceImage {
    /// From a G-buffer: per pixel, `position = [x, y, z, object + 1]` (w = 0: no surface)
    /// and `normal = [x, y, z, _]`, as `umbra_shadows::GBuffer` holds them.
    pub fn from_gbuffer(width: u32, height: u32, position: &[[f32; 4]], normal: &[[f32; 4]]) -> ReferenceResult<Self> {
        let n = width as usize * height as usize;
        for (what, len) in [("G-buffer positions", position.len()), ("G-buffer normals", normal.len())] {
            if len != n {
                return Err(ReferenceError::SizeMismatch { what, got: (len, 1), expected: (n, 1) });
            }
        }
        let pixels = position
            .iter()
            .zip(normal)
            .map(|(p, nrm)| {
                (p[3] >= 1.0).then(|| Surface {
                    position: Vec3::new(p[0], p[1], p[2]),
                    normal: Vec3::new(nrm[0], nrm[1], nrm[2]).normalize_or_zero(),
                    object: p[3] as usize - 1,
                })
            })
            .collect();
        Ok(Self { width, height, pixels })
    }

    /// Ray casts every pixel centre of `scene`'s camera at `width` × `height` (the pure
    /// ray-cast render's first step).
    pub fn ray_cast(scene: &Scene, bvh: &SceneBvh, width: u32, height: u32) -> Self {
        let view_proj = scene.camera.view_proj(width as f32 / height as f32);
        let pixels = (0..width as usize * height as usize)
            .into_par_iter()
            .map(|i| {
                let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
                let (origin, dir) = pixel_ray(view_proj, width, height, x, y);
                let hit = bvh.closest_hit(origin, dir, f32::INFINITY)?;
                let triangle = &bvh.triangles()[hit.triangle];
                let mut normal = triangle.normal();
                if normal.dot(dir) > 0.0 {
                    normal = -normal;
                }
                Some(Surface { position: origin + dir * hit.t, normal, object: triangle.object })
            })
            .collect();
        Self { width, height, pixels }
    }

    /// The surface at `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> Option<Surface> {
        self.pixels[(y * self.width + x) as usize]
    }
}

/// The world-space ray through the centre of pixel `(x, y)` (row 0 at the top) of a camera
/// with `view_proj` (umbra's conventions: Vulkan depth 0..1, y up in NDC): origin on the near
/// plane and unit direction.
pub fn pixel_ray(view_proj: Mat4, width: u32, height: u32, x: u32, y: u32) -> (Vec3, Vec3) {
    let inv = view_proj.inverse();
    let ndc_x = (x as f32 + 0.5) / width as f32 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / height as f32 * 2.0;
    let near = inv.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
    let far = inv.project_point3(Vec3::new(ndc_x, ndc_y, 0.5));
    (near, (far - near).normalize())
}
