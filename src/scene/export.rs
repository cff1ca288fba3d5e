//! Writes a [`Scene`] as a binary glTF (`.glb`): one buffer, one glTF mesh per raygraph mesh,
//! one node per instance (with its matrix), PBR materials with all five texture slots
//! (emission above 1 through `KHR_materials_emissive_strength`, unlit ones through
//! `KHR_materials_unlit`, each slot's sampler and `KHR_texture_transform`), PNG-embedded textures, the
//! file's lights (`KHR_lights_punctual`) and the camera presets as perspective cameras (the
//! first is the default view on import). The file is written to a temporary name and renamed,
//! so a failure never leaves a partial file.

use super::gltf_import::SceneError;
use super::{AlphaMode, Camera, LightKind, Lobes, Material, Mipmaps, PunctualLight, Scene, SlotSampling, TextureImage, Wrap};
use glam::{Mat3, Quat, Vec3};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::borrow::Cow;
use std::path::Path;

struct BinWriter {
    bin: Vec<u8>,
}

impl BinWriter {
    fn view(
        &mut self,
        root: &mut json::Root,
        buffer: json::Index<json::Buffer>,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: target.map(Valid),
        })
    }
}

fn accessor(
    root: &mut json::Root,
    view: json::Index<json::buffer::View>,
    count: usize,
    component: json::accessor::ComponentType,
    ty: json::accessor::Type,
    bounds: Option<([f32; 3], [f32; 3])>,
) -> json::Index<json::Accessor> {
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(count),
        component_type: Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(ty),
        min: bounds.map(|b| json::Value::from(b.0.to_vec())),
        max: bounds.map(|b| json::Value::from(b.1.to_vec())),
        name: None,
        normalized: false,
        sparse: None,
    })
}

/// Encodes the scene as GLB bytes.
pub(crate) fn to_glb(scene: &Scene) -> Result<Vec<u8>, String> {
    let mut root = json::Root::default();
    let buffer = root.push(json::Buffer { byte_length: USize64(0), extensions: None, extras: Default::default(), name: None, uri: None });
    let mut w = BinWriter { bin: Vec::new() };
    let textures = scene.textures.iter().map(|t| png_texture(&mut root, &mut w, buffer, t)).collect::<Result<Vec<_>, String>>()?;
    let materials = materials_json(&mut root, scene, &textures);
    let mut nodes = instance_nodes(&mut root, &mut w, buffer, scene, &materials);
    for (name, camera) in &scene.presets {
        nodes.push(camera_node(&mut root, name, camera));
    }
    nodes.extend(light_nodes(&mut root, scene));
    let s = root.push(json::Scene { name: Some(scene.name.clone()), nodes, extensions: None, extras: Default::default() });
    root.scene = Some(s);
    glb_bytes(root, w, scene)
}

/// A texture as a PNG image inside the buffer, with its glTF image and texture.
fn png_texture(root: &mut json::Root, w: &mut BinWriter, buffer: json::Index<json::Buffer>, t: &TextureImage) -> Result<json::Index<json::Texture>, String> {
    let png = t.png(true)?;
    let view = w.view(root, buffer, &png, None);
    let image = root.push(json::Image {
        buffer_view: Some(view),
        mime_type: Some(json::image::MimeType("image/png".into())),
        name: Some(t.name.clone()),
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    Ok(root.push(json::Texture { name: Some(t.name.clone()), sampler: None, source: image, extensions: None, extras: Default::default() }))
}

/// The glTF textures of the scene's textures: the plain one of each, and one per (texture,
/// sampler bits) where a slot's sampler is not glTF's default ([`sampled_textures`]).
struct GltfTextures<'a> {
    plain: &'a [json::Index<json::Texture>],
    sampled: std::collections::HashMap<(usize, u32), json::Index<json::Texture>>,
}

impl GltfTextures<'_> {
    /// The glTF texture of scene texture `i` with `m`'s slot `slot`'s sampler.
    fn of(&self, m: &Material, i: usize, slot: usize) -> json::Index<json::Texture> {
        self.sampled.get(&(i, m.sampling[slot].sampler_bits())).copied().unwrap_or(self.plain[i])
    }

    /// The texture info of `m`'s slot `slot` holding `t`.
    fn info(&self, m: &Material, t: Option<usize>, slot: usize) -> Option<json::texture::Info> {
        t.map(|i| json::texture::Info { index: self.of(m, i, slot), tex_coord: m.sampling[slot].tex_coord, extensions: None, extras: Default::default() })
    }
}

/// Every material, and the material extensions they use named in `extensionsUsed`.
fn materials_json(root: &mut json::Root, scene: &Scene, textures: &[json::Index<json::Texture>]) -> Vec<json::Index<json::Material>> {
    let textures = GltfTextures { plain: textures, sampled: sampled_textures(root, scene, textures) };
    let materials = scene.materials.iter().map(|m| material_json(root, m, &textures)).collect();
    if scene.materials.iter().any(|m| emissive_factor(m).1.is_some()) {
        root.extensions_used.push("KHR_materials_emissive_strength".into());
    }
    if scene.materials.iter().any(|m| m.unlit) {
        root.extensions_used.push("KHR_materials_unlit".into());
    }
    materials
}

/// One material, its lobe extensions named in `extensionsUsed`.
fn material_json(root: &mut json::Root, m: &Material, textures: &GltfTextures) -> json::Index<json::Material> {
    let (alpha_mode, alpha_cutoff) = match m.alpha_mode {
        AlphaMode::Opaque => (json::material::AlphaMode::Opaque, None),
        AlphaMode::Mask(c) => (json::material::AlphaMode::Mask, Some(json::material::AlphaCutoff(c))),
        AlphaMode::Blend => (json::material::AlphaMode::Blend, None),
    };
    let (emissive, emissive_strength) = emissive_factor(m);
    let lobes = lobe_extensions(&m.lobes, |k| textures.info(m, m.lobes.textures[k], 5 + k).and_then(|i| serde_json::to_value(i).ok()));
    for name in lobes.keys() {
        if !root.extensions_used.contains(name) {
            root.extensions_used.push(name.clone());
        }
    }
    root.push(json::Material {
        name: Some(m.name.clone()),
        alpha_mode: Valid(alpha_mode),
        alpha_cutoff,
        double_sided: m.double_sided,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(m.base_color),
            base_color_texture: textures.info(m, m.texture, 0),
            metallic_factor: json::material::StrengthFactor(m.metallic),
            roughness_factor: json::material::StrengthFactor(m.roughness),
            metallic_roughness_texture: textures.info(m, m.metallic_roughness_texture, 1),
            extensions: None,
            extras: Default::default(),
        },
        normal_texture: m.normal_texture.map(|i| json::material::NormalTexture {
            index: textures.of(m, i, 2),
            scale: m.normal_scale,
            tex_coord: m.sampling[2].tex_coord,
            extensions: None,
            extras: Default::default(),
        }),
        occlusion_texture: m.occlusion_texture.map(|i| json::material::OcclusionTexture {
            index: textures.of(m, i, 3),
            strength: json::material::StrengthFactor(m.occlusion_strength),
            tex_coord: m.sampling[3].tex_coord,
            extensions: None,
            extras: Default::default(),
        }),
        emissive_texture: textures.info(m, m.emissive_texture, 4),
        emissive_factor: json::material::EmissiveFactor(emissive),
        extensions: (emissive_strength.is_some() || m.unlit || !lobes.is_empty()).then(|| json::extensions::material::Material {
            emissive_strength: emissive_strength.map(|strength| json::extensions::material::EmissiveStrength {
                emissive_strength: json::extensions::material::EmissiveStrengthFactor(strength),
            }),
            unlit: m.unlit.then_some(json::extensions::material::Unlit {}),
            others: lobes,
            ..Default::default()
        }),
        ..Default::default()
    })
}

/// One node per instance (with its matrix, none for the identity). The material goes with
/// the primitive, so a mesh used with several materials is written once per (mesh, material)
/// pair.
fn instance_nodes(
    root: &mut json::Root,
    w: &mut BinWriter,
    buffer: json::Index<json::Buffer>,
    scene: &Scene,
    materials: &[json::Index<json::Material>],
) -> Vec<json::Index<json::Node>> {
    let mut gltf_mesh: std::collections::HashMap<(usize, usize), json::Index<json::Mesh>> = Default::default();
    let mut nodes = Vec::new();
    for inst in scene.instances.iter() {
        let key = (inst.mesh, inst.material);
        let mesh = *gltf_mesh.entry(key).or_insert_with(|| mesh_json(root, w, buffer, &scene.meshes[inst.mesh], materials[inst.material]));
        let matrix = inst.transform.to_cols_array();
        nodes.push(root.push(json::Node {
            mesh: Some(mesh),
            matrix: if inst.transform == glam::Mat4::IDENTITY { None } else { Some(matrix) },
            ..Default::default()
        }));
    }
    nodes
}

/// A mesh with one triangle primitive of `material`: its attributes and indices written into
/// the buffer.
fn mesh_json(
    root: &mut json::Root,
    w: &mut BinWriter,
    buffer: json::Index<json::Buffer>,
    mesh: &super::Mesh,
    material: json::Index<json::Material>,
) -> json::Index<json::Mesh> {
    use json::accessor::{ComponentType as C, Type as T};
    let attributes = mesh_attributes(root, w, buffer, mesh);
    let vi = w.view(root, buffer, bytemuck::cast_slice(&mesh.indices), Some(json::buffer::Target::ElementArrayBuffer));
    let ia = accessor(root, vi, mesh.indices.len(), C::U32, T::Scalar, None);
    root.push(json::Mesh {
        name: Some(mesh.name.clone()),
        primitives: vec![json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(ia),
            material: Some(material),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        }],
        weights: None,
        extensions: None,
        extras: Default::default(),
    })
}

/// The file's lights as nodes, and as `KHR_lights_punctual` in the root (none without lights).
fn light_nodes(root: &mut json::Root, scene: &Scene) -> Vec<json::Index<json::Node>> {
    if scene.lights.is_empty() {
        return Vec::new();
    }
    let nodes = scene.lights.iter().enumerate().map(|(i, light)| light_node(root, i, light)).collect();
    let lights = scene.lights.iter().map(light_json).collect();
    root.extensions =
        Some(json::extensions::root::Root { khr_lights_punctual: Some(json::extensions::root::KhrLightsPunctual { lights }), ..Default::default() });
    root.extensions_used.push("KHR_lights_punctual".into());
    nodes
}

/// The finished document as GLB bytes: the buffer padded to 4 bytes, the JSON with the
/// texture transforms.
fn glb_bytes(mut root: json::Root, mut w: BinWriter, scene: &Scene) -> Result<Vec<u8>, String> {
    while !w.bin.len().is_multiple_of(4) {
        w.bin.push(0);
    }
    root.buffers[0].byte_length = USize64::from(w.bin.len());
    let json_string = with_texture_transforms(&root, scene)?;
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
        bin: Some(Cow::Owned(w.bin)),
        json: Cow::Owned(json_string.into_bytes()),
    };
    glb.to_vec().map_err(|e| e.to_string())
}

/// A mesh's vertex attributes written into the buffer: positions (with their bounds), normals,
/// TEXCOORD_0, and where the mesh has them tangents, COLOR_0 and TEXCOORD_1.
fn mesh_attributes(
    root: &mut json::Root,
    w: &mut BinWriter,
    buffer: json::Index<json::Buffer>,
    mesh: &super::Mesh,
) -> std::collections::BTreeMap<json::validation::Checked<json::mesh::Semantic>, json::Index<json::Accessor>> {
    use json::accessor::{ComponentType as C, Type as T};
    use json::mesh::Semantic as S;
    let b = mesh.bounds();
    let bounds = if b.is_empty() { None } else { Some((b.min.to_array(), b.max.to_array())) };
    let n = mesh.vertices.len();
    let mut attributes = std::collections::BTreeMap::new();
    let mut add = |root: &mut json::Root, semantic: S, bytes: &[u8], ty: T, bounds: Option<([f32; 3], [f32; 3])>| {
        let view = w.view(root, buffer, bytes, Some(json::buffer::Target::ArrayBuffer));
        attributes.insert(Valid(semantic), accessor(root, view, n, C::F32, ty, bounds));
    };
    let pos: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
    let nrm: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.normal).collect();
    let uv: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv).collect();
    add(root, S::Positions, bytemuck::cast_slice(&pos), T::Vec3, bounds);
    add(root, S::Normals, bytemuck::cast_slice(&nrm), T::Vec3, None);
    add(root, S::TexCoords(0), bytemuck::cast_slice(&uv), T::Vec2, None);
    if let Some(t) = &mesh.tangents {
        add(root, S::Tangents, bytemuck::cast_slice(t), T::Vec4, None);
    }
    if let Some(extras) = mesh.extras.as_ref().filter(|e| e.len() == n) {
        let colors: Vec<[f32; 4]> = extras.iter().map(|e| e.color).collect();
        let uv1: Vec<[f32; 2]> = extras.iter().map(|e| e.uv1).collect();
        add(root, S::Colors(0), bytemuck::cast_slice(&colors), T::Vec4, None);
        add(root, S::TexCoords(1), bytemuck::cast_slice(&uv1), T::Vec2, None);
    }
    attributes
}

/// Extra glTF textures for slots whose sampler is not glTF's default: one per (scene texture,
/// sampler bits), each with its own sampler (the default keeps the plain texture of the image).
fn sampled_textures(
    root: &mut json::Root,
    scene: &Scene,
    plain: &[json::Index<json::Texture>],
) -> std::collections::HashMap<(usize, u32), json::Index<json::Texture>> {
    let mut out = std::collections::HashMap::new();
    for m in scene.materials.iter() {
        for (t, s) in m.slot_textures().iter().zip(&m.sampling) {
            let Some(t) = t.filter(|t| *t < plain.len() && s.sampler_bits() != 0) else { continue };
            out.entry((t, s.sampler_bits())).or_insert_with(|| {
                let sampler = root.push(sampler_json(s));
                let source = root.get(plain[t]).map(|p| p.source).unwrap_or_else(|| json::Index::new(0));
                root.push(json::Texture { name: None, sampler: Some(sampler), source, extensions: None, extras: Default::default() })
            });
        }
    }
    out
}

/// A slot's sampler as glTF's.
fn sampler_json(s: &SlotSampling) -> json::texture::Sampler {
    use json::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => WrappingMode::Repeat,
        Wrap::ClampToEdge => WrappingMode::ClampToEdge,
        Wrap::MirroredRepeat => WrappingMode::MirroredRepeat,
    };
    let min = match (s.min_nearest, s.mipmaps) {
        (false, Mipmaps::None) => MinFilter::Linear,
        (true, Mipmaps::None) => MinFilter::Nearest,
        (false, Mipmaps::Nearest) => MinFilter::LinearMipmapNearest,
        (true, Mipmaps::Nearest) => MinFilter::NearestMipmapNearest,
        (false, Mipmaps::Linear) => MinFilter::LinearMipmapLinear,
        (true, Mipmaps::Linear) => MinFilter::NearestMipmapLinear,
    };
    json::texture::Sampler {
        mag_filter: Some(Valid(if s.mag_nearest { MagFilter::Nearest } else { MagFilter::Linear })),
        min_filter: Some(Valid(min)),
        wrap_s: Valid(wrap(s.wrap_s)),
        wrap_t: Valid(wrap(s.wrap_t)),
        name: None,
        extensions: None,
        extras: Default::default(),
    }
}

/// The document's JSON with each slot's uv transform written as `KHR_texture_transform`
/// (offset, rotation and scale recovered from the matrix: translation x rotation x scale).
fn with_texture_transforms(root: &json::Root, scene: &Scene) -> Result<String, String> {
    let mut doc = json::serialize::to_value(root).map_err(|e| e.to_string())?;
    let mut any = false;
    for (i, m) in scene.materials.iter().enumerate() {
        for (slot, s) in m.sampling.iter().enumerate() {
            let Some([a, b]) = s.transform else { continue };
            let path = super::gltf_import::TextureSlot::ALL[slot].json_path();
            let info = path.iter().fold(&mut doc["materials"][i], |v, key| &mut v[*key]);
            if !info.is_object() {
                continue; // the slot has no texture
            }
            let rotation = (-b[0]).atan2(a[0]);
            let (sin, cos) = rotation.sin_cos();
            let scale = [a[0] * cos - b[0] * sin, a[1] * sin + b[1] * cos];
            let mut ext = json::Value::Object(Default::default());
            ext["offset"] = json::Value::from(vec![a[2], b[2]]);
            ext["rotation"] = json::Value::from(rotation);
            ext["scale"] = json::Value::from(scale.to_vec());
            info["extensions"]["KHR_texture_transform"] = ext;
            any = true;
        }
    }
    if any {
        match doc["extensionsUsed"].as_array_mut() {
            Some(used) => used.push("KHR_texture_transform".into()),
            None => doc["extensionsUsed"] = json::Value::from(vec!["KHR_texture_transform"]),
        }
    }
    json::serialize::to_string(&doc).map_err(|e| e.to_string())
}

/// glTF's emissiveFactor (at most 1) and, where the emission is brighter, the
/// `KHR_materials_emissive_strength` that multiplies it back.
fn emissive_factor(m: &Material) -> ([f32; 3], Option<f32>) {
    let max = m.emissive.iter().fold(0.0f32, |a, b| a.max(*b));
    if max > 1.0 {
        (m.emissive.map(|c| c / max), Some(max))
    } else {
        (m.emissive, None)
    }
}

/// A node whose local -Z is `forward` and whose +Y is `up` (made orthogonal to it).
fn oriented_node(name: &str, position: Vec3, forward: Vec3, up: Vec3) -> json::Node {
    let forward = forward.normalize_or(Vec3::NEG_Z);
    let right = forward.cross(up).try_normalize().unwrap_or_else(|| forward.any_orthonormal_vector());
    let up = right.cross(forward);
    let rotation = Quat::from_mat3(&Mat3::from_cols(right, up, -forward)).normalize();
    json::Node {
        name: Some(name.to_string()),
        translation: Some(position.to_array()),
        rotation: Some(json::scene::UnitQuaternion(rotation.to_array())),
        ..Default::default()
    }
}

/// A camera preset as a perspective or orthographic camera on its own node.
fn camera_node(root: &mut json::Root, name: &str, c: &Camera) -> json::Index<json::Node> {
    let perspective = c.orthographic.is_none().then(|| json::camera::Perspective {
        aspect_ratio: c.aspect_ratio,
        yfov: c.fov_y,
        zfar: Some(c.far),
        znear: c.near,
        extensions: None,
        extras: Default::default(),
    });
    let orthographic = c.orthographic.map(|half_height| json::camera::Orthographic {
        xmag: half_height * c.aspect_ratio.unwrap_or(1.0),
        ymag: half_height,
        zfar: c.far,
        znear: c.near,
        extensions: None,
        extras: Default::default(),
    });
    let camera = root.push(json::Camera {
        name: Some(name.to_string()),
        type_: Valid(if orthographic.is_some() { json::camera::Type::Orthographic } else { json::camera::Type::Perspective }),
        orthographic,
        perspective,
        extensions: None,
        extras: Default::default(),
    });
    let node = json::Node { camera: Some(camera), ..oriented_node(name, c.position, c.target - c.position, c.up) };
    root.push(node)
}

fn light_json(l: &PunctualLight) -> json::extensions::scene::khr_lights_punctual::Light {
    use json::extensions::scene::khr_lights_punctual::{Light, Spot, Type};
    let (type_, range, spot) = match l.kind {
        LightKind::Directional => (Type::Directional, None, None),
        LightKind::Point { range } => (Type::Point, range, None),
        LightKind::Spot { range, inner_cone, outer_cone } => (Type::Spot, range, Some(Spot { inner_cone_angle: inner_cone, outer_cone_angle: outer_cone })),
    };
    Light {
        color: l.color.to_array(),
        extensions: None,
        extras: Default::default(),
        intensity: l.intensity,
        name: Some(l.name.clone()),
        range,
        spot,
        type_: Valid(type_),
    }
}

/// The node of light `index`: at its position, shining along its local -Z.
fn light_node(root: &mut json::Root, index: usize, l: &PunctualLight) -> json::Index<json::Node> {
    let up = if l.direction.cross(Vec3::Y).length_squared() > 1e-6 { Vec3::Y } else { Vec3::Z };
    let extensions = json::extensions::scene::Node {
        khr_lights_punctual: Some(json::extensions::scene::khr_lights_punctual::KhrLightsPunctual { light: json::Index::new(index as u32) }),
        ..Default::default()
    };
    let node = json::Node { extensions: Some(extensions), ..oriented_node(&l.name, l.position, l.direction, up) };
    root.push(node)
}

/// Writes the scene to `path` as GLB, atomically.
pub fn write_glb(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    let err = |message: String| SceneError::Write { path: path.to_path_buf(), message };
    let bytes = to_glb(scene).map_err(err)?;
    crate::util::write_atomic(path, &bytes).map_err(|e| err(e.to_string()))
}

/// The lobe extensions a material needs (`KHR_materials_ior`, `KHR_materials_specular`,
/// `KHR_materials_clearcoat`), each only where its factors differ from glTF's defaults.
/// `texture_info(k)`: the texture info JSON of lobe texture `k` ([`Lobes::textures`]), `None`
/// without one.
fn lobe_extensions(lobes: &Lobes, texture_info: impl Fn(usize) -> Option<serde_json::Value>) -> serde_json::Map<String, serde_json::Value> {
    use crate::scene::{LOBE_CLEARCOAT, LOBE_CLEARCOAT_NORMAL, LOBE_CLEARCOAT_ROUGHNESS, LOBE_SPECULAR, LOBE_SPECULAR_COLOR, LOBE_TRANSMISSION};
    let core = Lobes::default();
    let mut out = serde_json::Map::new();
    let mut add = |name: &str, mut ext: serde_json::Value, textures: &[(usize, &str)]| {
        for &(k, key) in textures {
            if let Some(info) = texture_info(k) {
                ext[key] = info;
            }
        }
        out.insert(name.into(), ext);
    };
    let has = |ks: &[usize]| ks.iter().any(|&k| lobes.textures[k].is_some());
    if lobes.ior != core.ior {
        add("KHR_materials_ior", serde_json::json!({ "ior": lobes.ior }), &[]);
    }
    if lobes.specular != core.specular || lobes.specular_color != core.specular_color || has(&[LOBE_SPECULAR, LOBE_SPECULAR_COLOR]) {
        let ext = serde_json::json!({ "specularFactor": lobes.specular, "specularColorFactor": lobes.specular_color });
        add("KHR_materials_specular", ext, &[(LOBE_SPECULAR, "specularTexture"), (LOBE_SPECULAR_COLOR, "specularColorTexture")]);
    }
    if lobes.clearcoat != core.clearcoat || lobes.clearcoat_roughness != core.clearcoat_roughness || has(&[LOBE_CLEARCOAT, LOBE_CLEARCOAT_ROUGHNESS]) {
        let ext = serde_json::json!({ "clearcoatFactor": lobes.clearcoat, "clearcoatRoughnessFactor": lobes.clearcoat_roughness });
        let textures =
            [(LOBE_CLEARCOAT, "clearcoatTexture"), (LOBE_CLEARCOAT_ROUGHNESS, "clearcoatRoughnessTexture"), (LOBE_CLEARCOAT_NORMAL, "clearcoatNormalTexture")];
        add("KHR_materials_clearcoat", ext, &textures);
    }
    if lobes.transmission != core.transmission || has(&[LOBE_TRANSMISSION]) {
        add("KHR_materials_transmission", serde_json::json!({ "transmissionFactor": lobes.transmission }), &[(LOBE_TRANSMISSION, "transmissionTexture")]);
    }
    if let Some(normal) = out.get_mut("KHR_materials_clearcoat").and_then(|c| c.get_mut("clearcoatNormalTexture")) {
        normal["scale"] = serde_json::json!(lobes.clearcoat_normal_scale);
    }
    out
}
