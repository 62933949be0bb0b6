//! What the window shows: the image or one of the renderer's diagnostic views, as RGBA8.

use glam::{Vec3, Vec4};
use umbra::shadows::Frame;

/// A view the window cycles through (`V`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The rendered image.
    Image,
    /// The selected light's per-pixel classification (`RendererDesc::diagnostics`).
    Classification,
    /// Shadow-volume overdraw as a heat map (`ShadowVolumeSettings::overdraw`).
    Overdraw,
    /// The selected light's stencil after its volume pass: white where it is not zero.
    Stencil,
}

impl View {
    /// The next view in the cycle.
    pub fn next(self) -> Self {
        match self {
            View::Image => View::Classification,
            View::Classification => View::Overdraw,
            View::Overdraw => View::Stencil,
            View::Stencil => View::Image,
        }
    }

    /// Its name in the title.
    pub fn name(self) -> &'static str {
        match self {
            View::Image => "image",
            View::Classification => "classification",
            View::Overdraw => "volume overdraw",
            View::Stencil => "stencil",
        }
    }

    /// Whether the renderer must render its diagnostic views for this one.
    pub fn needs_diagnostics(self) -> bool {
        matches!(self, View::Classification | View::Stencil)
    }

    /// Whether the renderer must count volume overdraw for this one.
    pub fn needs_overdraw(self) -> bool {
        self == View::Overdraw
    }
}

/// The pixels of `view` for `light` in `frame`, converted into `scratch` where needed (kept
/// between frames, so nothing is allocated once it has grown), or the image with a note saying
/// why the view is not available this frame.
pub fn pixels<'a>(
    view: View,
    frame: &'a Frame,
    light: usize,
    scratch: &'a mut Vec<u8>,
) -> (&'a [u8], Option<&'static str>) {
    let diagnostics = frame.diagnostics.iter().find(|d| d.light == light);
    match view {
        View::Image => (&frame.rgba, None),
        View::Classification => match diagnostics {
            Some(d) => (&d.classification, None),
            None => (&frame.rgba, Some("selected light has no classification (unshadowed or skipped)")),
        },
        View::Overdraw => match &frame.overdraw {
            Some(o) => {
                scratch.clear();
                scratch.extend(o.chunks_exact(4).flat_map(|p| heat(p[0])));
                (scratch, None)
            }
            None => (&frame.rgba, Some("no light drew shadow volumes")),
        },
        View::Stencil => match diagnostics.and_then(|d| d.stencil.as_ref()) {
            Some(s) => {
                scratch.clear();
                scratch.extend(s.iter().flat_map(|&s| stencil_texel(s)));
                (scratch, None)
            }
            None => (&frame.rgba, Some("selected light has no stencil (not a volume or hybrid light)")),
        },
    }
}

/// White where a stencil count (bits 0–6; bit 7 is the hybrid's silhouette mark) is not zero.
pub fn stencil_texel(s: u8) -> [u8; 4] {
    if s & 0x7f != 0 {
        [255; 4]
    } else {
        [0, 0, 0, 255]
    }
}

/// A black → blue → red → yellow → white ramp over 0..=32 fragments (more saturates).
pub fn heat(count: u8) -> [u8; 4] {
    let t = (count as f32 / 32.0).min(1.0);
    let stops = [Vec3::ZERO, Vec3::new(0.1, 0.2, 0.9), Vec3::new(0.9, 0.1, 0.1), Vec3::new(1.0, 0.9, 0.1), Vec3::ONE];
    let x = t * (stops.len() - 1) as f32;
    let i = (x as usize).min(stops.len() - 2);
    let c = stops[i].lerp(stops[i + 1], x - i as f32);
    let c = Vec4::from((c * 255.0, 255.0));
    [c.x as u8, c.y as u8, c.z as u8, c.w as u8]
}
