//! The program's own object: a spinning cube drawn from its vertex index
//! (`shared::example::cube`), also a collider for the grass.

use anyhow::{Context as _, Result};
use ash::vk;
use runner::embed::{self};
use shared::example::cube::CubePush;

/// The program's own pipeline: the cube, from its vertex index.
pub struct Cube {
    pub(crate) pipeline: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
    pub(crate) device: ash::Device,
}

impl Cube {
    /// The pipeline for `color_format` images over [`embed::DEPTH_FORMAT`] depth.
    pub(crate) fn new(device: &ash::Device, color_format: vk::Format) -> Result<Self> {
        use vk::ShaderStageFlags as St;
        let stages_used = St::VERTEX | St::FRAGMENT;
        let push = [vk::PushConstantRange::default()
            .stage_flags(stages_used)
            .size(size_of::<CubePush>() as u32)];
        let info = vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push);
        let layout = unsafe { device.create_pipeline_layout(&info, None)? };
        // rust-gpu SPIR-V from `shaders-rs`, one module per entry point (`shared::cube`).
        let mut modules = Vec::new();
        for (stage, entry) in [
            (St::VERTEX, runner::shaders::CUBE_VS),
            (St::FRAGMENT, runner::shaders::CUBE_FS),
        ] {
            let bytes = runner::shaders::module(entry).context("cube shader")?;
            let words = ash::util::read_spv(&mut std::io::Cursor::new(bytes))?;
            let info = vk::ShaderModuleCreateInfo::default().code(&words);
            let module = unsafe { device.create_shader_module(&info, None)? };
            modules.push((stage, module, entry));
        }
        let names: Vec<_> = modules
            .iter()
            .map(|(_, _, entry)| std::ffi::CString::new(*entry).map_err(anyhow::Error::from))
            .collect::<Result<_>>()?;
        let stages: Vec<_> = modules
            .iter()
            .zip(&names)
            .map(|((stage, module, _), name)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(*stage)
                    .module(*module)
                    .name(name)
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
        let blend = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let formats = [color_format];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(embed::DEPTH_FORMAT);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        let made =
            unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        for (_, module, _) in &modules {
            unsafe { device.destroy_shader_module(*module, None) };
        }
        let pipeline = made.map_err(|(_, e)| e).context("cube pipeline")?[0];
        Ok(Self {
            pipeline,
            layout,
            device: device.clone(),
        })
    }
}

impl Drop for Cube {
    fn drop(&mut self) {
        unsafe {
            self.device.destroy_pipeline(self.pipeline, None);
            self.device.destroy_pipeline_layout(self.layout, None);
        }
    }
}
