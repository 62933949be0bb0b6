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
//! Directional lights and spots up to 80° half-angle take one 2D map each. Point lights (and
//! wider spots) take a face atlas (`shadow_map::atlas`): the six cube faces side by side in one
//! 2D depth map and one 2D silhouette map, each face widened by a two-texel border so that the
//! lookup, in the face the direction picks, reads no texel of another face; pass 2 draws the
//! edges into every face.

pub(crate) mod edges;
pub mod geometry;
pub(crate) mod pass;
