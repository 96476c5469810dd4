//! The passes of the frame. Each pass lives in its own file; `PassId` names them all, so the
//! timing table, the debug labels and validation messages use the same names.

pub mod caustics;
pub mod compose;
pub mod filter;
pub mod godrays;
pub mod grid_splat;
pub mod scene;
pub mod shadow;

use std::ffi::CStr;

/// Every pass underlight can record, in frame order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PassId {
    Shadow,
    Scene,
    Caustics,
    Godrays,
    Filter,
    Compose,
    /// The foundation's proof-of-stack pass: a photon grid subdivided by a geometry shader.
    GridSplat,
    /// Copy of a target into host memory (headless mode, screenshots).
    Readback,
    /// Blit of the output into the window's swapchain image (viewer only).
    Present,
}

impl PassId {
    pub const ALL: [PassId; 9] = [
        PassId::Shadow,
        PassId::Scene,
        PassId::Caustics,
        PassId::Godrays,
        PassId::Filter,
        PassId::Compose,
        PassId::GridSplat,
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
            PassId::Scene => c"scene",
            PassId::Caustics => c"caustics",
            PassId::Godrays => c"godrays",
            PassId::Filter => c"filter",
            PassId::Compose => c"compose",
            PassId::GridSplat => c"grid_splat",
            PassId::Readback => c"readback",
            PassId::Present => c"present",
        }
    }
}

impl std::fmt::Display for PassId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
