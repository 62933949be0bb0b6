//! Bring your own device: an engine creates the instance and device with plain `ash`, umbra
//! renders through them, and dropping umbra's context leaves them alive.
//!
//! The `unsafe` here is the engine's side of the contract (its own Vulkan set-up), not umbra's.

mod common;

use std::ffi::c_void;
use std::sync::atomic::{AtomicU64, Ordering};
use umbra::vk::{ash, selection, vk, Context, ExternalDevice};

static ENGINE_MESSAGES: AtomicU64 = AtomicU64::new(0);

unsafe extern "system" fn engine_messenger(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut c_void,
) -> vk::Bool32 {
    if kind.contains(vk::DebugUtilsMessageTypeFlagsEXT::GENERAL) {
        return vk::FALSE;
    }
    // SAFETY: the loader passes valid callback data for the duration of the call.
    let message = unsafe { data.as_ref().and_then(|d| d.message_as_c_str()).map(|m| m.to_string_lossy().into_owned()) };
    eprintln!("engine messenger {severity:?}: {}", message.unwrap_or_default());
    ENGINE_MESSAGES.fetch_add(1, Ordering::Relaxed);
    vk::FALSE
}

#[test]
fn umbra_renders_on_an_engine_owned_device_and_leaves_it_alive() {
    // SAFETY: a minimal engine set-up; every object is destroyed at the end of the test.
    unsafe {
        let entry = ash::Entry::load().expect("Vulkan loader");
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let exts = [ash::ext::debug_utils::NAME.as_ptr()];
        let instance = entry
            .create_instance(
                &vk::InstanceCreateInfo::default()
                    .application_info(&app)
                    .enabled_layer_names(&layers)
                    .enabled_extension_names(&exts),
                None,
            )
            .expect("instance with the validation layer (run ci/setup.sh)");
        let debug = ash::ext::debug_utils::Instance::new(&entry, &instance);
        let messenger = debug
            .create_debug_utils_messenger(
                &vk::DebugUtilsMessengerCreateInfoEXT::default()
                    .message_severity(
                        vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                    )
                    .message_type(
                        vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                    )
                    .pfn_user_callback(Some(engine_messenger)),
                None,
            )
            .unwrap();

        // The engine picks the device UMBRA_DEVICE names, with features of its own choosing:
        // here depth clamp only (no depth bounds even where the device has it).
        let physical = instance.enumerate_physical_devices().unwrap();
        let candidates: Vec<selection::Candidate> =
            physical.iter().map(|&pd| selection::Candidate::query(&instance, pd)).collect();
        let wanted = std::env::var(selection::DEVICE_ENV).ok();
        let chosen = selection::choose(&candidates, wanted.as_deref()).expect("a device");
        let (pd, family) = (physical[chosen], candidates[chosen].graphics_family.unwrap());
        let features = vk::PhysicalDeviceFeatures { depth_clamp: vk::TRUE, ..Default::default() };
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(true);
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
        let device = instance
            .create_device(
                pd,
                &vk::DeviceCreateInfo::default()
                    .queue_create_infos(&queues)
                    .enabled_features(&features)
                    .push_next(&mut f13),
                None,
            )
            .unwrap();
        let queue = device.get_device_queue(family, 0);

        let ctx = Context::from_external(ExternalDevice {
            entry: entry.clone(),
            instance: instance.clone(),
            physical_device: pd,
            device: device.clone(),
            queue,
            queue_family_index: family,
            enabled_features: features,
            debug_utils: true,
            conservative_rasterization: false,
            presentation: false,
        })
        .expect("context from the engine's device");
        let caps = ctx.capabilities().clone();
        assert!(caps.depth_clamp, "the engine enabled depthClamp");
        assert!(!caps.depth_bounds, "the engine did not enable depthBounds: umbra must not use it");
        let scene = umbra::scene::load("ball").unwrap();
        let mut renderer =
            umbra::shadows::Renderer::new(&ctx, umbra::shadows::RendererDesc::new(common::SIZE.0, common::SIZE.1))
                .unwrap();
        let frame = renderer.render(&scene).unwrap();
        assert!(frame.rgba.chunks_exact(4).any(|p| p[2] > 100), "the blue ball is visible");
        println!("rendered on the engine's {} ({} passes)", caps.device_name, frame.report.passes.len());
        drop(renderer);
        drop(ctx);

        // The engine's device is still alive and usable after umbra is gone.
        device.device_wait_idle().expect("engine device still valid");
        let pool = device
            .create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None)
            .expect("engine can still create objects");
        device.destroy_command_pool(pool, None);
        device.destroy_device(None);
        debug.destroy_debug_utils_messenger(messenger, None);
        instance.destroy_instance(None);
    }
    assert_eq!(ENGINE_MESSAGES.load(Ordering::Relaxed), 0, "validation messages on the engine's messenger");
}
