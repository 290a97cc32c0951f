//! Compiles `shaders-rs` to SPIR-V with rust-gpu, one module per entry point (so that
//! GPU-assisted validation, which refuses a module of several stages, can check each),
//! then adds the `Patch` decoration that rust-gpu 0.11 leaves off the
//! tessellation-level built-ins, and lists the modules for `src/shaders.rs`.
//!
//! Without it lavapipe tessellates nothing and NVIDIA draws with wrong levels, while
//! spirv-val and the validation layer stay silent; glslang always emits it.

use rspirv::binary::Assemble;
use rspirv::dr::{Instruction, Module, Operand};
use rspirv::spirv::{BuiltIn, Decoration, Op};
use spirv_builder::{Capability, ModuleResult, SpirvBuilder};
use std::path::PathBuf;

fn main() {
    if let Err(e) = build() {
        // A build script's panic buries the message; say it and fail plainly.
        eprintln!("error: shader build failed: {e}");
        std::process::exit(1);
    }
}

fn build() -> Result<(), Box<dyn std::error::Error>> {
    // Clones that share one target directory (as `.ci/run` does) share this script's
    // output: cargo keys it by package, not by path, and the shader sources it watches
    // are those of the clone that built last. Running again when cargo is started from
    // another directory keeps one clone from using another's shaders.
    println!("cargo::rerun-if-env-changed=PWD");
    let crate_dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR")?);
    let shaders = crate_dir.join("../shaders-rs");
    // spirv-builder's own target dir, one per clone: left at its default, clones that
    // share a target dir share its uplifted `shaders_rs.spv`, and a clone whose shader
    // build is fresh keeps whatever another clone built last.
    let clone: String = crate_dir
        .to_string_lossy()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let mut builder = SpirvBuilder::new(&shaders, "spirv-unknown-vulkan1.2")
        .target_dir_path(format!("spirv-builder/{}", clone.trim_matches('-')))
        .capability(Capability::Tessellation)
        // Mesh stages (`--pipeline mesh`), which read `DrawIndex`; the build removes
        // these again from every module without one, so the others need no mesh-shader
        // device.
        .capability(Capability::MeshShadingEXT)
        .capability(Capability::DrawParameters)
        .extension("SPV_EXT_mesh_shader")
        // Device-scope atomics (the visible-blade counter) under the Vulkan memory model.
        .capability(Capability::VulkanMemoryModelDeviceScope)
        // The compute rasterizer's 64-bit visibility buffer; removed again from every
        // module without a 64-bit integer type.
        .capability(Capability::Int64)
        .capability(Capability::Int64Atomics);
    builder.build_script.defaults = true;
    builder.build_script.env_shader_spv_path = Some(false);
    let result = builder.multimodule(true).build()?;
    let ModuleResult::MultiModule(modules) = &result.module else {
        return Err("spirv-builder made one module, not one per entry point".into());
    };

    let out = PathBuf::from(std::env::var("OUT_DIR")?);
    let mut added = 0;
    let mut list = String::new();
    for (entry, spv) in modules {
        let mut module = rspirv::dr::load_bytes(std::fs::read(spv)?)
            .map_err(|e| format!("cannot parse {}: {e}", spv.display()))?;
        added += add_patch_decorations(&mut module);
        strip_unused_mesh_shading(&mut module);
        strip_unused_int64(&mut module);
        let file = out.join(format!("{}.spv", entry.replace("::", "-")));
        std::fs::write(&file, bytemuck_words(&module.assemble()))?;
        list += &format!(
            "    ({entry:?}, include_bytes!({:?})),\n",
            file.display().to_string()
        );
    }
    if added == 0 {
        return Err("no tessellation-level built-in found in the shader modules".into());
    }
    let listing = out.join("modules.rs");
    std::fs::write(
        &listing,
        format!(
            "/// Every entry point and its own SPIR-V module (Patch decorations added by the\n\
             /// build script).\n\
             pub const MODULES: &[(&str, &[u8])] = &[\n{list}];\n"
        ),
    )?;
    println!(
        "cargo::rustc-env=GRASS_SHADER_MODULES={}",
        listing.display()
    );
    Ok(())
}

/// Removes the `MeshShadingEXT` and `DrawParameters` capabilities and the
/// `SPV_EXT_mesh_shader` extension from a module with no task or mesh entry point:
/// Vulkan refuses a module declaring a capability whose feature the device was not
/// created with.
fn strip_unused_mesh_shading(module: &mut Module) {
    use rspirv::spirv::{Capability as Cap, ExecutionModel};
    let meshy = module.entry_points.iter().any(|e| {
        matches!(
            e.operands.first(),
            Some(Operand::ExecutionModel(
                ExecutionModel::TaskEXT | ExecutionModel::MeshEXT
            ))
        )
    });
    if meshy {
        return;
    }
    module.capabilities.retain(|i| {
        !matches!(
            i.operands.first(),
            Some(Operand::Capability(
                Cap::MeshShadingEXT | Cap::DrawParameters
            ))
        )
    });
    module.extensions.retain(|i| {
        i.operands.first() != Some(&Operand::LiteralString("SPV_EXT_mesh_shader".into()))
    });
}

/// Removes the `Int64` and `Int64Atomics` capabilities from a module that declares no
/// 64-bit integer type (only the compute rasterizer's modules do), so the others need
/// no `shaderInt64` or 64-bit atomics.
fn strip_unused_int64(module: &mut Module) {
    use rspirv::spirv::Capability as Cap;
    let has_int64 = module.types_global_values.iter().any(|i| {
        i.class.opcode == Op::TypeInt && i.operands.first() == Some(&Operand::LiteralBit32(64))
    });
    if has_int64 {
        return;
    }
    module.capabilities.retain(|i| {
        !matches!(
            i.operands.first(),
            Some(Operand::Capability(Cap::Int64 | Cap::Int64Atomics))
        )
    });
}

/// Decorates every `TessLevelOuter`/`TessLevelInner` variable with `Patch` unless it
/// already is. Returns how many variables it looked at.
fn add_patch_decorations(module: &mut Module) -> usize {
    let decorated = |module: &Module, id: u32, pred: &dyn Fn(&[Operand]) -> bool| {
        module.annotations.iter().any(|i| {
            i.class.opcode == Op::Decorate
                && i.operands.first() == Some(&Operand::IdRef(id))
                && pred(&i.operands[1..])
        })
    };
    let levels: Vec<u32> = module
        .annotations
        .iter()
        .filter(|i| i.class.opcode == Op::Decorate)
        .filter_map(|i| match i.operands.as_slice() {
            [
                Operand::IdRef(id),
                Operand::Decoration(Decoration::BuiltIn),
                Operand::BuiltIn(BuiltIn::TessLevelOuter | BuiltIn::TessLevelInner),
            ] => Some(*id),
            _ => None,
        })
        .collect();
    for &id in &levels {
        let is_patch = |ops: &[Operand]| ops == [Operand::Decoration(Decoration::Patch)];
        if !decorated(module, id, &is_patch) {
            module.annotations.push(Instruction::new(
                Op::Decorate,
                None,
                None,
                vec![Operand::IdRef(id), Operand::Decoration(Decoration::Patch)],
            ));
        }
    }
    levels.len()
}

fn bytemuck_words(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}
