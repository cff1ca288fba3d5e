//! The animated benchmark scenes of `raygraph bench anim`: `organic-skinned`, the organic mesh
//! subdivided three times (250,880 triangles) and skinned to two joints (the head nods and
//! turns on its neck, the weights blended over its height), and `atrium-moving`, the atrium
//! with 200 balls (960 triangles each) orbiting the courtyard at different heights, speeds
//! and directions while they spin. Both loop every 4 seconds.

use super::super::animation::{Animation, Channel, ChannelTarget, Deformer, InstanceNode, Interpolation, Rig, RigNode, Skin, SkinWeights, Trs};
use super::super::{builtin, Instance, Material, Mesh, Scene, Vertex};
use glam::{Mat4, Quat, Vec3};
use std::collections::HashMap;
use std::sync::Arc;

/// Seconds of one loop of either clip.
pub(crate) const LOOP_SECONDS: f32 = 4.0;

/// `mesh` with every triangle split into four at its edges' midpoints (shared edges share
/// their midpoint, so a closed mesh stays closed); normals and uvs averaged.
pub(crate) fn subdivide(mesh: &Mesh) -> Mesh {
    let mut vertices = mesh.vertices.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Vertex>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (va, vb) = (vertices[a as usize], vertices[b as usize]);
            let mix = |x: &[f32], y: &[f32]| -> Vec<f32> { x.iter().zip(y).map(|(p, q)| 0.5 * (p + q)).collect() };
            let n = Vec3::from_slice(&mix(&va.normal, &vb.normal)).normalize_or(Vec3::Y);
            let p = mix(&va.position, &vb.position);
            let uv = mix(&va.uv, &vb.uv);
            vertices.push(Vertex { position: [p[0], p[1], p[2]], normal: n.into(), uv: [uv[0], uv[1]] });
            vertices.len() as u32 - 1
        })
    };
    let mut indices = Vec::with_capacity(mesh.indices.len() * 4);
    for t in mesh.indices.chunks_exact(3) {
        let (a, b, c) = (t[0], t[1], t[2]);
        let (ab, bc, ca) = (midpoint(a, b, &mut vertices), midpoint(b, c, &mut vertices), midpoint(c, a, &mut vertices));
        indices.extend_from_slice(&[a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    Mesh { name: format!("{} (subdivided)", mesh.name), vertices, indices, tangents: None, extras: None }
}

fn rest_node(name: &str, parent: Option<usize>, translation: Vec3) -> RigNode {
    RigNode { name: name.into(), parent, rest: Trs { translation, rotation: Quat::IDENTITY, scale: Vec3::ONE }, fixed: None, weights: Vec::new() }
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The organic head subdivided three times and skinned: joint 0 (the body, still) and joint 1
/// (the neck, at y = -0.35) that nods 25 degrees and turns 35 degrees over the loop.
pub(crate) fn organic_skinned() -> Scene {
    let mut scene = super::organic();
    let mut mesh = Mesh::clone(&scene.meshes[0]);
    for _ in 0..3 {
        mesh = subdivide(&mesh);
    }
    scene.name = "organic-skinned".into();
    let neck = Vec3::new(0.0, -0.35, 0.0);
    let nodes = vec![rest_node("body", None, Vec3::ZERO), rest_node("neck", Some(0), neck), rest_node("head mesh", None, Vec3::ZERO)];
    let (mut joints, mut weights) = (Vec::with_capacity(mesh.vertices.len() * 4), Vec::with_capacity(mesh.vertices.len() * 4));
    for v in &mesh.vertices {
        let w = smoothstep(-0.75, 0.05, v.position[1]);
        joints.extend_from_slice(&[0, 1, 0, 0]);
        weights.extend_from_slice(&[1.0 - w, w, 0.0, 0.0]);
    }
    let keys = [0.0, 1.0, 2.0, 3.0, 4.0];
    let (nod, turn) = ([0.0f32, 25.0, 0.0, -25.0, 0.0], [0.0f32, 35.0, 0.0, -35.0, 0.0]);
    let rotations: Vec<f32> =
        nod.iter().zip(&turn).flat_map(|(x, y)| (Quat::from_rotation_y(y.to_radians()) * Quat::from_rotation_x(x.to_radians())).to_array()).collect();
    let rig = Rig {
        nodes,
        instances: vec![InstanceNode { node: 2, skinned: true }],
        animations: vec![Animation {
            name: "nod and turn".into(),
            channels: vec![Channel {
                node: 1,
                target: ChannelTarget::Rotation,
                interpolation: Interpolation::Linear,
                times: keys.to_vec(),
                values: rotations,
                width: 4,
            }],
            duration: LOOP_SECONDS,
        }],
        skins: vec![Skin { name: "neck".into(), joints: vec![0, 1], inverse_bind: vec![Mat4::IDENTITY, Mat4::from_translation(-neck)] }],
        deformers: vec![Deformer {
            mesh: 0,
            node: 2,
            rest: mesh.vertices.clone(),
            targets: Vec::new(),
            skin: Some(SkinWeights { skin: 0, sets: 1, joints, weights }),
        }],
    };
    scene.meshes[0] = mesh.into();
    scene.rig = Some(Arc::new(rig));
    scene.pose(None, 0.0);
    scene
}

/// The number of balls of [`atrium_moving`].
pub(crate) const MOVING_BALLS: usize = 200;

/// The atrium with [`MOVING_BALLS`] balls orbiting the courtyard (each on its own circle,
/// height, speed and direction) and spinning; the atrium's own instances stay where they are.
pub(crate) fn atrium_moving(seed: u64) -> Scene {
    let mut scene = super::atrium(seed);
    scene.name = "atrium-moving".into();
    let mut nodes: Vec<RigNode> = scene
        .instances
        .iter()
        .enumerate()
        .map(|(i, inst)| {
            let (s, r, t) = inst.transform.to_scale_rotation_translation();
            RigNode { rest: Trs { translation: t, rotation: r, scale: s }, fixed: Some(inst.transform), ..rest_node(&format!("atrium {i}"), None, t) }
        })
        .collect();
    let ball = scene.meshes.len();
    scene.meshes.push(builtin::sphere("ball", 16, 32).into());
    let material = scene.materials.len();
    scene.materials_mut().push(Material { metallic: 0.3, roughness: 0.35, ..Material::diffuse("ball", [0.85, 0.3, 0.2, 1.0], None) });
    let b = scene.bounds();
    let (center, half) = (b.center(), 0.5 * (b.max - b.min));
    let mut channels = Vec::new();
    for k in 0..MOVING_BALLS {
        // A deterministic spread: radius, height, turns per loop (1 or 2, either way), phase.
        let f = k as f32 / MOVING_BALLS as f32;
        let radius = (0.15 + 0.6 * ((k * 37 % 101) as f32 / 101.0)) * half.z.min(half.x);
        let height = b.min.y + 1.0 + (b.max.y - b.min.y - 2.5) * ((k * 53 % 97) as f32 / 97.0);
        let turns = if k % 2 == 0 { 1.0 } else { -2.0 };
        let phase = std::f32::consts::TAU * f * 7.0;
        let size = 0.35 + 0.25 * ((k * 13 % 11) as f32 / 11.0);
        let node = nodes.len();
        nodes.push(RigNode {
            rest: Trs { translation: center, rotation: Quat::IDENTITY, scale: Vec3::splat(size) },
            ..rest_node(&format!("ball {k}"), None, center)
        });
        scene.instances_mut().push(Instance { mesh: ball, material, transform: Mat4::IDENTITY });
        let keys: Vec<f32> = (0..=16).map(|i| LOOP_SECONDS * i as f32 / 16.0).collect();
        let positions: Vec<f32> = keys
            .iter()
            .flat_map(|t| {
                let a = phase + turns * std::f32::consts::TAU * t / LOOP_SECONDS;
                [center.x + radius * a.cos() * half.x / half.z.max(1e-6), height, center.z + radius * a.sin()]
            })
            .collect();
        let spins: Vec<f32> = keys.iter().flat_map(|t| Quat::from_rotation_y(std::f32::consts::TAU * 3.0 * t / LOOP_SECONDS + phase).to_array()).collect();
        channels.push(Channel {
            node,
            target: ChannelTarget::Translation,
            interpolation: Interpolation::Linear,
            times: keys.clone(),
            values: positions,
            width: 3,
        });
        channels.push(Channel { node, target: ChannelTarget::Rotation, interpolation: Interpolation::Linear, times: keys, values: spins, width: 4 });
    }
    let instances = (0..scene.instances.len()).map(|node| InstanceNode { node, skinned: false }).collect();
    let rig = Rig {
        nodes,
        instances,
        animations: vec![Animation { name: "orbit".into(), channels, duration: LOOP_SECONDS }],
        skins: Vec::new(),
        deformers: Vec::new(),
    };
    scene.rig = Some(Arc::new(rig));
    scene.pose(Some(0), 0.0);
    scene
}
