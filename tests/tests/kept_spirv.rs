//! The SPIR-V kept in `runner/spirv` (what a build without the `rebuild-shaders`
//! feature uses) against the modules this build compiled from `shaders-rs`: the same
//! entry points, byte for byte, and the hash of the sources they came from.

use runner::shaders;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// How to make the kept modules those of the sources.
const UPDATE: &str = "GRASS_UPDATE_SHADERS=1 cargo build --release --features rebuild-shaders";

/// The kept modules' directory.
fn kept_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../runner/spirv")
}

/// Every kept module: entry point → its bytes (a file name's `-` is a path's `::`).
fn kept() -> BTreeMap<String, Vec<u8>> {
    let dir = kept_dir();
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    entries
        .map(|e| e.expect("a kept module's directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "spv"))
        .map(|p| {
            let stem = p.file_stem().expect("a module's name").to_string_lossy();
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (stem.replace('-', "::"), bytes)
        })
        .collect()
}

/// The entry points whose modules differ between `kept` and `built` (missing on
/// either side included).
fn differing(kept: &BTreeMap<String, Vec<u8>>, built: &BTreeMap<String, Vec<u8>>) -> Vec<String> {
    let mut names: Vec<&String> = kept.keys().chain(built.keys()).collect();
    names.sort();
    names.dedup();
    names
        .into_iter()
        .filter(|n| kept.get(*n) != built.get(*n))
        .cloned()
        .collect()
}

// The comparison needs a fresh build: the runner's `rebuild-shaders` feature.
const _: () = assert!(
    shaders::REBUILT,
    "the tests compare the kept SPIR-V with a fresh build: they need rebuild-shaders"
);

#[test]
fn kept_modules_are_the_ones_the_sources_build() {
    let built: BTreeMap<String, Vec<u8>> = shaders::MODULES
        .iter()
        .map(|(entry, spirv)| (entry.to_string(), spirv.to_vec()))
        .collect();
    let stale = differing(&kept(), &built);
    assert!(
        stale.is_empty(),
        "the SPIR-V kept in runner/spirv differs from what shaders-rs builds for {} of {} \
         entry points ({}): `{UPDATE}`",
        stale.len(),
        built.len(),
        stale.join(", ")
    );
}

#[test]
fn kept_modules_name_the_sources_they_came_from() {
    let recorded = std::fs::read_to_string(kept_dir().join("SOURCES"))
        .expect("runner/spirv/SOURCES, the hash of the sources the modules came from");
    assert!(
        !shaders::SOURCES_HASH.is_empty(),
        "the sources are beside the runner"
    );
    assert_eq!(
        recorded.trim(),
        shaders::SOURCES_HASH,
        "runner/spirv/SOURCES names other shader sources: `{UPDATE}`"
    );
}

#[test]
fn a_changed_missing_or_extra_module_is_found() {
    let module = |b: &[u8]| b.to_vec();
    let kept: BTreeMap<String, Vec<u8>> = [("a", module(&[1, 2])), ("b", module(&[3]))]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    let mut built = kept.clone();
    assert!(differing(&kept, &built).is_empty());
    built.insert("b".into(), vec![4]);
    built.insert("c".into(), vec![5]);
    built.remove("a");
    assert_eq!(differing(&kept, &built), ["a", "b", "c"]);
}
