//! Robust stenciled shadow volumes (Everitt–Kilgard 2002): the exact technique.
//!
//! Per light, top to bottom:
//! 1. on the CPU, per caster and in parallel (`build.rs`): facing of each triangle at the
//!    homogeneous light position, silhouette edges, side quads and caps
//!    (`umbra_scene::Volume`; open and non-manifold casters closed with multiplicity); the
//!    counting mode per caster (§3.4): z-pass when its volume cannot reach the near-plane
//!    region between the eye and the light, z-fail otherwise;
//! 2. on the GPU (`pass.rs`): vertices extruded to infinity in the vertex shader, with the far
//!    plane at infinity (§2.2) or depth clamp (§2.3); one draw per caster with two-sided
//!    stencil and wrap ops, colour and depth writes off, stencil cleared per light; in
//!    batches folded into one bit where the casters could count past the stencil
//!    (`batches.rs`);
//! 3. the light's additive pass where stencil == 0 and depth EQUAL.

pub(crate) mod batches;
pub(crate) mod build;
pub(crate) mod clip;
pub(crate) mod deform;
pub(crate) mod frame;
pub(crate) mod gpu;
pub(crate) mod gpu_frame;
pub(crate) mod pass;
mod report;
mod settings;

pub use gpu::GpuSilhouettes;
pub use report::{CasterMode, ShadowVolumeReport};
pub use settings::{FarPlane, HostClip, ShadowVolumeSettings, VolumeBuild, VolumeMode};
