//! `summary.md`: per scene, one table row per configuration, the plots, and what was skipped.

use crate::record::{Record, Results};
use std::fmt::Write;

fn ms(v: Option<f64>) -> String {
    v.map_or_else(|| "n/a".into(), |v| format!("{v:.3}"))
}

fn pct(v: f64) -> String {
    format!("{:.3}", 100.0 * v)
}

/// The table of `records` (one scene), fastest first.
pub fn table(records: &[&Record]) -> String {
    let mut rows: Vec<&&Record> = records.iter().collect();
    rows.sort_by(|a, b| {
        let t = |r: &Record| r.gpu_ms.map_or(f64::INFINITY, |s| s.median);
        t(a).total_cmp(&t(b))
    });
    let mut s = String::from(
        "| configuration | GPU ms median (p25–p75) | --no-cull GPU ms (saved) | passes (--no-cull) | CPU silhouette ms | wrong % | false shadow % | false lit % | edge-band wrong % | max wrong distance px | O (overdraw) | P % | masked volume fragments |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in rows {
        let a = &r.accuracy;
        let gpu = r.gpu_ms.map_or_else(|| "n/a".into(), |g| format!("{:.3} ({:.3}–{:.3})", g.median, g.p25, g.p75));
        let (no_cull, passes) = match &r.no_cull {
            Some(n) => {
                let t = n.gpu_ms.map(|g| g.median);
                let saved = t.zip(r.gpu_ms.map(|g| g.median)).map(|(n, p)| (n - p) / n);
                let same = if n.identical { "" } else { ", IMAGE DIFFERS" };
                (
                    format!("{} ({}{same})", ms(t), saved.map_or_else(|| "n/a".into(), |v| format!("{}%", pct(v)))),
                    format!("{} ({})", r.recorded_passes, n.recorded_passes),
                )
            }
            None => ("–".into(), r.recorded_passes.to_string()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.config.label(),
            gpu,
            no_cull,
            passes,
            ms(r.cpu_silhouette_ms.map(|c| c.median)),
            pct(a.wrong_fraction),
            pct(a.false_shadow_fraction),
            pct(a.false_lit_fraction),
            pct(a.edge_band_wrong_fraction),
            a.max_wrong_distance_px.map_or_else(|| "–".into(), |d| format!("{d:.1}")),
            r.fill.volume_overdraw.map_or_else(|| "–".into(), |o| format!("{o:.2}")),
            r.fill.silhouette_fraction.map_or_else(|| "–".into(), pct),
            r.fill.masked_volume_fragments.map_or_else(|| "–".into(), |m| m.to_string()),
        );
    }
    s
}

/// The shadow rays of `records` (one scene) that cast any, `None` without.
pub fn rays_table(records: &[&Record]) -> Option<String> {
    let rows: Vec<_> = records.iter().filter_map(|r| r.rays.map(|rays| (r, rays))).collect();
    if rows.is_empty() {
        return None;
    }
    let mut s = String::from(
        "| configuration | rays | rays per pixel % | BVH nodes per ray mean (p95) | triangles per ray mean (p95) | BVH KiB | BVH build ms (meshes + top) |\n\
         | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for (r, x) in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.1} ({}) | {:.2} ({}) | {:.0} | {:.2} + {:.3} |",
            r.config.label(),
            x.rays,
            pct(x.ray_fraction),
            x.nodes_mean,
            x.nodes_p95,
            x.triangles_mean,
            x.triangles_p95,
            x.bvh_bytes as f64 / 1024.0,
            x.mesh_build_ms,
            x.top_build_ms,
        );
    }
    Some(s)
}

/// The whole summary, with links to the plots written beside it.
pub fn markdown(results: &Results, scenes: &[String], plots: &[(String, Vec<String>)]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# umbra-bench sweep\n");
    let _ = writeln!(
        s,
        "Device: **{}** ({}); depthBounds: {}; timestamps: {}.",
        results.device, results.driver, results.depth_bounds, results.timestamps
    );
    if let Some(r) = results.records.first() {
        let _ = writeln!(
            s,
            "Image {}×{}, {} warm-up frames then {} timed frames per configuration.\n",
            r.width, r.height, results.warmup, r.frames
        );
    }
    let _ = writeln!(
        s,
        "GPU times are medians over the timed frames of the technique's passes (diagnostic passes: G-buffer, classification, overdraw, excluded). \
         Wrong pixels: pixels whose lit/shadowed state differs from the exact reference (obvhs shadow rays from the G-buffer), over the pixels both call in question; \
         the edge band is the pixels within 2 px of a true shadow edge.\n"
    );
    for scene in scenes {
        let records: Vec<&Record> = results.records.iter().filter(|r| &r.config.scene == scene).collect();
        let _ = writeln!(s, "## {scene}\n");
        if let Some(r) = records.first() {
            let _ = writeln!(s, "{} triangles.\n", r.triangles);
        }
        for (sc, files) in plots {
            if sc == scene {
                for f in files {
                    let _ = writeln!(s, "![{f}]({f})\n");
                }
            }
        }
        s.push_str(&table(&records));
        s.push('\n');
        if let Some(rays) = rays_table(&records) {
            let _ = writeln!(s, "Shadow rays (last frame, counted by the diagnostics' `ray stats` passes):\n");
            s.push_str(&rays);
            s.push('\n');
        }
    }
    if !results.skipped.is_empty() {
        let _ = writeln!(s, "## Skipped\n");
        for k in &results.skipped {
            let _ = writeln!(s, "- {} on {}: {}", k.config.label(), k.config.scene, k.reason);
        }
    }
    s
}
