//! The orbit camera: yaw and pitch around a target, at a distance.

use glam::camera::rh;
use glam::{Mat4, Vec3};
use shared::settings::Viewpoint;

/// A camera orbiting `target`.
#[derive(Copy, Clone, Debug)]
pub struct OrbitCamera {
    /// Point looked at.
    pub target: Vec3,
    /// Angle around +Y, radians.
    pub yaw: f32,
    /// Angle above the ground, radians.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Distance of the far plane; 0 for four times the distance (at least 200).
    pub far: f32,
}

impl OrbitCamera {
    /// What the shaders need of this camera on a target of `extent` (width, height
    /// in pixels).
    pub fn viewpoint(&self, extent: (u32, u32)) -> Viewpoint {
        let aspect = extent.0 as f32 / extent.1.max(1) as f32;
        Viewpoint {
            view_proj: self.view_proj(aspect),
            position: self.eye(),
            fov_y: self.fov_y,
            height: extent.1,
            forward: (self.target - self.eye()).normalize_or_zero(),
        }
    }

    /// A view of a square field of side `side` from beyond its edge, looking over it.
    pub fn framing(side: f32) -> Self {
        Self {
            target: Vec3::new(0.0, 0.5, 0.0),
            yaw: 0.5,
            pitch: 0.38,
            distance: side * 0.75 + 6.0,
            fov_y: 50f32.to_radians(),
            far: 0.0,
        }
    }

    /// Eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }

    /// World to clip (Vulkan: y down, depth 0..1), for `aspect` = width / height.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let view = rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y);
        let far = if self.far > 0.0 {
            self.far
        } else {
            (self.distance * 4.0).max(200.0)
        };
        rh::proj::vulkan::perspective(self.fov_y, aspect.max(1e-3), 0.1, far) * view
    }

    /// Drag: rotate by pixels moved.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.005;
        self.pitch = (self.pitch + dy * 0.005).clamp(0.02, 1.5);
    }

    /// Wheel: zoom by `steps` notches (positive is closer).
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(1.0, 2000.0);
    }

    /// Pan: move the target in the ground plane by pixels moved.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let (sy, cy) = self.yaw.sin_cos();
        let right = Vec3::new(cy, 0.0, -sy);
        let forward = Vec3::new(-sy, 0.0, -cy);
        let scale = self.distance * 0.0015;
        self.target += (-dx * right + dy * forward) * scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flying_forward_moves_the_target_where_the_camera_looks_and_keeps_it_over_the_ground() {
        let mut camera = OrbitCamera::framing(10.0);
        camera.yaw = 0.0;
        let fly = Fly {
            on: true,
            speed: 4.0,
        };
        let before = camera.target;
        let looking = (camera.target - camera.eye()).with_y(0.0).normalize();
        fly.step(&mut camera, glam::Vec2::new(0.0, 1.0), 0.5, |x, _| {
            Some(x * 0.1)
        });
        let moved = camera.target - before;
        assert!(
            (moved.with_y(0.0) - looking * 2.0).length() < 1e-5,
            "{moved}"
        );
        assert!((camera.target.y - (camera.target.x * 0.1 + 1.0)).abs() < 1e-6);
        let mut fast = fly;
        for _ in 0..20 {
            fast.change_speed(true);
        }
        assert_eq!(fast.speed, Fly::SPEEDS.1);
    }

    #[test]
    fn target_projects_to_the_centre_in_vulkan_depth() {
        let cam = OrbitCamera::framing(20.0);
        let clip = cam.view_proj(1.5) * cam.target.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!(ndc.x.abs() < 1e-5 && ndc.y.abs() < 1e-5);
        assert!(ndc.z > 0.0 && ndc.z < 1.0);
        // A point above the target appears higher: negative y in Vulkan.
        let above = cam.view_proj(1.5) * (cam.target + Vec3::Y).extend(1.0);
        assert!(above.y / above.w < 0.0);
    }
}

/// Flying the camera over the ground (the viewer's F key): the arrow keys move the
/// orbit's target forward, back and sideways at `speed` units a second, and the target
/// keeps `height` above the ground under it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Fly {
    /// The arrows fly the camera (else they roll the ball).
    pub on: bool,
    /// Units a second.
    pub speed: f32,
}

impl Default for Fly {
    /// Off, 8 units a second.
    fn default() -> Self {
        Self {
            on: false,
            speed: 8.0,
        }
    }
}

impl Fly {
    /// Slowest and fastest speeds (units a second) the keys and the overlay offer.
    pub const SPEEDS: (f32, f32) = (1.0, 512.0);

    /// Moves `camera`'s target by `axis` (right, forward in −1..1) for `dt` seconds,
    /// then to `height` above `ground(x, z)` where there is ground.
    pub fn step(
        &self,
        camera: &mut OrbitCamera,
        axis: glam::Vec2,
        dt: f32,
        ground: impl Fn(f32, f32) -> Option<f32>,
    ) {
        let (sy, cy) = camera.yaw.sin_cos();
        let right = Vec3::new(cy, 0.0, -sy);
        let forward = Vec3::new(-sy, 0.0, -cy);
        camera.target += (right * axis.x + forward * axis.y) * self.speed * dt;
        if let Some(y) = ground(camera.target.x, camera.target.z) {
            camera.target.y = y + 1.0;
        }
    }

    /// Twice as fast (`faster`) or half as fast, within [`Fly::SPEEDS`].
    pub fn change_speed(&mut self, faster: bool) {
        let factor = if faster { 2.0 } else { 0.5 };
        self.speed = (self.speed * factor).clamp(Self::SPEEDS.0, Self::SPEEDS.1);
    }
}
