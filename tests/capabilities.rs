//! Capabilities are probed, not assumed: depth bounds on the two CPU drivers, and features a
//! device lacks give typed errors instead of broken pipelines.

mod common;

use umbra::vk::{vk, DepthState, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout, VkError};

/// Which CPU driver this run uses, from the device name.
fn driver(name: &str) -> Option<&'static str> {
    let name = name.to_lowercase();
    if name.contains("llvmpipe") {
        Some("llvmpipe")
    } else if name.contains("swiftshader") {
        Some("swiftshader")
    } else {
        None
    }
}

#[test]
fn depth_bounds_is_false_on_lavapipe_and_true_on_swiftshader() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        println!("{}", serde_json::to_string_pretty(caps).unwrap());
        match driver(&caps.device_name) {
            Some("llvmpipe") => {
                assert!(!caps.depth_bounds, "lavapipe has no depthBounds (DESIGN.md, measured)");
                assert!(caps.geometry_shader && caps.pipeline_statistics && caps.wide_lines);
            }
            Some("swiftshader") => {
                assert!(caps.depth_bounds, "SwiftShader has depthBounds");
                assert!(!caps.geometry_shader && !caps.pipeline_statistics && !caps.wide_lines);
            }
            _ => panic!("this suite runs on llvmpipe or swiftshader; got {} (set UMBRA_DEVICE)", caps.device_name),
        }
        assert!(caps.depth_clamp && caps.timestamps);
        assert_eq!(caps.depth_stencil_format, vk::Format::D32_SFLOAT_S8_UINT);
        assert!(!caps.conservative_rasterization);
    });
}

#[test]
fn a_depth_bounds_pipeline_is_built_only_where_the_feature_exists() {
    common::with_context(|ctx| {
        let layout = PipelineLayout::new(ctx, "empty layout", &[], 0).unwrap();
        let mut desc = GraphicsPipelineDesc::new("depth bounds probe", umbra::shaders::fullscreen::TRIANGLE_VERT);
        desc.depth = DepthState { bounds_test: true, ..DepthState::TEST_AND_WRITE };
        desc.depth_format = ctx.capabilities().depth_stencil_format;
        match (ctx.capabilities().depth_bounds, GraphicsPipeline::new(ctx, &layout, &desc)) {
            (false, Err(VkError::Unsupported { what, .. })) => {
                println!("typed error as expected: {what}");
                assert!(what.contains("depthBounds"));
            }
            (true, Ok(_)) => println!("depth-bounds pipeline built"),
            (has, r) => panic!("depthBounds={has} but pipeline creation gave {:?}", r.map(|_| ())),
        }
    });
}

#[test]
fn an_unknown_device_gives_an_error_listing_the_devices() {
    let options = umbra::vk::ContextOptions {
        validation: false,
        synchronization_validation: false,
        device: Some("no-such-gpu-xyz".into()),
        surface_extensions: Vec::new(),
    };
    let err = umbra::vk::Context::with_options(&options).unwrap_err();
    let text = err.to_string();
    println!("{text}");
    assert!(matches!(err, VkError::NoDevice { .. }));
    assert!(text.contains("no-such-gpu-xyz"), "{text}");
    assert!(text.to_lowercase().contains("llvmpipe") || text.to_lowercase().contains("swiftshader"), "{text}");
}

#[test]
fn oversized_and_empty_images_are_typed_errors() {
    common::with_context(|ctx| {
        let max = ctx.capabilities().max_image_dimension_2d;
        let too_big =
            umbra::vk::ImageDesc::new_2d(vk::Format::R8G8B8A8_UNORM, max + 1, 4).usage(vk::ImageUsageFlags::SAMPLED);
        let err = umbra::vk::Image::new(ctx, "too big", too_big).unwrap_err();
        // Over a device limit: the error names it (maxImageDimension2D on both CPU drivers).
        assert!(
            matches!(&err, VkError::DeviceLimit { limit, what, .. }
                if limit.name == "maxImageDimension2D" && what.contains("too big")),
            "{err}"
        );
        let empty = umbra::vk::ImageDesc::new_2d(vk::Format::R8G8B8A8_UNORM, 0, 4).usage(vk::ImageUsageFlags::SAMPLED);
        assert!(matches!(umbra::vk::Image::new(ctx, "empty", empty), Err(VkError::InvalidDesc { .. })));
        let r = umbra::shadows::Renderer::new(ctx, umbra::shadows::RendererDesc::new(0, 10));
        assert!(matches!(r, Err(umbra::shadows::RenderError::InvalidSize { .. })));
    });
}
