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
