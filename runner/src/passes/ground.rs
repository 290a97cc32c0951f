//! The surfaces: the scene's ground mesh and the colliders, from one vertex and
//! one index buffer, textured and lit in the fragment stage.

use super::by_target::{ByTarget, DrawTarget};
use crate::field::{Field, PUSH_CONSTANTS};
use crate::shaders;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::pipeline::{GraphicsDesc, Pipeline, ShaderModules, vec4_vertex_input};
use crate::vulkan::{Buffer, Context, Recorder};
use anyhow::Result;
use ash::vk;
use glam::{Mat4, Vec4};
use shared::cull::tile::box_in_view;
use shared::gpu::layout::{GROUND_GRID, GROUND_MESH, SurfacePush, SurfaceVertex};
use shared::sim::collide::{COLLIDER_BOX, COLLIDER_CAPSULE, COLLIDER_SPHERE, Collider};
use shared::world::mesh::SurfaceMesh;
use std::sync::Arc;

/// A range of the index buffer drawn with one call.
#[derive(Copy, Clone, Debug, Default)]
struct Range {
    first_index: u32,
    index_count: u32,
    vertex_offset: i32,
}

/// Meshes gathered into one vertex and one index array, one range each.
#[derive(Default)]
struct MeshSet {
    vertices: Vec<SurfaceVertex>,
    indices: Vec<u32>,
}

impl MeshSet {
    fn add(&mut self, mesh: &SurfaceMesh, material: u32) -> Range {
        let range = Range {
            first_index: self.indices.len() as u32,
            index_count: 3 * mesh.triangles.len() as u32,
            vertex_offset: self.vertices.len() as i32,
        };
        self.vertices
            .extend(
                mesh.positions
                    .iter()
                    .zip(&mesh.normals)
                    .map(|(p, n)| SurfaceVertex {
                        position: p.extend(material as f32),
                        normal: n.extend(0.0),
                    }),
            );
        self.indices.extend(mesh.triangles.iter().flatten());
        range
    }
}

/// The surface pipelines and their meshes.
pub struct GroundPass {
    /// The lit surfaces, for each draw target.
    pipeline: ByTarget<Pipeline>,
    /// Depth only, for the occluder pre-pass.
    depth_only: Pipeline,
    vertices: Buffer,
    indices: Buffer,
    ground: Vec<Range>,
    ball: Range,
    /// A coarse unit sphere (80 triangles), stretched over a capsule or a box: the
    /// walkers, a thousand of them, at the ball's 1,280 triangles each would cost an
    /// NVIDIA H100 more than a millisecond of its raster units.
    coarse: Range,
    /// The camera's view-projection this frame: colliders outside its view are not
    /// drawn.
    view_proj: Mat4,
    /// The valley's ground grid, drawn around the camera instead of the ground
    /// meshes: its range and the world's half extent.
    grid: Option<(Range, f32)>,
    /// Where the grid is centred this frame ([`GroundPass::follow`]).
    centre: glam::Vec3,
}

/// Cells along a side of the valley's ground grid on a GPU (51,200 triangles) and on
/// a software device (3,200: lavapipe spent 10 ms of a 720p frame on 8,192 ground
/// triangles, 30 ms on 131,072).
pub const GRID_CELLS: (u32, u32) = (160, 40);
/// Width of the ground grid's cells at the camera (units).
pub const GRID_SPACING: f32 = 0.5;

impl GroundPass {
    /// Uploads `ground` (each mesh with its `shade::MATERIAL_*`) and the unit `ball`,
    /// and builds the pipeline for colour targets of `color_format` with `samples`
    /// samples. With `valley` (the world's half extent) the ground is the valley's
    /// grid around the camera instead (soil).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        module: &ShaderModules,
        field: &Field,
        color_format: vk::Format,
        ground: &[(&SurfaceMesh, u32)],
        ball: &SurfaceMesh,
        valley: Option<f32>,
    ) -> Result<Self> {
        let mut set = MeshSet::default();
        // Over the valley its grid takes the soil's place; its rocks stay meshes.
        let ground = ground
            .iter()
            .filter(|(mesh, material)| {
                !mesh.is_empty()
                    && !(valley.is_some() && *material == shared::draw::shade::MATERIAL_SOIL)
            })
            .map(|(mesh, material)| set.add(mesh, *material))
            .collect();
        let grid = valley.map(|half| {
            let cells = if ctx.is_software() {
                GRID_CELLS.1
            } else {
                GRID_CELLS.0
            };
            // From anywhere in the world to its farthest corner.
            let reach = 2.0 * std::f32::consts::SQRT_2 * half;
            let mesh = crate::scene::builtin::ground_grid(cells, GRID_SPACING, reach);
            (set.add(&mesh, shared::draw::shade::MATERIAL_SOIL), half)
        });
        let ball = set.add(ball, shared::draw::shade::MATERIAL_BALL);
        let coarse = crate::scene::builtin::sphere(glam::Vec3::ZERO, 1.0, 1);
        let coarse = set.add(&coarse, shared::draw::shade::MATERIAL_BALL);
        use vk::BufferUsageFlags as U;
        let vertices = Buffer::upload(
            ctx,
            pool,
            "surface vertices",
            &set.vertices,
            U::VERTEX_BUFFER,
        )?;
        let indices = Buffer::upload(ctx, pool, "surface indices", &set.indices, U::INDEX_BUFFER)?;
        let target = DrawTarget::single(color_format);
        let pipeline = ByTarget::new(target, Self::pipeline(ctx, module, field, target)?);
        let depth_only = DrawTarget::single(vk::Format::UNDEFINED);
        let depth_only = Self::pipeline(ctx, module, field, depth_only)?;
        Ok(Self {
            pipeline,
            depth_only,
            vertices,
            indices,
            ground,
            ball,
            coarse,
            view_proj: Mat4::IDENTITY,
            grid,
            centre: glam::Vec3::ZERO,
        })
    }

    /// Centres the valley's grid under `camera` for the frame's draws: on the
    /// centre cells' lattice, so near vertices keep their place as the camera moves.
    pub fn follow(&mut self, camera: glam::Vec3, view_proj: Mat4) {
        self.centre = (camera / GRID_SPACING).round() * GRID_SPACING;
        self.view_proj = view_proj;
    }

    /// The lit surface pipeline for `target` (colour `UNDEFINED`: depth only); a
    /// motion target is kept as it is (the resolve finds the ground's motion from the
    /// depth).
    fn pipeline(
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<Pipeline> {
        let color_format = target.format;
        use vk::ShaderStageFlags as St;
        // Position and material, normal: two vec4 at locations 0 and 1.
        let input = vec4_vertex_input::<SurfaceVertex>();
        let stages = [
            (St::VERTEX, shaders::GROUND_VS),
            (St::FRAGMENT, shaders::GROUND_FS),
        ];
        let depth = super::DEPTH_FORMAT;
        let stages = if color_format == vk::Format::UNDEFINED {
            &stages[..1]
        } else {
            &stages[..]
        };
        let mut desc =
            GraphicsDesc::opaque(module, stages, &field.layout, &input, color_format, depth);
        desc.samples = target.samples;
        desc.second_color = target.second_color(false);
        desc.depth_compare = target.depth_compare();
        Pipeline::graphics(ctx, &desc)
    }

    /// Uses the lit pipeline for `target`, made the first time it is asked for. No
    /// frame may be in flight.
    pub fn retarget(
        &mut self,
        ctx: &Arc<Context>,
        module: &ShaderModules,
        field: &Field,
        target: DrawTarget,
    ) -> Result<()> {
        self.pipeline
            .select(target, || Self::pipeline(ctx, module, field, target))
    }

    /// Records the ground and each of the `colliders` in the camera's view
    /// ([`collider_model`]) inside the frame's rendering scope.
    pub fn record(&self, rec: &Recorder, field: &Field, colliders: &[Collider]) {
        let seen = |c: &Collider| {
            let (lo, hi) = c.bounds();
            box_in_view(lo, hi, self.view_proj)
        };
        self.record_with(self.pipeline.current(), rec, field, (colliders, &seen));
    }

    /// Records the ground's depth alone (the occluders of the occlusion test) inside
    /// a depth-only rendering scope.
    pub fn record_occluders(&self, rec: &Recorder, field: &Field) {
        self.record_with(&self.depth_only, rec, field, (&[], &|_| false));
    }

    /// Records the ground and the `colliders` `drawn` says with `pipeline` (one
    /// taking the surface vertices).
    pub fn record_with(
        &self,
        pipeline: &Pipeline,
        rec: &Recorder,
        field: &Field,
        (colliders, drawn): (&[Collider], &Drawn<'_>),
    ) {
        let graphics = vk::PipelineBindPoint::GRAPHICS;
        let layout = field.layout.layout;
        rec.bind_pipeline(graphics, pipeline.pipeline, layout, field.descriptors.set);
        rec.bind_vertex_buffer(self.vertices.buffer);
        rec.bind_index_buffer(self.indices.buffer);
        let draw = |range: &Range, model: Mat4, terrain: Vec4| {
            let push = SurfacePush { model, terrain };
            rec.push_constants(layout, PUSH_CONSTANTS.0, bytemuck::bytes_of(&push));
            rec.draw_indexed(range.first_index, range.index_count, range.vertex_offset);
        };
        let mesh = Vec4::new(GROUND_MESH, 0.0, 0.0, 0.0);
        for range in &self.ground {
            draw(range, Mat4::IDENTITY, mesh);
        }
        if let Some((range, half)) = &self.grid {
            let centre = glam::Vec3::new(self.centre.x, 0.0, self.centre.z);
            let terrain = Vec4::new(GROUND_GRID, *half, 0.0, 0.0);
            draw(range, Mat4::from_translation(centre), terrain);
        }
        for c in colliders.iter().filter(|c| drawn(c)) {
            let range = if c.kind == COLLIDER_SPHERE {
                &self.ball
            } else {
                &self.coarse
            };
            draw(range, collider_model(c), mesh);
        }
    }
}

/// Which colliders a pass draws.
pub type Drawn<'a> = dyn Fn(&Collider) -> bool + 'a;

/// The model matrix of a unit sphere drawn for collider `c`: a sphere as itself, a
/// capsule as the ellipsoid through its ends and around its radius, a box as the
/// ellipsoid through its faces' centres.
pub fn collider_model(c: &Collider) -> Mat4 {
    let a = c.a.truncate();
    let r = c.a.w;
    match c.kind {
        COLLIDER_CAPSULE => {
            let b = c.b.truncate();
            let axis = b - a;
            let turn =
                glam::Quat::from_rotation_arc(glam::Vec3::Y, axis.normalize_or(glam::Vec3::Y));
            let half = glam::Vec3::new(r, 0.5 * axis.length() + r, r);
            Mat4::from_scale_rotation_translation(half, turn, (a + b) * 0.5)
        }
        COLLIDER_BOX => {
            let turn = glam::Quat::from_vec4(c.rotation);
            let half = c.b.truncate() + glam::Vec3::splat(r);
            Mat4::from_scale_rotation_translation(half, turn, a)
        }
        _ => Mat4::from_translation(a) * Mat4::from_scale(glam::Vec3::splat(r)),
    }
}
