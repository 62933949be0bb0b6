//! The poster's picture: a title, then one column per technique (its image above its error
//! image, a caption with GPU ms and wrong pixels), and the error colours' legend.

use super::{technique_title, Poster};
use crate::sweep::Measured;
use crate::{BenchError, BenchResult};
use plotters::prelude::*;
use std::path::Path;

/// Space around and between the tiles, in pixels.
const GAP: u32 = 12;
/// The title bar's height.
const TITLE_H: u32 = 64;
/// Each column's header (technique, configuration) above its image.
const HEADER_H: u32 = 52;
/// Each column's caption (GPU ms, wrong pixels) below its error image.
const CAPTION_H: u32 = 56;
/// The legend's height at the bottom.
const LEGEND_H: u32 = 36;

/// The error image's colours ([`umbra_reference::error_image`]) and what they mean.
const LEGEND: [([u8; 3], &str); 6] = [
    ([255, 0, 0], "false shadow"),
    ([0, 255, 255], "false light"),
    ([64, 64, 64], "shadow, correct"),
    ([190, 190, 190], "light, correct"),
    ([0, 0, 96], "undecided"),
    ([0, 0, 0], "no surface"),
];

/// Composes the poster of `measured` (in `poster.records` order) and saves it as PNG.
pub fn save(poster: &Poster, measured: &[Measured], path: &Path) -> BenchResult<()> {
    let (w, h) = (poster.width, poster.height);
    let columns = measured.len().max(1) as u32;
    let width = GAP + columns * (w + GAP);
    let height = TITLE_H + HEADER_H + 2 * h + GAP + CAPTION_H + LEGEND_H + GAP;
    let mut rgb = vec![255u8; 3 * width as usize * height as usize];
    for (i, m) in measured.iter().enumerate() {
        let x = GAP + i as u32 * (w + GAP);
        let y = TITLE_H + HEADER_H;
        blit(&mut rgb, width, &m.image, (w, h), (x, y));
        if m.error_image.len() == m.image.len() {
            blit(&mut rgb, width, &m.error_image, (w, h), (x, y + h + GAP));
        }
    }
    let err = |e: &dyn std::fmt::Display| BenchError::output(path, e);
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        let text = |size: u32, colour: &RGBColor| ("sans-serif", size).into_font().color(colour);
        let title = format!(
            "umbra · {} · {}×{} on {}, {} — every technique on the same frame, against the exact ray-traced reference",
            poster.scene, w, h, poster.device, poster.driver
        );
        root.draw(&Text::new(title, (GAP as i32, 20), text(22, &BLACK))).map_err(|e| err(&e))?;
        for (i, m) in measured.iter().enumerate() {
            let x = (GAP + i as u32 * (w + GAP)) as i32;
            let r = &m.record;
            let header = technique_title(r.config.technique);
            root.draw(&Text::new(header, (x, TITLE_H as i32), text(22, &BLACK))).map_err(|e| err(&e))?;
            let detail = config_detail(&r.config, r.map_resolution);
            root.draw(&Text::new(detail, (x, TITLE_H as i32 + 26), text(15, &RGBColor(90, 90, 90))))
                .map_err(|e| err(&e))?;
            let y = (TITLE_H + HEADER_H + 2 * h + GAP + 8) as i32;
            let gpu = r.gpu_ms.map_or_else(
                || "GPU time n/a (no timestamps)".into(),
                |g| format!("{:.2} ms GPU (p25–p75 {:.2}–{:.2})", g.median, g.p25, g.p75),
            );
            root.draw(&Text::new(gpu, (x, y), text(18, &BLACK))).map_err(|e| err(&e))?;
            let a = &r.accuracy;
            let wrong = format!(
                "{:.3} % wrong ({} of {} px: {} false shadow, {} false light)",
                100.0 * a.wrong_fraction,
                a.all.wrong,
                a.all.compared,
                a.all.false_shadow,
                a.all.false_lit
            );
            root.draw(&Text::new(wrong, (x, y + 24), text(14, &BLACK))).map_err(|e| err(&e))?;
        }
        let mut x = GAP as i32;
        let y = (height - LEGEND_H - GAP + 8) as i32;
        root.draw(&Text::new("error images:", (x, y), text(16, &BLACK))).map_err(|e| err(&e))?;
        x += 120;
        for (c, label) in LEGEND {
            let swatch = Rectangle::new([(x, y), (x + 18, y + 18)], RGBColor(c[0], c[1], c[2]).filled());
            root.draw(&swatch).map_err(|e| err(&e))?;
            root.draw(&Rectangle::new([(x, y), (x + 18, y + 18)], BLACK)).map_err(|e| err(&e))?;
            root.draw(&Text::new(label, (x + 24, y), text(16, &BLACK))).map_err(|e| err(&e))?;
            x += 40 + 9 * label.len() as i32;
        }
        root.present().map_err(|e| err(&e))?;
    }
    image::save_buffer(path, &rgb, width, height, image::ColorType::Rgb8).map_err(|e| err(&e))
}

/// `1024² map, PCF 2×2`, `256² map (default), stencil mask`, `z-fail/z-pass per caster`:
/// `resolution` is the map's size where the configuration names none.
fn config_detail(c: &crate::record::Config, resolution: Option<u32>) -> String {
    let map = match (c.sm_size, resolution) {
        (Some(s), _) => Some(format!("{s}² map")),
        (None, Some(s)) => Some(format!("{s}² map (default)")),
        (None, None) => None,
    };
    let rest = match (c.technique, c.filter, c.mask) {
        (_, Some(f), _) => Some(format!("{f} filter")),
        (_, _, Some(m)) => Some(format!("{m} computation mask")),
        ("silmap", ..) => Some("dual-grid silhouette points".to_owned()),
        ("sv", ..) => Some("z-pass / z-fail per caster, exact".to_owned()),
        ("rt", ..) => Some("a shadow ray per pixel through a BVH, exact".to_owned()),
        ("hybrid-rt", ..) => Some("rays only where the map is unsure, exact".to_owned()),
        _ => None,
    };
    map.into_iter().chain(rest).collect::<Vec<_>>().join(", ")
}

/// Copies an RGBA8 image of `size` into the RGB8 canvas `width` pixels wide at `at`.
fn blit(canvas: &mut [u8], width: u32, rgba: &[u8], size: (u32, u32), at: (u32, u32)) {
    let (w, h) = (size.0 as usize, size.1 as usize);
    for row in 0..h {
        for col in 0..w {
            let s = 4 * (row * w + col);
            let d = 3 * ((at.1 as usize + row) * width as usize + at.0 as usize + col);
            if let (Some(src), Some(dst)) = (rgba.get(s..s + 3), canvas.get_mut(d..d + 3)) {
                dst.copy_from_slice(src);
            }
        }
    }
}
