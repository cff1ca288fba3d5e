//! A disk-shaped emitter over a floor, and the form factor of a polygon from a floor point
//! (Lambert's contour integral): the closed form of the light a finite emitter gives.

use glam::{Mat4, Vec3};
use raygraph::scene::builtin::default_scene;
use raygraph::scene::{Camera, Instance, LightKind, Material, Mesh, PunctualLight, Scene, Vertex};

pub const DISK_SIDES: usize = 48;
pub const DISK_HEIGHT: f32 = 1.0;
pub const DISK_RADIUS: f32 = 1.0;

/// The disk's rim, counter-clockwise seen from above (its triangles face up).
pub fn disk_rim() -> Vec<Vec3> {
    (0..DISK_SIDES)
        .map(|i| {
            let a = -(i as f32) * std::f32::consts::TAU / DISK_SIDES as f32;
            Vec3::new(DISK_RADIUS * a.cos(), DISK_HEIGHT, DISK_RADIUS * a.sin())
        })
        .collect()
}

/// A floor (y = 0, 20 x 20, material `floor`) under a disk (`emitter`) of radius
/// [`DISK_RADIUS`] at height [`DISK_HEIGHT`], wound to face up (double-sided materials light
/// the floor), lit by nothing else.
pub fn disk_over_floor(emitter: Material, floor: Material) -> Scene {
    let mut s = default_scene();
    s.set_name("disk over a floor");
    let v = |p: Vec3, n: Vec3| Vertex { position: p.into(), normal: n.into(), uv: [0.0, 0.0] };
    let floor_mesh = Mesh {
        name: "floor".into(),
        vertices: [(-10.0, -10.0), (10.0, -10.0), (10.0, 10.0), (-10.0, 10.0)].iter().map(|&(x, z)| v(Vec3::new(x, 0.0, z), Vec3::Y)).collect(),
        indices: vec![0, 2, 1, 0, 3, 2],
        tangents: None,
        extras: None,
    };
    let mut vertices = vec![v(Vec3::new(0.0, DISK_HEIGHT, 0.0), Vec3::NEG_Y)];
    vertices.extend(disk_rim().into_iter().map(|p| v(p, Vec3::NEG_Y)));
    let indices = (0..DISK_SIDES as u32).flat_map(|i| [0, 1 + i, 1 + (i + 1) % DISK_SIDES as u32]).collect();
    let disk = Mesh { name: "disk".into(), vertices, indices, tangents: None, extras: None };
    s.set_meshes(vec![floor_mesh, disk]);
    *s.textures_mut() = Vec::new();
    *s.materials_mut() = vec![floor, emitter];
    *s.instances_mut() = vec![Instance { mesh: 0, material: 0, transform: Mat4::IDENTITY }, Instance { mesh: 1, material: 1, transform: Mat4::IDENTITY }];
    // No light: the disk is the only source the GI rays can find.
    *s.lights_mut() = vec![PunctualLight {
        name: "off".into(),
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 0.0,
    }];
    s.light_mut().ambient = 0.0;
    *s.camera_mut() = Camera::look(Vec3::new(0.0, 0.6, 3.2), Vec3::new(0.0, 0.0, 0.0), 70.0, 0.01, 100.0);
    s
}

/// The form factor from a floor point `p` (normal +y) to the polygon `rim`.
pub fn form_factor(p: Vec3, rim: &[Vec3]) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..rim.len() {
        let a = (rim[i] - p).as_dvec3().normalize();
        let b = (rim[(i + 1) % rim.len()] - p).as_dvec3().normalize();
        let c = a.cross(b);
        sum += a.dot(b).clamp(-1.0, 1.0).acos() * c.y / c.length();
    }
    (sum / std::f64::consts::TAU).abs()
}
