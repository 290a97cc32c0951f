//! Loading scene files (glTF 2.0, Wavefront OBJ) into surfaces, with clear errors.
//!
//! Every triangle of a file lands in one of two meshes: the surface the grass grows on,
//! or the bare one (drawn, no grass) for materials named `rock…` or `bare…`. A file's
//! data is checked before it is used, and anything wrong with it is a [`SceneError`]
//! naming the file and the problem, never a panic.
//!
//! Rules, in the order they apply:
//! - a file may have at most [`MAX_VERTICES`] vertices and [`MAX_TRIANGLES`] triangles,
//!   a glTF mesh counting once for every node that draws it; glTF counts are taken from
//!   the accessors before anything is read, so an absurd count costs nothing;
//! - a glTF buffer in a file of its own must be a regular file at least its
//!   `byteLength` long (only that much is read: no devices, no pipes);
//! - an OBJ face index must be within the file: a negative (relative) one can reach back
//!   no further than the first `v`, `vt` or `vn` line, a positive one can be no larger
//!   than the file's line count;
//! - every vertex position must be finite (after the node transforms, too);
//! - every index must name a vertex;
//! - a triangle is *degenerate* and skipped (counted in [`LoadedMesh::degenerate`]) when
//!   its longest edge has length zero or its area is at most 1e-7 × longest edge²,
//!   i.e. it is thinner than 2e-7 of its own length: about the rounding of an f32
//!   coordinate, so no direction on it can be trusted as a normal;
//! - vertex normals come from the file when it has one per vertex (normalised; a zero
//!   or non-finite one gives way to the face normal), otherwise every triangle gets
//!   its face normal on vertices of its own;
//! - a triangle whose winding disagrees with its file normals is turned round, so
//!   triangles are counter-clockwise seen from the normal side, as
//!   [`SurfaceMesh`] promises.

use glam::{Mat3, Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::{self, validation::Checked};
use gltf::mesh::{Mode, Semantic};
use shared::mesh::SurfaceMesh;
use std::io;
use std::path::{Path, PathBuf};

/// Most vertices a scene file may have (glTF: its POSITION accessors' counts, once per
/// node drawing each mesh; OBJ: its distinct vertices).
pub const MAX_VERTICES: usize = 1 << 22;

/// Most triangles a scene file may have (counted as [`MAX_VERTICES`] is).
pub const MAX_TRIANGLES: usize = 1 << 22;

/// A scene file's surfaces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadedMesh {
    /// Where the grass grows: every triangle whose material is not bare.
    pub surface: SurfaceMesh,
    /// Drawn, no grass: triangles whose material name starts with "rock" or "bare"
    /// (any case).
    pub bare: SurfaceMesh,
    /// Zero-area triangles skipped (see the module docs for the rule).
    pub degenerate: usize,
}

/// Why a scene file could not be loaded. Each message reads "scene <path>: <problem>".
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Nothing at that path.
    #[error("scene {scene}: file not found")]
    NotFound {
        /// The path as given.
        scene: String,
    },
    /// The path names a directory.
    #[error("scene {scene}: is a directory, not a scene file")]
    IsDirectory {
        /// The path as given.
        scene: String,
    },
    /// The file exists but could not be read.
    #[error("scene {scene}: cannot read the file: {error}")]
    Read {
        /// The path as given.
        scene: String,
        /// What the operating system said.
        error: io::Error,
    },
    /// The extension is none of .gltf, .glb, .obj.
    #[error("scene {scene}: unsupported file type `.{extension}` (expected .gltf, .glb or .obj)")]
    Unsupported {
        /// The path as given.
        scene: String,
        /// The extension found, without the dot.
        extension: String,
    },
    /// The path has no extension to tell its type by.
    #[error("scene {scene}: no file extension (expected .gltf, .glb or .obj)")]
    NoExtension {
        /// The path as given.
        scene: String,
    },
    /// The glTF parser rejected the file.
    #[error("scene {scene}: not a glTF file: {message}")]
    NotGltf {
        /// The path (or name) of the scene.
        scene: String,
        /// The parser's message.
        message: String,
    },
    /// A glTF buffer (an external .bin or a data URI) could not be loaded.
    #[error("scene {scene}: cannot load the glTF buffers: {message}")]
    GltfBuffers {
        /// The path (or name) of the scene.
        scene: String,
        /// What went wrong.
        message: String,
    },
    /// The OBJ parser rejected the file.
    #[error("scene {scene}: not an OBJ file: {message}")]
    NotObj {
        /// The path as given.
        scene: String,
        /// The parser's message.
        message: String,
    },
    /// The file holds no triangles at all.
    #[error("scene {scene}: contains no triangles")]
    NoTriangles {
        /// The path (or name) of the scene.
        scene: String,
    },
    /// Every triangle of the file is degenerate.
    #[error("scene {scene}: every triangle is degenerate (zero area)")]
    AllDegenerate {
        /// The path (or name) of the scene.
        scene: String,
        /// How many there are.
        triangles: usize,
    },
    /// A vertex position is NaN or infinite.
    #[error(
        "scene {scene}: {part}: vertex {vertex} has a non-finite coordinate ({}, {}, {})",
        .position.x, .position.y, .position.z
    )]
    NonFinite {
        /// The path (or name) of the scene.
        scene: String,
        /// Which mesh of the file.
        part: String,
        /// The vertex's index in that mesh.
        vertex: usize,
        /// Its position.
        position: Vec3,
    },
    /// A triangle names a vertex that does not exist.
    #[error("scene {scene}: {part}: index {index} is out of range ({vertices} vertices)")]
    IndexOutOfRange {
        /// The path (or name) of the scene.
        scene: String,
        /// Which mesh of the file.
        part: String,
        /// The index.
        index: u32,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A triangle so large its area overflows f32.
    #[error("scene {scene}: {part}: triangle {triangle} is too large (its area overflows f32)")]
    TooLarge {
        /// The path (or name) of the scene.
        scene: String,
        /// Which mesh of the file.
        part: String,
        /// The triangle's index in that mesh.
        triangle: usize,
    },
    /// More vertices or triangles than a scene may have ([`MAX_VERTICES`],
    /// [`MAX_TRIANGLES`]).
    #[error("scene {scene}: {count} {what}, more than the {limit} a scene may have")]
    TooMany {
        /// The path (or name) of the scene.
        scene: String,
        /// "vertices" or "triangles".
        what: &'static str,
        /// How many the file has (instances counted), as far as it was counted.
        count: u64,
        /// The limit.
        limit: usize,
    },
    /// Anything else wrong with the file's structure or data.
    #[error("scene {scene}: {part}: {problem}")]
    Malformed {
        /// The path (or name) of the scene.
        scene: String,
        /// Which part of the file.
        part: String,
        /// What is wrong.
        problem: String,
    },
}

/// Loads a scene file, by extension (any case): .gltf and .glb as glTF 2.0 (buffers
/// relative to the file; images are not needed and not read), .obj as Wavefront OBJ
/// (all its objects; material names from `usemtl`, so a missing .mtl is no error).
pub fn load(path: &Path) -> Result<LoadedMesh, SceneError> {
    let scene = path.display().to_string();
    // Ask first, so a missing file says so rather than what a parser makes of it.
    match std::fs::metadata(path) {
        Err(error) if error.kind() == io::ErrorKind::NotFound => {
            return Err(SceneError::NotFound { scene });
        }
        Err(error) => return Err(SceneError::Read { scene, error }),
        Ok(meta) if meta.is_dir() => return Err(SceneError::IsDirectory { scene }),
        Ok(_) => {}
    }
    let Some(extension) = path.extension() else {
        return Err(SceneError::NoExtension { scene });
    };
    let extension = extension.to_string_lossy();
    match extension.to_ascii_lowercase().as_str() {
        "gltf" | "glb" => {
            let bytes = read(path, &scene)?;
            let base = path.parent().unwrap_or(Path::new("."));
            load_gltf(&bytes, &scene, Some(base))
        }
        "obj" => load_obj(&read(path, &scene)?, &scene),
        _ => Err(SceneError::Unsupported {
            extension: extension.into_owned(),
            scene,
        }),
    }
}

/// Loads a glTF 2.0 scene (.gltf JSON or .glb) from memory; `name` stands for the path
/// in messages. Its buffers must be inside it (GLB binary chunk or data URIs).
pub fn load_gltf_slice(bytes: &[u8], name: &str) -> Result<LoadedMesh, SceneError> {
    load_gltf(bytes, name, None)
}

/// The whole file, with its errors told apart.
fn read(path: &Path, scene: &str) -> Result<Vec<u8>, SceneError> {
    let scene = scene.to_owned();
    std::fs::read(path).map_err(|error| match error.kind() {
        io::ErrorKind::NotFound => SceneError::NotFound { scene },
        io::ErrorKind::IsADirectory => SceneError::IsDirectory { scene },
        _ => SceneError::Read { scene, error },
    })
}

/// True for material names that mean "no grass here".
fn is_bare_material(name: &str) -> bool {
    let name = name.to_lowercase();
    name.starts_with("rock") || name.starts_with("bare")
}

/// One mesh of a file in world space, as read, before any check.
struct Part {
    /// Names it in messages: "node `n`, mesh `m`, primitive 0" or "object `o`".
    label: String,
    positions: Vec<Vec3>,
    /// One per position when the file has them.
    normals: Option<Vec<Vec3>>,
    /// Vertex indices as the file gives them, unchecked.
    triangles: Vec<[u32; 3]>,
    bare: bool,
}

/// Checks parts and gathers them into a [`LoadedMesh`].
struct Builder {
    scene: String,
    loaded: LoadedMesh,
    /// Triangles met, kept or not.
    triangles: usize,
    /// Vertices met (as parts give them).
    vertices: usize,
}

impl Builder {
    fn new(scene: &str) -> Self {
        Self {
            scene: scene.to_owned(),
            loaded: LoadedMesh::default(),
            triangles: 0,
            vertices: 0,
        }
    }

    /// Refuses more than [`MAX_VERTICES`] or [`MAX_TRIANGLES`].
    fn check_limits(&self, vertices: u64, triangles: u64) -> Result<(), SceneError> {
        for (what, count, limit) in [
            ("vertices", vertices, MAX_VERTICES),
            ("triangles", triangles, MAX_TRIANGLES),
        ] {
            if count > limit as u64 {
                return Err(SceneError::TooMany {
                    scene: self.scene.clone(),
                    what,
                    count,
                    limit,
                });
            }
        }
        Ok(())
    }

    fn malformed(&self, part: &str, problem: impl Into<String>) -> SceneError {
        SceneError::Malformed {
            scene: self.scene.clone(),
            part: part.to_owned(),
            problem: problem.into(),
        }
    }

    /// The first non-finite position, as an error.
    fn check_finite(&self, label: &str, positions: &[Vec3]) -> Result<(), SceneError> {
        match positions.iter().position(|p| !p.is_finite()) {
            Some(vertex) => Err(SceneError::NonFinite {
                scene: self.scene.clone(),
                part: label.to_owned(),
                vertex,
                position: positions[vertex],
            }),
            None => Ok(()),
        }
    }

    fn add(&mut self, part: Part) -> Result<(), SceneError> {
        let Part {
            label,
            positions,
            normals,
            triangles,
            bare,
        } = part;
        self.check_finite(&label, &positions)?;
        // Within the limits, the mesh's indices stay far within u32: each triangle adds
        // at most three vertices to the file's own.
        let vertices = self.vertices.saturating_add(positions.len());
        let met = self.triangles.saturating_add(triangles.len());
        self.check_limits(vertices as u64, met as u64)?;
        self.vertices = vertices;
        self.triangles = met;

        // File normals, one per vertex, or none at all.
        let normals: Option<Vec<Option<Vec3>>> = match normals {
            Some(n) if n.len() == positions.len() => Some(
                n.iter()
                    .map(|n| n.try_normalize().filter(|n| n.is_finite()))
                    .collect(),
            ),
            Some(n) => {
                log::warn!(
                    "scene {}: {label}: {} normals for {} vertices, using face normals",
                    self.scene,
                    n.len(),
                    positions.len()
                );
                None
            }
            None => None,
        };
        let normal_of = |i: u32| normals.as_ref().and_then(|n| n[i as usize]);

        let mut mesh = SurfaceMesh::default();
        let mut push = |p: Vec3, n: Vec3| {
            mesh.positions.push(p);
            mesh.normals.push(n);
            (mesh.positions.len() - 1) as u32
        };
        // Old index → new, for vertices that keep their file normal (shared).
        let mut shared = vec![u32::MAX; positions.len()];
        let mut kept = Vec::with_capacity(triangles.len());
        for (t, &triangle) in triangles.iter().enumerate() {
            if let Some(&index) = triangle.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(SceneError::IndexOutOfRange {
                    scene: self.scene.clone(),
                    part: label,
                    index,
                    vertices: positions.len(),
                });
            }
            let mut triangle = triangle;
            let [a, b, c] = triangle.map(|i| positions[i as usize]);
            let cross = (b - a).cross(c - a);
            let area = 0.5 * cross.length();
            let longest_squared = (b - a)
                .length_squared()
                .max((c - b).length_squared())
                .max((a - c).length_squared());
            if !area.is_finite() || !longest_squared.is_finite() {
                return Err(SceneError::TooLarge {
                    scene: self.scene.clone(),
                    part: label,
                    triangle: t,
                });
            }
            if longest_squared == 0.0 || area <= 1e-7 * longest_squared {
                self.loaded.degenerate += 1;
                continue;
            }
            let mut face = cross / (2.0 * area);
            let file_normals: Vec3 = triangle.iter().filter_map(|&i| normal_of(i)).sum();
            if file_normals.dot(face) < 0.0 {
                triangle.swap(1, 2);
                face = -face;
            }
            kept.push(triangle.map(|i| match normal_of(i) {
                Some(n) => {
                    let slot = &mut shared[i as usize];
                    if *slot == u32::MAX {
                        *slot = push(positions[i as usize], n);
                    }
                    *slot
                }
                None => push(positions[i as usize], face),
            }));
        }
        mesh.triangles = kept;
        let target = if bare {
            &mut self.loaded.bare
        } else {
            &mut self.loaded.surface
        };
        target.append(&mesh);
        Ok(())
    }

    fn finish(self) -> Result<LoadedMesh, SceneError> {
        let scene = self.scene;
        if self.triangles == 0 {
            Err(SceneError::NoTriangles { scene })
        } else if self.loaded.surface.is_empty() && self.loaded.bare.is_empty() {
            Err(SceneError::AllDegenerate {
                scene,
                triangles: self.triangles,
            })
        } else {
            Ok(self.loaded)
        }
    }
}

/// Parses and gathers a glTF file; `base` is where its relative buffer URIs point
/// (`None`: they are an error).
fn load_gltf(bytes: &[u8], scene: &str, base: Option<&Path>) -> Result<LoadedMesh, SceneError> {
    let not_gltf = |message: String| SceneError::NotGltf {
        scene: scene.to_owned(),
        message,
    };
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
        let error = |message: String| SceneError::GltfBuffers {
            scene: scene.to_owned(),
            message: format!("buffer {}: {message}", buffer.index()),
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
    let size = match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => meta.len(),
        Ok(_) => return Err(format!("{shown} is not a regular file")),
        Err(e) => return Err(format!("cannot read {shown}: {e}")),
    };
    if size < length as u64 {
        return Err(format!(
            "{shown} has {size} bytes, less than the buffer's byteLength of {length}"
        ));
    }
    let mut data = Vec::with_capacity(length);
    std::fs::File::open(path)
        .and_then(|file| file.take(length as u64).read_to_end(&mut data))
        .map_err(|e| format!("cannot read {shown}: {e}"))?;
    Ok(data)
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

/// Name of the material library handed to the OBJ parser (see [`load_obj`]).
const OBJ_NAMES_LIBRARY: &str = "grass-usemtl-names.mtl";

/// Parses and gathers an OBJ file: every object, triangulated, one index per vertex.
fn load_obj(bytes: &[u8], scene: &str) -> Result<LoadedMesh, SceneError> {
    let not_obj = |message: String| SceneError::NotObj {
        scene: scene.to_owned(),
        message,
    };
    let text = std::str::from_utf8(bytes).map_err(|e| not_obj(format!("not UTF-8 text ({e})")))?;
    // tobj resolves `usemtl` names only through a material library. Only the names
    // matter here, so hand it one made of the file's own `usemtl` names, whatever
    // .mtl the file asks for: a missing or partial .mtl then changes nothing.
    // On the way, face indices are checked the way tobj cannot: it resolves them with
    // unchecked arithmetic (a panic in debug builds, for `f 1//-5` or `f 1/-3` with a
    // vt line, or `f 1//9223372036854775807`).
    let lines = text.lines().count();
    let mut names: std::collections::BTreeSet<&str> = Default::default();
    // `v`, `vt` and `vn` lines so far: how far back a negative index may reach.
    let mut before = [0usize; 3];
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("usemtl") => {
                // Cut the way tobj cuts it, so the names match.
                let name = line.split_once(' ').unwrap_or_default().1.trim();
                if !name.is_empty() {
                    names.insert(name);
                }
            }
            Some("v") => before[0] += 1,
            Some("vt") => before[1] += 1,
            Some("vn") => before[2] += 1,
            Some("f" | "l") => {
                for word in words {
                    for (kind, index) in word.split('/').enumerate() {
                        // Anything else is tobj's to refuse.
                        let (Some(&before), Ok(index)) = (before.get(kind), index.parse::<isize>())
                        else {
                            continue;
                        };
                        let limit = if index < 0 { before } else { lines };
                        if index.unsigned_abs() > limit {
                            return Err(not_obj(format!(
                                "line {}: index `{word}` is out of range",
                                number + 1
                            )));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    let library: String = names.iter().map(|n| format!("newmtl {n}\n")).collect();
    let source = format!("mtllib {OBJ_NAMES_LIBRARY}\n{text}");
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj appends every library it is handed to the last: only the first `mtllib`
    // (the one above) gets the names, or n `mtllib` lines would make n copies of them.
    let handed = std::cell::Cell::new(false);
    let (models, materials) = tobj::load_obj_buf(&mut source.as_bytes(), &options, |_| {
        if handed.replace(true) {
            Ok(Default::default())
        } else {
            tobj::load_mtl_buf(&mut library.as_bytes())
        }
    })
    .map_err(|e| not_obj(e.to_string()))?;
    let materials = materials.unwrap_or_default();

    let mut builder = Builder::new(scene);
    for model in models {
        let mesh = model.mesh;
        let bare = mesh
            .material_id
            .and_then(|i| materials.get(i))
            .is_some_and(|m| is_bare_material(&m.name));
        let vec3s = |v: &[f32]| -> Vec<Vec3> {
            v.as_chunks::<3>()
                .0
                .iter()
                .map(|&p| Vec3::from_array(p))
                .collect()
        };
        builder.add(Part {
            label: format!("object `{}`", model.name),
            positions: vec3s(&mesh.positions),
            normals: (!mesh.normals.is_empty()).then(|| vec3s(&mesh.normals)),
            triangles: mesh.indices.as_chunks::<3>().0.to_vec(),
            bare,
        })?;
    }
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A file under the temp directory with a name no other test (or run) uses,
    /// removed when dropped.
    struct TempFile(PathBuf);

    impl TempFile {
        fn new(name: &str, contents: &[u8]) -> Self {
            static NEXT: AtomicUsize = AtomicUsize::new(0);
            let unique = NEXT.fetch_add(1, Ordering::Relaxed);
            let path = std::env::temp_dir()
                .join(format!("grass-load-{}-{unique}-{name}", std::process::id()));
            std::fs::write(&path, contents).expect("write a temp file");
            Self(path)
        }
    }

    impl Drop for TempFile {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.0);
        }
    }

    fn load_obj_text(text: &str) -> (TempFile, Result<LoadedMesh, SceneError>) {
        let file = TempFile::new("scene.obj", text.as_bytes());
        let result = load(&file.0);
        (file, result)
    }

    /// The message of an error, starting "scene <path>: ".
    fn problem(file: &TempFile, error: SceneError) -> String {
        let message = error.to_string();
        let prefix = format!("scene {}: ", file.0.display());
        message
            .strip_prefix(&prefix)
            .unwrap_or_else(|| panic!("`{message}` does not start with `{prefix}`"))
            .to_owned()
    }

    #[test]
    fn missing_file_is_not_found() {
        let path = std::env::temp_dir().join(format!("grass-missing-{}.obj", std::process::id()));
        let error = load(&path).unwrap_err();
        assert!(matches!(error, SceneError::NotFound { .. }));
        assert_eq!(
            error.to_string(),
            format!("scene {}: file not found", path.display())
        );
    }

    #[test]
    fn directory_is_refused() {
        let error = load(&std::env::temp_dir()).unwrap_err();
        assert!(matches!(error, SceneError::IsDirectory { .. }), "{error}");
        assert!(
            error
                .to_string()
                .ends_with(": is a directory, not a scene file")
        );
    }

    #[test]
    fn text_named_glb_is_not_gltf() {
        let file = TempFile::new("text.glb", b"hello, I am not a glTF file\n");
        let error = load(&file.0).unwrap_err();
        assert!(matches!(error, SceneError::NotGltf { .. }), "{error}");
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
        assert!(matches!(error, SceneError::NotGltf { .. }), "{error}");
    }

    #[test]
    fn unsupported_extension_says_what_is_supported() {
        let file = TempFile::new("cloud.PLY", b"ply\n");
        let error = load(&file.0).unwrap_err();
        assert_eq!(
            problem(&file, error),
            "unsupported file type `.PLY` (expected .gltf, .glb or .obj)"
        );
        let file = TempFile::new("noextension", b"");
        let error = load(&file.0).unwrap_err();
        assert!(matches!(error, SceneError::NoExtension { .. }), "{error}");
    }

    #[test]
    fn obj_with_only_vertices_contains_no_triangles() {
        let (file, result) = load_obj_text("v 0 0 0\nv 1 0 0\nv 0 0 1\nl 1 2\n");
        assert_eq!(problem(&file, result.unwrap_err()), "contains no triangles");
    }

    #[test]
    fn obj_with_a_nan_vertex_names_it() {
        // tobj parses `nan` (Rust's f32 parser does), so the check here must catch it.
        let (file, result) = load_obj_text("o field\nv 0 0 0\nv nan 0 1\nv 1 0 0\nf 1 2 3\n");
        assert_eq!(
            problem(&file, result.unwrap_err()),
            "object `field`: vertex 1 has a non-finite coordinate (NaN, 0, 1)"
        );
        let (file, result) = load_obj_text("v inf 0 0\nv 0 0 1\nv 1 0 0\nf 1 2 3\n");
        assert!(problem(&file, result.unwrap_err()).ends_with("(inf, 0, 0)"));
    }

    #[test]
    fn obj_skips_and_counts_a_degenerate_triangle() {
        let (_file, result) = load_obj_text(
            "v 0 0 0\nv 0 0 1\nv 1 0 0\nv 2 0 0\n\
             f 1 2 3\n\
             f 1 3 4\n",
        );
        let loaded = result.unwrap();
        assert_eq!(loaded.degenerate, 1);
        assert_eq!(loaded.surface.triangles.len(), 1);
        assert!(loaded.bare.is_empty());
    }

    #[test]
    fn obj_with_only_degenerate_triangles_is_refused() {
        let (file, result) =
            load_obj_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 0 0\nf 1 2 3\nf 1 4 2\n");
        let error = result.unwrap_err();
        assert!(matches!(
            error,
            SceneError::AllDegenerate { triangles: 2, .. }
        ));
        assert_eq!(
            problem(&file, error),
            "every triangle is degenerate (zero area)"
        );
    }

    #[test]
    fn obj_index_out_of_range_is_an_error() {
        let (file, result) = load_obj_text("v 0 0 0\nv 0 0 1\nv 1 0 0\nf 1 2 7\n");
        let message = problem(&file, result.unwrap_err());
        assert!(message.starts_with("not an OBJ file: "), "{message}");
    }

    #[test]
    fn binary_obj_is_not_obj() {
        let file = TempFile::new("binary.obj", &[0xff, 0xfe, 0x00, 0x76]);
        let message = problem(&file, load(&file.0).unwrap_err());
        assert!(
            message.starts_with("not an OBJ file: not UTF-8"),
            "{message}"
        );
    }

    #[test]
    fn good_obj_without_normals_gets_face_normals() {
        // A unit quad in y = 1, counter-clockwise seen from +Y.
        let (_file, result) = load_obj_text("v 0 1 0\nv 0 1 1\nv 1 1 1\nv 1 1 0\nf 1 2 3 4\n");
        let loaded = result.unwrap();
        let mesh = &loaded.surface;
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(mesh.positions.len(), 6, "face normals split the vertices");
        assert!(mesh.normals.iter().all(|&n| n == Vec3::Y));
        assert!((mesh.area() - 1.0).abs() < 1e-6);
        assert_eq!(loaded.degenerate, 0);
    }

    #[test]
    fn good_obj_with_normals_keeps_them() {
        let tilted = Vec3::new(1.0, 2.0, 0.0).normalize();
        let (_file, result) = load_obj_text(
            "v 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\n\
             vn 0 3 0\nvn 1 2 0\n\
             f 1//1 2//1 3//2 4//2\n",
        );
        let mesh = result.unwrap().surface;
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(
            mesh.positions.len(),
            4,
            "vertices with file normals are shared"
        );
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let expected = if p.x == 0.0 { Vec3::Y } else { tilted };
            assert!((*n - expected).length() < 1e-6, "{p}: {n}");
        }
    }

    #[test]
    fn obj_normals_decide_the_winding_and_zero_normals_fall_back() {
        // Clockwise seen from +Y, but the normals say +Y: the triangle is turned round.
        // The zero normal of the third vertex gives way to the face normal.
        let (_file, result) =
            load_obj_text("v 0 0 0\nv 1 0 0\nv 0 0 1\nvn 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//2\n");
        let mesh = result.unwrap().surface;
        let [a, b, c] = mesh.triangle(0);
        assert!((b - a).cross(c - a).y > 0.0);
        assert!(mesh.normals.iter().all(|&n| n == Vec3::Y));
    }

    #[test]
    fn obj_materials_named_rock_or_bare_are_bare_without_an_mtl() {
        let (_file, result) = load_obj_text(
            "mtllib missing.mtl\n\
             v 0 0 0\nv 0 0 1\nv 1 0 0\nv 5 0 0\nv 5 0 1\nv 6 0 0\n\
             usemtl Grass\nf 1 2 3\n\
             usemtl ROCK_granite\nf 4 5 6\n\
             usemtl bare soil\nf 1 5 6\n",
        );
        let loaded = result.unwrap();
        assert_eq!(loaded.surface.triangles.len(), 1);
        assert_eq!(loaded.bare.triangles.len(), 2);
    }

    #[test]
    fn meadow_loads_with_grass_and_rock() {
        let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/meadow.glb"));
        let loaded = load(path).unwrap();
        assert!(!loaded.surface.is_empty() && !loaded.bare.is_empty());
        assert_eq!(loaded.degenerate, 0);
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(load_gltf_slice(&bytes, "meadow").unwrap(), loaded);
        // The terrain is about 24 × 24 and rolls; the rock stands out of it.
        let (lo, hi) = loaded.surface.bounds().unwrap();
        assert!((hi.x - lo.x - 24.0).abs() < 0.01 && (hi.z - lo.z - 24.0).abs() < 0.01);
        assert!(hi.y - lo.y > 0.5, "flat terrain: {lo} {hi}");
        let (rock_lo, rock_hi) = loaded.bare.bounds().unwrap();
        let size = rock_hi - rock_lo;
        assert!(
            size.max_element() < 9.0 && size.min_element() > 4.0,
            "rock {size}"
        );
        // Unit normals, counter-clockwise triangles (the rock's node transform kept them so).
        for mesh in [&loaded.surface, &loaded.bare] {
            for n in &mesh.normals {
                assert!((n.length() - 1.0).abs() < 1e-5);
            }
            for (i, t) in mesh.triangles.iter().enumerate() {
                let [a, b, c] = mesh.triangle(i);
                let face = (b - a).cross(c - a);
                assert!(t.iter().all(|&v| face.dot(mesh.normals[v as usize]) > 0.0));
            }
        }
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
                error,
                SceneError::IndexOutOfRange {
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
        assert!(matches!(error, SceneError::Malformed { .. }), "{error}");
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
    fn obj_indices_out_of_reach_are_refused_before_tobj() {
        // tobj overflowed on these (a panic in debug builds).
        for (face, line) in [
            ("vn 0 1 0\nf 1//-5 2 3", 5),
            ("vn 0 1 0\nf 1//9223372036854775807 2 3", 5),
            ("vt 0 0\nf 1/-3 2 3", 5),
            ("f 1 2 -4", 4),
            ("f 1 2 9223372036854775807", 4),
        ] {
            let (file, result) = load_obj_text(&format!("v 0 0 0\nv 0 0 1\nv 1 0 0\n{face}\n"));
            let word = face
                .lines()
                .last()
                .unwrap()
                .split_whitespace()
                .find(|w| w.len() > 2);
            let word = word.unwrap_or("-4");
            assert_eq!(
                problem(&file, result.unwrap_err()),
                format!("not an OBJ file: line {line}: index `{word}` is out of range"),
            );
        }
        // Still fine: relative indices within reach.
        let (_file, result) = load_obj_text("v 0 0 0\nv 0 0 1\nv 1 0 0\nf -3 -2 -1\n");
        assert_eq!(result.unwrap().surface.triangles.len(), 1);
    }

    #[test]
    fn percent_decoding_check() {
        assert_eq!(percent_decode("a%20b.bin").as_deref(), Some("a b.bin"));
        assert_eq!(percent_decode("100%.bin").as_deref(), Some("100%.bin"));
        assert_eq!(percent_decode("%ff.bin"), None);
    }
}
