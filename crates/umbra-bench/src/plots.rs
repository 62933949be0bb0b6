//! The sweep's pictures, drawn with plotters: per scene the accuracy-versus-time chart (with
//! its Pareto front), the per-pass time breakdown (Chan–Durand Fig. 12) and the fill chart
//! (volume overdraw against silhouette pixels per shadow-map size, Fig. 11).

use crate::record::Record;
use crate::{BenchError, BenchResult};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::OnceLock;

/// Where the TrueType font comes from unless `UMBRA_FONT` names one (Debian's
/// fonts-dejavu-core, which `ci/setup.sh` installs).
pub const DEFAULT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

const SIZE: (u32, u32) = (900, 600);

/// One colour per technique, the same in every chart.
fn colour(technique: &str) -> RGBColor {
    match technique {
        "sm" => RGBColor(31, 119, 180),
        "silmap" => RGBColor(44, 160, 44),
        "sv" => RGBColor(214, 39, 40),
        "rt" => RGBColor(148, 103, 189),
        "hybrid-rt" => RGBColor(140, 86, 75),
        _ => RGBColor(255, 127, 14),
    }
}

/// Registers the font once; a missing font is a typed error naming the fix.
pub fn load_font() -> BenchResult<()> {
    static LOADED: OnceLock<Result<(), String>> = OnceLock::new();
    let result = LOADED.get_or_init(|| {
        let path = std::env::var("UMBRA_FONT").unwrap_or_else(|_| DEFAULT_FONT.into());
        let bytes = std::fs::read(&path).map_err(|e| {
            format!("plots need a TrueType font: {path}: {e} (install fonts-dejavu-core or set UMBRA_FONT)")
        })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| format!("{path} is not a TrueType font"))
    });
    result.clone().map_err(BenchError::Usage)
}

fn plot_error(path: &Path) -> impl Fn(Box<dyn std::error::Error + '_>) -> BenchError + '_ {
    move |e| BenchError::output(path, e)
}

/// The configurations no other one beats on both GPU time and wrong pixels, fastest first.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(points[a].1.total_cmp(&points[b].1)));
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in order {
        if points[i].1 < best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

/// Where techniques that score exactly 0 wrong pixels sit on the log axis: a quarter of the
/// smallest non-zero score, within [1e-5 %, 1e-2 %] (1e-3 % when every score is 0).
pub fn zero_floor(percents: &[f64]) -> f64 {
    let smallest = percents.iter().copied().filter(|&p| p > 0.0).fold(f64::INFINITY, f64::min);
    if smallest.is_finite() {
        (smallest / 4.0).clamp(1e-5, 1e-2)
    } else {
        1e-3
    }
}

/// x: median GPU ms, y: wrong-pixel % on a log scale (scores of 0 drawn hollow on a floor
/// line), one labelled point per configuration, the Pareto front drawn.
pub fn accuracy_vs_time(records: &[&Record], scene: &str, path: &Path) -> BenchResult<()> {
    let timed: Vec<&&Record> = records.iter().filter(|r| r.gpu_ms.is_some()).collect();
    let points: Vec<(f64, f64)> =
        timed.iter().filter_map(|r| Some((r.gpu_ms?.median, 100.0 * r.accuracy.wrong_fraction))).collect();
    let floor = zero_floor(&points.iter().map(|p| p.1).collect::<Vec<_>>());
    let shown: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x, y.max(floor))).collect();
    let err = plot_error(path);
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(Box::new(e)))?;
    let x_max = points.iter().map(|p| p.0).fold(0.0, f64::max).max(1e-3) * 1.2;
    let y_max = shown.iter().map(|p| p.1).fold(floor, f64::max) * 3.0;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{scene}: accuracy vs GPU time"), ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..x_max, (floor / 2.0..y_max).log_scale())
        .map_err(|e| err(Box::new(e)))?;
    chart
        .configure_mesh()
        .x_desc("median GPU time per frame (ms)")
        .y_desc(format!("wrong pixels (%, log; 0 drawn at {floor:.0e})"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    let front: Vec<(f64, f64)> = pareto_front(&points).into_iter().map(|i| shown[i]).collect();
    chart
        .draw_series(LineSeries::new(front, ShapeStyle::from(&BLACK.mix(0.5)).stroke_width(2)))
        .map_err(|e| err(Box::new(e)))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.mix(0.5)));
    chart
        .draw_series(LineSeries::new([(0.0, floor), (x_max, floor)], BLACK.mix(0.2)))
        .map_err(|e| err(Box::new(e)))?
        .label("0 wrong pixels (hollow)")
        .legend(|(x, y)| Circle::new((x + 8, y), 4, BLACK.stroke_width(1)));
    let font: TextStyle = ("sans-serif", 12).into_font().into();
    let anchors: Vec<(i32, i32)> = shown.iter().map(|p| chart.backend_coord(p)).collect();
    let labels: Vec<String> = timed.iter().map(|r| r.config.label()).collect();
    let sizes: Vec<(u32, u32)> = labels
        .iter()
        .map(|l| root.estimate_text_size(l, &font).map_err(|e| err(Box::new(e))))
        .collect::<BenchResult<_>>()?;
    let placed = place_labels(&anchors, &sizes, root.dim_in_pixel());
    for (i, r) in timed.iter().enumerate() {
        let c = colour(r.config.technique);
        let marker = if r.accuracy.wrong_fraction > 0.0 { c.filled() } else { c.stroke_width(2) };
        chart.draw_series(std::iter::once(Circle::new(shown[i], 5, marker))).map_err(|e| err(Box::new(e)))?;
        let (anchor, at, (w, h)) = (anchors[i], placed[i], sizes[i]);
        // A label pushed away from its point gets a leader line to the label's nearest edge.
        let nearest = (anchor.0.clamp(at.0, at.0 + w as i32), anchor.1.clamp(at.1, at.1 + h as i32));
        if (nearest.0 - anchor.0).abs() + (nearest.1 - anchor.1).abs() > 16 {
            root.draw(&PathElement::new(vec![anchor, nearest], c.mix(0.5))).map_err(|e| err(Box::new(e)))?;
        }
        root.draw(&Text::new(labels[i].clone(), at, font.color(&c))).map_err(|e| err(Box::new(e)))?;
    }
    // The legend goes to the plot corner that covers the fewest labels and points.
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let obstacles: Vec<(i32, i32, i32, i32)> = placed
        .iter()
        .zip(&sizes)
        .map(|(&(x, y), &(w, h))| (x, y, x + w as i32, y + h as i32))
        .chain(anchors.iter().map(|&(x, y)| (x - 6, y - 6, x + 6, y + 6)))
        .collect();
    let corner = legend_corner((xs.start, ys.start, xs.end, ys.end), LEGEND_SIZE, &obstacles);
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::Coordinate(corner.0 - xs.start, corner.1 - ys.start))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    root.present().map_err(|e| err(Box::new(e)))?;
    Ok(())
}

/// The accuracy chart's legend box, in pixels (two entries).
const LEGEND_SIZE: (i32, i32) = (200, 56);

/// The top-left corner, among the four corners of `area` (x0, y0, x1, y1), where a box of
/// `size` overlaps `obstacles` least (upper right on a tie).
pub fn legend_corner(area: (i32, i32, i32, i32), size: (i32, i32), obstacles: &[(i32, i32, i32, i32)]) -> (i32, i32) {
    let pad = 10;
    let corners = [
        (area.2 - size.0 - pad, area.1 + pad),
        (area.0 + pad, area.1 + pad),
        (area.0 + pad, area.3 - size.1 - pad),
        (area.2 - size.0 - pad, area.3 - size.1 - pad),
    ];
    let cost = |&(x, y): &(i32, i32)| -> i64 {
        obstacles
            .iter()
            .map(|o| {
                let w = ((x + size.0).min(o.2) - x.max(o.0)).max(0);
                let h = ((y + size.1).min(o.3) - y.max(o.1)).max(0);
                i64::from(w) * i64::from(h)
            })
            .sum()
    };
    corners.iter().copied().min_by_key(cost).unwrap_or(corners[0])
}

/// Top-left corners for labels of `sizes` beside the points at `anchors` (pixels), none
/// overlapping another label or a point, inside `bounds`: candidates on rings of growing radius
/// around each point, greedily, left to right; a label with no free spot takes the spot that
/// overlaps least.
pub fn place_labels(anchors: &[(i32, i32)], sizes: &[(u32, u32)], bounds: (u32, u32)) -> Vec<(i32, i32)> {
    type Rect = (i32, i32, i32, i32);
    let overlap = |a: Rect, b: Rect| {
        let w = (a.2.min(b.2) - a.0.max(b.0)).max(0);
        let h = (a.3.min(b.3) - a.1.max(b.1)).max(0);
        i64::from(w) * i64::from(h)
    };
    let points: Vec<Rect> = anchors.iter().map(|&(x, y)| (x - 6, y - 6, x + 6, y + 6)).collect();
    let mut order: Vec<usize> = (0..anchors.len()).collect();
    order.sort_by_key(|&i| (anchors[i].0, anchors[i].1));
    let mut taken: Vec<Rect> = Vec::new();
    let mut out = vec![(0, 0); anchors.len()];
    for i in order {
        let (w, h) = (sizes[i].0 as i32, sizes[i].1 as i32);
        let (ax, ay) = anchors[i];
        let mut best: Option<(i64, (i32, i32))> = None;
        'rings: for ring in 0..8 {
            let r = 8 + 14 * ring;
            let candidates = [
                (r, -h / 2),
                (r, -h - r / 2),
                (r, r / 2),
                (-w - r, -h / 2),
                (-w / 2, -h - r),
                (-w / 2, r),
                (-w - r, -h - r / 2),
                (-w - r, r / 2),
            ];
            for (dx, dy) in candidates {
                let (x, y) = (ax + dx, ay + dy);
                let rect = (x, y, x + w, y + h);
                if x < 0 || y < 0 || rect.2 > bounds.0 as i32 || rect.3 > bounds.1 as i32 {
                    continue;
                }
                let cost: i64 = taken.iter().chain(&points).map(|&t| overlap(rect, t)).sum();
                if best.is_none_or(|(c, _)| cost < c) {
                    best = Some((cost, (x, y)));
                }
                if cost == 0 {
                    break 'rings;
                }
            }
        }
        let at = best.map_or((ax + 8, ay - h / 2), |(_, at)| at);
        taken.push((at.0, at.1, at.0 + w, at.1 + h));
        out[i] = at;
    }
    out
}

/// The group a pass belongs to in the breakdown.
pub fn pass_group(name: &str) -> &'static str {
    const GROUPS: [(&str, &str); 15] = [
        ("ambient", "depth + ambient"),
        ("shadow_map", "shadow map"),
        ("silhouette_map", "silhouette points"),
        ("blocker culling", "blocker culling"),
        ("hybrid classify", "eye pass (classify)"),
        ("computation mask", "computation mask"),
        ("hybrid volumes", "shadow volumes"),
        ("shadow_volume", "shadow volumes"),
        ("visibility readback", "diagnostics"),
        ("visibility", "visibility"),
        ("hybrid visibility", "visibility"),
        ("light", "lighting"),
        ("readback", "readback"),
        ("g-buffer", "diagnostics"),
        ("volume overdraw", "diagnostics"),
    ];
    GROUPS.iter().find(|(prefix, _)| name.starts_with(prefix)).map_or("other", |&(_, g)| g)
}

const GROUP_ORDER: [&str; 11] = [
    "depth + ambient",
    "shadow map",
    "silhouette points",
    "blocker culling",
    "eye pass (classify)",
    "computation mask",
    "shadow volumes",
    "visibility",
    "lighting",
    "readback",
    "other",
];

/// Stacked horizontal bars: per configuration, the median GPU time of each pass group.
pub fn pass_breakdown(records: &[&Record], scene: &str, path: &Path) -> BenchResult<()> {
    let rows: Vec<(String, Vec<f64>)> = records
        .iter()
        .map(|r| {
            let mut groups = vec![0.0; GROUP_ORDER.len()];
            for p in &r.passes {
                let g = pass_group(&p.name);
                if let Some(i) = GROUP_ORDER.iter().position(|&o| o == g) {
                    groups[i] += p.gpu_ms.median;
                }
            }
            (r.config.label(), groups)
        })
        .collect();
    let err = plot_error(path);
    let height = (120 + 28 * rows.len() as u32).max(300);
    let root = BitMapBackend::new(path, (SIZE.0, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(Box::new(e)))?;
    let x_max = rows.iter().map(|(_, g)| g.iter().sum::<f64>()).fold(0.0, f64::max).max(1e-3) * 1.1;
    let n = rows.len().max(1) as u32;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{scene}: GPU time per pass (median)"), ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(40)
        .y_label_area_size(170)
        .build_cartesian_2d(0.0..x_max, (0..n).into_segmented())
        .map_err(|e| err(Box::new(e)))?;
    let labels: Vec<String> = rows.iter().map(|(l, _)| l.clone()).collect();
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc("GPU ms")
        .y_labels(rows.len())
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => labels.get(*i as usize).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    for (g, group) in GROUP_ORDER.iter().enumerate() {
        let c = Palette99::pick(g);
        let bars: Vec<Rectangle<(f64, SegmentValue<u32>)>> = rows
            .iter()
            .enumerate()
            .filter(|(_, (_, groups))| groups[g] > 0.0)
            .map(|(i, (_, groups))| {
                let start: f64 = groups[..g].iter().sum();
                let i = i as u32;
                Rectangle::new(
                    [(start, SegmentValue::Exact(i)), (start + groups[g], SegmentValue::Exact(i + 1))],
                    c.filled(),
                )
            })
            .collect();
        if bars.is_empty() {
            continue;
        }
        chart
            .draw_series(bars)
            .map_err(|e| err(Box::new(e)))?
            .label(*group)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    root.present().map_err(|e| err(Box::new(e)))?;
    Ok(())
}

/// Chan–Durand Fig. 11: per shadow-map size, the shadow volumes' overdraw O (fragments per
/// pixel, %) and the hybrid's silhouette pixels P (%), log scale.
pub fn fill_chart(records: &[&Record], scene: &str, path: &Path) -> BenchResult<bool> {
    let overdraw = records.iter().find(|r| r.config.technique == "sv").and_then(|r| r.fill.volume_overdraw);
    let mut hybrid: Vec<(u32, f64, Option<f64>)> = records
        .iter()
        .filter(|r| r.config.technique == "hybrid")
        .filter_map(|r| {
            let p = 100.0 * r.fill.silhouette_fraction?;
            let masked = r.fill.masked_volume_fragments.map(|m| 100.0 * m as f64 / f64::from(r.width * r.height));
            Some((r.config.sm_size?, p, masked))
        })
        .collect();
    hybrid.sort_by_key(|h| h.0);
    hybrid.dedup_by_key(|h| h.0);
    if hybrid.is_empty() {
        return Ok(false);
    }
    let err = plot_error(path);
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(Box::new(e)))?;
    let values = hybrid.iter().flat_map(|h| [Some(h.1), h.2]).flatten().chain(overdraw.map(|o| 100.0 * o));
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v.max(1e-3)), hi.max(v)));
    let sizes: Vec<f64> = hybrid.iter().map(|h| f64::from(h.0)).collect();
    let (x_lo, x_hi) = (sizes[0] / 1.5, sizes[sizes.len() - 1] * 1.5);
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{scene}: fill vs shadow-map size (Chan–Durand Fig. 11)"), ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d((x_lo..x_hi).log_scale(), (lo / 2.0..hi * 2.0).log_scale())
        .map_err(|e| err(Box::new(e)))?;
    chart
        .configure_mesh()
        .x_desc("shadow-map size (texels per side)")
        .y_desc("% of image pixels")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    if let Some(o) = overdraw {
        let y = 100.0 * o;
        chart
            .draw_series(LineSeries::new([(x_lo, y), (x_hi, y)], colour("sv").stroke_width(2)))
            .map_err(|e| err(Box::new(e)))?
            .label("shadow volumes: overdraw O")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour("sv")));
    }
    let p: Vec<(f64, f64)> = hybrid.iter().map(|h| (f64::from(h.0), h.1.max(1e-3))).collect();
    let hc = colour("hybrid");
    chart
        .draw_series(LineSeries::new(p.clone(), hc.stroke_width(2)))
        .map_err(|e| err(Box::new(e)))?
        .label("hybrid: silhouette pixels P")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], hc));
    chart.draw_series(p.iter().map(|&q| Circle::new(q, 4, hc.filled()))).map_err(|e| err(Box::new(e)))?;
    let masked: Vec<(f64, f64)> = hybrid.iter().filter_map(|h| Some((f64::from(h.0), h.2?.max(1e-3)))).collect();
    if !masked.is_empty() {
        let mc = RGBColor(148, 103, 189);
        chart
            .draw_series(LineSeries::new(masked, mc.stroke_width(2)))
            .map_err(|e| err(Box::new(e)))?
            .label("hybrid: volume fragments through the mask")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], mc));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(Box::new(e)))?;
    root.present().map_err(|e| err(Box::new(e)))?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_the_undominated() {
        let points = [(1.0, 5.0), (2.0, 1.0), (1.5, 6.0), (3.0, 0.0), (2.5, 1.0)];
        assert_eq!(pareto_front(&points), vec![0, 1, 3]);
    }

    #[test]
    fn labels_never_overlap_when_there_is_room() {
        // Four points on one spot (the hybrid's four masks on cubes) and two close by.
        let anchors = [(300, 300), (300, 300), (301, 300), (300, 301), (320, 305), (340, 290)];
        let sizes = [(90, 12); 6];
        let placed = place_labels(&anchors, &sizes, (900, 600));
        let rects: Vec<_> =
            placed.iter().zip(&sizes).map(|(&(x, y), &(w, h))| (x, y, x + w as i32, y + h as i32)).collect();
        for (i, a) in rects.iter().enumerate() {
            for b in &rects[i + 1..] {
                let apart = a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1;
                assert!(apart, "{a:?} overlaps {b:?}");
            }
            assert!(a.0 >= 0 && a.1 >= 0 && a.2 <= 900 && a.3 <= 600);
        }
    }

    #[test]
    fn the_legend_avoids_the_labels() {
        let area = (0, 0, 800, 500);
        // Labels in the upper right: the legend goes to the upper left.
        assert_eq!(legend_corner(area, (200, 56), &[(600, 10, 780, 60)]), (10, 10));
        assert_eq!(legend_corner(area, (200, 56), &[]), (590, 10));
    }

    #[test]
    fn zero_scores_sit_below_the_smallest_non_zero_one() {
        assert_eq!(zero_floor(&[0.0, 0.025, 0.076, 1.6]), 0.025 / 4.0);
        assert_eq!(zero_floor(&[0.0, 0.0]), 1e-3);
        assert_eq!(zero_floor(&[1e-9, 0.5]), 1e-5);
    }

    #[test]
    fn pass_groups() {
        assert_eq!(pass_group("hybrid volumes 0"), "shadow volumes");
        assert_eq!(pass_group("shadow_volume 1"), "shadow volumes");
        assert_eq!(pass_group("light 0 (point)"), "lighting");
        assert_eq!(pass_group("hybrid visibility 0"), "visibility");
        assert_eq!(pass_group("visibility 1 (stencil)"), "visibility");
        assert_eq!(pass_group("visibility readback 1"), "diagnostics");
        assert_eq!(pass_group("shadow_map 0"), "shadow map");
    }
}
