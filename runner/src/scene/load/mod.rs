//! Loading scene files (glTF 2.0, Wavefront OBJ) into surfaces, with clear errors.
//!
//! Every triangle of a file lands in one of two meshes: the surface the grass grows on,
//! or the bare one (drawn, no grass) for materials named `rock…` or `bare…`. A file's
//! data is checked before it is used, and anything wrong with it is a [`SceneError`]
//! naming the file and the problem, never a panic.
//!
//! Rules, in the order they apply:
//! - a scene file must be a regular file (after following links: no pipes, devices,
//!   sockets or directories) of at most [`MAX_FILE_BYTES`], checked before a byte is
//!   read, and read once, capped there (`file`);
//! - a file may have at most [`MAX_VERTICES`] vertices and [`MAX_TRIANGLES`] triangles,
//!   a glTF mesh counting once for every node that draws it; glTF counts are taken from
//!   the accessors before anything is read, so an absurd count costs nothing;
//! - a glTF buffer in a file of its own must be a regular file too, at least its
//!   `byteLength` long (only that much is read);
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
//!
//! The files: `error` (what can go wrong, and the limits), `file` (opening and
//! reading a file within its limit), `mesh` (the builder that
//! checks meshes and gathers them), and the two loaders, `gltf` and `obj`.

mod error;
mod file;
mod gltf;
mod mesh;
mod obj;

pub use error::{MAX_TRIANGLES, MAX_VERTICES, SceneError, SceneErrorKind};
pub use file::MAX_FILE_BYTES;

use shared::world::mesh::SurfaceMesh;
use std::path::Path;

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

/// Loads a scene file, by extension (any case): .gltf and .glb as glTF 2.0 (buffers
/// relative to the file; images are not needed and not read), .obj as Wavefront OBJ
/// (all its objects; material names from `usemtl`, so a missing .mtl is no error).
pub fn load(path: &Path) -> Result<LoadedMesh, SceneError> {
    let scene = path.display().to_string();
    let error = |kind| SceneError::new(&scene, kind);
    // Opened first, so a missing file or a device says so rather than what a parser
    // makes of it; read only once the type is known.
    let (file, size) = file::open(path).map_err(error)?;
    let Some(extension) = path.extension() else {
        return Err(error(SceneErrorKind::NoExtension));
    };
    let extension = extension.to_string_lossy().to_ascii_lowercase();
    if !matches!(extension.as_str(), "gltf" | "glb" | "obj") {
        let extension = path.extension().unwrap_or_default().to_string_lossy();
        return Err(error(SceneErrorKind::Unsupported {
            extension: extension.into_owned(),
        }));
    }
    let bytes = file::read_capped(file, size, MAX_FILE_BYTES).map_err(error)?;
    if extension == "obj" {
        obj::load_obj(&bytes, &scene)
    } else {
        let base = path.parent().unwrap_or(Path::new("."));
        gltf::load_gltf(&bytes, &scene, Some(base))
    }
}

/// Loads a glTF 2.0 scene (.gltf JSON or .glb) from memory; `name` stands for the path
/// in messages. Its buffers must be inside it (GLB binary chunk or data URIs).
pub fn load_gltf_slice(bytes: &[u8], name: &str) -> Result<LoadedMesh, SceneError> {
    gltf::load_gltf(bytes, name, None)
}

/// Checks a caller's own triangle mesh (the embedding API) by the rules files are
/// checked by: finite positions, indices in range, the size limits, degenerate
/// triangles skipped, normals (or face normals where it has none) and winding. All of
/// it grows grass; `name` names it in messages.
pub fn from_mesh(mesh: &SurfaceMesh, name: &str) -> Result<LoadedMesh, SceneError> {
    let mut builder = mesh::Builder::new(name);
    let per_vertex = |n: usize| n == mesh.positions.len();
    builder.add(mesh::Part {
        label: "the mesh".into(),
        positions: mesh.positions.clone(),
        normals: per_vertex(mesh.normals.len()).then(|| mesh.normals.clone()),
        uvs: per_vertex(mesh.uvs.len()).then(|| mesh.uvs.clone()),
        triangles: mesh.triangles.clone(),
        bare: false,
    })?;
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A file under the temp directory with a name no other test (or run) uses,
    /// removed when dropped.
    pub(super) struct TempFile(pub(super) PathBuf);

    impl TempFile {
        /// Writes `contents` to a new file whose name ends in `name`.
        pub(super) fn new(name: &str, contents: &[u8]) -> Self {
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

    /// `text` loaded from an .obj file (kept until the result is looked at).
    pub(super) fn load_obj_text(text: &str) -> (TempFile, Result<LoadedMesh, SceneError>) {
        let file = TempFile::new("scene.obj", text.as_bytes());
        let result = load(&file.0);
        (file, result)
    }

    /// The message of an error, starting "scene <path>: ".
    pub(super) fn problem(file: &TempFile, error: SceneError) -> String {
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
        assert!(matches!(error.kind, SceneErrorKind::NotFound));
        assert_eq!(
            error.to_string(),
            format!("scene {}: file not found", path.display())
        );
    }

    #[test]
    fn directory_is_refused() {
        let error = load(&std::env::temp_dir()).unwrap_err();
        assert!(matches!(error.kind, SceneErrorKind::IsDirectory), "{error}");
        assert!(
            error
                .to_string()
                .ends_with(": is a directory, not a scene file")
        );
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
        assert!(matches!(error.kind, SceneErrorKind::NoExtension), "{error}");
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
}
