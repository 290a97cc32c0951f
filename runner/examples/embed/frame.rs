//! Where things stand (the cube over the field, the camera on it) and one frame
//! recorded: the cube's pass, then the grass into the same images.

use anyhow::Result;
use ash::vk;
use glam::camera::rh;
use glam::{Mat4, Vec2, Vec3};
use runner::embed::{self, Frame, GrassField, Targets};
use shared::example::cube::{CUBE_VERTICES, CubePush};

use super::cube::*;
use super::gpu::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// Colour the frame is cleared to: the sky (linear).
pub(crate) const SKY: [f32; 4] = [0.42, 0.62, 0.86, 1.0];
/// Blades in the field.
pub const BLADES: u32 = 20_000;
/// Simulated seconds a frame.
pub(crate) const FRAME_SECONDS: f64 = 1.0 / 60.0;

/// Where things stand: the cube over the middle of the field, spinning, and the
/// camera looking at it.
pub struct Stage {
    /// The cube's centre.
    pub cube: Vec3,
    /// The camera's position.
    pub eye: Vec3,
}

impl Stage {
    /// The stage over `field`'s ground.
    pub fn new(field: &GrassField) -> Self {
        let ground = field.ground_at(0.0, 0.0).unwrap_or(field.bounds().0);
        let cube = ground + Vec3::new(0.0, 1.7, 0.0);
        Self {
            cube,
            eye: cube + Vec3::new(3.0, 3.2, 8.5),
        }
    }

    /// The cube's model matrix at `time` seconds: a quarter turn a second about y,
    /// tilted so three faces show.
    pub fn cube_model(&self, time: f32) -> Mat4 {
        Mat4::from_translation(self.cube)
            * Mat4::from_rotation_y(time * std::f32::consts::FRAC_PI_2)
            * Mat4::from_rotation_x(0.5)
            * Mat4::from_scale(Vec3::splat(CUBE_HALF))
    }

    /// (view, projection) on a `width` × `height` target (Vulkan clip space).
    pub fn camera(&self, (width, height): (u32, u32)) -> (Mat4, Mat4) {
        let view = rh::view::look_at_mat4(self.eye, self.cube, Vec3::Y);
        let aspect = width as f32 / height.max(1) as f32;
        let proj = rh::proj::vulkan::perspective(50f32.to_radians(), aspect, 0.1, 300.0);
        (view, proj)
    }

    /// The cube's 8 corners at `time`, in pixels on a `size` target.
    pub fn cube_corners_px(&self, time: f32, size: (u32, u32)) -> Vec<Vec2> {
        let (view, proj) = self.camera(size);
        let mvp = proj * view * self.cube_model(time);
        (0..8)
            .map(|i| {
                let corner = Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                let clip = mvp * corner.extend(1.0);
                let ndc = clip.truncate().truncate() / clip.w;
                (ndc * 0.5 + 0.5) * Vec2::new(size.0 as f32, size.1 as f32)
            })
            .collect()
    }
}

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
        colliders: &[stage.cube.extend(CUBE_HALF * 3f32.sqrt())],
    };
    field.record(cmd, &frame)
}
