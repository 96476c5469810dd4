//! The frame: which passes run for a scene, in order, and their recording.
//!
//! `FramePlan` derives the passes from the scene (model only what the scene requires) and
//! their recording order (`FramePlan::schedule`, from `UNDER_WATER_ORDER` and
//! `FROM_ABOVE_ORDER` below: the one place the order is written). `Frame` creates exactly
//! those passes and targets, and `Frame::record` is one loop over the schedule, each pass
//! through the timing wrapper.

pub mod photon_density;
pub mod uniforms;

pub use crate::shader_abi::bindings;

use crate::error::{Error, Result};
use crate::passes::caustics::CausticsPass;
use crate::passes::compose::ComposePass;
use crate::passes::filter::FilterPass;
use crate::passes::godrays::GodraysPass;
use crate::passes::mesh::GpuMeshes;
use crate::passes::reflection::ReflectionPass;
use crate::passes::refraction::RefractionPass;
use crate::passes::scene::{Background, ScenePass, SurfaceInputs};
use crate::passes::shadow::ShadowPass;
use crate::passes::PassId;
use crate::passes::{photon_set_index, PHOTON_SETS};
use crate::scene::{CausticEstimator, GodrayMethod, LightKind, Scene};
use crate::shader_math::NoiseTexture;
use crate::vk::buffer::Buffer;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets, Resource};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::sampler::Sampler;
use crate::vk::upload::{clear_to_sampled, image_with_data};
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::fmt;
use std::sync::Arc;
use uniforms::{FrameExtents, FrameUniforms};

/// GPU milliseconds per pass of one frame, in recording order: the backend's timing table
/// for the method's passes.
pub type PassTimings = crate::vk::timing::PassTimings<PassId>;
/// The ring of frames in flight, timing the method's passes.
pub type FrameRing = crate::vk::commands::FrameRing<PassId>;
/// One frame in flight of that ring.
pub type FrameSlot = crate::vk::commands::FrameSlot<PassId>;

/// Which passes a scene needs, and why each is in or out.
#[derive(Clone, Debug)]
pub struct FramePlan {
    /// The passes a frame of the scene's own camera records, in recording order: what
    /// `--explain`, the timing table and the benches list.
    pub passes: Vec<PassId>,
    /// Every pass of the method with whether it is created and the reason.
    pub decisions: Vec<(PassId, bool, String)>,
    /// The recording order for a camera under the lowest trough, and (when the passes for the
    /// surface seen from above exist) for a camera above it (`FramePlan::schedule`).
    under_water: Vec<PassId>,
    from_above: Option<Vec<PassId>>,
    /// The filter pass smooths the caustic buffer too: only the paper's point splats need it
    /// (the triangle estimator's buffer is already the irradiance of a surface, and the
    /// filter measured worse on it: docs/accuracy.md).
    pub filters_caustics: bool,
}

/// The frame's passes in recording order, for a camera under the water and for one that
/// sees the surface from above. This is the one place the order is written.
///
/// Under the water the scene pass comes first: the photons are tested against its depth and
/// compose reads everything. From above, the photons are splatted into the refraction pass's
/// view (the underwater part the surface refracts), then the reflection pass draws the part
/// above the water, and only then the scene pass, whose water surface reads all of them.
const UNDER_WATER_ORDER: [PassId; 6] =
    [PassId::Shadow, PassId::Scene, PassId::Caustics, PassId::Godrays, PassId::Filter, PassId::Compose];
const FROM_ABOVE_ORDER: [PassId; 8] = [
    PassId::Shadow,
    PassId::Refraction,
    PassId::Caustics,
    PassId::Godrays,
    PassId::Filter,
    PassId::Reflection,
    PassId::Scene,
    PassId::Compose,
];

/// The camera's lowest point that can see the water from above: under the lowest trough
/// (by its near distance, as the near plane reaches past the camera) it sees the surface only
/// from below.
pub fn camera_sees_surface_from_above(scene: &Scene) -> bool {
    let w = &scene.water;
    let trough = w.level - w.amplitude.abs() - w.noise_amplitude.abs();
    scene.camera.position.y + 2.0 * scene.camera.z_near >= trough
}

impl FramePlan {
    /// The plan for the scene's own, fixed camera (headless renders, benches).
    pub fn for_scene(scene: &Scene) -> Self {
        Self::new(scene, false)
    }

    /// `camera_moves`: the camera may go anywhere (the viewer): the passes any camera
    /// position needs are created and each frame records those its camera needs.
    pub fn new(scene: &Scene, camera_moves: bool) -> Self {
        let level = scene.water.level;
        let below = scene.meshes.iter().any(|m| m.positions.iter().any(|p| p.y < level));
        // The method casts photons into the water through its surface from above; a point
        // light below the lowest trough has no photon that does.
        let trough = level - scene.water.amplitude.abs() - scene.water.noise_amplitude.abs();
        let light_under = scene.light.kind == crate::scene::LightKind::Point && scene.light.position.y < trough;
        let light_under_why = || {
            format!(
                "the point light is under the water (y = {} m, below the lowest trough at {trough} m): photons enter through the surface from above",
                scene.light.position.y
            )
        };
        let caustics = scene.effects.caustics && below && !light_under;
        let caustics_why = if !scene.effects.caustics {
            "off in the scene's effects".to_string()
        } else if !below {
            format!("no receiver lies below the water level ({level} m)")
        } else if light_under {
            light_under_why()
        } else {
            format!(
                "receivers below the water; {}² cells × {}² photons into {:.0}% of the output, {} estimator{}",
                scene.effects.caustic_grid,
                scene.effects.caustic_subdivision,
                100.0 * scene.effects.caustic_target_scale,
                scene.effects.caustic_estimator.name(),
                if scene.effects.caustic_refinement {
                    ", refined at receivers' borders (a second, indirect draw)"
                } else {
                    ""
                }
            )
        };
        let scatters = scene.medium.scattering > 0.0;
        let godrays = scene.effects.godrays && scatters && below && !light_under;
        let godrays_why = if !scene.effects.godrays {
            "off in the scene's effects".to_string()
        } else if light_under {
            light_under_why()
        } else if !scatters {
            "the medium does not scatter (scattering = 0)".to_string()
        } else if !below {
            "no receiver below the water ends a beam".to_string()
        } else {
            format!(
                "the medium scatters (σs = {} /m); {}² cells × {}² beams into {:.0}% of the output",
                scene.medium.scattering,
                scene.effects.godray_grid,
                scene.effects.godray_subdivision,
                100.0 * scene.effects.godray_target_scale
            )
        };
        // Only the paper's points: the footprint points and the triangles leave no gaps to
        // fill, and the filter blurs their lines (the footprint points' first build, squares,
        // on the tank at 320×200: relative RMSE 0.39 unfiltered, 1.32 filtered).
        let filters_caustics =
            scene.effects.filter && caustics && scene.effects.caustic_estimator == CausticEstimator::Paper;
        let filter = filters_caustics || (scene.effects.filter && godrays);
        let filter_why = if !scene.effects.filter {
            "off in the scene's effects".to_string()
        } else if !filter {
            if caustics {
                format!(
                    "no photon buffer to filter (the {} estimator's caustics need none)",
                    scene.effects.caustic_estimator.name()
                )
            } else {
                "no photon buffer to filter".to_string()
            }
        } else {
            format!(
                "low-pass over the {} buffer(s){}",
                [(filters_caustics, "caustic"), (godrays, "godray")]
                    .iter()
                    .filter(|e| e.0)
                    .map(|e| e.1)
                    .collect::<Vec<_>>()
                    .join(" and "),
                if caustics && !filters_caustics {
                    format!(
                        "; not the caustic buffer, which the {} estimator draws without splat noise",
                        scene.effects.caustic_estimator.name()
                    )
                } else {
                    String::new()
                }
            )
        };
        let shadow = caustics || godrays;
        let trough = level - scene.water.amplitude.abs() - scene.water.noise_amplitude.abs();
        let from_above = camera_moves || camera_sees_surface_from_above(scene);
        let surface_why = if camera_moves {
            format!("the camera moves: created, and recorded in frames where it is above the lowest trough ({trough} m) and can see the surface from above")
        } else if from_above {
            format!(
                "the camera (y = {} m) is above the lowest trough ({trough} m): it sees the surface from above",
                scene.camera.position.y
            )
        } else {
            format!(
                "the camera (y = {} m) is under the lowest trough ({trough} m): it sees the surface only from below (Snell's window)",
                scene.camera.position.y
            )
        };
        let mut decisions = vec![
            (
                PassId::Shadow,
                shadow,
                if shadow {
                    "photons need the light's receiver positions and normals (the water mask is derived from them, no separate target)".to_string()
                } else {
                    "no photon pass needs the light's view".to_string()
                },
            ),
            (
                PassId::Refraction,
                from_above,
                format!(
                    "{surface_why}; the underwater part, with its caustics and godrays, for the surface to refract"
                ),
            ),
            (
                PassId::Reflection,
                from_above,
                format!("{surface_why}; the part above the water, mirrored, for the surface to reflect"),
            ),
            (PassId::Scene, true, "camera colour and depth are always needed".to_string()),
            (PassId::Caustics, caustics, caustics_why),
            (PassId::Godrays, godrays, godrays_why),
            (PassId::Filter, filter, filter_why),
            (PassId::Compose, true, "the output image".to_string()),
        ];
        let created = |id: PassId| decisions.iter().any(|d| d.0 == id && d.1);
        let under_water: Vec<PassId> = UNDER_WATER_ORDER.into_iter().filter(|&p| created(p)).collect();
        let from_above: Option<Vec<PassId>> =
            from_above.then(|| FROM_ABOVE_ORDER.into_iter().filter(|&p| created(p)).collect());
        // Decisions in the order of the fullest schedule, so --explain reads top to bottom.
        decisions.sort_by_key(|d| FROM_ABOVE_ORDER.iter().position(|p| *p == d.0));
        let own_camera_above = from_above.is_some() && camera_sees_surface_from_above(scene);
        let passes = if own_camera_above { from_above.clone().unwrap_or_default() } else { under_water.clone() };
        Self { passes, decisions, under_water, from_above, filters_caustics }
    }

    /// Whether the frame creates this pass (it may record it only in some frames: the
    /// surface passes with a moving camera).
    pub fn runs(&self, id: PassId) -> bool {
        self.under_water.contains(&id) || self.from_above.as_ref().is_some_and(|p| p.contains(&id))
    }

    /// The passes a frame records, in order, for a camera that does or does not see the
    /// surface from above (`camera_sees_surface_from_above`). Borrowed: no per-frame
    /// allocation.
    pub fn schedule(&self, camera_above: bool) -> &[PassId] {
        match (&self.from_above, camera_above) {
            (Some(above), true) => above,
            _ => &self.under_water,
        }
    }
}

impl fmt::Display for FramePlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = |list: &[PassId]| list.iter().map(|p| p.name()).collect::<Vec<_>>().join(" → ");
        writeln!(f, "records, camera under the water: {}", names(&self.under_water))?;
        if let Some(above) = &self.from_above {
            writeln!(f, "records, camera above the water: {}", names(above))?;
        }
        for (id, runs, why) in &self.decisions {
            writeln!(f, "{:<10} {:<4} {}", id.name(), if *runs { "run" } else { "skip" }, why)?;
        }
        Ok(())
    }
}

/// Sizes of the frame's targets for an output size and a scene's effect scales.
pub fn frame_extents(scene: &Scene, output: vk::Extent2D, device: &Device) -> FrameExtents {
    let limits = device.limits();
    target_extents(scene, [output.width, output.height], limits.point_size_range[1], limits.line_width_range[1])
}

/// `frame_extents` with the device's largest point and line given: the CPU reference sizes
/// its buffers with this, without a device.
pub fn target_extents(scene: &Scene, output: [u32; 2], max_point_size: f32, max_line_width: f32) -> FrameExtents {
    let scaled =
        |s: f32| [((output[0] as f32 * s).round() as u32).max(1), ((output[1] as f32 * s).round() as u32).max(1)];
    FrameExtents {
        output,
        caustic: scaled(scene.effects.caustic_target_scale),
        godray: scaled(scene.effects.godray_target_scale),
        light_map: scene.effects.shadow_map_size,
        max_point_size,
        max_line_width,
    }
}

/// What the device cannot draw as the scene asks: splats larger than its largest point are
/// drawn at that size, lines wider than its widest line at that width (and narrower than
/// 1 px at 1 px). One line per setting.
pub fn device_clamps(scene: &Scene, plan: &FramePlan, device: &Device) -> Vec<String> {
    let limits = device.limits();
    let e = &scene.effects;
    let mut notes = Vec::new();
    let [_, max_point] = limits.point_size_range;
    if plan.runs(PassId::Caustics) {
        for (name, v) in [("point_size_min", e.point_size_min), ("point_size_max", e.point_size_max)] {
            if v > max_point {
                notes.push(format!("effects.{name} = {v} px exceeds the device's largest point ({max_point} px): splats are drawn at {max_point} px"));
            }
        }
    }
    let [lo, hi] = limits.line_width_range;
    if plan.runs(PassId::Godrays) {
        if e.line_width > hi {
            notes.push(format!("effects.line_width = {} px exceeds the device's widest line ({hi} px): godray lines are drawn {hi} px wide", e.line_width));
        } else if e.line_width < lo.max(1.0) {
            notes.push(format!(
                "effects.line_width = {} px is below {} px: godray lines are drawn {} px wide",
                e.line_width,
                lo.max(1.0),
                lo.max(1.0)
            ));
        }
    }
    notes
}

/// Switches that change what a frame records, for tests and debugging.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameOptions {
    /// The caustics pass writes every photon's cast, and the godray beams' pass every beam's,
    /// to a host-visible buffer (needs vertexPipelineStoresAndAtomics).
    pub record_photons: bool,
    /// How photons are generated and splatted (the geometry shader, or a peer it is measured
    /// against).
    pub photon_path: crate::passes::PhotonPath,
    /// The camera may move anywhere between frames (the viewer): passes for both sides of the
    /// water are created (`FramePlan::new`).
    pub camera_moves: bool,
    /// Each pass also counts its work per shader stage (pipeline-statistics queries, where the
    /// device has them): `bench` and `render --pipeline-statistics`.
    pub pipeline_statistics: bool,
}

/// Filter kernel radii, pixels of each buffer. The caustic radius is about half the paper's
/// smallest splat (5 px), enough to close the gaps between sparse photons without blurring
/// caustic lines much; the godray buffer is small, so a smaller radius.
pub const CAUSTIC_FILTER_RADIUS_PX: f32 = 2.5;
pub const GODRAY_FILTER_RADIUS_PX: f32 = 1.5;

/// How far (relative) a texel's reciprocal depth may lie off a pixel's surface plane and still
/// lend it light, in the filter and compose (glsl/shared/depth_aware.glsl). Caustics are light
/// on a surface: 5 %, well above a curved receiver's departure from its tangent plane over a
/// few texels, below the jump at any silhouette the scenes hold (a shelf 0.3 m before a wall
/// 3 m away is 10 %). Godrays are light along the view ray, which changes with the ray's length
/// slowly: 25 %, so only real depth jumps (a pillar at 1.5 m before a wall at 3 m is 50 %)
/// stop the filter. At 5 % the port's godray buffer read 0.150 against the reference instead
/// of 0.141 (the taps it left out were noise it no longer averaged); at 25 %, 0.143.
pub const CAUSTIC_SAME_SURFACE: f32 = 0.05;
pub const GODRAY_SAME_SURFACE: f32 = 0.25;

/// What a photon-density survey depends on: the camera's and the light's matrices and the
/// photon window.
type PhotonDensityKey = ([[f32; 4]; 4], [[f32; 4]; 4], [f32; 2], [f32; 2]);

/// While the camera moves, the photon density is surveyed again at most every this many
/// frames. The survey costs 9–16 ms of CPU (docs/performance.md). A warp a few frames old only
/// spreads the photons for where the camera just was: each photon still carries its warped
/// cell's flux, so the light stays right, and only the photons' spacing lags.
pub const PHOTON_SURVEY_INTERVAL: u32 = 8;

pub struct Frame {
    pub plan: FramePlan,
    pub extents: FrameExtents,
    /// Settings the device cannot honour and what is drawn instead (point sizes and line
    /// widths beyond its ranges), for the user to be told.
    pub clamped: Vec<String>,
    scene: Scene,
    /// The scene's bounds, for the light frustum each frame.
    bounds: (glam::Vec3, glam::Vec3),
    // Passes before the resources they read: dropped first.
    pub shadow: Option<ShadowPass>,
    pub refraction: Option<RefractionPass>,
    pub reflection: Option<ReflectionPass>,
    pub scene_pass: ScenePass,
    pub caustics: Option<CausticsPass>,
    pub godrays: Option<GodraysPass>,
    /// Filters of the caustic and godray buffers, when the plan filters.
    pub caustic_filter: Option<FilterPass>,
    pub godray_filter: Option<FilterPass>,
    pub compose: ComposePass,
    uniforms: Vec<Buffer>,
    meshes: GpuMeshes,
    // Read through the descriptor sets only; owned here so they live as long as the frame.
    _noise: Image,
    /// The noise's CPU twin: the surface's height at the camera each frame.
    noise_twin: NoiseTexture,
    /// The scene's triangles, for the survey of what the camera sees when the caustic photons
    /// or the godray beams follow the view (`effects.caustic_photon_density` or
    /// `godray_photon_density = "view"`); None otherwise.
    photon_survey: Option<crate::bvh::Bvh>,
    /// The last warps surveyed and the frame they were surveyed for (camera, light, window):
    /// surveyed again only when those change, and at most every PHOTON_SURVEY_INTERVAL frames.
    photon_density: Option<(PhotonDensityKey, photon_density::ViewDensities)>,
    /// Frames recorded since the last survey.
    frames_since_survey: u32,
    /// Surveys run since the frame was created (for the tests and the curious).
    pub photon_surveys: u64,
    /// The last survey's CPU time (`render` prints it; docs/performance.md).
    pub photon_survey_time: std::time::Duration,
    _nearest: Sampler,
    _linear: Sampler,
}

/// Whether the photon passes compile only Newton's search of the water crossing
/// (WATER_NEWTON_ONLY, photon_cast.glsl): a directional light's photon rays all share its
/// direction, so whether that search serves every one of them is the scene's to say, once
/// (`shader_math::newton_finds_every_crossing`).
pub fn newton_crossing(scene: &Scene) -> bool {
    scene.light.kind == LightKind::Directional
        && crate::shader_math::newton_finds_every_crossing(&scene.water, scene.light.direction.normalize())
}

impl Frame {
    /// Creates the passes the scene needs for an output of `output` texels, leaving the
    /// output in `output_layout` (TRANSFER_SRC_OPTIMAL headless, PRESENT_SRC_KHR for a window).
    pub fn new(
        device: &Arc<Device>,
        scene: &Scene,
        output: vk::Extent2D,
        output_layout: vk::ImageLayout,
        options: FrameOptions,
    ) -> Result<Self> {
        // A scene built in code meets the ranges a scene file is held to (`Scene::validate`).
        scene.validate()?;
        let plan = FramePlan::new(scene, options.camera_moves);
        let extents = frame_extents(scene, output, device);
        let clamped = device_clamps(scene, &plan, device);
        let mut uniforms = Vec::with_capacity(FRAMES_IN_FLIGHT);
        for i in 0..FRAMES_IN_FLIGHT {
            uniforms.push(Buffer::new(
                device,
                &format!("frame {i} uniforms"),
                std::mem::size_of::<FrameUniforms>() as u64,
                // Read as a read-only storage buffer, and its values by the fragment shaders as a
                // uniform block: glsl/shared/frame.glsl says why.
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::UNIFORM_BUFFER,
                MemoryLocation::CpuToGpu,
            )?);
        }
        let meshes = GpuMeshes::new(device, scene)?;
        let noise_data = NoiseTexture::generate();
        let noise = image_with_data(
            device,
            "water noise",
            vk::Extent2D { width: noise_data.size, height: noise_data.size },
            vk::Format::R32G32B32A32_SFLOAT,
            bytemuck::cast_slice(&noise_data.texels),
        )?;
        let nearest = Sampler::new(device, "nearest", vk::Filter::NEAREST)?;
        let linear = Sampler::new(device, "linear", vk::Filter::LINEAR)?;
        // The second, steeper light maps where the maps bend (a directional light entering
        // the water from above): uniforms::steep_light_axis.
        let steep_maps = uniforms::steep_light_axis(scene) != glam::Vec3::ZERO;
        let shadow = if plan.runs(PassId::Shadow) {
            Some(ShadowPass::new(device, extents.light_map, steep_maps)?)
        } else {
            None
        };
        let (refraction, reflection) = if plan.runs(PassId::Refraction) {
            (Some(RefractionPass::new(device, output)?), Some(ReflectionPass::new(device, output)?))
        } else {
            (None, None)
        };
        let newton_crossing = newton_crossing(scene);
        let caustics = if plan.runs(PassId::Caustics) {
            let e = &scene.effects;
            let ext = vk::Extent2D { width: extents.caustic[0], height: extents.caustic[1] };
            Some(CausticsPass::new(device, ext, e, options.record_photons, options.photon_path, newton_crossing)?)
        } else {
            None
        };
        let godrays = if plan.runs(PassId::Godrays) {
            let e = &scene.effects;
            let ext = vk::Extent2D { width: extents.godray[0], height: extents.godray[1] };
            // The scene file refuses this too; a scene built in code reaches here.
            if e.godray_method == GodrayMethod::Marched && scene.light.kind == LightKind::Point {
                return Err(Error::InvalidParameter {
                    name: "godray_method",
                    message: "\"marched\" needs a directional light: it takes the light through flat water along one refracted direction".into(),
                });
            }
            Some(GodraysPass::new(device, ext, e, options.photon_path, options.record_photons, newton_crossing)?)
        } else {
            None
        };
        let filtering = plan.runs(PassId::Filter);
        let caustic_filter = match (&caustics, filtering && plan.filters_caustics) {
            (Some(c), true) => Some(FilterPass::new(
                device,
                "caustics filter",
                &c.target.image,
                CAUSTIC_FILTER_RADIUS_PX,
                CAUSTIC_SAME_SURFACE,
            )?),
            _ => None,
        };
        let godray_filter = match (&godrays, filtering) {
            (Some(g), true) => Some(FilterPass::new(
                device,
                "godrays filter",
                &g.target.image,
                GODRAY_FILTER_RADIUS_PX,
                GODRAY_SAME_SURFACE,
            )?),
            _ => None,
        };
        let surface = SurfaceInputs {
            through_surface: refraction.is_some(),
            caustics: caustics.is_some(),
            godrays: godrays.is_some(),
        };
        let scene_pass = ScenePass::new(device, output, surface)?;
        let compose = ComposePass::new(
            device,
            output,
            caustics.is_some(),
            godrays.is_some(),
            surface.through_surface,
            output_layout,
        )?;
        // With the surface seen from above possible, the scene pass binds what the surface
        // reads in every frame, also those that record it later (camera under the water) or
        // never wrote it yet: all must be in the sampled layout from the start.
        if let (Some(r), Some(m)) = (&refraction, &reflection) {
            let mut images = vec![&r.color, &r.albedo, &r.depth, &m.color];
            images.extend(caustics.as_ref().map(|c| &c.target.image));
            images.extend(godrays.as_ref().map(|g| &g.target.image));
            images.extend(caustic_filter.iter().chain(&godray_filter).map(|f| &f.output.image));
            clear_to_sampled(device, "surface inputs cleared to the sampled layout", &images)?;
        }

        // Each pass declared the bindings its shaders read; fill them from what this frame
        // made. A binding whose producer is not in the plan would be a bug in the plan.
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let tex = |image: &Image, sampler: &Sampler| Resource::Texture {
            view: image.view,
            sampler: sampler.raw,
            layout: read,
        };
        let refraction_image = |image: fn(&RefractionPass) -> &Image| {
            image(refraction.as_ref().expect("plan: the surface reads the refraction pass the frame lacks"))
        };
        // `set`: a set index; photon passes have two per frame in flight (photon_set_index).
        let resource = |binding: u32, set: usize| -> Resource {
            let frame = set % FRAMES_IN_FLIGHT;
            let through_surface = set >= FRAMES_IN_FLIGHT;
            match binding {
                bindings::UNIFORMS => Resource::Storage { buffer: uniforms[frame].raw, range: uniforms[frame].size },
                bindings::FRAME_VALUES => {
                    Resource::Uniform { buffer: uniforms[frame].raw, range: crate::shader_abi::FRAME_VALUES_BYTES }
                }
                bindings::NOISE => tex(&noise, &nearest),
                // Both maps are arrays with a layer per pair (passes::shadow::FIRST_MAPS, STEEP_MAPS).
                bindings::LIGHT_POSITION => {
                    tex(&shadow.as_ref().expect("plan: photon passes need the shadow pass").position, &nearest)
                }
                bindings::LIGHT_NORMAL => {
                    tex(&shadow.as_ref().expect("plan: photon passes need the shadow pass").normal, &nearest)
                }
                // Photon passes test against the view the camera sees them in (photon_set_index).
                bindings::SCENE_DEPTH if through_surface && refraction.is_some() => {
                    tex(refraction_image(|r| &r.depth), &nearest)
                }
                bindings::SCENE_DEPTH => tex(&scene_pass.depth, &nearest),
                bindings::REFRACTION_COLOR => tex(refraction_image(|r| &r.color), &linear),
                bindings::REFRACTION_ALBEDO => tex(refraction_image(|r| &r.albedo), &linear),
                bindings::REFRACTION_DEPTH => tex(refraction_image(|r| &r.depth), &nearest),
                bindings::REFLECTION_COLOR => tex(&reflection.as_ref().expect("plan: reflection").color, &linear),
                bindings::SCENE_COLOR => tex(&scene_pass.color, &nearest),
                bindings::ALBEDO_TRANSMITTANCE => tex(&scene_pass.albedo_transmittance, &nearest),
                // Effect targets are smaller than the output; compose upsamples them along the
                // scene's depth itself and reads the filtered buffer when there is one.
                bindings::CAUSTICS => match (&caustic_filter, &caustics) {
                    (Some(f), _) => tex(&f.output.image, &linear),
                    (None, Some(c)) => tex(&c.target.image, &linear),
                    _ => panic!("plan: compose reads caustics the frame lacks"),
                },
                bindings::GODRAYS => match (&godray_filter, &godrays) {
                    (Some(f), _) => tex(&f.output.image, &linear),
                    (None, Some(g)) => tex(&g.target.image, &linear),
                    _ => panic!("plan: compose reads godrays the frame lacks"),
                },
                other => panic!("no resource for binding {other}"),
            }
        };
        // Each pass's sets, the bindings its shaders read, and how many sets it has.
        type PassSets<'a> = Vec<(&'a DescriptorSets, Vec<(u32, Binding)>, usize)>;
        let mut pass_sets: PassSets = vec![
            (&scene_pass.sets, surface.bindings(), FRAMES_IN_FLIGHT),
            (&compose.sets, ComposePass::bindings(caustics.is_some(), godrays.is_some()), FRAMES_IN_FLIGHT),
        ];
        if let (Some(r), Some(m)) = (&refraction, &reflection) {
            pass_sets.push((&r.sets, crate::passes::refraction::BINDINGS.to_vec(), FRAMES_IN_FLIGHT));
            pass_sets.push((&m.sets, crate::passes::reflection::BINDINGS.to_vec(), FRAMES_IN_FLIGHT));
        }
        if let Some(s) = &shadow {
            pass_sets.push((&s.sets, crate::passes::shadow::BINDINGS.to_vec(), FRAMES_IN_FLIGHT));
        }
        if let Some(c) = &caustics {
            pass_sets.push((&c.sets, crate::passes::caustics::BINDINGS.to_vec(), PHOTON_SETS));
        }
        if let Some(g) = &godrays {
            pass_sets.push((&g.sets, crate::passes::godrays::BINDINGS.to_vec(), PHOTON_SETS));
        }
        for (sets, list, count) in pass_sets {
            for frame in 0..count {
                sets.write_at(frame, list.iter().map(|(b, _)| (*b as usize, resource(*b, frame))).collect());
            }
        }
        // Each filter instance reads its own effect buffer through the one input binding, and
        // the depth its photon pass tested against.
        for (filter, input) in [
            (&caustic_filter, caustics.as_ref().map(|c| &c.target.image)),
            (&godray_filter, godrays.as_ref().map(|g| &g.target.image)),
        ] {
            if let (Some(f), Some(input)) = (filter, input) {
                for set in 0..PHOTON_SETS {
                    f.sets.write_at(
                        set,
                        vec![
                            (bindings::UNIFORMS as usize, resource(bindings::UNIFORMS, set)),
                            (bindings::FRAME_VALUES as usize, resource(bindings::FRAME_VALUES, set)),
                            (bindings::SCENE_DEPTH as usize, resource(bindings::SCENE_DEPTH, set)),
                            (bindings::FILTER_INPUT as usize, tex(input, &linear)),
                        ],
                    );
                }
            }
        }
        let view = crate::scene::PhotonSpread::View;
        let caustics_follow = caustics.is_some() && scene.effects.caustic_photon_density == view;
        let beams_follow =
            godrays.as_ref().is_some_and(|g| g.method.casts_beams()) && scene.effects.godray_photon_density == view;
        let photon_survey = (caustics_follow || beams_follow).then(|| crate::bvh::Bvh::of_scene(scene));
        Ok(Self {
            plan,
            extents,
            clamped,
            scene: scene.clone(),
            bounds: scene.bounds(),
            shadow,
            refraction,
            reflection,
            scene_pass,
            caustics,
            godrays,
            caustic_filter,
            godray_filter,
            compose,
            uniforms,
            meshes,
            _noise: noise,
            noise_twin: noise_data,
            photon_survey,
            photon_density: None,
            frames_since_survey: 0,
            photon_surveys: 0,
            photon_survey_time: std::time::Duration::ZERO,
            _nearest: nearest,
            _linear: linear,
        })
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene, to change what the uniforms carry (camera, water, medium) between frames.
    /// Geometry and effect switches need a new frame: they decide passes and targets.
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }

    /// The caustic photons' warp as last surveyed (`effects.caustic_photon_density = "view"`;
    /// None before the first survey, or where the view holds too little lit water): its grid
    /// aspect and order, which `render` prints.
    pub fn caustic_photon_warp(&self) -> Option<&photon_density::PhotonDensity> {
        let view = self.scene.effects.caustic_photon_density == crate::scene::PhotonSpread::View;
        self.photon_density.as_ref().filter(|_| view).and_then(|(_, densities)| densities.caustics.as_ref())
    }

    /// Writes this frame's uniforms (the slot's fence has signalled, so its buffer is free)
    /// and records the plan's schedule for where the camera is, each pass through the slot's
    /// timer.
    pub fn record(&mut self, slot: &mut FrameSlot, time: f32) {
        let through_surface = self.refraction.is_some() && camera_sees_surface_from_above(&self.scene);
        let mut u = FrameUniforms::new(&self.scene, self.bounds, &self.extents, time);
        u.surface_views_ready = if through_surface { 1.0 } else { 0.0 };
        let c = self.scene.camera.position;
        let hg =
            crate::shader_math::water_height_grad(&self.scene.water, &self.noise_twin, glam::Vec2::new(c.x, c.z), time);
        (u.camera_water_height, u.camera_water_gradient) = (hg.x, [hg.y, hg.z]);
        if let Some(bvh) = &self.photon_survey {
            let key = (u.camera_view_proj, u.light_view_proj, u.photon_window_min, u.photon_window_size);
            self.frames_since_survey = self.frames_since_survey.saturating_add(1);
            let stale = match &self.photon_density {
                None => true,
                Some((k, _)) => *k != key && self.frames_since_survey >= PHOTON_SURVEY_INTERVAL,
            };
            if stale {
                let previous = self.photon_density.as_ref().map(|(_, densities)| densities);
                let started = std::time::Instant::now();
                let densities = photon_density::view_adapted(&self.scene, self.bounds, bvh, &u, previous);
                self.photon_survey_time = started.elapsed();
                self.photon_density = Some((key, densities));
                self.frames_since_survey = 0;
                self.photon_surveys += 1;
            }
            if let Some((_, densities)) = &self.photon_density {
                let e = &self.scene.effects;
                let view = crate::scene::PhotonSpread::View;
                if let (Some(d), true) = (&densities.caustics, e.caustic_photon_density == view) {
                    d.apply_to_caustics(&mut u);
                }
                if let (Some(d), true) = (&densities.godrays, e.godray_photon_density == view) {
                    d.apply_to_godrays(&mut u);
                }
            }
        }
        if let Some(bytes) = self.uniforms[slot.index].mapped_mut() {
            bytes.copy_from_slice(bytemuck::bytes_of(&u));
        }
        // Every ray starts under the water when the camera cannot see the surface from above.
        let background = if !camera_sees_surface_from_above(&self.scene) {
            let fog = crate::shader_math::water_fog_radiance(
                u.ambient_irradiance,
                glam::Vec3::from_array(u.attenuation),
                u.scattering,
            );
            Background::Uniform(fog.to_array())
        } else {
            Background::Draw
        };
        let (i, cmd) = (slot.index, slot.cmd);
        let photon_set = photon_set_index(i, through_surface);
        for &id in self.plan.schedule(through_surface) {
            slot.timer.pass(cmd, id, |cmd| self.record_pass(id, cmd, i, photon_set, background));
        }
    }

    /// Records one pass of the schedule. `i`: the frame in flight; `photon_set`: the photon
    /// passes' descriptor set (which depth their splats are tested against).
    fn record_pass(&self, id: PassId, cmd: vk::CommandBuffer, i: usize, photon_set: usize, background: Background) {
        let planned = "FramePlan::schedule lists only passes the frame created";
        match id {
            PassId::Shadow => self.shadow.as_ref().expect(planned).record(cmd, i, &self.meshes),
            PassId::Refraction => self.refraction.as_ref().expect(planned).record(cmd, i, &self.meshes),
            PassId::Reflection => self.reflection.as_ref().expect(planned).record(cmd, i, &self.meshes),
            PassId::Scene => self.scene_pass.record(cmd, i, &self.meshes, background),
            PassId::Caustics => self.caustics.as_ref().expect(planned).record(cmd, photon_set),
            PassId::Godrays => self.godrays.as_ref().expect(planned).record(cmd, photon_set),
            PassId::Filter => {
                for f in self.caustic_filter.iter().chain(&self.godray_filter) {
                    f.record(cmd, photon_set);
                }
            }
            PassId::Compose => self.compose.record(cmd, i),
            PassId::Readback | PassId::Present => {
                unreachable!("{id} is not a pass of the method's frame")
            }
        }
    }
}
