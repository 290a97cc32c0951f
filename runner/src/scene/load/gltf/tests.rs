//! Unit tests of `gltf`.

use super::super::tests::{TempFile, problem};
use super::super::{SceneErrorKind, load, load_gltf_slice};
use super::*;

#[test]
fn text_named_glb_is_not_gltf() {
    let file = TempFile::new("text.glb", b"hello, I am not a glTF file\n");
    let error = load(&file.0).unwrap_err();
    assert!(
        matches!(error.kind, SceneErrorKind::NotGltf { .. }),
        "{error}"
    );
    let message = problem(&file, error);
    assert!(message.starts_with("not a glTF file: "), "{message}");
    assert!(message.len() > "not a glTF file: ".len());
}

#[test]
fn short_glb_header_is_not_gltf() {
    let mut bytes = b"glTF".to_vec();
    bytes.extend(2u32.to_le_bytes());
    bytes.extend(4u32.to_le_bytes());
    let error = load_gltf_slice(&bytes, "tiny.glb").unwrap_err();
    assert!(
        matches!(error.kind, SceneErrorKind::NotGltf { .. }),
        "{error}"
    );
}

/// A GLB holding one mesh, with the JSON of its nodes, primitive and extra
/// accessors; the binary chunk is `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// A triangle (0,0,0), (0,0,1), (1,0,0) (counter-clockwise from +Y) with positions
/// `p` as f32 bytes, indices 0 1 2 (u16) at byte 36, and a glTF whose node has
/// `node` (extra node fields), material `material` and `indices` on its primitive.
fn one_triangle(p: [f32; 9], node: &str, indices: &str, material: &str) -> Vec<u8> {
    let mut bin: Vec<u8> = p.iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0{node}}}],
        "materials":[{{"name":"{material}"}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}{indices},"material":0}}]}}],
        "buffers":[{{"byteLength":42}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},
                       {{"buffer":0,"byteOffset":36,"byteLength":6}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                       "min":[0,0,0],"max":[1,0,1]}},
                     {{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}]}}"#
    );
    glb(&json, &bin)
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0];

#[test]
fn gltf_node_transforms_place_the_mesh() {
    let bytes = one_triangle(
        TRIANGLE,
        r#","translation":[10,0,0],"scale":[2,2,2]"#,
        r#","indices":1"#,
        "Grass",
    );
    let mesh = load_gltf_slice(&bytes, "t").unwrap().surface;
    assert_eq!(mesh.triangles.len(), 1);
    assert!((mesh.area() - 2.0).abs() < 1e-6);
    assert_eq!(
        mesh.bounds(),
        Some((Vec3::new(10.0, 0.0, 0.0), Vec3::new(12.0, 0.0, 2.0)))
    );
    assert!(mesh.normals.iter().all(|&n| n == Vec3::Y));
    // Mirrored in x: still counter-clockwise from +Y (glTF turns the winding round).
    let bytes = one_triangle(TRIANGLE, r#","scale":[-1,1,1]"#, "", "rock");
    let loaded = load_gltf_slice(&bytes, "t").unwrap();
    assert!(loaded.surface.is_empty());
    let [a, b, c] = loaded.bare.triangle(0);
    assert!((b - a).cross(c - a).y > 0.0);
}

/// TEXCOORD_0 reaches the surface, one per vertex, as the file gives them; a
/// count that is not the positions' is left out, not an error.
#[test]
fn gltf_texture_coordinates_reach_the_surface() {
    let uv = |count: u32| {
        let mut bin: Vec<u8> = TRIANGLE.iter().flat_map(|f| f.to_le_bytes()).collect();
        let coords = [0.0f32, 0.0, 0.0, 1.0, 0.5, 0.25];
        bin.extend(coords.iter().flat_map(|f| f.to_le_bytes()));
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}}}}]}}],
            "buffers":[{{"byteLength":60}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},
                           {{"buffer":0,"byteOffset":36,"byteLength":24}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                           "min":[0,0,0],"max":[1,0,1]}},
                         {{"bufferView":1,"componentType":5126,"count":{count},
                           "type":"VEC2"}}]}}"#
        );
        load_gltf_slice(&glb(&json, &bin), "t").unwrap().surface
    };
    let mesh = uv(3);
    assert!(mesh.has_uvs());
    // Each vertex keeps its own coordinates (the builder may reorder vertices).
    for (p, t) in mesh.positions.iter().zip(&mesh.uvs) {
        let expected = match (p.x, p.z) {
            (0.0, 0.0) => glam::Vec2::new(0.0, 0.0),
            (0.0, _) => glam::Vec2::new(0.0, 1.0),
            _ => glam::Vec2::new(0.5, 0.25),
        };
        assert_eq!(*t, expected, "at {p}");
    }
    assert!(!uv(2).has_uvs());
}

#[test]
fn gltf_non_finite_vertex_and_bad_index_are_errors() {
    let mut p = TRIANGLE;
    p[5] = f32::INFINITY;
    let error = load_gltf_slice(&one_triangle(p, "", "", "g"), "t").unwrap_err();
    assert_eq!(
        error.to_string(),
        "scene t: node 0, mesh 0, primitive 0: vertex 1 has a non-finite coordinate (0, 0, inf)"
    );
    // Index 2 → 9 (past the three vertices).
    let mut bytes = one_triangle(TRIANGLE, "", r#","indices":1"#, "g");
    let at = bytes.len() - 4; // the last index, before two bytes of padding
    bytes[at..at + 2].copy_from_slice(&9u16.to_le_bytes());
    let error = load_gltf_slice(&bytes, "t").unwrap_err();
    assert!(
        matches!(
            error.kind,
            SceneErrorKind::IndexOutOfRange {
                index: 9,
                vertices: 3,
                ..
            }
        ),
        "{error}"
    );
}

#[test]
fn gltf_wrong_accessor_and_overrun_are_errors_not_panics() {
    // POSITION as VEC2: refused before the reader would misread it.
    let bytes = one_triangle(TRIANGLE, "", "", "g");
    let json_end = 20 + u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json = std::str::from_utf8(&bytes[20..json_end]).unwrap();
    let bin = &bytes[json_end + 8..];
    let vec2 = json.replacen(r#""type":"VEC3""#, r#""type":"VEC2""#, 1);
    let error = load_gltf_slice(&glb(&vec2, bin), "t").unwrap_err();
    assert!(
        matches!(error.kind, SceneErrorKind::Malformed { .. }),
        "{error}"
    );
    // Five vertices in a 36-byte view.
    let overrun = json.replacen(
        r#""count":3,"type":"VEC3""#,
        r#""count":5,"type":"VEC3""#,
        1,
    );
    let error = load_gltf_slice(&glb(&overrun, bin), "t").unwrap_err();
    assert!(error.to_string().contains("past the end"), "{error}");
    // A stride shorter than the element.
    let stride = json.replacen(
        r#""byteLength":36}"#,
        r#""byteLength":36,"byteStride":4}"#,
        1,
    );
    let error = load_gltf_slice(&glb(&stride, bin), "t").unwrap_err();
    assert!(error.to_string().contains("stride"), "{error}");
}

#[test]
fn gltf_without_triangles_and_with_a_cycle() {
    let bytes = one_triangle(TRIANGLE, "", r#","mode":1"#, "g");
    let error = load_gltf_slice(&bytes, "lines.glb").unwrap_err();
    assert_eq!(error.to_string(), "scene lines.glb: contains no triangles");
    let bytes = one_triangle(TRIANGLE, r#","children":[0]"#, "", "g");
    let error = load_gltf_slice(&bytes, "t").unwrap_err();
    assert!(error.to_string().contains("reached twice"), "{error}");
}

#[test]
fn gltf_position_naming_no_accessor_is_not_gltf() {
    // The glTF crate's validator indexed the accessors with it, and panicked.
    let json =
        r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    let error = load_gltf_slice(json.as_bytes(), "t").unwrap_err();
    assert_eq!(
        error.to_string(),
        "scene t: not a glTF file: invalid glTF: meshes[0].primitives[0].attributes\
         [\"POSITION\"]: accessor 0 does not exist (0 accessors)"
    );
}

#[test]
fn percent_decoding_check() {
    assert_eq!(percent_decode("a%20b.bin").as_deref(), Some("a b.bin"));
    assert_eq!(percent_decode("100%.bin").as_deref(), Some("100%.bin"));
    assert_eq!(percent_decode("%ff.bin"), None);
}
