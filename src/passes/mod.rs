//! The passes of the frame. Each pass lives in its own file; `PassId` names them all, so the
//! timing table, the debug labels and validation messages use the same names.

pub mod caustics;
pub mod compose;
pub mod filter;
pub mod godrays;
pub mod mesh;
pub mod photon_accumulation;
pub mod photon_records;
pub mod photon_visibility;
pub mod present;
pub mod reflection;
pub mod refraction;
pub mod scene;
pub mod shadow;

use std::ffi::CStr;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::vk::device::Device;
use crate::vk::vk;

/// The format the photon passes accumulate into. Single floats: thousands of splats or beam
/// fragments land on one pixel, each a tiny fraction of the sum, and half floats (11-bit
/// mantissa) stop adding once a pixel's sum is 2¹¹ times a splat. Measured on lavapipe:
/// godrays read −13 % (tests/godrays.rs); caustics at 1M photons −8 % against the point
/// light's exact law, and at 16.8M photons (the largest grid) 99 % of the flux was lost.
pub const ACCUMULATION_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// Photon targets are blended into and sampled bilinearly by compose: the device must
/// support both on `ACCUMULATION_FORMAT` (`target` names the pass's target in the error).
pub fn require_accumulation_format(device: &Arc<Device>, target: &'static str) -> Result<()> {
    let features =
        unsafe { device.instance.raw.get_physical_device_format_properties(device.info.handle, ACCUMULATION_FORMAT) }
            .optimal_tiling_features;
    let needed = vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
    if !features.contains(needed) {
        return Err(Error::MissingFeatures { device: device.info.name.clone(), missing: vec![target] });
    }
    Ok(())
}

/// Descriptor sets of each photon pass: one per frame in flight and per depth its splats and
/// beams are tested against. The camera under the water sees receivers directly (the scene
/// pass's depth); above it, through the surface (the refraction pass's depth, the view the
/// surface refracts). A frame picks one by where the camera is, so crossing the waterline
/// rebuilds nothing.
pub const PHOTON_SETS: usize = 2 * crate::vk::commands::FRAMES_IN_FLIGHT;

/// The photon passes' set for a frame in flight and the depth they test against.
pub fn photon_set_index(frame_index: usize, through_surface: bool) -> usize {
    frame_index + if through_surface { crate::vk::commands::FRAMES_IN_FLIGHT } else { 0 }
}

/// How the photon passes generate and splat their photons. The geometry shader is the
/// method's; the others draw the same buffers without it, so `underlight bench
/// --compare-paths` can put a measured figure on what the amplification stage costs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum PhotonPath {
    /// The method's: a geometry shader turns each coarse cell into SUBDIVISION² photons.
    #[default]
    GeometryShader,
    /// No amplification stage: one vertex per caustic photon (drawn as points) and two per
    /// godray photon (drawn as lines), each finding its photon from gl_VertexIndex.
    VertexOnly,
    /// A compute shader casts each photon and adds its splat or beam with float atomics
    /// (needs VK_EXT_shader_atomic_float).
    Compute,
    /// Not a path but a floor to compare with: the caustics pass draws, every frame, the
    /// points the compute cast recorded on its first frame (the same number, sizes and
    /// irradiance, no photon math). Godrays use the geometry shader.
    SplatFloor,
}

impl PhotonPath {
    pub const ALL: [PhotonPath; 4] =
        [PhotonPath::GeometryShader, PhotonPath::VertexOnly, PhotonPath::Compute, PhotonPath::SplatFloor];

    pub fn name(self) -> &'static str {
        match self {
            PhotonPath::GeometryShader => "geometry shader",
            PhotonPath::VertexOnly => "vertex only",
            PhotonPath::Compute => "compute (atomics)",
            PhotonPath::SplatFloor => "raw splat floor",
        }
    }
}

/// Every pass underlight can record. The order the method's frame records them in is
/// `frame::FramePlan::schedule`'s, not this enum's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PassId {
    Shadow,
    /// The underwater view the surface refracts (camera above the water only).
    Refraction,
    /// The mirrored view the surface reflects (camera above the water only).
    Reflection,
    Scene,
    Caustics,
    Godrays,
    Filter,
    Compose,
    /// Copy of a target into host memory (headless mode, screenshots).
    Readback,
    /// Blit of the output into the window's swapchain image (viewer only).
    Present,
}

impl PassId {
    pub const ALL: [PassId; 10] = [
        PassId::Shadow,
        PassId::Refraction,
        PassId::Reflection,
        PassId::Scene,
        PassId::Caustics,
        PassId::Godrays,
        PassId::Filter,
        PassId::Compose,
        PassId::Readback,
        PassId::Present,
    ];

    pub fn name(self) -> &'static str {
        // Kept as C strings too (see `label`), so recording a label allocates nothing.
        let s = self.label().to_str();
        s.unwrap_or("?")
    }

    pub fn label(self) -> &'static CStr {
        match self {
            PassId::Shadow => c"shadow",
            PassId::Refraction => c"refraction",
            PassId::Reflection => c"reflection",
            PassId::Scene => c"scene",
            PassId::Caustics => c"caustics",
            PassId::Godrays => c"godrays",
            PassId::Filter => c"filter",
            PassId::Compose => c"compose",
            PassId::Readback => c"readback",
            PassId::Present => c"present",
        }
    }
}

impl crate::vk::timing::TimedPass for PassId {
    fn label(self) -> &'static CStr {
        PassId::label(self)
    }
}

impl std::fmt::Display for PassId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
