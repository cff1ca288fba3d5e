//! The procedural scenes (`box`, `organic`, `atrium`, `cornell`): counts within the ranges of
//! the paper's Table 1, valid geometry (indices in range, finite positions, no degenerate
//! triangles, unit normals, winding agreeing with the normals), a closed and consistently wound
//! organic mesh, a deterministic, seed-dependent atrium, and a Lambert Cornell box lit by its
//! light quad alone, closed on five sides.

use glam::{DVec3, Vec3};
use raygraph::scene::procedural::{atrium, box_scene, by_name, organic, ATRIUM_DEFAULT_SEED, NAMES};
use raygraph::scene::{Mesh, Scene};
use std::collections::HashMap;
use std::ops::RangeInclusive;

fn check_counts(s: &Scene, tris: RangeInclusive<usize>, meshes: RangeInclusive<usize>, textures: RangeInclusive<usize>) {
    println!(
        "{}: {} triangles, {} meshes, {} textures, {} materials, {} instances",
        s.name(),
        s.triangle_count(),
        s.meshes().len(),
        s.textures().len(),
        s.materials().len(),
        s.instances().len()
    );
    assert!(tris.contains(&s.triangle_count()), "{}: {} triangles, want {:?}", s.name(), s.triangle_count(), tris);
    assert!(meshes.contains(&s.meshes().len()), "{}: {} meshes, want {:?}", s.name(), s.meshes().len(), meshes);
    assert!(textures.contains(&s.textures().len()), "{}: {} textures, want {:?}", s.name(), s.textures().len(), textures);
}

fn check_references(s: &Scene) {
    for inst in s.instances().iter() {
        assert!(inst.mesh < s.meshes().len() && inst.material < s.materials().len());
        assert!(inst.transform.is_finite() && inst.transform.determinant() > 0.0, "{}: instance transform must be finite and not mirror", s.name());
    }
    for m in s.materials().iter() {
        for t in [m.texture, m.metallic_roughness_texture, m.normal_texture, m.emissive_texture].into_iter().flatten() {
            assert!(t < s.textures().len(), "{}: material {} uses texture {t}", s.name(), m.name);
        }
    }
    for t in s.textures() {
        assert!((64..=256).contains(&t.width) && (64..=256).contains(&t.height), "{}: texture {} is {}x{}", s.name(), t.name, t.width, t.height);
        assert_eq!(t.rgba.len(), (t.width * t.height * 4) as usize);
    }
    // Every mesh is placed and every texture is used by some material.
    for i in 0..s.meshes().len() {
        assert!(s.instances().iter().any(|inst| inst.mesh == i), "{}: mesh {} has no instance", s.name(), s.meshes()[i].name);
    }
    for i in 0..s.textures().len() {
        assert!(
            s.materials().iter().any(|m| m.texture == Some(i) || m.metallic_roughness_texture == Some(i)),
            "{}: texture {} is unused",
            s.name(),
            s.textures()[i].name
        );
    }
}

fn check_mesh(scene: &str, m: &Mesh) {
    assert!(!m.indices.is_empty(), "{scene}/{}: empty", m.name);
    assert_eq!(m.indices.len() % 3, 0);
    let n = m.vertices.len();
    for &i in &m.indices {
        assert!((i as usize) < n, "{scene}/{}: index {i} out of range ({n} vertices)", m.name);
    }
    for v in &m.vertices {
        assert!(v.position.iter().chain(&v.normal).chain(&v.uv).all(|c| c.is_finite()), "{scene}/{}: non-finite vertex {v:?}", m.name);
        let len = Vec3::from(v.normal).length();
        assert!((len - 1.0).abs() < 1e-3, "{scene}/{}: normal length {len}", m.name);
    }
    let mut disagree = 0;
    for t in m.indices.chunks_exact(3) {
        let p = |i: u32| Vec3::from(m.vertices[i as usize].position).as_dvec3();
        let face = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
        assert!(face.length() > 1e-10, "{scene}/{}: zero-area triangle {t:?}", m.name);
        // Counter-clockwise seen from the side the normals point to.
        let nsum: DVec3 = t.iter().map(|&i| Vec3::from(m.vertices[i as usize].normal).as_dvec3()).sum();
        if face.dot(nsum) <= 0.0 {
            disagree += 1;
        }
    }
    // Smooth normals may disagree with a sliver at a sharp fold; allow a tiny fraction.
    assert!(disagree * 1000 <= m.triangle_count(), "{scene}/{}: {disagree} of {} triangles wound against their normals", m.name, m.triangle_count());
}

fn check_scene(s: &Scene) {
    check_references(s);
    for m in s.meshes() {
        check_mesh(s.name(), m);
    }
    assert!(s.light().direction.is_normalized());
    assert!(s.camera().position.is_finite() && s.camera().position != s.camera().target);
}

#[test]
fn box_scene_matches_table_1() {
    let s = box_scene();
    assert_eq!(s.name(), "box");
    check_counts(&s, 12..=12, 1..=1, 2..=2);
    assert_eq!(s.instances().len(), 1);
    check_scene(&s);
}

#[test]
fn organic_scene_is_a_closed_consistently_wound_mesh() {
    let s = organic();
    assert_eq!(s.name(), "organic");
    check_counts(&s, 3800..=4100, 1..=1, 2..=2);
    assert_eq!(s.instances().len(), 1);
    check_scene(&s);
    let m = &s.meshes()[0];
    // Positions are shared: no two vertices at the same place.
    let mut seen = HashMap::new();
    for (i, v) in m.vertices.iter().enumerate() {
        let key = v.position.map(f32::to_bits);
        assert!(seen.insert(key, i).is_none(), "duplicated position {:?}", v.position);
    }
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    let mut undirected: HashMap<(u32, u32), u32> = HashMap::new();
    for t in m.indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *directed.entry((a, b)).or_default() += 1;
            *undirected.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    assert!(undirected.values().all(|&c| c == 2), "an edge is not shared by exactly two triangles");
    assert!(directed.values().all(|&c| c == 1), "inconsistent winding: a directed edge is used twice");
    // Euler characteristic of a sphere, and outward winding (positive enclosed volume).
    let v = m.vertices.len() as i64;
    assert_eq!(v - undirected.len() as i64 + m.triangle_count() as i64, 2);
    let volume: f64 = m
        .indices
        .chunks_exact(3)
        .map(|t| {
            let p = |i: u32| Vec3::from(m.vertices[i as usize].position).as_dvec3();
            p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0
        })
        .sum();
    assert!(volume > 0.5, "enclosed volume {volume}: winding must be counter-clockwise from outside");
}

#[test]
fn atrium_scene_matches_table_1() {
    let start = std::time::Instant::now();
    let s = atrium(ATRIUM_DEFAULT_SEED);
    println!("atrium generated in {:?}", start.elapsed());
    assert_eq!(s.name(), "atrium");
    check_counts(&s, 250_000..=275_000, 95..=110, 65..=75);
    check_scene(&s);
    // Roughly 30 x 14 x 12 m, y up, floor at 0, no roof over the courtyard.
    let b = s.bounds();
    let size = b.max - b.min;
    assert!((29.0..=32.0).contains(&size.x) && (13.0..=16.0).contains(&size.z) && (11.5..=13.0).contains(&size.y), "bounds {b:?}");
    assert!(b.min.y.abs() < 1e-3);
    let sky = s.light().direction;
    assert!(sky.y > 0.5 && sky.y < 0.99, "the light comes from above at an angle");
}

#[test]
fn atrium_is_deterministic_and_seed_dependent() {
    let a = atrium(1);
    let b = atrium(1);
    let c = atrium(2);
    assert_eq!(a.meshes().len(), b.meshes().len());
    for (x, y) in a.meshes().iter().zip(b.meshes()) {
        assert!(x.vertices == y.vertices && x.indices == y.indices, "mesh {} differs between runs", x.name);
    }
    for (x, y) in a.textures().iter().zip(b.textures()) {
        assert!(x.rgba == y.rgba, "texture {} differs between runs", x.name);
    }
    let same_vertices = a.meshes().iter().zip(c.meshes()).all(|(x, y)| x.vertices == y.vertices);
    assert!(!same_vertices, "atrium(2) must differ from atrium(1)");
    assert!(a.textures().iter().zip(c.textures()).any(|(x, y)| x.rgba != y.rgba));
    // The structure does not depend on the seed.
    assert_eq!(a.triangle_count(), c.triangle_count());
    assert_eq!((a.meshes().len(), a.textures().len(), a.instances().len()), (c.meshes().len(), c.textures().len(), c.instances().len()));
}

#[test]
fn by_name_knows_every_scene() {
    for name in NAMES {
        let s = by_name(name).unwrap_or_else(|| panic!("{name}"));
        assert_eq!(s.name(), *name);
    }
    assert!(by_name("sponza").is_none());
}

/// The distance along the ray `origin + t dir` to the nearest triangle of `s` (world space),
/// if any (Möller-Trumbore, both faces).
fn nearest_hit(s: &Scene, origin: Vec3, dir: Vec3) -> Option<f32> {
    let mut nearest: Option<f32> = None;
    for inst in s.instances().iter() {
        let m = &s.meshes()[inst.mesh];
        for t in m.indices.chunks_exact(3) {
            let p = |i: u32| inst.transform.transform_point3(Vec3::from(m.vertices[i as usize].position));
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let (e1, e2) = (b - a, c - a);
            let q = dir.cross(e2);
            let det = e1.dot(q);
            if det.abs() < 1e-12 {
                continue;
            }
            let o = origin - a;
            let (u, r) = (o.dot(q) / det, o.cross(e1));
            let v = dir.dot(r) / det;
            let dist = e2.dot(r) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && dist > 0.0 && nearest.is_none_or(|n| dist < n) {
                nearest = Some(dist);
            }
        }
    }
    nearest
}

#[test]
fn cornell_box_is_lambert_lit_by_its_light_quad_alone_and_closed_on_five_sides() {
    let s = raygraph::scene::procedural::cornell();
    assert_eq!(s.name(), "cornell");
    // 5 walls, 2 blocks of 5 faces and the light, 2 triangles a quad; white, red, green, light.
    check_counts(&s, 32..=32, 8..=8, 0..=0);
    assert_eq!((s.materials().len(), s.instances().len()), (4, 8));
    check_scene(&s);
    for m in s.materials().iter() {
        assert_eq!((m.metallic, m.roughness, m.lobes.specular, m.texture), (0.0, 1.0, 0.0, None), "{}: Lambert", m.name);
    }
    let emissive: Vec<[f32; 3]> = s.materials().iter().map(|m| m.emissive).filter(|e| *e != [0.0; 3]).collect();
    assert_eq!(emissive, vec![raygraph::scene::procedural::CORNELL_LIGHT_RADIANCE], "one emissive material, the light's");
    // No sun, no sky, no lights of its own.
    assert!(s.lights().is_empty() && s.point_light().is_none());
    assert_eq!((s.light().intensity, s.light().ambient), (0.0, 0.0));
    assert!(s.effective_lights().iter().all(|l| l.intensity == 0.0));
    // From points inside, rays towards the floor, ceiling, back and side walls hit within the
    // box (about 5.6 units a side); towards the open front (-z) they leave it.
    let b = s.bounds();
    assert!((b.max - b.min).min_element() > 5.4 && (b.max - b.min).max_element() < 5.7, "{b:?}");
    for inside in [Vec3::new(1.5, 2.74, 2.8), Vec3::new(1.0, 4.5, 0.5), Vec3::new(4.5, 4.0, 5.0)] {
        for dir in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z] {
            let hit = nearest_hit(&s, inside, dir);
            assert!(hit.is_some_and(|d| d < 5.7), "from {inside} towards {dir}: {hit:?}");
        }
        assert_eq!(nearest_hit(&s, inside, Vec3::NEG_Z), None, "from {inside}: the front is open");
    }
}
