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

/// Whether shadow volumes are clipped to the view on the host before they are drawn: the
/// workaround for drivers whose own frustum clipping is not watertight
/// (`Capabilities::watertight_clipping`, false on SwiftShader). A volume triangle that leaves
/// the view is cut to just inside it (|x|, |y| ≤ 0.9999 w, z ≥ 0) so that the driver clips
/// nothing; its cut points are points on its original edges, found from the edges' endpoints
/// alone, so neighbours share them, and the vertex shader places them, so the vertices the
/// triangles keep stay bit-identical to the caster's own (`shadow_volume/clip.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HostClip {
    /// Where the device needs it (its clipping is not watertight).
    #[default]
    Auto,
    /// On every device.
    Always,
    /// Never: the driver clips.
    Never,
}

impl HostClip {
    /// Whether volumes are clipped on the host on a device whose clipping is
    /// `watertight_clipping`.
    pub fn applies(self, watertight_clipping: bool) -> bool {
        match self {
            HostClip::Auto => !watertight_clipping,
            HostClip::Always => true,
            HostClip::Never => false,
        }
    }
}

/// Where shadow volumes are built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumeBuild {
    /// On the GPU wherever the device allows it ([`VolumeBuild::Gpu`]: a graphics queue that
    /// runs compute, and a rasterizer whose clipping needs no host clipping), else on the host
    /// ([`VolumeBuild::Cpu`]; SwiftShader, whose clipping is not watertight). The frame
    /// report's `shadow_volume.gpu_built` says which.
    #[default]
    Auto,
    /// On the host, every frame (`build.rs`, the reference implementation).
    Cpu,
    /// In compute (`gpu.rs`): each mesh's adjacency uploaded once, then per caster and light
    /// the triangles' facing and the silhouette edges found on the GPU and the volume drawn
    /// from them indirectly; the host only names the casters. The same volumes as the CPU's
    /// (`tests/gpu_volumes.rs`). For `shadow_volume` lights and the hybrid's z-fail volumes
    /// (drawn behind its computation mask); needs a graphics queue that runs compute, and
    /// refuses host clipping, which only the CPU path has. In `auto` mode the GPU decides
    /// each caster's counting mode (§3.4). The one path that follows meshes an engine
    /// deforms on the GPU
    /// ([`crate::Shadows::add_deforming_mesh`]).
    Gpu,
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
    /// Clip the volumes to the view on the host ([`HostClip`]; default: where the driver
    /// needs it).
    #[serde(default)]
    pub host_clip: HostClip,
    /// Where the volumes are built ([`VolumeBuild`]; default: on the GPU where the device
    /// allows it).
    #[serde(default)]
    pub build: VolumeBuild,
}
