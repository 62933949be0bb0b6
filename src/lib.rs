//! # umbra — a Vulkan-native hard-shadow renderer
//!
//! The facade over umbra's crates:
//! - [`vk`] (`umbra-vk`): core Vulkan on raw `ash` — context, capabilities, resources,
//!   pipelines, queries;
//! - [`shaders`] (`umbra-shaders`): the GLSL compiled to SPIR-V at build time;
//! - [`scene`] (`umbra-scene`): meshes, lights, cameras, glTF and scene files, the papers'
//!   procedural scenes (pure CPU);
//! - [`shadows`] (`umbra-shadows`): the renderer, the shadow techniques, frame reports.
//!
//! ```no_run
//! let ctx = umbra::vk::Context::new()?; // honours UMBRA_DEVICE and UMBRA_VALIDATION
//! let scene = umbra::scene::load("cubes")?;
//! let mut renderer = umbra::shadows::Renderer::new(&ctx, umbra::shadows::RendererDesc::new(256, 192))?;
//! let frame = renderer.render(&scene)?;
//! frame.save_png("render.png".as_ref())?;
//! println!("{}", frame.report.to_json());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub use umbra_scene as scene;
pub use umbra_shaders as shaders;
pub use umbra_shadows as shadows;
pub use umbra_vk as vk;
