//! Where things stand, in the embedding examples (`embed`, `wgpu`): the cube over
//! the middle of the field, spinning, the camera looking at it, the sky behind.

use glam::camera::rh;
use glam::{Mat4, Quat, Vec2, Vec3};
use runner::embed::GrassField;
use shared::sim::collide::Collider;

/// The cube's colour (linear): a magenta nothing else in the frame has.
pub const CUBE_COLOR: Vec3 = Vec3::new(0.8, 0.06, 0.5);
/// Half the cube's side.
pub const CUBE_HALF: f32 = 1.0;

/// Colour the frame is cleared to: the sky (linear).
pub(crate) const SKY: [f32; 4] = [0.42, 0.62, 0.86, 1.0];
/// Blades in the field.
pub const BLADES: u32 = 20_000;
/// Simulated seconds a frame.
pub(crate) const FRAME_SECONDS: f64 = 1.0 / 60.0;

/// Where things stand: the cube over the middle of the field, spinning, and the
/// camera looking at it.
pub struct Stage {
    /// The cube's centre.
    pub cube: Vec3,
    /// The camera's position.
    pub eye: Vec3,
}

impl Stage {
    /// The stage over `field`'s ground.
    pub fn new(field: &GrassField) -> Self {
        let ground = field.ground_at(0.0, 0.0).unwrap_or(field.bounds().0);
        let cube = ground + Vec3::new(0.0, 1.7, 0.0);
        Self {
            cube,
            eye: cube + Vec3::new(3.0, 3.2, 8.5),
        }
    }

    /// The cube's model matrix at `time` seconds: a quarter turn a second about y,
    /// tilted so three faces show.
    pub fn cube_model(&self, time: f32) -> Mat4 {
        Mat4::from_translation(self.cube)
            * Mat4::from_quat(self.cube_turn(time))
            * Mat4::from_scale(Vec3::splat(CUBE_HALF))
    }

    /// The cube's turn at simulated `time`.
    fn cube_turn(&self, time: f32) -> Quat {
        Quat::from_rotation_y(time * std::f32::consts::FRAC_PI_2) * Quat::from_rotation_x(0.5)
    }

    /// The cube as a collider at simulated `time`: a box turning with it.
    pub fn cube_collider(&self, time: f32) -> Collider {
        Collider::cuboid(self.cube, Vec3::splat(CUBE_HALF), self.cube_turn(time), 0.0)
    }

    /// (view, projection) on a `width` × `height` target (Vulkan clip space).
    pub fn camera(&self, (width, height): (u32, u32)) -> (Mat4, Mat4) {
        let view = rh::view::look_at_mat4(self.eye, self.cube, Vec3::Y);
        let aspect = width as f32 / height.max(1) as f32;
        let proj = rh::proj::vulkan::perspective(50f32.to_radians(), aspect, 0.1, 300.0);
        (view, proj)
    }

    /// The cube's 8 corners at `time`, in pixels on a `size` target.
    pub fn cube_corners_px(&self, time: f32, size: (u32, u32)) -> Vec<Vec2> {
        let (view, proj) = self.camera(size);
        let mvp = proj * view * self.cube_model(time);
        (0..8)
            .map(|i| {
                let corner = Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                let clip = mvp * corner.extend(1.0);
                let ndc = clip.truncate().truncate() / clip.w;
                (ndc * 0.5 + 0.5) * Vec2::new(size.0 as f32, size.1 as f32)
            })
            .collect()
    }
}

/// `WIDTHxHEIGHT`, both from 1 to 8192.
pub fn size(text: &str) -> Result<(u32, u32), String> {
    let parsed = text
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    match parsed {
        Some((w, h)) if (1..=8192).contains(&w) && (1..=8192).contains(&h) => Ok((w, h)),
        _ => Err(format!("{text:?} is no size: WIDTHxHEIGHT, each 1 to 8192")),
    }
}
