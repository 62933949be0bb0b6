//! Physical-device choice: discrete > integrated > virtual > CPU, overridable by `UMBRA_DEVICE`.

use ash::vk;

/// The environment variable that picks a device by a case-insensitive substring of its name.
pub const DEVICE_ENV: &str = "UMBRA_DEVICE";

/// One physical device as the selector sees it.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Device name.
    pub name: String,
    /// Device type.
    pub device_type: vk::PhysicalDeviceType,
    /// Why umbra cannot use it (`None` when usable).
    pub unusable: Option<String>,
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

/// Picks the index of the device to use, or `None`.
///
/// With `wanted` set, only usable devices whose name contains it (ignoring case) qualify;
/// among the qualifying ones the best type wins and ties keep the loader's order.
pub fn choose(candidates: &[Candidate], wanted: Option<&str>) -> Option<usize> {
    let wanted = wanted.map(str::to_lowercase);
    candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.unusable.is_none())
        .filter(|(_, c)| wanted.as_ref().is_none_or(|w| c.name.to_lowercase().contains(w.as_str())))
        .min_by_key(|(i, c)| (type_rank(c.device_type), *i))
        .map(|(i, _)| i)
}

/// One line per candidate for error messages.
pub fn describe(candidates: &[Candidate]) -> Vec<String> {
    candidates
        .iter()
        .map(|c| {
            let kind = crate::capabilities::device_type_name(c.device_type);
            match &c.unusable {
                None => format!("  {} ({kind})", c.name),
                Some(why) => format!("  {} ({kind}): unusable, {why}", c.name),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(name: &str, t: vk::PhysicalDeviceType, ok: bool) -> Candidate {
        Candidate { name: name.into(), device_type: t, unusable: (!ok).then(|| "no Vulkan 1.3".into()) }
    }

    #[test]
    fn prefers_discrete_then_integrated_then_virtual_then_cpu() {
        let c = [
            cand("llvmpipe", vk::PhysicalDeviceType::CPU, true),
            cand("virt", vk::PhysicalDeviceType::VIRTUAL_GPU, true),
            cand("igpu", vk::PhysicalDeviceType::INTEGRATED_GPU, true),
            cand("dgpu", vk::PhysicalDeviceType::DISCRETE_GPU, true),
        ];
        assert_eq!(choose(&c, None), Some(3));
        assert_eq!(choose(&c[..3], None), Some(2));
        assert_eq!(choose(&c[..2], None), Some(1));
        assert_eq!(choose(&c[..1], None), Some(0));
    }

    #[test]
    fn env_filter_is_a_case_insensitive_substring() {
        let c = [
            cand("NVIDIA H200", vk::PhysicalDeviceType::DISCRETE_GPU, true),
            cand("SwiftShader Device (Subzero)", vk::PhysicalDeviceType::CPU, true),
            cand("llvmpipe (LLVM 15)", vk::PhysicalDeviceType::CPU, true),
        ];
        assert_eq!(choose(&c, Some("swiftshader")), Some(1));
        assert_eq!(choose(&c, Some("LLVMPIPE")), Some(2));
        assert_eq!(choose(&c, Some("radeon")), None);
    }

    #[test]
    fn unusable_devices_are_never_chosen() {
        let c = [
            cand("old gpu", vk::PhysicalDeviceType::DISCRETE_GPU, false),
            cand("llvmpipe", vk::PhysicalDeviceType::CPU, true),
        ];
        assert_eq!(choose(&c, None), Some(1));
        assert_eq!(choose(&c, Some("old")), None);
        assert!(describe(&c)[0].contains("unusable"));
    }
}
