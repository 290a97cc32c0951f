//! Shader module, pipeline layout, compute and graphics pipelines.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;
use std::ffi::CString;
use std::sync::Arc;

/// The shader modules, one per entry point (GPU-assisted validation refuses a module
/// of several stages), each found by its entry point's name.
pub struct ShaderModules {
    ctx: Arc<Context>,
    /// (entry point, its module).
    modules: Vec<(&'static str, vk::ShaderModule)>,
}

impl ShaderModules {
    /// Creates a module for each (entry point, SPIR-V bytes).
    pub fn new(ctx: &Arc<Context>, spirv: &[(&'static str, &[u8])]) -> Result<Self> {
        let mut set = Self {
            ctx: ctx.clone(),
            modules: Vec::with_capacity(spirv.len()),
        };
        for &(entry, bytes) in spirv {
            let words = ash::util::read_spv(&mut std::io::Cursor::new(bytes))
                .with_context(|| format!("read SPIR-V of {entry}"))?;
            let info = vk::ShaderModuleCreateInfo::default().code(&words);
            let module = unsafe { ctx.device.create_shader_module(&info, None) }
                .with_context(|| format!("create shader module {entry}"))?;
            set.modules.push((entry, module));
        }
        Ok(set)
    }

    /// The module of `entry`.
    pub fn get(&self, entry: &str) -> Result<vk::ShaderModule> {
        self.modules
            .iter()
            .find(|(name, _)| *name == entry)
            .map(|(_, module)| *module)
            .with_context(|| format!("no shader module has the entry point {entry}"))
    }
}

impl Drop for ShaderModules {
    fn drop(&mut self) {
        for (_, module) in &self.modules {
            unsafe { self.ctx.device.destroy_shader_module(*module, None) };
        }
    }
}

/// A pipeline layout: one descriptor set and at most one push-constant range.
pub struct PipelineLayout {
    ctx: Arc<Context>,
    /// The layout.
    pub layout: vk::PipelineLayout,
}

impl PipelineLayout {
    /// A layout of `set` and `push` (stages, size in bytes; size 0 for none).
    pub fn new(
        ctx: &Arc<Context>,
        set: vk::DescriptorSetLayout,
        push: (vk::ShaderStageFlags, u32),
    ) -> Result<Self> {
        Self::of_sets(ctx, &[set], push)
    }

    /// A layout of `sets` (set k the k-th) and `push`, as [`Self::new`].
    pub fn of_sets(
        ctx: &Arc<Context>,
        sets: &[vk::DescriptorSetLayout],
        push: (vk::ShaderStageFlags, u32),
    ) -> Result<Self> {
        let ranges = [vk::PushConstantRange {
            stage_flags: push.0,
            offset: 0,
            size: push.1,
        }];
        let ranges: &[_] = if push.1 == 0 { &[] } else { &ranges };
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(sets)
            .push_constant_ranges(ranges);
        let layout = unsafe { ctx.device.create_pipeline_layout(&info, None) }
            .context("create pipeline layout")?;
        Ok(Self {
            ctx: ctx.clone(),
            layout,
        })
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_pipeline_layout(self.layout, None) };
    }
}

/// A compute or graphics pipeline, destroyed on drop.
pub struct Pipeline {
    ctx: Arc<Context>,
    /// The pipeline.
    pub pipeline: vk::Pipeline,
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_pipeline(self.pipeline, None) };
    }
}

impl Pipeline {
    /// The compute pipeline of `entry` in `module`.
    pub fn compute(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        module: &ShaderModules,
        entry: &str,
    ) -> Result<Self> {
        Self::compute_specialised(ctx, layout, module, entry, &[])
    }

    /// A compute pipeline with the 32-bit specialisation constants `constants`
    /// (constant id, value).
    pub fn compute_specialised(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        module: &ShaderModules,
        entry: &str,
        constants: &[(u32, u32)],
    ) -> Result<Self> {
        log::debug!("compute pipeline {entry} {constants:?}");
        let name = CString::new(entry)?;
        let size = std::mem::size_of::<u32>();
        let entries: Vec<vk::SpecializationMapEntry> = (0..constants.len())
            .map(|i| {
                vk::SpecializationMapEntry::default()
                    .constant_id(constants[i].0)
                    .offset((i * size) as u32)
                    .size(size)
            })
            .collect();
        let data: Vec<u8> = constants
            .iter()
            .flat_map(|(_, value)| value.to_ne_bytes())
            .collect();
        let specialisation = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(&data);
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.get(entry)?)
            .name(&name);
        if !constants.is_empty() {
            stage = stage.specialization_info(&specialisation);
        }
        let mut info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.layout);
        if ctx.executables.is_some() {
            info = info.flags(vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR);
        }
        let pipeline = unsafe {
            ctx.device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
                .map_err(|(_, e)| e)
        }
        .with_context(|| format!("create compute pipeline {entry}"))?[0];
        if let Some(executables) = &ctx.executables {
            log_statistics(executables, pipeline, entry, constants);
        }
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
        })
    }

    /// A graphics pipeline as `desc` describes it.
    pub fn graphics(ctx: &Arc<Context>, desc: &GraphicsDesc) -> Result<Self> {
        let names: Vec<CString> = desc
            .stages
            .iter()
            .map(|(_, e)| CString::new(*e))
            .collect::<Result<_, _>>()?;
        let stages: Vec<_> = desc
            .stages
            .iter()
            .zip(&names)
            .map(|((stage, entry), name)| {
                Ok(vk::PipelineShaderStageCreateInfo::default()
                    .stage(*stage)
                    .module(desc.module.get(entry)?)
                    .name(name))
            })
            .collect::<Result<_>>()?;
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(desc.vertex_bindings)
            .vertex_attribute_descriptions(desc.vertex_attributes);
        let topology = if desc.patch_control_points > 0 {
            vk::PrimitiveTopology::PATCH_LIST
        } else {
            vk::PrimitiveTopology::TRIANGLE_LIST
        };
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
        let tessellation = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(desc.patch_control_points);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(desc.polygon_mode)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
        let has_depth = desc.depth_format != vk::Format::UNDEFINED;
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(has_depth)
            .depth_write_enable(has_depth)
            .depth_compare_op(desc.depth_compare);
        let mut attachment = vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA);
        if desc.premultiplied_blend {
            use vk::BlendFactor as F;
            attachment = attachment
                .blend_enable(true)
                .src_color_blend_factor(F::ONE)
                .dst_color_blend_factor(F::ONE_MINUS_SRC_ALPHA)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(F::ONE)
                .dst_alpha_blend_factor(F::ONE_MINUS_SRC_ALPHA)
                .alpha_blend_op(vk::BlendOp::ADD);
        }
        let has_color = desc.color_format != vk::Format::UNDEFINED;
        let mut blend = vec![];
        let mut color_formats = vec![];
        if has_color {
            blend.push(attachment);
            color_formats.push(desc.color_format);
        }
        if let Some((format, written)) = desc.second_color {
            let mask = if written {
                vk::ColorComponentFlags::RGBA
            } else {
                vk::ColorComponentFlags::empty()
            };
            blend.push(vk::PipelineColorBlendAttachmentState::default().color_write_mask(mask));
            color_formats.push(format);
        }
        let color_blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(desc.depth_format);
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&color_blend)
            .dynamic_state(&dynamic)
            .layout(desc.layout.layout)
            .push_next(&mut rendering);
        if desc.patch_control_points > 0 {
            info = info.tessellation_state(&tessellation);
        }
        // Mesh pipelines have no vertex input or input assembly.
        let mesh = desc
            .stages
            .iter()
            .any(|(stage, _)| stage.contains(vk::ShaderStageFlags::MESH_EXT));
        if !mesh {
            info = info
                .vertex_input_state(&vertex_input)
                .input_assembly_state(&input_assembly);
        }
        let pipeline = unsafe {
            ctx.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
                .map_err(|(_, e)| e)
        }
        .with_context(|| format!("create graphics pipeline {}", desc.stages[0].1))?[0];
        Ok(Self {
            ctx: ctx.clone(),
            pipeline,
        })
    }
}

/// What a graphics pipeline is made of.
#[derive(Copy, Clone)]
pub struct GraphicsDesc<'a> {
    /// The module with every entry point.
    pub module: &'a ShaderModules,
    /// (stage, entry point name), in pipeline order.
    pub stages: &'a [(vk::ShaderStageFlags, &'a str)],
    /// The layout.
    pub layout: &'a PipelineLayout,
    /// Vertex buffer bindings.
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    /// Vertex attributes.
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// Control points per patch; 0 for triangle lists.
    pub patch_control_points: u32,
    /// Fill or wireframe.
    pub polygon_mode: vk::PolygonMode,
    /// Colour attachment format; `UNDEFINED` for none (a depth-only pass).
    pub color_format: vk::Format,
    /// A second colour attachment after it, of this format, written by the
    /// fragment stage (`true`) or left as it is (the draw's motion target).
    pub second_color: Option<(vk::Format, bool)>,
    /// Depth attachment format (tested and written); `UNDEFINED` for none.
    pub depth_format: vk::Format,
    /// The depth test: `LESS_OR_EQUAL` (depth 0 near, 1 far), or `GREATER_OR_EQUAL`
    /// into a caller's reversed depth (1 near, 0 far, as Bevy's).
    pub depth_compare: vk::CompareOp,
    /// Blend premultiplied-alpha colour over the target instead of replacing it.
    pub premultiplied_blend: bool,
    /// Samples per pixel of the targets.
    pub samples: vk::SampleCountFlags,
}

impl<'a> GraphicsDesc<'a> {
    /// An opaque, depth-tested triangle-list pipeline of `stages` over one buffer of
    /// `vec4` vertex attributes; change fields for the rest.
    pub fn opaque(
        module: &'a ShaderModules,
        stages: &'a [(vk::ShaderStageFlags, &'a str)],
        layout: &'a PipelineLayout,
        vertex_input: &'a VertexInput,
        color_format: vk::Format,
        depth_format: vk::Format,
    ) -> Self {
        Self {
            vertex_bindings: &vertex_input.0,
            vertex_attributes: &vertex_input.1,
            patch_control_points: 0,
            ..Self::patches(module, stages, layout, color_format, depth_format)
        }
    }

    /// An opaque, depth-tested pipeline of one-control-point patches with no vertex
    /// buffer (the vertex stage works from its index); change fields for the rest.
    pub fn patches(
        module: &'a ShaderModules,
        stages: &'a [(vk::ShaderStageFlags, &'a str)],
        layout: &'a PipelineLayout,
        color_format: vk::Format,
        depth_format: vk::Format,
    ) -> Self {
        Self {
            module,
            stages,
            layout,
            vertex_bindings: &[],
            vertex_attributes: &[],
            patch_control_points: 1,
            polygon_mode: vk::PolygonMode::FILL,
            color_format,
            second_color: None,
            depth_format,
            depth_compare: vk::CompareOp::LESS_OR_EQUAL,
            premultiplied_blend: false,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }
}

/// Vertex buffer bindings and attributes.
pub type VertexInput = (
    [vk::VertexInputBindingDescription; 1],
    Vec<vk::VertexInputAttributeDescription>,
);

/// Vertex input of one buffer of `T`, read per vertex as consecutive `vec4`
/// attributes at locations 0, 1, … (`T` is a whole number of `vec4`).
pub fn vec4_vertex_input<T>() -> VertexInput {
    let stride = size_of::<T>() as u32;
    let binding = vk::VertexInputBindingDescription {
        binding: 0,
        stride,
        input_rate: vk::VertexInputRate::VERTEX,
    };
    let attributes = (0..stride / 16)
        .map(|i| vk::VertexInputAttributeDescription {
            location: i,
            binding: 0,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset: i * 16,
        })
        .collect();
    ([binding], attributes)
}

/// Logs what the driver tells of `pipeline`'s executables
/// (`VK_KHR_pipeline_executable_properties`: registers, shared memory, instructions,
/// spills, as its driver names them), for `GRASS_PIPELINE_STATS`.
fn log_statistics(
    executables: &ash::khr::pipeline_executable_properties::Device,
    pipeline: vk::Pipeline,
    entry: &str,
    constants: &[(u32, u32)],
) {
    let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
    let Ok(properties) = (unsafe { executables.get_pipeline_executable_properties(&info) }) else {
        return;
    };
    for index in 0..properties.len() as u32 {
        let at = vk::PipelineExecutableInfoKHR::default()
            .pipeline(pipeline)
            .executable_index(index);
        let Ok(statistics) = (unsafe { executables.get_pipeline_executable_statistics(&at) })
        else {
            continue;
        };
        let values: Vec<String> = statistics
            .iter()
            .map(|s| {
                let name = s
                    .name_as_c_str()
                    .map(|n| n.to_string_lossy())
                    .unwrap_or_default();
                let value = unsafe {
                    match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => s.value.b32.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64.to_string(),
                        _ => s.value.f64.to_string(),
                    }
                };
                format!("{name} {value}")
            })
            .collect();
        log::info!("pipeline {entry} {constants:?}: {}", values.join(", "));
    }
}
