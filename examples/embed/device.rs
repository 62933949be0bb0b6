//! The engine's own Vulkan set-up with plain `ash`: instance (with the validation layer and a
//! messenger of its own when `UMBRA_VALIDATION=1`), the device `UMBRA_DEVICE` names, the
//! features umbra can use where the device has them, one graphics queue, and a command pool
//! with a command buffer and a fence per frame in flight. umbra gets a `Context` over it
//! (`Context::from_external`) and never creates or destroys any of it.
//!
//! The `unsafe` here is the engine's side of the contract, not umbra's.

use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicU64, Ordering};
use umbra::vk::{ash, selection, vk, Context, ExternalDevice};

/// Validation messages the engine's messenger received.
pub static MESSAGES: AtomicU64 = AtomicU64::new(0);

unsafe extern "system" fn messenger(
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
    eprintln!("validation {severity:?}: {}", message.unwrap_or_default());
    MESSAGES.fetch_add(1, Ordering::Relaxed);
    vk::FALSE
}

/// The engine's device and its frames' command buffers and fences.
pub struct EngineDevice {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub family: u32,
    pub features: vk::PhysicalDeviceFeatures,
    /// Whether the instance has a window system's surface extensions and the device
    /// `VK_KHR_swapchain`.
    pub presentation: bool,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    pool: vk::CommandPool,
    /// One command buffer and fence per frame in flight.
    pub frames: Vec<(vk::CommandBuffer, vk::Fence)>,
}

impl EngineDevice {
    /// Creates everything, with `frames_in_flight` command buffers and signalled fences; with
    /// `surface_extensions` (a window's), the instance gets them and the device
    /// `VK_KHR_swapchain`.
    pub fn new(frames_in_flight: u32, surface_extensions: &[&CStr]) -> anyhow::Result<Self> {
        let validation = std::env::var("UMBRA_VALIDATION").is_ok_and(|v| v == "1");
        // SAFETY: plain object creation; everything is destroyed in `Drop`, in reverse order.
        unsafe {
            let entry = ash::Entry::load()?;
            let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
            let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
            let mut exts = vec![ash::ext::debug_utils::NAME.as_ptr()];
            exts.extend(surface_extensions.iter().map(|e| e.as_ptr()));
            let presentation = !surface_extensions.is_empty();
            let mut info = vk::InstanceCreateInfo::default().application_info(&app).enabled_extension_names(&exts);
            if validation {
                info = info.enabled_layer_names(&layers);
            }
            let instance = entry.create_instance(&info, None)?;
            let debug = match validation {
                true => {
                    let d = ash::ext::debug_utils::Instance::new(&entry, &instance);
                    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                        .message_severity(
                            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                        )
                        .message_type(
                            vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                        )
                        .pfn_user_callback(Some(messenger));
                    let m = d.create_debug_utils_messenger(&info, None)?;
                    Some((d, m))
                }
                false => None,
            };
            let physical = pick(&instance)?;
            let family = instance
                .get_physical_device_queue_family_properties(physical)
                .iter()
                .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
                .ok_or_else(|| anyhow::anyhow!("no graphics queue"))? as u32;
            // The features umbra uses where the device has them: the hybrid's depth-bounds
            // mask, depth clamp for volume caps, clamped depth bias for shadow maps.
            let has = instance.get_physical_device_features(physical);
            let features = vk::PhysicalDeviceFeatures {
                depth_bounds: has.depth_bounds,
                depth_clamp: has.depth_clamp,
                depth_bias_clamp: has.depth_bias_clamp,
                ..Default::default()
            };
            let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
                .dynamic_rendering(true)
                .synchronization2(true)
                .maintenance4(true);
            let priorities = [1.0];
            let queues =
                [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
            let device_exts = [ash::khr::swapchain::NAME.as_ptr()];
            let device_exts = if presentation { &device_exts[..] } else { &[] };
            let info = vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_extension_names(device_exts)
                .enabled_features(&features)
                .push_next(&mut f13);
            let device = instance.create_device(physical, &info, None)?;
            let queue = device.get_device_queue(family, 0);
            let info = vk::CommandPoolCreateInfo::default()
                .queue_family_index(family)
                .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
            let pool = device.create_command_pool(&info, None)?;
            let alloc =
                vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(frames_in_flight);
            let cmds = device.allocate_command_buffers(&alloc)?;
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let mut frames = Vec::new();
            for cmd in cmds {
                frames.push((cmd, device.create_fence(&signalled, None)?));
            }
            Ok(Self { entry, instance, physical, device, queue, family, features, presentation, debug, pool, frames })
        }
    }

    /// umbra's context over the engine's objects.
    pub fn umbra_context(&self) -> anyhow::Result<Context> {
        Ok(Context::from_external(ExternalDevice {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            physical_device: self.physical,
            device: self.device.clone(),
            queue: self.queue,
            queue_family_index: self.family,
            enabled_features: self.features,
            debug_utils: true,
            conservative_rasterization: false,
            presentation: self.presentation,
        })?)
    }

    /// Waits for frame slot `slot`'s last submission and begins its command buffer again.
    pub fn begin_frame(&self, slot: usize) -> anyhow::Result<vk::CommandBuffer> {
        let (cmd, fence) = self.frames[slot];
        // SAFETY: the slot's fence guards its command buffer: once signalled it is not pending.
        unsafe {
            self.device.wait_for_fences(&[fence], true, u64::MAX)?;
            self.device.reset_fences(&[fence])?;
            self.device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
            self.device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
        }
        Ok(cmd)
    }

    /// Ends and submits frame slot `slot`'s command buffer, signalling its fence.
    pub fn submit_frame(&self, slot: usize) -> anyhow::Result<()> {
        let (cmd, fence) = self.frames[slot];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the command buffer is recording (begin_frame) and everything it uses is
        // kept alive by the engine until its fence signals.
        unsafe {
            self.device.end_command_buffer(cmd)?;
            self.device.queue_submit2(self.queue, &submit, fence)?;
        }
        Ok(())
    }

    /// Waits for every frame in flight.
    pub fn wait_all(&self) -> anyhow::Result<()> {
        let fences: Vec<vk::Fence> = self.frames.iter().map(|f| f.1).collect();
        // SAFETY: waiting on the engine's own fences.
        unsafe { self.device.wait_for_fences(&fences, true, u64::MAX)? };
        Ok(())
    }
}

/// The device `UMBRA_DEVICE` names (or the first one), as umbra itself would pick it.
fn pick(instance: &ash::Instance) -> anyhow::Result<vk::PhysicalDevice> {
    // SAFETY: plain queries on a live instance.
    let physical = unsafe { instance.enumerate_physical_devices()? };
    // SAFETY: every `pd` comes from this live instance.
    let candidates: Vec<selection::Candidate> =
        physical.iter().map(|&pd| unsafe { selection::Candidate::query(instance, pd) }).collect();
    let i = selection::choose(&candidates, std::env::var(selection::DEVICE_ENV).ok().as_deref())?;
    Ok(physical[i])
}

impl Drop for EngineDevice {
    fn drop(&mut self) {
        // SAFETY: every frame completed (the engine waits before dropping), and umbra's context,
        // which never destroys these, is gone.
        unsafe {
            let _ = self.device.device_wait_idle();
            for (_, fence) in &self.frames {
                self.device.destroy_fence(*fence, None);
            }
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            if let Some((d, m)) = &self.debug {
                d.destroy_debug_utils_messenger(*m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
