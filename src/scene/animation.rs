//! What moves in a scene and how, on the CPU: the node hierarchy a glTF file places its meshes
//! with ([`Rig`]), its animation clips (translation, rotation, scale and morph-weight channels,
//! linear, step or cubic-spline), morph targets and skins, and the pose at a time: node world
//! matrices, joint matrices and morph weights ([`Pose`]), applied to a scene by
//! [`crate::scene::Scene::pose`] ([`crate::scene::posing`]). The GPU deformation of the executor ([`crate::runtime`]'s deform pass)
//! reads the same joint matrices and weights (`Pose::deform_inputs`); this module's CPU
//! deformation ([`Deformer::deform`]) is the reference it is tested against, and what CPU
//! builders and the f64 reference tracer see.

use super::vertex::Vertex;
use glam::{Mat3, Mat4, Quat, Vec3};

/// A node's local transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trs {
    /// Translation.
    pub translation: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
    /// Scale.
    pub scale: Vec3,
}

impl Trs {
    /// The matrix `T * R * S`.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// One node of the hierarchy.
#[derive(Debug, Clone)]
pub struct RigNode {
    /// The node's name (or `node N`).
    pub name: String,
    /// Its parent, if any.
    pub parent: Option<usize>,
    /// Its transform when no channel drives it.
    pub rest: Trs,
    /// Its exact matrix when no channel drives it (a glTF `matrix` node, or a placed instance
    /// that never moves): kept bit for bit instead of `rest`'s recomposition.
    pub fixed: Option<Mat4>,
    /// Its morph weights when no channel drives them (the node's, else its mesh's, else zeros).
    pub weights: Vec<f32>,
}

/// The property a channel drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelTarget {
    /// `translation`.
    Translation,
    /// `rotation`.
    Rotation,
    /// `scale`.
    Scale,
    /// `weights` (morph targets).
    Weights,
}

/// How values between two keys are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// Linear (spherical linear for rotations).
    Linear,
    /// The earlier key's value.
    Step,
    /// Cubic Hermite spline with the file's in- and out-tangents.
    CubicSpline,
}

/// One animation channel: a node property keyed in time.
#[derive(Debug, Clone)]
pub struct Channel {
    /// The node it drives.
    pub node: usize,
    /// What it drives.
    pub target: ChannelTarget,
    /// How it interpolates.
    pub interpolation: Interpolation,
    /// Key times in seconds, increasing.
    pub times: Vec<f32>,
    /// `width` floats per value; cubic splines hold in-tangent, value and out-tangent per key.
    pub values: Vec<f32>,
    /// Floats per value: 3, 4, or the number of morph targets.
    pub width: usize,
}

/// A named clip.
#[derive(Debug, Clone)]
pub struct Animation {
    /// The clip's name (or `animation N`).
    pub name: String,
    /// Its channels.
    pub channels: Vec<Channel>,
    /// The last key time over its channels: playback loops with this period.
    pub duration: f32,
}

/// A skin: joints and their inverse bind matrices.
#[derive(Debug, Clone)]
pub struct Skin {
    /// The skin's name (or `skin N`).
    pub name: String,
    /// The joint nodes.
    pub joints: Vec<usize>,
    /// Per joint, the inverse of its bind-pose world matrix.
    pub inverse_bind: Vec<Mat4>,
}

/// One morph target of a mesh: per-vertex displacements.
#[derive(Debug, Clone, Default)]
pub struct MorphTarget {
    /// Position displacements, one per vertex.
    pub positions: Vec<Vec3>,
    /// Normal displacements, one per vertex, where the file has them.
    pub normals: Option<Vec<Vec3>>,
}

/// The joints and weights of a skinned mesh: `sets` groups of four influences per vertex,
/// vertex-major (vertex `v`'s influences are at `v * sets * 4 ..`).
#[derive(Debug, Clone)]
pub struct SkinWeights {
    /// The skin ([`Rig::skins`]).
    pub skin: usize,
    /// Groups of four influences per vertex (glTF `JOINTS_n`/`WEIGHTS_n` sets).
    pub sets: usize,
    /// Joint indices into the skin's joints.
    pub joints: Vec<u32>,
    /// Weights, summing to one per vertex.
    pub weights: Vec<f32>,
}

/// A scene mesh that deforms: its rest vertices, morph targets and skin.
#[derive(Debug, Clone)]
pub struct Deformer {
    /// The scene mesh it writes ([`crate::scene::Scene::meshes`]).
    pub mesh: usize,
    /// The node whose weights (and skin) drive it.
    pub node: usize,
    /// The vertices before morphing and skinning.
    pub rest: Vec<Vertex>,
    /// Morph targets (may be empty).
    pub targets: Vec<MorphTarget>,
    /// Joints and weights, for a skinned mesh (its instance's transform is then the identity:
    /// the joints place it).
    pub skin: Option<SkinWeights>,
}

/// Where an instance of the scene comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InstanceNode {
    /// The node that places it.
    pub node: usize,
    /// Whether a skin places it instead (its transform is then the identity).
    pub skinned: bool,
}

/// Everything that moves in a scene: the hierarchy, clips, skins and deforming meshes.
#[derive(Debug, Clone, Default)]
pub struct Rig {
    /// The nodes of the drawn scene, in file order.
    pub nodes: Vec<RigNode>,
    /// Per scene instance, its node.
    pub instances: Vec<InstanceNode>,
    /// The clips.
    pub animations: Vec<Animation>,
    /// The skins.
    pub skins: Vec<Skin>,
    /// The deforming meshes.
    pub deformers: Vec<Deformer>,
}

/// The pose at one time: world matrices and morph weights per node.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Per node, its world matrix.
    pub world: Vec<Mat4>,
    /// Per node, its morph weights.
    pub weights: Vec<Vec<f32>>,
}

/// Which clips drive a pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum ClipSet {
    /// None: the rest pose.
    #[default]
    Rest,
    /// One clip, by index.
    One(usize),
    /// Every clip at once, each looping over its own duration (what glTF viewers play); where
    /// two clips drive the same property, the later clip's value is used.
    All,
}

impl From<Option<usize>> for ClipSet {
    fn from(clip: Option<usize>) -> Self {
        clip.map_or(ClipSet::Rest, ClipSet::One)
    }
}

impl ClipSet {
    /// Whether any clip plays.
    pub fn is_playing(self) -> bool {
        self != ClipSet::Rest
    }
}

/// When a scene was posed, and where its deforming meshes were deformed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseTime {
    /// The clips (rest: the rest pose).
    pub clip: ClipSet,
    /// Seconds into it.
    pub time: f32,
    /// The deforming meshes' vertices in [`crate::scene::Scene::meshes`] hold this pose (false: they are left
    /// as they were, and the executor deforms them on the GPU).
    pub meshes_deformed: bool,
}

/// Which clip plays, as a user names it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum ClipChoice {
    /// The file's first clip (the rest pose in a file without clips).
    #[default]
    First,
    /// Every clip at once (`all`).
    All,
    /// A clip by index.
    Index(usize),
    /// A clip by name.
    Name(String),
}

impl std::str::FromStr for ClipChoice {
    type Err = std::convert::Infallible;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "all" {
            return Ok(ClipChoice::All);
        }
        Ok(s.parse::<usize>().map(ClipChoice::Index).unwrap_or_else(|_| ClipChoice::Name(s.to_string())))
    }
}

impl Rig {
    /// Whether anything moves: a clip with channels.
    pub(crate) fn is_animated(&self) -> bool {
        self.animations.iter().any(|a| !a.channels.is_empty())
    }

    /// The clips `choice` names: [`ClipSet::Rest`] for a file without clips and
    /// [`ClipChoice::First`] or [`ClipChoice::All`]; an error listing the clips for a name or
    /// index that is not there.
    pub fn clip(&self, choice: &ClipChoice) -> Result<ClipSet, String> {
        let list = || {
            if self.animations.is_empty() {
                "the scene has no animations".to_string()
            } else {
                let names: Vec<String> = self.animations.iter().enumerate().map(|(i, a)| format!("{i}: `{}` ({:.2} s)", a.name, a.duration)).collect();
                format!("its animations are {}", names.join(", "))
            }
        };
        let any = !self.animations.is_empty();
        match choice {
            ClipChoice::First => Ok(if any { ClipSet::One(0) } else { ClipSet::Rest }),
            ClipChoice::All => Ok(if any { ClipSet::All } else { ClipSet::Rest }),
            ClipChoice::Index(i) if *i < self.animations.len() => Ok(ClipSet::One(*i)),
            ClipChoice::Index(i) => Err(format!("no animation {i}: {}", list())),
            ClipChoice::Name(n) => {
                self.animations.iter().position(|a| a.name == *n).map(ClipSet::One).ok_or_else(|| format!("no animation named `{n}`: {}", list()))
            }
        }
    }

    /// The clips of `clips`, by index.
    fn playing(&self, clips: ClipSet) -> std::ops::Range<usize> {
        match clips {
            ClipSet::Rest => 0..0,
            ClipSet::One(c) => c.min(self.animations.len())..(c + 1).min(self.animations.len()),
            ClipSet::All => 0..self.animations.len(),
        }
    }

    /// The length of `clips` in seconds: the longest clip's (0 at rest).
    pub fn duration(&self, clips: ClipSet) -> f32 {
        self.playing(clips).map(|c| self.animations[c].duration).fold(0.0, f32::max)
    }

    /// A short name of `clips` for messages: the clip's name, `all clips` or `rest pose`.
    pub fn describe(&self, clips: ClipSet) -> String {
        match clips {
            ClipSet::Rest => "rest pose".into(),
            ClipSet::One(c) => self.animations.get(c).map_or_else(|| format!("clip {c}"), |a| a.name.clone()),
            ClipSet::All => format!("all {} clips", self.animations.len()),
        }
    }

    /// The pose of `clips` (a clip index, `None` for the rest pose, or a [`ClipSet`]) at `time`
    /// seconds, each clip looping over its own duration.
    pub fn pose(&self, clips: impl Into<ClipSet>, time: f32) -> Pose {
        let mut local: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        let mut weights: Vec<Vec<f32>> = self.nodes.iter().map(|n| n.weights.clone()).collect();
        let mut driven = vec![false; self.nodes.len()];
        for anim in self.playing(clips.into()).map(|c| &self.animations[c]) {
            let t = if anim.duration > 0.0 && time.is_finite() { time.rem_euclid(anim.duration) } else { 0.0 };
            for ch in &anim.channels {
                let v = ch.sample(t);
                driven[ch.node] |= ch.target != ChannelTarget::Weights;
                let node = &mut local[ch.node];
                match ch.target {
                    ChannelTarget::Translation => node.translation = Vec3::from_slice(&v),
                    ChannelTarget::Scale => node.scale = Vec3::from_slice(&v),
                    ChannelTarget::Rotation => node.rotation = Quat::from_slice(&v).normalize(),
                    ChannelTarget::Weights => weights[ch.node] = v,
                }
            }
        }
        // Parents come before children in a valid hierarchy of any order: resolve recursively
        // through a memo (the importer has checked there is no cycle).
        let local: Vec<Mat4> =
            self.nodes.iter().zip(&local).zip(&driven).map(|((n, trs), &d)| if d { trs.matrix() } else { n.fixed.unwrap_or_else(|| trs.matrix()) }).collect();
        let mut world: Vec<Option<Mat4>> = vec![None; self.nodes.len()];
        for n in 0..self.nodes.len() {
            self.resolve_world(n, &local, &mut world);
        }
        Pose { world: world.into_iter().map(|m| m.unwrap_or(Mat4::IDENTITY)).collect(), weights }
    }

    fn resolve_world(&self, n: usize, local: &[Mat4], world: &mut [Option<Mat4>]) -> Mat4 {
        // Walk up to the first resolved ancestor, then down.
        let mut chain = vec![n];
        while let Some(p) = self.nodes[*chain.last().unwrap_or(&n)].parent {
            if world[p].is_some() || chain.len() > self.nodes.len() {
                break;
            }
            chain.push(p);
        }
        let top = *chain.last().unwrap_or(&n);
        let mut m = self.nodes[top].parent.and_then(|p| world[p]).unwrap_or(Mat4::IDENTITY);
        for &c in chain.iter().rev() {
            m = world[c].unwrap_or_else(|| m * local[c]);
            world[c] = Some(m);
        }
        m
    }
}

impl Pose {
    /// The joint matrices of `skin` (world from bind-pose space) and the morph weights that
    /// deform `deformer`.
    pub(crate) fn deform_inputs(&self, rig: &Rig, deformer: &Deformer) -> (Vec<Mat4>, Vec<f32>) {
        let joints = deformer
            .skin
            .as_ref()
            .and_then(|s| rig.skins.get(s.skin))
            .map(|skin| skin.joints.iter().zip(&skin.inverse_bind).map(|(&j, ib)| self.world[j] * *ib).collect())
            .unwrap_or_default();
        let mut weights = self.weights[deformer.node].clone();
        weights.resize(deformer.targets.len(), 0.0);
        (joints, weights)
    }
}

impl Channel {
    /// The value at `t` (clamped to the first and last keys).
    pub fn sample(&self, t: f32) -> Vec<f32> {
        let w = self.width;
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| -> &[f32] {
            let start = if cubic { (3 * k + 1) * w } else { k * w };
            &self.values[start..start + w]
        };
        let n = self.times.len();
        if n == 0 {
            return vec![0.0; w];
        }
        if n == 1 || t <= self.times[0] {
            return value(0).to_vec();
        }
        if t >= self.times[n - 1] {
            return value(n - 1).to_vec();
        }
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = if dt > 0.0 { (t - t0) / dt } else { 0.0 };
        match self.interpolation {
            Interpolation::Step => value(k).to_vec(),
            Interpolation::Linear if self.target == ChannelTarget::Rotation => {
                let (a, b) = (Quat::from_slice(value(k)).normalize(), Quat::from_slice(value(k + 1)).normalize());
                a.slerp(b, s).to_array().to_vec()
            }
            Interpolation::Linear => value(k).iter().zip(value(k + 1)).map(|(a, b)| a + (b - a) * s).collect(),
            Interpolation::CubicSpline => {
                let out_tangent = &self.values[(3 * k + 2) * w..][..w];
                let in_tangent = &self.values[(3 * (k + 1)) * w..][..w];
                let (s2, s3) = (s * s, s * s * s);
                let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2);
                let mut v: Vec<f32> =
                    (0..w).map(|i| h00 * value(k)[i] + h10 * dt * out_tangent[i] + h01 * value(k + 1)[i] + h11 * dt * in_tangent[i]).collect();
                if self.target == ChannelTarget::Rotation {
                    v = Quat::from_slice(&v).normalize().to_array().to_vec();
                }
                v
            }
        }
    }
}

/// The linear part that carries normals through `m`: its cofactor matrix (the inverse
/// transpose times the determinant), signed so a mirroring matrix keeps normals outward.
pub(crate) fn normal_matrix(m: &Mat4) -> Mat3 {
    let a = Mat3::from_mat4(*m);
    let (c0, c1, c2) = (a.x_axis, a.y_axis, a.z_axis);
    let cof = Mat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    if a.determinant() < 0.0 {
        -cof
    } else {
        cof
    }
}

impl Deformer {
    /// The deformed vertices for joint matrices `joints` and morph `weights`: morph targets
    /// added to the rest positions and normals, then linear blend skinning with the
    /// weighted sum of the joint matrices (normals through its cofactor matrix).
    pub fn deform(&self, joints: &[Mat4], weights: &[f32]) -> Vec<Vertex> {
        self.rest
            .iter()
            .enumerate()
            .map(|(v, rest)| {
                let mut p = Vec3::from(rest.position);
                let mut n = Vec3::from(rest.normal);
                for (t, &w) in self.targets.iter().zip(weights) {
                    if w != 0.0 {
                        p += w * t.positions[v];
                        if let Some(dn) = &t.normals {
                            n += w * dn[v];
                        }
                    }
                }
                if let Some(skin) = &self.skin {
                    let m = skin_matrix(skin, v, joints);
                    p = m.transform_point3(p);
                    n = normal_matrix(&m) * n;
                }
                let n = if n.is_finite() && n.length_squared() > 1e-20 { n.normalize() } else { Vec3::Y };
                Vertex { position: p.into(), normal: n.into(), uv: rest.uv }
            })
            .collect()
    }
}

/// The weighted sum of vertex `v`'s joint matrices.
fn skin_matrix(skin: &SkinWeights, v: usize, joints: &[Mat4]) -> Mat4 {
    let mut m = Mat4::ZERO;
    for k in v * skin.sets * 4..(v + 1) * skin.sets * 4 {
        let w = skin.weights[k];
        if w != 0.0 {
            m += joints.get(skin.joints[k] as usize).copied().unwrap_or(Mat4::IDENTITY) * w;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(target: ChannelTarget, interpolation: Interpolation, times: Vec<f32>, values: Vec<f32>, width: usize) -> Channel {
        Channel { node: 0, target, interpolation, times, values, width }
    }

    #[test]
    fn linear_step_and_clamping() {
        let c = channel(ChannelTarget::Translation, Interpolation::Linear, vec![1.0, 3.0], vec![0.0, 0.0, 0.0, 2.0, 4.0, 6.0], 3);
        assert_eq!(c.sample(0.0), vec![0.0, 0.0, 0.0]);
        assert_eq!(c.sample(2.0), vec![1.0, 2.0, 3.0]);
        assert_eq!(c.sample(9.0), vec![2.0, 4.0, 6.0]);
        let s = Channel { interpolation: Interpolation::Step, ..c };
        assert_eq!(s.sample(2.9), vec![0.0, 0.0, 0.0]);
        assert_eq!(s.sample(3.0), vec![2.0, 4.0, 6.0]);
    }

    #[test]
    fn cubic_spline_matches_hermite_closed_form() {
        // p(s) from 0 to 1 over [0, 2] with tangents 3 (out of the first key) and -1 (into the
        // second), in units per second: Hermite basis with dt = 2.
        let values = vec![9.0, 0.0, 3.0, -1.0, 1.0, 9.0];
        let c = channel(ChannelTarget::Weights, Interpolation::CubicSpline, vec![0.0, 2.0], values, 1);
        for s in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
            let expected = (s * s * s - 2.0 * s * s + s) * 2.0 * 3.0 + (-2.0 * s * s * s + 3.0 * s * s) * 1.0 - (s * s * s - s * s) * 2.0;
            assert!((c.sample(2.0 * s)[0] - expected).abs() < 1e-6, "s {s}");
        }
    }

    #[test]
    fn rotations_slerp_at_constant_speed() {
        let q1 = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let mut values = Quat::IDENTITY.to_array().to_vec();
        values.extend(q1.to_array());
        let c = channel(ChannelTarget::Rotation, Interpolation::Linear, vec![0.0, 1.0], values, 4);
        let q = Quat::from_slice(&c.sample(0.5));
        assert!(q.angle_between(Quat::from_rotation_y(std::f32::consts::FRAC_PI_4)) < 1e-5);
    }

    #[test]
    fn hierarchy_composes_parent_first_and_clip_loops() {
        let node = |parent, x: f32| RigNode {
            name: String::new(),
            parent,
            rest: Trs { translation: Vec3::new(x, 0.0, 0.0), rotation: Quat::IDENTITY, scale: Vec3::ONE },
            fixed: None,
            weights: vec![],
        };
        // The child comes first in file order.
        let mut rig = Rig { nodes: vec![node(Some(1), 1.0), node(None, 10.0)], ..Default::default() };
        rig.animations.push(Animation {
            name: "move".into(),
            channels: vec![Channel {
                node: 1,
                ..channel(ChannelTarget::Translation, Interpolation::Linear, vec![0.0, 2.0], vec![0.0; 3].into_iter().chain([20.0, 0.0, 0.0]).collect(), 3)
            }],
            duration: 2.0,
        });
        assert_eq!(rig.pose(None, 0.0).world[0].w_axis.x, 11.0);
        assert_eq!(rig.pose(Some(0), 1.0).world[0].w_axis.x, 11.0);
        assert_eq!(rig.pose(Some(0), 3.0).world[0].w_axis.x, 11.0, "3 s loops to 1 s");
        assert_eq!(rig.clip(&ClipChoice::Name("move".into())), Ok(ClipSet::One(0)));
        assert!(rig.clip(&ClipChoice::Index(4)).unwrap_err().contains("`move`"));
    }
}
