//! What is simulated and drawn: the surfaces (built in or loaded from a file), the
//! blades grown on them, and the settings that fill the frame's uniform block.

pub mod builtin;
pub mod load;

use crate::camera::OrbitCamera;
use anyhow::{Context as _, Result, bail};
use glam::{UVec4, Vec3, Vec4};
use shared::Blade;
use shared::cull;
use shared::generate::{DENSITY, side_for};
use shared::layout::{FrameUniforms, MAX_COLLIDERS};
use shared::mesh::{SurfaceMesh, scatter};
use shared::simulate::Environment;
use std::path::PathBuf;

/// The project's own glTF scene, built into the binary (regenerate with
/// `cargo run --release -p runner --example make_meadow`).
pub const MEADOW_GLB: &[u8] = include_bytes!("../../../assets/meadow.glb");

/// Which surface the grass grows on.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneKind {
    /// A flat square sized for the blade count (the course scene).
    Plane,
    /// A height field of rolling hills.
    Hills,
    /// A small sphere with gravity towards its centre.
    Planet,
    /// `assets/meadow.glb`: a terrain with a rock, loaded through the glTF path.
    Meadow,
    /// A field with stone walls and a block: the occlusion test's showcase.
    Walls,
    /// A glTF 2.0 (`.gltf`, `.glb`) or Wavefront OBJ file.
    File(PathBuf),
}

impl SceneKind {
    /// A built-in name, or else a file path.
    pub fn parse(s: &str) -> Self {
        match s {
            "plane" => Self::Plane,
            "hills" => Self::Hills,
            "planet" => Self::Planet,
            "meadow" => Self::Meadow,
            "walls" => Self::Walls,
            path => Self::File(PathBuf::from(path)),
        }
    }
}

/// How many blades to grow.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum BladeCount {
    /// This many in total, spread by area.
    Total(u32),
    /// Blades per square unit of surface.
    Density(f32),
}

/// The surfaces and the blades on them.
pub struct Scene {
    /// Name for logs and titles.
    pub name: String,
    /// The blades at rest.
    pub blades: Vec<Blade>,
    /// Where grass grows (drawn as soil).
    pub surface: SurfaceMesh,
    /// Drawn without grass (rock).
    pub bare: SurfaceMesh,
    /// Everything solid, for placing the collider ball.
    pub solid: SurfaceMesh,
    /// Gravity pulls towards this point (the planet's centre), if any.
    pub gravity_centre: Option<Vec3>,
    /// Centre and radius of a sphere around everything, blades included.
    pub bounds: (Vec3, f32),
    /// Zero-area triangles skipped while loading.
    pub degenerate: usize,
}

/// True when every vertex of `mesh` lies on one plane with the same normal: such a
/// ground can never hide grass standing on it from a camera above it.
pub fn is_flat(mesh: &SurfaceMesh) -> bool {
    let (Some(&p0), Some(&n0)) = (mesh.positions.first(), mesh.normals.first()) else {
        return true;
    };
    let scale = mesh
        .bounds()
        .map_or(1.0, |(lo, hi)| (hi - lo).length().max(1.0));
    mesh.normals.iter().all(|n| n.dot(n0) > 1.0 - 1e-5)
        && mesh
            .positions
            .iter()
            .all(|p| (*p - p0).dot(n0).abs() <= 1e-5 * scale)
}

/// A scene file, read and checked.
pub struct SceneFile {
    /// Name for logs: the path, or the built-in's name.
    pub name: String,
    /// Its surfaces.
    pub mesh: load::LoadedMesh,
}

impl SceneKind {
    /// Reads the scene's file, if it has one. Done before the device is opened, so a
    /// bad file fails fast and without a GPU.
    pub fn read(&self) -> Result<Option<SceneFile>> {
        Ok(match self {
            SceneKind::Meadow => Some(SceneFile {
                name: "meadow".into(),
                mesh: load::load_gltf_slice(MEADOW_GLB, "meadow (assets/meadow.glb)")?,
            }),
            SceneKind::File(path) => Some(SceneFile {
                name: path.display().to_string(),
                mesh: load::load(path)?,
            }),
            _ => None,
        })
    }
}

impl Scene {
    /// The scene `kind` (with its file from [`SceneKind::read`]) with `count` blades
    /// from `seed`. `check` sees the final blade count before any blade is generated
    /// (the device's limits).
    pub fn build(
        kind: &SceneKind,
        file: Option<SceneFile>,
        count: BladeCount,
        seed: u64,
        check: impl Fn(u64) -> Result<()>,
    ) -> Result<Self> {
        // Built-in surfaces are sized for the requested count at the course density.
        let total = match count {
            BladeCount::Total(n) => n,
            BladeCount::Density(_) => 1 << 13,
        };
        let none = SurfaceMesh::default;
        let (name, surface, bare, degenerate, gravity_centre) = match (kind, file) {
            (_, Some(f)) => (f.name, f.mesh.surface, f.mesh.bare, f.mesh.degenerate, None),
            (SceneKind::Hills, None) => {
                let side = side_for(total).max(16.0);
                ("hills".into(), builtin::hills(side, 96), none(), 0, None)
            }
            (SceneKind::Planet, None) => {
                let area = total as f32 / DENSITY;
                let radius = (area / (4.0 * std::f32::consts::PI)).sqrt().max(4.0);
                let sphere = builtin::sphere(Vec3::ZERO, radius, 5);
                ("planet".into(), sphere, none(), 0, Some(Vec3::ZERO))
            }
            (SceneKind::Walls, None) => {
                // At least 12 units across, so the walls have room between them.
                let side = side_for(total).max(12.0);
                let (ground, stones) = builtin::walls(side, 48);
                ("walls".into(), ground, stones, 0, None)
            }
            (SceneKind::Plane, None) => {
                let side = side_for(total);
                ("plane".into(), builtin::plane(side, 8), none(), 0, None)
            }
            (kind, None) => bail!("scene {kind:?} was not read"),
        };
        if surface.is_empty() {
            bail!("scene {name}: no surface for grass (every triangle is bare rock)");
        }
        let blades = match count {
            BladeCount::Total(n) => u64::from(n),
            BladeCount::Density(d) => shared::mesh::count_for_density(&surface, d).max(1),
        };
        check(blades)?;
        let blades = u32::try_from(blades)
            .with_context(|| format!("{blades} blades are more than this program can hold"))?;
        let mut solid = surface.clone();
        solid.append(&bare);
        let (min, max) = solid.bounds().context("scene has no triangles")?;
        let centre = 0.5 * (min + max);
        let reach = solid
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0, f32::max);
        let radius = reach + shared::generate::HEIGHT.1;
        Ok(Self {
            name,
            blades: scatter(&surface, blades, seed),
            surface,
            bare,
            solid,
            gravity_centre,
            bounds: (centre, radius),
            degenerate,
        })
    }

    /// A plane with `count` blades from `seed` (the course scene).
    pub fn plane(count: u32, seed: u64) -> Self {
        Self::build(
            &SceneKind::Plane,
            None,
            BladeCount::Total(count),
            seed,
            |_| Ok(()),
        )
        .expect("the built-in plane always builds")
    }

    /// A view that frames the scene: over a field from beyond its edge, or the whole
    /// planet.
    pub fn camera(&self) -> OrbitCamera {
        let (centre, radius) = self.bounds;
        let mut camera = OrbitCamera::framing(radius * std::f32::consts::SQRT_2);
        if self.gravity_centre.is_some() {
            camera.target = centre;
            camera.distance = radius / (0.5 * camera.fov_y).sin() * 1.05;
        } else {
            camera.target = centre + Vec3::new(0.0, 0.5, 0.0);
        }
        camera
    }

    /// Blades in the scene.
    pub fn blade_count(&self) -> u32 {
        self.blades.len() as u32
    }

    /// True when some surface can hide grass: bare rock, or ground that is not one
    /// flat plane. Without occluders the occlusion test's depth pre-pass is skipped.
    pub fn has_occluders(&self) -> bool {
        !self.bare.is_empty() || !is_flat(&self.surface)
    }
}

/// The settings of the simulation, culling, LOD and shading.
#[derive(Copy, Clone, Debug)]
pub struct Settings {
    /// Gravity, wind and collision decay (the collider count is set per frame).
    pub env: Environment,
    /// Direction towards the light (xyz, unit) and ambient (w).
    pub light: Vec4,
    /// Orientation threshold.
    pub orientation_threshold: f32,
    /// Frustum tolerance in clip units.
    pub frustum_tolerance: f32,
    /// Distance beyond which blades are culled.
    pub max_distance: f32,
    /// Distance buckets.
    pub buckets: u32,
    /// Enabled cull tests (mask of `shared::cull::*`).
    pub cull: u32,
    /// Level of detail on; off, every blade gets `lod_most`.
    pub lod: bool,
    /// LOD: screen pixels per segment along a blade.
    pub lod_pixels: f32,
    /// Tessellation level along the blade near the camera.
    pub lod_most: f32,
    /// Tessellation level far away.
    pub lod_fewest: f32,
    /// Grass view (`shared::layout::VIEW_*`).
    pub view: u32,
    /// Blade shape (`shared::shape::SHAPE_*`).
    pub shape: u32,
    /// Tip start k of the triangle-tip shape.
    pub tip_start: f32,
}

impl Settings {
    /// Defaults for `scene`: distances from its size, gravity towards its centre if
    /// it has one.
    pub fn for_scene(scene: &Scene) -> Self {
        let size = 2.0 * scene.bounds.1;
        let (centre, blend) = match scene.gravity_centre {
            Some(c) => (c.extend(9.8), 1.0),
            None => (Vec4::ZERO, 0.0),
        };
        Self {
            env: Environment {
                gravity: Vec4::new(0.0, -1.0, 0.0, 9.8),
                gravity_centre: centre,
                centre_blend: blend,
                wind: Vec4::new(1.0, 0.0, 0.35, 7.0),
                wind_kind: shared::wind::WIND_BREEZE,
                strength_decay: 0.25,
                stiffness_scale: 1.0,
                colliders: 0,
            },
            light: Vec3::new(0.4, 0.8, 0.3).normalize().extend(0.35),
            orientation_threshold: 0.9,
            frustum_tolerance: 0.5,
            max_distance: (size * 1.5).max(40.0),
            buckets: 8,
            cull: cull::ALL,
            lod: true,
            lod_pixels: shared::lod::PIXELS_PER_SEGMENT,
            lod_most: 7.0,
            lod_fewest: 1.0,
            view: shared::layout::VIEW_SHADED,
            shape: shared::shape::SHAPE_QUADRATIC,
            tip_start: 0.5,
        }
    }

    /// The uniform block of a frame seen by `camera` on a target of `extent` (width,
    /// height in pixels), with the sphere colliders `balls` (centre xyz, radius w; at
    /// most `MAX_COLLIDERS`).
    pub fn uniforms(
        &self,
        camera: &OrbitCamera,
        extent: (u32, u32),
        scene: &Scene,
        balls: &[Vec4],
    ) -> FrameUniforms {
        let aspect = extent.0 as f32 / extent.1.max(1) as f32;
        let mut colliders = [Vec4::ZERO; MAX_COLLIDERS];
        let used = balls.len().min(MAX_COLLIDERS);
        colliders[..used].copy_from_slice(&balls[..used]);
        FrameUniforms {
            view_proj: camera.view_proj(aspect),
            camera: camera.eye().extend(1.0),
            light: self.light,
            gravity: self.env.gravity,
            wind: self.env.wind,
            cull: Vec4::new(
                self.orientation_threshold,
                self.frustum_tolerance,
                self.max_distance,
                self.buckets as f32,
            ),
            lod: Vec4::new(
                shared::lod::focal_pixels(camera.fov_y, extent.1 as f32),
                self.lod_pixels,
                self.lod_most,
                if self.lod {
                    self.lod_fewest
                } else {
                    self.lod_most
                },
            ),
            blade_shape: Vec4::new(self.tip_start, 0.0, 0.0, 0.0),
            gravity_centre: self.env.gravity_centre,
            sim: Vec4::new(
                self.env.centre_blend,
                self.env.strength_decay,
                self.env.stiffness_scale,
                0.0,
            ),
            flags: UVec4::new(self.cull, self.shape, scene.blade_count(), used as u32),
            modes: UVec4::new(self.env.wind_kind, self.view, 0, 0),
            // Filled in by the renderer, which knows the target.
            hiz: Default::default(),
            colliders,
        }
    }
}
