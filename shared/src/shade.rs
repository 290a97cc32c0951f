//! Shading of the fragment stages: Lambert plus ambient, blades lit on both faces.

use spirv_std::glam::{Vec2, Vec3, Vec4};

/// Blade colour at the root (linear RGB).
pub const BLADE_BASE: Vec3 = Vec3::new(0.02, 0.10, 0.01);
/// Blade colour at the tip (linear RGB).
pub const BLADE_TIP: Vec3 = Vec3::new(0.30, 0.55, 0.08);

/// Lambert with ambient: albedo·(ambient + (1 − ambient)·max(n·l, 0)); `light` is
/// the direction towards the light (xyz) and the ambient term (w).
pub fn lambert(albedo: Vec3, normal: Vec3, light: Vec4) -> Vec3 {
    let diffuse = normal.dot(light.truncate()).max(0.0);
    albedo * (light.w + (1.0 - light.w) * diffuse)
}

/// A blade fragment at height `v` (0 root, 1 tip): the base-to-tip gradient, lit with
/// the normal flipped towards the viewer so both faces of the thin blade are lit.
pub fn shade_blade(normal: Vec3, position: Vec3, camera: Vec3, light: Vec4, v: f32) -> Vec3 {
    let n = if normal.dot(camera - position) < 0.0 {
        -normal
    } else {
        normal
    };
    lambert(BLADE_BASE.lerp(BLADE_TIP, v), n, light)
}

fn hash(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    (h & 0x00ff_ffff) as f32 / 16_777_216.0
}

/// Bilinear value noise in 0..1 on a unit grid.
pub fn value_noise(p: Vec2) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let s = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x, y) = (cell.x as i32 as u32, cell.y as i32 as u32);
    let a = hash(x, y);
    let b = hash(x.wrapping_add(1), y);
    let c = hash(x, y.wrapping_add(1));
    let d = hash(x.wrapping_add(1), y.wrapping_add(1));
    let top = a + (b - a) * s.x;
    let bottom = c + (d - c) * s.x;
    top + (bottom - top) * s.y
}

/// The ground's texture, generated: soil with patches of two noise octaves.
pub fn ground_albedo(xz: Vec2) -> Vec3 {
    let n = 0.65 * value_noise(xz * 1.7) + 0.35 * value_noise(xz * 7.3);
    let soil = Vec3::new(0.16, 0.10, 0.05);
    let moss = Vec3::new(0.07, 0.11, 0.03);
    soil.lerp(moss, n) * (0.7 + 0.6 * value_noise(xz * 23.0))
}

/// Corner `index` (0..6, two triangles) of the square ground of half size `half`,
/// in the XZ plane at y = 0.
pub fn ground_corner(index: u32, half: f32) -> Vec3 {
    // Triangles (0, 1, 2) and (2, 1, 3) of the corners (−,−), (+,−), (−,+), (+,+).
    let corner = match index {
        3 => 2,
        4 => 1,
        5 => 3,
        i => i,
    };
    let x = if corner & 1 == 0 { -half } else { half };
    let z = if corner & 2 == 0 { -half } else { half };
    Vec3::new(x, 0.0, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_hand_worked() {
        let light = Vec3::Y.extend(0.2);
        assert_eq!(lambert(Vec3::ONE, Vec3::Y, light), Vec3::ONE);
        assert_eq!(lambert(Vec3::ONE, -Vec3::Y, light), Vec3::splat(0.2));
    }

    #[test]
    fn both_faces_are_lit() {
        let light = Vec3::Z.extend(0.1);
        let cam = Vec3::new(0.0, 0.0, 5.0);
        let front = shade_blade(Vec3::Z, Vec3::ZERO, cam, light, 0.5);
        let back = shade_blade(-Vec3::Z, Vec3::ZERO, cam, light, 0.5);
        assert_eq!(front, back);
        assert!(shade_blade(Vec3::Z, Vec3::ZERO, cam, light, 1.0).y > front.y);
    }

    #[test]
    fn ground_is_two_triangles_covering_the_square() {
        let c: Vec<Vec3> = (0..6).map(|i| ground_corner(i, 2.0)).collect();
        assert_eq!(c[0], Vec3::new(-2.0, 0.0, -2.0));
        assert_eq!(c[5], Vec3::new(2.0, 0.0, 2.0));
        // Shared edge between the triangles, and both wound the same way.
        assert_eq!((c[2], c[1]), (c[3], c[4]));
        let n0 = (c[1] - c[0]).cross(c[2] - c[0]);
        let n1 = (c[4] - c[3]).cross(c[5] - c[3]);
        assert!(n0.y * n1.y > 0.0);
    }

    #[test]
    fn noise_is_in_range_and_continuous() {
        for i in -50..50 {
            let p = Vec2::new(i as f32 * 0.37, i as f32 * -0.61);
            let n = value_noise(p);
            assert!((0.0..=1.0).contains(&n));
            assert!((value_noise(p + Vec2::splat(1e-4)) - n).abs() < 1e-2);
        }
    }
}
