//! The Wavefront OBJ loader: every object, triangulated, its `usemtl` names deciding
//! what is bare, its face indices checked before tobj resolves them.

use super::LoadedMesh;
use super::error::{SceneError, SceneErrorKind};
use super::mesh::{Builder, Part, is_bare_material};
use glam::Vec3;

/// Name of the material library handed to the OBJ parser (see [`load_obj`]).
const OBJ_NAMES_LIBRARY: &str = "grass-usemtl-names.mtl";

/// Checks that the first `needed` words of a `v`, `vt` or `vn` line are numbers, so
/// that a bad one is named with its line (tobj's own error names none).
fn numbers(words: &std::str::SplitWhitespace, needed: usize) -> Result<(), String> {
    let mut count = 0;
    for word in words.clone().take(needed) {
        if word.parse::<f32>().is_err() {
            return Err(format!("`{word}` is not a number"));
        }
        count += 1;
    }
    if count < needed {
        return Err(format!("{needed} numbers needed, {count} found"));
    }
    Ok(())
}

/// Parses and gathers an OBJ file: every object, triangulated, one index per vertex.
pub(super) fn load_obj(bytes: &[u8], scene: &str) -> Result<LoadedMesh, SceneError> {
    let not_obj = |message: String| SceneError::new(scene, SceneErrorKind::NotObj { message });
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
            Some("v") => {
                numbers(&words, 3).map_err(|e| not_obj(format!("line {}: {e}", number + 1)))?;
                before[0] += 1;
                // Checked here, where the line is known: tobj reorders the vertices.
                let xyz: Vec<f32> = words
                    .clone()
                    .take(3)
                    .map_while(|w| w.parse().ok())
                    .collect();
                if let [x, y, z] = xyz[..]
                    && !(x.is_finite() && y.is_finite() && z.is_finite())
                {
                    return Err(SceneError::new(
                        scene,
                        SceneErrorKind::NonFinite {
                            part: format!("line {}", number + 1),
                            // OBJ numbers its vertices from 1, as its faces name them.
                            vertex: before[0],
                            position: Vec3::new(x, y, z),
                        },
                    ));
                }
            }
            Some(kind @ ("vt" | "vn")) => {
                let (slot, needed) = if kind == "vt" { (1, 1) } else { (2, 3) };
                numbers(&words, needed)
                    .map_err(|e| not_obj(format!("line {}: {e}", number + 1)))?;
                before[slot] += 1;
            }
            Some(kind @ ("f" | "l")) => {
                let corners = words.clone().count();
                if kind == "f" && corners < 3 {
                    return Err(not_obj(format!(
                        "line {}: a face needs three vertices or more, this one has {corners}",
                        number + 1
                    )));
                }
                for word in words {
                    for (kind, index) in word.split('/').enumerate() {
                        // Anything else is tobj's to refuse.
                        if !index.is_empty() && index.parse::<isize>().is_err() {
                            return Err(not_obj(format!(
                                "line {}: index `{word}` is not a number",
                                number + 1
                            )));
                        }
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
    // The library line goes in front of the file's text without copying the text: a
    // large file is held once.
    let header = format!("mtllib {OBJ_NAMES_LIBRARY}\n");
    let mut source = std::io::Read::chain(header.as_bytes(), text.as_bytes());
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj appends every library it is handed to the last: only the first `mtllib`
    // (the one above) gets the names, or n `mtllib` lines would make n copies of them.
    let handed = std::cell::Cell::new(false);
    let (models, materials) = tobj::load_obj_buf(&mut source, &options, |_| {
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
            // OBJ's v runs up the image; the maps' rows, like glTF's, down it.
            uvs: (!mesh.texcoords.is_empty()).then(|| {
                let uv = mesh.texcoords.as_chunks::<2>().0.iter();
                uv.map(|&[u, v]| glam::Vec2::new(u, 1.0 - v)).collect()
            }),
            triangles: mesh.indices.as_chunks::<3>().0.to_vec(),
            bare,
        })?;
    }
    builder.finish()
}

#[cfg(test)]
mod tests {
    use super::super::load;

    use super::super::tests::{TempFile, load_obj_text, problem};

    #[test]
    fn bad_numbers_are_named_by_their_line() {
        for (text, message) in [
            ("v 0 0 0\nv 1 x 0\n", "line 2: `x` is not a number"),
            ("v 0 0\n", "line 1: 3 numbers needed, 2 found"),
            ("v 0 0 0\nvn 0 1\n", "line 2: 3 numbers needed, 2 found"),
            ("vt u\n", "line 1: `u` is not a number"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 two 3\n",
                "line 4: index `two` is not a number",
            ),
        ] {
            let (file, result) = load_obj_text(text);
            assert_eq!(
                problem(&file, result.unwrap_err()),
                format!("not an OBJ file: {message}"),
                "{text:?}"
            );
        }
    }

    /// `vt` lines reach the surface, one per vertex, as the faces name them, v turned
    /// to run down the image; a file whose faces name none has none.
    #[test]
    fn obj_texture_coordinates_reach_the_surface() {
        let text = "v 0 0 0\nv 0 0 1\nv 1 0 0\nvt 0.5 0.25\nvt 0 1\nf 1/2 2/2 3/1\n";
        let (_file, result) = load_obj_text(text);
        let mesh = result.unwrap().surface;
        assert!(mesh.has_uvs());
        for (p, t) in mesh.positions.iter().zip(&mesh.uvs) {
            let expected = if p.x == 1.0 {
                glam::Vec2::new(0.5, 0.75)
            } else {
                glam::Vec2::new(0.0, 0.0)
            };
            assert_eq!(*t, expected, "at {p}");
        }
        let (_file, result) = load_obj_text("v 0 0 0\nv 0 0 1\nv 1 0 0\nf 1 2 3\n");
        assert!(!result.unwrap().surface.has_uvs());
    }

    #[test]
    fn a_face_of_two_vertices_is_named_by_its_line() {
        let (file, result) = load_obj_text("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\nf 1 2\n");
        assert_eq!(
            problem(&file, result.unwrap_err()),
            "not an OBJ file: line 5: a face needs three vertices or more, this one has 2"
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
}
