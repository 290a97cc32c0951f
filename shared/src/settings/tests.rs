//! Unit tests of `settings`.

use super::*;

#[test]
fn cull_masks_round_trip() {
    for mask in 0..16 {
        assert_eq!(CullTests::from_mask(mask).mask(), mask);
    }
    assert_eq!(CullTests::ALL.mask(), crate::cull::blade::ALL);
    assert_eq!(CullTests::PAPER.mask(), ORIENTATION | FRUSTUM | DISTANCE);
}

#[test]
fn enums_are_the_shaders_numbers() {
    assert_eq!(WindField::Vortex as u32, WIND_VORTEX);
    assert_eq!(BladeShape::TriangleTip as u32, SHAPE_TRIANGLE_TIP);
    assert_eq!(View::Wireframe as u32, VIEW_WIREFRAME);
    assert_eq!(View::Wireframe.next(), View::Shaded);
    assert_eq!(WindField::Calm.next(), WindField::Breeze);
}

#[test]
fn the_block_by_hand() {
    let mut s = Settings::default();
    s.lod.on = false;
    s.cull.tests.distance = false;
    s.gravity.centre = Vec3::new(0.0, -30.0, 0.0);
    s.wind.direction = 90.0;
    let eye = Viewpoint {
        view_proj: Mat4::IDENTITY,
        position: Vec3::new(1.0, 2.0, 3.0),
        fov_y: std::f32::consts::FRAC_PI_2,
        height: 200,
        forward: Vec3::Z,
    };
    let balls = [Vec4::ONE; MAX_COLLIDERS + 3];
    let u = s.uniforms(&eye, 1234, &balls);
    // tan(45°) = 1: the focal length is half the height.
    assert!((u.camera.focal_pixels - 100.0).abs() < 1e-4);
    assert_eq!(u.camera.position, eye.position);
    // LOD off: the fewest segments are the most.
    assert_eq!((u.lod.most, u.lod.fewest), (7.0, 7.0));
    assert_eq!(u.cull.enabled, ORIENTATION | FRUSTUM | OCCLUSION);
    assert_eq!(u.forces.colliders, MAX_COLLIDERS as u32);
    assert_eq!(u.forces.gravity_centre, Vec4::new(0.0, -30.0, 0.0, 9.8));
    assert!((u.forces.wind - Vec4::new(0.0, 0.0, 1.0, 7.0)).length() < 1e-6);
    assert_eq!(u.grass.blades, 1234);
    assert_eq!(u.grass.shape, SHAPE_QUADRATIC);
    assert!(u.hiz.is_empty());
}
