//! Whether a mesh is closed and wound outwards: every edge of its triangles (vertices joined by
//! position, so that seams of normals or texture coordinates do not open it) is shared by
//! exactly two triangles that run along it in opposite directions, and every connected part of
//! it encloses a positive volume. Seen from any point outside such a mesh, the nearest surface
//! along a ray is a front face, which lets a depth-only pass from a light outside it cull back
//! faces without changing its depth (`runtime::raster`).

use super::Mesh;
use std::collections::HashMap;

/// Whether `mesh` is closed and wound outwards (see the module docs). Degenerate triangles
/// (two corners at one position) are left out; an empty mesh is not closed.
pub(crate) fn is_closed_outward(mesh: &Mesh) -> bool {
    let Some(triangles) = welded_triangles(mesh) else { return false };
    if triangles.is_empty() || !edges_paired(&triangles) {
        return false;
    }
    let positions = |t: &[u32; 3]| t.map(|i| glam::DVec3::from(glam::Vec3::from(mesh.vertices[i as usize].position)));
    let parts = connected_parts(&triangles);
    let mut volume = vec![0.0f64; parts.count];
    for (t, &part) in triangles.iter().zip(&parts.of_triangle) {
        let [a, b, c] = positions(&t.1);
        volume[part] += a.dot(b.cross(c)) / 6.0;
    }
    volume.iter().all(|v| *v > 0.0)
}

/// Each non-degenerate triangle as (its corners joined by position, its original corners);
/// `None` when an index is out of range or a position is not finite.
fn welded_triangles(mesh: &Mesh) -> Option<Vec<([u32; 3], [u32; 3])>> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut weld = |i: u32| -> Option<u32> {
        let p = mesh.vertices.get(i as usize)?.position;
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        // +0.0 and -0.0 are one position.
        let key = p.map(|x| (x + 0.0).to_bits());
        let next = ids.len() as u32;
        Some(*ids.entry(key).or_insert(next))
    };
    let mut out = Vec::with_capacity(mesh.indices.len() / 3);
    for t in mesh.indices.chunks_exact(3) {
        let welded = [weld(t[0])?, weld(t[1])?, weld(t[2])?];
        if welded[0] != welded[1] && welded[1] != welded[2] && welded[2] != welded[0] {
            out.push((welded, [t[0], t[1], t[2]]));
        }
    }
    Some(out)
}

/// Whether every directed edge occurs once and its reverse once.
fn edges_paired(triangles: &[([u32; 3], [u32; 3])]) -> bool {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 3);
    for (w, _) in triangles {
        for k in 0..3 {
            *directed.entry((w[k], w[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    directed.iter().all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
}

/// The connected parts of a mesh, triangles joined by shared (welded) vertices.
struct Parts {
    count: usize,
    of_triangle: Vec<usize>,
}

fn connected_parts(triangles: &[([u32; 3], [u32; 3])]) -> Parts {
    let vertex_count = triangles.iter().flat_map(|(w, _)| w.iter()).max().map_or(0, |m| *m as usize + 1);
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for (w, _) in triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[k]));
            parent[a as usize] = b;
        }
    }
    let mut part_of_root: HashMap<u32, usize> = HashMap::new();
    let of_triangle = triangles
        .iter()
        .map(|(w, _)| {
            let r = root(&mut parent, w[0]);
            let next = part_of_root.len();
            *part_of_root.entry(r).or_insert(next)
        })
        .collect();
    Parts { count: part_of_root.len(), of_triangle }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Vertex;

    fn mesh(positions: &[[f32; 3]], indices: &[u32]) -> Mesh {
        Mesh {
            name: "t".into(),
            vertices: positions.iter().map(|&position| Vertex { position, ..Default::default() }).collect(),
            indices: indices.to_vec(),
            tangents: None,
            extras: None,
        }
    }

    const TETRA: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    // Counter-clockwise seen from outside.
    const TETRA_OUT: [u32; 12] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];

    #[test]
    fn a_tetrahedron_wound_outwards_is_closed() {
        assert!(is_closed_outward(&mesh(&TETRA, &TETRA_OUT)));
    }

    #[test]
    fn a_tetrahedron_wound_inwards_is_not() {
        let inward: Vec<u32> = TETRA_OUT.chunks(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
        assert!(!is_closed_outward(&mesh(&TETRA, &inward)));
    }

    #[test]
    fn an_open_mesh_is_not() {
        assert!(!is_closed_outward(&mesh(&TETRA, &TETRA_OUT[..9])));
    }

    #[test]
    fn split_vertices_at_one_position_are_joined() {
        // Every triangle with vertices of its own, as a glTF file with flat normals has them.
        let positions: Vec<[f32; 3]> = TETRA_OUT.iter().map(|&i| TETRA[i as usize]).collect();
        let indices: Vec<u32> = (0..12).collect();
        assert!(is_closed_outward(&mesh(&positions, &indices)));
    }

    #[test]
    fn an_inverted_part_makes_it_not_closed_outward() {
        // A large outward tetrahedron and a small inverted one apart from it: the total volume
        // is positive, the small part is inside out.
        let mut positions: Vec<[f32; 3]> = TETRA.iter().map(|p| p.map(|x| x * 4.0)).collect();
        positions.extend(TETRA.iter().map(|p| [p[0] + 10.0, p[1], p[2]]));
        let mut indices = TETRA_OUT.to_vec();
        indices.extend(TETRA_OUT.chunks(3).flat_map(|t| [t[0] + 4, t[2] + 4, t[1] + 4]));
        assert!(!is_closed_outward(&mesh(&positions, &indices)));
    }

    #[test]
    fn a_doubled_face_or_a_bad_index_is_not() {
        let mut doubled = TETRA_OUT.to_vec();
        doubled.extend_from_slice(&TETRA_OUT[..3]);
        assert!(!is_closed_outward(&mesh(&TETRA, &doubled)));
        let mut bad = TETRA_OUT.to_vec();
        bad[0] = 99;
        assert!(!is_closed_outward(&mesh(&TETRA, &bad)));
    }

    #[test]
    fn the_built_in_sphere_and_cube_are_closed_and_the_plane_is_not() {
        use crate::scene::builtin::{cube, plane, sphere};
        assert!(is_closed_outward(&sphere("s", 12, 24)));
        assert!(is_closed_outward(&cube("c")));
        assert!(!is_closed_outward(&plane("p", 1.0, 1.0)));
    }

    #[test]
    fn degenerate_triangles_are_left_out() {
        let mut indices = TETRA_OUT.to_vec();
        indices.extend_from_slice(&[0, 0, 1]);
        assert!(is_closed_outward(&mesh(&TETRA, &indices)));
    }
}
