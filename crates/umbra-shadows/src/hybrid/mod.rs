//! The hybrid of Chan and Durand (2004): a shadow map finds the pixels near shadow edges, and
//! z-fail shadow volumes run only there, masked by the depth-bounds test used as a computation
//! mask. Shadow-volume accuracy at close to shadow-map cost.
//!
//! Per light, top to bottom (declared in `frame.rs`, recorded in `pass.rs`):
//! 1. a shadow map (the shadow-map module's pass), by default below the image's resolution;
//!    blocker culling (§6.3, `cull.rs`) may then drop casters no map texel sees; and
//!    `hybrid bounds` (`bounds.rs`): per texel, the least depth any occluder can have over the
//!    texel and the greatest depth of a triangle that covers all of it;
//! 2. `hybrid classify`: over the frame's depth, a pixel facing the light is decided from the
//!    bounds only where they cannot be wrong (certainly lit, certainly shadowed); every other
//!    one is a *silhouette pixel* (Fig. 4, made conservative);
//! 3. `computation mask` (§4): with `depth-bounds`, the frame's depth is copied and a
//!    full-screen pass writes depth 0 at every non-silhouette pixel; with `stencil`, it sets the
//!    stencil's high bit at silhouette pixels instead;
//! 4. `hybrid volumes`: the shadow-volume module's z-fail volumes, two-sided with wrap ops,
//!    depth-bounds test on `[DEPTH_BOUNDS_EPSILON, 1]` (or the stencil bit), so masked pixels
//!    discard volume fragments before any stencil update;
//! 5. `light N silhouettes`: silhouette pixels lit where their count is zero.

pub(crate) mod bounds;
pub(crate) mod cull;
pub(crate) mod frame;
pub(crate) mod masked;
pub(crate) mod pass;
pub(crate) mod rays;
mod settings;
#[cfg(test)]
mod stencil_bits;

pub use settings::{HybridSettings, MaskKind, COUNT_BITS, DEPTH_BOUNDS_EPSILON, SILHOUETTE_BIT};
