//! Shadow silhouette maps (Sen, Cammarano, Hanrahan 2003): a depth map plus a dual-grid map of
//! points on the silhouette edges, for piecewise-linear shadow edges.
//!
//! The passes, as the renderer records them for a light whose technique is `silhouette_map`:
//! 1. the light's depth map: the shadow-map pass (`shadow_map::pass`), unchanged;
//! 2. the silhouette map (§3.1, `pass`): the caster's silhouette edges (`edges`, from the
//!    shadow-volume module's silhouette code) drawn as conservative quads into an RG32F map
//!    offset by half a texel, each fragment storing the point §3.1 picks
//!    (`silhouette_map/points.frag`), hidden silhouettes discarded against the depth map;
//! 3. lighting (§3.2, `silhouette_map/lookup.glsl`): four depth comparisons by one gather;
//!    where they disagree, the skewed quadrant of the five silhouette points picks the corner.
//!
//! `geometry` is the CPU mirror of the shaders' point picking and quadrant test, unit-tested.
//! Spot (up to 80° half-angle) and directional lights are supported; point lights (cube maps)
//! are a typed error, [`crate::RenderError::UnsupportedLight`].

pub(crate) mod edges;
pub mod geometry;
pub(crate) mod pass;
