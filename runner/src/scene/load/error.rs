//! What can go wrong loading a scene file, and the limits on its size.

use glam::Vec3;
use std::io;

/// Most vertices a scene file may have (glTF: its POSITION accessors' counts, once per
/// node drawing each mesh; OBJ: its distinct vertices).
pub const MAX_VERTICES: usize = 1 << 22;

/// Most triangles a scene file may have (counted as [`MAX_VERTICES`] is).
pub const MAX_TRIANGLES: usize = 1 << 22;

/// Why a scene file could not be loaded: the scene and the problem. Each message reads
/// `"scene <path>: <problem>"`.
#[derive(Debug, thiserror::Error)]
#[error("scene {scene}: {kind}")]
pub struct SceneError {
    /// The path as given, or the name a scene loaded from memory goes by.
    pub scene: String,
    /// What is wrong with it.
    pub kind: SceneErrorKind,
}

impl SceneError {
    /// The error `kind` of the scene `scene` (its path or name).
    pub(super) fn new(scene: impl Into<String>, kind: SceneErrorKind) -> Self {
        Self {
            scene: scene.into(),
            kind,
        }
    }
}

/// What is wrong with a scene file (the part of a [`SceneError`]'s message after
/// `"scene <path>: "`).
#[derive(Debug, thiserror::Error)]
pub enum SceneErrorKind {
    /// Nothing at that path.
    #[error("file not found")]
    NotFound,
    /// The path names a directory.
    #[error("is a directory, not a scene file")]
    IsDirectory,
    /// The path names something that is not a regular file, after following links.
    #[error("is a {what}, not a regular file")]
    NotRegular {
        /// What it is: a named pipe, a device, a socket.
        what: &'static str,
    },
    /// The file is larger than a scene file may be.
    #[error("{bytes} bytes, more than the {limit} a scene file may have")]
    TooBig {
        /// Its size.
        bytes: u64,
        /// The limit (`file::MAX_FILE_BYTES`).
        limit: u64,
    },
    /// The file grew past the limit while it was read.
    #[error("grew past {limit} bytes while it was read")]
    Grew {
        /// The limit.
        limit: u64,
    },
    /// The file exists but could not be read.
    #[error("cannot read the file: {error}")]
    Read {
        /// What the operating system said.
        error: io::Error,
    },
    /// The extension is none of .gltf, .glb, .obj.
    #[error("unsupported file type `.{extension}` (expected .gltf, .glb or .obj)")]
    Unsupported {
        /// The extension found, without the dot.
        extension: String,
    },
    /// The path has no extension to tell its type by.
    #[error("no file extension (expected .gltf, .glb or .obj)")]
    NoExtension,
    /// The glTF parser rejected the file.
    #[error("not a glTF file: {message}")]
    NotGltf {
        /// The parser's message.
        message: String,
    },
    /// A glTF buffer (an external .bin or a data URI) could not be loaded.
    #[error("cannot load the glTF buffers: {message}")]
    GltfBuffers {
        /// What went wrong.
        message: String,
    },
    /// The OBJ parser rejected the file.
    #[error("not an OBJ file: {message}")]
    NotObj {
        /// The parser's message.
        message: String,
    },
    /// The file holds no triangles at all.
    #[error("contains no triangles")]
    NoTriangles,
    /// Every triangle of the file is degenerate.
    #[error("every triangle is degenerate (zero area)")]
    AllDegenerate {
        /// How many there are.
        triangles: usize,
    },
    /// A vertex position is NaN or infinite.
    #[error(
        "{part}: vertex {vertex} has a non-finite coordinate ({}, {}, {})",
        .position.x, .position.y, .position.z
    )]
    NonFinite {
        /// Which mesh of the file.
        part: String,
        /// The vertex's index in that mesh.
        vertex: usize,
        /// Its position.
        position: Vec3,
    },
    /// A triangle names a vertex that does not exist.
    #[error("{part}: index {index} is out of range ({vertices} vertices)")]
    IndexOutOfRange {
        /// Which mesh of the file.
        part: String,
        /// The index.
        index: u32,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A triangle so large its area overflows f32.
    #[error("{part}: triangle {triangle} is too large (its area overflows f32)")]
    TooLarge {
        /// Which mesh of the file.
        part: String,
        /// The triangle's index in that mesh.
        triangle: usize,
    },
    /// More vertices or triangles than a scene may have ([`MAX_VERTICES`],
    /// [`MAX_TRIANGLES`]).
    #[error("{count} {what}, more than the {limit} a scene may have")]
    TooMany {
        /// "vertices" or "triangles".
        what: &'static str,
        /// How many the file has (instances counted), as far as it was counted.
        count: u64,
        /// The limit.
        limit: usize,
    },
    /// Anything else wrong with the file's structure or data.
    #[error("{part}: {problem}")]
    Malformed {
        /// Which part of the file.
        part: String,
        /// What is wrong.
        problem: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind's message, after the "scene <path>: " the error puts first.
    #[test]
    fn messages_name_the_scene_then_the_problem() {
        let at = |kind| SceneError::new("dir/a.glb", kind).to_string();
        let part = || "object `o`".to_owned();
        for (kind, message) in [
            (SceneErrorKind::NotFound, "file not found"),
            (
                SceneErrorKind::IsDirectory,
                "is a directory, not a scene file",
            ),
            (
                SceneErrorKind::Read {
                    error: io::Error::other("oops"),
                },
                "cannot read the file: oops",
            ),
            (
                SceneErrorKind::Unsupported {
                    extension: "PLY".into(),
                },
                "unsupported file type `.PLY` (expected .gltf, .glb or .obj)",
            ),
            (
                SceneErrorKind::NoExtension,
                "no file extension (expected .gltf, .glb or .obj)",
            ),
            (
                SceneErrorKind::NotGltf {
                    message: "m".into(),
                },
                "not a glTF file: m",
            ),
            (
                SceneErrorKind::GltfBuffers {
                    message: "m".into(),
                },
                "cannot load the glTF buffers: m",
            ),
            (
                SceneErrorKind::NotObj {
                    message: "m".into(),
                },
                "not an OBJ file: m",
            ),
            (SceneErrorKind::NoTriangles, "contains no triangles"),
            (
                SceneErrorKind::AllDegenerate { triangles: 2 },
                "every triangle is degenerate (zero area)",
            ),
            (
                SceneErrorKind::NonFinite {
                    part: part(),
                    vertex: 1,
                    position: Vec3::new(f32::NAN, 0.0, f32::INFINITY),
                },
                "object `o`: vertex 1 has a non-finite coordinate (NaN, 0, inf)",
            ),
            (
                SceneErrorKind::IndexOutOfRange {
                    part: part(),
                    index: 9,
                    vertices: 3,
                },
                "object `o`: index 9 is out of range (3 vertices)",
            ),
            (
                SceneErrorKind::TooLarge {
                    part: part(),
                    triangle: 4,
                },
                "object `o`: triangle 4 is too large (its area overflows f32)",
            ),
            (
                SceneErrorKind::TooMany {
                    what: "triangles",
                    count: 5,
                    limit: 4,
                },
                "5 triangles, more than the 4 a scene may have",
            ),
            (
                SceneErrorKind::Malformed {
                    part: part(),
                    problem: "is odd".into(),
                },
                "object `o`: is odd",
            ),
        ] {
            assert_eq!(at(kind), format!("scene dir/a.glb: {message}"));
        }
    }
}
