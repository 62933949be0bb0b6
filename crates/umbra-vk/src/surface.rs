//! Window-system surfaces through `ash-window`: the instance extensions a display needs, and
//! the `VkSurfaceKHR` of one window.

use crate::context::Context;
use crate::error::{CallContext, VkError, VkResult};
use ash::vk;
use raw_window_handle::{HandleError, HasDisplayHandle, HasWindowHandle};
use std::any::Any;
use std::ffi::CStr;
use std::sync::Arc;

/// The instance extensions presenting to `display`'s windows needs (`VK_KHR_surface` and the
/// window system's own, e.g. `VK_KHR_xlib_surface`), for
/// [`crate::ContextOptions::surface_extensions`].
///
/// An engine that creates its own instance enables the same list, enables `VK_KHR_swapchain`
/// on its device and sets [`crate::ExternalDevice::presentation`].
pub fn surface_extensions(display: &impl HasDisplayHandle) -> VkResult<Vec<&'static CStr>> {
    let handle = display.display_handle().map_err(window_error)?.as_raw();
    let names = ash_window::enumerate_required_extensions(handle).map_err(|_| VkError::Unsupported {
        device: "ash-window".into(),
        what: format!("presenting to this window system ({handle:?})"),
    })?;
    // SAFETY: ash-window returns pointers to ash's `'static` NUL-terminated extension names.
    Ok(names.iter().map(|&p| unsafe { CStr::from_ptr(p) }).collect())
}

/// A window's surface; keeps the window alive until the surface is destroyed.
pub(crate) struct Surface {
    pub(crate) raw: vk::SurfaceKHR,
    pub(crate) fns: ash::khr::surface::Instance,
    ctx: Context,
    /// The window (an `Arc` of it), dropped after the surface.
    _window: Arc<dyn Any + Send + Sync>,
}

impl Surface {
    /// Creates the surface of `window` and checks that umbra's queue can present to it.
    pub(crate) fn new<W>(ctx: &Context, window: Arc<W>) -> VkResult<Self>
    where
        W: HasWindowHandle + HasDisplayHandle + Send + Sync + 'static,
    {
        if !ctx.presentation() {
            return Err(ctx.unsupported(
                "presenting to a window: the context was created without ContextOptions::surface_extensions",
            ));
        }
        let display = window.display_handle().map_err(window_error)?.as_raw();
        let handle = window.window_handle().map_err(window_error)?.as_raw();
        let inner = &ctx.inner;
        // SAFETY: the handles belong to a live window, which `_window` keeps alive until the
        // surface is destroyed in `Drop`; the instance has the extensions ash-window asked for.
        let raw = unsafe { ash_window::create_surface(&inner.entry, &inner.instance, display, handle, None) }
            .call("vkCreate*SurfaceKHR")?;
        let fns = ash::khr::surface::Instance::new(&inner.entry, &inner.instance);
        let surface = Surface { raw, fns, ctx: ctx.clone(), _window: window };
        // SAFETY: plain query of a live physical device and surface.
        let supported =
            unsafe { surface.fns.get_physical_device_surface_support(inner.physical_device, inner.queue_family, raw) }
                .call("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(ctx.unsupported(format!("presenting to this window from queue family {}", inner.queue_family)));
        }
        // Not named: the surface is an instance-level object, and naming one through the
        // device's vkSetDebugUtilsObjectNameEXT crashes Mesa 22.3's lavapipe (it frees the
        // surface's memory as if it were a device object's name). Everything else is named.
        Ok(surface)
    }

    /// The surface's capabilities now (its extent follows the window's size).
    pub(crate) fn capabilities(&self) -> VkResult<vk::SurfaceCapabilitiesKHR> {
        // SAFETY: plain query of a live physical device and surface.
        unsafe { self.fns.get_physical_device_surface_capabilities(self.ctx.inner.physical_device, self.raw) }
            .call("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")
    }

    /// The surface's formats.
    pub(crate) fn formats(&self) -> VkResult<Vec<vk::SurfaceFormatKHR>> {
        // SAFETY: plain query of a live physical device and surface.
        unsafe { self.fns.get_physical_device_surface_formats(self.ctx.inner.physical_device, self.raw) }
            .call("vkGetPhysicalDeviceSurfaceFormatsKHR")
    }

    /// The surface's present modes.
    pub(crate) fn present_modes(&self) -> VkResult<Vec<vk::PresentModeKHR>> {
        // SAFETY: plain query of a live physical device and surface.
        unsafe { self.fns.get_physical_device_surface_present_modes(self.ctx.inner.physical_device, self.raw) }
            .call("vkGetPhysicalDeviceSurfacePresentModesKHR")
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: the swapchain made from this surface was destroyed first (`Swapchain::drop`).
        unsafe { self.fns.destroy_surface(self.raw, None) };
    }
}

fn window_error(e: HandleError) -> VkError {
    VkError::Window(e.to_string())
}
