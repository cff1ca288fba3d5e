//! The scene's triangles as the `rt-pipeline` back-end's BLAS builds and hit shaders read
//! them: one position and one index array for every unit, each unit's geometries (opaque or
//! alpha-tested), and the merged layout's triangle owners.

use crate::accel::alpha::instance_tested as alpha_tested;
use crate::scene::Scene;

/// One geometry of a BLAS: a range of the packed triangles, opaque or alpha-tested.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Geometry {
    pub(super) first: u32,
    pub(super) count: u32,
    pub(super) opaque: bool,
}

/// Every unit's triangles packed into one position and one index array (indices already
/// offset to the packed positions), which the BLAS builds read and so do the hit shaders.
pub(super) struct Packed {
    pub(super) positions: Vec<[f32; 3]>,
    pub(super) indices: Vec<u32>,
    /// Per unit, its BLAS's geometries (`None`: no valid triangle, no BLAS).
    pub(super) spans: Vec<Option<Vec<Geometry>>>,
    /// The merged layout: each merged triangle's instance and primitive (bit 31: mirrored).
    pub(super) owners: Vec<[u32; 2]>,
    /// `accel_first_triangle`: per scene instance its unit's first triangle; merged, per
    /// geometry of the one BLAS its first triangle.
    pub(super) first_triangles: Vec<u32>,
}

/// Packs the scene's triangles (see [`Packed`]). Two levels: a unit's one geometry is
/// alpha-tested when any instance of it is (its opaque instances are forced opaque in the
/// TLAS). Merged: opaque triangles first, then alpha-tested ones, as two geometries.
pub(super) fn pack(scene: &Scene, unit_meshes: &[usize], unit_of_instance: &dyn Fn(usize) -> usize, merged: bool) -> Packed {
    let mut packed = Packed { positions: Vec::new(), indices: Vec::new(), spans: Vec::new(), owners: Vec::new(), first_triangles: Vec::new() };
    if merged {
        // One unit: every instance's triangles in world space (`layout::merge_instances`),
        // mirrored instances' triangles wound back so that facing stays the object-space
        // facing the other layouts report and cull by.
        let (mesh, origin) = crate::accel::layout::merge_instances(scene);
        let Some((p, i)) = crate::accel::bvh::driver_triangles(&mesh) else {
            packed.spans.push(None);
            packed.spans.resize(unit_meshes.len(), None);
            return packed;
        };
        let alpha: Vec<bool> = (0..scene.instances().len()).map(|i| alpha_tested(scene, i)).collect();
        let mut geometries = Vec::new();
        for opaque in [true, false] {
            let first = (packed.indices.len() / 3) as u32;
            for (t, o) in origin.iter().enumerate().filter(|(_, o)| alpha[o.instance as usize] != opaque) {
                let tri = &i[3 * t..3 * t + 3];
                packed.indices.extend(if o.mirrored { [tri[0], tri[2], tri[1]] } else { [tri[0], tri[1], tri[2]] });
                packed.owners.push([o.instance, o.prim | (o.mirrored as u32) << 31]);
            }
            let count = (packed.indices.len() / 3) as u32 - first;
            if count > 0 {
                geometries.push(Geometry { first, count, opaque });
                packed.first_triangles.push(first);
            }
        }
        packed.positions = p;
        packed.spans.push(Some(geometries));
    } else {
        let mut unit_alpha = vec![false; unit_meshes.len()];
        for i in (0..scene.instances().len()).filter(|&i| alpha_tested(scene, i)) {
            if let Some(a) = unit_alpha.get_mut(unit_of_instance(i)) {
                *a = true;
            }
        }
        for (u, &mesh) in unit_meshes.iter().enumerate() {
            let Some((p, i)) = scene.meshes().get(mesh).and_then(|m| crate::accel::bvh::driver_triangles(m)) else {
                packed.spans.push(None);
                continue;
            };
            let base = packed.positions.len() as u32;
            let geometry = Geometry { first: (packed.indices.len() / 3) as u32, count: (i.len() / 3) as u32, opaque: !unit_alpha[u] };
            packed.spans.push(Some(vec![geometry]));
            packed.positions.extend_from_slice(&p);
            packed.indices.extend(i.iter().map(|&x| x + base));
        }
        packed.first_triangles =
            (0..scene.instances().len()).map(|i| packed.spans.get(unit_of_instance(i)).and_then(|s| s.as_ref()).map_or(0, |g| g[0].first)).collect();
    }
    packed.spans.resize(unit_meshes.len(), None);
    packed
}
