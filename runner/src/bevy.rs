//! The grass in a Bevy app (the `bevy` feature; Bevy 0.19, whose wgpu 29 uses this
//! crate's ash and gpu-allocator).
//!
//! - **The device.** Bevy's renderer runs on a device made by
//!   [`crate::embed::wgpu::GrassDevice`] (wgpu's features as Bevy asks them, and the
//!   grass's), handed to Bevy as `RenderCreation::Manual`: [`GrassPlugin::new`] gives
//!   the `RenderPlugin` to add with Bevy's plugins and the plugin to add after them.
//! - **The field** grows on the mesh of the entity carrying [`Grass`] (its `Mesh3d`,
//!   placed by its transform), made in the render world once the mesh is loaded.
//! - **Each frame** the field is simulated and drawn for the camera carrying
//!   [`GrassCamera`], in its `Core3d` schedule after the main pass and before post
//!   processing: into the view's HDR main texture (the camera needs `Hdr` and
//!   `Msaa::Off`), depth-tested against Bevy's reverse-Z depth, then tone-mapped by
//!   Bevy with the rest of the frame. The camera's matrices are Bevy's (its clip space
//!   flipped to Vulkan's), the sun is the first `DirectionalLight`, the colliders are
//!   the entities carrying [`GrassCollider`], and [`GrassSettings`] (wind, look,
//!   stiffness) is read every frame.

use crate::embed::wgpu::{GrassDevice, TextureTarget, record};
use crate::embed::{FieldDesc, GrassField, Ground, Settings, viewpoint};
use anyhow::{Context as _, Result};
use bevy::core_pipeline::schedule::{Core3d, Core3dSystems};
use bevy::light::DirectionalLight;
use bevy::mesh::{Indices, Mesh, Mesh3d, VertexAttributeValues};
use bevy::prelude::{
    App, Assets, Component, GlobalTransform, IntoScheduleConfigs, Plugin, Query, Res, ResMut,
    Resource, Time, With,
};
use bevy::render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy::render::renderer::{
    RenderAdapter, RenderAdapterInfo, RenderContext, RenderDevice, RenderInstance, RenderQueue,
    ViewQuery, WgpuWrapper,
};
use bevy::render::settings::RenderCreation;
use bevy::render::view::{ExtractedView, ViewDepthTexture, ViewTarget};
use bevy::render::{Extract, ExtractSchedule, Render, RenderApp, RenderPlugin, RenderSystems};
use shared::sim::collide::Collider;
use shared::world::mesh::SurfaceMesh;
use std::sync::{Arc, Mutex};

/// The colour format the grass draws into: Bevy's HDR main texture.
pub const HDR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Grass on this entity's mesh (`Mesh3d`, placed by the entity's transform).
#[derive(Component, Clone, Copy, Debug)]
pub struct Grass {
    /// Blades scattered over the mesh by area.
    pub blades: u32,
    /// Seed of their places and shapes.
    pub seed: u64,
    /// The species and their shares (`shared::species::Mix`; `Mix::GRASS`: grass
    /// alone).
    pub species: shared::species::Mix,
}

/// A sphere that pushes the blades down: centred on the entity, of this radius. At
/// most `shared::sim::collide::MAX_COLLIDERS` are taken, the first found.
#[derive(Component, Clone, Copy, Debug)]
pub struct GrassCollider {
    /// The sphere's radius.
    pub radius: f32,
}

/// The camera the grass is drawn for (the first one, with `Hdr` and `Msaa::Off`).
#[derive(Component, Clone, Copy, Debug, Default, ExtractComponent)]
pub struct GrassCamera;

/// What the field is drawn with, read every frame.
#[derive(Resource, Clone, Debug)]
pub struct GrassSettings {
    /// The wind.
    pub wind: shared::settings::Wind,
    /// The look: the paper's or the natural one (linear radiance, for Bevy's tone map).
    pub look: shared::settings::Look,
    /// Scale of every blade's stiffness.
    pub stiffness: f32,
}

impl Default for GrassSettings {
    fn default() -> Self {
        let settings = Settings::default();
        Self {
            wind: settings.wind,
            look: shared::settings::Look::Natural,
            stiffness: settings.stiffness,
        }
    }
}

/// The plugin: add it after Bevy's plugins, whose `RenderPlugin` is
/// [`GrassPlugin::render_plugin`]'s.
pub struct GrassPlugin {
    device: Mutex<Option<GrassDevice>>,
}

impl GrassPlugin {
    /// A device for Bevy and the grass on the first Vulkan adapter (the validation
    /// layer on with `validation`): the `RenderPlugin` that hands it to Bevy, and
    /// this plugin.
    pub fn new(validation: bool) -> Result<(RenderPlugin, Self)> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        if validation {
            desc.flags |= wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = bevy::tasks::block_on(
            instance.request_adapter(&wgpu::RequestAdapterOptions::default()),
        )
        .context("no Vulkan adapter")?;
        // As Bevy asks for its own device: every feature the adapter has (bar mappable
        // primary buffers on a discrete GPU), its limits, experimental features on.
        let mut features = adapter.features();
        let info = adapter.get_info();
        if info.device_type == wgpu::DeviceType::DiscreteGpu {
            features.remove(wgpu::Features::MAPPABLE_PRIMARY_BUFFERS);
        }
        let desc = wgpu::DeviceDescriptor {
            label: Some("bevy and grass"),
            required_features: features,
            required_limits: adapter.limits(),
            experimental_features: unsafe { wgpu::ExperimentalFeatures::enabled() },
            ..Default::default()
        };
        let device = GrassDevice::new(instance, adapter, HDR_FORMAT, &desc)?;
        let render = RenderPlugin {
            render_creation: RenderCreation::manual(
                RenderDevice::from(device.device.clone()),
                RenderQueue(Arc::new(WgpuWrapper::new(device.queue.clone()))),
                RenderAdapterInfo(WgpuWrapper::new(info)),
                RenderAdapter(Arc::new(WgpuWrapper::new(device.adapter.clone()))),
                RenderInstance(Arc::new(WgpuWrapper::new(device.instance.clone()))),
            ),
            ..Default::default()
        };
        let plugin = Self {
            device: Mutex::new(Some(device)),
        };
        Ok((render, plugin))
    }
}

impl Plugin for GrassPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<GrassSettings>()
            .add_plugins(ExtractComponentPlugin::<GrassCamera>::default());
        let device = self.device.lock().ok().and_then(|mut d| d.take());
        let Some(device) = device else {
            bevy::log::error!("the grass plugin was added twice: the second draws nothing");
            return;
        };
        let Some(render) = app.get_sub_app_mut(RenderApp) else {
            bevy::log::error!("no render app: the grass plugin goes after Bevy's RenderPlugin");
            return;
        };
        render
            .insert_resource(RenderGrass {
                field: None,
                device,
                ground: None,
                frame: FrameInput::default(),
                warned: false,
            })
            .add_systems(ExtractSchedule, extract)
            .add_systems(Render, make_field.in_set(RenderSystems::Prepare))
            .add_systems(
                Core3d,
                draw.after(Core3dSystems::MainPass)
                    .before(Core3dSystems::PostProcess),
            );
    }
}

/// What a frame of the field takes from the main world.
#[derive(Default)]
struct FrameInput {
    seconds: f64,
    colliders: Vec<Collider>,
    sun: Option<glam::Vec3>,
    settings: Option<GrassSettings>,
}

/// The render world's grass: the device, the field once made, the ground it waits
/// for, and this frame's input.
#[derive(Resource)]
struct RenderGrass {
    // The field goes before the device it was made on.
    field: Option<GrassField>,
    device: GrassDevice,
    /// The ground extracted, waiting for the field to be made on it.
    ground: Option<(SurfaceMesh, Grass)>,
    frame: FrameInput,
    /// A view the grass cannot draw into was reported.
    warned: bool,
}

/// From the main world: the ground (once, when its mesh is loaded), the frame's
/// time, colliders, sun and settings.
#[allow(clippy::type_complexity)]
fn extract(
    mut grass: ResMut<RenderGrass>,
    fields: Extract<Query<(&Grass, &Mesh3d, &GlobalTransform)>>,
    meshes: Extract<Res<Assets<Mesh>>>,
    colliders: Extract<Query<(&GrassCollider, &GlobalTransform)>>,
    lights: Extract<Query<&GlobalTransform, With<DirectionalLight>>>,
    time: Extract<Res<Time>>,
    settings: Extract<Res<GrassSettings>>,
) {
    if grass.field.is_none() && grass.ground.is_none() {
        let found = fields.iter().next();
        if let Some((g, mesh, at)) = found
            && let Some(mesh) = meshes.get(&mesh.0)
        {
            match surface(mesh, at) {
                Ok(surface) => grass.ground = Some((surface, *g)),
                Err(e) => bevy::log::error!("no grass on that mesh: {e:#}"),
            }
        }
    }
    let max = shared::sim::collide::MAX_COLLIDERS;
    grass.frame = FrameInput {
        seconds: time.delta_secs_f64(),
        colliders: colliders
            .iter()
            .take(max)
            .map(|(c, at)| Collider::sphere(vec3(at.translation()), c.radius))
            .collect(),
        // Towards the light: against its forward direction.
        sun: lights.iter().next().map(|at| -vec3(*at.forward())),
        settings: Some(settings.clone()),
    };
}

/// `mesh`'s triangles placed by `at`, in this crate's glam.
fn surface(mesh: &Mesh, at: &GlobalTransform) -> Result<SurfaceMesh> {
    let Some(VertexAttributeValues::Float32x3(positions)) =
        mesh.attribute(Mesh::ATTRIBUTE_POSITION)
    else {
        anyhow::bail!("the mesh has no 3-float positions");
    };
    let positions: Vec<glam::Vec3> = positions
        .iter()
        .map(|&p| vec3(at.transform_point(p.into())))
        .collect();
    let indices: Vec<u32> = match mesh.indices() {
        Some(Indices::U16(i)) => i.iter().map(|&k| u32::from(k)).collect(),
        Some(Indices::U32(i)) => i.clone(),
        None => (0..positions.len() as u32).collect(),
    };
    Ok(SurfaceMesh {
        positions,
        normals: Vec::new(),
        triangles: indices.as_chunks::<3>().0.to_vec(),
        uvs: Vec::new(),
    })
}

/// Bevy's vector in this crate's glam.
fn vec3(v: bevy::math::Vec3) -> glam::Vec3 {
    glam::Vec3::from_array(v.to_array())
}

/// Bevy's matrix in this crate's glam.
fn mat4(m: bevy::math::Mat4) -> glam::Mat4 {
    glam::Mat4::from_cols_array(&m.to_cols_array())
}

/// The field, on the ground extracted (once): its uploads submitted to Bevy's queue
/// here, before the frame's commands.
fn make_field(mut grass: ResMut<RenderGrass>) {
    let Some((ground, g)) = grass.ground.take() else {
        return;
    };
    let desc = FieldDesc {
        ground: Ground::Mesh(ground),
        blades: g.blades,
        tiled: false,
        seed: g.seed,
        species: g.species,
        color_format: ash::vk::Format::R16G16B16A16_SFLOAT,
        draw_ground: false,
        reverse_z: true,
    };
    let device = &grass.device;
    match GrassField::new(device.grass(), &device.features, desc) {
        Ok(field) => grass.field = Some(field),
        Err(e) => bevy::log::error!("the grass field: {e:#}"),
    }
}

/// The field simulated and drawn into the grass camera's view, after Bevy's main
/// pass: its own command buffer after the render context's.
fn draw(
    view: ViewQuery<(&ExtractedView, &ViewTarget, &ViewDepthTexture), With<GrassCamera>>,
    mut grass: ResMut<RenderGrass>,
    mut ctx: RenderContext,
) {
    let (view, target, depth) = view.into_inner();
    let grass = &mut *grass;
    let Some(field) = grass.field.as_mut() else {
        return;
    };
    let single = depth.texture.sample_count() == 1;
    if target.main_texture_format() != HDR_FORMAT || !single {
        if !grass.warned {
            bevy::log::warn!(
                "the grass camera's view is {:?} at {} samples: the grass draws into Hdr \
                 views with Msaa::Off",
                target.main_texture_format(),
                depth.texture.sample_count()
            );
            grass.warned = true;
        }
        return;
    }
    let input = &grass.frame;
    if let Some(s) = &input.settings {
        field.settings.wind = s.wind;
        field.settings.look.style = s.look;
        field.settings.stiffness = s.stiffness;
    }
    if let Some(sun) = input.sun {
        field.settings.light.direction = sun;
        field.settings.look.sun = sun;
    }
    // Bevy's clip space has y up (wgpu's); the field's is Vulkan's.
    let y_down = glam::Mat4::from_scale(glam::Vec3::new(1.0, -1.0, 1.0));
    let proj = y_down * mat4(view.clip_from_view);
    let eye = mat4(view.world_from_view.to_matrix()).inverse();
    let height = depth.texture.height();
    let camera = viewpoint(eye, proj, height);
    let color = TextureTarget {
        texture: target.main_texture(),
        view: target.main_texture_view(),
    };
    let depth = TextureTarget {
        texture: &depth.texture,
        view: depth.view(),
    };
    let encoder = ctx.command_encoder();
    let frame = (camera, input.seconds);
    match record(
        &grass.device,
        encoder,
        (color, depth),
        field,
        frame,
        &input.colliders,
    ) {
        Ok(commands) => ctx.add_command_buffer(commands),
        Err(e) => bevy::log::error!("the grass: {e:#}"),
    }
}
