//! umbra-vk on its own: rendering, occlusion queries and the depth-bounds test.

mod common;

use umbra::vk::{
    vk, Buffer, BufferDesc, DepthState, GraphicsPipeline, GraphicsPipelineDesc, ImageState, PipelineLayout, QueryKind,
    QueryPool,
};

const W: u32 = 64;
const H: u32 = 48;

/// A depth-only pipeline drawing the full-screen triangle at `depth`.
fn fullscreen<'a>(name: &'a str, spec: &'a [(u32, u32)], format: vk::Format) -> GraphicsPipelineDesc<'a> {
    let mut desc = GraphicsPipelineDesc::new(name, umbra::shaders::fullscreen::TRIANGLE_VERT);
    desc.specialization = spec;
    desc.cull = vk::CullModeFlags::NONE;
    desc.depth_format = format;
    desc
}

#[test]
fn occlusion_queries_count_every_covered_sample_and_depth_is_read_back() {
    common::with_context(|ctx| {
        let format = ctx.capabilities().depth_stencil_format;
        let depth = common::depth_target(ctx, "depth", W, H, vk::ImageUsageFlags::TRANSFER_SRC);
        let layout = PipelineLayout::new(ctx, "empty", &[], 0).unwrap();
        let spec = [(0, 0.25f32.to_bits())];
        let pipeline = GraphicsPipeline::new(ctx, &layout, &fullscreen("write 0.25", &spec, format)).unwrap();
        let queries = QueryPool::new(ctx, "occlusion", QueryKind::Occlusion, 2).unwrap();
        let mut readback = Buffer::new(ctx, "depth readback", BufferDesc::readback(4 * (W * H) as u64)).unwrap();
        readback.write(0, &vec![0xCD; 4 * (W * H) as usize]).unwrap();

        let mut rec = ctx.begin_commands("occlusion test").unwrap();
        rec.reset_queries(&queries);
        common::begin_depth_pass(&mut rec, &depth);
        rec.bind_pipeline(&pipeline);
        rec.begin_query(&queries, 0);
        rec.draw(3); // depth 0.25 < 1.0: every sample passes
        rec.end_query(&queries, 0);
        rec.begin_query(&queries, 1);
        rec.draw(3); // 0.25 < 0.25 fails: LESS_OR_EQUAL passes again
        rec.end_query(&queries, 1);
        rec.end_rendering();
        rec.transition(&[(&depth, ImageState::DepthStencilAttachment, ImageState::TransferSrc)]);
        rec.copy_image_to_buffer(&depth, 0, &readback);
        ctx.submit_and_wait(rec).unwrap();

        let counts = queries.results().unwrap();
        assert_eq!(counts, vec![(W * H) as u64; 2], "occlusion counts");
        let bytes = readback.read().unwrap();
        let depths: Vec<f32> = bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        assert!(depths.iter().all(|&d| d == 0.25), "depth readback {:?}", &depths[..4]);
    });
}

#[test]
fn depth_bounds_masks_by_the_stored_depth_where_supported() {
    common::with_context(|ctx| {
        let caps = ctx.capabilities();
        if !caps.depth_bounds {
            println!("SKIPPED on {}: no depthBounds feature (covered on SwiftShader)", caps.device_name);
            return;
        }
        let format = caps.depth_stencil_format;
        let depth = common::depth_target(ctx, "depth", W, H, vk::ImageUsageFlags::empty());
        let layout = PipelineLayout::new(ctx, "empty", &[], 0).unwrap();
        let write_spec = [(0, 0.6f32.to_bits())];
        let write = GraphicsPipeline::new(ctx, &layout, &fullscreen("write 0.6", &write_spec, format)).unwrap();
        // The tested draw is at depth 0.1 and always passes the depth test: only the bounds
        // test on the *stored* 0.6 can reject it.
        let probe_spec = [(0, 0.1f32.to_bits())];
        let mut probe_desc = fullscreen("bounds probe", &probe_spec, format);
        probe_desc.depth = DepthState {
            test: true,
            write: false,
            compare: vk::CompareOp::ALWAYS,
            bounds_test: true,
            ..DepthState::NONE
        };
        let probe = GraphicsPipeline::new(ctx, &layout, &probe_desc).unwrap();
        let queries = QueryPool::new(ctx, "occlusion", QueryKind::Occlusion, 2).unwrap();

        let mut rec = ctx.begin_commands("depth bounds test").unwrap();
        rec.reset_queries(&queries);
        common::begin_depth_pass(&mut rec, &depth);
        rec.bind_pipeline(&write);
        rec.draw(3);
        rec.bind_pipeline(&probe);
        rec.set_depth_bounds(0.5, 0.7); // contains the stored 0.6
        rec.begin_query(&queries, 0);
        rec.draw(3);
        rec.end_query(&queries, 0);
        rec.set_depth_bounds(0.0, 0.2); // contains the fragment's 0.1 but not the stored 0.6
        rec.begin_query(&queries, 1);
        rec.draw(3);
        rec.end_query(&queries, 1);
        rec.end_rendering();
        ctx.submit_and_wait(rec).unwrap();
        let counts = queries.results().unwrap();
        println!("depth bounds [0.5,0.7]: {} samples, [0,0.2]: {} samples", counts[0], counts[1]);
        assert_eq!(counts, vec![(W * H) as u64, 0]);
    });
}

/// Counts 300 decrements then 300 increments on every pixel (the order z-fail meets the front
/// and back faces of 300 volumes behind a lit surface) and returns the final stencil values
/// as "lit" (0) or not. Wrap ops return to 0; saturating ops stop at 0 on the way down and at
/// 255 on the way up, and end at 255.
fn three_hundred_in_and_out(ctx: &umbra::vk::Context, decrement: vk::StencilOp, increment: vk::StencilOp) -> u64 {
    let format = ctx.capabilities().depth_stencil_format;
    let depth = common::depth_target(ctx, "depth/stencil", W, H, vk::ImageUsageFlags::empty());
    let layout = PipelineLayout::new(ctx, "empty", &[], 0).unwrap();
    let spec = [(0, 0.5f32.to_bits())];
    let mut desc = fullscreen("stencil op", &spec, format);
    desc.depth = DepthState::NONE;
    let op = |o: vk::StencilOp| umbra::vk::StencilFace { pass: o, ..umbra::vk::StencilFace::KEEP };
    desc.stencil = Some((op(decrement), op(decrement)));
    let down = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
    desc.stencil = Some((op(increment), op(increment)));
    let up = GraphicsPipeline::new(ctx, &layout, &desc).unwrap();
    // Then count the pixels whose stencil is still 0.
    let probe = common::StencilProbe::new(ctx, &layout, vk::CompareOp::EQUAL);
    let mut rec = ctx.begin_commands("300 in and out").unwrap();
    probe.reset(&mut rec);
    common::begin_depth_pass(&mut rec, &depth);
    rec.bind_pipeline(&down);
    rec.set_stencil_reference(0);
    for _ in 0..300 {
        rec.draw(3);
    }
    rec.bind_pipeline(&up);
    for _ in 0..300 {
        rec.draw(3);
    }
    probe.record(&mut rec);
    rec.end_rendering();
    ctx.submit_and_wait(rec).unwrap();
    probe.pixels()
}

#[test]
fn wrap_ops_survive_300_interleaved_counts_where_saturating_ops_do_not() {
    common::with_context(|ctx| {
        let wrap = three_hundred_in_and_out(ctx, vk::StencilOp::DECREMENT_AND_WRAP, vk::StencilOp::INCREMENT_AND_WRAP);
        let clamp =
            three_hundred_in_and_out(ctx, vk::StencilOp::DECREMENT_AND_CLAMP, vk::StencilOp::INCREMENT_AND_CLAMP);
        println!("pixels back at 0 after 300 out and 300 in: wrap {wrap}, saturate {clamp} of {}", W * H);
        assert_eq!(wrap, (W * H) as u64, "wrap ops return every count to 0");
        assert_eq!(clamp, 0, "saturating ops end at 255: the lit surface would read as shadowed");
    });
}

/// The suite runs the layer's synchronization validation (`common::with_context` asks for it
/// through `ContextOptions::from_env`): two writes to one buffer with no barrier between them
/// are reported as a hazard, so a missing barrier anywhere in umbra fails its test.
#[test]
fn synchronization_validation_reports_a_planted_hazard() {
    let _ = env_logger::builder().is_test(true).filter_level(log::LevelFilter::Warn).try_init();
    let options = umbra::vk::ContextOptions { validation: true, ..umbra::vk::ContextOptions::from_env() };
    assert!(options.synchronization_validation, "UMBRA_SYNC_VALIDATION=0 turned it off for the suite");
    let ctx = umbra::vk::Context::with_options(&options).expect("Vulkan context (run ci/setup.sh)");
    let counter = ctx.validation();
    {
        let buffer = Buffer::new(&ctx, "twice-written buffer", BufferDesc::readback(256)).unwrap();
        let mut rec = ctx.begin_commands("planted write-after-write").unwrap();
        rec.fill_buffer(&buffer, 1);
        rec.fill_buffer(&buffer, 2); // no barrier: WRITE_AFTER_WRITE
        ctx.submit_and_wait(rec).unwrap();
    }
    drop(ctx);
    println!("planted hazard: {} validation errors", counter.errors());
    assert!(counter.errors() >= 1, "synchronization validation missed a write-after-write");
}
