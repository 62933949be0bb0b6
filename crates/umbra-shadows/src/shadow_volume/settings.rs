//! Shadow-volume settings: counting mode and how volumes reach infinity.

use serde::{Deserialize, Serialize};

/// How a caster's volume is counted in the stencil buffer (Everitt–Kilgard §2.1, §3.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumeMode {
    /// Depth-pass: count volume faces in front of the visible surface (sides only, no caps).
    /// Wrong where the near plane cuts a volume (the eye inside a shadow).
    ZPass,
    /// Depth-fail: count volume faces behind the visible surface (sides and both caps).
    /// Robust everywhere with the far plane at infinity.
    ZFail,
    /// Per caster: z-pass where its volume cannot reach the near plane, z-fail otherwise.
    #[default]
    Auto,
}

impl VolumeMode {
    /// The name used on command lines and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::ZPass => "zpass",
            Self::ZFail => "zfail",
            Self::Auto => "auto",
        }
    }
}

impl std::str::FromStr for VolumeMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        [Self::ZPass, Self::ZFail, Self::Auto]
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("{s:?}: expected zpass, zfail or auto"))
    }
}

/// How volumes extruded to infinity survive clipping.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FarPlane {
    /// The camera's far plane at infinity (P_inf, §2.2): points at infinity in front of the
    /// eye land exactly on depth 1.
    #[default]
    Infinite,
    /// The scene camera's finite far plane, with depth clamp on the volume passes (§2.3,
    /// `depthClamp` required).
    DepthClamp,
}

/// How lights whose technique is `shadow_volume` are rendered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ShadowVolumeSettings {
    /// Counting mode.
    pub mode: VolumeMode,
    /// P_inf or depth clamp.
    pub far_plane: FarPlane,
    /// Also render every volume fragment into an overdraw image (`Frame::overdraw`) and count
    /// them (Chan–Durand's O).
    pub overdraw: bool,
}
