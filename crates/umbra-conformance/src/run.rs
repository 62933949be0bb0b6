//! Running one case: load its scene, render it with every technique (twice, for
//! determinism), check the read-backs for NaN, and judge each technique's masks.

use crate::cases::{Case, Expect, Outcome, TECHNIQUES};
use crate::judge::{judge, Judgement};
use crate::{ConformanceError, ConformanceResult};
use serde::Serialize;
use std::path::{Path, PathBuf};
use umbra_reference::{error_image, SceneBvh};
use umbra_scene::{Scene, SceneError, Technique};
use umbra_shadows::{Frame, RenderError, Renderer, RendererDesc};
use umbra_vk::{Context, VkError};

/// How a technique fared on a case.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "status", content = "detail", rename_all = "snake_case")]
pub enum Verdict {
    /// Within the technique's own tolerance.
    Pass,
    /// Within the case's documented tolerance (the reason).
    Documented(String),
    /// The technique or the driver cannot run it (the typed error's message).
    Unsupported(String),
    /// Outside every tolerance, not deterministic, NaN in a read-back, or an untyped failure.
    Fail(String),
}

impl Verdict {
    /// Whether this counts as conformant.
    pub fn ok(&self) -> bool {
        !matches!(self, Self::Fail(_))
    }
}

/// One technique on one case.
#[derive(Clone, Debug, Serialize)]
pub struct TechniqueRun {
    /// The technique.
    pub technique: Technique,
    /// The verdict.
    pub verdict: Verdict,
    /// The masks' numbers (absent when nothing was rendered).
    pub judgement: Option<Judgement>,
    /// Two frames of the same scene gave identical pixels and classifications.
    pub deterministic: bool,
    /// Every float read back (G-buffer positions and normals) is finite.
    pub nan_free: bool,
    /// Notes: the hybrid's mask, driver issues.
    pub notes: Vec<String>,
    /// The frame (RGBA8, row 0 at the top), kept for pictures.
    #[serde(skip)]
    pub rgba: Vec<u8>,
    /// The first light's error image (RGBA8; `umbra_reference::error_image`'s colours).
    #[serde(skip)]
    pub error_rgba: Vec<u8>,
}

/// One case on one device.
#[derive(Clone, Debug, Serialize)]
pub struct CaseRun {
    /// The case's file stem.
    pub case: String,
    /// Its title (the scene's name, or the file stem when it failed to load).
    pub title: String,
    /// Why it is hard (the file's `# Why it is hard:` line).
    pub why: String,
    /// The device it ran on.
    pub device: String,
    /// Image size.
    pub size: (u32, u32),
    /// `TypedError` cases: the error loading gave, if it was typed.
    pub typed_error: Option<String>,
    /// One entry per technique that ran (none for `TypedError` cases).
    pub techniques: Vec<TechniqueRun>,
    /// The verdict of the case as a whole (`TypedError` cases only; see each technique).
    pub verdict: Verdict,
}

impl CaseRun {
    /// Every verdict is conformant.
    pub fn ok(&self) -> bool {
        self.verdict.ok() && self.techniques.iter().all(|t| t.verdict.ok())
    }
}

/// The scene file of `case` in `dir`.
pub fn case_path(dir: &Path, case: &Case) -> PathBuf {
    dir.join(format!("{}.toml", case.file))
}

/// The `# Why it is hard:` line of a case file.
pub fn why_hard(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let mut lines = text.lines().skip_while(|l| !l.starts_with("# Why it is hard:"));
    let mut why = lines.next().map(|l| l.trim_start_matches("# Why it is hard:").trim().to_owned()).unwrap_or_default();
    for l in lines.take_while(|l| l.starts_with("# ")) {
        why.push(' ');
        why.push_str(l.trim_start_matches("# ").trim());
    }
    why
}

/// The title in a case file's first line, `# Hard case N: <title>.` (for files that do not load).
fn header_title(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok()?;
    let first = text.lines().next()?;
    let (_, title) = first.strip_prefix("# Hard case ")?.split_once(": ")?;
    Some(title.trim_end_matches('.').to_owned())
}

/// Shadow-map and silhouette-map texels per side in every case (a light's `shadow_map_size`
/// wins): the suite judges numerical robustness at one fixed, fine size rather than at the
/// size a 256×192 frame would pick (`ShadowMapSettings::resolution_from_frame`: 256²). The
/// hybrid keeps its own default, from the frame.
pub const CASE_MAP_SIZE: u32 = 2048;

/// The suite's shadow-map memory budget (`RendererDesc::shadow_map_budget_bytes`), above the
/// 1 GiB default: case 20's three point lights take cube silhouette maps of 2048² per face,
/// 3 × 505 MB with the diagnostics' read-backs, beside its five 2D lights' 5 × 84 MB.
pub const CASE_BUDGET_BYTES: u64 = 2 << 30;

/// Runs `case` (scene file in `dir`) with every technique at `size` on `ctx`.
pub fn run_case(ctx: &Context, dir: &Path, case: &Case, size: (u32, u32)) -> ConformanceResult<CaseRun> {
    let path = case_path(dir, case);
    let loaded = umbra_scene::load_scene_file(&path);
    let mut run = CaseRun {
        case: case.file.to_owned(),
        title: loaded
            .as_ref()
            .map_or_else(|_| header_title(&path).unwrap_or_else(|| case.file.to_owned()), |s| s.name.clone()),
        why: why_hard(&path),
        device: ctx.capabilities().device_name.clone(),
        size,
        typed_error: None,
        techniques: Vec::new(),
        verdict: Verdict::Pass,
    };
    match (case.outcome, loaded) {
        (Outcome::TypedError, Err(e @ SceneError::SceneFile { .. })) => {
            run.typed_error = Some(e.to_string());
        }
        (Outcome::TypedError, Ok(_)) => {
            run.verdict = Verdict::Fail("the scene loaded: a typed error was expected".into())
        }
        (Outcome::TypedError, Err(e)) => run.verdict = Verdict::Fail(format!("unexpected error: {e}")),
        (Outcome::Judged(_), Err(source)) => return Err(ConformanceError::Scene { case: case.file.into(), source }),
        (Outcome::Judged(_), Ok(scene)) => {
            let bvh = SceneBvh::build(&scene);
            for &technique in TECHNIQUES {
                let expect = case.expect(technique).unwrap_or(Expect::Strict);
                run.techniques.push(run_technique(ctx, &scene, &bvh, technique, expect, size)?);
            }
        }
    }
    Ok(run)
}

/// Renders `scene` with every light on `technique`, twice, and judges the second frame by
/// `expect`.
pub fn run_technique(
    ctx: &Context,
    scene: &Scene,
    bvh: &SceneBvh,
    technique: Technique,
    expect: Expect,
    size: (u32, u32),
) -> ConformanceResult<TechniqueRun> {
    let mut scene = scene.clone();
    for l in &mut scene.lights {
        l.technique = technique;
    }
    let mut desc = RendererDesc::new(size.0, size.1);
    desc.shadow_map.resolution = Some(CASE_MAP_SIZE);
    desc.shadow_map_budget_bytes = CASE_BUDGET_BYTES;
    desc.diagnostics = true;
    desc.gbuffer = true;
    desc.read_visibility = true;
    let mut out = TechniqueRun {
        technique,
        verdict: Verdict::Pass,
        judgement: None,
        deterministic: false,
        nan_free: false,
        notes: Vec::new(),
        rgba: Vec::new(),
        error_rgba: Vec::new(),
    };
    let frames = Renderer::new(ctx, desc).and_then(|mut r| {
        if technique == Technique::Hybrid {
            out.notes.push(format!("mask: {}", r.mask().name()));
        }
        Ok((r.render(&scene)?, r.render(&scene)?))
    });
    let (first, second) = match frames {
        Ok(f) => f,
        Err(e @ (RenderError::Vk(VkError::Unsupported { .. }) | RenderError::UnsupportedLight { .. })) => {
            out.verdict = Verdict::Unsupported(e.to_string());
            return Ok(out);
        }
        Err(e) => return Err(e.into()),
    };
    out.deterministic = same_output(&first, &second);
    out.nan_free = second
        .gbuffer
        .as_ref()
        .is_some_and(|g| g.position.iter().chain(&g.normal).all(|v| v.iter().all(|c| c.is_finite())));
    let (j, masks) = judge(&scene, bvh, &second, technique, ctx.capabilities().sub_pixel_precision_bits)?;
    if let Some((mask, truth)) = masks.first() {
        out.error_rgba = error_image(mask, truth);
    }
    out.rgba = second.rgba;
    out.verdict = verdict(&j, expect, out.deterministic, out.nan_free);
    out.judgement = Some(j);
    Ok(out)
}

fn same_output(a: &Frame, b: &Frame) -> bool {
    a.rgba == b.rgba
        && a.visibility == b.visibility
        && a.diagnostics.len() == b.diagnostics.len()
        && a.diagnostics.iter().zip(&b.diagnostics).all(|(x, y)| x.classification == y.classification)
}

fn verdict(j: &Judgement, expect: Expect, deterministic: bool, nan_free: bool) -> Verdict {
    if !nan_free {
        return Verdict::Fail("NaN or infinity in the G-buffer read-back".into());
    }
    if !deterministic {
        return Verdict::Fail("two frames of the same scene differ".into());
    }
    if j.class_disagreements > 0 {
        return Verdict::Fail(format!(
            "the visibility images and the classifications disagree on {} pixels",
            j.class_disagreements
        ));
    }
    if !j.thin_lights.is_empty() {
        return Verdict::Fail(format!("lights {:?} decide too few pixels to judge", j.thin_lights));
    }
    let summary = format!(
        "{} of {} pixels unexplained ({} volume, {} map, {} ray; {} on seams, {} snapped, {} in texel bands, {} edge-on)",
        j.unexplained(),
        j.compared,
        j.volume_unexplained,
        j.map_unexplained,
        j.ray_unexplained,
        j.seam,
        j.snapping,
        j.texel_band,
        j.edge_on
    );
    match expect {
        Expect::Strict if j.unexplained() == 0 => Verdict::Pass,
        Expect::Strict => Verdict::Fail(summary),
        Expect::Misses { min, why } => {
            let missed = if j.shadowed == 0 { 0.0 } else { j.false_lit as f64 / j.shadowed as f64 };
            if j.unexplained() == 0 && missed >= min {
                Verdict::Documented(format!(
                    "{why} ({:.0} % of the true shadow missed, documented at least {:.0} %)",
                    100.0 * missed,
                    100.0 * min
                ))
            } else {
                Verdict::Fail(format!(
                    "{summary}; {:.0} % of the true shadow missed, documented at least {:.0} % ({why})",
                    100.0 * missed,
                    100.0 * min
                ))
            }
        }
        Expect::Documented { min, max, why } => {
            let f = j.unexplained_fraction();
            if (min..=max).contains(&f) {
                Verdict::Documented(format!(
                    "{why} ({:.3} % unexplained, documented {:.3}–{:.3} %)",
                    100.0 * f,
                    100.0 * min,
                    100.0 * max
                ))
            } else {
                Verdict::Fail(format!(
                    "{summary}: outside the documented {:.3}–{:.3} % ({why})",
                    100.0 * min,
                    100.0 * max
                ))
            }
        }
    }
}
