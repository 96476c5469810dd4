//! underlight: real-time underwater caustics and godrays after Papadopoulos & Papaioannou
//! (2009), on a hand-written Vulkan backend.
//!
//! - [`vk`]: the backend, one module per Vulkan concept.
//! - [`passes`]: the frame's passes, one module each, named by [`passes::PassId`].
//! - [`shaders`]: GLSL → committed SPIR-V, embedded at build time.
//! - [`shader_abi`]: the interface with the shaders (parameter block, binding numbers).
//! - [`shader_math`]: the Rust twin of the shared GLSL math.
//! - [`headless`], [`image_io`]: off-screen rendering and its files.
//! - [`grid_splat`]: the foundation's demo, outside the method's passes.
//! - [`mod@reference`], [`metrics`]: the CPU reference and the GPU frame's error against it.
//! - [`bvh`]: exact ray casts against the scene's triangles (the reference, the photon density).
//!
//! # Rendering from Rust
//!
//! Load a scene with [`scene::load`] (a built-in name or a `.toml` path), make a device with
//! [`vk::Context::new`], render with [`headless::SceneRenderer`], and read the HDR buffers
//! ([`headless::SceneImages`]: scene colour, caustic irradiance, godray radiance, in physical
//! units) and the per-pass GPU times ([`frame::PassTimings`]). `examples/render_headless.rs`
//! does all of it:
//!
//! ```no_run
//! use underlight::vk::{vk, Context, ContextDesc};
//! let scene = underlight::scene::load("tank")?;
//! let ctx = Context::new(&ContextDesc::from_env())?;
//! let extent = vk::Extent2D { width: 320, height: 200 };
//! let (timings, images) = {
//!     let mut renderer = underlight::headless::SceneRenderer::new(&ctx.device, &scene, extent)?;
//!     renderer.render(3, 1.0, 1.0 / 60.0, true)?
//! };
//! let caustics = images.unwrap().caustics.expect("the tank has caustics"); // W/m²
//! println!("caustics {}×{}", caustics.width, caustics.height);
//! println!("{}", underlight::headless::median_timings(&timings));
//! assert!(ctx.shutdown().is_clean());
//! # Ok::<(), anyhow::Error>(())
//! ```
#![warn(unsafe_op_in_unsafe_fn)]
// `!(x > 0.0)` is how this code rejects NaN together with out-of-range values (a NaN fails
// every comparison); `partial_cmp` spelled out would hide that intent, not clarify it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accuracy;
pub mod bench;
pub mod bvh;
pub mod error;
pub mod flux_budget;
pub mod frame;
pub mod grid_splat;
pub mod headless;
pub mod image_io;
pub mod memory;
pub mod metrics;
pub mod passes;
pub mod reference;
pub mod scene;
pub mod shader_abi;
pub mod shader_math;
pub mod shaders;
pub mod viewer;
pub mod vk;

pub use error::{Error, Result};
