//! Scene duplication for the build-time experiment: N×N×N copies on a grid, sharing meshes
//! (one BLAS per mesh) or with every copy owning its meshes (one BLAS per copy).

use super::Scene;
use glam::{Mat4, Vec3};

/// Copies `scene` on an `n`×`n`×`n` grid spaced by 1.1× its extent. With `dedup`, copies
/// share the original meshes; without, each copy gets its own mesh entries.
pub fn duplicate(scene: &Scene, n: u32, dedup: bool) -> Scene {
    let n = n.max(1);
    let b = scene.bounds();
    let step = if b.is_empty() { Vec3::ONE } else { (b.max - b.min).max(Vec3::splat(1e-3)) * 1.1 };
    let mut out = Scene { name: format!("{}x{n}", scene.name), meshes: Vec::new(), instances: Default::default(), ..scene.clone() };
    if dedup {
        out.meshes = scene.meshes.clone();
    }
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let offset = Mat4::from_translation(step * Vec3::new(x as f32, y as f32, z as f32));
                let base = out.meshes.len();
                if !dedup {
                    out.meshes.extend(scene.meshes.iter().cloned());
                }
                for inst in scene.instances.iter() {
                    let mut i = inst.clone();
                    i.transform = offset * inst.transform;
                    if !dedup {
                        i.mesh += base;
                    }
                    out.instances_mut().push(i);
                }
            }
        }
    }
    let grid = b.union(&super::Bounds { min: b.min, max: b.max + step * (n - 1) as f32 });
    out.camera = super::Camera::framing(grid);
    out.presets.insert(0, ("grid".into(), out.camera));
    out
}
