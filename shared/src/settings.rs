//! The user's settings, typed: what the command line parses, the overlay and the keys
//! edit, and what `Settings::uniforms` (in [`crate::plan`]) turns into the frame's GPU
//! block, the one place where enums and switches become the shaders' numbers.

use crate::cull::blade::{DISTANCE, FRUSTUM, OCCLUSION, ORIENTATION, TEST_NAMES};
use crate::cull::lod::PIXELS_PER_SEGMENT;
use crate::draw::look::{LOOK_NATURAL, LOOK_PAPER};
use crate::draw::shade::{Light, VIEW_LOD, VIEW_SHADED, VIEW_WIREFRAME};
use crate::draw::shape::{
    SHAPE_DANDELION, SHAPE_QUAD, SHAPE_QUADRATIC, SHAPE_TRIANGLE, SHAPE_TRIANGLE_TIP,
};
use crate::sim::simulate::Environment;
use crate::sim::wind::{WIND_BREEZE, WIND_CALM, WIND_GUSTS, WIND_TURBULENT, WIND_VORTEX};
use spirv_std::glam::{Mat4, Vec3, Vec4};

/// The wind fields (`wind::wind_field`).
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum WindField {
    /// No wind.
    Calm = WIND_CALM,
    /// A steady breeze with travelling waves.
    #[default]
    Breeze = WIND_BREEZE,
    /// Gust fronts crossing the field over a light breeze.
    Gusts = WIND_GUSTS,
    /// A wandering whirlwind.
    Vortex = WIND_VORTEX,
    /// Irregular gusts, large and fine, travelling downwind at the gust speed.
    Turbulent = WIND_TURBULENT,
}

/// The blade shapes of the paper's section 6.1 (`shape::shape_tau`).
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum BladeShape {
    /// Full width to the tip.
    Quad = SHAPE_QUAD,
    /// Narrowing linearly to the tip.
    Triangle = SHAPE_TRIANGLE,
    /// Narrowing along a parabola.
    #[default]
    Quadratic = SHAPE_QUADRATIC,
    /// Full width up to `--tip-start`, then a triangle.
    TriangleTip = SHAPE_TRIANGLE_TIP,
    /// A dandelion leaf: three lobes with teeth pointing back to the root.
    Dandelion = SHAPE_DANDELION,
}

/// The look of the frame (`look`).
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum Look {
    /// The paper's image: Lambert blades with a base-to-tip gradient on a flat sky,
    /// drawn straight into the sRGB target (the reference images).
    Paper = LOOK_PAPER,
    /// Clumps and colour, rounded leaves lit through, ambient occlusion, sun shadows,
    /// sky and fog, rendered in linear HDR and tone-mapped.
    #[default]
    Natural = LOOK_NATURAL,
}

impl Look {
    /// Both looks, in the order the viewer's key cycles them.
    pub const ALL: [Self; 2] = [Self::Paper, Self::Natural];
    /// The next look in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

/// How the edges of blades are smoothed.
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum Antialiasing {
    /// One sample per pixel, nothing blended.
    #[default]
    None = 0,
    /// Multisampling: `LookSettings::msaa` samples per pixel, averaged.
    Msaa = 1,
    /// Temporal: one jittered sample per pixel a frame, blended into a history that
    /// follows every pixel's motion (`draw::temporal`).
    Taa = 2,
}

impl Antialiasing {
    /// Every method, in the order the viewer's key cycles them.
    pub const ALL: [Self; 3] = [Self::None, Self::Msaa, Self::Taa];
    /// The next method in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

/// How the frame looks: the style and its parts.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LookSettings {
    /// Paper or natural.
    pub style: Look,
    /// Sun shadows (natural look).
    pub shadows: bool,
    /// How edges are smoothed.
    pub aa: Antialiasing,
    /// Samples per pixel of multisampling (`Antialiasing::Msaa`): 1, 2, 4 or 8.
    pub msaa: u32,
    /// Share of the output's width and height the scene is drawn at, from
    /// [`MIN_RENDER_SCALE`] to 1: below 1 the frame (and its temporal history) is
    /// drawn smaller and the tone map scales it up, as games lower their resolution
    /// on a weak device. A field embedded in a caller's frame draws at its targets'
    /// size.
    pub render_scale: f32,
    /// Side of the sun's shadow map in texels, one of [`SHADOW_SIZES`].
    pub shadow_size: u32,
    /// Factor on the radiance before the tone map (natural look).
    pub exposure: f32,
    /// Aerial perspective: fog density per unit of distance.
    pub fog_density: f32,
    /// Clump size in scene units.
    pub clump_size: f32,
    /// Farthest a blade casts a shadow from the camera, scene units.
    pub caster_distance: f32,
    /// The field's seed (clumps and colours).
    pub seed: u32,
    /// The scene's bounding sphere (centre, radius): the shadow map covers it, or
    /// the part of it in front of the camera.
    pub scene: (Vec3, f32),
    /// Height of the plane that carries the meadow to the horizon; `None` for
    /// scenes that are not a ground under a sky (a planet).
    pub ground_level: Option<f32>,
    /// Unit direction towards the sun of the natural look: lower than the paper's
    /// light (30° up), and ahead of the default camera, so blades are lit from
    /// behind and their shadows fall towards the viewer.
    pub sun: Vec3,
}

impl Default for LookSettings {
    fn default() -> Self {
        Self {
            style: Look::Natural,
            shadows: true,
            aa: Antialiasing::None,
            msaa: 1,
            render_scale: 1.0,
            shadow_size: SHADOW_SIZE,
            exposure: 1.0,
            fog_density: 0.0012,
            clump_size: 1.6,
            caster_distance: 24.0,
            seed: 1,
            scene: (Vec3::ZERO, 12.0),
            ground_level: Some(0.0),
            sun: Vec3::new(-0.75, 0.55, -0.55).normalize(),
        }
    }
}

/// The smallest [`LookSettings::render_scale`]: a quarter of the output's width.
pub const MIN_RENDER_SCALE: f32 = 0.25;

/// Side of each of the sun's two shadow cascades in texels on a GPU. The shadow pass
/// is bound by the texels its casters cover: on an NVIDIA H100 at 1 M blades from the
/// edge, one cascade took 0.42 ms at 1024 and 0.92 ms at 2048, and the two cascades
/// 1.06 ms at 1024 and 2.72 ms at 2048.
pub const SHADOW_SIZE: u32 = 1024;
/// Side of each shadow cascade on a software device, whose rasteriser pays for every
/// texel cleared and drawn.
pub const SHADOW_SIZE_SOFTWARE: u32 = 512;
/// The shadow map's sides that can be chosen: powers of two up to 4096, the least
/// `maxImageDimension2D` Vulkan allows a device.
pub const SHADOW_SIZES: [u32; 5] = [256, 512, 1024, 2048, 4096];

/// Farthest the shadow map reaches from the camera, in units: beyond, the sun's map
/// would spread too thin over a large field.
pub const SHADOW_REACH: f32 = 48.0;

/// How the grass is drawn.
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum View {
    /// Lit blades.
    #[default]
    Shaded = VIEW_SHADED,
    /// Blades coloured by tessellation level: blue (1) through green to red (9).
    Lod = VIEW_LOD,
    /// The tessellated triangles' edges.
    Wireframe = VIEW_WIREFRAME,
}

/// The value after `current` in `all`, round to the first (what the viewer's keys do).
fn next_of<T: Copy + PartialEq>(all: &[T], current: T) -> T {
    let index = all.iter().position(|v| *v == current).map_or(0, |i| i + 1);
    all[index % all.len()]
}

impl WindField {
    /// Every field, in the order the viewer's key cycles them.
    pub const ALL: [Self; 5] = [
        Self::Calm,
        Self::Breeze,
        Self::Gusts,
        Self::Vortex,
        Self::Turbulent,
    ];
    /// The next field in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

impl BladeShape {
    /// Every shape, in the order the viewer's key cycles them.
    pub const ALL: [Self; 5] = [
        Self::Quad,
        Self::Triangle,
        Self::Quadratic,
        Self::TriangleTip,
        Self::Dandelion,
    ];
    /// The next shape in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

impl View {
    /// Every view, in the order the viewer's key cycles them.
    pub const ALL: [Self; 3] = [Self::Shaded, Self::Lod, Self::Wireframe];
    /// The next view in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

/// Which culling tests run (paper section 4.2), in the order they run.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct CullTests {
    /// Remove blades seen edge-on.
    pub orientation: bool,
    /// Remove blades outside the view frustum.
    pub frustum: bool,
    /// Thin the field with distance.
    pub distance: bool,
    /// Remove blades hidden behind the scene's surfaces (Hi-Z).
    pub occlusion: bool,
}

impl Default for CullTests {
    /// Every test.
    fn default() -> Self {
        Self::ALL
    }
}

impl CullTests {
    /// Every test.
    pub const ALL: Self = Self {
        orientation: true,
        frustum: true,
        distance: true,
        occlusion: true,
    };
    /// No test.
    pub const NONE: Self = Self {
        orientation: false,
        frustum: false,
        distance: false,
        occlusion: false,
    };
    /// Orientation, frustum and distance: the paper's three tests without occlusion.
    pub const PAPER: Self = Self {
        occlusion: false,
        ..Self::ALL
    };

    /// The tests as a mask of `cull::ORIENTATION`, `FRUSTUM`, `DISTANCE`, `OCCLUSION`.
    pub fn mask(self) -> u32 {
        let bits = [ORIENTATION, FRUSTUM, DISTANCE, OCCLUSION];
        self.switches()
            .iter()
            .zip(bits)
            .filter(|(on, _)| **on)
            .fold(0, |mask, (_, bit)| mask | bit)
    }

    /// The tests whose bits are set in `mask`.
    pub fn from_mask(mask: u32) -> Self {
        Self {
            orientation: mask & ORIENTATION != 0,
            frustum: mask & FRUSTUM != 0,
            distance: mask & DISTANCE != 0,
            occlusion: mask & OCCLUSION != 0,
        }
    }

    /// Each test's switch, in the order they run.
    pub fn switches(self) -> [bool; 4] {
        [
            self.orientation,
            self.frustum,
            self.distance,
            self.occlusion,
        ]
    }

    /// (name, switch) of each test, in the order they run, for the overlay and keys.
    pub fn named_mut(&mut self) -> [(&'static str, &mut bool); 4] {
        let [o, f, d, c] = TEST_NAMES;
        [
            (o, &mut self.orientation),
            (f, &mut self.frustum),
            (d, &mut self.distance),
            (c, &mut self.occlusion),
        ]
    }
}

/// Gravity: straight down, or blended towards a centre (paper eq. 2).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Gravity {
    /// Acceleration, towards the ground and towards the centre alike.
    pub acceleration: f32,
    /// The point gravity pulls towards (a planet's centre).
    pub centre: Vec3,
    /// Blend t between straight down (0) and towards `centre` (1).
    pub centre_blend: f32,
}

/// The wind.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Wind {
    /// Which field.
    pub field: WindField,
    /// Acceleration at full alignment.
    pub strength: f32,
    /// Direction it blows towards, degrees around the vertical (0 = +X, 90 = +Z).
    pub direction: f32,
    /// Speed of the turbulent field's gusts downwind, units a second.
    pub gust_speed: f32,
}

impl Wind {
    /// Unit direction the wind blows towards.
    pub fn direction_vector(&self) -> Vec3 {
        let (sin, cos) = self.direction.to_radians().sin_cos();
        Vec3::new(cos, 0.0, sin)
    }
}

/// The orientation test's default guard: an edge-on blade is removed where it is
/// narrower than 2 pixels ([`NATURAL_EDGE_ON_SHARE`] of that in the natural look). On
/// the NVIDIA H100 at 1920x1080 (`grass bench --configs culls-lod --looks
/// paper,natural --frames 120`) the paper look's frame then differs from the unculled
/// one by 0.23 of 255 from the field's edge at 1 M blades (commit bd7636f), against
/// 1.19 removing every edge-on blade (commit a6b78b5; docs/culling.md, "The
/// orientation test's guard").
pub const EDGE_ON_PIXELS: f32 = 2.0;

/// The natural look's share of the orientation test's guard ([`EDGE_ON_PIXELS`] or
/// `--edge-on-pixels`): its blades stand out more from what lies behind them, so an
/// edge-on blade's removal shows more. On the NVIDIA H100 at 4 M blades from the
/// field's edge, the orientation test alone changed about as many pixels in either
/// look (0.88 % natural, 0.72 % paper) but each by 37.7 levels against 17.5. With
/// three quarters of the guard (1.5 pixels), culls + LOD differ from the unculled
/// frame by 0.34 there (paper look 0.24; the whole guard 0.42, half of it 0.26), and
/// the valley flight takes 4.92 ms (the whole guard 4.86, half of it 5.00).
pub const NATURAL_EDGE_ON_SHARE: f32 = 0.75;

/// The culling tests and their thresholds.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Culling {
    /// Which tests run.
    pub tests: CullTests,
    /// Orientation: remove a blade when |view · width direction| exceeds this.
    pub orientation_threshold: f32,
    /// Orientation: and only where it is narrower than this many pixels on screen
    /// (0: every such blade, the paper's test); in the natural look
    /// [`NATURAL_EDGE_ON_SHARE`] of it.
    pub edge_on_pixels: f32,
    /// Frustum: slack around the view volume, in clip-space units.
    pub frustum_tolerance: f32,
    /// Distance: nothing drawn beyond this.
    pub max_distance: f32,
    /// Distance: buckets thinning the field between the camera and the maximum.
    pub buckets: u32,
}

/// Screen-size level of detail.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Lod {
    /// On; off, every blade gets `most` segments.
    pub on: bool,
    /// Screen pixels per segment along a blade.
    pub pixels_per_segment: f32,
    /// Tessellation level along the blade near the camera.
    pub most: f32,
    /// Tessellation level far away.
    pub fewest: f32,
}

/// Straight segments along a blade drawn by the compute rasterizer: far blades are a
/// few pixels tall, and three segments follow their curve to a pixel.
pub const RASTER_SEGMENTS: u32 = 3;

/// Every setting of the simulation, culling, level of detail and shading.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Settings {
    /// Gravity.
    pub gravity: Gravity,
    /// Wind.
    pub wind: Wind,
    /// Collision strength lost per second (strength 1 holds a blade down fully); a
    /// negative rate is taken as 0 (strength grows only by pushes).
    pub trample_decay: f32,
    /// Seconds a cut blade takes to grow back (`sim::cut::regrown`).
    pub regrow: f32,
    /// Factor on every blade's stiffness.
    pub stiffness: f32,
    /// The sun.
    pub light: Light,
    /// Culling.
    pub cull: Culling,
    /// Level of detail.
    pub lod: Lod,
    /// How the grass is drawn.
    pub view: View,
    /// Blade shape.
    pub shape: BladeShape,
    /// Tip start k of the triangle-tip shape, 0 (root) to 1 (tip).
    pub tip_start: f32,
    /// The look.
    pub look: LookSettings,
    /// Tessellation or mesh stages.
    pub pipeline: GrassPipeline,
    /// Blades shorter than this on screen (pixels) are drawn by the compute
    /// rasterizer (`raster`); 0 turns it off.
    pub compute_raster_below: f32,
    /// A tiled field's far blades sway in the pose the wind settles them into
    /// (`sway::settled`); off, they stand at rest.
    pub far_sway: bool,
}

/// How the grass is drawn (`--pipeline`; `auto` is resolved against the device before
/// it gets here).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum GrassPipeline {
    /// One patch per blade through the tessellator (the paper's way).
    #[default]
    Tess = crate::gpu::layout::PIPELINE_TESS,
    /// Task and mesh stages building blade strips (`VK_EXT_mesh_shader`).
    Mesh = crate::gpu::layout::PIPELINE_MESH,
}

impl GrassPipeline {
    /// Both, in the order the viewer's key cycles them.
    pub const ALL: [Self; 2] = [Self::Tess, Self::Mesh];
    /// The next in [`Self::ALL`].
    pub fn next(self) -> Self {
        next_of(&Self::ALL, self)
    }
}

impl Default for Settings {
    /// The command line's defaults, on a field small enough that 40 units of view
    /// distance hold it (scenes set their own).
    fn default() -> Self {
        Self {
            gravity: Gravity {
                acceleration: 9.8,
                centre: Vec3::ZERO,
                centre_blend: 0.0,
            },
            wind: Wind {
                field: WindField::Breeze,
                strength: 7.0,
                direction: 19.3,
                gust_speed: crate::sim::simulate::DEFAULT_GUST_SPEED,
            },
            trample_decay: 0.25,
            regrow: crate::sim::simulate::DEFAULT_REGROW,
            stiffness: 1.0,
            light: Light {
                direction: Vec3::new(0.4, 0.8, 0.3).normalize(),
                ambient: 0.35,
            },
            cull: Culling {
                tests: CullTests::ALL,
                orientation_threshold: 0.9,
                edge_on_pixels: EDGE_ON_PIXELS,
                frustum_tolerance: 0.5,
                max_distance: 40.0,
                buckets: 8,
            },
            lod: Lod {
                on: true,
                pixels_per_segment: PIXELS_PER_SEGMENT,
                most: 7.0,
                fewest: 1.0,
            },
            view: View::Shaded,
            shape: BladeShape::Quadratic,
            tip_start: 0.5,
            look: LookSettings::default(),
            pipeline: GrassPipeline::Tess,
            compute_raster_below: 0.0,
            far_sway: true,
        }
    }
}

/// Where a frame is seen from: the camera reduced to what the shaders need.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Viewpoint {
    /// World to clip space (Vulkan: y down, depth 0..1).
    pub view_proj: Mat4,
    /// Camera position.
    pub position: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Height of the target in pixels.
    pub height: u32,
    /// Unit direction the camera looks along.
    pub forward: Vec3,
}

impl Viewpoint {
    /// The viewpoint of a camera given as matrices: `view` (world to eye,
    /// right-handed, looking down -z), `proj` (eye to Vulkan clip space: y down,
    /// depth 0 near to 1 far, its y scale 1 / tan(fov_y / 2), negative when it flips
    /// y) and the target's `height` in pixels.
    pub fn from_matrices(view: Mat4, proj: Mat4, height: u32) -> Self {
        let eye_to_world = view.inverse();
        let fov_y = 2.0 * (1.0 / proj.y_axis.y.abs().max(1e-6)).atan();
        Self {
            view_proj: proj * view,
            position: eye_to_world.w_axis.truncate(),
            fov_y,
            height,
            forward: -eye_to_world.z_axis.truncate().normalize_or_zero(),
        }
    }
}

impl Settings {
    /// The forces' environment with `colliders` spheres in use: gravity as the paper's
    /// D (straight down) and C (the centre), both at the one acceleration.
    pub fn environment(&self, colliders: u32) -> Environment {
        let g = &self.gravity;
        Environment {
            gravity: Vec4::new(0.0, -1.0, 0.0, g.acceleration),
            gravity_centre: g.centre.extend(g.acceleration),
            wind: self.wind.direction_vector().extend(self.wind.strength),
            centre_blend: g.centre_blend,
            wind_kind: self.wind.field as u32,
            strength_decay: self.trample_decay.max(0.0),
            stiffness_scale: self.stiffness,
            colliders,
            time: 0.0,
            far_sway: u32::from(self.far_sway),
            gust_speed: self.wind.gust_speed,
            impulses: 0,
            regrow: self.regrow,
            cutting: 0,
            pad: 0,
        }
    }

    /// The light of `look`: the paper's, or the natural look's sun.
    pub fn look_light(&self, look: Look) -> Light {
        match look {
            Look::Paper => self.light,
            Look::Natural => Light {
                direction: self.look.sun,
                ..self.light
            },
        }
    }
}

/// The sphere the shadow map covers: the scene's, or where it is larger than
/// [`SHADOW_REACH`], a sphere of that radius around the camera (not ahead of it: the
/// map must not turn with the camera), its centre snapped to a grid of a sixteenth of
/// the radius so the map does not swim as the camera moves.
pub fn shadow_sphere(scene: (Vec3, f32), camera: Vec3) -> (Vec3, f32) {
    let (centre, radius) = scene;
    if radius <= SHADOW_REACH {
        return (centre, radius);
    }
    let r = SHADOW_REACH;
    (crate::draw::look::shadow::snapped(camera, r), r)
}

#[cfg(test)]
mod tests;
