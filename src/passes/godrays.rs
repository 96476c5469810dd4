//! Godrays pass (method step 6): photons cast on their own, coarser grid; each one that
//! lands becomes a line from the water surface to its hit, whose fragments add the beam's
//! in-scattered radiance (Henyey–Greenstein phase, attenuation along both legs) into a
//! low-resolution RGBA32F target. Units: docs/units.md.
//!
//! With `effects.godray_method = "footprint"`, each beam is instead a ribbon as wide as its
//! refracted cell's cross-section (glsl/godrays/godrays_footprint.geom), through the geometry
//! shader only: the width comes from the neighbouring photons one invocation casts.
//!
//! Or, with `effects.godray_method = "marched"`, the cheap end of the trade: one fullscreen
//! draw over the same target in which each pixel marches its view ray through the water
//! (glsl/godrays/godrays_marched.frag): single scattering through flat water, shadowed by the
//! light's position map, no photons.

use crate::error::{Error, Result};
use crate::passes::photon_accumulation::{dispatch_per_photon, require_float_atomics, AtomicAccumulation};
use crate::passes::photon_records::PhotonRecords;
use crate::passes::photon_visibility::{VisibilityDepth, VisibilityTarget};
use crate::passes::{require_accumulation_format, PhotonPath, ACCUMULATION_FORMAT, PHOTON_SETS};
use crate::scene::{Effects, GodrayMethod, PhotonSpread};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, ComputePipelineDesc, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

/// What the godray shaders read: the water's noise, the light's position map, scene depth.
pub const BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Storage),
    (b::FRAME_VALUES, Binding::Uniform),
    (b::NOISE, Binding::Texture),
    (b::LIGHT_POSITION, Binding::Texture),
    (b::LIGHT_NORMAL, Binding::Texture),
    (b::SCENE_DEPTH, Binding::Texture),
];

/// Steps of the marched method along each pixel's under-water ray. The samples are dithered
/// per pixel, so fewer steps turn into noise, which the filter smooths, rather than bands.
pub const MARCH_STEPS: u32 = 32;

pub struct GodraysPass {
    pub method: GodrayMethod,
    /// The geometry shader, vertex-only or compute path (the splat floor is a caustics-only
    /// measurement: godrays use the geometry shader there). The marched method ignores it.
    pub path: PhotonPath,
    pub grid: u32,
    pub subdivision: u32,
    /// Line width actually drawn, px (the scene's, clamped to the device's range).
    pub line_width: f32,
    pipeline: Pipeline,
    /// Where the beams are rasterised: the draw that writes their visibility test's depth
    /// before them (`passes::photon_visibility`).
    visibility: Option<VisibilityDepth>,
    accumulation: Option<AtomicAccumulation>,
    /// With `FrameOptions::record_photons` and the beams' geometry shader: two records per
    /// beam (`glsl/godrays/godrays.geom`, PHOTON_DEBUG), read back by the flux budget.
    pub photon_records: Option<PhotonRecords>,
    pub target: ColorTarget,
    /// This pass's descriptor sets (`passes::photon_set_index`), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl GodraysPass {
    /// The scene's godray settings (`effects`: method, grid, subdivision, line width) into a
    /// target of `extent`, through `path`; `record_photons` records every beam;
    /// `newton_crossing` as for `CausticsPass::new`.
    pub fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        effects: &Effects,
        path: PhotonPath,
        record_photons: bool,
        newton_crossing: bool,
    ) -> Result<Self> {
        let (grid, subdivision, method) = (effects.godray_grid, effects.godray_subdivision, effects.godray_method);
        let path = if path == PhotonPath::SplatFloor { PhotonPath::GeometryShader } else { path };
        // The march casts no beams: there is nothing to record.
        let record_photons = record_photons && method.casts_beams();
        if method == GodrayMethod::Footprint && path != PhotonPath::GeometryShader {
            return Err(Error::InvalidParameter {
                name: "godray_method",
                message: format!(
                    "\"footprint\" needs the geometry-shader photon path (asked: {}): a beam's width comes from the photons one invocation casts",
                    path.name()
                ),
            });
        }
        // The march draws no photons, so it has no photon path of its own.
        let atomics = method == GodrayMethod::Beams && path == PhotonPath::Compute;
        if atomics {
            require_float_atomics(device)?;
        }
        let max = method.max_subdivision();
        if subdivision == 0 || subdivision > max {
            return Err(Error::InvalidParameter {
                name: "godray_subdivision",
                message: format!(
                    "{subdivision} is outside 1..={max} for the {} godrays (their geometry shader's output limit)",
                    method.name()
                ),
            });
        }
        let [lo, hi] = device.limits().line_width_range;
        let line_width = effects.line_width.clamp(lo.max(1.0), hi);
        require_accumulation_format(device, "R32G32B32A32_SFLOAT with blending and linear filtering (godray target)")?;
        let mut bindings = BINDINGS.to_vec();
        if atomics {
            bindings.push((b::PHOTON_ACCUMULATION, Binding::Storage));
        }
        if record_photons {
            bindings.push((b::PHOTON_DEBUG, Binding::Storage));
        }
        let sets = DescriptorSets::new(device, "godrays", &bindings, PHOTON_SETS as u32)?;
        let beams = (grid as u64 * subdivision as u64).pow(2);
        let photon_records =
            record_photons.then(|| PhotonRecords::new(device, "godray beam records", beams, path)).transpose()?;
        if let Some(records) = &photon_records {
            for frame in 0..PHOTON_SETS {
                sets.write_at(frame, vec![(b::PHOTON_DEBUG as usize, records.resource())]);
            }
        }
        // Rasterised beams test their visibility with the depth test, against a depth the pass
        // writes first; the compute path tests in its shader, the march has nothing to test.
        let rasterised_beams = method.casts_beams() && path != PhotonPath::Compute;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let target =
            ColorTarget::with_optional_depth(device, "godrays", extent, ACCUMULATION_FORMAT, read, rasterised_beams)?;
        // PHOTON_WARP (photon_cast.glsl): the cast evaluates the view's warp only where the
        // scene spreads its beams for the view; WATER_NEWTON_ONLY as for the caustics.
        let warps = effects.godray_photon_density == PhotonSpread::View;
        let specialization = [(0, subdivision), (1, warps as u32), (2, newton_crossing as u32)];
        let set_layouts = [sets.layout];
        // The photon beams' draws, lines or ribbons, adding into the target.
        let beam_pipeline = |vertex, geometry, topology| GraphicsPipelineDesc {
            geometry,
            topology,
            blend: Blend::Additive,
            depth_test: true,
            specialization: &specialization,
            push_constant_bytes: 4,
            set_layouts: &set_layouts,
            dynamic_line_width: true,
            ..GraphicsPipelineDesc::new("godrays", vertex, "godrays.frag", target.render_pass.raw)
        };
        let (pipeline, accumulation) = match (method, path) {
            // One fullscreen draw that writes every texel of the target.
            (GodrayMethod::Marched, _) => (
                shaders::graphics_pipeline(
                    device,
                    &GraphicsPipelineDesc {
                        specialization: &[(0, MARCH_STEPS)],
                        set_layouts: &set_layouts,
                        ..GraphicsPipelineDesc::new(
                            "godrays marched",
                            "fullscreen.vert",
                            "godrays_marched.frag",
                            target.render_pass.raw,
                        )
                    },
                )?,
                None,
            ),
            (_, PhotonPath::VertexOnly) => (
                shaders::graphics_pipeline(
                    device,
                    &beam_pipeline("godrays_vertex.vert", None, vk::PrimitiveTopology::LINE_LIST),
                )?,
                None,
            ),
            (_, PhotonPath::Compute) => {
                let accumulation = AtomicAccumulation::new(device, "godrays", &target)?;
                for frame in 0..PHOTON_SETS {
                    sets.write_at(frame, vec![(b::PHOTON_ACCUMULATION as usize, accumulation.resource())]);
                }
                let desc = ComputePipelineDesc {
                    name: "godrays compute",
                    shader: "godrays.comp",
                    specialization: &specialization,
                    push_constant_bytes: 4,
                    set_layouts: &set_layouts,
                };
                (shaders::compute_pipeline(device, &desc)?, Some(accumulation))
            }
            (GodrayMethod::Footprint, _) => {
                let geometry = if record_photons { "godrays_footprint_debug.geom" } else { "godrays_footprint.geom" };
                let desc = GraphicsPipelineDesc {
                    fragment: "godrays_footprint.frag",
                    ..beam_pipeline("photon_grid.vert", Some(geometry), vk::PrimitiveTopology::POINT_LIST)
                };
                (shaders::graphics_pipeline(device, &desc)?, None)
            }
            _ => {
                let geometry = if record_photons { "godrays_debug.geom" } else { "godrays.geom" };
                let desc = beam_pipeline("photon_grid.vert", Some(geometry), vk::PrimitiveTopology::POINT_LIST);
                (shaders::graphics_pipeline(device, &desc)?, None)
            }
        };
        let visibility = rasterised_beams
            .then(|| VisibilityDepth::new(device, VisibilityTarget::Godrays, &target, &set_layouts))
            .transpose()?;
        Ok(Self {
            method,
            path,
            grid,
            subdivision,
            line_width,
            pipeline,
            visibility,
            accumulation,
            photon_records,
            target,
            sets,
            device: device.clone(),
        })
    }

    /// The recorded beams, as (hit, fate) and (surface, flux) per beam in grid order. Only
    /// meaningful after the frame that recorded them has finished.
    pub fn read_photon_records(&self) -> Option<Vec<[f32; 4]>> {
        self.photon_records.as_ref()?.read()
    }

    /// `set_index`: the frame in flight and the depth the photons are tested against
    /// (`passes::photon_set_index`).
    pub fn record(&self, cmd: vk::CommandBuffer, set_index: usize) {
        let dev = &self.device;
        let set = Some(self.sets.sets[set_index]);
        if self.method == GodrayMethod::Marched {
            self.target.render_pass.begin(cmd);
            self.pipeline.bind(cmd, set);
            unsafe { dev.raw.cmd_draw(cmd, 3, 1, 0, 0) };
            self.target.render_pass.end(cmd);
            return;
        }
        let photons = (self.grid as u64 * self.subdivision as u64).pow(2);
        if let Some(acc) = &self.accumulation {
            acc.record_clear(cmd);
            self.pipeline.bind(cmd, set);
            self.pipeline.push(cmd, &self.grid.to_ne_bytes());
            dispatch_per_photon(dev, cmd, photons);
            acc.record_resolve(cmd, &self.target);
            return;
        }
        self.target.render_pass.begin(cmd);
        if let Some(visibility) = &self.visibility {
            visibility.record(dev, cmd, set);
        }
        self.pipeline.bind(cmd, set);
        self.pipeline.push(cmd, &self.grid.to_ne_bytes());
        let vertices = match self.path {
            PhotonPath::VertexOnly => 2 * photons as u32,
            _ => self.grid * self.grid,
        };
        unsafe {
            dev.raw.cmd_set_line_width(cmd, self.line_width);
            dev.raw.cmd_draw(cmd, vertices, 1, 0, 0);
        }
        self.target.render_pass.end(cmd);
        if let Some(records) = &self.photon_records {
            records.record_host_barrier(dev, cmd);
        }
    }
}
