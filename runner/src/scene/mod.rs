//! What is simulated and drawn: the surfaces (built in or loaded from a file), the
//! blades grown on them, and the default settings they call for.

pub mod builtin;
pub mod load;

use crate::camera::OrbitCamera;
use crate::renderer::Meshes;
use crate::tiles::TiledSpec;
use anyhow::{Context as _, Result, bail};
use glam::{Vec3, Vec3Swizzles};
use shared::Blade;
use shared::settings::Settings;
use shared::world::generate::{DENSITY, side_for};
use shared::world::mesh::bvh::IndexedMesh;
use shared::world::mesh::{SurfaceMesh, scatter_scaled};
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
    /// A generated valley 2 km wide with a bare path (`shared::terrain`): the tiled
    /// field's world.
    Valley,
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
            "valley" => Self::Valley,
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
    /// Which scene it is.
    pub kind: SceneKind,
    /// The blades at rest.
    pub blades: Vec<Blade>,
    /// Blades grown before the painted maps thinned them (what [`Self::rescale`]
    /// grows again).
    pub grown: u32,
    /// Where grass grows (drawn as soil).
    pub surface: SurfaceMesh,
    /// Drawn without grass (rock).
    pub bare: SurfaceMesh,
    /// Everything solid, with its hierarchy, for placing the collider ball.
    pub solid: IndexedMesh,
    /// The collider ball's mesh: a unit sphere, placed and sized per frame.
    pub ball: SurfaceMesh,
    /// Gravity pulls towards this point (the planet's centre), if any.
    pub gravity_centre: Option<Vec3>,
    /// Centre and radius of a sphere around everything, blades included.
    pub bounds: (Vec3, f32),
    /// Zero-area triangles skipped while loading.
    pub degenerate: usize,
    /// Factor on the blades' size in the natural look (`natural_blade_scale`): 1 on
    /// the built-in scenes (the course's units), smaller on loaded ones (metres).
    pub natural_scale: f32,
    /// Factor the current blades were grown with.
    pub blade_scale: f32,
    /// Seed of the blades.
    pub seed: u64,
    /// A tiled field's layout: then `blades` is empty and the blades come from tiles
    /// every frame.
    pub tiles: Option<TiledSpec>,
    /// The painted maps laid over the world (`shared::paint` words; empty for none).
    pub paint: Vec<u32>,
    /// How the species mix where the type map leaves it to the field.
    pub species: shared::species::Mix,
}

/// Side of the valley scene (units, metres in its terrain's terms): 2 km.
pub const VALLEY_SIDE: f32 = 2000.0;
/// Quads along a side of the valley's mesh (7.8 units each): what the ball rolls on
/// and the camera flies over, and what a stored field's blades grow on; it follows the
/// analytic height within 0.18 units between its vertices (the shortest hill, 41
/// units long and 1 high, curves by 0.024 a unit²: 0.024 · 7.8² / 8), the path's
/// carve excepted. The ground is drawn from the height field itself
/// (`passes::ground::GRID_CELLS`).
pub const VALLEY_CELLS: u32 = 256;

/// The blade scale of the natural look on a loaded scene of radius `radius`: glTF
/// units are metres, and meadow grass stands 0.35 to 0.7 m (0.28 times the course's
/// 1.3 to 2.5 units), but never taller than 8 % of the scene's radius, so a small
/// object (a torus of a metre) gets a lawn, not fur.
pub fn natural_blade_scale(radius: f32) -> f32 {
    let tallest = shared::world::generate::HEIGHT.1;
    (0.08 * radius / tallest).clamp(1e-3, 0.28)
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
            (SceneKind::Valley, None) => {
                let ground = builtin::valley(VALLEY_SIDE, VALLEY_CELLS);
                let rocks = builtin::valley_rocks(VALLEY_SIDE);
                ("valley".into(), ground, rocks, 0, None)
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
            BladeCount::Density(d) => shared::world::mesh::count_for_density(&surface, d).max(1),
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
        let radius = reach + shared::world::generate::HEIGHT.1;
        let natural_scale = if matches!(kind, SceneKind::Meadow | SceneKind::File(_)) {
            natural_blade_scale(reach)
        } else {
            1.0
        };
        Ok(Self {
            name,
            kind: kind.clone(),
            blades: scatter_scaled(&surface, blades, seed, 1.0),
            grown: blades,
            natural_scale,
            blade_scale: 1.0,
            seed,
            surface,
            bare,
            solid: IndexedMesh::new(solid),
            ball: builtin::sphere(Vec3::ZERO, 1.0, 3),
            gravity_centre,
            bounds: (centre, radius),
            degenerate,
            tiles: None,
            paint: Vec::new(),
            species: shared::species::Mix::GRASS,
        })
    }

    /// Makes the field a tiled one laid out by `spec` (the stored blades go).
    pub fn make_tiled(&mut self, spec: TiledSpec) {
        self.blades = Vec::new();
        self.tiles = Some(spec);
        if spec.params.terrain == shared::world::tiles::TERRAIN_MESH {
            let table =
                shared::world::surface::build(&self.surface, spec.params.size, spec.tile_blades());
            self.paint =
                shared::world::paint::with_surface(std::mem::take(&mut self.paint), &table);
        }
    }

    /// The square a stored field's painted maps are laid over: its centre (x, z) and
    /// half its side, the ground's seen from above.
    pub fn paint_square(&self) -> (glam::Vec2, f32) {
        let Some((lo, hi)) = self.surface.bounds() else {
            return (glam::Vec2::ZERO, 1.0);
        };
        let centre = 0.5 * (lo + hi);
        (centre.xz(), 0.5 * (hi.x - lo.x).max(hi.z - lo.z))
    }

    /// A stored field under its painted maps (`paint`, over [`Self::paint_square`])
    /// and its species mix: each blade kept with the probability the density map reads
    /// at its root (by a hash of its index); then, under a type or height map or a
    /// mix of species, gone from bare ground, grown as its species (the type map's, or
    /// the mix's by a second hash), its height scaled
    /// (`shared::world::paint::painted_blade`). The colour map is read on the GPU, at
    /// the same point.
    pub fn apply_paint(&mut self) {
        use shared::world::paint::{HEADER_WORDS, HEIGHT, TYPE, has, painted_blade};
        let mixed = self.species != shared::species::Mix::GRASS;
        if (self.paint.len() <= HEADER_WORDS && !mixed) || self.tiles.is_some() {
            return;
        }
        let (centre, half) = self.paint_square();
        let at = |b: &Blade| b.root().xz() - centre;
        let mut index = 0u32;
        let paint = &self.paint;
        self.blades.retain(|b| {
            index += 1;
            shared::noise::hash_unit(index.wrapping_mul(0x9e37_79b9))
                < shared::world::paint::density(paint, at(b), half)
        });
        if has(paint, TYPE) || has(paint, HEIGHT) || mixed {
            let unit = |i: usize| shared::noise::hash_unit((i as u32) ^ 0x27d4_eb2f);
            let mix = self.species;
            self.blades = self
                .blades
                .iter()
                .enumerate()
                .filter_map(|(i, b)| painted_blade(b, paint, at(b), half, (mix, unit(i))))
                .collect();
        }
    }

    /// The ground's lowest and highest points.
    pub fn ground_range(&self) -> (f32, f32) {
        self.surface
            .bounds()
            .map_or((0.0, 0.0), |(lo, hi)| (lo.y, hi.y))
    }

    /// Grows the blades again (same seed, same roots) at `scale` times the course's
    /// size; true when it did. Nothing happens when they already are that size, or on
    /// a tiled field (its tiles keep the size they were laid out with: it stores no
    /// blades to grow).
    pub fn rescale(&mut self, scale: f32) -> bool {
        if scale == self.blade_scale || self.tiles.is_some() {
            return false;
        }
        self.blade_scale = scale;
        self.regrow();
        true
    }

    /// A stored field's blades grown again from the seed at the current blade scale,
    /// under the painted maps and the species mix.
    fn regrow(&mut self) {
        self.blades = scatter_scaled(&self.surface, self.grown, self.seed, self.blade_scale);
        self.apply_paint();
    }

    /// Grows the species `mix` from now on: a stored field's blades grown again (same
    /// seed, same roots, so the same count) under it; a tiled field's tiles take it
    /// when they are made (`TileParams::species`). True when it changed.
    pub fn set_species(&mut self, mix: shared::species::Mix) -> bool {
        if mix == self.species {
            return false;
        }
        self.species = mix;
        if let Some(tiles) = &mut self.tiles {
            tiles.params.species = mix.weights;
        } else {
            self.regrow();
        }
        true
    }

    /// The blade scale `look` asks for on this scene.
    pub fn scale_for(&self, look: shared::settings::Look) -> f32 {
        match look {
            shared::settings::Look::Paper => 1.0,
            shared::settings::Look::Natural => self.natural_scale,
        }
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
        if self.kind == SceneKind::Valley {
            return valley_camera(0.0);
        }
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

    /// What the renderer draws of this scene.
    pub fn meshes(&self) -> Meshes<'_> {
        Meshes {
            blades: &self.blades,
            surface: &self.surface,
            bare: &self.bare,
            ball: &self.ball,
            has_occluders: self.has_occluders(),
            tiles: self.tiles,
            paint: &self.paint,
            paint_square: self.paint_square(),
            valley: (self.kind == SceneKind::Valley).then_some(0.5 * VALLEY_SIDE),
        }
    }

    /// Blades in the scene: a tiled field's room for them.
    pub fn blade_count(&self) -> u32 {
        match &self.tiles {
            Some(spec) => spec.capacity(),
            None => self.blades.len() as u32,
        }
    }

    /// The default settings on this scene: the distance test's reach from its size,
    /// gravity towards its centre if it has one.
    pub fn settings(&self) -> Settings {
        let mut settings = Settings::default();
        settings.cull.max_distance = (2.0 * self.bounds.1 * 1.5).max(40.0);
        settings.look.scene = self.bounds;
        // Clumps and shadow casters in the blades' own measure.
        settings.look.clump_size *= self.natural_scale;
        settings.look.caster_distance *= self.natural_scale;
        // A ground under a sky (not a planet, not a closed object such as a torus)
        // goes on to the horizon in the natural look.
        let ground = self.gravity_centre.is_none() && self.surface.mean_upness() > 0.5;
        settings.look.ground_level = if ground {
            self.surface.bounds().map(|(min, _)| min.y)
        } else {
            None
        };
        if let Some(centre) = self.gravity_centre {
            settings.gravity.centre = centre;
            settings.gravity.centre_blend = 1.0;
        }
        settings
    }

    /// True when some surface can hide grass: bare rock, or ground that is not one
    /// flat plane. Without occluders the occlusion test's depth pre-pass is skipped.
    pub fn has_occluders(&self) -> bool {
        !self.bare.is_empty() || !is_flat(&self.surface)
    }
}

/// The valley's camera `travelled` units along its path (`shared::terrain`): 5 units
/// above the ground beside the path (over the blades, 2.5 at most), looking down the
/// path and a little down, the far plane at the valley's far side.
pub fn valley_camera(travelled: f32) -> OrbitCamera {
    use shared::world::terrain::{path_centre, valley_height};
    let z = -travelled;
    let (x, slope) = path_centre(z);
    let eye = glam::Vec2::new(x + 3.0, z);
    // Looking along −z, following the path's bend.
    let ahead = glam::Vec2::new(-slope, -1.0).normalize();
    let distance = 30.0;
    let target2 = eye + ahead * distance;
    let eye_height = valley_height(eye) + 5.0;
    let target = Vec3::new(target2.x, valley_height(target2) + 1.0, target2.y);
    let mut camera = OrbitCamera::framing(VALLEY_SIDE);
    camera.target = target;
    camera.distance = distance;
    let flat = (eye - target2).length();
    camera.pitch = ((eye_height - target.y) / flat).atan().clamp(0.02, 1.5);
    camera.yaw = (eye.x - target2.x).atan2(eye.y - target2.y);
    camera.far = VALLEY_SIDE;
    camera
}

/// The tiled field's layout on `scene`: on a GPU, tiles of 64² blades at
/// the course's density (36 a square unit), every blade kept to 48 units, a pool of
/// 96 tiles (393,216 blades simulated) for those within 16 units, and room for 4 M
/// far blades out to 800 units; on a `software` device, tiles of 32² blades, every
/// blade kept to 4.5 units, 16 pool tiles for those within 3 units, and room for
/// 65,536 far blades out to 120 (lavapipe's grass pass at 1280x720 took 41 ms for
/// the 3,338 blades drawn when every blade was kept to 6 units, 21 ms for 895 at 3).
pub fn tiled_spec(scene: &Scene, software: bool, scale: f32) -> TiledSpec {
    use shared::world::tiles::{TERRAIN_FLAT, TERRAIN_MESH, TERRAIN_VALLEY, TileParams};
    let terrain = match scene.kind {
        SceneKind::Valley => TERRAIN_VALLEY,
        SceneKind::Plane => TERRAIN_FLAT,
        _ => TERRAIN_MESH,
    };
    // The plane and the valley are centred on the origin, at the course's size.
    let scale = if terrain == TERRAIN_MESH { scale } else { 1.0 };
    let (lo, hi) = scene.surface.bounds().unwrap_or_default();
    let half_extent = 0.5 * (hi.x - lo.x).max(hi.z - lo.z);
    let centre = if terrain == TERRAIN_MESH {
        shared::glam::Vec2::new(0.5 * (lo.x + hi.x), 0.5 * (lo.z + hi.z))
    } else {
        shared::glam::Vec2::ZERO
    };
    let params = TileParams {
        size: if software { 16.0 / 3.0 } else { 32.0 / 3.0 } * scale,
        per_side: if software { 32 } else { 64 },
        seed: scene.seed as u32,
        full_distance: if software { 4.5 } else { 48.0 } * scale,
        terrain,
        half_extent,
        centre,
        blade_scale: scale,
        species: scene.species.weights,
        ..TileParams::default()
    };
    let area = if terrain == TERRAIN_MESH {
        f64::from(scene.surface.area())
    } else {
        (2.0 * f64::from(half_extent)).powi(2)
    };
    TiledSpec {
        params,
        pool_tiles: if software { 16 } else { 96 },
        pool_radius: if software { 3.0 } else { 16.0 } * scale,
        far_blades: if software { 1 << 16 } else { 1 << 22 },
        reach: if software { 120.0 } else { 800.0 } * scale,
        ground: scene.ground_range(),
        area,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loaded_scenes_get_grass_of_their_size() {
        // A 24 m meadow: meadow grass, 0.28 times the course's blades (0.7 m at most).
        assert!((natural_blade_scale(17.0) - 0.28).abs() < 1e-6);
        // A torus of a metre: blades at most 8 % of its radius.
        let torus = natural_blade_scale(1.4);
        assert!((torus * shared::world::generate::HEIGHT.1 - 0.08 * 1.4).abs() < 1e-6);
    }

    /// A stored field grows again once per new size; a tiled one stores no blades
    /// and is never regrown (the viewer replaced its blades by none when the look
    /// changed on a tiled meadow, and failed).
    #[test]
    fn only_stored_fields_grow_again() {
        let mut scene = Scene::plane(64, 1);
        assert!(scene.rescale(0.5));
        assert_eq!(scene.blades.len(), 64);
        assert!(!scene.rescale(0.5));
        let params = shared::world::tiles::TileParams {
            size: 4.0,
            per_side: 16,
            terrain: shared::world::tiles::TERRAIN_FLAT,
            half_extent: 8.0,
            ..Default::default()
        };
        let spec = TiledSpec::flat_for_tests(params, 4, 1 << 12);
        scene.make_tiled(spec);
        assert!(!scene.rescale(1.0));
        assert!(scene.blades.is_empty());
        assert_eq!(scene.blade_scale, 0.5);
        // A tiled field takes a new mix in its tiles' parameters.
        let mix = shared::species::Mix::new([1, 0, 1, 0]);
        assert!(scene.set_species(mix));
        assert_eq!(scene.tiles.unwrap().params.species, mix.weights);
        assert!(scene.blades.is_empty());
    }

    /// A stored field grows again under a new mix of species: the same roots (the
    /// same count), the mix's species, and back to grass alone as it was.
    #[test]
    fn a_stored_field_grows_again_as_its_species() {
        use shared::species::{self, Mix};
        let mut scene = Scene::plane(2048, 3);
        let grass = scene.blades.clone();
        assert!(!scene.set_species(Mix::GRASS));
        assert!(scene.set_species(Mix::new([1, 0, 1, 1])));
        assert_eq!(scene.blades.len(), grass.len());
        let count = |s: u32| scene.blades.iter().filter(|b| species::of(b) == s).count();
        let (flowers, seeds) = (count(species::FLOWER), count(species::SEED_GRASS));
        assert!(flowers > 500 && seeds > 500, "{flowers} {seeds}");
        assert!(
            scene
                .blades
                .iter()
                .zip(&grass)
                .all(|(a, b)| a.root() == b.root())
        );
        assert!(scene.set_species(Mix::GRASS));
        assert_eq!(scene.blades, grass);
    }
}
