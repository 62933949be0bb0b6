//! # umbra-reference — the exact CPU reference
//!
//! What every technique is scored against. No Vulkan: a [`SceneBvh`] (obvhs's compressed wide
//! BVH over every scene triangle in world space, built in parallel, with a watertight
//! double-precision triangle test) answers shadow rays; [`ShadowMask::reference`] casts one
//! from every pixel's surface to a light (read from the renderer's G-buffer with
//! [`SurfaceImage::from_gbuffer`], or ray cast with [`SurfaceImage::ray_cast`]); a
//! [`Comparison`] scores a technique's mask: wrong pixels split into false shadow and false
//! light, the same inside a band around the true edges, and the farthest wrong pixel's
//! distance from the true edge; [`error_image`] and [`ShadowMask::save_exr`] show them.
//!
//! ```
//! use umbra_reference::{SceneBvh, ShadowMask, SurfaceImage};
//! let scene = umbra_scene::procedural::build("cylinder").unwrap();
//! let bvh = SceneBvh::build(&scene);
//! let surfaces = SurfaceImage::ray_cast(&scene, &bvh, 64, 48);
//! let mask = ShadowMask::reference(&scene, &bvh, 0, &surfaces).unwrap();
//! let (shadowed, lit) = mask.counts();
//! assert!(shadowed > 0 && lit > 0);
//! ```

#![warn(missing_docs)]

mod bvh;
mod compare;
mod distance;
mod error;
mod mask;
mod surfaces;

pub use bvh::{Hit, SceneBvh, SceneTriangle};
pub use compare::{edge_distance, error_image, save_error_png, Comparison, WrongPixels, EDGE_BAND_PX};
pub use distance::distance_to_seeds;
pub use error::{ReferenceError, ReferenceResult};
pub use mask::{ray_cast_image, shadow_blockers, shadow_ray, shadow_state, towards, ShadowMask, RAY_OFFSET_SCALE};
pub use surfaces::{pixel_ray, Surface, SurfaceImage};
