//! Change detection without reading data: values computed once per mesh content (content
//! hashes, bounds: `MeshMemo`), and a whole scene kept by pointer (`SceneSnapshot`), so a
//! frame of a static scene costs one pointer comparison per mesh and a few per scene.
//!
//! A scene holds its meshes behind `Arc`s and is edited through `Arc::make_mut` (its fields
//! are private: `Scene::mesh_mut`, `Scene::materials_mut` and `Scene::instances_mut` do it). A
//! memo keeps a clone of the `Arc` of each mesh it computed a value from, so an edited mesh is
//! always a new allocation (`make_mut` copies a shared mesh before the edit): the same pointer
//! means the same content, and a frame of a static scene costs one pointer comparison per mesh.
//! The memo keeps the meshes it last saw alive until its next call.

use super::{Instance, Material, Mesh, Scene};
use rayon::prelude::*;
use std::sync::Arc;

/// Everything a frame reads of a scene but its name, cameras and presets, kept as the `Arc`s it
/// saw (meshes, materials, instances, texture pixels, rig) and the small rest by value (lights,
/// pose time). While a snapshot holds them, an edit through `Arc::make_mut` cannot reuse their
/// allocations, so [`SceneSnapshot::matches`] is exact.
#[derive(Debug, Clone)]
pub(crate) struct SceneSnapshot {
    meshes: Vec<Arc<Mesh>>,
    materials: Arc<Vec<Material>>,
    instances: Arc<Vec<Instance>>,
    textures: Vec<(u32, u32, Arc<Vec<u8>>)>,
    lights: Vec<super::PunctualLight>,
    light: super::Light,
    point_light: Option<super::PointLight>,
    rig: Option<Arc<super::animation::Rig>>,
    posed: Option<super::animation::PoseTime>,
}

impl SceneSnapshot {
    /// The parts of `scene` a frame reads.
    pub fn of(scene: &Scene) -> Self {
        Self {
            meshes: scene.meshes.clone(),
            materials: Arc::clone(&scene.materials),
            instances: Arc::clone(&scene.instances),
            textures: scene.textures.iter().map(|t| (t.width, t.height, Arc::clone(&t.rgba))).collect(),
            lights: scene.lights.clone(),
            light: scene.light,
            point_light: scene.point_light,
            rig: scene.rig.clone(),
            posed: scene.posed,
        }
    }

    /// Whether `scene` is what this snapshot saw: the same allocations and the same lights.
    pub fn matches(&self, scene: &Scene) -> bool {
        fn same<T>(a: &Option<Arc<T>>, b: &Option<Arc<T>>) -> bool {
            match (a, b) {
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                (None, None) => true,
                _ => false,
            }
        }
        Arc::ptr_eq(&self.instances, &scene.instances)
            && Arc::ptr_eq(&self.materials, &scene.materials)
            && self.meshes.len() == scene.meshes.len()
            && self.meshes.iter().zip(&scene.meshes).all(|(a, b)| Arc::ptr_eq(a, b))
            && self.textures.len() == scene.textures.len()
            && self.textures.iter().zip(&scene.textures).all(|((w, h, p), t)| (*w, *h) == (t.width, t.height) && Arc::ptr_eq(p, &t.rgba))
            && self.light == scene.light
            && self.point_light == scene.point_light
            && self.lights == scene.lights
            && same(&self.rig, &scene.rig)
            && self.posed == scene.posed
    }
}

/// A value per mesh, kept while the mesh is the same `Arc`.
#[derive(Debug, Default)]
pub(crate) struct MeshMemo<T> {
    entries: Vec<Option<(Arc<Mesh>, T)>>,
}

impl<T: Clone + Send + Sync> MeshMemo<T> {
    /// An empty memo.
    pub fn new() -> Self {
        Self { entries: Vec::new() }
    }

    /// The value of every mesh of `meshes`, in order: a mesh that is the same `Arc` as at the
    /// same index on the last call keeps its value; the others get `f` (in parallel).
    pub fn values(&mut self, meshes: &[Arc<Mesh>], f: impl Fn(&Mesh) -> T + Sync) -> Vec<T> {
        self.entries.resize_with(meshes.len(), || None);
        let stale: Vec<usize> = (0..meshes.len()).filter(|&i| !self.entries[i].as_ref().is_some_and(|(seen, _)| Arc::ptr_eq(seen, &meshes[i]))).collect();
        let fresh: Vec<T> = stale.par_iter().map(|&i| f(&meshes[i])).collect();
        for (i, value) in stale.into_iter().zip(fresh) {
            self.entries[i] = Some((Arc::clone(&meshes[i]), value));
        }
        self.entries.iter().map(|e| e.as_ref().map(|(_, v)| v.clone()).expect("filled above")).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_snapshot_matches_its_scene_and_its_copies_until_one_is_edited() {
        let scene = crate::scene::builtin::default_scene();
        let seen = SceneSnapshot::of(&scene);
        let mut copy = scene.clone();
        assert!(seen.matches(&scene) && seen.matches(&copy), "a copy shares every allocation");
        copy.instances_mut()[0].transform = glam::Mat4::from_translation(glam::Vec3::X);
        assert!(!seen.matches(&copy) && seen.matches(&scene), "the edit copied the list: only the copy changed");
        let mut copy = scene.clone();
        copy.materials_mut()[0].roughness = 0.5;
        assert!(!seen.matches(&copy));
        let mut copy = scene.clone();
        copy.mesh_mut(0).vertices[0].position[0] += 1.0;
        assert!(!seen.matches(&copy));
        let mut copy = scene.clone();
        copy.light.intensity *= 2.0;
        assert!(!seen.matches(&copy));
    }

    #[test]
    fn only_meshes_edited_since_the_last_call_are_computed_again() {
        let mut meshes: Vec<Arc<Mesh>> = vec![Arc::new(crate::scene::builtin::cube("a")), Arc::new(crate::scene::builtin::cube("b"))];
        let calls = AtomicUsize::new(0);
        let mut memo = MeshMemo::new();
        let count = |m: &Mesh| {
            calls.fetch_add(1, Ordering::SeqCst);
            m.vertices[0].position[0]
        };
        let first = memo.values(&meshes, count);
        assert_eq!(calls.load(Ordering::SeqCst), 2);
        assert_eq!(memo.values(&meshes, count), first, "nothing edited: the same values");
        assert_eq!(calls.load(Ordering::SeqCst), 2, "and nothing computed");
        // An edit through make_mut copies the shared mesh: a new pointer, computed again.
        Arc::make_mut(&mut meshes[1]).vertices[0].position[0] += 1.0;
        let second = memo.values(&meshes, count);
        assert_eq!(calls.load(Ordering::SeqCst), 3);
        assert_eq!(second[1], first[1] + 1.0);
        meshes.push(Arc::new(crate::scene::builtin::cube("c")));
        assert_eq!(memo.values(&meshes, count).len(), 3);
        assert_eq!(calls.load(Ordering::SeqCst), 4);
    }
}
