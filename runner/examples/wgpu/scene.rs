//! The program's own scene, drawn by wgpu (the cube of `shared::example::cube`, its
//! SPIR-V from `shaders-rs` passed through), and one frame: wgpu's pass, then the
//! grass in a command buffer of its own (`runner::embed::wgpu::record`), both
//! submitted together.

use anyhow::{Context as _, Result};
use runner::embed::wgpu::{TextureTarget, record};
use runner::embed::{self, GrassField};
use shared::example::cube::{CUBE_VERTICES, CubePush};
use std::borrow::Cow;

use super::device::Devices;
use super::stage::*;

/// The frame's colour format (written to PNG as it is).
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The frame's depth format: the grass's (`embed::DEPTH_FORMAT`, 0 near, 1 far).
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The cube's wgpu pipeline.
pub struct CubePass {
    pipeline: wgpu::RenderPipeline,
}

impl CubePass {
    /// The pipeline for [`COLOR`] over [`DEPTH`], from the cube's two SPIR-V modules.
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        let module = |entry: &str| -> Result<wgpu::ShaderModule> {
            let bytes = runner::shaders::module(entry).context("cube shader")?;
            let words = ash::util::read_spv(&mut std::io::Cursor::new(bytes))?;
            let desc = wgpu::ShaderModuleDescriptorPassthrough {
                label: Some(entry),
                spirv: Some(Cow::Owned(words)),
                ..Default::default()
            };
            Ok(unsafe { device.create_shader_module_passthrough(desc) })
        };
        let (vs, fs) = (
            module(runner::shaders::CUBE_VS)?,
            module(runner::shaders::CUBE_FS)?,
        );
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("cube"),
            bind_group_layouts: &[],
            immediate_size: size_of::<CubePush>() as u32,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("cube"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &vs,
                entry_point: Some(runner::shaders::CUBE_VS),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &fs,
                entry_point: Some(runner::shaders::CUBE_FS),
                compilation_options: Default::default(),
                targets: &[Some(COLOR.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Ok(Self { pipeline })
    }
}

/// The frame's colour and depth textures.
pub struct Textures {
    pub color: wgpu::Texture,
    pub depth: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

impl Textures {
    /// Both of `(width, height)`; the colour one can be copied out.
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Self {
        let texture = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as U;
        let color = texture("colour", COLOR, U::RENDER_ATTACHMENT | U::COPY_SRC);
        let depth = texture("depth", DEPTH, U::RENDER_ATTACHMENT);
        let (color_view, depth_view) = (
            color.create_view(&Default::default()),
            depth.create_view(&Default::default()),
        );
        Self {
            color,
            depth,
            color_view,
            depth_view,
        }
    }
}

/// Records and submits one frame: wgpu draws the cube (clearing colour and depth),
/// then the grass draws into the same textures, depth-tested against the cube; with
/// `then`, wgpu commands after the grass (a copy out) in the same submission.
pub fn draw_frame(
    devices: &Devices,
    (cube, field, stage): (&CubePass, &mut GrassField, &Stage),
    textures: &Textures,
    then: Option<wgpu::CommandEncoder>,
) -> Result<()> {
    let (device, queue) = (&devices.gpu.device, &devices.gpu.queue);
    let size = textures.color.size();
    let (view, proj) = stage.camera((size.width, size.height));
    let model = stage.cube_model(field.time());
    // wgpu's clip space has y up (it flips its Vulkan viewport); the camera's
    // projection, which the grass takes too, is Vulkan's (y down).
    let y_up = glam::Mat4::from_scale(glam::Vec3::new(1.0, -1.0, 1.0));
    let push = CubePush {
        model_view_proj: y_up * proj * view * model,
        model,
        color: CUBE_COLOR.extend(1.0),
        light: glam::Vec3::new(0.4, 0.8, 0.3).normalize().extend(0.3),
    };
    let mut scene = device.create_command_encoder(&Default::default());
    {
        let [r, g, b, a] = SKY.map(f64::from);
        let mut pass = scene.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("cube"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &textures.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &textures.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&cube.pipeline);
        pass.set_immediates(0, bytemuck::bytes_of(&push));
        pass.draw(0..CUBE_VERTICES, 0..1);
    }
    // The grass, into the same textures, depth-tested against the cube, which
    // pushes the blades aside.
    let gpu = &devices.gpu;
    let targets = (
        TextureTarget {
            texture: &textures.color,
            view: &textures.color_view,
        },
        TextureTarget {
            texture: &textures.depth,
            view: &textures.depth_view,
        },
    );
    let camera = embed::viewpoint(view, proj, size.height);
    let colliders = [stage.cube_collider(field.time())];
    let grass = record(
        gpu,
        &mut scene,
        targets,
        field,
        (camera, FRAME_SECONDS),
        &colliders,
    )?;
    let mut buffers = vec![scene.finish(), grass];
    buffers.extend(then.map(|e| e.finish()));
    queue.submit(buffers);
    Ok(())
}
