//! Caustics pass (method step 5): the photon grid, subdivided by the geometry shader,
//! refracted at the water and intersected with the scene in image space; the photons that
//! land become irradiance in an RGBA32F target a fraction of the output's size (units:
//! docs/units.md), by one of two estimators (`CausticEstimator`): the paper's
//! distance-sized points, or warped-cell triangles (glsl/caustics/caustics_triangles.geom).

use crate::error::{Error, Result};
use crate::passes::photon_accumulation::{dispatch_per_photon, require_float_atomics, AtomicAccumulation};
use crate::passes::photon_records::PhotonRecords;
use crate::passes::photon_visibility::{VisibilityDepth, VisibilityTarget};
use crate::passes::{require_accumulation_format, PhotonPath, ACCUMULATION_FORMAT, PHOTON_SETS};
use crate::scene::{CausticEstimator, Effects, PhotonSpread};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::buffer::Buffer;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets, Resource};
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, ComputePipelineDesc, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, ColorTarget, Load, RenderPass, Store};
use ash::vk;
use std::cell::Cell;
use std::sync::Arc;

/// What the caustics shaders read: the water's noise, the light's receiver maps, and the
/// scene's depth for the visibility test.
pub const BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Storage),
    (b::FRAME_VALUES, Binding::Uniform),
    (b::NOISE, Binding::Texture),
    (b::LIGHT_POSITION, Binding::Texture),
    (b::LIGHT_NORMAL, Binding::Texture),
    (b::SCENE_DEPTH, Binding::Texture),
];

/// Bytes of one recorded splat of the raw splat floor: clip position, irradiance, and
/// (point size, view depth) padded to a vec4 (`SplatRecord` in glsl/caustics/caustics_record.comp).
const SPLAT_RECORD_BYTES: u64 = 48;

/// The raw splat floor's extra state: the recorded splats and the compute cast that records
/// them on the first frame.
struct SplatFloor {
    records: Buffer,
    cast: Pipeline,
    recorded: Cell<bool>,
}

/// The triangles' refinement at receivers' borders (`effects.caustic_refinement`,
/// caustics_triangles.geom's CAUSTIC_REFINEMENT): the grid's draw lists the mesh cells it
/// hands on, and a second draw, as many invocations as it listed, casts each again finer.
struct Refinement {
    /// Per frame in flight: the second draw's `VkDrawIndirectCommand`, whose vertex count the
    /// grid's draw counts up, then each handed-on cell's first photon (an ivec2).
    cells: Vec<Buffer>,
    /// The second draw's pipeline (REFINED_DRAW) and its render pass, which keeps what the
    /// grid's draw left in the target.
    draw: Pipeline,
    render_pass: RenderPass,
}

/// Bytes of `Refinement::cells`' head, the indirect command, and of each cell it lists.
const INDIRECT_COMMAND_BYTES: u64 = 16;
const REFINED_CELL_BYTES: u64 = 8;

/// How many mesh cells the refinement's list holds: a quarter of the grid's mesh, past which
/// cells are drawn unrefined. The built-in scenes hand on 5–9 % of the cells the camera sees
/// (docs/accuracy.md, "Refinement at receivers' borders").
fn refined_cells_capacity(grid: u32, subdivision: u32) -> u64 {
    (grid as u64 * subdivision as u64).pow(2).div_ceil(4)
}

pub struct CausticsPass {
    pub path: PhotonPath,
    pub estimator: CausticEstimator,
    /// The pipeline is the triangles' (caustics_triangles.geom), which meshes a ring of cells
    /// besides the grid's own (`mesh_invocations`); not when recording photons, which go
    /// through the points' recording variant.
    draws_triangles: bool,
    /// Where points are drawn: the draw that writes their visibility test's depth before them
    /// (`passes::photon_visibility`).
    visibility: Option<VisibilityDepth>,
    pub grid: u32,
    pub subdivision: u32,
    /// With photon recording on: two vec4 per photon, (hit, 1 if landed else −drop reason)
    /// and (surface, flux: transmitted, or the light's before the water where dropped);
    /// `flux_budget` reads them.
    pub photon_records: Option<PhotonRecords>,
    /// The photon pipeline: graphics for the rasterised paths and the splat floor's draw,
    /// compute for the compute path.
    pipeline: Pipeline,
    accumulation: Option<AtomicAccumulation>,
    splat_floor: Option<SplatFloor>,
    refinement: Option<Refinement>,
    pub target: ColorTarget,
    /// This pass's descriptor sets (`passes::photon_set_index`), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

/// Invocations of the triangles' geometry shader for a grid of `grid`² coarse cells: the
/// grid's own cells, shaped N/k × N·k (`shader_math::caustic_grid_cell`), then a ring of
/// N/k + N·k + 1 cells before its first row and column (`mesh_cell` in
/// caustics_triangles.geom). The survey keeps k within 1/2..2 (`photon_density`'s
/// GRID_ASPECT_MAX), so the ring holds at most 2.5·N + 2 cells.
fn mesh_invocations(grid: u32) -> u32 {
    grid * grid + 3 * grid + 2
}

impl CausticsPass {
    /// `newton_crossing`: every photon ray of the scene finds its water crossing by Newton's
    /// method alone (`shader_math::newton_finds_every_crossing`; WATER_NEWTON_ONLY).
    pub fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        effects: &Effects,
        record_photons: bool,
        path: PhotonPath,
        newton_crossing: bool,
    ) -> Result<Self> {
        let (grid, subdivision, estimator) =
            (effects.caustic_grid, effects.caustic_subdivision, effects.caustic_estimator);
        let triangles = estimator == CausticEstimator::Triangles;
        if estimator.geometry_shader_only() && path != PhotonPath::GeometryShader {
            return Err(Error::InvalidParameter {
                name: "caustic_estimator",
                message: format!(
                    "\"{}\" needs the geometry-shader photon path (asked: {})",
                    estimator.name(),
                    path.name()
                ),
            });
        }
        let (min, max) = (estimator.min_subdivision(), estimator.max_subdivision());
        if subdivision < min || subdivision > max {
            return Err(Error::InvalidParameter {
                name: "caustic_subdivision",
                message: format!(
                    "{subdivision} is outside {min}..={max} for the {} estimator (its geometry shader's output limit, and the neighbours its footprints need)",
                    estimator.name()
                ),
            });
        }
        if path == PhotonPath::Compute {
            require_float_atomics(device)?;
        }
        // Recording, the triangles' photons go through the points' recording variant.
        let refines = effects.caustic_refinement && triangles && !record_photons;
        if refines && !device.has_pipeline_stores() {
            return Err(Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["vertexPipelineStoresAndAtomics (effects.caustic_refinement)"],
            });
        }
        let photons = (grid as u64 * subdivision as u64).pow(2);
        // Each path binds what its shaders read besides the frame's textures.
        let mut bindings = BINDINGS.to_vec();
        match (path, record_photons) {
            _ if refines => bindings.push((b::REFINED_CELLS, Binding::Storage)),
            (_, true) => bindings.push((b::PHOTON_DEBUG, Binding::Storage)),
            (PhotonPath::Compute, _) => bindings.push((b::PHOTON_ACCUMULATION, Binding::Storage)),
            (PhotonPath::SplatFloor, _) => bindings.push((b::SPLAT_RECORDS, Binding::Storage)),
            _ => {}
        }
        let sets = DescriptorSets::new(device, "caustics", &bindings, PHOTON_SETS as u32)?;
        let photon_records =
            record_photons.then(|| PhotonRecords::new(device, "caustic photon records", photons, path)).transpose()?;
        require_accumulation_format(device, "R32G32B32A32_SFLOAT with blending and linear filtering (caustic target)")?;
        // The points (caustics.frag) test their visibility with the depth test; the compute
        // path and the triangles test in their shaders.
        let draws_triangles = triangles && !record_photons;
        let draws_points = path != PhotonPath::Compute && !(path == PhotonPath::GeometryShader && draws_triangles);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let target =
            ColorTarget::with_optional_depth(device, "caustics", extent, ACCUMULATION_FORMAT, read, draws_points)?;
        // PHOTON_WARP (photon_cast.glsl): the cast evaluates the view's warp only where the
        // scene spreads its photons for the view; WATER_NEWTON_ONLY: it compiles only the
        // water search its rays take.
        let warps = effects.caustic_photon_density == PhotonSpread::View;
        let specialization = [(0, subdivision), (1, warps as u32), (2, newton_crossing as u32)];
        // The refinement's second draw: the same, with REFINED_DRAW (3) on.
        let [sub, warp, newton] = specialization;
        let refined_specialization = [sub, warp, newton, (3, 1)];
        let set_layouts = [sets.layout];
        let compute = |name: &str, shader: &str| {
            shaders::compute_pipeline(
                device,
                &ComputePipelineDesc {
                    name,
                    shader,
                    specialization: &specialization,
                    push_constant_bytes: 4,
                    set_layouts: &set_layouts,
                },
            )
        };
        let splat_attributes = [
            (0, vk::Format::R32G32B32A32_SFLOAT, 0),
            (1, vk::Format::R32G32B32A32_SFLOAT, 16),
            (2, vk::Format::R32G32B32A32_SFLOAT, 32),
        ];
        let points = |vertex: &'static str, geometry: Option<&'static str>| GraphicsPipelineDesc {
            geometry,
            topology: vk::PrimitiveTopology::POINT_LIST,
            blend: Blend::Additive,
            depth_test: draws_points,
            specialization: &specialization,
            push_constant_bytes: 4,
            set_layouts: &set_layouts,
            ..GraphicsPipelineDesc::new("caustics", vertex, "caustics.frag", target.render_pass.raw)
        };
        // The triangles' draws: one invocation per coarse cell, their own fragment shader.
        let triangle_pipeline = |name, geometry, specialization: &[(u32, u32)]| {
            shaders::graphics_pipeline(
                device,
                &GraphicsPipelineDesc {
                    name,
                    fragment: "caustics_triangles.frag",
                    specialization,
                    ..points("photon_grid.vert", Some(geometry))
                },
            )
        };
        let (pipeline, accumulation, splat_floor) = match path {
            // Recording, the triangles' photons go through the points' recording variant,
            // which numbers them over the triangles' grid (caustics.geom, PHOTON_DEBUG): the
            // flux budget counts the photons the triangles cast.
            PhotonPath::GeometryShader if triangles && !record_photons => {
                let geometry = if refines { "caustics_triangles_refined.geom" } else { "caustics_triangles.geom" };
                (triangle_pipeline("caustics triangles", geometry, &specialization)?, None, None)
            }
            PhotonPath::GeometryShader => {
                // Recording, the footprint points record which of them were clamped.
                // Recording goes without the receiver test, which changes no photon's record.
                let footprint = estimator == CausticEstimator::Footprint;
                let receiver_test = footprint && effects.caustic_receiver_test && !record_photons;
                let geometry = match (footprint, record_photons) {
                    _ if receiver_test => "caustics_footprint_receiver.geom",
                    (true, true) => "caustics_footprint_debug.geom",
                    (true, false) => "caustics_footprint.geom",
                    (false, true) => "caustics_debug.geom",
                    (false, false) => "caustics.geom",
                };
                // The footprint points spread each photon's light by its hat (caustics.frag).
                let fragment = match footprint {
                    _ if receiver_test => "caustics_footprint_receiver.frag",
                    true => "caustics_footprint.frag",
                    false => "caustics.frag",
                };
                let desc = GraphicsPipelineDesc { fragment, ..points("photon_grid.vert", Some(geometry)) };
                (shaders::graphics_pipeline(device, &desc)?, None, None)
            }
            PhotonPath::VertexOnly => {
                (shaders::graphics_pipeline(device, &points("caustics_vertex.vert", None))?, None, None)
            }
            PhotonPath::Compute => {
                let accumulation = AtomicAccumulation::new(device, "caustics", &target)?;
                (compute("caustics compute", "caustics.comp")?, Some(accumulation), None)
            }
            PhotonPath::SplatFloor => {
                let records = Buffer::new(
                    device,
                    "caustic splat records",
                    photons * SPLAT_RECORD_BYTES,
                    vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::VERTEX_BUFFER,
                    gpu_allocator::MemoryLocation::GpuOnly,
                )?;
                let draw = shaders::graphics_pipeline(
                    device,
                    &GraphicsPipelineDesc {
                        vertex_stride: SPLAT_RECORD_BYTES as u32,
                        vertex_attributes: &splat_attributes,
                        ..points("splat_floor.vert", None)
                    },
                )?;
                let cast = compute("caustic splat recording", "caustics_record.comp")?;
                (draw, None, Some(SplatFloor { records, cast, recorded: Cell::new(false) }))
            }
        };
        let refinement = refines
            .then(|| -> Result<Refinement> {
                let size = INDIRECT_COMMAND_BYTES + refined_cells_capacity(grid, subdivision) * REFINED_CELL_BYTES;
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::INDIRECT_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_DST;
                let cells = (0..FRAMES_IN_FLIGHT)
                    .map(|frame| {
                        let name = format!("caustic cells refined, frame {frame}");
                        Buffer::new(device, &name, size, usage, gpu_allocator::MemoryLocation::GpuOnly)
                    })
                    .collect::<Result<Vec<_>>>()?;
                for set in 0..PHOTON_SETS {
                    let buffer = &cells[set % FRAMES_IN_FLIGHT];
                    let resource = Resource::Storage { buffer: buffer.raw, range: buffer.size };
                    sets.write_at(set, vec![(b::REFINED_CELLS as usize, resource)]);
                }
                let draw = triangle_pipeline(
                    "caustics triangles refined",
                    "caustics_triangles_refined.geom",
                    &refined_specialization,
                )?;
                let kept = Attachment::new(&target.image, Load::Keep { layout: read }, Store::Keep, read);
                let render_pass = RenderPass::new(device, "caustics refined", &[kept], None)?;
                Ok(Refinement { cells, draw, render_pass })
            })
            .transpose()?;
        // The buffers only this pass knows, in every frame's set.
        let own: Option<Resource> = match (&photon_records, &accumulation, &splat_floor) {
            (Some(r), _, _) => Some(r.resource()),
            (_, Some(a), _) => Some(a.resource()),
            (_, _, Some(f)) => Some(Resource::Storage { buffer: f.records.raw, range: f.records.size }),
            _ => None,
        };
        if let (Some(resource), Some(binding)) = (own, bindings.get(BINDINGS.len())) {
            for frame in 0..PHOTON_SETS {
                sets.write_at(frame, vec![(binding.0 as usize, resource)]);
            }
        }
        let which = match estimator {
            CausticEstimator::Footprint => VisibilityTarget::LitCaustics,
            _ => VisibilityTarget::Caustics,
        };
        let visibility =
            draws_points.then(|| VisibilityDepth::new(device, which, &target, &set_layouts)).transpose()?;
        Ok(Self {
            path,
            estimator,
            draws_triangles,
            visibility,
            grid,
            subdivision,
            photon_records,
            pipeline,
            accumulation,
            splat_floor,
            refinement,
            target,
            sets,
            device: device.clone(),
        })
    }

    fn photons(&self) -> u64 {
        (self.grid as u64 * self.subdivision as u64).pow(2)
    }

    /// `set_index`: the frame in flight and the depth the photons are tested against
    /// (`passes::photon_set_index`).
    pub fn record(&self, cmd: vk::CommandBuffer, set_index: usize) {
        let dev = &self.device;
        let set = Some(self.sets.sets[set_index]);
        let grid = self.grid.to_ne_bytes();
        if let Some(acc) = &self.accumulation {
            acc.record_clear(cmd);
            self.pipeline.bind(cmd, set);
            self.pipeline.push(cmd, &grid);
            dispatch_per_photon(dev, cmd, self.photons());
            acc.record_resolve(cmd, &self.target);
            return;
        }
        if let Some(floor) = &self.splat_floor {
            if !floor.recorded.replace(true) {
                floor.cast.bind(cmd, set);
                floor.cast.push(cmd, &grid);
                dispatch_per_photon(dev, cmd, self.photons());
                let to_vertices = [vk::MemoryBarrier2::default()
                    .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                    .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                    .dst_stage_mask(vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT)
                    .dst_access_mask(vk::AccessFlags2::VERTEX_ATTRIBUTE_READ)];
                unsafe {
                    dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_vertices))
                };
            }
        }
        if let Some(refinement) = &self.refinement {
            refinement.record_reset(dev, cmd, set_index);
        }
        self.target.render_pass.begin(cmd);
        if let Some(visibility) = &self.visibility {
            visibility.record(dev, cmd, set);
        }
        self.pipeline.bind(cmd, set);
        self.pipeline.push(cmd, &grid);
        let vertices = match self.path {
            PhotonPath::GeometryShader if self.draws_triangles => mesh_invocations(self.grid),
            PhotonPath::GeometryShader => self.grid * self.grid,
            _ => self.photons() as u32,
        };
        if let Some(floor) = &self.splat_floor {
            unsafe { dev.raw.cmd_bind_vertex_buffers(cmd, 0, &[floor.records.raw], &[0]) };
        }
        unsafe { dev.raw.cmd_draw(cmd, vertices, 1, 0, 0) };
        self.target.render_pass.end(cmd);
        if let Some(refinement) = &self.refinement {
            refinement.record_draw(dev, cmd, set, set_index, &grid);
        }
        if let Some(records) = &self.photon_records {
            records.record_host_barrier(dev, cmd);
        }
    }

    /// The recorded photons, as (hit, landed) and (surface, flux) per photon in grid order.
    /// Only meaningful after the frame that recorded them has finished.
    pub fn read_photon_records(&self) -> Option<Vec<[f32; 4]>> {
        self.photon_records.as_ref()?.read()
    }
}

impl Refinement {
    /// Before the grid's draw: no cells handed on yet, one instance of the second draw.
    fn record_reset(&self, dev: &Device, cmd: vk::CommandBuffer, set_index: usize) {
        let cells = &self.cells[set_index % FRAMES_IN_FLIGHT];
        let command: [u32; 4] = [0, 1, 0, 0];
        unsafe { dev.raw.cmd_update_buffer(cmd, cells.raw, 0, bytemuck::cast_slice(&command)) };
        let to_grid_draw = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::GEOMETRY_SHADER)
            .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE)];
        unsafe { dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_grid_draw)) };
    }

    /// After the grid's draw: the cells it handed on, cast finer into the same target.
    fn record_draw(
        &self,
        dev: &Device,
        cmd: vk::CommandBuffer,
        set: Option<vk::DescriptorSet>,
        set_index: usize,
        grid: &[u8],
    ) {
        let cells = &self.cells[set_index % FRAMES_IN_FLIGHT];
        let to_second_draw = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::GEOMETRY_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::GEOMETRY_SHADER)
            .dst_access_mask(vk::AccessFlags2::INDIRECT_COMMAND_READ | vk::AccessFlags2::SHADER_STORAGE_READ)];
        unsafe { dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_second_draw)) };
        self.render_pass.begin(cmd);
        self.draw.bind(cmd, set);
        self.draw.push(cmd, grid);
        unsafe { dev.raw.cmd_draw_indirect(cmd, cells.raw, 0, 1, INDIRECT_COMMAND_BYTES as u32) };
        self.render_pass.end(cmd);
    }
}
