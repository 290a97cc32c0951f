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
mod tests;
