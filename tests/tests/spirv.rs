//! The compiled SPIR-V modules, one per entry point: each valid for Vulkan, tessellation
//! levels decorated `Patch`, and their interface (bindings, push constants, workgroup sizes, entry points) equal
//! to what the runner creates.

use ash::vk;
use rspirv::dr::{Module, Operand};
use rspirv::spirv::{BuiltIn, Decoration, ExecutionMode, ExecutionModel, Op, StorageClass};
use runner::field::{BINDINGS, PUSH_CONSTANTS};
use runner::passes::{overlay, shade, temporal, tonemap};
use runner::shaders;
use runner::vulkan::descriptors::BindingSpec;
use shared::draw::look::shadow::CASTERS_PER_GROUP;
use shared::gpu::layout;
use shared::sim::grid::ColliderGrid;
use std::collections::{BTreeMap, BTreeSet};

/// Every (entry point, its module).
fn modules() -> Vec<(&'static str, Module)> {
    shaders::MODULES
        .iter()
        .map(|&(entry, spirv)| {
            let m = rspirv::dr::load_bytes(spirv)
                .unwrap_or_else(|e| panic!("parse the module of {entry}: {e}"));
            (entry, m)
        })
        .collect()
}

/// The module of `entry`.
fn module_of(entry: &str) -> Module {
    let spirv = shaders::module(entry).unwrap_or_else(|| panic!("no module for {entry}"));
    rspirv::dr::load_bytes(spirv).expect("parse the shader module")
}

fn decorations(m: &Module, id: u32) -> Vec<&[Operand]> {
    m.annotations
        .iter()
        .filter(|i| i.class.opcode == Op::Decorate && i.operands[0] == Operand::IdRef(id))
        .map(|i| &i.operands[1..])
        .collect()
}

fn decoration_value(m: &Module, id: u32, which: Decoration) -> Option<u32> {
    decorations(m, id).into_iter().find_map(|ops| match ops {
        [Operand::Decoration(d), Operand::LiteralBit32(v)] if *d == which => Some(*v),
        _ => None,
    })
}

/// Entry point name → (execution model, interface ids, function id).
fn entry_points(m: &Module) -> BTreeMap<String, (ExecutionModel, Vec<u32>, u32)> {
    m.entry_points
        .iter()
        .map(|e| {
            let model = match e.operands[0] {
                Operand::ExecutionModel(model) => model,
                _ => unreachable!(),
            };
            let function = e.operands[1].unwrap_id_ref();
            let name = e.operands[2].unwrap_literal_string().to_string();
            let interface = e.operands[3..].iter().map(|o| o.unwrap_id_ref()).collect();
            (name, (model, interface, function))
        })
        .collect()
}

#[test]
fn every_module_passes_spirv_val_for_vulkan() {
    for &(entry, spirv) in shaders::MODULES {
        let path = std::env::temp_dir().join(format!("grass-{}.spv", std::process::id()));
        std::fs::write(&path, spirv).unwrap();
        let out = std::process::Command::new("spirv-val")
            .args(["--target-env", "vulkan1.3"])
            .arg(&path)
            .output()
            .expect("run spirv-val (Debian/Ubuntu: apt-get install spirv-tools)");
        let _ = std::fs::remove_file(&path);
        assert!(
            out.status.success(),
            "spirv-val rejected the module of {entry}:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// One entry point, one stage, in each module: what GPU-assisted validation needs.
#[test]
fn each_module_holds_its_entry_point_alone() {
    assert!(
        shaders::MODULES.len() >= 16,
        "{} modules",
        shaders::MODULES.len()
    );
    for (entry, m) in modules() {
        let names: Vec<String> = entry_points(&m).into_keys().collect();
        assert_eq!(names, [entry], "the module of {entry}");
    }
}

#[test]
fn tessellation_levels_are_patch_decorated() {
    let mut seen = BTreeSet::new();
    for (_, m) in modules() {
        for i in &m.annotations {
            if let [
                Operand::IdRef(id),
                Operand::Decoration(Decoration::BuiltIn),
                Operand::BuiltIn(b @ (BuiltIn::TessLevelOuter | BuiltIn::TessLevelInner)),
            ] = i.operands.as_slice()
            {
                let patch = decorations(&m, *id)
                    .iter()
                    .any(|ops| *ops == [Operand::Decoration(Decoration::Patch)]);
                assert!(patch, "{b:?} (id {id}) lacks the Patch decoration");
                seen.insert(format!("{b:?}"));
            }
        }
    }
    assert_eq!(
        seen.len(),
        2,
        "both tessellation levels must be declared: {seen:?}"
    );
}

#[test]
fn every_entry_point_the_runner_uses_exists_with_its_stage() {
    let entries: BTreeMap<_, _> = modules()
        .iter()
        .flat_map(|(_, m)| entry_points(m))
        .collect();
    let expected = [
        (shaders::SIMULATE_CULL, ExecutionModel::GLCompute),
        (shaders::SIMULATE_CULL_NATURAL, ExecutionModel::GLCompute),
        (shaders::WRITE_DRAWS, ExecutionModel::GLCompute),
        (shaders::GRASS_VS, ExecutionModel::Vertex),
        (shaders::GRASS_TCS, ExecutionModel::TessellationControl),
        (shaders::GRASS_TES, ExecutionModel::TessellationEvaluation),
        (shaders::GRASS_FS, ExecutionModel::Fragment),
        (shaders::GRASS_LOD_FS, ExecutionModel::Fragment),
        (shaders::GROUND_VS, ExecutionModel::Vertex),
        (shaders::GROUND_FS, ExecutionModel::Fragment),
        (shaders::BUILD_HIZ, ExecutionModel::GLCompute),
        (shaders::COPY_BLADES, ExecutionModel::GLCompute),
        (shaders::OVERLAY_VS, ExecutionModel::Vertex),
        (shaders::OVERLAY_FS, ExecutionModel::Fragment),
        (shaders::THROUGHPUT_VS, ExecutionModel::Vertex),
        (shaders::THROUGHPUT_TCS, ExecutionModel::TessellationControl),
        (
            shaders::THROUGHPUT_TES,
            ExecutionModel::TessellationEvaluation,
        ),
        (shaders::THROUGHPUT_FS, ExecutionModel::Fragment),
        (shaders::SHADOW_SURFACE_VS, ExecutionModel::Vertex),
        (shaders::SHADOW_SURFACE_NEAR_VS, ExecutionModel::Vertex),
        (shaders::RASTER_CASTERS, ExecutionModel::GLCompute),
        (shaders::RASTER_NEAR_CASTERS, ExecutionModel::GLCompute),
        (shaders::NATURAL_VS, ExecutionModel::Vertex),
        (shaders::CLUMP_BLADES, ExecutionModel::GLCompute),
        (shaders::NATURAL_TCS, ExecutionModel::TessellationControl),
        (shaders::NATURAL_TES, ExecutionModel::TessellationEvaluation),
        (shaders::NATURAL_FS, ExecutionModel::Fragment),
        (shaders::NATURAL_VIEW_FS, ExecutionModel::Fragment),
        (
            shaders::NATURAL_VIS_TES,
            ExecutionModel::TessellationEvaluation,
        ),
        (shaders::NATURAL_VIS_FS, ExecutionModel::Fragment),
        (shaders::NATURAL_VIS_MESH, ExecutionModel::MeshEXT),
        (shaders::SHADE_NATURAL, ExecutionModel::GLCompute),
        (
            shaders::GRASS_TAA_TES,
            ExecutionModel::TessellationEvaluation,
        ),
        (shaders::GRASS_TAA_FS, ExecutionModel::Fragment),
        (shaders::PAPER_TAA_MESH, ExecutionModel::MeshEXT),
        (shaders::RESOLVE_TAA, ExecutionModel::GLCompute),
        (shaders::TONEMAP_VS, ExecutionModel::Vertex),
        (shaders::TONEMAP_FS, ExecutionModel::Fragment),
        (shaders::PAPER_MESH, ExecutionModel::MeshEXT),
        (shaders::NATURAL_MESH, ExecutionModel::MeshEXT),
    ];
    for (name, model) in expected {
        let found = entries.get(name).map(|e| e.0);
        assert_eq!(
            found,
            Some(model),
            "entry point {name}; the module has {:?}",
            entries.keys()
        );
    }
}

fn stage_of(model: ExecutionModel) -> vk::ShaderStageFlags {
    match model {
        ExecutionModel::GLCompute => vk::ShaderStageFlags::COMPUTE,
        ExecutionModel::Vertex => vk::ShaderStageFlags::VERTEX,
        ExecutionModel::TessellationControl => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        ExecutionModel::TessellationEvaluation => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        ExecutionModel::Fragment => vk::ShaderStageFlags::FRAGMENT,
        ExecutionModel::TaskEXT => vk::ShaderStageFlags::TASK_EXT,
        ExecutionModel::MeshEXT => vk::ShaderStageFlags::MESH_EXT,
        other => panic!("unexpected stage {other:?}"),
    }
}

/// The type a pointer variable points to, and its storage class.
fn pointee(m: &Module, var: u32) -> Option<(StorageClass, u32)> {
    let var = m
        .types_global_values
        .iter()
        .find(|i| i.result_id == Some(var))?;
    if var.class.opcode != Op::Variable {
        return None;
    }
    let ptr = m
        .types_global_values
        .iter()
        .find(|i| i.result_id == var.result_type)?;
    match ptr.operands.as_slice() {
        [Operand::StorageClass(sc), Operand::IdRef(ty)] => Some((*sc, *ty)),
        _ => None,
    }
}

/// Size in bytes of a struct type of 32-bit scalars, vectors, matrices and structs
/// (what the push-constant blocks are made of), from its member offsets.
fn struct_size(m: &Module, ty: u32) -> u32 {
    let scalar_size = |t: u32| -> u32 {
        let d = type_def(m, t);
        match d.class.opcode {
            Op::TypeInt | Op::TypeFloat => 4,
            Op::TypeVector => 4 * d.operands[1].unwrap_literal_bit32(),
            Op::TypeMatrix => 16 * d.operands[1].unwrap_literal_bit32(),
            // rust-gpu wraps a push-constant block in a one-member struct.
            Op::TypeStruct => struct_size(m, t),
            other => panic!("push-constant member of type {other:?}"),
        }
    };
    members(m, ty)
        .iter()
        .map(|&(member, offset)| offset + scalar_size(member))
        .max()
        .unwrap_or(0)
}

/// The descriptor bindings and push-constant range of the pipeline layout the runner
/// builds for entry point `name`: the overlay's own, or the field's.
fn runner_layout(name: &str) -> (&'static [BindingSpec], (vk::ShaderStageFlags, u32)) {
    if name == shaders::OVERLAY_VS || name == shaders::OVERLAY_FS {
        let push = size_of::<layout::OverlayPush>() as u32;
        (&overlay::BINDINGS, (vk::ShaderStageFlags::VERTEX, push))
    } else if name == shaders::TONEMAP_VS || name == shaders::TONEMAP_FS {
        (&tonemap::BINDINGS, tonemap::PUSH_CONSTANTS)
    } else if name == shaders::RESOLVE_TAA {
        // The temporal resolve's own set, no push constants.
        (&temporal::BINDINGS, (vk::ShaderStageFlags::COMPUTE, 0))
    } else if name == shaders::CUBE_VS || name == shaders::CUBE_FS {
        // The embedding example's own pipeline: no descriptors, one push range.
        let push = size_of::<shared::example::cube::CubePush>() as u32;
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        (&[], (stages, push))
    } else {
        (&BINDINGS, PUSH_CONSTANTS)
    }
}

#[test]
fn descriptor_bindings_and_push_constants_match_the_runner() {
    for (_, m) in modules() {
        for (name, (model, interface, _)) in entry_points(&m) {
            let stage = stage_of(model);
            let (bindings, push_range) = runner_layout(&name);
            // SPIR-V 1.4+: the interface lists every global the entry point uses.
            for &var in &interface {
                let Some((class, ty)) = pointee(&m, var) else {
                    continue;
                };
                match class {
                    StorageClass::Uniform
                    | StorageClass::StorageBuffer
                    | StorageClass::UniformConstant => {
                        let set = decoration_value(&m, var, Decoration::DescriptorSet);
                        let binding = decoration_value(&m, var, Decoration::Binding);
                        // The shading after the draw has a set of its own after the
                        // field's.
                        let bindings = match set {
                            Some(1) if name == shaders::SHADE_NATURAL => &shade::BINDINGS[..],
                            _ => {
                                assert_eq!(set, Some(layout::SET), "{name}: set of id {var}");
                                bindings
                            }
                        };
                        let binding = binding.expect("binding decoration");
                        let spec = bindings
                        .iter()
                        .find(|b| b.binding == binding)
                        .unwrap_or_else(|| {
                            panic!(
                                "{name} uses binding {binding}, which the runner does not create"
                            )
                        });
                        let ty_expected = match class {
                            StorageClass::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
                            StorageClass::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
                            _ => match type_def(&m, ty).class.opcode {
                                // Sampled 2: a storage image.
                                Op::TypeImage
                                    if type_def(&m, ty).operands.get(5)
                                        == Some(&Operand::LiteralBit32(2)) =>
                                {
                                    vk::DescriptorType::STORAGE_IMAGE
                                }
                                Op::TypeImage => vk::DescriptorType::SAMPLED_IMAGE,
                                Op::TypeSampler => vk::DescriptorType::SAMPLER,
                                _ => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                            },
                        };
                        assert_eq!(spec.ty, ty_expected, "{name}: type of binding {binding}");
                        assert!(
                            spec.stages.contains(stage),
                            "{name}: binding {binding} not visible to {stage:?}"
                        );
                    }
                    StorageClass::PushConstant => {
                        let size = struct_size(&m, ty);
                        assert!(
                            push_range.0.contains(stage),
                            "{name}: push constants not in its stage"
                        );
                        assert!(
                            size <= push_range.1,
                            "{name}: push block of {size} bytes, runner range {}",
                            push_range.1
                        );
                        let expected = match name.as_str() {
                            n if n == shaders::SIMULATE_CULL
                                || n == shaders::SIMULATE_CULL_NATURAL =>
                            {
                                size_of::<layout::SimulatePush>()
                            }
                            n if n == shaders::WRITE_DRAWS => size_of::<layout::ChunkPush>(),
                            n if n == shaders::GROUND_VS => size_of::<layout::SurfacePush>(),
                            n if n == shaders::SHADOW_SURFACE_VS
                                || n == shaders::SHADOW_SURFACE_NEAR_VS =>
                            {
                                size_of::<layout::SurfacePush>()
                            }
                            n if n == shaders::TONEMAP_FS || n == shaders::TONEMAP_VS => {
                                size_of::<layout::ToneMapPush>()
                            }
                            n if n == shaders::BUILD_HIZ => size_of::<layout::HiZPush>(),
                            n if n == shaders::RASTER_PREPARE_MS => {
                                size_of::<layout::PreparePush>()
                            }
                            n if n == shaders::GENERATE_TILE
                                || n == shaders::GENERATE_POOL_TILE =>
                            {
                                size_of::<shared::gpu::layout::TilePush>()
                            }
                            n if n == shaders::SELECT_TILES
                                || n == shaders::SELECT_FAR_TILES
                                || n == shaders::GENERATE_FAR =>
                            {
                                size_of::<shared::gpu::layout::SelectPush>()
                            }
                            n if n == shaders::COPY_BLADES => size_of::<layout::CopyPush>(),
                            n if n == shaders::OVERLAY_VS => size_of::<layout::OverlayPush>(),
                            n if n == shaders::CUBE_VS || n == shaders::CUBE_FS => {
                                size_of::<shared::example::cube::CubePush>()
                            }
                            n if n == shaders::THROUGHPUT_VS || n == shaders::THROUGHPUT_MESH => {
                                size_of::<layout::ThroughputPush>()
                            }
                            _ => panic!("{name} has push constants the runner does not push"),
                        };
                        assert_eq!(size as usize, expected, "{name}: push block size");
                    }
                    _ => {}
                }
            }
        }
    }
}

#[test]
fn compute_workgroup_sizes_match_the_dispatches() {
    for (name, size) in [
        (shaders::SIMULATE_CULL, layout::CULL_WORKGROUP),
        (shaders::SIMULATE_CULL_NATURAL, layout::CULL_WORKGROUP),
        (shaders::WRITE_DRAWS, layout::CHUNK_WORKGROUP),
        (shaders::BUILD_HIZ, layout::HIZ_WORKGROUP),
        (shaders::COPY_BLADES, layout::COPY_WORKGROUP),
        (shaders::CLUMP_BLADES, layout::SIMULATE_WORKGROUP),
        (shaders::RASTER_FAR, layout::SIMULATE_WORKGROUP),
        (shaders::RASTER_FAR_NATURAL, layout::SIMULATE_WORKGROUP),
        (shaders::RASTER_PREPARE, layout::PREPARE_WORKGROUP),
        (shaders::RASTER_PREPARE_MS, layout::PREPARE_WORKGROUP),
        (shaders::GENERATE_TILE, layout::SIMULATE_WORKGROUP),
        (shaders::SELECT_TILES, layout::SIMULATE_WORKGROUP),
        (shaders::PAPER_MESH, shared::draw::meshlet::MESH_THREADS),
        (shaders::NATURAL_MESH, shared::draw::meshlet::MESH_THREADS),
        (
            shaders::NATURAL_VIS_MESH,
            shared::draw::meshlet::MESH_THREADS,
        ),
        (shaders::RASTER_CASTERS, CASTERS_PER_GROUP),
        (shaders::RASTER_NEAR_CASTERS, CASTERS_PER_GROUP),
        (shaders::SHADE_NATURAL, layout::TEMPORAL_WORKGROUP),
        (shaders::RESOLVE_TAA, layout::TEMPORAL_WORKGROUP),
        (shaders::GENERATE_FAR, layout::GENERATE_WORKGROUP),
    ] {
        let m = module_of(name);
        let function = entry_points(&m)[name].2;
        let local_size = m
            .execution_modes
            .iter()
            .find_map(|i| match i.operands.as_slice() {
                [
                    Operand::IdRef(f),
                    Operand::ExecutionMode(ExecutionMode::LocalSize),
                    Operand::LiteralBit32(x),
                    ..,
                ] if *f == function => Some(*x),
                _ => None,
            })
            .expect("LocalSize");
        assert_eq!(local_size, size, "{name}: threads per workgroup");
    }
}

/// The type instruction of `id`.
fn type_def(m: &Module, id: u32) -> &rspirv::dr::Instruction {
    m.types_global_values
        .iter()
        .find(|i| i.result_id == Some(id))
        .expect("type definition")
}

/// The members of struct type `ty` with their `Offset` decorations, in order.
fn members(m: &Module, ty: u32) -> Vec<(u32, u32)> {
    let def = type_def(m, ty);
    assert_eq!(def.class.opcode, Op::TypeStruct, "id {ty} is not a struct");
    def.operands
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let offset = m
                .annotations
                .iter()
                .find_map(|a| match a.operands.as_slice() {
                    [
                        Operand::IdRef(s),
                        Operand::LiteralBit32(idx),
                        Operand::Decoration(Decoration::Offset),
                        Operand::LiteralBit32(off),
                    ] if *s == ty && *idx as usize == i => Some(*off),
                    _ => None,
                })
                .expect("member offset");
            (o.unwrap_id_ref(), offset)
        })
        .collect()
}

#[test]
fn frame_block_layout_matches_the_host_struct() {
    use shared::camera::CameraParams;
    use shared::cull::blade::CullParams;
    use shared::cull::hiz::HiZLayout;
    use shared::cull::lod::LodParams;
    use shared::draw::look::LookParams;
    use shared::draw::raster::RasterParams;
    use shared::draw::shade::Light;
    use shared::draw::temporal::TemporalParams;
    use shared::gpu::layout::{FrameUniforms, GrassParams};
    use shared::sim::simulate::Environment;
    use std::mem::offset_of;

    // Each member of the frame block: its offset, and the offsets of its own members
    // where it is a struct (none for arrays).
    let expected: [(&str, usize, Vec<usize>); 12] = [
        (
            "camera",
            offset_of!(FrameUniforms, camera),
            vec![
                offset_of!(CameraParams, view_proj),
                offset_of!(CameraParams, position),
                offset_of!(CameraParams, focal_pixels),
            ],
        ),
        (
            "light",
            offset_of!(FrameUniforms, light),
            vec![offset_of!(Light, direction), offset_of!(Light, ambient)],
        ),
        (
            "forces",
            offset_of!(FrameUniforms, forces),
            vec![
                offset_of!(Environment, gravity),
                offset_of!(Environment, gravity_centre),
                offset_of!(Environment, wind),
                offset_of!(Environment, centre_blend),
                offset_of!(Environment, wind_kind),
                offset_of!(Environment, strength_decay),
                offset_of!(Environment, stiffness_scale),
                offset_of!(Environment, colliders),
                offset_of!(Environment, time),
                offset_of!(Environment, far_sway),
                offset_of!(Environment, gust_speed),
                offset_of!(Environment, impulses),
                offset_of!(Environment, regrow),
                offset_of!(Environment, cutting),
                offset_of!(Environment, pad),
            ],
        ),
        (
            "collider_grid",
            offset_of!(FrameUniforms, collider_grid),
            vec![
                offset_of!(ColliderGrid, cell),
                offset_of!(ColliderGrid, reach),
                offset_of!(ColliderGrid, slots),
                offset_of!(ColliderGrid, low),
                offset_of!(ColliderGrid, high),
                offset_of!(ColliderGrid, watch_cell),
                offset_of!(ColliderGrid, pad),
            ],
        ),
        ("impulses", offset_of!(FrameUniforms, impulses), vec![]),
        (
            "hiz",
            offset_of!(FrameUniforms, hiz),
            vec![
                offset_of!(HiZLayout, width),
                offset_of!(HiZLayout, height),
                offset_of!(HiZLayout, levels),
                offset_of!(HiZLayout, len),
                offset_of!(HiZLayout, offsets),
            ],
        ),
        (
            "lod",
            offset_of!(FrameUniforms, lod),
            vec![
                offset_of!(LodParams, pixels_per_segment),
                offset_of!(LodParams, most),
                offset_of!(LodParams, fewest),
            ],
        ),
        (
            "grass",
            offset_of!(FrameUniforms, grass),
            vec![
                offset_of!(GrassParams, blades),
                offset_of!(GrassParams, shape),
                offset_of!(GrassParams, tip_start),
                offset_of!(GrassParams, view),
                offset_of!(GrassParams, pipeline),
                offset_of!(GrassParams, simulated),
                offset_of!(GrassParams, tiled),
                offset_of!(GrassParams, mixed),
            ],
        ),
        (
            "cull",
            offset_of!(FrameUniforms, cull),
            vec![
                offset_of!(CullParams, orientation_threshold),
                offset_of!(CullParams, frustum_tolerance),
                offset_of!(CullParams, max_distance),
                offset_of!(CullParams, buckets),
                offset_of!(CullParams, enabled),
                offset_of!(CullParams, edge_on_pixels),
                offset_of!(CullParams, focal_pixels),
                offset_of!(CullParams, padding),
            ],
        ),
        (
            "look",
            offset_of!(FrameUniforms, look),
            vec![
                offset_of!(LookParams, shadow_view_proj),
                offset_of!(LookParams, near_view_proj),
                offset_of!(LookParams, style),
                offset_of!(LookParams, shadows),
                offset_of!(LookParams, seed),
                offset_of!(LookParams, shadow_size),
                offset_of!(LookParams, fog_density),
                offset_of!(LookParams, field_distance),
                offset_of!(LookParams, pixel_angle),
                offset_of!(LookParams, clump_size),
                offset_of!(LookParams, caster_distance),
                offset_of!(LookParams, padding),
                offset_of!(LookParams, exposure),
                offset_of!(LookParams, ground_level),
                offset_of!(LookParams, ground_to_horizon),
            ],
        ),
        (
            "raster",
            offset_of!(FrameUniforms, raster),
            vec![
                offset_of!(RasterParams, width),
                offset_of!(RasterParams, height),
                offset_of!(RasterParams, below),
                offset_of!(RasterParams, segments),
            ],
        ),
        (
            "temporal",
            offset_of!(FrameUniforms, temporal),
            vec![
                offset_of!(TemporalParams, previous_view_proj),
                offset_of!(TemporalParams, to_previous),
                offset_of!(TemporalParams, jitter),
                offset_of!(TemporalParams, on),
                offset_of!(TemporalParams, reset),
            ],
        ),
    ];

    let m = module_of(shaders::SIMULATE_CULL);
    let (_, interface, _) = &entry_points(&m)[shaders::SIMULATE_CULL];
    let block = interface
        .iter()
        .find(|&&var| {
            decoration_value(&m, var, Decoration::Binding) == Some(layout::BINDING_UNIFORMS)
        })
        .and_then(|&var| pointee(&m, var))
        .expect("the frame block's variable")
        .1;
    // rust-gpu may wrap the block in a struct of one member.
    let mut ty = block;
    if let [(inner, 0)] = members(&m, ty)[..]
        && type_def(&m, inner).class.opcode == Op::TypeStruct
    {
        ty = inner;
    }
    let top = members(&m, ty);
    assert_eq!(top.len(), expected.len(), "members of the frame block");
    for ((member, offset), (name, host, inner)) in top.iter().zip(&expected) {
        assert_eq!(*offset as usize, *host, "offset of {name}");
        if inner.is_empty() {
            continue;
        }
        let found: Vec<usize> = members(&m, *member)
            .iter()
            .map(|&(_, o)| o as usize)
            .collect();
        assert_eq!(&found, inner, "member offsets of {name}");
    }
    assert_eq!(
        size_of::<FrameUniforms>() % 16,
        0,
        "the block's size is a whole number of vec4"
    );
}

/// The value of execution mode `mode` of `entry` in its module.
fn execution_mode(m: &Module, entry: &str, mode: ExecutionMode) -> Option<u32> {
    let function = entry_points(m)[entry].2;
    m.execution_modes
        .iter()
        .find_map(|i| match i.operands.as_slice() {
            [Operand::IdRef(f), Operand::ExecutionMode(found), rest @ ..]
                if *f == function && *found == mode =>
            {
                Some(match rest.first() {
                    Some(Operand::LiteralBit32(x)) => *x,
                    _ => 1,
                })
            }
            _ => None,
        })
}

#[test]
fn mesh_stages_declare_the_meshlet_limits() {
    use shared::draw::meshlet::{MESHLET_TRIANGLES, MESHLET_VERTICES};
    for name in [
        shaders::PAPER_MESH,
        shaders::NATURAL_MESH,
        shaders::NATURAL_VIS_MESH,
    ] {
        let m = module_of(name);
        let vertices = execution_mode(&m, name, ExecutionMode::OutputVertices);
        let triangles = execution_mode(&m, name, ExecutionMode::OutputPrimitivesEXT);
        assert_eq!(vertices, Some(MESHLET_VERTICES), "{name}: output vertices");
        assert_eq!(
            triangles,
            Some(MESHLET_TRIANGLES),
            "{name}: output triangles"
        );
        assert!(execution_mode(&m, name, ExecutionMode::OutputTrianglesEXT).is_some());
    }
}

/// Only the mesh modules declare the mesh-shading and draw-parameter capabilities
/// (the grass's mesh stages read `DrawIndex`), so a device without mesh shaders
/// accepts every other module.
#[test]
fn only_mesh_modules_need_mesh_shading() {
    use rspirv::spirv::{BuiltIn, Capability, Decoration};
    for (name, m) in modules() {
        let stage = entry_points(&m)[name].0;
        let meshy = matches!(stage, ExecutionModel::TaskEXT | ExecutionModel::MeshEXT);
        for capability in [Capability::MeshShadingEXT, Capability::DrawParameters] {
            let declares = m
                .capabilities
                .iter()
                .any(|i| i.operands.first() == Some(&Operand::Capability(capability)));
            assert_eq!(
                declares, meshy,
                "{name}: {capability:?} declared {declares}"
            );
        }
        let draw_index = m.annotations.iter().any(|i| {
            i.operands.get(1) == Some(&Operand::Decoration(Decoration::BuiltIn))
                && i.operands.get(2) == Some(&Operand::BuiltIn(BuiltIn::DrawIndex))
        });
        // The grass's mesh stages tell their draws apart by DrawIndex.
        let grass_mesh = [
            shaders::PAPER_MESH,
            shaders::NATURAL_MESH,
            shaders::NATURAL_VIS_MESH,
            shaders::PAPER_MESH_CAPTURE,
            shaders::PAPER_TAA_MESH,
        ]
        .contains(&name);
        assert_eq!(
            draw_index, grass_mesh,
            "{name}: reads DrawIndex {draw_index}"
        );
    }
}
