//! `umbra-bench fingerprint`: one line per configuration with three hashes of everything a frame
//! returns except its times — one of the pixels, the overdraw and diagnostic views and the
//! G-buffer, one of the report with every `*_ms` field left out, one of the visibility images —
//! and, where the frame has both, how many pixels the lights' visibility images and their
//! classifications disagree on (`masks N`, `VisibilityImage::disagreements_with`). Run it before and
//! after a refactor that must not change behaviour and `diff` the two outputs: equal lines are
//! the same images, bit for bit, and the same report fields.

use crate::{scenes, BenchResult};
use serde_json::Value;
use umbra_scene::Technique;
use umbra_shadows::{Frame, MaskKind, Renderer, RendererDesc, VolumeMode};

/// Arguments of `umbra-bench fingerprint`.
#[derive(clap::Args, Debug)]
pub struct FingerprintArgs {
    /// Scenes: procedural names, scene files or glTF paths.
    #[arg(long, value_delimiter = ',', default_value = "cubes,cage,tree,pins,ball,plaza,suzanne.glb")]
    scenes: Vec<String>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "128x96", value_parser = crate::parse_size)]
    size: (u32, u32),
    /// Report fields to leave out as well, wherever they are (fields added since the run to
    /// compare with: the report only ever gains fields).
    #[arg(long, value_delimiter = ',')]
    ignore: Vec<String>,
}

/// The variants of the renderer every scene and technique is fingerprinted under.
const VARIANTS: &[&str] = &["default", "views", "no-cull", "stencil-mask", "no-mask", "zpass", "culled", "spots"];

/// Renders every scene × technique × variant (two frames each: the second, warm, is hashed) and
/// prints `scene technique variant images HASH report HASH` lines, or the error a
/// configuration gets.
pub fn run(args: &FingerprintArgs) -> BenchResult<()> {
    let ctx = umbra_vk::Context::new()?;
    for name in &args.scenes {
        for technique in Technique::ALL {
            for &variant in VARIANTS {
                let line = match fingerprint(&ctx, name, technique, variant, args) {
                    Ok(f) => format!(
                        "images {:016x} report {:016x} visibility {:016x} masks {}",
                        f.images,
                        f.report,
                        f.visibility,
                        f.mask_disagreements.map_or_else(|| "-".into(), |n| n.to_string())
                    ),
                    Err(e) => format!("error: {e}"),
                };
                println!("{name} {} {variant} {line}", technique.name());
            }
        }
    }
    Ok(())
}

fn fingerprint(
    ctx: &umbra_vk::Context,
    name: &str,
    technique: Technique,
    variant: &str,
    args: &FingerprintArgs,
) -> BenchResult<Fingerprint> {
    let (width, height) = args.size;
    let mut scene = scenes::load(
        name,
        scenes::LightArgs { spot_lights: variant == "spots", light_range: (variant == "culled").then_some(6.0) },
    )?;
    for light in &mut scene.lights {
        light.technique = technique;
    }
    let mut desc = RendererDesc::new(width, height);
    match variant {
        "views" => {
            desc.diagnostics = true;
            desc.gbuffer = true;
            desc.read_visibility = true;
            desc.shadow_volume.overdraw = true;
        }
        "no-cull" => desc.cull = false,
        "stencil-mask" => {
            desc.hybrid.mask = Some(MaskKind::Stencil);
            desc.hybrid.cull_blockers = true;
            desc.diagnostics = true;
        }
        "no-mask" => {
            desc.hybrid.mask = Some(MaskKind::None);
            desc.shadow_volume.overdraw = true;
        }
        "zpass" => desc.shadow_volume.mode = VolumeMode::ZPass,
        _ => {}
    }
    let mut renderer = Renderer::new(ctx, desc)?;
    renderer.render(&scene)?;
    let frame = renderer.render(&scene)?;
    Ok(hash_frame(&frame, &args.ignore))
}

/// What `fingerprint` prints of one frame.
struct Fingerprint {
    images: u64,
    report: u64,
    visibility: u64,
    /// Pixels where a light's visibility image and its classification give another shadow mask,
    /// summed over the lights that have both.
    mask_disagreements: Option<u64>,
}

/// FNV-1a over the images of `frame` (pixels, overdraw, diagnostic views, G-buffer), over its
/// report but for its times and the fields `ignore`d, and over its visibility images.
fn hash_frame(frame: &Frame, ignore: &[String]) -> Fingerprint {
    let mut h = Fnv::default();
    h.bytes(&frame.rgba);
    if let Some(o) = &frame.overdraw {
        h.bytes(o);
    }
    for d in &frame.diagnostics {
        h_light(&mut h, d.light);
        h.bytes(&d.classification);
        for part in [&d.points, &d.stencil].into_iter().flatten() {
            h.bytes(part);
        }
        if let Some(m) = &d.silhouette_map {
            m.points.iter().flatten().for_each(|f| h.bytes(&f.to_le_bytes()));
        }
    }
    if let Some(g) = &frame.gbuffer {
        g.position.iter().chain(&g.normal).flatten().for_each(|f| h.bytes(&f.to_le_bytes()));
    }
    let mut report = serde_json::to_value(&frame.report).unwrap_or(Value::Null);
    strip(&mut report, ignore);
    let mut r = Fnv::default();
    r.bytes(report.to_string().as_bytes());
    let mut v = Fnv::default();
    let mut mask_disagreements = None;
    for image in &frame.visibility {
        h_light(&mut v, image.light);
        image.texels.iter().flatten().for_each(|f| v.bytes(&f.to_le_bytes()));
        if let Some(d) = frame.diagnostics.iter().find(|d| d.light == image.light) {
            *mask_disagreements.get_or_insert(0) += image.disagreements_with(&d.shadow_mask());
        }
    }
    Fingerprint { images: h.0, report: r.0, visibility: v.0, mask_disagreements }
}

fn h_light(h: &mut Fnv, light: usize) {
    h.bytes(light.to_string().as_bytes());
}

/// Removes every `*_ms` field (GPU and CPU times) and every field named in `ignore`, recursively.
fn strip(value: &mut Value, ignore: &[String]) {
    match value {
        Value::Object(map) => {
            map.retain(|k, _| !k.ends_with("_ms") && !ignore.contains(k));
            map.values_mut().for_each(|v| strip(v, ignore));
        }
        Value::Array(items) => items.iter_mut().for_each(|v| strip(v, ignore)),
        _ => {}
    }
}

struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}
