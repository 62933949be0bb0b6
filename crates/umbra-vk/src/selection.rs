//! Physical-device choice: discrete > integrated > virtual > CPU, overridable by `UMBRA_DEVICE`.
//!
//! `UMBRA_DEVICE` is a case-insensitive piece of a device's name or of its driver (the driver's
//! name and version, as frame reports print it), with `-` and `_` standing for spaces so that it
//! needs no quoting. Two drivers can name their devices alike: Debian 12's lavapipe and Mesa
//! 25's both call theirs `llvmpipe (LLVM 15.0.6, 256 bits)`, and only their drivers,
//! `llvmpipe Mesa 22.3.6 (LLVM 15.0.6)` and `llvmpipe Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)`,
//! tell them apart: `UMBRA_DEVICE=llvmpipe-mesa-25` picks the newer. A filter that fits two
//! different devices is an error naming both, never a guess.

use crate::capabilities::{device_type_name, driver_label};
use crate::error::{VkError, VkResult};
use ash::vk;

/// The environment variable that picks a device by a piece of its name or driver.
pub const DEVICE_ENV: &str = "UMBRA_DEVICE";

/// One physical device as the selector sees it.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Device name (`deviceName`).
    pub name: String,
    /// Driver name and version (`driverName driverInfo`), as [`crate::Capabilities::driver`]
    /// gives it; empty where the device does not say.
    pub driver: String,
    /// Device type.
    pub device_type: vk::PhysicalDeviceType,
    /// Its first queue family with graphics.
    pub graphics_family: Option<u32>,
    /// Why umbra cannot use it (`None` when usable).
    pub unusable: Option<String>,
}

impl Candidate {
    /// What umbra sees of `pd`: its name, driver, type, graphics queue family and whether umbra
    /// can use it (Vulkan 1.3 with dynamic rendering and synchronization2, and a graphics
    /// queue). An engine that creates its own device picks with this as umbra would.
    ///
    /// # Safety
    /// `instance` must be live and `pd` one of its physical devices.
    pub unsafe fn query(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Self {
        // SAFETY: plain queries of a live physical device of this instance (the caller's
        // contract); the chained structs are core in Vulkan 1.2 and 1.3, asked for only there.
        let (props, families, driver, f13) = unsafe {
            let props = instance.get_physical_device_properties(pd);
            let families = instance.get_physical_device_queue_family_properties(pd);
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            if props.api_version >= vk::API_VERSION_1_2 {
                let mut p2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
                instance.get_physical_device_properties2(pd, &mut p2);
            }
            let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
            if props.api_version >= vk::API_VERSION_1_3 {
                let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
                instance.get_physical_device_features2(pd, &mut f2);
            }
            (props, families, driver, (f13.dynamic_rendering, f13.synchronization2))
        };
        let text = |s: Result<&std::ffi::CStr, _>| {
            s.map(|c: &std::ffi::CStr| c.to_string_lossy().into_owned()).unwrap_or_default()
        };
        let graphics_family =
            families.iter().position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS)).map(|i| i as u32);
        let unusable = if props.api_version < vk::API_VERSION_1_3 {
            Some("needs Vulkan 1.3".to_owned())
        } else if graphics_family.is_none() {
            Some("no graphics queue".to_owned())
        } else if f13 != (vk::TRUE, vk::TRUE) {
            Some("no dynamicRendering/synchronization2".to_owned())
        } else {
            None
        };
        Self {
            name: text(props.device_name_as_c_str()),
            driver: driver_label(&text(driver.driver_name_as_c_str()), &text(driver.driver_info_as_c_str())),
            device_type: props.device_type,
            graphics_family,
            unusable,
        }
    }

    /// Whether the `UMBRA_DEVICE` filter `wanted` fits this device ([`fits`]).
    pub fn matches(&self, wanted: &str) -> bool {
        fits(wanted, &self.name, &self.driver)
    }
}

/// Whether the `UMBRA_DEVICE` filter `wanted` is a piece of a device's `name` or of its
/// `driver` ([`crate::Capabilities::driver`]), ignoring case, with `-` and `_` read as spaces.
pub fn fits(wanted: &str, name: &str, driver: &str) -> bool {
    let wanted = normalized(wanted);
    normalized(name).contains(&wanted) || normalized(driver).contains(&wanted)
}

/// Lower case, with `-` and `_` read as spaces.
fn normalized(s: &str) -> String {
    s.chars().map(|c| if c == '-' || c == '_' { ' ' } else { c.to_ascii_lowercase() }).collect()
}

/// Rank of a device type: lower is preferred.
fn type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// Picks the index of the device to use.
///
/// Without `wanted`, the best usable type wins and ties keep the loader's order. With it, only
/// usable devices it [matches](Candidate::matches) qualify, and they must be one device: copies
/// of one device under one driver (two identical GPUs) take the loader's first, and devices
/// that differ in name or driver are [`VkError::AmbiguousDevice`]. None qualifying is
/// [`VkError::NoDevice`]; both errors list every device the loader reported.
pub fn choose(candidates: &[Candidate], wanted: Option<&str>) -> VkResult<usize> {
    let fitting: Vec<(usize, &Candidate)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.unusable.is_none())
        .filter(|(_, c)| wanted.is_none_or(|w| c.matches(w)))
        .collect();
    if let Some(w) = wanted {
        let first = fitting.first().map(|(_, c)| (&c.name, &c.driver));
        if fitting.iter().any(|(_, c)| Some((&c.name, &c.driver)) != first) {
            return Err(VkError::AmbiguousDevice {
                wanted: w.to_owned(),
                matching: describe(&fitting.iter().map(|(_, c)| (*c).clone()).collect::<Vec<_>>()),
            });
        }
    }
    fitting
        .iter()
        .min_by_key(|(i, c)| (type_rank(c.device_type), *i))
        .map(|(i, _)| *i)
        .ok_or_else(|| VkError::NoDevice { wanted: wanted.map(str::to_owned), available: describe(candidates) })
}

/// One line per candidate for error messages: name, type, driver, and why it is unusable.
pub fn describe(candidates: &[Candidate]) -> Vec<String> {
    candidates
        .iter()
        .map(|c| {
            let kind = device_type_name(c.device_type);
            let driver = if c.driver.is_empty() { String::new() } else { format!("; driver {}", c.driver) };
            match &c.unusable {
                None => format!("  {} ({kind}{driver})", c.name),
                Some(why) => format!("  {} ({kind}{driver}): unusable, {why}", c.name),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(name: &str, driver: &str, t: vk::PhysicalDeviceType, ok: bool) -> Candidate {
        Candidate {
            name: name.into(),
            driver: driver.into(),
            device_type: t,
            graphics_family: Some(0),
            unusable: (!ok).then(|| "needs Vulkan 1.3".into()),
        }
    }

    const LVP22: &str = "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)";
    const LVP25: &str = "llvmpipe Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)";
    const LLVMPIPE: &str = "llvmpipe (LLVM 15.0.6, 256 bits)";

    #[test]
    fn prefers_discrete_then_integrated_then_virtual_then_cpu() {
        let c = [
            cand("llvmpipe", "", vk::PhysicalDeviceType::CPU, true),
            cand("virt", "", vk::PhysicalDeviceType::VIRTUAL_GPU, true),
            cand("igpu", "", vk::PhysicalDeviceType::INTEGRATED_GPU, true),
            cand("dgpu", "", vk::PhysicalDeviceType::DISCRETE_GPU, true),
        ];
        assert_eq!(choose(&c, None).unwrap(), 3);
        assert_eq!(choose(&c[..3], None).unwrap(), 2);
        assert_eq!(choose(&c[..2], None).unwrap(), 1);
        assert_eq!(choose(&c[..1], None).unwrap(), 0);
    }

    #[test]
    fn env_filter_is_a_case_insensitive_piece_of_the_name_or_the_driver() {
        let c = [
            cand("NVIDIA H200", "NVIDIA 580.65.06", vk::PhysicalDeviceType::DISCRETE_GPU, true),
            cand("SwiftShader Device (Subzero)", "", vk::PhysicalDeviceType::CPU, true),
            cand(LLVMPIPE, LVP22, vk::PhysicalDeviceType::CPU, true),
        ];
        assert_eq!(choose(&c, Some("swiftshader")).unwrap(), 1);
        assert_eq!(choose(&c, Some("LLVMPIPE")).unwrap(), 2);
        assert_eq!(choose(&c, Some("mesa 22")).unwrap(), 2);
        assert_eq!(choose(&c, Some("nvidia-580")).unwrap(), 0);
        assert!(matches!(choose(&c, Some("radeon")), Err(VkError::NoDevice { .. })));
    }

    #[test]
    fn two_lavapipes_are_told_apart_by_their_driver_and_never_guessed() {
        let c = [
            cand("SwiftShader Device (Subzero)", "", vk::PhysicalDeviceType::CPU, true),
            cand(LLVMPIPE, LVP25, vk::PhysicalDeviceType::CPU, true),
            cand(LLVMPIPE, LVP22, vk::PhysicalDeviceType::CPU, true),
        ];
        assert_eq!(choose(&c, Some("llvmpipe-mesa-25")).unwrap(), 1);
        assert_eq!(choose(&c, Some("llvmpipe_mesa_22")).unwrap(), 2);
        assert_eq!(choose(&c, Some("Mesa 25.0.7")).unwrap(), 1);
        let err = choose(&c, Some("llvmpipe")).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, VkError::AmbiguousDevice { .. }), "{text}");
        assert!(text.contains(LVP22) && text.contains(LVP25) && !text.contains("SwiftShader"), "{text}");
        // Two copies of one GPU under one driver cannot be told apart: the loader's first.
        let twins = [
            cand("NVIDIA H100", "NVIDIA 580", vk::PhysicalDeviceType::DISCRETE_GPU, true),
            cand("NVIDIA H100", "NVIDIA 580", vk::PhysicalDeviceType::DISCRETE_GPU, true),
        ];
        assert_eq!(choose(&twins, Some("h100")).unwrap(), 0);
    }

    #[test]
    fn unusable_devices_are_never_chosen() {
        let c = [
            cand("old gpu", "", vk::PhysicalDeviceType::DISCRETE_GPU, false),
            cand("llvmpipe", LVP22, vk::PhysicalDeviceType::CPU, true),
        ];
        assert_eq!(choose(&c, None).unwrap(), 1);
        assert!(matches!(choose(&c, Some("old")), Err(VkError::NoDevice { .. })));
        // An unusable device never makes a filter ambiguous.
        assert_eq!(choose(&c, Some("l")).unwrap(), 1);
        assert!(describe(&c)[0].contains("unusable"));
        assert!(describe(&c)[1].contains(LVP22));
    }
}
