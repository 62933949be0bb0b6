//! Shared test harness: a validated context on the device `UMBRA_DEVICE` names, and the
//! check that the validation layer stayed silent.
#![allow(dead_code)]

pub mod bvh;
pub mod raycast;

use std::path::PathBuf;
use umbra::vk::{Context, ContextOptions};

/// Runs `body` with a fresh context (validation layer always on), drops everything, then fails
/// if the layer reported any warning or error — including leaks reported at device
/// destruction.
pub fn with_context<R>(body: impl FnOnce(&Context) -> R) -> R {
    let _ = env_logger::builder().is_test(true).filter_level(log::LevelFilter::Warn).try_init();
    let options = ContextOptions { validation: true, ..ContextOptions::from_env() };
    let ctx = Context::with_options(&options).expect("Vulkan context (run ci/setup.sh)");
    let counter = ctx.validation();
    let out = body(&ctx);
    drop(ctx);
    assert_eq!(
        (counter.errors(), counter.warnings()),
        (0, 0),
        "validation layer reported (errors, warnings); messages are in the log above"
    );
    out
}

/// `../shared/assets` beside the checkout, or `UMBRA_ASSETS`.
pub fn assets() -> PathBuf {
    let dir = std::env::var_os("UMBRA_ASSETS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/assets"));
    assert!(dir.is_dir(), "assets folder {} missing (set UMBRA_ASSETS)", dir.display());
    dir
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
    rec.begin_rendering(&RenderTargets {
        color: &[],
        depth: Some(DepthAttachment {
            image: depth,
            view: None,
            clear: Some((1.0, 0)),
            clear_stencil: None,
            read_only: false,
        }),
    });
}

/// Test image size (small: CPU drivers).
pub const SIZE: (u32, u32) = (256, 192);
