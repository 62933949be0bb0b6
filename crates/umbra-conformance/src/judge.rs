//! How a technique's shadow masks are judged against the exact reference.
//!
//! Every light's mask (its visibility image, `umbra_shadows::VisibilityImage::shadow_mask`) is
//! compared with [`umbra_reference::ShadowMask::reference`] on the frame's own G-buffer, so
//! which surface each pixel shows is shared and only the shadow decision is judged. The
//! light's classification (a diagnostic view) must give the very same mask
//! ([`Judgement::class_disagreements`]); it also tells which pixels the hybrid's volumes
//! decided. A wrong pixel is **explained** by its
//! technique's own tolerance, or **unexplained**:
//!
//! - **Shadow volumes** decide each pixel exactly at its centre, so a wrong pixel is explained
//!   only on the **seam**: a pixel with a 4-neighbour on the other side of the true edge
//!   (every pixel whose centre lies within 0.5 px of a straight edge is one). Rasterization
//!   ties and the G-buffer's own precision live there.
//! - **Shadow maps and silhouette maps** decide from depth samples one texel apart, so a wrong
//!   pixel is explained within [`TEXEL_BAND`] texels of a change of the true shadow, measured
//!   on the receiver: the pixel's surface point is moved by ±`TEXEL_BAND` texels in the
//!   light's own map (eight directions, the map's x and y and the diagonals), to the centre of
//!   every map texel within `TEXEL_BAND` texels of it (the samples the map decided from: a
//!   caster thinner than a texel that one of them hit can pass between the eight points), and
//!   to a grid of 1/8 texel over the band (needle shadows thinner still), projected back along
//!   the light's rays onto the receiver's plane, and the exact shadow ray is cast from there;
//!   if any disagrees with the pixel's, the pixel is in the band.
//!   The band also covers discontinuities of the map's depth field: if the first caster the
//!   light sees through one of those eight neighbours is not on the pixel's plane (a crease
//!   of the receiver, another object, a silhouette), the map's samples around the pixel are
//!   not the pixel's surface, and acne or a leak there (the classic speck at a lit convex
//!   edge) is the map's resolution at work.
//!   A wrong pixel the truth shadows is also explained when a caster lies within
//!   `TEXEL_BAND` texels of it along its shadow ray (**contact**): the depth bias that keeps
//!   surfaces from shadowing themselves cannot tell such a caster from the receiver.
//! - **The hybrid** uses the volume rule on the pixels its shadow map flagged as silhouette
//!   pixels (decided by the stencil count) and the map rule elsewhere.
//!
//! Surfaces seen edge-on by the light (|n·l| < [`EDGE_ON`]) are not judged: the shadow ray
//! runs inside the surface, so their shadow is undefined.
//!
//! - **Snapping.** A rasterizer snaps every vertex to 1/2^`subPixelPrecisionBits` of a pixel
//!   (a device limit: 8 bits on lavapipe, 4 on SwiftShader) before it decides coverage and
//!   interpolates depth, so a volume's faces move by up to 2^−(bits+1) px in x and in y
//!   against the exact geometry, while the receiver keeps its own depth (the G-buffer and the
//!   depth buffer are snapped alike). A wrong volume-decided pixel is explained when the truth
//!   changes for its surface point moved by [`snap_step`] in x, in y or both, parallel to the
//!   image at its own depth (`snapping_explains`); a point so moved below its own surface
//!   is brought back onto it along its light ray, since its own front cap moves with it.
//!   Two things make such pixels lie off the seam: volumes of sub-pixel casters (needles,
//!   twigs), and volume faces that pass within a fraction of a pixel of the surface point in
//!   depth, not across the image (grazing light, where the shadow ray skims a neighbouring
//!   face). The same rule holds on every device, with its own bits; the step is 2^−bits px,
//!   twice the snapping bound, for the f32 arithmetic of clipping and interpolation.

use crate::{ConformanceError, ConformanceResult};
use glam::Mat4;
use glam::{Vec3, Vec4};
use serde::Serialize;
use umbra_reference::{edge_distance, shadow_blockers, shadow_state, SceneBvh, ShadowMask, Surface, SurfaceImage};
use umbra_scene::{Light, Scene, Technique};
use umbra_shadows::{Frame, ShadowMapReport};

/// Half-width of a map technique's tolerance band, in shadow-map texels: 2×2 PCF blends the
/// texels on both sides of an edge (one texel), and the slope-scaled bias and normal offset
/// move the edge by up to about one more.
pub const TEXEL_BAND: f32 = 2.0;

/// |cos| of the light's incidence below which a surface is edge-on to the light (89.94°).
pub const EDGE_ON: f32 = 1e-3;

/// Unexplained pixels listed in [`Judgement::unexplained_at`].
pub const SHOWN: usize = 12;

/// Fewest decided pixels a light must give for its case to test anything.
pub const MIN_COMPARED: u64 = 500;

/// One technique's masks against the exact ones, over every light of a frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Judgement {
    /// Pixels both masks decide, summed over lights.
    pub compared: u64,
    /// Of those, shadowed in truth.
    pub shadowed: u64,
    /// Pixels whose state differs.
    pub wrong: u64,
    /// Wrong pixels shadowed by the technique only.
    pub false_shadow: u64,
    /// Wrong pixels lit by the technique only.
    pub false_lit: u64,
    /// Wrong pixels on surfaces edge-on to the light (not judged).
    pub edge_on: u64,
    /// Wrong pixels on the seam of a true edge.
    pub seam: u64,
    /// Wrong map-decided pixels inside the texel band or in contact (beyond the seam).
    pub texel_band: u64,
    /// Wrong volume-decided pixels beyond the seam explained by vertex snapping (the module's
    /// "Snapping" rule).
    pub snapping: u64,
    /// Wrong volume-decided pixels nothing explains.
    pub volume_unexplained: u64,
    /// Wrong map-decided pixels beyond the texel band.
    pub map_unexplained: u64,
    /// Wrong ray-traced pixels beyond the seam (the rule of an exact technique: none).
    pub ray_unexplained: u64,
    /// Where the first unexplained pixels are: (light, x, y), at most [`SHOWN`].
    pub unexplained_at: Vec<(usize, u32, u32)>,
    /// Lights whose mask decided fewer than [`MIN_COMPARED`] pixels.
    pub thin_lights: Vec<usize>,
    /// Pixels a light's classification decides and its visibility image does not agree on
    /// (`VisibilityImage::disagreements_with`), summed over lights: 0 unless the visibility
    /// passes and the diagnostic views decide differently.
    pub class_disagreements: u64,
}

impl Judgement {
    /// Wrong pixels no tolerance explains.
    pub fn unexplained(&self) -> u64 {
        self.volume_unexplained + self.map_unexplained + self.ray_unexplained
    }

    /// `unexplained / compared`.
    pub fn unexplained_fraction(&self) -> f64 {
        if self.compared == 0 {
            0.0
        } else {
            self.unexplained() as f64 / self.compared as f64
        }
    }
}

/// Judges every light of `frame` (rendered from `scene`, whose lights all use `technique`,
/// with diagnostics, the visibility readback and a G-buffer, on a device with
/// `sub_pixel_precision_bits`); returns the judgement and, per light, the technique's and the
/// true mask. Shadow volumes and the hybrid are held to the volume rule on every pixel (the
/// hybrid promises shadow-volume accuracy: its map decides only where it cannot be wrong),
/// shadow and silhouette maps to the map rule.
pub fn judge(
    scene: &Scene,
    bvh: &SceneBvh,
    frame: &Frame,
    technique: Technique,
    sub_pixel_precision_bits: u32,
) -> ConformanceResult<(Judgement, Vec<(ShadowMask, ShadowMask)>)> {
    let snap = Snap {
        view_proj: scene.camera.view_proj(frame.width as f32 / frame.height as f32),
        size: (frame.width as f32, frame.height as f32),
        step: snap_step(sub_pixel_precision_bits),
    };
    let gbuffer = frame.gbuffer.as_ref().ok_or_else(|| missing("G-buffer"))?;
    let surfaces = SurfaceImage::from_gbuffer(frame.width, frame.height, &gbuffer.position, &gbuffer.normal)?;
    let mut j = Judgement::default();
    let mut masks = Vec::new();
    // Every light with a shadow mask (`Frame::shadow_masks`): ray-traced lights have no
    // classification pass, only their visibility image.
    for (index, mask) in frame.shadow_masks() {
        let light = scene.lights.get(index).ok_or_else(|| missing("the scene light of a shadow mask"))?;
        let diagnostics = frame.diagnostics.iter().find(|d| d.light == index);
        let visibility = frame.visibility.iter().find(|v| v.light == index);
        let map = frame.report.lights.get(index).and_then(|l| l.shadow_map.as_ref());
        if let (Some(v), Some(d)) = (visibility, diagnostics) {
            j.class_disagreements += v.disagreements_with(&d.shadow_mask());
        }
        let mask = ShadowMask::new(frame.width, frame.height, mask)?;
        let truth = ShadowMask::reference(scene, bvh, index, &surfaces)?;
        j.shadowed += truth.counts().0;
        let mut compared = 0;
        let distance = edge_distance(&truth);
        let w = frame.width as usize;
        for (i, (t, r)) in mask.shadowed.iter().zip(&truth.shadowed).enumerate() {
            let (Some(t), Some(r)) = (*t, *r) else { continue };
            compared += 1;
            if t == r {
                continue;
            }
            j.wrong += 1;
            j.false_shadow += u64::from(t);
            j.false_lit += u64::from(r);
            let surface = surfaces.pixels[i].as_ref();
            if surface
                .is_some_and(|s| s.normal.dot(umbra_reference::towards(light.position, s.position).0).abs() < EDGE_ON)
            {
                j.edge_on += 1;
                continue;
            }
            if distance[i] <= 0.5 {
                j.seam += 1;
                continue;
            }
            let by_volume = matches!(technique, Technique::ShadowVolume | Technique::Hybrid);
            if matches!(technique, Technique::RayTraced | Technique::HybridRt) {
                // The reference's own rays, walked in f32 (the ray-traced hybrid's map decides
                // only where its bounds cannot be wrong): nothing beyond the seam explains a
                // wrong pixel.
                j.ray_unexplained += 1;
            } else if by_volume && surface.is_some_and(|s| snapping_explains(light, bvh, &snap, s, r)) {
                j.snapping += 1;
                continue;
            } else if by_volume {
                j.volume_unexplained += 1;
            } else if surface.is_some_and(|s| map_explains(light, bvh, map, s, r)) {
                j.texel_band += 1;
                continue;
            } else {
                j.map_unexplained += 1;
            }
            if j.unexplained_at.len() < SHOWN {
                j.unexplained_at.push((index, (i % w) as u32, (i / w) as u32));
            }
        }
        if compared < MIN_COMPARED {
            j.thin_lights.push(index);
        }
        j.compared += compared;
        masks.push((mask, truth));
    }
    Ok((j, masks))
}

/// The camera and the snapping step, for [`snapping_explains`].
struct Snap {
    view_proj: Mat4,
    size: (f32, f32),
    step: f32,
}

/// How far the judge's snapping rule moves a surface point, in pixels: 2^−bits, twice the
/// distance a vertex snapped to 1/2^bits of a pixel moves in x or y.
pub fn snap_step(sub_pixel_precision_bits: u32) -> f32 {
    0.5f32.powi(sub_pixel_precision_bits.min(24) as i32)
}

/// Whether vertex snapping explains a wrong volume-decided pixel at `s` (`truth` its true
/// state). Moved by `snap.step` pixels in x, in y or both, parallel to the image at its own
/// depth, the point stands where snapped volumes could put it: a pixel wrongly shadowed is
/// explained when some move meets a caster, a pixel wrongly lit when each caster on its
/// shadow ray is missed by some move (every volume's vertices snap on their own). The point's
/// own surface is snapped with it (its front cap and the depth buffer alike), so a point
/// moved below that surface is brought back onto it along its light ray.
fn snapping_explains(light: &Light, bvh: &SceneBvh, snap: &Snap, s: &Surface, truth: bool) -> bool {
    let c = snap.view_proj * s.position.extend(1.0);
    if c.w <= 0.0 {
        return false;
    }
    let ndc = c.truncate() / c.w;
    let inverse = snap.view_proj.inverse();
    let (dir, _) = umbra_reference::towards(light.position, s.position);
    let light_side = s.normal.dot(dir).signum();
    let directions =
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)];
    let moved: Vec<Vec<usize>> = directions
        .iter()
        .filter_map(|&(dx, dy)| {
            let step = Vec3::new(dx * 2.0 * snap.step / snap.size.0, dy * 2.0 * snap.step / snap.size.1, 0.0);
            let q = inverse.project_point3(ndc + step);
            let q = if s.normal.dot(q - s.position) * light_side >= 0.0 {
                q
            } else {
                onto_plane(light.position, q, s.position, s.normal)?
            };
            shadow_blockers(light, bvh, &Surface { position: q, ..*s })
        })
        .collect();
    if !truth {
        return moved.iter().any(|b| !b.is_empty());
    }
    let Some(blockers) = shadow_blockers(light, bvh, s) else { return false };
    blockers.iter().all(|b| moved.iter().any(|m| !m.contains(b)))
}

fn missing(what: &str) -> ConformanceError {
    ConformanceError::Incomplete(format!("the frame has no {what} (render with diagnostics and gbuffer on)"))
}

/// Whether a shadow map's tolerance explains a wrong pixel at `s` (`truth` is its true state):
/// the true shadow changes within [`TEXEL_BAND`] texels of it in the light's map, or (for a
/// shadowed pixel) a caster lies within `TEXEL_BAND` texels along its shadow ray. Points
/// outside every view of the map are not explained: the map cannot have seen them.
fn map_explains(light: &Light, bvh: &SceneBvh, map: Option<&ShadowMapReport>, s: &Surface, truth: bool) -> bool {
    let Some(map) = map else { return false };
    let p = s.position.extend(1.0);
    // The view the lookup uses: of those holding the point, the one it lies furthest inside
    // (the face its direction's major axis selects, where a cube's faces overlap at seams).
    let views = map.view_proj.iter().filter_map(|vp| {
        let c = *vp * p;
        let ndc = c.truncate() / c.w;
        let inside = c.w > 0.0 && ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z);
        inside.then_some((*vp, ndc))
    });
    let Some((view_proj, ndc)) =
        views.min_by(|a, b| a.1.x.abs().max(a.1.y.abs()).total_cmp(&b.1.x.abs().max(b.1.y.abs())))
    else {
        return false;
    };
    let inverse = view_proj.inverse();
    let step = TEXEL_BAND * 2.0 / map.view_texels as f32;
    let at = |dx: f32, dy: f32| {
        let moved = inverse * Vec4::new(ndc.x + dx * step, ndc.y + dy * step, ndc.z, 1.0);
        moved.truncate() / moved.w
    };
    if truth {
        let band = at(1.0, 0.0).distance(at(0.0, 0.0));
        let (dir, _) = umbra_reference::towards(light.position, s.position);
        let offset = umbra_reference::RAY_OFFSET_SCALE * s.position.abs().max_element().max(1.0);
        if bvh.occluded(s.position + s.normal * offset, dir, band) {
            return true;
        }
    }
    let tolerance = at(1.0, 0.0).distance(at(0.0, 0.0));
    band_samples(ndc.truncate(), map.view_texels).any(|(dx, dy)| {
        let q = at(dx, dy);
        // What the map stores there: the first surface from the light through q. Off p's
        // plane (a crease, another object, a silhouette) the map's depth field is not p's.
        let off_plane = |(h, normal): (Vec3, Vec3)| {
            s.normal.dot(h - s.position).abs() > 0.01 * tolerance || s.normal.dot(normal).abs() < 0.999
        };
        if first_from_light(light.position, bvh, q).is_some_and(off_plane) {
            return true;
        }
        let Some(on_receiver) = onto_plane(light.position, q, s.position, s.normal) else { return false };
        let moved = Surface { position: on_receiver, ..*s };
        shadow_state(light, bvh, &moved) != Some(truth)
    })
}

/// Where [`map_explains`] looks for a change of the true shadow around a point at `ndc` of a
/// `resolution`² map, as offsets in units of the band (`TEXEL_BAND` texels): first the eight
/// points of the band's square (its x and y and the diagonals), then the centre of every texel
/// of the map inside that square, then a grid of 1/8 texel over the square. The map decided
/// the pixel from those texels' samples, so a caster narrower than a texel (a thin arm, a
/// twig) that one of them hit is found there even when it passes between the eight points;
/// the grid finds shadows thinner still (a needle's) that the rasterizer, snapping vertices,
/// put under a centre the exact needle misses.
fn band_samples(ndc: glam::Vec2, resolution: u32) -> impl Iterator<Item = (f32, f32)> {
    let ring = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)];
    let size = resolution as f32;
    // The point in texels (texel centres at k + 0.5), and the centres within the band of it.
    let texel = (ndc * 0.5 + 0.5) * size;
    let first = (texel - TEXEL_BAND - 0.5).ceil();
    let reach = 2 * TEXEL_BAND as i32 + 1;
    let centres = (0..reach * reach).filter_map(move |k| {
        let centre = first + glam::Vec2::new((k % reach) as f32, (k / reach) as f32) + 0.5;
        let d = (centre - texel) / TEXEL_BAND;
        (d.x.abs() <= 1.0 && d.y.abs() <= 1.0).then_some((d.x, d.y))
    });
    // Last, a grid of 1/8 texel over the whole band: a shadow thinner than a texel (a needle's)
    // that passes between the map's own centres.
    const FINE: i32 = 8 * TEXEL_BAND as i32;
    let fine =
        (-FINE..=FINE).flat_map(|j| (-FINE..=FINE).map(move |i| (i as f32 / FINE as f32, j as f32 / FINE as f32)));
    ring.into_iter().chain(centres).chain(fine)
}

/// The first caster point the light sees on its ray through `q`: what its depth map stores
/// there (non-casters are not drawn into maps, so the walk steps past them).
/// Returns the point and its triangle's unit normal.
fn first_from_light(light: Vec4, bvh: &SceneBvh, q: Vec3) -> Option<(Vec3, Vec3)> {
    let (dir, distance) = umbra_reference::towards(light, q);
    let reach = if distance.is_finite() { distance } else { 1e3 * q.abs().max_element().max(1.0) };
    let origin = q + dir * reach;
    let mut t0 = 0.0;
    for _ in 0..8 {
        let start = origin - dir * t0;
        let hit = bvh.closest_hit(start, -dir, f32::INFINITY)?;
        let triangle = &bvh.triangles()[hit.triangle];
        if triangle.casts_shadows {
            return Some((start - dir * hit.t, triangle.normal().normalize_or_zero()));
        }
        t0 += hit.t + 1e-4 * reach;
    }
    None
}

/// Where the light's ray through `q` meets the plane through `p` with normal `n`.
fn onto_plane(light: Vec4, q: Vec3, p: Vec3, n: Vec3) -> Option<Vec3> {
    let (dir, _) = umbra_reference::towards(light, q);
    let along = n.dot(dir);
    if along.abs() < 1e-6 {
        return None;
    }
    let r = q + dir * (n.dot(p - q) / along);
    r.is_finite().then_some(r)
}
