//! Caustics pass (method step 5): the photon grid, subdivided by the geometry shader,
//! refracted at the water and intersected with the scene in image space; each photon that
//! lands is splatted as a distance-sized point carrying an irradiance estimate, added into
//! an RGBA16F target a fraction of the output's size (units: docs/units.md).

use crate::error::{Error, Result};
use crate::shader_math::MAX_SUBDIVISION;
use crate::frame::bindings as b;
use crate::vk::buffer::Buffer;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

/// What the caustics shaders read: the water's noise, the light's receiver maps, and the
/// scene's depth for the visibility test.
pub const BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Uniform),
    (b::NOISE, Binding::Texture),
    (b::LIGHT_POSITION, Binding::Texture),
    (b::LIGHT_NORMAL, Binding::Texture),
    (b::SCENE_DEPTH, Binding::Texture),
];

pub const TARGET_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// The debug variant also writes every photon's cast into a host-visible buffer.
pub const DEBUG_BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Uniform),
    (b::NOISE, Binding::Texture),
    (b::LIGHT_POSITION, Binding::Texture),
    (b::LIGHT_NORMAL, Binding::Texture),
    (b::SCENE_DEPTH, Binding::Texture),
    (b::PHOTON_DEBUG, Binding::Storage),
];

/// How photons are generated from the coarse grid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum PhotonPath {
    /// The method's: a geometry shader subdivides each coarse cell into SUBDIVISION² photons.
    #[default]
    GeometryShader,
    /// No amplification stage: one vertex per photon, drawn as points (for comparison).
    VertexOnly,
}

pub struct CausticsPass {
    pub path: PhotonPath,
    pub grid: u32,
    pub subdivision: u32,
    /// With photon recording on: two vec4 per photon, (hit, landed) and (surface, flux).
    pub photon_records: Option<Buffer>,
    pipeline: Pipeline,
    pub target: ColorTarget,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl CausticsPass {
    pub fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        grid: u32,
        subdivision: u32,
        record_photons: bool,
        path: PhotonPath,
    ) -> Result<Self> {
        if record_photons && path != PhotonPath::GeometryShader {
            return Err(Error::InvalidParameter {
                name: "record_photons",
                message: "photon recording is a feature of the geometry-shader path".into(),
            });
        }
        if record_photons && !device.has_pipeline_stores() {
            return Err(Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["vertexPipelineStoresAndAtomics (photon recording)"],
            });
        }
        let bindings = if record_photons { DEBUG_BINDINGS } else { BINDINGS };
        let sets = DescriptorSets::new(device, "caustics", bindings, FRAMES_IN_FLIGHT as u32)?;
        let photon_records = if record_photons {
            let photons = (grid as u64 * subdivision as u64).pow(2);
            Some(Buffer::new(
                device,
                "caustic photon records",
                photons * 32,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                gpu_allocator::MemoryLocation::GpuToCpu,
            )?)
        } else {
            None
        };
        if subdivision == 0 || subdivision > MAX_SUBDIVISION {
            return Err(Error::InvalidParameter {
                name: "caustic_subdivision",
                message: format!("{subdivision} is outside 1..={MAX_SUBDIVISION}"),
            });
        }
        let target = ColorTarget::new(device, "caustics", extent, TARGET_FORMAT, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let vertex = match path {
            PhotonPath::GeometryShader => "photon_grid.vert",
            PhotonPath::VertexOnly => "caustics_vertex.vert",
        };
        let pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                geometry: match (path, record_photons) {
                    (PhotonPath::VertexOnly, _) => None,
                    (PhotonPath::GeometryShader, true) => Some("caustics_debug.geom"),
                    (PhotonPath::GeometryShader, false) => Some("caustics.geom"),
                },
                topology: vk::PrimitiveTopology::POINT_LIST,
                blend: Blend::Additive,
                specialization: &[(0, subdivision)],
                push_constant_bytes: 4,
                set_layouts: &[sets.layout],
                ..GraphicsPipelineDesc::new("caustics", vertex, "caustics.frag", target.render_pass.raw)
            },
        )?;
        Ok(Self { path, grid, subdivision, photon_records, pipeline, target, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize) {
        let dev = &self.device;
        self.target.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[frame_index]));
        self.pipeline.push(cmd, &self.grid.to_ne_bytes());
        let vertices = match self.path {
            PhotonPath::GeometryShader => self.grid * self.grid,
            PhotonPath::VertexOnly => (self.grid * self.subdivision).pow(2),
        };
        unsafe { dev.raw.cmd_draw(cmd, vertices, 1, 0, 0) };
        self.target.render_pass.end(cmd);
        if self.photon_records.is_some() {
            // The records are read by the host once the frame's fence signals.
            let to_host = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::GEOMETRY_SHADER)
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            unsafe { dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host)) };
        }
    }

    /// The recorded photons, as (hit, landed) and (surface, flux) per photon in grid order.
    /// Only meaningful after the frame that recorded them has finished.
    pub fn read_photon_records(&self) -> Option<Vec<[f32; 4]>> {
        let bytes = self.photon_records.as_ref()?.mapped()?;
        let floats: Vec<f32> = bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        Some(floats.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
    }
}
