//! Diagnostic views, rendered on request (`RendererDesc::diagnostics`) by passes per light
//! that are not part of the technique's cost: the per-pixel classification (Chan–Durand
//! Fig. 6b colours, `shaders-glsl/debug/classes.glsl`); for silhouette maps, a mask of the
//! silhouette points as the camera sees them (Sen et al. Fig. 9, middle) and the map itself;
//! for the hybrid, the stencil after its volumes and the fill image (Chan–Durand Fig. 10).
//! Shadow-map and shadow-volume lights get the classification alone (`light diagnostics N`,
//! `debug/light_classes.frag`; a shadow-volume light's classes come from its stencil).
//! [`LightDiagnostics::shadow_mask`] turns any of them into the light's shadow mask; the
//! accuracy measurements use the visibility image's instead
//! ([`crate::VisibilityImage::shadow_mask`]), which the suite checks equal to it.

use crate::RenderResult;
use umbra_vk::{Buffer, BufferDesc, Context, Image};

/// How the lighting decided one pixel, decoded from the classification image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PixelClass {
    /// The depth comparisons agreed: shadowed (red). Also surfaces facing away from the light.
    MapShadowed,
    /// The depth comparisons agreed: lit (blue).
    MapLit,
    /// A silhouette pixel the accurate technique decided: shadowed (black).
    SilhouetteShadowed,
    /// A silhouette pixel the accurate technique decided: lit (green).
    SilhouetteLit,
    /// A surface that does not receive shadows (light grey).
    NotReceiver,
    /// A receiver the light does not reach: facing away from it, or outside a spot's cone
    /// (dark grey).
    Unreached,
    /// No geometry (the clear colour, mid grey).
    Background,
}

impl PixelClass {
    /// The class of an RGBA8 classification pixel.
    pub fn decode(rgba: [u8; 4]) -> Self {
        match [rgba[0], rgba[1], rgba[2]] {
            [255, 0, 0] => Self::MapShadowed,
            [0, 0, 255] => Self::MapLit,
            [0, 0, 0] => Self::SilhouetteShadowed,
            [0, 255, 0] => Self::SilhouetteLit,
            [191, 191, 191] => Self::NotReceiver,
            [64, 64, 64] => Self::Unreached,
            _ => Self::Background,
        }
    }

    /// Whether the accurate technique decided the pixel.
    pub fn is_silhouette(self) -> bool {
        matches!(self, Self::SilhouetteShadowed | Self::SilhouetteLit)
    }

    /// The light's shadow here: `Some(true)` shadowed, `Some(false)` lit, `None` where it is
    /// not in question (background, non-receivers, surfaces the light does not reach).
    pub fn shadowed(self) -> Option<bool> {
        match self {
            Self::MapShadowed | Self::SilhouetteShadowed => Some(true),
            Self::MapLit | Self::SilhouetteLit => Some(false),
            Self::NotReceiver | Self::Unreached | Self::Background => None,
        }
    }
}

/// The clear colour of the classification image (decodes as [`PixelClass::Background`]).
pub(crate) const BACKGROUND: [f32; 4] = [0.5, 0.5, 0.5, 1.0];

/// A light's silhouette map read back: texel-local points, row 0 first.
///
/// A spot or directional light's map is square. A point light's is a face atlas: its six
/// cube faces in three columns and two rows (+X, -X, +Y on top; -Y, +Z, -Z below), each face
/// `width / 3` texels per side: the 90° interior and a border of two texels beyond it on every
/// side (rendered by the face's widened frustum), which keeps every lookup's texels inside one
/// face.
#[derive(Clone, Debug)]
pub struct SilhouetteMapImage {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` points, `(0.5, 0.5)` where no silhouette passes.
    pub points: Vec<[f32; 2]>,
}

impl SilhouetteMapImage {
    /// The point of texel `(x, y)`.
    pub fn point(&self, x: u32, y: u32) -> [f32; 2] {
        self.points[(y * self.width + x) as usize]
    }

    /// Texels holding a point other than the default.
    pub fn silhouette_texels(&self) -> usize {
        self.points.iter().filter(|p| **p != [0.5, 0.5]).count()
    }
}

/// One light's diagnostic views, at the frame's size (RGBA8, row 0 at the top).
#[derive(Clone, Debug)]
pub struct LightDiagnostics {
    /// Index of the light.
    pub light: usize,
    /// Per-pixel classification (decode with [`PixelClass::decode`]).
    pub classification: Vec<u8>,
    /// Silhouette-map lights: red (alpha 255) where the pixel shows a stored silhouette point,
    /// alpha 0 elsewhere.
    pub points: Option<Vec<u8>>,
    /// The silhouette map, for silhouette-map lights.
    pub silhouette_map: Option<SilhouetteMapImage>,
    /// Hybrid lights: the stencil after the volume pass, one byte per pixel (with the
    /// `stencil` mask, bit 7 marks silhouette pixels and bits 0–6 hold the count).
    pub stencil: Option<Vec<u8>>,
}

impl LightDiagnostics {
    /// The light's shadow mask, per pixel as [`PixelClass::shadowed`] (row 0 at the top).
    pub fn shadow_mask(&self) -> Vec<Option<bool>> {
        self.classification.chunks_exact(4).map(|p| PixelClass::decode([p[0], p[1], p[2], p[3]]).shadowed()).collect()
    }

    /// Pixels the silhouette decided (green or black).
    pub fn silhouette_pixels(&self) -> u64 {
        self.classification
            .chunks_exact(4)
            .filter(|p| PixelClass::decode([p[0], p[1], p[2], p[3]]).is_silhouette())
            .count() as u64
    }

    /// The silhouette points drawn over `frame_rgba` (the frame's pixels): Sen et al. Fig. 9,
    /// middle. `None` for lights without points.
    pub fn points_over(&self, frame_rgba: &[u8]) -> Option<Vec<u8>> {
        let points = self.points.as_ref()?;
        Some(
            frame_rgba
                .chunks_exact(4)
                .zip(points.chunks_exact(4))
                .flat_map(|(f, m)| if m[3] > 127 { [m[0], m[1], m[2], 255] } else { [f[0], f[1], f[2], f[3]] })
                .collect(),
        )
    }

    /// Chan–Durand Fig. 10: volume overdraw in yellow (brighter where more volume fragments
    /// land; `overdraw` is `Frame::overdraw`, its red channel a count per pixel) with this
    /// light's silhouette pixels in green on top.
    pub fn fill_image(&self, overdraw: &[u8]) -> Vec<u8> {
        let max = overdraw.chunks_exact(4).map(|p| p[0]).max().unwrap_or(0).max(1);
        self.classification
            .chunks_exact(4)
            .zip(overdraw.chunks_exact(4))
            .flat_map(|(c, o)| {
                if PixelClass::decode([c[0], c[1], c[2], c[3]]).is_silhouette() {
                    [0, 255, 0, 255]
                } else if o[0] == 0 {
                    [0, 0, 0, 255]
                } else {
                    let v = (48 + u32::from(o[0]) * 207 / u32::from(max)) as u8;
                    [v, v, 0, 255]
                }
            })
            .collect()
    }
}

/// The two diagnostic render targets, reused by every light of a frame.
pub(crate) struct DiagnosticTargets {
    pub classification: Image,
    pub points: Image,
}

/// Host-visible copies of one light's classes and, where a stencil count decides some of its
/// pixels (shadow volumes, the hybrid), the stencil.
pub(crate) struct ClassReadback {
    pub classes: Buffer,
    pub stencil: Option<Buffer>,
}

impl ClassReadback {
    pub fn new(ctx: &Context, width: u32, height: u32, stencil: bool) -> RenderResult<Self> {
        let pixels = u64::from(width) * u64::from(height);
        Ok(Self {
            classes: Buffer::new(ctx, "diagnostics readback: classes", BufferDesc::readback(4 * pixels))?,
            stencil: match stencil {
                true => Some(Buffer::new(ctx, "diagnostics readback: stencil", BufferDesc::readback(pixels))?),
                false => None,
            },
        })
    }

    /// The light's diagnostics. Pixels nothing was drawn to (still the clear value, transparent
    /// black; the hybrid's additive classes never write alpha) are background. With `stencil_decides = Some((class, count_bits))`, pixels of `class` are
    /// the stencil's to decide: black where `stencil & count_bits` is non-zero, green where it
    /// is zero.
    pub fn read(&self, light: usize, stencil_decides: Option<(PixelClass, u8)>) -> RenderResult<LightDiagnostics> {
        let mut classification = self.classes.read()?;
        let stencil = self.stencil.as_ref().map(Buffer::read).transpose()?;
        let background = BACKGROUND.map(|c| (c * 255.0).round() as u8);
        for (i, p) in classification.chunks_exact_mut(4).enumerate() {
            if p == [0, 0, 0, 0] {
                p.copy_from_slice(&background);
                continue;
            }
            p[3] = 255;
            let (Some((class, bits)), Some(s)) = (stencil_decides, &stencil) else { continue };
            if PixelClass::decode([p[0], p[1], p[2], p[3]]) == class {
                let shadowed = s[i] & bits != 0;
                p[..3].copy_from_slice(if shadowed { &[0, 0, 0] } else { &[0, 255, 0] });
            }
        }
        Ok(LightDiagnostics { light, classification, points: None, silhouette_map: None, stencil })
    }
}

/// What the raster pass saw at every pixel (with `RendererDesc::gbuffer`), row 0 at the top:
/// the input of the exact reference (`umbra_reference::SurfaceImage::from_gbuffer`).
#[derive(Clone, Debug)]
pub struct GBuffer {
    /// World position; w = object index + 1, or 0 where no surface covers the pixel.
    pub position: Vec<[f32; 4]>,
    /// Unit geometric normal turned towards the camera (zero for a triangle seen edge-on); w = 0.
    pub normal: Vec<[f32; 4]>,
}

/// Host-visible copies of one light's diagnostic views and silhouette map.
pub(crate) struct DiagnosticReadback {
    pub classification: Buffer,
    pub points: Buffer,
    pub silhouette_map: Buffer,
    extent: (u32, u32),
}

impl DiagnosticReadback {
    pub fn new(ctx: &Context, width: u32, height: u32, silhouette_map: &Image) -> RenderResult<Self> {
        let frame = BufferDesc::readback(4 * u64::from(width) * u64::from(height));
        let extent = (silhouette_map.desc.width, silhouette_map.desc.height);
        let points = BufferDesc::readback(8 * u64::from(extent.0) * u64::from(extent.1));
        Ok(Self {
            classification: Buffer::new(ctx, "diagnostics readback: classification", frame)?,
            points: Buffer::new(ctx, "diagnostics readback: silhouette points", frame)?,
            silhouette_map: Buffer::new(ctx, "diagnostics readback: silhouette map", points)?,
            extent,
        })
    }

    /// Whether it is the readback of a silhouette map as large as `silhouette_map`.
    pub fn fits(&self, silhouette_map: &Image) -> bool {
        self.extent == (silhouette_map.desc.width, silhouette_map.desc.height)
    }

    pub fn read(&self, light: usize) -> RenderResult<LightDiagnostics> {
        let points = crate::visibility::rg32f_texels(&self.silhouette_map.read()?);
        Ok(LightDiagnostics {
            light,
            classification: self.classification.read()?,
            points: Some(self.points.read()?),
            silhouette_map: Some(SilhouetteMapImage { width: self.extent.0, height: self.extent.1, points }),
            stencil: None,
        })
    }
}
