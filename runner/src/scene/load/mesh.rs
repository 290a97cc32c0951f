//! The builder that checks a file's meshes, as its loader reads them, and gathers them
//! into the surface and the bare [`SurfaceMesh`] of a [`LoadedMesh`]: finite positions,
//! indices in range, degenerate triangles skipped, file normals or face normals, and
//! the winding that agrees with them.

use super::LoadedMesh;
use super::error::{MAX_TRIANGLES, MAX_VERTICES, SceneError, SceneErrorKind};
use glam::Vec3;
use shared::world::mesh::SurfaceMesh;

/// True for material names that mean "no grass here".
pub(super) fn is_bare_material(name: &str) -> bool {
    let name = name.to_lowercase();
    name.starts_with("rock") || name.starts_with("bare")
}

/// One mesh of a file in world space, as read, before any check.
pub(super) struct Part {
    /// Names it in messages: "node `n`, mesh `m`, primitive 0" or "object `o`".
    pub(super) label: String,
    /// Vertex positions, world space.
    pub(super) positions: Vec<Vec3>,
    /// One per position when the file has them.
    pub(super) normals: Option<Vec<Vec3>>,
    /// Texture coordinates, one per position, when the file has them.
    pub(super) uvs: Option<Vec<glam::Vec2>>,
    /// Vertex indices as the file gives them, unchecked.
    pub(super) triangles: Vec<[u32; 3]>,
    /// Drawn without grass (a bare material).
    pub(super) bare: bool,
}

/// Checks parts and gathers them into a [`LoadedMesh`].
pub(super) struct Builder {
    /// The path (or name) of the scene, for messages.
    pub(super) scene: String,
    /// What is gathered so far.
    loaded: LoadedMesh,
    /// Triangles met, kept or not.
    triangles: usize,
    /// Vertices met (as parts give them).
    vertices: usize,
}

impl Builder {
    /// An empty builder for the scene `scene` (its path or name).
    pub(super) fn new(scene: &str) -> Self {
        Self {
            scene: scene.to_owned(),
            loaded: LoadedMesh::default(),
            triangles: 0,
            vertices: 0,
        }
    }

    /// Refuses more than [`MAX_VERTICES`] or [`MAX_TRIANGLES`].
    pub(super) fn check_limits(&self, vertices: u64, triangles: u64) -> Result<(), SceneError> {
        for (what, count, limit) in [
            ("vertices", vertices, MAX_VERTICES),
            ("triangles", triangles, MAX_TRIANGLES),
        ] {
            if count > limit as u64 {
                return Err(self.error(SceneErrorKind::TooMany { what, count, limit }));
            }
        }
        Ok(())
    }

    /// The error `kind` of this builder's scene.
    pub(super) fn error(&self, kind: SceneErrorKind) -> SceneError {
        SceneError::new(self.scene.clone(), kind)
    }

    /// A [`SceneErrorKind::Malformed`] of `part`.
    pub(super) fn malformed(&self, part: &str, problem: impl Into<String>) -> SceneError {
        self.error(SceneErrorKind::Malformed {
            part: part.to_owned(),
            problem: problem.into(),
        })
    }

    /// The first non-finite position, as an error.
    pub(super) fn check_finite(&self, label: &str, positions: &[Vec3]) -> Result<(), SceneError> {
        match positions.iter().position(|p| !p.is_finite()) {
            Some(vertex) => Err(self.error(SceneErrorKind::NonFinite {
                part: label.to_owned(),
                vertex,
                position: positions[vertex],
            })),
            None => Ok(()),
        }
    }

    /// Checks `part` and adds its triangles to the surface or the bare mesh: see the
    /// module docs of [`super`] for the rules.
    pub(super) fn add(&mut self, part: Part) -> Result<(), SceneError> {
        let Part {
            label,
            positions,
            normals,
            uvs,
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
        // Texture coordinates, one per vertex (non-finite ones as 0), or none.
        let uvs: Option<Vec<glam::Vec2>> = match uvs {
            Some(t) if t.len() == positions.len() => Some(
                t.iter()
                    .map(|t| if t.is_finite() { *t } else { glam::Vec2::ZERO })
                    .collect(),
            ),
            Some(t) => {
                log::warn!(
                    "scene {}: {label}: {} texture coordinates for {} vertices, none used",
                    self.scene,
                    t.len(),
                    positions.len()
                );
                None
            }
            None => None,
        };

        let mut mesh = SurfaceMesh::default();
        let mut push = |i: u32, n: Vec3| {
            mesh.positions.push(positions[i as usize]);
            mesh.normals.push(n);
            if let Some(t) = &uvs {
                mesh.uvs.push(t[i as usize]);
            }
            (mesh.positions.len() - 1) as u32
        };
        // Old index → new, for vertices that keep their file normal (shared).
        let mut shared = vec![u32::MAX; positions.len()];
        let mut kept = Vec::with_capacity(triangles.len());
        for (t, &triangle) in triangles.iter().enumerate() {
            if let Some(&index) = triangle.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(self.error(SceneErrorKind::IndexOutOfRange {
                    part: label,
                    index,
                    vertices: positions.len(),
                }));
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
                return Err(self.error(SceneErrorKind::TooLarge {
                    part: label,
                    triangle: t,
                }));
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
                        *slot = push(i, n);
                    }
                    *slot
                }
                None => push(i, face),
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

    /// The meshes gathered, or why there are none: no triangles at all, or only
    /// degenerate ones.
    pub(super) fn finish(self) -> Result<LoadedMesh, SceneError> {
        if self.triangles == 0 {
            Err(self.error(SceneErrorKind::NoTriangles))
        } else if self.loaded.surface.is_empty() && self.loaded.bare.is_empty() {
            Err(self.error(SceneErrorKind::AllDegenerate {
                triangles: self.triangles,
            }))
        } else {
            Ok(self.loaded)
        }
    }
}

#[cfg(test)]
mod tests {
    //! The builder's rules, through OBJ files (the shortest way to write a mesh).
    use super::super::tests::{load_obj_text, problem};
    use super::*;

    #[test]
    fn obj_with_only_vertices_contains_no_triangles() {
        let (file, result) = load_obj_text("v 0 0 0\nv 1 0 0\nv 0 0 1\nl 1 2\n");
        assert_eq!(problem(&file, result.unwrap_err()), "contains no triangles");
    }

    #[test]
    fn obj_with_a_nan_vertex_names_it() {
        // tobj parses `nan` (Rust's f32 parser does), so the check here must catch it.
        // Named by its line and its number in the file (from 1, as faces count), not
        // by where tobj put it: the third `v` line was once called "vertex 1".
        let (file, result) = load_obj_text("o field\nv 0 0 0\nv 1 0 0\nv nan 0 1\nf 1 2 3\n");
        assert_eq!(
            problem(&file, result.unwrap_err()),
            "line 4: vertex 3 has a non-finite coordinate (NaN, 0, 1)"
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
            error.kind,
            SceneErrorKind::AllDegenerate { triangles: 2 }
        ));
        assert_eq!(
            problem(&file, error),
            "every triangle is degenerate (zero area)"
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
}
