//! The embedding example's own object (`runner/examples/embed/`): a cube of half
//! side 1 drawn from its vertex index alone (36 vertices, two triangles a face, no
//! vertex buffer), flat-shaded by one light. Not part of the grass: it stands for the
//! caller's scene the grass is drawn into.

use crate::glam::{Mat4, Vec3, Vec4};

/// Vertices of the cube's draw: 6 faces of 2 triangles.
pub const CUBE_VERTICES: u32 = 36;

/// The cube's push constants: where it stands and how it is lit.
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct CubePush {
    /// Model to clip space.
    pub model_view_proj: Mat4,
    /// Model to world space (a rotation, scale and move: normals turn with it).
    pub model: Mat4,
    /// Base colour (linear rgb, w unused).
    pub color: Vec4,
    /// Unit direction towards the light (xyz), ambient share (w).
    pub light: Vec4,
}

/// Unit vector along axis `axis` (0 x, 1 y, 2 z).
fn axis_vector(axis: u32) -> Vec3 {
    if axis == 0 {
        Vec3::X
    } else if axis == 1 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// Position and outward normal of vertex `vertex` (0..[`CUBE_VERTICES`]) in model
/// space. Face `f = vertex / 6` faces +axis for even `f`, -axis for odd, with axis
/// `f / 2`; its quad's corners run counter-clockwise seen from outside, split into
/// triangles (0, 1, 2) and (0, 2, 3).
pub fn cube_vertex(vertex: u32) -> (Vec3, Vec3) {
    let face = (vertex / 6) % 6;
    let axis = face / 2;
    let sign = if face & 1 == 0 { 1.0 } else { -1.0 };
    let normal = sign * axis_vector(axis);
    // u × v = +axis; swapped on the negative face so the quad still turns
    // counter-clockwise seen from outside.
    let (mut u, mut v) = (axis_vector((axis + 1) % 3), axis_vector((axis + 2) % 3));
    if sign < 0.0 {
        core::mem::swap(&mut u, &mut v);
    }
    let corner = match vertex % 6 {
        0 | 3 => 0,
        1 => 1,
        2 | 4 => 2,
        _ => 3,
    };
    let a = if corner == 1 || corner == 2 {
        1.0
    } else {
        -1.0
    };
    let b = if corner >= 2 { 1.0 } else { -1.0 };
    (normal + a * u + b * v, normal)
}

/// Lambert shading of a face of world normal `normal`: `color` times the ambient
/// share plus the direct light.
pub fn cube_shade(push: &CubePush, normal: Vec3) -> Vec3 {
    let ambient = push.light.w;
    let direct = normal
        .normalize_or_zero()
        .dot(push.light.truncate())
        .max(0.0);
    push.color.truncate() * (ambient + (1.0 - ambient) * direct)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn twelve_outward_counter_clockwise_triangles_cover_the_cube() {
        let mut area = 0.0;
        let mut corners = std::collections::BTreeSet::new();
        for t in 0..CUBE_VERTICES / 3 {
            let [(a, n), (b, _), (c, _)] = [0, 1, 2].map(|k| cube_vertex(3 * t + k));
            // On its face, every corner at distance 1 from the centre along the normal.
            for p in [a, b, c] {
                assert!(
                    (p.dot(n) - 1.0).abs() < 1e-6,
                    "triangle {t}: {p} off face {n}"
                );
                assert!(p.abs().max_element() == 1.0 && p.abs().min_element() == 1.0);
                corners.insert(p.to_array().map(|x| x as i32));
            }
            let cross = (b - a).cross(c - a);
            // Counter-clockwise seen from outside: the winding's normal is the face's.
            assert!(
                (cross.normalize() - n).length() < 1e-6,
                "triangle {t} winds inwards"
            );
            area += 0.5 * cross.length();
        }
        assert_eq!(corners.len(), 8);
        // Six faces of side 2.
        assert!((area - 24.0).abs() < 1e-4, "area {area}");
        let normals: std::collections::BTreeSet<_> = (0..CUBE_VERTICES)
            .map(|v| cube_vertex(v).1.to_array().map(|x| x as i32))
            .collect();
        assert_eq!(normals.len(), 6);
    }

    #[test]
    fn faces_towards_the_light_are_brighter() {
        let push = CubePush {
            color: Vec4::new(1.0, 0.5, 0.25, 0.0),
            light: Vec4::new(0.0, 1.0, 0.0, 0.25),
            ..Default::default()
        };
        assert_eq!(cube_shade(&push, Vec3::Y), Vec3::new(1.0, 0.5, 0.25));
        assert_eq!(cube_shade(&push, -Vec3::Y), Vec3::new(0.25, 0.125, 0.0625));
        assert_eq!(cube_shade(&push, Vec3::X), cube_shade(&push, -Vec3::Y));
    }
}
