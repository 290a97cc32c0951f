//! Writes `assets/meadow.glb`, the project's own glTF scene: a gently rolling terrain
//! 24 × 24 units (material "soil": grass grows on it) and a rock about 7 units
//! across (material "rock": bare), half sunk into the terrain.
//!
//! Regenerate with `cargo run --release -p runner --example make_meadow`.
//!
//! The GLB 2.0 is written by hand (no exporter): a JSON chunk padded with spaces and a
//! BIN chunk with positions, normals and u32 indices, every piece 4-byte aligned. The
//! rock is a unit-sized mesh placed by its node's translation, rotation and
//! non-uniform scale, so loading it exercises node transforms and inverse-transpose
//! normals. Fixed seed: the same bytes every run.

use anyhow::{Context, ensure};
use glam::{Quat, Vec3};
use runner::scene::builtin::{hills, hills_height, sphere};
use runner::scene::load::load_gltf_slice;
use shared::world::generate::SplitMix64;
use shared::world::mesh::SurfaceMesh;
use std::fmt::Write as _;
use std::path::Path;

/// Side of the terrain square.
const SIDE: f32 = 24.0;
/// Grid cells along a side of the terrain.
const CELLS: u32 = 48;
/// Seed of the rock's shape.
const SEED: u64 = 0x6d65_6164_6f77;
/// Where the rock sits on the terrain (x, z).
const ROCK_AT: (f32, f32) = (3.5, -2.5);

fn main() -> anyhow::Result<()> {
    let terrain = hills(SIDE, CELLS);
    let rock = rock(SEED);
    let (x, z) = ROCK_AT;
    // Centre at ground level: half of the rock under the terrain.
    let translation = Vec3::new(x, hills_height(x, z, SIDE), z);
    let rotation = (Quat::from_rotation_y(0.6) * Quat::from_rotation_x(0.15)).normalize();
    let scale = Vec3::new(3.4, 2.6, 3.0);

    let bytes = meadow_glb(&terrain, &rock, translation, rotation, scale);
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/meadow.glb"));

    // Check it before writing it.
    let loaded = load_gltf_slice(&bytes, "meadow.glb").context("load the new meadow")?;
    ensure!(!loaded.surface.is_empty() && !loaded.bare.is_empty() && loaded.degenerate == 0);
    gltf::Gltf::from_slice(&bytes).context("glTF parser rejects the meadow")?;

    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
    }
    std::fs::write(path, &bytes).with_context(|| format!("write {}", path.display()))?;
    println!(
        "wrote {} ({} bytes): terrain {} triangles, {:.1} square units; rock {} triangles",
        path.display(),
        bytes.len(),
        loaded.surface.triangles.len(),
        loaded.surface.area(),
        loaded.bare.triangles.len(),
    );
    Ok(())
}

/// A lumpy unit-sized rock: an icosphere (2 subdivisions) with each vertex pushed in or
/// out at random, smoothed once over its neighbours, normals from the faces around
/// each vertex.
fn rock(seed: u64) -> SurfaceMesh {
    let mut mesh = sphere(Vec3::ZERO, 1.0, 2);
    let mut rng = SplitMix64::new(seed);
    let bumps: Vec<f32> = mesh
        .positions
        .iter()
        .map(|_| rng.range(-0.6, 0.6))
        .collect();
    // Average each bump with its neighbours' so the rock is lumpy, not spiky.
    let mut sum = bumps.clone();
    let mut count = vec![1.0_f32; bumps.len()];
    for t in &mesh.triangles {
        for (i, j) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            // Each edge is met twice, once each way round.
            sum[i as usize] += bumps[j as usize];
            count[i as usize] += 1.0;
        }
    }
    for ((p, s), c) in mesh.positions.iter_mut().zip(&sum).zip(&count) {
        *p *= 1.0 + s / c;
    }
    let mut normals = vec![Vec3::ZERO; mesh.positions.len()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        // Area-weighted: the cross product is twice the area along the normal.
        let n = (b - a).cross(c - a);
        for i in t {
            normals[*i as usize] += n;
        }
    }
    mesh.normals = normals.into_iter().map(Vec3::normalize).collect();
    mesh
}

/// The binary chunk being filled, with the JSON of its buffer views and accessors.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

/// glTF `bufferView.target` values.
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// glTF `accessor.componentType` values.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

impl Bin {
    /// Appends `bytes` as a new buffer view (4-byte aligned); returns its index.
    fn view(&mut self, bytes: &[u8], target: u32) -> usize {
        while !self.data.len().is_multiple_of(4) {
            self.data.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{},"target":{target}}}"#,
            self.data.len(),
            bytes.len()
        ));
        self.data.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A VEC3 float accessor over `values`, with min and max when `bounds`; its index.
    fn vec3s(&mut self, values: &[Vec3], bounds: bool) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let view = self.view(&bytes, ARRAY_BUFFER);
        let mut accessor = format!(
            r#"{{"bufferView":{view},"componentType":{FLOAT},"count":{},"type":"VEC3""#,
            values.len()
        );
        if bounds {
            let lo = values.iter().fold(Vec3::INFINITY, |a, &b| a.min(b));
            let hi = values.iter().fold(Vec3::NEG_INFINITY, |a, &b| a.max(b));
            let _ = write!(
                accessor,
                r#","min":{},"max":{}"#,
                json_vec3(lo),
                json_vec3(hi)
            );
        }
        accessor.push('}');
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A SCALAR u32 accessor over the triangles' indices; its index.
    fn indices(&mut self, triangles: &[[u32; 3]]) -> usize {
        let bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = self.view(&bytes, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(format!(
            r#"{{"bufferView":{view},"componentType":{UNSIGNED_INT},"count":{},"type":"SCALAR"}}"#,
            3 * triangles.len()
        ));
        self.accessors.len() - 1
    }

    /// A triangle primitive of `mesh` with `material`, as JSON.
    fn primitive(&mut self, mesh: &SurfaceMesh, material: usize) -> String {
        let position = self.vec3s(&mesh.positions, true);
        let normal = self.vec3s(&mesh.normals, false);
        let indices = self.indices(&mesh.triangles);
        format!(
            r#"{{"attributes":{{"POSITION":{position},"NORMAL":{normal}}},"indices":{indices},"material":{material},"mode":4}}"#
        )
    }
}

/// `[x,y,z]` exactly: the f32s widened to f64 print digits that read back as the same
/// f32 and, as doubles, equal them (validators compare min/max with the data).
fn json_vec3(v: Vec3) -> String {
    let [x, y, z] = v.to_array().map(f64::from);
    format!("[{x},{y},{z}]")
}

/// The meadow as a GLB: terrain at the origin, rock placed by its node.
fn meadow_glb(
    terrain: &SurfaceMesh,
    rock: &SurfaceMesh,
    translation: Vec3,
    rotation: Quat,
    scale: Vec3,
) -> Vec<u8> {
    let mut bin = Bin::default();
    let terrain_primitive = bin.primitive(terrain, 0);
    let rock_primitive = bin.primitive(rock, 1);
    while !bin.data.len().is_multiple_of(4) {
        bin.data.push(0);
    }
    let [qx, qy, qz, qw] = rotation.to_array();
    let json = format!(
        r#"{{
"asset":{{"version":"2.0","generator":"grass make_meadow"}},
"scene":0,
"scenes":[{{"name":"meadow","nodes":[0,1]}}],
"nodes":[
{{"name":"terrain","mesh":0}},
{{"name":"rock","mesh":1,"translation":{translation},"rotation":[{qx},{qy},{qz},{qw}],"scale":{scale}}}
],
"meshes":[
{{"name":"terrain","primitives":[{terrain_primitive}]}},
{{"name":"rock","primitives":[{rock_primitive}]}}
],
"materials":[
{{"name":"soil","pbrMetallicRoughness":{{"baseColorFactor":[0.36,0.27,0.18,1],"metallicFactor":0,"roughnessFactor":1}}}},
{{"name":"rock","pbrMetallicRoughness":{{"baseColorFactor":[0.45,0.45,0.43,1],"metallicFactor":0,"roughnessFactor":0.9}}}}
],
"buffers":[{{"byteLength":{length}}}],
"bufferViews":[
{views}
],
"accessors":[
{accessors}
]
}}
"#,
        translation = json_vec3(translation),
        scale = json_vec3(scale),
        length = bin.data.len(),
        views = bin.views.join(",\n"),
        accessors = bin.accessors.join(",\n"),
    );
    let mut json = json.into_bytes();
    // The JSON chunk is padded with spaces, the binary one with zeros (GLB 2.0, 4.4).
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.data.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.data.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin.data);
    glb
}
