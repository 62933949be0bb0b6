//! Capabilities are probed, not assumed: each CI driver reports what docs/architecture.md's
//! driver table says of it, and features a device lacks give typed errors instead of broken
//! pipelines.

mod common;

use umbra::vk::selection::fits;
use umbra::vk::{vk, DepthState, GraphicsPipeline, GraphicsPipelineDesc, PipelineLayout, VkError};

/// The driver table of docs/architecture.md: its column headings and its rows, cell by cell.
fn driver_table() -> (Vec<String>, Vec<Vec<String>>) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/architecture.md");
    let text = std::fs::read_to_string(path).expect("docs/architecture.md");
    let section = text.split("## Drivers").nth(1).expect("a Drivers section");
    let cells =
        |line: &str| line.trim().trim_matches('|').split(" | ").map(|c| c.trim().to_owned()).collect::<Vec<_>>();
    let mut lines = section.lines().skip_while(|l| !l.starts_with('|')).take_while(|l| l.starts_with('|'));
    let header = cells(lines.next().expect("a table"));
    let rows = lines.skip(1).map(cells).collect();
    (header, rows)
}

/// The `UMBRA_DEVICE` name a column heading gives in backquotes: `` lavapipe (`llvmpipe-mesa-25`) ``.
fn column_device(heading: &str) -> Option<&str> {
    heading.rsplit_once("(`").and_then(|(_, rest)| rest.split_once("`)")).map(|(name, _)| name)
}

#[test]
fn the_driver_table_in_the_architecture_doc_is_what_this_driver_reports() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        println!("{}", serde_json::to_string_pretty(caps).unwrap());
        let (header, rows) = driver_table();
        let columns: Vec<usize> = (1..header.len())
            .filter(|&i| column_device(&header[i]).is_some_and(|d| fits(d, &caps.device_name, &caps.driver())))
            .collect();
        let [column] = columns[..] else {
            panic!(
                "{} ({}) is not one column of docs/architecture.md's driver table: {header:?}",
                caps.device_name,
                caps.driver()
            );
        };
        println!("this driver's column: {}", header[column]);
        let yes = |row: &str| -> bool {
            let cells = rows.iter().find(|r| r[0].starts_with(row)).unwrap_or_else(|| panic!("no row {row:?}"));
            let cell = &cells[column];
            assert!(cell.starts_with("yes") || cell.starts_with("no"), "row {row:?}: {cell:?} is neither yes nor no");
            cell.starts_with("yes")
        };
        let vulkan = rows.iter().find(|r| r[0] == "Vulkan").expect("a Vulkan row");
        assert_eq!(vulkan[column], caps.api_version, "Vulkan version");
        assert_eq!(yes("depthBounds"), caps.depth_bounds, "depthBounds");
        assert_eq!(yes("depthClamp"), caps.depth_clamp, "depthClamp");
        let gs = yes("geometry shaders, wide lines, pipeline statistics");
        assert_eq!([gs; 3], [caps.geometry_shader, caps.wide_lines, caps.pipeline_statistics], "geometry shaders etc.");
        assert_eq!(yes("timestamps"), caps.timestamps, "timestamps");
        assert_eq!(yes("D32_SFLOAT_S8_UINT"), caps.depth_stencil_format == vk::Format::D32_SFLOAT_S8_UINT);
        assert_eq!(yes("watertight frustum clipping"), caps.watertight_clipping, "watertight clipping");
        assert_eq!(yes("ray queries"), caps.ray_query, "ray queries");
        // Not in the table, and the same on every CI driver.
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

/// Options that pick `device` by name, validation off.
fn picking(device: &str) -> umbra::vk::ContextOptions {
    umbra::vk::ContextOptions {
        validation: false,
        synchronization_validation: false,
        device: Some(device.into()),
        surface_extensions: Vec::new(),
    }
}

#[test]
fn an_unknown_device_gives_an_error_listing_the_devices() {
    let options = picking("no-such-gpu-xyz");
    let err = umbra::vk::Context::with_options(&options).unwrap_err();
    let text = err.to_string();
    println!("{text}");
    assert!(matches!(err, VkError::NoDevice { .. }));
    assert!(text.contains("no-such-gpu-xyz"), "{text}");
    assert!(text.to_lowercase().contains("llvmpipe") || text.to_lowercase().contains("swiftshader"), "{text}");
}

#[test]
fn a_device_name_both_lavapipes_share_is_an_error_naming_both_drivers() {
    let options = picking("llvmpipe");
    let icds = std::env::var("VK_ICD_FILENAMES").unwrap_or_default();
    let lavapipes = icds.split(':').filter(|f| f.ends_with("lvp_icd.json") || f.contains("/lvp_icd.")).count();
    match umbra::vk::Context::with_options(&options) {
        Err(err @ VkError::AmbiguousDevice { .. }) => {
            let text = err.to_string();
            println!("{text}");
            assert!(text.contains("Mesa 22.3.6") && text.contains("Mesa 25."), "{text}");
            assert!(text.contains("llvmpipe-mesa-25"), "the error shows how to name one: {text}");
        }
        Ok(ctx) => {
            assert!(lavapipes < 2, "{lavapipes} lavapipe ICDs in VK_ICD_FILENAMES, yet `llvmpipe` picked one");
            println!("one lavapipe installed: {}", ctx.capabilities().driver());
        }
        Err(other) => panic!("{other}"),
    }
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
