//! The passes of a frame, in the order the renderer records them, with what each reads
//! and writes:
//!
//! 0. [`tiles`]: in a tiled field, generates the tiles entering the pool of simulated
//!    tiles and the far tiles' blades in view (reads the frame block and the pool's
//!    table; writes the blades, their ids and clumps, the tile list and counters).
//! 1. [`occlusion`]: draws the scene's surfaces depth-only and reduces the depth to a
//!    pyramid (reads the surfaces and the camera; writes the depth image and the
//!    pyramid buffer). Only with the occlusion test and something that can hide grass.
//! 2. [`simulate`]: simulates, culls and compacts every blade, then writes one draw
//!    command per chunk (reads the frame block and the pyramid; writes the blades,
//!    their collision strengths, the visible indices, the counters and the draws).
//! 3. [`shadow`]: the sun's shadow map (natural look, shadows on): surfaces, balls and
//!    the visible grass at its fewest segments (reads what `ground` and `grass` read;
//!    writes the shadow map).
//! 4. [`draw`]: the main draw, which records these in one rendering scope:
//!    - [`grass`]: the visible blades as tessellated patches or mesh strips (reads
//!      the visible indices, the blades, the draws and the frame block; writes colour
//!      and depth);
//!    - [`ground`]: the surfaces and the collider ball (reads the surface meshes and
//!      the frame block; writes colour and depth);
//!    - [`raster`]: the far blades of the compute rasterizer, then resolved into the
//!      same images in a second scope.
//!
//!    In the natural look they draw into a linear HDR target (multisampled with
//!    `--msaa`, resolved when the last scope ends); with temporal anti-aliasing
//!    (either look) into the HDR target and a motion target, each pixel's motion.
//!
//!    At one sample the natural look's grass draws only which blade covers each
//!    pixel and where on it, packed into the HDR image.
//! 5. [`shade`]: the natural look at one sample, shaded after the draw (reads the
//!    packed pixels, the dressed blades, their previous control points and the
//!    shadow map; writes the HDR image in place and, with TAA, the motion image).
//! 6. [`temporal`]: with temporal anti-aliasing, the resolve (reads the HDR image,
//!    the motion target, the depth and the last history; writes the next history).
//! 7. [`tonemap`]: the natural look's sky and tone map (reads the resolved HDR
//!    image, or the history just written, drawn at the render scale; writes the
//!    target, but for what the overlay covers opaquely).
//! 8. [`overlay`]: the viewer's egui panel (reads egui's meshes and textures into its
//!    layer when they change, before the frame; copies the layer's opaque part into
//!    the target and blends the rest). [`area`] has the rectangles around it.
//!
//! [`reference`](mod@reference) is no part of a frame: the benchmark's bandwidth and triangle
//! references.

pub mod area;
pub mod by_target;
pub mod draw;
pub mod grass;
pub mod ground;
pub mod occlusion;
#[cfg(feature = "app")]
pub mod overlay;
pub mod raster;
pub mod reference;
pub mod shade;
pub mod shadow;
pub mod simulate;
pub mod temporal;
pub mod tiles;
pub mod tonemap;

/// The timestamps of a frame, in the order they are written: the start, then the end
/// of each pass of `renderer::PassTimes`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Mark {
    /// Before anything.
    Start,
    /// After the uniform upload, the counter reset and the depth pyramid.
    Pyramid,
    /// After simulate, cull and the draw commands.
    SimulateCull,
    /// After the sun's shadow map (natural look with shadows).
    Shadow,
    /// After the grass, drawn first so that the ground it covers fails the early
    /// depth test.
    Grass,
    /// After the ground and the ball (inside the rendering scope: before its
    /// resolve).
    Ground,
    /// After the compute rasterizer (`passes::raster`): the hardware's rendering scope
    /// ended, its depth copied, the far blades drawn; at once without it.
    Raster,
    /// After the last rendering scope ended: the compute rasterizer's resolve and the
    /// multisample resolve, when there are any.
    Resolve,
    /// After the natural look's shading after the draw (one sample per pixel).
    Shade,
    /// After the temporal resolve and the sky and the tone map (natural look, or
    /// temporal anti-aliasing).
    ToneMap,
    /// After the overlay.
    Overlay,
}

impl Mark {
    /// Timestamps per frame.
    pub const COUNT: u32 = 11;
}

/// Depth format of every pass.
pub const DEPTH_FORMAT: ash::vk::Format = ash::vk::Format::D32_SFLOAT;

/// Format of the linear HDR image the natural look draws into (and either look with
/// temporal anti-aliasing), and of the temporal histories.
pub const HDR_FORMAT: ash::vk::Format = ash::vk::Format::R16G16B16A16_SFLOAT;

/// The colour attachment `image` the draw wrote, to sampled for `reader`.
pub(crate) fn to_sampled(
    rec: &crate::vulkan::Recorder,
    image: ash::vk::Image,
    reader: (ash::vk::PipelineStageFlags2, ash::vk::AccessFlags2),
) {
    use ash::vk;
    use vk::AccessFlags2 as A;
    use vk::PipelineStageFlags2 as S;
    rec.image_barrier(
        image,
        vk::ImageAspectFlags::COLOR,
        (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        ),
        (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
        reader,
    );
}
