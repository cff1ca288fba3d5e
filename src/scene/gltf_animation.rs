//! glTF import of what moves: the node hierarchy, animation clips, skins and morph targets, as
//! a [`Rig`]. Every accessor is checked before it is read (types, counts, finite values, joint
//! indices); what cannot be played is a `RigError` naming the clip, channel, skin or
//! primitive (the importer adds the file); what can be repaired (weights that do not sum to one, a `weights`
//! channel on a node without morph targets, an animated node given as a matrix) is counted and
//! logged.

use super::animation::{Animation, Channel, ChannelTarget, Deformer, InstanceNode, Interpolation, MorphTarget, Rig, RigNode, Skin, SkinWeights, Trs};
use super::{Instance, Mesh};
use glam::{Mat4, Quat, Vec3};
use std::collections::HashSet;

/// What the rig builder reads besides the document: the buffers, and for every scene mesh the
/// glTF mesh and primitive it came from.
pub(super) struct RigInput<'a> {
    pub doc: &'a gltf::Document,
    pub buffers: &'a [gltf::buffer::Data],
    pub mesh_primitive: &'a [(usize, usize)],
}

/// Why a file's animation data cannot be played.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RigError {
    /// A clip, channel or skin, named in the message.
    Rig(String),
    /// A primitive's morph targets or skin attributes.
    Primitive {
        /// The mesh's name.
        mesh: String,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// What is wrong.
        message: String,
    },
}

/// Counts of what the rig builder repaired.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigRepairs {
    /// Vertices whose skin weights did not sum to one (normalised; all-zero: joint 0).
    pub renormalised_weights: usize,
    /// `weights` channels on nodes without morph targets (dropped).
    pub dropped_channels: usize,
    /// Animated nodes given as a matrix (decomposed into translation, rotation and scale).
    pub decomposed_matrices: usize,
}

/// The rig of the file, where it has clips, skins or morph targets; `None` otherwise. Meshes
/// that deform get one scene mesh per instance (copied where several instances shared one),
/// and `instance_nodes` says which node placed each instance.
pub(super) fn rig(
    input: &RigInput,
    meshes: &mut Vec<Mesh>,
    instances: &mut [Instance],
    instance_nodes: &[usize],
) -> Result<Option<(Rig, RigRepairs)>, RigError> {
    let doc = input.doc;
    let morphing = |m: usize| {
        input.mesh_primitive.get(m).and_then(|&(mesh, prim)| doc.meshes().nth(mesh)?.primitives().nth(prim)).is_some_and(|p| p.morph_targets().next().is_some())
    };
    let deforms = |i: usize| doc.nodes().nth(instance_nodes[i]).is_some_and(|n| n.skin().is_some()) || morphing(instances[i].mesh);
    let deforming: Vec<bool> = (0..instances.len()).map(deforms).collect();
    if doc.animations().next().is_none() && !deforming.contains(&true) {
        return Ok(None);
    }
    let mut repairs = RigRepairs::default();
    let animated_nodes: HashSet<usize> = doc.animations().flat_map(|a| a.channels().map(|c| c.target().node().index()).collect::<Vec<_>>()).collect();
    let mut rig = Rig { nodes: nodes(doc, &animated_nodes, &mut repairs), ..Default::default() };
    rig.skins = doc.skins().map(|s| skin(input, &s)).collect::<Result<_, _>>()?;
    let mut claimed = HashSet::new();
    for (i, inst) in instances.iter_mut().enumerate() {
        let node = doc.nodes().nth(instance_nodes[i]).ok_or_else(|| rig_error(format!("instance {i} has no node")))?;
        let skin = node.skin().map(|s| s.index());
        rig.instances.push(InstanceNode { node: node.index(), skinned: skin.is_some() });
        if !deforming[i] {
            continue;
        }
        if !claimed.insert(inst.mesh) {
            meshes.push(meshes[inst.mesh].clone());
            inst.mesh = meshes.len() - 1;
            claimed.insert(inst.mesh);
        }
        let deformer = deformer(input, &meshes[inst.mesh], inst.mesh, &node, skin.map(|s| (s, rig.skins[s].joints.len())), &mut repairs)?;
        rig.deformers.push(deformer);
    }
    let target_counts: Vec<usize> = (0..rig.nodes.len())
        .map(|n| doc.nodes().nth(n).and_then(|n| n.mesh()).and_then(|m| m.primitives().next()).map_or(0, |p| p.morph_targets().count()))
        .collect();
    for a in doc.animations() {
        rig.animations.push(animation(input, &a, &target_counts, &mut repairs)?);
    }
    Ok(Some((rig, repairs)))
}

impl RigRepairs {
    /// One warning line per kind of repair made.
    pub fn warnings(&self) -> Vec<String> {
        [
            (self.renormalised_weights, "vertices' skin weights did not sum to one (normalised)"),
            (self.dropped_channels, "weights channels drive nodes without morph targets (dropped)"),
            (self.decomposed_matrices, "animated nodes are given as a matrix (decomposed into translation, rotation and scale)"),
        ]
        .into_iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect()
    }
}

fn rig_error(message: String) -> RigError {
    RigError::Rig(message)
}

/// Every node with its parent and rest transform; a matrix node that a channel drives is
/// decomposed (glTF forbids animating one: counted as a repair).
fn nodes(doc: &gltf::Document, animated: &HashSet<usize>, repairs: &mut RigRepairs) -> Vec<RigNode> {
    let mut parent = vec![None; doc.nodes().count()];
    for n in doc.nodes() {
        for c in n.children() {
            parent[c.index()].get_or_insert(n.index());
        }
    }
    doc.nodes()
        .map(|n| {
            let is_matrix = matches!(n.transform(), gltf::scene::Transform::Matrix { .. });
            if is_matrix && animated.contains(&n.index()) {
                repairs.decomposed_matrices += 1;
            }
            let fixed = is_matrix.then(|| Mat4::from_cols_array_2d(&n.transform().matrix()));
            let (t, r, s) = n.transform().decomposed();
            let targets = n.mesh().and_then(|m| m.primitives().next()).map_or(0, |p| p.morph_targets().count());
            let mut weights = n.weights().or_else(|| n.mesh().and_then(|m| m.weights())).map(<[f32]>::to_vec).unwrap_or_default();
            weights.resize(targets, 0.0);
            let rest = Trs { translation: Vec3::from(t), rotation: Quat::from_array(r).normalize(), scale: Vec3::from(s) };
            let rest = if rest.rotation.is_finite() { rest } else { Trs { rotation: Quat::IDENTITY, ..rest } };
            RigNode { name: n.name().map(str::to_string).unwrap_or_else(|| format!("node {}", n.index())), parent: parent[n.index()], rest, fixed, weights }
        })
        .collect()
}

fn skin_name(s: &gltf::Skin) -> String {
    s.name().map(|n| format!("`{n}`")).unwrap_or_else(|| s.index().to_string())
}

/// A skin's joints and inverse bind matrices (identity where the file gives none).
fn skin(input: &RigInput, s: &gltf::Skin) -> Result<Skin, RigError> {
    let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
    let err = |m: String| rig_error(format!("skin {}: {m}", skin_name(s)));
    let inverse_bind = match s.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(acc) => {
            if acc.data_type() != gltf::accessor::DataType::F32 || acc.dimensions() != gltf::accessor::Dimensions::Mat4 {
                return Err(err(format!(
                    "inverseBindMatrices accessor {} is {:?} {:?}; glTF requires Mat4 of F32",
                    acc.index(),
                    acc.dimensions(),
                    acc.data_type()
                )));
            }
            if acc.count() != joints.len() {
                return Err(err(format!("inverseBindMatrices accessor {} has {} matrices for {} joints", acc.index(), acc.count(), joints.len())));
            }
            let reader = s.reader(|b| input.buffers.get(b.index()).map(|d| &d.0[..]));
            let m: Vec<Mat4> = reader.read_inverse_bind_matrices().map(|it| it.map(|m| Mat4::from_cols_array_2d(&m)).collect()).unwrap_or_default();
            if let Some(j) = m.iter().position(|m| !m.is_finite()) {
                return Err(err(format!("inverse bind matrix {j} is not finite")));
            }
            m
        }
    };
    Ok(Skin { name: skin_name(s), joints, inverse_bind })
}

/// The deformer of scene mesh `mesh_index` (`mesh`, placed by `node`): its morph targets and,
/// with `skin = (index, joint count)`, its joints and weights.
fn deformer(
    input: &RigInput,
    mesh: &Mesh,
    mesh_index: usize,
    node: &gltf::Node,
    skin: Option<(usize, usize)>,
    repairs: &mut RigRepairs,
) -> Result<Deformer, RigError> {
    let &(gm, gp) = input.mesh_primitive.get(mesh_index).ok_or_else(|| rig_error(format!("mesh {mesh_index} has no primitive")))?;
    let gmesh = input.doc.meshes().nth(gm).ok_or_else(|| rig_error(format!("mesh {gm} is missing")))?;
    let prim = gmesh.primitives().nth(gp).ok_or_else(|| rig_error(format!("mesh {gm} primitive {gp} is missing")))?;
    let prim_err =
        |message: String| RigError::Primitive { mesh: gmesh.name().map(str::to_string).unwrap_or_else(|| format!("mesh {gm}")), primitive: gp, message };
    let n = mesh.vertices.len();
    let reader = prim.reader(|b| input.buffers.get(b.index()).map(|d| &d.0[..]));
    let mut targets = Vec::new();
    for (t, target) in prim.morph_targets().enumerate() {
        for (what, acc) in [("POSITION", target.positions()), ("NORMAL", target.normals())] {
            if let Some(acc) = acc {
                if acc.data_type() != gltf::accessor::DataType::F32 || acc.dimensions() != gltf::accessor::Dimensions::Vec3 {
                    return Err(prim_err(format!(
                        "morph target {t} {what} accessor {} is {:?} {:?}; raygraph reads Vec3 of F32",
                        acc.index(),
                        acc.dimensions(),
                        acc.data_type()
                    )));
                }
                if acc.count() != n {
                    return Err(prim_err(format!("morph target {t} {what} accessor {} has {} elements but POSITION has {n}", acc.index(), acc.count())));
                }
            }
        }
    }
    for (t, (positions, normals, _)) in reader.read_morph_targets().enumerate() {
        let positions: Vec<Vec3> = positions.map(|p| p.map(Vec3::from).collect()).unwrap_or_else(|| vec![Vec3::ZERO; n]);
        let normals: Option<Vec<Vec3>> = normals.map(|it| it.map(Vec3::from).collect());
        if let Some(v) = positions.iter().chain(normals.iter().flatten()).position(|p| !p.is_finite()) {
            return Err(prim_err(format!("morph target {t} has a non-finite displacement (element {})", v % n.max(1))));
        }
        targets.push(MorphTarget { positions, normals });
    }
    let skin = match skin {
        Some((index, joints)) => Some(skin_weights(&prim, &reader, n, index, joints, repairs).map_err(prim_err)?),
        None => None,
    };
    Ok(Deformer { mesh: mesh_index, node: node.index(), rest: mesh.vertices.clone(), targets, skin })
}

/// The `JOINTS_n`/`WEIGHTS_n` sets of a skinned primitive with `n` vertices, checked against
/// the skin's `joint_count`, the weights normalised per vertex.
fn skin_weights<'a, 's, F>(
    prim: &gltf::Primitive,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    n: usize,
    skin: usize,
    joint_count: usize,
    repairs: &mut RigRepairs,
) -> Result<SkinWeights, String>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    use gltf::accessor::{DataType as T, Dimensions as D};
    let mut sets = 0;
    let mut joints: Vec<Vec<[u16; 4]>> = Vec::new();
    let mut weights: Vec<Vec<[f32; 4]>> = Vec::new();
    loop {
        let (j, w) = (prim.get(&gltf::Semantic::Joints(sets)), prim.get(&gltf::Semantic::Weights(sets)));
        let (j, w) = match (j, w) {
            (None, None) => break,
            (Some(j), Some(w)) => (j, w),
            _ => return Err(format!("JOINTS_{sets} and WEIGHTS_{sets} must come together")),
        };
        if !matches!(j.data_type(), T::U8 | T::U16) || j.dimensions() != D::Vec4 {
            return Err(format!("JOINTS_{sets} accessor {} is {:?} {:?}; glTF requires Vec4 of U8 or U16", j.index(), j.dimensions(), j.data_type()));
        }
        if !matches!(w.data_type(), T::F32 | T::U8 | T::U16) || w.dimensions() != D::Vec4 {
            return Err(format!("WEIGHTS_{sets} accessor {} is {:?} {:?}; glTF requires Vec4 of F32, U8 or U16", w.index(), w.dimensions(), w.data_type()));
        }
        for (what, acc) in [("JOINTS", &j), ("WEIGHTS", &w)] {
            if acc.count() != n {
                return Err(format!("{what}_{sets} accessor {} has {} elements but POSITION has {n}", acc.index(), acc.count()));
            }
        }
        joints.push(reader.read_joints(sets).map(|r| r.into_u16().collect()).unwrap_or_default());
        weights.push(reader.read_weights(sets).map(|r| r.into_f32().collect()).unwrap_or_default());
        sets += 1;
    }
    if sets == 0 {
        return Err("the node has a skin but the primitive has no JOINTS_0 and WEIGHTS_0".into());
    }
    let sets = sets as usize;
    let mut out = SkinWeights { skin, sets, joints: Vec::with_capacity(n * sets * 4), weights: Vec::with_capacity(n * sets * 4) };
    for v in 0..n {
        let start = out.weights.len();
        for s in 0..sets {
            for k in 0..4 {
                let (j, w) = (joints[s][v][k], weights[s][v][k]);
                if !w.is_finite() || w < 0.0 {
                    return Err(format!("vertex {v}: WEIGHTS_{s} holds {w}; weights must be finite and not negative"));
                }
                if w > 0.0 && j as usize >= joint_count {
                    return Err(format!("vertex {v}: JOINTS_{s} names joint {j}, but the skin has {joint_count} joints"));
                }
                out.joints.push(if (j as usize) < joint_count { j as u32 } else { 0 });
                out.weights.push(w);
            }
        }
        let sum: f32 = out.weights[start..].iter().sum();
        if (sum - 1.0).abs() > 2e-3 {
            repairs.renormalised_weights += 1;
            if sum > 0.0 {
                out.weights[start..].iter_mut().for_each(|w| *w /= sum);
            } else {
                out.weights[start] = 1.0;
            }
        }
    }
    Ok(out)
}

/// One clip: its channels read and checked (key times finite and increasing, outputs finite,
/// output counts matching the keys).
fn animation(input: &RigInput, a: &gltf::Animation, target_counts: &[usize], repairs: &mut RigRepairs) -> Result<Animation, RigError> {
    let name = a.name().map(str::to_string).unwrap_or_else(|| format!("animation {}", a.index()));
    let mut channels = Vec::new();
    for (c, ch) in a.channels().enumerate() {
        let err = |m: String| rig_error(format!("animation `{name}` channel {c}: {m}"));
        channels.extend(channel(input, &ch, target_counts, repairs).map_err(err)?);
    }
    let duration = channels.iter().filter_map(|c| c.times.last()).fold(0.0f32, |a, &b| a.max(b));
    Ok(Animation { name, channels, duration })
}

/// One channel read and checked; `None` for a `weights` channel on a node without morph
/// targets (counted as dropped). The error says what is wrong with the channel.
fn channel(input: &RigInput, ch: &gltf::animation::Channel, target_counts: &[usize], repairs: &mut RigRepairs) -> Result<Option<Channel>, String> {
    use gltf::animation::util::ReadOutputs;
    let sampler = ch.sampler();
    let node = ch.target().node().index();
    let target = match ch.target().property() {
        gltf::animation::Property::Translation => ChannelTarget::Translation,
        gltf::animation::Property::Rotation => ChannelTarget::Rotation,
        gltf::animation::Property::Scale => ChannelTarget::Scale,
        gltf::animation::Property::MorphTargetWeights => ChannelTarget::Weights,
    };
    let width = match target {
        ChannelTarget::Translation | ChannelTarget::Scale => 3,
        ChannelTarget::Rotation => 4,
        ChannelTarget::Weights => target_counts[node],
    };
    if width == 0 {
        repairs.dropped_channels += 1;
        return Ok(None);
    }
    let interpolation = match sampler.interpolation() {
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let keys = check_sampler(&sampler, target, width, interpolation)?;
    let reader = ch.reader(|b| input.buffers.get(b.index()).map(|d| &d.0[..]));
    let times: Vec<f32> = reader.read_inputs().map(|i| i.collect()).unwrap_or_default();
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("key time {k} is {}", times[k]));
    }
    if let Some(k) = (1..times.len()).find(|&k| times[k] <= times[k - 1]) {
        return Err(format!("key time {k} ({}) does not come after key {} ({})", times[k], k - 1, times[k - 1]));
    }
    let values: Vec<f32> = match reader.read_outputs() {
        Some(ReadOutputs::Translations(it)) | Some(ReadOutputs::Scales(it)) => it.flatten().collect(),
        Some(ReadOutputs::Rotations(r)) => r.into_f32().flatten().collect(),
        Some(ReadOutputs::MorphTargetWeights(w)) => w.into_f32().collect(),
        None => return Err("the sampler's output cannot be read".into()),
    };
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        let floats_per_key = values.len() / keys;
        return Err(format!("keyframe value {k} (key {}) is {}", k / floats_per_key, values[k]));
    }
    Ok(Some(Channel { node, target, interpolation, times, values, width }))
}

/// The number of keys of a channel's sampler, once its accessors are checked: Scalar F32 key
/// times, outputs of the target's type, and as many of them as the keys need.
fn check_sampler(sampler: &gltf::animation::Sampler, target: ChannelTarget, width: usize, interpolation: Interpolation) -> Result<usize, String> {
    use gltf::accessor::{DataType as T, Dimensions as D};
    let (input_acc, output_acc) = (sampler.input(), sampler.output());
    if input_acc.data_type() != T::F32 || input_acc.dimensions() != D::Scalar {
        return Err(format!(
            "input accessor {} is {:?} {:?}; glTF requires Scalar F32 key times",
            input_acc.index(),
            input_acc.dimensions(),
            input_acc.data_type()
        ));
    }
    let expected_dims = match target {
        ChannelTarget::Translation | ChannelTarget::Scale => D::Vec3,
        ChannelTarget::Rotation => D::Vec4,
        ChannelTarget::Weights => D::Scalar,
    };
    let float_only = matches!(target, ChannelTarget::Translation | ChannelTarget::Scale);
    if output_acc.dimensions() != expected_dims || (float_only && output_acc.data_type() != T::F32) || output_acc.data_type() == T::U32 {
        return Err(format!(
            "output accessor {} is {:?} {:?}; a {target:?} channel needs {expected_dims:?}",
            output_acc.index(),
            output_acc.dimensions(),
            output_acc.data_type()
        ));
    }
    let keys = input_acc.count();
    let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 } * if target == ChannelTarget::Weights { width } else { 1 };
    if keys == 0 || output_acc.count() != keys * per_key {
        return Err(format!(
            "the sampler's output accessor {} has {} elements, but {keys} key times need {} ({per_key} per key)",
            output_acc.index(),
            output_acc.count(),
            keys * per_key
        ));
    }
    Ok(keys)
}
