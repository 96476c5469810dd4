//! Scenes: what the frame renders. Built-in scenes are scene files too (`assets/scenes/`).
//!
//! Conventions: metres, right-handed, **y up**; the water's mean plane is `y = water.level`
//! and "under water" is below it. Everything here is world space and validated: the
//! renderer may assume finite values inside the documented ranges.

pub mod file;
pub mod generate;
pub mod obj;

use glam::{Vec2, Vec3};

pub use file::{load, load_str, BUILTIN_SCENES};

#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    /// Default output resolution (width, height).
    pub output: [u32; 2],
    pub camera: Camera,
    pub light: Light,
    pub water: Water,
    pub medium: Medium,
    pub effects: Effects,
    /// World-space triangle meshes, one per OBJ object/material group.
    pub meshes: Vec<Mesh>,
}

#[derive(Clone, Debug)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex unit normals, same length as `positions` (computed when the OBJ has none).
    pub normals: Vec<Vec3>,
    /// Triangle list indices into `positions`/`normals`.
    pub indices: Vec<u32>,
    /// Diffuse albedo (MTL `Kd`), linear RGB in [0, 1].
    pub albedo: Vec3,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look_at: Vec3,
    /// Vertical field of view, degrees, in (0, 180).
    pub fov_y_degrees: f32,
    pub z_near: f32,
    pub z_far: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    /// Infinitely far; `direction` is the direction light travels (unit, pointing down-ish).
    /// Its position tracks the camera (method step 1).
    Directional,
    /// At `position`, fixed.
    Point,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// Directional: unit direction of travel. Point: ignored.
    pub direction: Vec3,
    /// Point: position. Directional: ignored.
    pub position: Vec3,
    /// Radiant intensity, W/sr (the paper: 9.2).
    pub intensity: f32,
    /// Directional only: distance from the point it looks at to where the tracking light sits.
    pub distance: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaterModel {
    /// Circular cosine waves around `center`, plus a small Perlin-noise contribution.
    CircularCosine,
    /// Cosine along the x axis plus a strong Perlin-noise contribution.
    AxisCosineNoise,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Water {
    pub model: WaterModel,
    /// Height of the mean plane, m.
    pub level: f32,
    /// Cosine amplitude, m (0: flat unless noise is on).
    pub amplitude: f32,
    /// Cosine wavelength, m (> 0).
    pub wavelength: f32,
    /// Phase speed, m/s.
    pub speed: f32,
    /// Perlin-noise amplitude, m.
    pub noise_amplitude: f32,
    /// Size of one noise-texture tile, m (> 0).
    pub noise_scale: f32,
    /// Origin (x, z) of circular waves.
    pub center: Vec2,
    /// The water covers the rectangle [extent_min, extent_max] in (x, z).
    pub extent_min: Vec2,
    pub extent_max: Vec2,
    /// Refractive index of the water (air is 1); the paper: 1.333.
    pub ior: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Attenuation coefficient γ per RGB channel, 1/m (the paper: 0.13 for all).
    pub gamma: Vec3,
    /// Scattering coefficient σ_s, 1/m; 0 means no godrays.
    pub scattering: f32,
    /// Henyey–Greenstein asymmetry g in (-1, 1).
    pub hg_g: f32,
}

/// How the caustics pass turns landed photons into irradiance (`effects.caustic_estimator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CausticEstimator {
    /// The paper's: each photon a square point sized by its distance to the camera
    /// (`point_size_min`..`point_size_max`), its flux spread over the pixels it covers.
    Paper,
    /// Footprint-sized points: each photon a square point as large as its cell refracted onto
    /// its receiver (from its grid neighbours' hits: photon differentials), its flux over that
    /// area; the paper's size where no neighbour landed on its receiver
    /// (glsl/caustics/caustics.geom, FOOTPRINT_POINTS). The geometry-shader path only, with
    /// `caustic_subdivision` ≥ 2 (a photon's neighbours are its invocation's).
    Footprint,
    /// Warped-cell triangles: the photons are the vertices of a mesh whose cells, refracted
    /// onto the receivers, carry their flux over their area (glsl/caustics_triangles.geom).
    /// The geometry-shader path only, with `caustic_subdivision` ≤ 3.
    Triangles,
}

impl CausticEstimator {
    pub const ALL: [CausticEstimator; 3] =
        [CausticEstimator::Paper, CausticEstimator::Footprint, CausticEstimator::Triangles];

    /// The name scene files and command lines use.
    pub fn name(self) -> &'static str {
        match self {
            CausticEstimator::Paper => "paper",
            CausticEstimator::Footprint => "footprint",
            CausticEstimator::Triangles => "triangles",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }

    /// The largest `caustic_subdivision` its geometry shader emits (`shader_abi::limits`).
    pub fn max_subdivision(self) -> u32 {
        use crate::shader_abi::limits as l;
        match self {
            CausticEstimator::Paper => l::MAX_SUBDIVISION,
            CausticEstimator::Footprint => l::FOOTPRINT_MAX_SUBDIVISION,
            CausticEstimator::Triangles => l::TRIANGLE_MAX_SUBDIVISION,
        }
    }

    /// The smallest `caustic_subdivision` it takes: the footprint points find their
    /// neighbours among their invocation's photons, so one photon per cell would have none.
    pub fn min_subdivision(self) -> u32 {
        match self {
            CausticEstimator::Footprint => 2,
            CausticEstimator::Paper | CausticEstimator::Triangles => 1,
        }
    }

    /// Whether only the geometry-shader photon path draws it (its photons need their
    /// neighbours'; `PhotonPath`).
    pub fn geometry_shader_only(self) -> bool {
        self != CausticEstimator::Paper
    }
}

/// How the godrays pass computes the light the water scatters towards the camera
/// (`effects.godray_method`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GodrayMethod {
    /// The paper's: each photon of the godray grid a line from where it enters the water to
    /// where it lands, its fragments adding the beam's in-scattered radiance. Focusing and
    /// shadows come from the photons.
    #[default]
    Beams,
    /// The same beams, each drawn as a ribbon facing the camera as wide as its refracted cell's
    /// cross-section (the survey's illumination volume), its flux spread over that width: a
    /// density estimate without gaps between lines or light piled on one pixel where beams
    /// spread (glsl/godrays/godrays_footprint.geom). Geometry-shader path only, subdivision at
    /// most GODRAY_FOOTPRINT_MAX_SUBDIVISION.
    Footprint,
    /// Each pixel of the godray target marches its view ray through the water and sums the
    /// single scattering of the light that reaches each step: through flat water (no focusing),
    /// shadowed by the light's position map (glsl/godrays/godrays_marched.frag). Directional
    /// lights only.
    Marched,
}

impl GodrayMethod {
    pub const ALL: [GodrayMethod; 3] = [GodrayMethod::Beams, GodrayMethod::Footprint, GodrayMethod::Marched];

    /// The name scene files and command lines use.
    pub fn name(self) -> &'static str {
        match self {
            GodrayMethod::Beams => "beams",
            GodrayMethod::Footprint => "footprint",
            GodrayMethod::Marched => "marched",
        }
    }

    /// Whether it casts photon beams (lines or ribbons), which the photon density, the flux
    /// budget and the photon counts concern; the march casts none.
    pub fn casts_beams(self) -> bool {
        self != GodrayMethod::Marched
    }

    /// The largest `godray_subdivision` its geometry shader emits (`shader_abi::limits`); the
    /// march casts no photons and takes the lines' bound.
    pub fn max_subdivision(self) -> u32 {
        use crate::shader_abi::limits as l;
        match self {
            GodrayMethod::Footprint => l::GODRAY_FOOTPRINT_MAX_SUBDIVISION,
            GodrayMethod::Beams | GodrayMethod::Marched => l::GODRAY_MAX_SUBDIVISION,
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }
}

/// How the photons of a grid are spread over the water's footprint
/// (`effects.caustic_photon_density`, `effects.godray_photon_density`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PhotonSpread {
    /// The paper's: an even grid over the water's footprint seen from the light.
    #[default]
    Even,
    /// The grid warped to where the view needs photons (`frame::photon_density`): caustic
    /// photons in proportion to the pixels that see where they land (the near floor gets
    /// more, water out of view few), godray beams in proportion to the length of view ray
    /// they cross.
    View,
}

impl PhotonSpread {
    pub const ALL: [PhotonSpread; 2] = [PhotonSpread::Even, PhotonSpread::View];

    /// The name scene files and command lines use.
    pub fn name(self) -> &'static str {
        match self {
            PhotonSpread::Even => "even",
            PhotonSpread::View => "view",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effects {
    pub caustics: bool,
    pub godrays: bool,
    pub filter: bool,
    /// Coarse caustic photon grid per axis (the paper: 200) and GS subdivision (2).
    pub caustic_grid: u32,
    pub caustic_subdivision: u32,
    /// Photons into irradiance: the paper's points or warped-cell triangles.
    pub caustic_estimator: CausticEstimator,
    /// The caustic photons on an even grid (the paper's) or spread as the view needs them.
    pub caustic_photon_density: PhotonSpread,
    /// The godray beams alike.
    pub godray_photon_density: PhotonSpread,
    /// Godrays from photon beams (the paper's) or ray-marched single scattering.
    pub godray_method: GodrayMethod,
    /// Godray grid (100) and subdivision (2): the beams' photons.
    pub godray_grid: u32,
    pub godray_subdivision: u32,
    /// Effect targets as a fraction of the output size per axis (the paper: 512/800, 128/800).
    pub caustic_target_scale: f32,
    pub godray_target_scale: f32,
    /// Point size at the far plane and at the near plane, px (the paper: 5 and 20).
    pub point_size_min: f32,
    pub point_size_max: f32,
    /// Godray line width, px.
    pub line_width: f32,
    /// Image-space intersection iterations.
    pub iterations: u32,
    /// Side of the light-space maps (shadow depth, receiver positions, water mask), texels.
    pub shadow_map_size: u32,
    /// Shift the photon grids by a sub-cell offset that changes every frame (an R2
    /// low-discrepancy sequence, `frame::uniforms::photon_jitter`), so that the grid's
    /// regular staircase becomes noise that time averages out.
    pub photon_jitter: bool,
    /// Cast the triangle estimator's mesh cells that span two receivers again, each as
    /// `caustic_subdivision`² finer cells (caustics_triangles.geom, CAUSTIC_REFINEMENT): more
    /// photons only where the mesh meets a receiver's edge. Needs the triangles and the
    /// device's vertexPipelineStoresAndAtomics.
    pub caustic_refinement: bool,
    /// Hold each footprint point's hat to the pixels that show its receiver (the surface there
    /// off its plane by at most a quarter of its distance from the photon), so that a hat does
    /// not run past a receiver's outline onto what lies behind (caustics.frag,
    /// FOOTPRINT_RECEIVER_TEST; docs/accuracy.md, "Hats on their own receiver"). Needs the
    /// footprint points; on lavapipe it costs 1.03–1.29× the caustic pass (docs/performance.md,
    /// "Footprint hats drawn as quads").
    pub caustic_receiver_test: bool,
}

impl Default for Medium {
    fn default() -> Self {
        Self { gamma: Vec3::splat(0.13), scattering: 0.05, hg_g: 0.5 }
    }
}

impl Default for Effects {
    fn default() -> Self {
        Self {
            caustics: true,
            godrays: true,
            filter: true,
            caustic_grid: 200,
            caustic_subdivision: 2,
            caustic_estimator: CausticEstimator::Paper,
            caustic_photon_density: PhotonSpread::Even,
            godray_photon_density: PhotonSpread::Even,
            godray_method: GodrayMethod::Beams,
            godray_grid: 100,
            godray_subdivision: 2,
            caustic_target_scale: 0.64,
            godray_target_scale: 0.16,
            point_size_min: 5.0,
            point_size_max: 20.0,
            line_width: 1.0,
            iterations: 5,
            shadow_map_size: 1024,
            photon_jitter: false,
            caustic_refinement: false,
            caustic_receiver_test: false,
        }
    }
}

impl Scene {
    /// Axis-aligned bounds of all meshes (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for m in &self.meshes {
            for p in &m.positions {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
        (lo, hi)
    }
}
