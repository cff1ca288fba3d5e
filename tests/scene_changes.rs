//! The executor follows the scene by pointer (`scene::memo`): frames of an unchanged scene find
//! no change, an edit of a copy of the scene is not an edit of the scene, and every edit made
//! through the scene's accessors (`instances_mut`, `materials_mut`, `mesh_mut`) or its public
//! fields is seen: after each edit, the picture equals the one a new executor makes of the
//! edited scene, byte for byte, in the three modes.

mod common;

use glam::{Mat4, Vec3};
use raygraph::backend::Backend;
use raygraph::scene::builtin::default_scene;
use raygraph::scene::Scene;

type Edit = (&'static str, fn(&mut Scene));

/// Edits of every kind of scene data a frame reads.
fn edits() -> Vec<Edit> {
    vec![
        ("an instance moved", |s| s.instances_mut()[1].transform = Mat4::from_translation(Vec3::new(0.3, 0.4, 0.0)) * s.instances()[1].transform),
        ("a material's colour", |s| s.materials_mut()[0].base_color = [0.9, 0.2, 0.1, 1.0]),
        ("a mesh's vertices", |s| {
            let mesh = s.mesh_mut(2);
            for v in &mut mesh.vertices {
                v.position[1] *= 1.5;
            }
        }),
        ("an instance added", |s| {
            let mut copy = s.instances()[2].clone();
            copy.transform = Mat4::from_translation(Vec3::new(-0.8, 0.6, 0.4)) * copy.transform;
            s.instances_mut().push(copy);
        }),
        ("the sun turned", |s| s.light_mut().direction = Vec3::new(-0.6, 0.5, 0.3).normalize()),
    ]
}

#[test]
fn every_edit_is_seen_and_an_unchanged_scene_is_not_looked_at_again() {
    let gpu = common::gpu();
    let size = (48, 32);
    for graph in ["graph/raster.ron", "graph/hybrid.ron", "graph/full_rt.ron"] {
        let mut scene = default_scene();
        let mut exec = common::modes::render_without_effects(&gpu, graph, Backend::Compute, &scene, size);
        for _ in 0..3 {
            exec.render(&gpu, scene.camera(), &scene).unwrap();
        }
        assert_eq!(exec.scene_changes(), 1, "{graph}: frames of an unchanged scene find no change");
        // An edit of a copy leaves the scene as it was.
        let mut copy = scene.clone();
        copy.instances_mut()[0].transform = Mat4::from_translation(Vec3::Y) * copy.instances()[0].transform;
        copy.materials_mut()[0].base_color = [0.0, 0.0, 1.0, 1.0];
        exec.render(&gpu, scene.camera(), &scene).unwrap();
        assert_eq!(exec.scene_changes(), 1, "{graph}: editing a copy is not an edit of the scene");
        for (k, (what, edit)) in edits().into_iter().enumerate() {
            let before = exec.read_output(&gpu).unwrap();
            edit(&mut scene);
            exec.render(&gpu, scene.camera(), &scene).unwrap();
            exec.render(&gpu, scene.camera(), &scene).unwrap();
            assert_eq!(exec.scene_changes(), k as u64 + 2, "{graph}, {what}: one change seen, once");
            let after = exec.read_output(&gpu).unwrap();
            assert_ne!(before, after, "{graph}, {what}: the picture changed");
            let fresh = common::modes::render_without_effects(&gpu, graph, Backend::Compute, &scene, size).read_output(&gpu).unwrap();
            assert!(after == fresh, "{graph}, {what}: the followed scene's picture is a new executor's of the edited scene");
        }
    }
}
