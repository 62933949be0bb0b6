//! Shared test harness: a validated context on the device `UMBRA_DEVICE` names, and the
//! check that the validation layer stayed silent.
#![allow(dead_code)]

pub mod clip;
pub mod exact;
pub mod raycast;

use std::path::PathBuf;
use umbra::vk::{Context, ContextOptions};

/// Runs `body` with a fresh context (validation layer always on), drops everything, then fails
/// if the layer reported any warning or error — including leaks reported at device
/// destruction.
pub fn with_context<R>(body: impl FnOnce(&Context) -> R) -> R {
    let _ = env_logger::builder().is_test(true).filter_level(log::LevelFilter::Warn).try_init();
    let options = ContextOptions { validation: true, ..ContextOptions::from_env() };
    let ctx = {
        let _one_at_a_time = lifecycle();
        Context::with_options(&options).expect("Vulkan context (run ci/setup.sh)")
    };
    let counter = ctx.validation();
    let out = body(&ctx);
    {
        let _one_at_a_time = lifecycle();
        drop(ctx);
    }
    assert_eq!(
        (counter.errors(), counter.warnings()),
        (0, 0),
        "validation layer reported (errors, warnings); messages are in the log above"
    );
    out
}

/// Held while a test creates or destroys its context: instances and devices are made and
/// torn down one at a time in a test process, while the tests' frames still run in parallel.
/// (A CI run once lost the first two tests of a file, which create their contexts at the same
/// moment, to a hang on lavapipe that never reproduced; the driver and the layers are not
/// exercised concurrently there any more.)
fn lifecycle() -> std::sync::MutexGuard<'static, ()> {
    static LIFECYCLE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LIFECYCLE.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The repository's `assets/` folder, or `UMBRA_ASSETS`.
pub fn assets() -> PathBuf {
    let dir = std::env::var_os("UMBRA_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets"));
    assert!(dir.is_dir(), "assets folder {} missing (set UMBRA_ASSETS)", dir.display());
    dir
}

/// `target/<profile>/examples/<name>`, beside this test binary, built now by the cargo that
/// runs the tests (`cargo test --test window` alone would not rebuild the examples).
pub fn example(name: &str) -> PathBuf {
    static BUILT: std::sync::Once = std::sync::Once::new();
    BUILT.call_once(|| {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let release = std::env::current_exe().is_ok_and(|e| e.components().any(|c| c.as_os_str() == "release"));
        let status = std::process::Command::new(cargo)
            // --workspace: the same feature set as `cargo test --workspace`, so nothing rebuilds.
            .args(["build", "--workspace", "--examples", "--manifest-path"])
            .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"))
            .args(release.then_some("--release"))
            .status()
            .expect("run cargo build --examples");
        assert!(status.success(), "cargo build --examples failed");
    });
    let exe = std::env::current_exe().expect("test binary path");
    let dir = exe.parent().and_then(std::path::Path::parent).expect("target/<profile>");
    let path = dir.join("examples").join(name);
    assert!(path.is_file(), "{} missing: cargo test builds the examples", path.display());
    path
}

/// Where tests write their images for people to look at.
pub fn output_dir(test: &str) -> PathBuf {
    let device = std::env::var("UMBRA_DEVICE").unwrap_or_else(|_| "default".into());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("umbra-tests").join(device).join(test);
    std::fs::create_dir_all(&dir).expect("create test output folder");
    dir
}

/// A `w` × `h` depth/stencil attachment in the device's preferred format (plus `extra` usage).
pub fn depth_target(
    ctx: &Context,
    name: &str,
    w: u32,
    h: u32,
    extra: umbra::vk::vk::ImageUsageFlags,
) -> umbra::vk::Image {
    use umbra::vk::{vk, Image, ImageDesc};
    let format = ctx.capabilities().depth_stencil_format;
    Image::new(ctx, name, ImageDesc::new_2d(format, w, h).usage(vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | extra))
        .expect("depth/stencil target")
}

/// Starts rendering into `depth` alone, cleared to depth 1 and stencil 0.
pub fn begin_depth_pass<'a>(rec: &mut umbra::vk::Recorder<'a>, depth: &'a umbra::vk::Image) {
    use umbra::vk::{DepthAttachment, ImageState, RenderTargets};
    rec.transition(&[(depth, ImageState::Undefined, ImageState::DepthStencilAttachment)]);
    rec.begin_rendering(&RenderTargets { color: &[], depth: Some(DepthAttachment::cleared(depth, 1.0, 0)) });
}

/// A full-screen draw that counts, with an occlusion query, the pixels whose stencil value
/// passes `compare` against reference 0 (stencil left unchanged).
pub struct StencilProbe {
    pipeline: umbra::vk::GraphicsPipeline,
    queries: umbra::vk::QueryPool,
}

impl StencilProbe {
    /// A probe for a depth/stencil target of the device's preferred format.
    pub fn new(ctx: &Context, layout: &umbra::vk::PipelineLayout, compare: umbra::vk::vk::CompareOp) -> Self {
        use umbra::vk::{vk, DepthState, GraphicsPipeline, GraphicsPipelineDesc, QueryKind, QueryPool, StencilFace};
        let mut desc = GraphicsPipelineDesc::new("stencil probe", umbra::shaders::fullscreen::TRIANGLE_VERT);
        desc.cull = vk::CullModeFlags::NONE;
        desc.depth = DepthState::NONE;
        desc.depth_format = ctx.capabilities().depth_stencil_format;
        let face = StencilFace { compare, write_mask: 0, ..StencilFace::KEEP };
        desc.stencil = Some((face, face));
        Self {
            pipeline: GraphicsPipeline::new(ctx, layout, &desc).expect("probe pipeline"),
            queries: QueryPool::new(ctx, "stencil probe", QueryKind::Occlusion, 1).expect("probe query"),
        }
    }

    /// Resets the query; record before the rendering pass.
    pub fn reset<'a>(&'a self, rec: &mut umbra::vk::Recorder<'a>) {
        rec.reset_queries(&self.queries);
    }

    /// Draws the probe (inside the rendering pass, after the stencil was written).
    pub fn record<'a>(&'a self, rec: &mut umbra::vk::Recorder<'a>) {
        rec.bind_pipeline(&self.pipeline);
        rec.set_stencil_reference(0);
        rec.begin_query(&self.queries, 0);
        rec.draw(3);
        rec.end_query(&self.queries, 0);
    }

    /// Pixels that passed, once the submission completed.
    pub fn pixels(&self) -> u64 {
        self.queries.results().expect("probe result")[0]
    }
}

/// Test image size (small: CPU drivers).
pub const SIZE: (u32, u32) = (256, 192);
