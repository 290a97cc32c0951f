//! Grass in your own Vulkan program (`runner::embed`): this program makes its own
//! instance, device, queue, allocator, images and command buffers, draws its own
//! object (a spinning cube, `shared::cube`), and has a `GrassField` draw the grass
//! into the same colour and depth images, depth-tested against the cube. The cube is
//! also a collider: the blades under it bend away.
//!
//! ```text
//! cargo run --release --example embed                       # a window
//! cargo run --release --example embed -- --out frame.png    # headless, one PNG
//! cargo run --release --example embed -- --help             # every option
//! ```
//!
//! `--resize-through` goes through those sizes first (headless, a frame at each; in
//! a window, asked of the window 10 frames apart).
//!
//! `--look natural` (headless) draws the natural look into a linear HDR image
//! (`R16G16B16A16_SFLOAT`), as an engine with its own tone map would, and tone-maps
//! it on the host (`shared::look::tone_map`) for the PNG. `--tiled` makes the field a
//! tiled one, generated tile by tile around the camera out to the horizon.
//!
//! Headless, `--frames` (90 by default) are simulated and the last one written; in a
//! window, `--frames` closes it after that many (else it runs until closed).

use anyhow::{Context as _, Result, bail};
use ash::vk;
use glam::camera::rh;
use glam::{Mat4, Vec2, Vec3};
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use runner::embed::{self, FieldDesc, Frame, GrassField, Ground, Targets};
use shared::cube::{CUBE_VERTICES, CubePush};
use shared::settings::Look;
use std::ffi::{CStr, c_char, c_void};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// Format of the headless colour image (written to PNG as is).
pub const HEADLESS_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// Format of the headless HDR image of the natural look (tone-mapped on the host).
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// Colour the frame is cleared to: the sky (linear).
const SKY: [f32; 4] = [0.42, 0.62, 0.86, 1.0];
/// The cube's colour (linear): a magenta nothing else in the frame has.
pub const CUBE_COLOR: Vec3 = Vec3::new(0.8, 0.06, 0.5);
/// Half the cube's side.
pub const CUBE_HALF: f32 = 1.0;
/// Blades in the field.
pub const BLADES: u32 = 20_000;
/// Simulated seconds a frame.
const FRAME_SECONDS: f64 = 1.0 / 60.0;
/// Validation errors the layer reported (with `--validation`).
pub static VALIDATION_ERRORS: AtomicU32 = AtomicU32::new(0);

#[allow(dead_code)] // Also compiled into `runner/tests/embed.rs`, which has its own main.
fn main() -> std::process::ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    // A usage error (or --help) ends here, as clap says it.
    let args = <Args as clap::Parser>::parse();
    match run(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Draws as `args` ask: a window, or one PNG headless.
fn run(args: &Args) -> Result<()> {
    let Some(out) = &args.out else {
        if args.look != Look::Paper {
            bail!("the window draws the paper look; --look natural needs --out (headless)");
        }
        return window::run(args);
    };
    runner::files::check_output(out, &["png"])?;
    let shot = render_headless(args)?;
    runner::files::save_png(out, &shot.rgba, shot.size, image::ColorType::Rgba8)?;
    let out = out.display();
    let errors = VALIDATION_ERRORS.load(Ordering::SeqCst);
    println!(
        "wrote {out}: {} blades drawn, {errors} validation errors",
        shot.drawn
    );
    if shot.software {
        println!("(a software device: its timestamps do not time passes, none is printed)");
    } else if let Some(t) = shot.times {
        let per_blade = 1e6 * t.total / f64::from(shot.drawn.max(1));
        println!(
            "the field's GPU time in the last frame: simulate and cull {:.3} ms, shadow map \
             {:.3}, grass {:.3}, ground {:.3}; {:.3} ms in all, {per_blade:.1} ns a drawn blade",
            t.depth_pyramid + t.simulate_cull,
            t.shadow,
            t.grass,
            t.ground,
            t.total
        );
    }
    if errors > 0 {
        bail!("validation reported {errors} errors");
    }
    Ok(())
}

/// The command line: what to draw, and where.
#[derive(clap::Parser, Debug, Clone)]
#[command(
    name = "embed",
    about = "Grass in your own Vulkan program: a cube of its own and runner::embed's field"
)]
pub struct Args {
    /// The PNG to write (headless); without it, a window opens.
    #[arg(long)]
    pub out: Option<std::path::PathBuf>,
    /// Frames to draw: headless, the last is written [default: 90]; in a window, it
    /// closes after them [default: when closed].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Headless image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x360", value_parser = size)]
    pub size: (u32, u32),
    /// The field's look (the natural one headless only).
    #[arg(long, value_enum, default_value_t = Look::Paper)]
    pub look: Look,
    /// Blades of a stored field.
    #[arg(long, default_value_t = BLADES, value_parser = clap::value_parser!(u32).range(1..=(1 << 24)))]
    pub blades: u32,
    /// A tiled field, generated tile by tile around the camera to the horizon.
    #[arg(long)]
    pub tiled: bool,
    /// Sizes to go through first, WxH,WxH,...: headless, a frame each before --size; in
    /// a window, the window asks for each in turn, 10 frames apart (the field follows
    /// its targets' size either way).
    #[arg(long, value_delimiter = ',', value_parser = size)]
    pub resize_through: Vec<(u32, u32)>,
    /// The validation layer on (core and synchronization), its errors counted.
    #[arg(long)]
    pub validation: bool,
}

impl Default for Args {
    fn default() -> Self {
        Self {
            out: None,
            frames: None,
            size: (640, 360),
            look: Look::Paper,
            blades: BLADES,
            tiled: false,
            resize_through: Vec::new(),
            validation: false,
        }
    }
}

/// `WIDTHxHEIGHT`, both from 1 to 8192.
fn size(text: &str) -> Result<(u32, u32), String> {
    let parsed = text
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    match parsed {
        Some((w, h)) if (1..=8192).contains(&w) && (1..=8192).contains(&h) => Ok((w, h)),
        _ => Err(format!("{text:?} is no size: WIDTHxHEIGHT, each 1 to 8192")),
    }
}

/// The program's own Vulkan objects: what any ash renderer has before it adds grass.
pub struct Gpu {
    entry: ash::Entry,
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    device: ash::Device,
    queue_family: u32,
    queue: vk::Queue,
    /// Shared with the field; dropped before the device.
    allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    /// What the field asked to enable (and this device has).
    features: embed::DeviceFeatures,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
}

impl Gpu {
    /// The instance, with `extensions` (a window system's) and, if asked, validation.
    pub fn instance(
        extensions: &[*const c_char],
        validation: bool,
    ) -> Result<(ash::Entry, ash::Instance)> {
        let entry = unsafe { ash::Entry::load() }.context("load Vulkan")?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"embed example")
            .api_version(vk::API_VERSION_1_3);
        let mut extensions = extensions.to_vec();
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let layers: &[_] = if validation { &layers } else { &[] };
        if validation {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        // Synchronization validation too: hazards between the program's commands and
        // the field's.
        let checks = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&checks);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(layers)
            .enabled_extension_names(&extensions);
        if validation {
            info = info.push_next(&mut features);
        }
        let instance = unsafe { entry.create_instance(&info, None) }.context("create instance")?;
        Ok((entry, instance))
    }

    /// On the first device with a graphics + compute queue family that `format_for`
    /// gives a colour format for (the one its images will have) and that has what the
    /// grass needs for that format (`embed::requirements`, asked before anything is
    /// made): a device with those features and `extensions`, and its allocator.
    pub fn new(
        (entry, instance): (ash::Entry, ash::Instance),
        validation: bool,
        format_for: impl Fn(vk::PhysicalDevice, u32) -> Option<vk::Format>,
        extensions: &[&CStr],
    ) -> Result<(Self, vk::Format)> {
        let debug = match validation {
            true => Some(debug_messenger(&entry, &instance)?),
            false => None,
        };
        let mut reasons = Vec::new();
        let mut chosen = None;
        for physical in unsafe { instance.enumerate_physical_devices()? } {
            let families =
                unsafe { instance.get_physical_device_queue_family_properties(physical) };
            let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
            let found = (0..families.len() as u32)
                .filter(|&f| families[f as usize].queue_flags.contains(wanted))
                .find_map(|f| Some((f, format_for(physical, f)?)));
            let Some((family, format)) = found else {
                reasons.push("no graphics queue for these images".to_string());
                continue;
            };
            match embed::requirements(&instance, physical, format) {
                Ok(features) => {
                    chosen = Some((physical, family, format, features));
                    break;
                }
                Err(missing) => reasons.push(missing.to_string()),
            }
        }
        let Some((physical, queue_family, format, mut features)) = chosen else {
            bail!("no device can draw the grass: {}", reasons.join("; "));
        };
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let names: Vec<_> = features
            .extensions()
            .into_iter()
            .chain(extensions.iter().copied())
            .map(CStr::as_ptr)
            .collect();
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&names);
        let info = features.enable(info);
        let device =
            unsafe { instance.create_device(physical, &info, None) }.context("create device")?;
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let gpu = Gpu {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue,
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            features,
            debug,
        };
        Ok((gpu, format))
    }

    /// The grass: `blades` on `ground` (or a tiled field), drawing into `format`
    /// images.
    pub fn grass(
        &self,
        ground: Ground,
        blades: u32,
        tiled: bool,
        format: vk::Format,
    ) -> Result<GrassField> {
        let device = embed::Device {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            physical: self.physical,
            device: self.device.clone(),
            queue_family: self.queue_family,
            queue: self.queue,
            allocator: Arc::clone(&self.allocator),
        };
        let desc = FieldDesc {
            ground,
            blades,
            seed: 1,
            color_format: format,
            draw_ground: true,
            tiled,
        };
        GrassField::new(device, &self.features, desc)
    }

    /// A single-sampled image of `format` with its memory and a view.
    fn image(
        &self,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<OwnedImage> {
        let aspect = if format == embed::DEPTH_FORMAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(extent.into())
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let image = unsafe { self.device.create_image(&info, None)? };
        let requirements = unsafe { self.device.get_image_memory_requirements(image) };
        let memory = self.lock()?.allocate(&AllocationCreateDesc {
            name: "example image",
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        unsafe {
            self.device
                .bind_image_memory(image, memory.memory(), memory.offset())?
        };
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range(aspect));
        let view = unsafe { self.device.create_image_view(&view_info, None)? };
        Ok(OwnedImage {
            image,
            view,
            memory: Some(memory),
            aspect,
        })
    }

    /// Destroys an image of [`Self::image`] (no longer in use).
    fn destroy_image(&self, mut image: OwnedImage) {
        unsafe {
            self.device.destroy_image_view(image.view, None);
            self.device.destroy_image(image.image, None);
        }
        if let (Some(memory), Ok(mut allocator)) = (image.memory.take(), self.lock()) {
            let _ = allocator.free(memory);
        }
    }

    fn lock(&self) -> Result<std::sync::MutexGuard<'_, Allocator>> {
        self.allocator
            .lock()
            .map_err(|_| anyhow::anyhow!("allocator lock poisoned"))
    }

    /// A command pool on the queue's family, and one command buffer from it.
    fn commands(&self) -> Result<(vk::CommandPool, vk::CommandBuffer)> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { self.device.create_command_pool(&info, None)? };
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let cmd = unsafe { self.device.allocate_command_buffers(&info)? }[0];
        Ok((pool, cmd))
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            // The field (holding the other clone) is gone by now.
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.debug.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// An image this program made.
pub struct OwnedImage {
    image: vk::Image,
    view: vk::ImageView,
    memory: Option<Allocation>,
    aspect: vk::ImageAspectFlags,
}

/// The whole of a single-level image.
fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}

/// A layout change of the whole `image`, after `src` and before `dst`.
fn transition(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (image, aspect): (vk::Image, vk::ImageAspectFlags),
    layouts: (vk::ImageLayout, vk::ImageLayout),
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(range(aspect))
        .old_layout(layouts.0)
        .new_layout(layouts.1)
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    let info = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { device.cmd_pipeline_barrier2(cmd, &info) };
}

/// Counts the validation layer's errors and prints every message.
fn debug_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
) -> Result<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)> {
    unsafe extern "system" fn callback(
        severity: vk::DebugUtilsMessageSeverityFlagsEXT,
        _types: vk::DebugUtilsMessageTypeFlagsEXT,
        data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
        _user: *mut c_void,
    ) -> vk::Bool32 {
        let message = unsafe { data.as_ref() }
            .and_then(|d| unsafe { d.message_as_c_str() })
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            VALIDATION_ERRORS.fetch_add(1, Ordering::SeqCst);
        }
        eprintln!("validation: {message}");
        vk::FALSE
    }
    use vk::DebugUtilsMessageSeverityFlagsEXT as Sev;
    use vk::DebugUtilsMessageTypeFlagsEXT as Ty;
    let utils = ash::ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(Sev::ERROR | Sev::WARNING)
        .message_type(Ty::GENERAL | Ty::VALIDATION)
        .pfn_user_callback(Some(callback));
    let messenger = unsafe { utils.create_debug_utils_messenger(&info, None)? };
    Ok((utils, messenger))
}

/// The program's own pipeline: the cube, from its vertex index.
pub struct Cube {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    device: ash::Device,
}

impl Cube {
    /// The pipeline for `color_format` images over [`embed::DEPTH_FORMAT`] depth.
    fn new(device: &ash::Device, color_format: vk::Format) -> Result<Self> {
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
fn record_frame(
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

/// One headless run's picture.
pub struct Shot {
    /// RGBA8 (sRGB) pixels, row by row.
    pub rgba: Vec<u8>,
    /// (width, height).
    pub size: (u32, u32),
    /// Blades the last frame drew.
    pub drawn: u32,
    /// The cube's corners in pixels, in the last frame.
    pub cube_corners: Vec<Vec2>,
    /// GPU time of the field's passes in the last frame, where the device has
    /// timestamps.
    pub times: Option<embed::PassTimes>,
    /// The device is a software rasterizer (lavapipe): its timestamps do not time
    /// passes (its drawing is deferred).
    pub software: bool,
}

/// `args.frames` frames of `args.size` in `args.look` into an offscreen image, the
/// last one read back (the natural look's HDR image tone-mapped on the host).
pub fn render_headless(args: &Args) -> Result<Shot> {
    let (size, frames, look, validation) = (
        args.size,
        args.frames.unwrap_or(90),
        args.look,
        args.validation,
    );
    let format = match look {
        Look::Paper => HEADLESS_FORMAT,
        Look::Natural => HDR_FORMAT,
    };
    let (gpu, format) = Gpu::new(
        Gpu::instance(&[], validation)?,
        validation,
        |_, _| Some(format),
        &[],
    )?;
    let extent = vk::Extent2D {
        width: size.0,
        height: size.1,
    };
    use vk::ImageUsageFlags as U;
    let color = gpu.image(extent, format, U::COLOR_ATTACHMENT | U::TRANSFER_SRC)?;
    let depth = gpu.image(extent, embed::DEPTH_FORMAT, U::DEPTH_STENCIL_ATTACHMENT)?;
    let texel = if format == HDR_FORMAT { 8 } else { 4 };
    let bytes = u64::from(size.0) * u64::from(size.1) * texel;
    let info = vk::BufferCreateInfo::default()
        .size(bytes)
        .usage(vk::BufferUsageFlags::TRANSFER_DST);
    let buffer = unsafe { gpu.device.create_buffer(&info, None)? };
    let requirements = unsafe { gpu.device.get_buffer_memory_requirements(buffer) };
    let memory = gpu.lock()?.allocate(&AllocationCreateDesc {
        name: "readback",
        requirements,
        location: MemoryLocation::GpuToCpu,
        linear: true,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    })?;
    unsafe {
        gpu.device
            .bind_buffer_memory(buffer, memory.memory(), memory.offset())?
    };
    let cube = Cube::new(&gpu.device, format)?;
    let mut field = gpu.grass(Ground::Hills, args.blades, args.tiled, format)?;
    field.settings.look.style = look;
    let stage = Stage::new(&field);
    let (pool, cmd) = gpu.commands()?;
    let fence = unsafe {
        gpu.device
            .create_fence(&vk::FenceCreateInfo::default(), None)?
    };
    let device = &gpu.device;
    // One frame into `color` and `depth` of `extent`, copied to the buffer if `copy`.
    let mut frame_into = |color: &OwnedImage, depth: &OwnedImage, extent, copy| -> Result<()> {
        unsafe {
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(cmd, &begin)?;
        }
        let target = (color.image, color.view);
        record_frame(&gpu, &cube, &mut field, &stage, cmd, target, depth, extent)?;
        if copy {
            transition(
                device,
                cmd,
                (color.image, color.aspect),
                (L::COLOR_ATTACHMENT_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (S::COPY, A::TRANSFER_READ),
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(color.aspect)
                        .layer_count(1),
                )
                .image_extent(extent.into());
            unsafe {
                device.cmd_copy_image_to_buffer(
                    cmd,
                    color.image,
                    L::TRANSFER_SRC_OPTIMAL,
                    buffer,
                    &[region],
                );
            }
        }
        unsafe {
            device.end_command_buffer(cmd)?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            device.queue_submit(gpu.queue, &[submit], fence)?;
            device.wait_for_fences(&[fence], true, u64::MAX)?;
            device.reset_fences(&[fence])?;
        }
        Ok(())
    };
    // A window's resizes: a frame at each size first, into images of that size.
    for &(width, height) in &args.resize_through {
        let extent = vk::Extent2D { width, height };
        let color = gpu.image(extent, format, U::COLOR_ATTACHMENT | U::TRANSFER_SRC)?;
        let depth = gpu.image(extent, embed::DEPTH_FORMAT, U::DEPTH_STENCIL_ATTACHMENT)?;
        frame_into(&color, &depth, extent, false)?;
        gpu.destroy_image(color);
        gpu.destroy_image(depth);
    }
    for frame in 0..frames {
        frame_into(&color, &depth, extent, frame + 1 == frames)?;
    }
    let mapped = memory.mapped_slice().context("readback not mapped")?;
    let exposure = field.settings.look.exposure;
    let rgba = match look {
        Look::Paper => mapped[..bytes as usize].to_vec(),
        Look::Natural => tone_map_on_host(&mapped[..bytes as usize], exposure),
    };
    let shot = Shot {
        rgba,
        size,
        drawn: field.counts()?.drawn,
        times: field.times()?,
        software: unsafe { gpu.instance.get_physical_device_properties(gpu.physical) }.device_type
            == vk::PhysicalDeviceType::CPU,
        cube_corners: stage.cube_corners_px(field.time(), size),
    };
    drop(field);
    drop(cube);
    unsafe {
        gpu.device.destroy_fence(fence, None);
        gpu.device.destroy_command_pool(pool, None);
        gpu.device.destroy_buffer(buffer, None);
    }
    let _ = gpu.lock()?.free(memory);
    gpu.destroy_image(color);
    gpu.destroy_image(depth);
    Ok(shot)
}

/// RGBA16F linear radiance to RGBA8 sRGB: `shared::look::tone_map` (ACES, with the
/// field's exposure), as the program's own tone-map pass does it.
fn tone_map_on_host(hdr: &[u8], exposure: f32) -> Vec<u8> {
    hdr.as_chunks::<8>()
        .0
        .iter()
        .flat_map(|texel| {
            let channel = |i: usize| half::f16::from_le_bytes([texel[2 * i], texel[2 * i + 1]]);
            let radiance = Vec3::new(channel(0).into(), channel(1).into(), channel(2).into());
            let display = shared::look::tone_map(radiance, exposure);
            let byte = |c: f32| (shared::shade::linear_to_srgb(c) * 255.0).round() as u8;
            [byte(display.x), byte(display.y), byte(display.z), 255]
        })
        .collect()
}

/// The window: a swapchain, the same frame into each of its images.
mod window {
    use super::*;
    use ash::khr;
    use winit::application::ApplicationHandler;
    use winit::event::WindowEvent;
    use winit::event_loop::{ActiveEventLoop, EventLoop};
    use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
    use winit::window::{Window, WindowId};

    /// Opens the window and draws until it is closed.
    pub fn run(args: &Args) -> Result<()> {
        let (validation, frames, tiled) = (args.validation, args.frames, args.tiled);
        let event_loop = EventLoop::new().context("event loop (is there a display?)")?;
        let mut app = App {
            validation,
            tiled,
            resizes: args.resize_through.iter().rev().copied().collect(),
            frames,
            drawn: 0,
            state: None,
            error: None,
        };
        event_loop.run_app(&mut app)?;
        if let Some(e) = app.error.take() {
            return Err(e);
        }
        let drawn = app.drawn;
        // Everything destroyed (and checked by the layer) before the count.
        drop(app);
        let errors = VALIDATION_ERRORS.load(Ordering::SeqCst);
        println!("drew {drawn} frames, {errors} validation errors");
        match errors {
            0 => Ok(()),
            _ => bail!("validation reported {errors} errors"),
        }
    }

    struct App {
        validation: bool,
        tiled: bool,
        /// Window sizes still to ask for, the next last.
        resizes: Vec<(u32, u32)>,
        /// Close after this many frames.
        frames: Option<u32>,
        drawn: u32,
        state: Option<State>,
        error: Option<anyhow::Error>,
    }

    /// Everything on the GPU, in the order it is dropped.
    struct State {
        swapchain: Swapchain,
        field: GrassField,
        cube: Cube,
        stage: Stage,
        pool: vk::CommandPool,
        cmd: vk::CommandBuffer,
        fence: vk::Fence,
        acquired: vk::Semaphore,
        surface: vk::SurfaceKHR,
        surface_fn: khr::surface::Instance,
        gpu: Gpu,
        window: Arc<Window>,
    }

    /// The swapchain, its images, their depth and the semaphores their presentation
    /// waits for.
    struct Swapchain {
        loader: khr::swapchain::Device,
        swapchain: vk::SwapchainKHR,
        images: Vec<(vk::Image, vk::ImageView, vk::Semaphore)>,
        depth: Option<OwnedImage>,
        extent: vk::Extent2D,
        format: vk::Format,
    }

    impl ApplicationHandler for App {
        fn resumed(&mut self, event_loop: &ActiveEventLoop) {
            if self.state.is_none() {
                match State::new(event_loop, self.validation, self.tiled) {
                    Ok(state) => self.state = Some(state),
                    Err(e) => {
                        self.error = Some(e);
                        event_loop.exit();
                    }
                }
            }
        }

        fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
            let Some(state) = self.state.as_mut() else {
                return;
            };
            let result = match event {
                WindowEvent::CloseRequested => {
                    event_loop.exit();
                    Ok(())
                }
                WindowEvent::Resized(_) => state.resize(),
                WindowEvent::RedrawRequested => {
                    let drawn = state.draw();
                    self.drawn += 1;
                    if self.frames.is_some_and(|n| self.drawn >= n) {
                        event_loop.exit();
                    }
                    if self.drawn.is_multiple_of(10)
                        && let Some((w, h)) = self.resizes.pop()
                    {
                        let size = winit::dpi::PhysicalSize::new(w, h);
                        let _ = state.window.request_inner_size(size);
                    }
                    state.window.request_redraw();
                    drawn
                }
                _ => Ok(()),
            };
            if let Err(e) = result {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    impl State {
        fn new(event_loop: &ActiveEventLoop, validation: bool, tiled: bool) -> Result<Self> {
            let attributes = Window::default_attributes()
                .with_title("grass in your own renderer (runner::embed)")
                .with_inner_size(winit::dpi::LogicalSize::new(960, 540));
            let window = Arc::new(event_loop.create_window(attributes)?);
            let display = window.display_handle()?.as_raw();
            let extensions = ash_window::enumerate_required_extensions(display)?;
            let (entry, instance) = Gpu::instance(extensions, validation)?;
            let handle = window.window_handle()?.as_raw();
            let surface =
                unsafe { ash_window::create_surface(&entry, &instance, display, handle, None)? };
            let surface_fn = khr::surface::Instance::new(&entry, &instance);
            let format_for = |physical, family| {
                let presents = unsafe {
                    surface_fn.get_physical_device_surface_support(physical, family, surface)
                };
                if !presents.unwrap_or(false) {
                    return None;
                }
                let formats =
                    unsafe { surface_fn.get_physical_device_surface_formats(physical, surface) }
                        .ok()?;
                let srgb = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];
                formats
                    .iter()
                    .map(|f| f.format)
                    .find(|f| srgb.contains(f))
                    .or(formats.first().map(|f| f.format))
            };
            let swapchain_ext = [khr::swapchain::NAME];
            let (gpu, format) =
                Gpu::new((entry, instance), validation, format_for, &swapchain_ext)?;
            let cube = Cube::new(&gpu.device, format)?;
            let field = gpu.grass(Ground::Hills, BLADES, tiled, format)?;
            let stage = Stage::new(&field);
            let (pool, cmd) = gpu.commands()?;
            let device = &gpu.device;
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let fence = unsafe { device.create_fence(&signalled, None)? };
            let acquired =
                unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)? };
            let loader = khr::swapchain::Device::new(&gpu.instance, device);
            let mut swapchain = Swapchain {
                loader,
                swapchain: vk::SwapchainKHR::null(),
                images: Vec::new(),
                depth: None,
                extent: vk::Extent2D::default(),
                format,
            };
            swapchain.make(&gpu, &surface_fn, surface, format, &window)?;
            window.request_redraw();
            Ok(Self {
                swapchain,
                field,
                cube,
                stage,
                pool,
                cmd,
                fence,
                acquired,
                surface,
                surface_fn,
                gpu,
                window,
            })
        }

        fn resize(&mut self) -> Result<()> {
            let format = self.swapchain.format;
            unsafe { self.gpu.device.device_wait_idle()? };
            self.swapchain.make(
                &self.gpu,
                &self.surface_fn,
                self.surface,
                format,
                &self.window,
            )
        }

        /// One frame: wait for the last, acquire, record the cube and the grass,
        /// submit, present.
        fn draw(&mut self) -> Result<()> {
            let device = &self.gpu.device;
            let sc = &self.swapchain;
            if sc.extent.width == 0 || sc.extent.height == 0 {
                return Ok(());
            }
            unsafe { device.wait_for_fences(&[self.fence], true, u64::MAX)? };
            let acquire = unsafe {
                sc.loader.acquire_next_image(
                    sc.swapchain,
                    u64::MAX,
                    self.acquired,
                    vk::Fence::null(),
                )
            };
            let index = match acquire {
                Ok((index, _)) => index as usize,
                Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return self.resize(),
                Err(e) => return Err(e.into()),
            };
            unsafe {
                device.reset_fences(&[self.fence])?;
                let begin = vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
                device.begin_command_buffer(self.cmd, &begin)?;
            }
            let (image, view, rendered) = sc.images[index];
            let depth = sc.depth.as_ref().context("depth image")?;
            let (gpu, cube, stage) = (&self.gpu, &self.cube, &self.stage);
            let cmd = self.cmd;
            record_frame(
                gpu,
                cube,
                &mut self.field,
                stage,
                cmd,
                (image, view),
                depth,
                sc.extent,
            )?;
            transition(
                device,
                cmd,
                (image, vk::ImageAspectFlags::COLOR),
                (L::COLOR_ATTACHMENT_OPTIMAL, L::PRESENT_SRC_KHR),
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (S::NONE, A::NONE),
            );
            unsafe {
                device.end_command_buffer(cmd)?;
                let waits = [self.acquired];
                let stages = [vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT];
                let cmds = [cmd];
                let signals = [rendered];
                let submit = vk::SubmitInfo::default()
                    .wait_semaphores(&waits)
                    .wait_dst_stage_mask(&stages)
                    .command_buffers(&cmds)
                    .signal_semaphores(&signals);
                device.queue_submit(gpu.queue, &[submit], self.fence)?;
                let swapchains = [sc.swapchain];
                let indices = [index as u32];
                let present = vk::PresentInfoKHR::default()
                    .wait_semaphores(&signals)
                    .swapchains(&swapchains)
                    .image_indices(&indices);
                match sc.loader.queue_present(gpu.queue, &present) {
                    Ok(_) => Ok(()),
                    Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.resize(),
                    Err(e) => Err(e.into()),
                }
            }
        }
    }

    impl Swapchain {
        /// (Re)makes the swapchain for the window's size, with its views, semaphores
        /// and depth image.
        fn make(
            &mut self,
            gpu: &Gpu,
            surface_fn: &khr::surface::Instance,
            surface: vk::SurfaceKHR,
            format: vk::Format,
            window: &Window,
        ) -> Result<()> {
            let caps = unsafe {
                surface_fn.get_physical_device_surface_capabilities(gpu.physical, surface)?
            };
            let size = window.inner_size();
            let extent = match caps.current_extent.width {
                u32::MAX => vk::Extent2D {
                    width: size.width,
                    height: size.height,
                },
                _ => caps.current_extent,
            };
            self.release(gpu);
            self.extent = extent;
            println!("swapchain {}x{}", extent.width, extent.height);
            if extent.width == 0 || extent.height == 0 {
                return Ok(());
            }
            let count = (caps.min_image_count + 1).min(match caps.max_image_count {
                0 => u32::MAX,
                n => n,
            });
            let info = vk::SwapchainCreateInfoKHR::default()
                .surface(surface)
                .min_image_count(count)
                .image_format(format)
                .image_color_space(vk::ColorSpaceKHR::SRGB_NONLINEAR)
                .image_extent(extent)
                .image_array_layers(1)
                .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT)
                .pre_transform(caps.current_transform)
                .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
                .present_mode(vk::PresentModeKHR::FIFO)
                .clipped(true)
                .old_swapchain(self.swapchain);
            let made = unsafe { self.loader.create_swapchain(&info, None)? };
            unsafe { self.loader.destroy_swapchain(self.swapchain, None) };
            self.swapchain = made;
            self.format = format;
            for image in unsafe { self.loader.get_swapchain_images(made)? } {
                let view_info = vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(format)
                    .subresource_range(range(vk::ImageAspectFlags::COLOR));
                let view = unsafe { gpu.device.create_image_view(&view_info, None)? };
                let info = vk::SemaphoreCreateInfo::default();
                let rendered = unsafe { gpu.device.create_semaphore(&info, None)? };
                self.images.push((image, view, rendered));
            }
            let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
            self.depth = Some(gpu.image(extent, embed::DEPTH_FORMAT, usage)?);
            Ok(())
        }

        /// Destroys the views, semaphores and depth image (not the swapchain: the
        /// next one is made from it).
        fn release(&mut self, gpu: &Gpu) {
            for (_, view, rendered) in self.images.drain(..) {
                unsafe {
                    gpu.device.destroy_image_view(view, None);
                    gpu.device.destroy_semaphore(rendered, None);
                }
            }
            if let Some(depth) = self.depth.take() {
                gpu.destroy_image(depth);
            }
        }
    }

    impl Drop for State {
        fn drop(&mut self) {
            let gpu = &self.gpu;
            unsafe {
                let _ = gpu.device.device_wait_idle();
                self.swapchain.release(gpu);
                self.swapchain
                    .loader
                    .destroy_swapchain(self.swapchain.swapchain, None);
                gpu.device.destroy_semaphore(self.acquired, None);
                gpu.device.destroy_fence(self.fence, None);
                gpu.device.destroy_command_pool(self.pool, None);
                self.surface_fn.destroy_surface(self.surface, None);
            }
            // The field and the cube go next (field order), then the device.
        }
    }
}
