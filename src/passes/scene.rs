//! Scene pass (method step 3): the scene from the camera into off-screen colour (ambient and
//! above-water sun, attenuated by the water on the way to the camera), the factor caustics
//! are multiplied by in compose (albedo/π × transmittance), and depth, which caustics and
//! godrays are tested against when the camera is under the water. Drawn in order: the
//! background (sky or the water's glow, per pixel), the meshes, and the water surface as a
//! displaced grid, shaded from whichever side each pixel sees it (`glsl/surface/water.frag`).

use crate::error::Result;
use crate::passes::mesh::{GpuMeshes, MeshVertex, MESH_ATTRIBUTES};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, Load, RenderPass, Store};
use ash::vk;
use std::sync::Arc;

/// Cells per axis of the water-surface grid.
pub const WATER_GRID_CELLS: u32 = 128;

/// Format of the scene's colour targets (this pass's and the refraction and reflection
/// passes'): radiance in W/(m²·sr), well beyond 8 bits' range.
pub const COLOR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// Which view a mesh draw renders (`glsl/shared/view.glsl`, specialization constant 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Camera = 0,
    Refraction = 1,
    Reflection = 2,
}

/// The meshes' pipeline for one view: opaque, depth-tested, into colour and (`attachments`
/// = 2) albedo×transmittance, or colour only (1, reflection.frag).
pub fn mesh_pipeline(
    device: &Arc<Device>,
    name: &str,
    view: View,
    attachments: u32,
    set_layout: vk::DescriptorSetLayout,
    render_pass: vk::RenderPass,
) -> Result<Pipeline> {
    shaders::graphics_pipeline(
        device,
        &GraphicsPipelineDesc {
            color_attachments: attachments,
            depth_test: true,
            depth_write: true,
            set_layouts: &[set_layout],
            specialization: &[(0, view as u32)],
            vertex_stride: std::mem::size_of::<MeshVertex>() as u32,
            vertex_attributes: &MESH_ATTRIBUTES,
            ..GraphicsPipelineDesc::new(
                name,
                "mesh.vert",
                if attachments == 2 { "scene.frag" } else { "reflection.frag" },
                render_pass,
            )
        },
    )
}

/// A camera view's targets and their render pass: radiance, albedo/π (× transmittance in
/// the scene pass), depth, all at the camera's extent and left sampled (the scene and
/// refraction passes).
pub struct CameraTargets {
    pub color: Image,
    pub albedo: Image,
    pub depth: Image,
    pub render_pass: RenderPass,
}

impl CameraTargets {
    /// `pass`: the pass's name (prefixes the images'); `albedo_name`: the second target's.
    pub fn new(
        device: &Arc<Device>,
        pass: &str,
        albedo_name: &str,
        extent: vk::Extent2D,
        extra_usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        // TRANSFER_DST: the frame may clear them before their first pass (upload::clear_to_sampled).
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_DST
            | extra_usage;
        let color = Image::new(device, &format!("{pass} colour"), extent, COLOR_FORMAT, usage)?;
        let albedo = Image::new(device, &format!("{pass} {albedo_name}"), extent, COLOR_FORMAT, usage)?;
        let depth = Image::new(
            device,
            &format!("{pass} depth"),
            extent,
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST,
        )?;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let render_pass = RenderPass::new(
            device,
            pass,
            &[
                Attachment::new(&color, Load::Clear([0.0; 4]), Store::Keep, read),
                Attachment::new(&albedo, Load::Clear([0.0; 4]), Store::Keep, read),
            ],
            Some(&Attachment::new(&depth, Load::Clear([1.0; 4]), Store::Keep, read)),
        )?;
        Ok(Self { color, albedo, depth, render_pass })
    }
}

/// What the frame gives the water surface to shade it from above.
#[derive(Clone, Copy, Debug, Default)]
pub struct SurfaceInputs {
    /// The refraction and reflection passes exist.
    pub through_surface: bool,
    /// Their caustic / godray buffers, refracted with the floor.
    pub caustics: bool,
    pub godrays: bool,
}

impl SurfaceInputs {
    fn water_fragment(self) -> &'static str {
        match (self.through_surface, self.caustics, self.godrays) {
            (false, _, _) => "water.frag",
            (true, false, false) => "water_above.frag",
            (true, true, false) => "water_above_caustics.frag",
            (true, false, true) => "water_above_godrays.frag",
            (true, true, true) => "water_above_caustics_godrays.frag",
        }
    }

    /// What the pass's shaders read: the noise for the surface's shape, and what the surface
    /// refracts and reflects when seen from above.
    pub fn bindings(self) -> Vec<(u32, Binding)> {
        let mut v =
            vec![(b::UNIFORMS, Binding::Storage), (b::FRAME_VALUES, Binding::Uniform), (b::NOISE, Binding::Texture)];
        if self.through_surface {
            for binding in [b::REFRACTION_COLOR, b::REFRACTION_ALBEDO, b::REFRACTION_DEPTH, b::REFLECTION_COLOR] {
                v.push((binding, Binding::Texture));
            }
            if self.caustics {
                v.push((b::CAUSTICS, Binding::Texture));
            }
            if self.godrays {
                v.push((b::GODRAYS, Binding::Texture));
            }
        }
        v
    }
}

/// What the scene pass puts behind the meshes and the surface.
#[derive(Clone, Copy, Debug)]
pub enum Background {
    /// The background shader: per pixel, the sky or the water's glow by where its ray starts.
    Draw,
    /// Every ray starts under the water (the camera's near plane lies under the lowest
    /// trough, `frame::camera_sees_surface_from_above` is false): the target is cleared to the water's glow, which the shader would draw on
    /// every pixel (`shader_math::water_fog_radiance`), and the draw is skipped.
    Uniform([f32; 3]),
}

pub struct ScenePass {
    background_pipeline: Pipeline,
    mesh_pipeline: Pipeline,
    water_pipeline: Pipeline,
    render_pass: RenderPass,
    pub color: Image,
    pub albedo_transmittance: Image,
    pub depth: Image,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl ScenePass {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D, surface: SurfaceInputs) -> Result<Self> {
        let sets = DescriptorSets::new(device, "scene", &surface.bindings(), FRAMES_IN_FLIGHT as u32)?;
        // Every pixel is drawn (the background or its clear covers the target), so the clear
        // values only matter to a broken draw. Read back by the headless renderer.
        let CameraTargets { color, albedo: albedo_transmittance, depth, render_pass } =
            CameraTargets::new(device, "scene", "albedo×transmittance", extent, vk::ImageUsageFlags::TRANSFER_SRC)?;
        let layouts = [sets.layout];
        let background_pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                color_attachments: 2,
                set_layouts: &layouts,
                ..GraphicsPipelineDesc::new("background", "fullscreen.vert", "background.frag", render_pass.raw)
            },
        )?;
        let mesh_pipeline = mesh_pipeline(device, "scene meshes", View::Camera, 2, sets.layout, render_pass.raw)?;
        let water_pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                color_attachments: 2,
                depth_test: true,
                depth_write: true,
                set_layouts: &layouts,
                specialization: &[(0, WATER_GRID_CELLS)],
                ..GraphicsPipelineDesc::new("water surface", "water.vert", surface.water_fragment(), render_pass.raw)
            },
        )?;
        Ok(Self {
            background_pipeline,
            mesh_pipeline,
            water_pipeline,
            render_pass,
            color,
            albedo_transmittance,
            depth,
            sets,
            device: device.clone(),
        })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes, background: Background) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        match background {
            Background::Draw => {
                self.render_pass.begin(cmd);
                // No depth test or write: what follows draws over it.
                self.background_pipeline.bind(cmd, Some(set));
                unsafe { dev.raw.cmd_draw(cmd, 3, 1, 0, 0) };
                // Same set layout: set 0 stays bound across the pipeline changes.
                self.mesh_pipeline.bind(cmd, None);
            }
            Background::Uniform(radiance) => {
                self.render_pass.begin_with_first_clear(cmd, [radiance[0], radiance[1], radiance[2], 0.0]);
                self.mesh_pipeline.bind(cmd, Some(set));
            }
        }
        meshes.draw(dev, cmd);
        self.water_pipeline.bind(cmd, None);
        unsafe { dev.raw.cmd_draw(cmd, 6 * WATER_GRID_CELLS * WATER_GRID_CELLS, 1, 0, 0) };
        self.render_pass.end(cmd);
    }
}
