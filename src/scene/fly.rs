//! The fly camera of the viewer and the web page: position, yaw and pitch moved by held keys
//! (WASD, Q/E down/up), turned by mouse movement, its speed scaled by the wheel.

use crate::scene::Camera;
use glam::Vec3;

/// Keys held this frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct Motion {
    /// Forward (W).
    pub forward: bool,
    /// Back (S).
    pub back: bool,
    /// Left (A).
    pub left: bool,
    /// Right (D).
    pub right: bool,
    /// Up (E).
    pub up: bool,
    /// Down (Q).
    pub down: bool,
    /// Four times the speed (Shift).
    pub fast: bool,
}

/// A camera as position, yaw and pitch (radians; yaw 0 looks down -z), moved by [`Motion`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlyCamera {
    position: Vec3,
    yaw: f32,
    pitch: f32,
    /// Units per second.
    speed: f32,
    fov_y: f32,
    near: f32,
    far: f32,
    orthographic: Option<f32>,
    aspect_ratio: Option<f32>,
}

impl FlyCamera {
    /// Units per second.
    pub fn speed(&self) -> f32 {
        self.speed
    }

    /// The same camera moving at `speed` units per second (a speed kept from another one).
    pub fn with_speed(self, speed: f32) -> Self {
        Self { speed, ..self }
    }

    /// Looking where `c` looks; `scene_radius` sets the starting speed (a quarter of the scene
    /// per second).
    pub fn from_camera(c: &Camera, scene_radius: f32) -> Self {
        let d = (c.target - c.position).normalize_or(Vec3::NEG_Z);
        Self {
            position: c.position,
            yaw: d.x.atan2(-d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin(),
            speed: (scene_radius * 0.25).max(1e-3),
            fov_y: c.fov_y,
            near: c.near,
            far: c.far,
            orthographic: c.orthographic,
            aspect_ratio: c.aspect_ratio,
        }
    }

    pub(crate) fn forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::new(sy * cp, sp, -cy * cp)
    }

    /// The camera it describes.
    pub fn camera(&self) -> Camera {
        Camera {
            position: self.position,
            target: self.position + self.forward(),
            up: Vec3::Y,
            fov_y: self.fov_y,
            near: self.near,
            far: self.far,
            orthographic: self.orthographic,
            aspect_ratio: self.aspect_ratio,
        }
    }

    /// Moves by the held keys over `dt` seconds.
    pub fn advance(&mut self, m: &Motion, dt: f32) {
        let f = self.forward();
        let right = f.cross(Vec3::Y).normalize_or(Vec3::X);
        let mut d = Vec3::ZERO;
        let axis = |on: bool| if on { 1.0 } else { 0.0 };
        d += f * (axis(m.forward) - axis(m.back));
        d += right * (axis(m.right) - axis(m.left));
        d += Vec3::Y * (axis(m.up) - axis(m.down));
        if d != Vec3::ZERO {
            self.position += d.normalize() * self.speed * dt * if m.fast { 4.0 } else { 1.0 };
        }
    }

    /// Turns by a mouse movement of `dx`, `dy` pixels.
    pub fn look(&mut self, dx: f32, dy: f32) {
        const RADIANS_PER_PIXEL: f32 = 0.003;
        self.yaw += dx * RADIANS_PER_PIXEL;
        self.pitch = (self.pitch - dy * RADIANS_PER_PIXEL).clamp(-1.55, 1.55);
    }

    /// Wheel: each notch scales the speed by 1.2.
    pub fn scale_speed(&mut self, notches: f32) {
        self.speed = (self.speed * 1.2f32.powf(notches)).clamp(1e-4, 1e6);
    }
}
