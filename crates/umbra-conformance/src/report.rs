//! The conformance table (`docs/hard-cases.md`) and a picture per case.

use crate::run::{CaseRun, Verdict};
use crate::{ConformanceError, ConformanceResult, TECHNIQUES};
use std::fmt::Write;
use std::path::Path;
use umbra_scene::Technique;

/// A verdict in one table cell.
pub fn cell(v: &Verdict) -> &'static str {
    match v {
        Verdict::Pass => "pass",
        Verdict::Documented(_) => "documented tolerance",
        Verdict::Unsupported(_) => "unsupported",
        Verdict::Fail(_) => "**FAIL**",
    }
}

/// One line per device after the first: in how many case–technique runs it gives the first
/// device's judgement (compared, shadowed and wrong pixels, and the verdict) and the same
/// frame, pixel for pixel, naming the runs that differ.
pub fn agreement(devices: &[(String, Vec<CaseRun>)]) -> String {
    let mut md = String::new();
    let Some(((first, reference), others)) = devices.split_first() else { return md };
    for (name, runs) in others {
        let (mut pairs, mut same_judgement, mut same_frame, mut differ) = (0, 0, 0, Vec::new());
        for (a, b) in reference.iter().zip(runs) {
            for (ta, tb) in a.techniques.iter().zip(&b.techniques) {
                pairs += 1;
                let counts =
                    |t: &crate::run::TechniqueRun| t.judgement.as_ref().map(|j| (j.compared, j.shadowed, j.wrong));
                if counts(ta) == counts(tb) && ta.verdict == tb.verdict {
                    same_judgement += 1;
                } else {
                    differ.push(format!("{} {}", a.case, ta.technique.name()));
                }
                same_frame += usize::from(ta.rgba == tb.rgba);
            }
        }
        let _ = write!(
            md,
            "- `{name}` gives `{first}`'s judgement (compared, shadowed and wrong pixels, verdict) in {same_judgement} \
             of {pairs} case–technique runs, and the same frame pixel for pixel in {same_frame}"
        );
        if differ.is_empty() {
            md.push_str(".\n");
        } else {
            let more = differ.len().saturating_sub(6);
            differ.truncate(6);
            let more = if more > 0 { format!(" and {more} more") } else { String::new() };
            let _ = writeln!(md, "; the judgement differs in {}{more}.", differ.join(", "));
        }
    }
    md
}

/// The table of cases × techniques × devices, then per case its reason, picture and every
/// non-pass verdict's detail. `devices` pairs a device name with its runs (same case order);
/// `images` is the pictures' folder relative to the page.
pub fn markdown(devices: &[(String, Vec<CaseRun>)], images: &str) -> String {
    let mut md = String::new();
    let Some((_, first)) = devices.first() else { return md };
    let _ = write!(md, "| # | case |");
    for (d, _) in devices {
        for t in TECHNIQUES {
            let _ = write!(md, " {} ({}) |", t.column(), d);
        }
    }
    md.push_str("\n|---|---|");
    md.push_str(&"---|".repeat(devices.len() * TECHNIQUES.len()));
    md.push('\n');
    for (i, case) in first.iter().enumerate() {
        let _ = write!(md, "| {} | [{}](#{}) |", number(&case.case), case.title, case.case);
        for (_, runs) in devices {
            let run = &runs[i];
            if run.techniques.is_empty() {
                let v = if run.verdict.ok() { "typed error" } else { "**FAIL**" };
                md.push_str(&format!(" {v} |").repeat(TECHNIQUES.len()));
            } else {
                for t in &run.techniques {
                    let _ = write!(md, " {} |", cell(&t.verdict));
                }
            }
        }
        md.push('\n');
    }
    for (i, case) in first.iter().enumerate() {
        let _ =
            write!(md, "\n### <a id=\"{}\"></a>{}. {}\n\n{}\n\n", case.case, number(&case.case), case.title, case.why);
        if case.techniques.is_empty() {
            for (d, runs) in devices {
                let e = runs[i].typed_error.as_deref().unwrap_or("none");
                let _ = writeln!(md, "- {d}: {} — `{e}`", cell(&runs[i].verdict));
            }
            continue;
        }
        let _ = writeln!(
            md,
            "![{}]({images}/{}.png)\n\n*Left to right: the frame with shadow volumes, then the first light's error \
             image for SM, silmap, SV and hybrid (red false shadow, cyan false light, greys correct); {}.*\n",
            case.title, case.case, devices[0].0
        );
        for (d, runs) in devices {
            for t in &runs[i].techniques {
                let detail = match &t.verdict {
                    Verdict::Pass => None,
                    Verdict::Documented(s) | Verdict::Unsupported(s) | Verdict::Fail(s) => Some(s.as_str()),
                };
                let notes = t.notes.join("; ");
                if detail.is_some() || !notes.is_empty() {
                    let _ = writeln!(
                        md,
                        "- {} on {d}: {}{}{}",
                        t.technique.column(),
                        cell(&t.verdict),
                        detail.map(|s| format!(" — {s}")).unwrap_or_default(),
                        if notes.is_empty() { String::new() } else { format!(" ({notes})") }
                    );
                }
            }
        }
    }
    md
}

fn number(file: &str) -> &str {
    file.split('-').next().unwrap_or(file)
}

/// Saves `run`'s picture: the shadow-volume frame, then each technique's first-light error
/// image, side by side with 4-pixel gaps (black where a technique did not run).
pub fn save_picture(run: &CaseRun, path: &Path) -> ConformanceResult<()> {
    let (w, h) = run.size;
    let gap = 4;
    let panels: Vec<&[u8]> = std::iter::once(
        run.techniques.iter().find(|t| t.technique == Technique::ShadowVolume).map_or(&[][..], |t| &t.rgba[..]),
    )
    .chain(run.techniques.iter().map(|t| &t.error_rgba[..]))
    .collect();
    let width = panels.len() as u32 * (w + gap) - gap;
    let mut img = image::RgbaImage::from_pixel(width, h, image::Rgba([255, 255, 255, 255]));
    for (k, panel) in panels.iter().enumerate() {
        let x0 = k as u32 * (w + gap);
        for y in 0..h {
            for x in 0..w {
                let i = ((y * w + x) * 4) as usize;
                let p = panel.get(i..i + 4).map_or([0, 0, 0, 255], |p| [p[0], p[1], p[2], 255]);
                img.put_pixel(x0 + x, y, image::Rgba(p));
            }
        }
    }
    img.save(path).map_err(|e| ConformanceError::Output { path: path.to_owned(), message: e.to_string() })
}
