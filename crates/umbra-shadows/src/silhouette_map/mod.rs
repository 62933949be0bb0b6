//! Shadow silhouette maps (Sen, Cammarano, Hanrahan 2003): a depth map plus a dual-grid map of
//! points on the silhouette edges, for piecewise-linear shadow edges.
//!
//! This build has the CPU reference of the two geometric steps (`geometry`): §3.1's point
//! picking and §3.2's skewed-quadrant choice. The GPU passes come next; lights that ask for
//! `silhouette_map` get `RenderError::TechniqueUnavailable` until then.

pub mod geometry;
