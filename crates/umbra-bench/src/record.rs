//! What one run measured, as written to `results.json` and `results.csv`.

use serde::{Deserialize, Serialize};
use umbra_reference::WrongPixels;

/// Median and spread of a series of samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// The median.
    pub median: f64,
    /// The smallest sample.
    pub min: f64,
    /// The largest sample.
    pub max: f64,
    /// First quartile.
    pub p25: f64,
    /// Third quartile.
    pub p75: f64,
    /// Number of samples.
    pub samples: usize,
}

impl Spread {
    /// The spread of `samples`, `None` when empty.
    pub fn of(samples: &[f64]) -> Option<Self> {
        if samples.is_empty() {
            return None;
        }
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        // Linear interpolation between closest ranks.
        let q = |p: f64| {
            let x = p * (s.len() - 1) as f64;
            let (lo, hi) = (x.floor() as usize, x.ceil() as usize);
            s[lo] + (s[hi] - s[lo]) * (x - lo as f64)
        };
        Some(Self { median: q(0.5), min: s[0], max: s[s.len() - 1], p25: q(0.25), p75: q(0.75), samples: s.len() })
    }
}

/// One technique configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Config {
    /// Scene name as given to `--scenes`.
    pub scene: String,
    /// Short technique name: `sm`, `silmap`, `sv`, `hybrid`, `rt` or `hybrid-rt`.
    pub technique: &'static str,
    /// Shadow-map size (sm, silmap, hybrid).
    pub sm_size: Option<u32>,
    /// Shadow-map filter (sm).
    pub filter: Option<&'static str>,
    /// Computation mask (hybrid).
    pub mask: Option<&'static str>,
    /// The meshes' BVH layout when not binary (rt, hybrid-rt): `cwbvh`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bvh: Option<&'static str>,
}

impl Config {
    /// A short label: `hybrid 512 stencil`, `sm 1024 pcf2x2`, `sv`.
    pub fn label(&self) -> String {
        let mut parts = vec![self.technique.to_owned()];
        parts.extend(self.sm_size.map(|s| s.to_string()));
        parts.extend(self.filter.map(str::to_owned));
        parts.extend(self.mask.map(str::to_owned));
        parts.extend(self.bvh.map(str::to_owned));
        parts.join(" ")
    }

    /// A file-name-safe identifier: `cubes-hybrid-512-stencil`.
    pub fn id(&self) -> String {
        let scene: String = self
            .scene
            .rsplit('/')
            .next()
            .unwrap_or(&self.scene)
            .chars()
            .filter(|c| c.is_ascii_alphanumeric())
            .collect();
        format!("{scene}-{}", self.label().replace(' ', "-"))
    }
}

/// One pass's GPU time over the timed frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassTime {
    /// Pass name as in the frame report (`shadow_map 0`, `hybrid volumes 0`, …).
    pub name: String,
    /// Its GPU milliseconds.
    pub gpu_ms: Spread,
}

/// Fill counts of the last frame (Chan–Durand's O and P, Sen's Table 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Fill {
    /// Shadow-volume fragments (all lights) per image pixel, O.
    pub volume_overdraw: Option<f64>,
    /// Shadow-volume fragments.
    pub volume_fragments: Option<u64>,
    /// Volume fragments that passed the hybrid's computation mask.
    pub masked_volume_fragments: Option<u64>,
    /// Silhouette pixels per image pixel, P (hybrid, silhouette maps).
    pub silhouette_fraction: Option<f64>,
}

/// Shadow rays of the last frame (ray-traced and ray-traced hybrid lights, with the
/// renderer's diagnostics), over the scene's lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rays {
    /// Shadow rays cast.
    pub rays: u64,
    /// Rays per image pixel.
    pub ray_fraction: f64,
    /// BVH nodes a ray tested, mean over every ray.
    pub nodes_mean: f64,
    /// The largest light's 95th percentile of nodes per ray.
    pub nodes_p95: u64,
    /// Triangles a ray tested, mean over every ray.
    pub triangles_mean: f64,
    /// The largest light's 95th percentile of triangles per ray.
    pub triangles_p95: u64,
    /// Bytes of the BVH on the GPU (both levels and the triangles).
    pub bvh_bytes: u64,
    /// Host milliseconds building the meshes' BVHs, in the first frame.
    pub mesh_build_ms: f64,
    /// Host milliseconds building the top level, in the first frame.
    pub top_build_ms: f64,
}

/// Accuracy against the exact reference, summed over the scene's lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Every compared pixel.
    pub all: WrongPixels,
    /// Pixels within `edge_band_px` of a true shadow edge.
    pub edge_band: WrongPixels,
    /// Half-width of the band.
    pub edge_band_px: f32,
    /// Wrong pixels / compared pixels.
    pub wrong_fraction: f64,
    /// False shadow / compared.
    pub false_shadow_fraction: f64,
    /// False light / compared.
    pub false_lit_fraction: f64,
    /// Wrong / compared inside the edge band.
    pub edge_band_wrong_fraction: f64,
    /// The farthest wrong pixel's distance from a true edge, in pixels.
    pub max_wrong_distance_px: Option<f32>,
    /// Pixels only one side called in question.
    pub undecided: u64,
}

/// One run: a configuration measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// What ran.
    #[serde(flatten)]
    pub config: Config,
    /// Device name.
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Triangles in the scene.
    pub triangles: usize,
    /// Timed frames (after the warm-up).
    pub frames: usize,
    /// The frame's total GPU time (technique passes only), `None` without timestamps.
    pub gpu_ms: Option<Spread>,
    /// Every technique pass.
    pub passes: Vec<PassTime>,
    /// CPU milliseconds per frame building silhouettes (silhouette-map edge extraction,
    /// shadow-volume construction).
    pub cpu_silhouette_ms: Option<Spread>,
    /// Fill counts.
    pub fill: Fill,
    /// Shadow rays (ray-casting techniques).
    pub rays: Option<Rays>,
    /// Against the reference.
    pub accuracy: Accuracy,
    /// The error image, relative to the output folder.
    pub error_image: String,
    /// Passes the planned frame recorded (diagnostic ones included).
    pub recorded_passes: usize,
    /// The same configuration without planning (`--no-cull`).
    pub no_cull: Option<NoCull>,
    /// Texels per side of the first shadowed light's map in the last frame: the size the
    /// renderer picked where the configuration names none (`None`: no map).
    #[serde(default)]
    pub map_resolution: Option<u32>,
}

/// A configuration measured again with `RendererDesc::cull` off.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NoCull {
    /// The frame's total GPU time without planning.
    pub gpu_ms: Option<Spread>,
    /// Passes recorded without planning.
    pub recorded_passes: usize,
    /// Whether its last image equals the planned one byte for byte.
    pub identical: bool,
}

/// A configuration the device cannot run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    /// What was asked.
    #[serde(flatten)]
    pub config: Config,
    /// Why it did not run.
    pub reason: String,
}

/// Everything a sweep wrote to `results.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Results {
    /// Device name.
    pub device: String,
    /// Driver name and version.
    pub driver: String,
    /// The device's capabilities that decide what runs.
    pub depth_bounds: bool,
    /// Timestamps per pass are available.
    pub timestamps: bool,
    /// Warm-up frames per run.
    pub warmup: usize,
    /// Measured runs.
    pub records: Vec<Record>,
    /// Skipped configurations.
    pub skipped: Vec<Skipped>,
}

/// The CSV header, one column per flat field of a [`Record`].
pub const CSV_HEADER: [&str; 30] = [
    "scene",
    "technique",
    "sm_size",
    "filter",
    "mask",
    "device",
    "width",
    "height",
    "frames",
    "gpu_ms_median",
    "gpu_ms_p25",
    "gpu_ms_p75",
    "cpu_silhouette_ms_median",
    "volume_overdraw",
    "masked_volume_fragments",
    "silhouette_fraction",
    "rays",
    "nodes_per_ray_mean",
    "nodes_per_ray_p95",
    "triangles_per_ray_mean",
    "triangles_per_ray_p95",
    "compared_pixels",
    "wrong_fraction",
    "false_shadow_fraction",
    "false_lit_fraction",
    "edge_band_wrong_fraction",
    "max_wrong_distance_px",
    "recorded_passes",
    "no_cull_gpu_ms_median",
    "no_cull_identical",
];

impl Record {
    /// The CSV row under [`CSV_HEADER`].
    pub fn csv_row(&self) -> Vec<String> {
        fn opt<T: ToString>(v: Option<T>) -> String {
            v.map(|v| v.to_string()).unwrap_or_default()
        }
        let c = &self.config;
        let a = &self.accuracy;
        vec![
            c.scene.clone(),
            c.technique.to_owned(),
            opt(c.sm_size),
            opt(c.filter),
            opt(c.mask),
            self.device.clone(),
            self.width.to_string(),
            self.height.to_string(),
            self.frames.to_string(),
            opt(self.gpu_ms.map(|s| s.median)),
            opt(self.gpu_ms.map(|s| s.p25)),
            opt(self.gpu_ms.map(|s| s.p75)),
            opt(self.cpu_silhouette_ms.map(|s| s.median)),
            opt(self.fill.volume_overdraw),
            opt(self.fill.masked_volume_fragments),
            opt(self.fill.silhouette_fraction),
            opt(self.rays.map(|r| r.rays)),
            opt(self.rays.map(|r| r.nodes_mean)),
            opt(self.rays.map(|r| r.nodes_p95)),
            opt(self.rays.map(|r| r.triangles_mean)),
            opt(self.rays.map(|r| r.triangles_p95)),
            a.all.compared.to_string(),
            a.wrong_fraction.to_string(),
            a.false_shadow_fraction.to_string(),
            a.false_lit_fraction.to_string(),
            a.edge_band_wrong_fraction.to_string(),
            opt(a.max_wrong_distance_px),
            self.recorded_passes.to_string(),
            opt(self.no_cull.as_ref().and_then(|n| n.gpu_ms).map(|s| s.median)),
            opt(self.no_cull.as_ref().map(|n| n.identical)),
        ]
    }
}

/// `results.json`'s configurations read back with the static names the sweep writes; an
/// unknown name is an error naming it.
mod names {
    use super::{Config, Deserialize};
    use serde::Deserializer;
    use umbra_shadows::ray_traced::BvhLayout;
    use umbra_shadows::{MaskKind, ShadowFilter};

    /// A [`Config`] as text.
    #[derive(Deserialize)]
    struct ConfigText {
        scene: String,
        technique: String,
        sm_size: Option<u32>,
        filter: Option<String>,
        mask: Option<String>,
        #[serde(default)]
        bvh: Option<String>,
    }

    fn known(
        name: Option<String>,
        what: &str,
        find: impl Fn(&str) -> Option<&'static str>,
    ) -> Result<Option<&'static str>, String> {
        name.map(|s| find(&s).ok_or_else(|| format!("unknown {what} `{s}`"))).transpose()
    }

    // By hand: a derived impl would ask the input to outlive 'static for the `&'static str`s.
    impl<'de> Deserialize<'de> for Config {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            Self::try_from(ConfigText::deserialize(d)?).map_err(serde::de::Error::custom)
        }
    }

    impl TryFrom<ConfigText> for Config {
        type Error = String;

        fn try_from(t: ConfigText) -> Result<Self, String> {
            let technique = known(Some(t.technique), "technique", |s| crate::sweep::technique(s).map(|t| t.short()))?;
            Ok(Self {
                scene: t.scene,
                technique: technique.unwrap_or_default(),
                sm_size: t.sm_size,
                filter: known(t.filter, "filter", |s| s.parse::<ShadowFilter>().ok().map(ShadowFilter::name))?,
                mask: known(t.mask, "mask", |s| s.parse::<MaskKind>().ok().map(MaskKind::name))?,
                bvh: known(t.bvh, "BVH layout", |s| s.parse::<BvhLayout>().ok().map(BvhLayout::name))?,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_of_known_samples() {
        let s = Spread::of(&[4.0, 1.0, 3.0, 2.0, 5.0]).expect("samples");
        assert_eq!((s.median, s.min, s.max, s.p25, s.p75, s.samples), (3.0, 1.0, 5.0, 2.0, 4.0, 5));
        let even = Spread::of(&[1.0, 2.0]).expect("samples");
        assert_eq!(even.median, 1.5);
        assert!(Spread::of(&[]).is_none());
    }

    #[test]
    fn config_names() {
        let c = Config {
            scene: "../assets/spot.glb".into(),
            technique: "hybrid",
            sm_size: Some(512),
            filter: None,
            mask: Some("stencil"),
            bvh: None,
        };
        assert_eq!(c.label(), "hybrid 512 stencil");
        assert_eq!(c.id(), "spotglb-hybrid-512-stencil");
    }

    #[test]
    fn configs_read_back_as_written_and_unknown_names_are_named() {
        for c in [
            Config {
                scene: "cubes".into(),
                technique: "sm",
                sm_size: Some(64),
                filter: Some("pcf2x2"),
                mask: None,
                bvh: None,
            },
            Config {
                scene: "tree".into(),
                technique: "hybrid",
                sm_size: Some(512),
                filter: None,
                mask: Some("depth-bounds"),
                bvh: None,
            },
            Config {
                scene: "cage".into(),
                technique: "rt",
                sm_size: None,
                filter: None,
                mask: None,
                bvh: Some("cwbvh"),
            },
        ] {
            let json = serde_json::to_string(&c).expect("written");
            assert_eq!(serde_json::from_str::<Config>(&json).expect("read"), c, "{json}");
        }
        let bad = r#"{"scene":"cubes","technique":"raymarch","sm_size":null,"filter":null,"mask":null}"#;
        let e = serde_json::from_str::<Config>(bad).expect_err("refused").to_string();
        assert!(e.contains("unknown technique `raymarch`"), "{e}");
        let bad = r#"{"scene":"cubes","technique":"sm","sm_size":64,"filter":"pcf9x9","mask":null}"#;
        let e = serde_json::from_str::<Config>(bad).expect_err("refused").to_string();
        assert!(e.contains("unknown filter `pcf9x9`"), "{e}");
    }
}
