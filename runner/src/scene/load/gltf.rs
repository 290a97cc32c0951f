//! The glTF 2.0 loader (.gltf, .glb): the document checked where the glTF crate trusts
//! it, its buffers (GLB chunk, data URIs, external files read no further than their
//! `byteLength`), the node tree walked into world space, and every triangle primitive
//! handed to the [`Builder`].

use super::LoadedMesh;
use super::error::{SceneError, SceneErrorKind};
use super::mesh::{Builder, Part, is_bare_material};
use glam::{Mat3, Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::{self, validation::Checked};
use gltf::mesh::{Mode, Semantic};
use std::path::{Path, PathBuf};

/// Parses and gathers a glTF file; `base` is where its relative buffer URIs point
/// (`None`: they are an error).
pub(super) fn load_gltf(
    bytes: &[u8],
    scene: &str,
    base: Option<&Path>,
) -> Result<LoadedMesh, SceneError> {
    let not_gltf = |message: String| SceneError::new(scene, SceneErrorKind::NotGltf { message });
    // The GLB reader subtracts the header size from the declared length unchecked.
    if let Some(&[a, b, c, d]) = bytes.get(8..12).filter(|_| bytes.starts_with(b"glTF")) {
        let declared = u32::from_le_bytes([a, b, c, d]);
        if declared < 12 {
            return Err(not_gltf(format!(
                "GLB header declares {declared} bytes, less than the header itself"
            )));
        }
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| not_gltf(e.to_string()))?;
    // The validator indexes the accessors with each POSITION attribute unchecked.
    let json = document.into_json();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = Checked::Valid(json::mesh::Semantic::Positions);
            if let Some(accessor) = primitive.attributes.get(&position)
                && accessor.value() >= json.accessors.len()
            {
                return Err(not_gltf(format!(
                    "invalid glTF: meshes[{m}].primitives[{p}].attributes[\"POSITION\"]: \
                     accessor {} does not exist ({} accessors)",
                    accessor.value(),
                    json.accessors.len()
                )));
            }
        }
    }
    let document = gltf::Document::from_json(json).map_err(|e| not_gltf(e.to_string()))?;
    let buffers = read_buffers(&document, scene, base, blob)?;
    let buffers: Vec<&[u8]> = buffers.iter().map(|b| &b[..]).collect();

    let mut builder = Builder::new(scene);
    // The default scene, else the first, else every node that is nobody's child.
    let roots: Vec<gltf::Node> = match document.default_scene().or(document.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => {
            let mut child = vec![false; document.nodes().count()];
            for node in document.nodes() {
                for c in node.children() {
                    child[c.index()] = true;
                }
            }
            document.nodes().filter(|n| !child[n.index()]).collect()
        }
    };
    // Depth first with a stack (no recursion to overflow). glTF nodes form trees, so a
    // node met twice means a cycle or a shared child: refused, not walked forever.
    let mut seen = vec![false; document.nodes().count()];
    let mut stack: Vec<(gltf::Node, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    let mut drawn: Vec<(gltf::Node, Mat4)> = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            return Err(builder.malformed(
                &node_label(&node),
                "is reached twice in the node hierarchy (glTF requires a tree)",
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
        if node.mesh().is_some() {
            drawn.push((node, world));
        }
    }
    // The sizes first, from the accessors' counts: a mesh drawn by many nodes, or an
    // accessor with no buffer view (zeros, then its sparse values), costs nothing to
    // declare, so nothing is read before they are known to be within the limits.
    let (mut vertices, mut triangles) = (0u64, 0u64);
    for (node, _) in &drawn {
        for primitive in node.mesh().iter().flat_map(|m| m.primitives()) {
            if primitive.mode() == Mode::Triangles {
                let count = |a: Option<gltf::Accessor>| a.map(|a| a.count() as u64);
                let positions = count(primitive.get(&Semantic::Positions)).unwrap_or(0);
                let corners = count(primitive.indices()).unwrap_or(positions);
                vertices = vertices.saturating_add(positions);
                triangles = triangles.saturating_add(corners / 3);
            }
        }
    }
    builder.check_limits(vertices, triangles)?;
    for (node, world) in drawn {
        let Some(mesh) = node.mesh() else { continue };
        for primitive in mesh.primitives() {
            // Points, lines, strips and fans: not surfaces the grass grows on.
            if primitive.mode() != Mode::Triangles {
                continue;
            }
            let label = format!(
                "{}, {}, primitive {}",
                node_label(&node),
                match mesh.name() {
                    Some(name) => format!("mesh `{name}`"),
                    None => format!("mesh {}", mesh.index()),
                },
                primitive.index()
            );
            let part = read_primitive(&builder, &primitive, &buffers, world, label)?;
            builder.add(part)?;
        }
    }
    builder.finish()
}

/// Names a node in messages: by name, else by index.
fn node_label(node: &gltf::Node) -> String {
    match node.name() {
        Some(name) => format!("node `{name}`"),
        None => format!("node {}", node.index()),
    }
}

/// The bytes of every buffer of `document`: the GLB binary chunk, a base64 data URI, or
/// a file (relative to `base`; `None`: an error) that must be a regular file at least
/// the buffer's `byteLength` long, of which only those bytes are read. (The glTF
/// crate's importer reads any path to its end: `/dev/zero` never ends.)
fn read_buffers(
    document: &gltf::Document,
    scene: &str,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, SceneError> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let error = |message: String| {
            let message = format!("buffer {}: {message}", buffer.index());
            SceneError::new(scene, SceneErrorKind::GltfBuffers { message })
        };
        let length = buffer.length();
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| error("the GLB has no binary chunk for it".into()))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                gltf::buffer::Data::from_source_and_blob(buffer.source(), None, &mut None)
                    .map_err(|e| error(e.to_string()))?
                    .0
            }
            gltf::buffer::Source::Uri(uri) => {
                let path = match uri.strip_prefix("file://").or(uri.strip_prefix("file:")) {
                    Some(path) => PathBuf::from(path),
                    None if uri.contains(':') => {
                        return Err(error(format!("URI `{uri}` has an unsupported scheme")));
                    }
                    None => match percent_decode(uri) {
                        Some(path) => PathBuf::from(path),
                        None => {
                            return Err(error(format!(
                                "URI `{uri}` is not UTF-8 once percent-decoded"
                            )));
                        }
                    },
                };
                let Some(base) = base else {
                    return Err(error(
                        "an external buffer cannot be resolved for a scene loaded from memory"
                            .into(),
                    ));
                };
                read_external(&base.join(path), length).map_err(error)?
            }
        };
        if data.len() < length {
            return Err(error(format!(
                "{} bytes, less than its byteLength of {length}",
                data.len()
            )));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// The first `length` bytes of the regular file at `path`.
fn read_external(path: &Path, length: usize) -> Result<Vec<u8>, String> {
    use std::io::Read as _;
    let shown = path.display();
    let (file, size) = super::file::open(path).map_err(|kind| match kind {
        SceneErrorKind::NotRegular { .. } | SceneErrorKind::IsDirectory => {
            format!("{shown} is not a regular file")
        }
        kind => format!("cannot read {shown}: {kind}"),
    })?;
    if size < length as u64 {
        return Err(format!(
            "{shown} has {size} bytes, less than the buffer's byteLength of {length}"
        ));
    }
    // Only the buffer's bytes: the file may hold more, or grow.
    super::file::read_capped(file.take(length as u64), length as u64, length as u64)
        .map_err(|kind| format!("cannot read {shown}: {kind}"))
}

/// `uri` percent-decoded the way the glTF importer does it, if that is UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (bytes[i], bytes.get(i + 1), bytes.get(i + 2)) {
            (b'%', Some(&h), Some(&l)) if hex(h).is_some() && hex(l).is_some() => {
                decoded.push((hex(h).unwrap_or(0) * 16 + hex(l).unwrap_or(0)) as u8);
                i += 3;
            }
            (b, ..) => {
                decoded.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(decoded).ok()
}

/// One triangle primitive in world space: positions (checked finite before they are
/// transformed), normals (by the inverse transpose) and indices (sequential when it
/// has none). A mirroring transform turns the winding round, as glTF asks.
fn read_primitive(
    builder: &Builder,
    primitive: &gltf::Primitive,
    buffers: &[&[u8]],
    world: Mat4,
    label: String,
) -> Result<Part, SceneError> {
    let malformed = |problem: String| builder.malformed(&label, problem);
    let reader = primitive.reader(|b| buffers.get(b.index()).copied());

    let Some(accessor) = primitive.get(&Semantic::Positions) else {
        return Err(malformed("has no POSITION attribute".into()));
    };
    check_accessor(
        &accessor,
        "POSITION",
        &[DataType::F32],
        Dimensions::Vec3,
        buffers,
    )
    .map_err(&malformed)?;
    let Some(positions) = reader.read_positions() else {
        return Err(malformed("POSITION has no data".into()));
    };
    let positions: Vec<Vec3> = positions.map(Vec3::from_array).collect();
    builder.check_finite(&label, &positions)?;

    let normals = match primitive.get(&Semantic::Normals) {
        // Not read: `Builder::add` would drop them (and they could be any size).
        Some(accessor) if accessor.count() != positions.len() => {
            log::warn!(
                "scene {}: {label}: {} normals for {} vertices, using face normals",
                builder.scene,
                accessor.count(),
                positions.len()
            );
            None
        }
        Some(accessor) => {
            check_accessor(
                &accessor,
                "NORMAL",
                &[DataType::F32],
                Dimensions::Vec3,
                buffers,
            )
            .map_err(&malformed)?;
            reader
                .read_normals()
                .map(|n| n.map(Vec3::from_array).collect::<Vec<_>>())
        }
        None => None,
    };

    // Texture coordinates (set 0), where there are as many as positions.
    let uvs = match primitive.get(&Semantic::TexCoords(0)) {
        Some(accessor) if accessor.count() == positions.len() => {
            let types = [DataType::F32, DataType::U8, DataType::U16];
            check_accessor(&accessor, "TEXCOORD_0", &types, Dimensions::Vec2, buffers)
                .map_err(&malformed)?;
            reader
                .read_tex_coords(0)
                .map(|t| t.into_f32().map(glam::Vec2::from_array).collect::<Vec<_>>())
        }
        Some(accessor) => {
            log::warn!(
                "scene {}: {label}: {} texture coordinates for {} vertices, none used",
                builder.scene,
                accessor.count(),
                positions.len()
            );
            None
        }
        None => None,
    };

    let indices: Vec<u32> = match primitive.indices() {
        Some(accessor) => {
            let types = [DataType::U8, DataType::U16, DataType::U32];
            check_accessor(&accessor, "indices", &types, Dimensions::Scalar, buffers)
                .map_err(&malformed)?;
            match reader.read_indices() {
                Some(indices) => indices.into_u32().collect(),
                None => return Err(malformed("indices have no data".into())),
            }
        }
        // Checked by `Builder::add` against u32 before any index is used.
        None => (0..positions.len().min(u32::MAX as usize) as u32).collect(),
    };
    let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
    let triangles = indices
        .as_chunks::<3>()
        .0
        .iter()
        .map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
        .collect();

    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    Ok(Part {
        positions: positions
            .iter()
            .map(|&p| world.transform_point3(p))
            .collect(),
        // A singular transform gives non-finite normals here: they fall back to face
        // normals (and its triangles, squashed flat, are degenerate anyway).
        normals: normals.map(|n| n.iter().map(|&n| normal_matrix * n).collect()),
        uvs,
        triangles,
        bare: primitive.material().name().is_some_and(is_bare_material),
        label,
    })
}

/// Checks what the glTF crate's accessor reader takes on trust (it slices and indexes
/// with these numbers): component type and shape, a count of at least one, strides at
/// least an element wide, and every byte it will read inside its buffer.
fn check_accessor(
    accessor: &gltf::Accessor,
    name: &str,
    types: &[DataType],
    dimensions: Dimensions,
    buffers: &[&[u8]],
) -> Result<(), String> {
    if !types.contains(&accessor.data_type()) || accessor.dimensions() != dimensions {
        return Err(format!(
            "{name} accessor {} is {:?} {:?}, expected {types:?} {dimensions:?}",
            accessor.index(),
            accessor.data_type(),
            accessor.dimensions()
        ));
    }
    let size = accessor.size();
    let check = |view: gltf::buffer::View, offset: usize, count: usize, size: usize| {
        let stride = view.stride().unwrap_or(size);
        let inside = count.checked_sub(1).and_then(|last| {
            let end = stride
                .checked_mul(last)?
                .checked_add(offset)?
                .checked_add(size)?;
            let view_end = view.offset().checked_add(view.length())?;
            let buffer = buffers.get(view.buffer().index())?;
            (end <= view.length() && view_end <= buffer.len()).then_some(())
        });
        if count == 0 {
            Err(format!("{name} accessor {} is empty", accessor.index()))
        } else if stride < size {
            Err(format!(
                "{name} accessor {}: stride {stride} is less than its {size}-byte elements",
                accessor.index()
            ))
        } else if inside.is_none() {
            Err(format!(
                "{name} accessor {} reads past the end of its buffer view or buffer",
                accessor.index()
            ))
        } else {
            Ok(())
        }
    };
    match accessor.view() {
        Some(view) => check(view, accessor.offset(), accessor.count(), size)?,
        None if accessor.sparse().is_none() => {
            return Err(format!("{name} accessor {} has no data", accessor.index()));
        }
        None if accessor.count() == 0 => {
            return Err(format!("{name} accessor {} is empty", accessor.index()));
        }
        None => {}
    }
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let index_size = indices.index_type().size();
        check(indices.view(), indices.offset(), sparse.count(), index_size)?;
        let values = sparse.values();
        check(values.view(), values.offset(), sparse.count(), size)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
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
        let json = r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
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
}
