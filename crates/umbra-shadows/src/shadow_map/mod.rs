//! Shadow maps (Williams 1978) as the papers use them: Chan–Durand §3 step 1 and §5,
//! Arneson §3, Sen §1. The fast, inexact baseline every other technique is compared with.
//!
//! Per light, top to bottom:
//! 1. fit the light's views (`frustum.rs`): orthographic for directional lights (fitted to the
//!    casters that can shadow visible receivers), perspective around a spot's cone, six cube
//!    faces for point lights;
//! 2. render depth from the light (`pass.rs`): positions only, no colour attachment, casters
//!    front to back, constant + slope-scaled depth bias through `vkCmdSetDepthBias`;
//! 3. in the light's lighting pass, compare against the map (`shaders-glsl/shadow_map/lookup.glsl`):
//!    nearest, hardware 2×2 PCF through a LINEAR comparison sampler, or 3×3 / 5×5 kernels;
//!    optional normal offset; points outside a 2D map's frustum are explicitly lit.

pub(crate) mod atlas;
pub(crate) mod fits;
pub(crate) mod frustum;
mod kept;
mod map_frame;
pub(crate) mod pass;
pub(crate) mod samples;
mod settings;
pub(crate) mod texels;

pub(crate) use map_frame::MapFrame;
pub use settings::{DepthBias, ShadowFilter, ShadowMapSettings};
