//! Perspective and orthographic cameras (right-handed, y up, wgpu depth range 0..1), and their
//! clip planes fitted to a scene's bounds.

use glam::{Mat4, Vec3};

/// A camera looking from `position` at `target`: perspective, or orthographic where
/// `orthographic` is set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// World-space eye position.
    pub position: Vec3,
    /// World-space point looked at.
    pub target: Vec3,
    /// World-space up direction.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
    /// `Some(half height)`: an orthographic camera whose view volume is that many units above
    /// and below its axis (glTF `ymag`; the output's aspect ratio sets the half width), with
    /// parallel rays; `fov_y` is then unused. `None`: perspective.
    pub orthographic: Option<f32>,
    /// The width / height its image is meant to have (glTF perspective `aspectRatio`,
    /// orthographic `xmag / ymag`): `render` sizes its output by it unless given both
    /// `--width` and `--height`. `None`: the output's aspect ratio.
    pub aspect_ratio: Option<f32>,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            position: Vec3::new(0.0, 1.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 50f32.to_radians(),
            near: 0.05,
            far: 1000.0,
            orthographic: None,
            aspect_ratio: None,
        }
    }
}

impl Camera {
    /// The camera `factor` times as far from its target along its view axis (closer below 1),
    /// its far plane moved back as far, its near plane kept.
    #[cfg(feature = "cli")]
    pub(crate) fn moved_back(&self, factor: f32) -> Camera {
        let offset = self.position - self.target;
        let position = self.target + offset * factor;
        Camera { position, far: self.far + offset.length() * (factor - 1.0).max(0.0), ..*self }
    }

    /// Directions of the rays through the centres of every `stride`-th pixel of a `w`×`h`
    /// image in each direction, row by row (all the view direction for an orthographic camera).
    pub fn ray_dirs(&self, size: (u32, u32), stride: u32) -> Vec<Vec3> {
        self.rays(size, stride).into_iter().map(|(_, d)| d).collect()
    }

    /// The origins and directions of the rays through the centres of every `stride`-th pixel
    /// of a `w`×`h` image in each direction, row by row: from `position` for a perspective
    /// camera, from the near plane along the view direction for an orthographic one.
    pub fn rays(&self, (w, h): (u32, u32), stride: u32) -> Vec<(Vec3, Vec3)> {
        let inv = self.view_proj(w as f32 / h as f32).inverse();
        let mut rays = Vec::with_capacity(((w / stride.max(1) + 1) * (h / stride.max(1) + 1)) as usize);
        for y in (0..h).step_by(stride.max(1) as usize) {
            for x in (0..w).step_by(stride.max(1) as usize) {
                rays.push(self.ray_with(&inv, (w, h), glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5)));
            }
        }
        rays
    }

    /// The origin and direction of the ray through `point` (in pixels from the top left corner)
    /// of a `w`×`h` image, as [`Camera::rays`] gives them.
    pub fn ray_through(&self, (w, h): (u32, u32), point: glam::Vec2) -> (Vec3, Vec3) {
        self.ray_with(&self.view_proj(w as f32 / h as f32).inverse(), (w, h), point)
    }

    fn ray_with(&self, inv_view_proj: &Mat4, (w, h): (u32, u32), point: glam::Vec2) -> (Vec3, Vec3) {
        let ndc = glam::Vec2::new(point.x / w as f32 * 2.0 - 1.0, 1.0 - point.y / h as f32 * 2.0);
        let far = inv_view_proj.project_point3(ndc.extend(1.0));
        match self.orthographic {
            Some(_) => {
                let near = inv_view_proj.project_point3(ndc.extend(0.0));
                (near, (far - near).normalize())
            }
            None => (self.position, (far - self.position).normalize()),
        }
    }

    /// A perspective camera at `position` looking at `target`, y up, `fov_y_deg` vertical field
    /// of view.
    pub fn look(position: Vec3, target: Vec3, fov_y_deg: f32, near: f32, far: f32) -> Self {
        Self { position, target, up: Vec3::Y, fov_y: fov_y_deg.to_radians(), near, far, orthographic: None, aspect_ratio: None }
    }

    /// This camera with its near and far planes fitted to `bounds` from where it stands: the
    /// far plane just past the bounds' far side, the near plane just before their near side
    /// (inside the bounds: 1/10,000 of the far distance), so that a camera at any distance
    /// draws the whole scene. Unchanged for empty bounds.
    pub fn fit_clip_planes(self, bounds: super::Bounds) -> Self {
        if bounds.is_empty() {
            return self;
        }
        let radius = (0.5 * bounds.diagonal()).max(1e-6);
        let distance = self.position.distance(bounds.center());
        let far = (distance + radius) * 1.01;
        let near = ((distance - radius) * 0.99).max(far * 1e-4);
        Self { near, far, ..self }
    }

    /// Presets for any scene from its bounds: `front` (framing all of it), `top` (looking
    /// down) and `side`.
    pub(crate) fn presets_for(bounds: super::Bounds) -> Vec<(String, Camera)> {
        let front = Self::framing(bounds);
        let d = front.position.distance(front.target);
        let c = bounds.center();
        let top = Self::look(c + Vec3::new(0.0, d, d * 1e-3), c, front.fov_y.to_degrees(), front.near, front.far);
        let side = Self::look(c + Vec3::new(d, d * 0.1, 0.0), c, front.fov_y.to_degrees(), front.near, front.far);
        vec![("front".into(), front), ("top".into(), top), ("side".into(), side)]
    }

    /// A camera that sees all of `bounds` from the front (on +Z, looking towards -Z: the
    /// glTF convention).
    pub fn framing(bounds: super::Bounds) -> Self {
        if bounds.is_empty() {
            return Self::default();
        }
        let radius = (0.5 * bounds.diagonal()).max(1e-3);
        let fov_y = 50f32.to_radians();
        let distance = radius / (0.5 * fov_y).sin() * 1.05;
        Self {
            position: bounds.center() + Vec3::Z * distance,
            target: bounds.center(),
            up: Vec3::Y,
            fov_y,
            near: (distance - radius).max(distance * 1e-3) * 0.5,
            far: (distance + radius) * 2.0,
            orthographic: None,
            aspect_ratio: None,
        }
    }

    /// World to view space.
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// View to clip space for a viewport of `aspect` (width / height).
    pub(crate) fn projection(&self, aspect: f32) -> Mat4 {
        match self.orthographic {
            Some(h) => Mat4::orthographic_rh(-h * aspect, h * aspect, -h, h, self.near, self.far),
            None => Mat4::perspective_rh(self.fov_y, aspect, self.near, self.far),
        }
    }

    /// World to clip space (`projection * view`).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}
