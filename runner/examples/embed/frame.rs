//! One frame recorded: the cube's pass, then the grass into the same images.

use anyhow::Result;
use ash::vk;
use glam::Vec3;
use runner::embed::{self, Frame, GrassField, Targets};
use shared::example::cube::{CUBE_VERTICES, CubePush};

use super::cube::*;
use super::gpu::*;
use super::stage::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// Records one frame into `cmd`: the program's own pass (the cube, clearing colour
/// and depth), then the grass into the same images. The colour image is left in
/// COLOR_ATTACHMENT_OPTIMAL for the caller to move on.
#[allow(clippy::too_many_arguments)]
pub(crate) fn record_frame(
    gpu: &Gpu,
    cube: &Cube,
    field: &mut GrassField,
    stage: &Stage,
    cmd: vk::CommandBuffer,
    color: (vk::Image, vk::ImageView),
    depth: &OwnedImage,
    extent: vk::Extent2D,
) -> Result<()> {
    let device = &gpu.device;
    let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
    let depth_rw = A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE;
    let aspect = vk::ImageAspectFlags::COLOR;
    transition(
        device,
        cmd,
        (color.0, aspect),
        (L::UNDEFINED, L::COLOR_ATTACHMENT_OPTIMAL),
        (S::COLOR_ATTACHMENT_OUTPUT, A::NONE),
        color_out,
    );
    transition(
        device,
        cmd,
        (depth.image, depth.aspect),
        (L::UNDEFINED, L::DEPTH_ATTACHMENT_OPTIMAL),
        (tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
        (tests, depth_rw),
    );
    let color_attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(color.1)
        .image_layout(L::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue { float32: SKY },
        })];
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(depth.view)
        .image_layout(L::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color_attachment)
        .depth_attachment(&depth_attachment);
    let time = field.time();
    let size = (extent.width, extent.height);
    let (view, proj) = stage.camera(size);
    let model = stage.cube_model(time);
    let push = CubePush {
        model_view_proj: proj * view * model,
        model,
        color: CUBE_COLOR.extend(1.0),
        light: Vec3::new(0.4, 0.8, 0.3).normalize().extend(0.3),
    };
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, cube.pipeline);
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        device.cmd_push_constants(cmd, cube.layout, stages, 0, bytemuck::bytes_of(&push));
        device.cmd_draw(cmd, CUBE_VERTICES, 1, 0, 0);
        device.cmd_end_rendering(cmd);
    }
    // The grass, over the cube's picture and depth; the cube (its bounding sphere)
    // pushes the blades aside.
    let frame = Frame {
        targets: Targets {
            color: color.1,
            depth: depth.view,
            extent,
        },
        camera: embed::viewpoint(view, proj, extent.height),
        seconds: FRAME_SECONDS,
        colliders: &[stage.cube_collider(field.time())],
    };
    field.record(cmd, &frame)
}
