//! The shaders' SPIR-V, one module per entry point (so that GPU-assisted validation,
//! which refuses a module of several stages, can check each), listed for
//! `src/shaders.rs`.
//!
//! By default the modules come from `spirv/`, where this script keeps them: a build
//! then needs neither rust-gpu's SPIR-V backend nor its nightly toolchain. With the
//! `rebuild-shaders` feature it compiles `shaders-rs` with rust-gpu's spirv-builder
//! instead, adds the `Patch` decoration that rust-gpu 0.11 leaves off the
//! tessellation-level built-ins (without it lavapipe tessellates nothing and NVIDIA
//! draws with wrong levels, while spirv-val and the validation layer stay silent;
//! glslang always emits it), and with `GRASS_UPDATE_SHADERS=1` replaces the kept
//! modules with the new ones. `spirv/SOURCES` names the hash of the sources they were
//! built from ([`sources_hash`]); a build from kept modules that no longer match the
//! sources beside them says so.

#[cfg(feature = "rebuild-shaders")]
use rspirv::binary::Assemble;
#[cfg(feature = "rebuild-shaders")]
use rspirv::dr::{Instruction, Module, Operand};
#[cfg(feature = "rebuild-shaders")]
use rspirv::spirv::{BuiltIn, Decoration, Op};
#[cfg(feature = "rebuild-shaders")]
use spirv_builder::{Capability, ModuleResult, SpirvBuilder};
use std::path::{Path, PathBuf};

type Error = Box<dyn std::error::Error>;

fn main() {
    if let Err(e) = build() {
        // A build script's panic buries the message; say it and fail plainly.
        eprintln!("error: shader build failed: {e}");
        std::process::exit(1);
    }
}

fn build() -> Result<(), Error> {
    // Clones that share one target directory (as `.ci/run` does) share this script's
    // output: cargo keys it by package, not by path, and the shader sources it watches
    // are those of the clone that built last. Running again when cargo is started from
    // another directory keeps one clone from using another's shaders.
    println!("cargo::rerun-if-env-changed=PWD");
    println!("cargo::rerun-if-env-changed=GRASS_UPDATE_SHADERS");
    let crate_dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR")?);
    let kept = crate_dir.join("spirv");
    let out = PathBuf::from(std::env::var("OUT_DIR")?);
    let sources = sources_hash(&crate_dir.join(".."))?;
    let modules = if cfg!(feature = "rebuild-shaders") {
        let modules = rebuilt(&crate_dir, &out)?;
        if std::env::var_os("GRASS_UPDATE_SHADERS").is_some_and(|v| v == "1") {
            keep(&modules, &kept, sources.as_deref())?;
        }
        modules
    } else {
        if std::env::var_os("GRASS_UPDATE_SHADERS").is_some() {
            println!(
                "cargo::warning=GRASS_UPDATE_SHADERS does nothing without a shader build: \
                 add --features rebuild-shaders"
            );
        }
        println!("cargo::rerun-if-changed={}", kept.display());
        kept_modules(&kept, sources.as_deref())?
    };
    let mut list = String::new();
    for (entry, file) in &modules {
        list += &format!(
            "    ({entry:?}, include_bytes!({:?})),\n",
            file.display().to_string()
        );
    }
    let listing = out.join("modules.rs");
    let rebuilt = cfg!(feature = "rebuild-shaders");
    std::fs::write(
        &listing,
        format!(
            "/// Every entry point and its own SPIR-V module.\n\
             pub const MODULES: &[(&str, &[u8])] = &[\n{list}];\n\
             /// Whether [`MODULES`] were compiled from `shaders-rs` by this build\n\
             /// (the `rebuild-shaders` feature) rather than taken from `runner/spirv`.\n\
             pub const REBUILT: bool = {rebuilt};\n\
             /// The hash of the shader sources beside the crate (as `runner/spirv/SOURCES`\n\
             /// names it), empty where they are not.\n\
             pub const SOURCES_HASH: &str = {:?};\n",
            sources.unwrap_or_default()
        ),
    )?;
    println!(
        "cargo::rustc-env=GRASS_SHADER_MODULES={}",
        listing.display()
    );
    Ok(())
}

/// The file in `spirv/` that names the hash of the sources its modules were built
/// from.
const SOURCES_FILE: &str = "SOURCES";

/// The module file of an entry point (`compute::simulate::simulate_cull` is
/// `compute-simulate-simulate_cull.spv`), and back.
fn file_name(entry: &str) -> String {
    format!("{}.spv", entry.replace("::", "-"))
}

/// The modules kept in `dir`, as (entry point, file), by name; a warning where
/// `sources` (the hash of the sources beside the crate) is not the one they were
/// built from.
fn kept_modules(dir: &Path, sources: Option<&str>) -> Result<Vec<(String, PathBuf)>, Error> {
    let read = std::fs::read_dir(dir).map_err(|e| {
        format!(
            "no SPIR-V modules kept in {} ({e}): build with --features rebuild-shaders",
            dir.display()
        )
    })?;
    let mut modules = Vec::new();
    for entry in read {
        let path = entry?.path();
        let Some(stem) = path
            .extension()
            .filter(|e| *e == "spv")
            .and_then(|_| path.file_stem())
        else {
            continue;
        };
        modules.push((stem.to_string_lossy().replace('-', "::"), path));
    }
    if modules.is_empty() {
        return Err(format!(
            "no SPIR-V modules kept in {}: build with --features rebuild-shaders",
            dir.display()
        )
        .into());
    }
    modules.sort();
    let built_from = std::fs::read_to_string(dir.join(SOURCES_FILE)).unwrap_or_default();
    if let Some(hash) = sources.filter(|h| *h != built_from.trim()) {
        println!(
            "cargo::warning=the SPIR-V kept in runner/spirv was built from other shader \
             sources (hash {}, now {hash}): rebuild them with \
             `GRASS_UPDATE_SHADERS=1 cargo build --release --features rebuild-shaders`",
            built_from.trim()
        );
    }
    Ok(modules)
}

/// Replaces the modules kept in `dir` with `modules` (removing any other) and records
/// the `sources` they were built from.
fn keep(modules: &[(String, PathBuf)], dir: &Path, sources: Option<&str>) -> Result<(), Error> {
    std::fs::create_dir_all(dir)?;
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.extension().is_some_and(|e| e == "spv") {
            std::fs::remove_file(&path)?;
        }
    }
    for (entry, file) in modules {
        std::fs::copy(file, dir.join(file_name(entry)))?;
    }
    std::fs::write(
        dir.join(SOURCES_FILE),
        format!("{}\n", sources.unwrap_or("")),
    )?;
    Ok(())
}

/// FNV-1a (64-bit) over the shader sources in `root` (the repository): every file under
/// `shaders-rs/src` and `shared/src` and their manifests, by path, in order; `None`
/// where they are not there (a packaged crate). Each file is watched.
fn sources_hash(root: &Path) -> Result<Option<String>, Error> {
    let mut files = Vec::new();
    for dir in ["shaders-rs/src", "shared/src"] {
        if !root.join(dir).is_dir() {
            return Ok(None);
        }
        collect(&root.join(dir), &mut files)?;
    }
    files.push(root.join("shaders-rs/Cargo.toml"));
    files.push(root.join("shared/Cargo.toml"));
    files.sort();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for b in bytes {
            hash = (hash ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for file in &files {
        println!("cargo::rerun-if-changed={}", file.display());
        let name = file
            .strip_prefix(root)?
            .to_string_lossy()
            .replace('\\', "/");
        eat(name.as_bytes());
        eat(&[0]);
        eat(&std::fs::read(file)?);
        eat(&[0]);
    }
    Ok(Some(format!("{hash:016x}")))
}

/// Every file under `dir`, recursively.
fn collect(dir: &Path, files: &mut Vec<PathBuf>) -> Result<(), Error> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect(&path, files)?;
        } else {
            files.push(path);
        }
    }
    Ok(())
}

/// `shaders-rs` compiled now, one module per entry point, each with its `Patch`
/// decorations and without the capabilities it does not use, into `out`.
#[cfg(feature = "rebuild-shaders")]
fn rebuilt(crate_dir: &Path, out: &Path) -> Result<Vec<(String, PathBuf)>, Error> {
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
    let mut added = 0;
    let mut files = Vec::new();
    for (entry, spv) in modules {
        let mut module = rspirv::dr::load_bytes(std::fs::read(spv)?)
            .map_err(|e| format!("cannot parse {}: {e}", spv.display()))?;
        added += add_patch_decorations(&mut module);
        strip_unused_mesh_shading(&mut module);
        strip_unused_int64(&mut module);
        let file = out.join(file_name(entry));
        std::fs::write(&file, bytemuck_words(&module.assemble()))?;
        files.push((entry.clone(), file));
    }
    if added == 0 {
        return Err("no tessellation-level built-in found in the shader modules".into());
    }
    files.sort();
    Ok(files)
}

/// Without the feature nothing is compiled.
#[cfg(not(feature = "rebuild-shaders"))]
fn rebuilt(_: &Path, _: &Path) -> Result<Vec<(String, PathBuf)>, Error> {
    unreachable!("only with the rebuild-shaders feature")
}

/// Removes the `MeshShadingEXT` and `DrawParameters` capabilities and the
/// `SPV_EXT_mesh_shader` extension from a module with no task or mesh entry point:
/// Vulkan refuses a module declaring a capability whose feature the device was not
/// created with.
#[cfg(feature = "rebuild-shaders")]
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
#[cfg(feature = "rebuild-shaders")]
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
#[cfg(feature = "rebuild-shaders")]
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

#[cfg(feature = "rebuild-shaders")]
fn bytemuck_words(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}
