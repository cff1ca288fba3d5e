//! glTF 2.0 import (`.gltf` with external or embedded buffers, `.glb`): the chosen scene's node
//! hierarchy with transforms, meshes and primitives (with `COLOR_0` and `TEXCOORD_1`), PBR
//! metallic-roughness materials with all five texture slots (a per-slot fallback where an image
//! cannot be loaded; each slot's sampler, uv set and `KHR_texture_transform`),
//! `KHR_materials_emissive_strength`, `KHR_materials_unlit`, `KHR_lights_punctual` lights and
//! perspective and orthographic cameras (camera presets, with the built-in ones). Bad input becomes a
//! [`SceneError`] naming the file, or a counted warning where loading can go on; what the file
//! uses that raygraph approximates or ignores is listed in the [`ImportReport`].

use super::{
    AlphaMode, Bounds, Camera, Instance, LightKind, Material, Mesh, Mipmaps, PunctualLight, Scene, SlotSampling, TextureImage, Vertex, VertexExtra, Wrap,
};
use glam::{Mat4, Vec3};
use gltf::json::Value;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// Why a scene could not be opened or written.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file is not glTF 2.0 that parses.
    #[error("{path}: not a readable glTF file: {message}\n  help: give a .gltf or .glb file (glTF 2.0)")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// A buffer the file names cannot be loaded.
    #[error("{path}: buffer {buffer} ({uri}) cannot be loaded: {message}\n  help: put the buffer file next to the .gltf or fix its uri")]
    Buffer {
        /// The file.
        path: PathBuf,
        /// The buffer's index.
        buffer: usize,
        /// Its uri.
        uri: String,
        /// Why it cannot be loaded.
        message: String,
    },
    /// A mesh primitive cannot be read.
    #[error("{path}: mesh `{mesh}` primitive {primitive}: {message}")]
    Primitive {
        /// The file.
        path: PathBuf,
        /// The mesh's name.
        mesh: String,
        /// The primitive's index in the mesh.
        primitive: usize,
        /// What is wrong with it.
        message: String,
    },
    /// The file's animation data cannot be played (clip, channel, skin or morph target).
    #[error("{path}: {message}\n  help: fix the animation data, or export the file without animation")]
    Rig {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the clip, channel, skin or primitive.
        message: String,
    },
    /// The file has nothing to draw.
    #[error("{path}: the file has no scene and no nodes to draw")]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The file requires extensions raygraph does not read.
    #[error("{path}: the file requires {extensions}, which raygraph does not support\n  help: raygraph reads {supported}; export the file without the required extension (for example without mesh or texture compression)")]
    UnsupportedRequired {
        /// The file.
        path: PathBuf,
        /// The required extensions raygraph lacks.
        extensions: String,
        /// The extensions it reads (`SUPPORTED_EXTENSIONS`).
        supported: String,
    },
    /// The scene asked for with `--gltf-scene` is not in the file.
    #[error("{path}: no scene `{asked}`; the file's scenes are: {scenes}\n  help: give a scene's index or name (see `raygraph scene info`)")]
    NoSuchScene {
        /// The file.
        path: PathBuf,
        /// What was asked for.
        asked: String,
        /// The file's scenes, by index and name.
        scenes: String,
    },
    /// `--gltf-scene` given for a scene that is not a glTF file.
    #[error("--gltf-scene {asked}: `{scene}` is a built-in scene, not a glTF file\n  help: give --gltf-scene only with a .gltf or .glb path")]
    SceneOfBuiltin {
        /// The built-in scene.
        scene: String,
        /// What was asked for.
        asked: String,
    },
    /// Neither a built-in scene nor a glTF path: the name, and the built-in names.
    #[error("unknown scene `{0}`; built-in scenes are: {1}\n  help: give a built-in scene name or a .gltf/.glb path")]
    UnknownScene(String, String),
    /// An exported file could not be written.
    #[error("could not write {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        message: String,
    },
}

/// What to load. Textures are decoded only when a pass of the active graph samples them.
#[derive(Debug, Clone)]
pub struct LoadOptions {
    /// Decode the material textures (`false`: materials keep their factors only).
    pub textures: bool,
    /// Seed of the generated `atrium`.
    pub seed: u64,
    /// The glTF scene to draw, by index or name (`None`: the file's `scene`, else its first).
    pub gltf_scene: Option<String>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self { textures: true, seed: super::procedural::ATRIUM_DEFAULT_SEED, gltf_scene: None }
    }
}

/// The glTF extensions raygraph reads (everything else in `extensionsUsed` is listed as
/// ignored, and a file that requires anything else is refused).
pub(crate) const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_clearcoat",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_texture_transform",
];

/// The lobe factors of a material's JSON (`KHR_materials_ior`, `KHR_materials_specular`,
/// `KHR_materials_clearcoat`, `KHR_materials_transmission`), glTF's defaults where absent.
fn material_lobes(json: &Value) -> crate::scene::Lobes {
    let ext = &json["extensions"];
    let number = |v: &Value, default: f32| v.as_f64().map_or(default, |x| x as f32);
    let mut lobes = crate::scene::Lobes { ior: number(&ext["KHR_materials_ior"]["ior"], 1.5), ..Default::default() };
    let specular = &ext["KHR_materials_specular"];
    lobes.specular = number(&specular["specularFactor"], 1.0);
    if let Some(c) = specular["specularColorFactor"].as_array().filter(|c| c.len() == 3) {
        lobes.specular_color = [0, 1, 2].map(|k| number(&c[k], 1.0));
    }
    let coat = &ext["KHR_materials_clearcoat"];
    lobes.clearcoat = number(&coat["clearcoatFactor"], 0.0);
    lobes.clearcoat_roughness = number(&coat["clearcoatRoughnessFactor"], 0.0);
    lobes.clearcoat_normal_scale = number(&coat["clearcoatNormalTexture"]["scale"], 1.0);
    lobes.transmission = number(&ext["KHR_materials_transmission"]["transmissionFactor"], 0.0);
    lobes
}

/// The texture slots of a glTF material: the core five, then the lobe extensions' six.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureSlot {
    /// The base colour texture (sRGB).
    BaseColor,
    /// The metallic-roughness texture.
    MetallicRoughness,
    /// The tangent-space normal map.
    Normal,
    /// The ambient-occlusion texture.
    Occlusion,
    /// The emissive texture (sRGB).
    Emissive,
    /// `KHR_materials_specular` `specularTexture` (alpha).
    Specular,
    /// `KHR_materials_specular` `specularColorTexture` (sRGB).
    SpecularColor,
    /// `KHR_materials_clearcoat` `clearcoatTexture` (red).
    Clearcoat,
    /// `KHR_materials_clearcoat` `clearcoatRoughnessTexture` (green).
    ClearcoatRoughness,
    /// `KHR_materials_clearcoat` `clearcoatNormalTexture`.
    ClearcoatNormal,
    /// `KHR_materials_transmission` `transmissionTexture` (red).
    Transmission,
}

impl TextureSlot {
    /// Every slot, in the order of [`Material::sampling`] and `Material::slot_textures`.
    pub const ALL: [TextureSlot; crate::scene::TEXTURE_SLOTS] = [
        TextureSlot::BaseColor,
        TextureSlot::MetallicRoughness,
        TextureSlot::Normal,
        TextureSlot::Occlusion,
        TextureSlot::Emissive,
        TextureSlot::Specular,
        TextureSlot::SpecularColor,
        TextureSlot::Clearcoat,
        TextureSlot::ClearcoatRoughness,
        TextureSlot::ClearcoatNormal,
        TextureSlot::Transmission,
    ];

    /// The keys from a glTF material's JSON down to the slot's texture info.
    pub fn json_path(self) -> &'static [&'static str] {
        match self {
            TextureSlot::BaseColor => &["pbrMetallicRoughness", "baseColorTexture"],
            TextureSlot::MetallicRoughness => &["pbrMetallicRoughness", "metallicRoughnessTexture"],
            TextureSlot::Normal => &["normalTexture"],
            TextureSlot::Occlusion => &["occlusionTexture"],
            TextureSlot::Emissive => &["emissiveTexture"],
            TextureSlot::Specular => &["extensions", "KHR_materials_specular", "specularTexture"],
            TextureSlot::SpecularColor => &["extensions", "KHR_materials_specular", "specularColorTexture"],
            TextureSlot::Clearcoat => &["extensions", "KHR_materials_clearcoat", "clearcoatTexture"],
            TextureSlot::ClearcoatRoughness => &["extensions", "KHR_materials_clearcoat", "clearcoatRoughnessTexture"],
            TextureSlot::ClearcoatNormal => &["extensions", "KHR_materials_clearcoat", "clearcoatNormalTexture"],
            TextureSlot::Transmission => &["extensions", "KHR_materials_transmission", "transmissionTexture"],
        }
    }

    /// The slot's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            TextureSlot::BaseColor => "base colour",
            TextureSlot::MetallicRoughness => "metallic-roughness",
            TextureSlot::Normal => "normal",
            TextureSlot::Occlusion => "occlusion",
            TextureSlot::Emissive => "emissive",
            TextureSlot::Specular => "specular",
            TextureSlot::SpecularColor => "specular colour",
            TextureSlot::Clearcoat => "clearcoat",
            TextureSlot::ClearcoatRoughness => "clearcoat roughness",
            TextureSlot::ClearcoatNormal => "clearcoat normal",
            TextureSlot::Transmission => "transmission",
        }
    }

    /// What stands in for the slot's texture when its image cannot be loaded.
    pub fn fallback(self) -> &'static str {
        match self {
            TextureSlot::BaseColor => "the magenta checker (a visible marker)",
            TextureSlot::MetallicRoughness => "no texture (the metallic and roughness factors alone)",
            TextureSlot::Normal => "no normal map (the flat normal)",
            TextureSlot::Occlusion => "no occlusion texture (occlusion 1)",
            TextureSlot::Emissive => "no emission (emissive 0)",
            TextureSlot::ClearcoatNormal => "no coat normal map (the surface's normal)",
            _ => "no texture (the extension's factor alone)",
        }
    }

    /// Whether the slot's texels are colour (sRGB-encoded): base colour, emissive, specular
    /// colour. The others hold linear data.
    pub(crate) fn is_colour(self) -> bool {
        matches!(self, TextureSlot::BaseColor | TextureSlot::Emissive | TextureSlot::SpecularColor)
    }
}

/// A material texture slot whose image could not be loaded and that took its fallback.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureFallback {
    /// The material's name.
    pub material: String,
    /// The slot.
    pub slot: TextureSlot,
    /// The image's name or uri.
    pub image: String,
    /// Why the image could not be loaded.
    pub reason: String,
}

/// What import noticed but could work around.
#[derive(Debug, Clone, Default)]
pub struct ImportReport {
    /// Everything noticed, one line each, for the user.
    pub warnings: Vec<String>,
    /// Triangles dropped because a vertex position was NaN or infinite.
    pub non_finite_triangles: usize,
    /// Zero-area triangles (kept for drawing, left out of acceleration structures).
    pub degenerate_triangles: usize,
    /// Primitives skipped because their mode is not triangles.
    pub skipped_primitives: usize,
    /// Distinct images that failed to load (each slot using one takes its fallback).
    pub missing_images: usize,
    /// Every material slot that took its fallback, with the image and the reason.
    pub texture_fallbacks: Vec<TextureFallback>,
    /// Distinct images the materials' five texture slots use (`None` for built-in scenes).
    pub images_used: Option<usize>,
    /// What the file uses that raygraph draws differently (per material, camera, image).
    pub approximated: Vec<String>,
    /// What the file uses that raygraph does not read (per extension, material, mesh, ...).
    pub ignored_features: Vec<String>,
    /// Cameras of the file that became camera presets.
    pub file_cameras: usize,
    /// The file's scenes, one line each (index, name, whether it is drawn and the file's
    /// default); empty for built-in scenes.
    pub scenes: Vec<String>,
    /// A `default` material was added for primitives that name none.
    pub default_material: bool,
    /// Texture references not loaded because the active graph samples no textures.
    pub textures_not_loaded: usize,
    /// What the import of clips, skins and morph targets repaired.
    pub rig_repairs: super::gltf_animation::RigRepairs,
}

impl ImportReport {
    fn warn(&mut self, w: String) {
        log::warn!("{w}");
        self.warnings.push(w);
    }

    /// The approximated and ignored features, one line each (`render` prints them once; the
    /// repairs and fallbacks are logged as warnings while loading).
    pub fn notes(&self) -> Vec<String> {
        let approximated = self.approximated.iter().map(|a| format!("approximated: {a}"));
        approximated.chain(self.ignored_features.iter().map(|i| format!("ignored: {i}"))).collect()
    }
}

/// A magenta/black checker that marks a texture that could not be loaded.
pub(crate) fn fallback_texture(name: &str) -> TextureImage {
    super::builtin::checker(&format!("missing: {name}"), 64, 8, [255, 0, 255], [0, 0, 0])
}

/// `gltf::Gltf::from_slice` with three checks first: every extension the file requires is one
/// raygraph reads (an error naming them otherwise); every accessor a primitive names exists
/// (gltf-json 1.4's validator reads the accessor a primitive's `POSITION` names without a
/// bounds check, so a file naming a missing accessor would panic inside it); and every
/// animation channel targets a node that exists through a path glTF defines (unvalidated by
/// gltf-json, unwrapped by the `gltf` crate).
fn parse_and_validate(path: &Path, bytes: &[u8]) -> Result<gltf::Gltf, SceneError> {
    use gltf::json::validation::Validate;
    let parse_err = |message: String| SceneError::Parse { path: path.to_path_buf(), message };
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| parse_err(e.to_string()))?;
    let root = gltf.document.as_json();
    let unsupported: Vec<&str> = root.extensions_required.iter().map(String::as_str).filter(|e| !SUPPORTED_EXTENSIONS.contains(e)).collect();
    if !unsupported.is_empty() {
        return Err(SceneError::UnsupportedRequired {
            path: path.to_path_buf(),
            extensions: unsupported.join(", "),
            supported: SUPPORTED_EXTENSIONS.join(", "),
        });
    }
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(parse_err(format!(
                        "meshes[{m}].primitives[{p}].attributes: {} names accessor {}, but the file has {} accessors",
                        match semantic {
                            gltf::json::validation::Checked::Valid(s) => s.to_string(),
                            gltf::json::validation::Checked::Invalid => "an unknown attribute".to_string(),
                        },
                        accessor.value(),
                        root.accessors.len()
                    )));
                }
            }
        }
    }
    // gltf-json 1.4 does not validate an animation channel's target (its node index and path),
    // and the `gltf` crate's accessors for them panic on a bad one.
    for (a, anim) in root.animations.iter().enumerate() {
        for (c, channel) in anim.channels.iter().enumerate() {
            let at = format!("animations[{a}].channels[{c}].target");
            if channel.target.node.value() >= root.nodes.len() {
                return Err(parse_err(format!("{at}.node: names node {}, but the file has {} nodes", channel.target.node.value(), root.nodes.len())));
            }
            if matches!(channel.target.path, gltf::json::validation::Checked::Invalid) {
                return Err(parse_err(format!("{at}.path: not one of translation, rotation, scale, weights")));
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| errors.push((path(), error)));
    if !errors.is_empty() {
        return Err(parse_err(gltf::Error::Validation(errors).to_string()));
    }
    Ok(gltf)
}

/// The component types and shapes glTF 2.0 allows for what the importer reads (the `gltf`
/// crate's readers assume them and would panic on others).
fn check_accessor_types(prim: &gltf::Primitive) -> Result<(), String> {
    use gltf::accessor::{DataType as T, Dimensions as D};
    use gltf::Semantic as S;
    let check = |what: &str, acc: gltf::Accessor, types: &[T], dims: D| {
        if types.contains(&acc.data_type()) && acc.dimensions() == dims {
            Ok(())
        } else {
            Err(format!(
                "{what} accessor {} is {:?} {:?}; glTF requires {:?} of {}",
                acc.index(),
                acc.dimensions(),
                acc.data_type(),
                dims,
                types.iter().map(|t| format!("{t:?}")).collect::<Vec<_>>().join(" or ")
            ))
        }
    };
    if let Some(acc) = prim.indices() {
        check("the indices", acc, &[T::U8, T::U16, T::U32], D::Scalar)?;
    }
    for (semantic, acc) in prim.attributes() {
        match semantic {
            S::Positions => check("the POSITION", acc, &[T::F32], D::Vec3)?,
            S::Normals => check("the NORMAL", acc, &[T::F32], D::Vec3)?,
            S::Tangents => check("the TANGENT", acc, &[T::F32], D::Vec4)?,
            S::TexCoords(n @ 0..=1) => check(&format!("the TEXCOORD_{n}"), acc, &[T::F32, T::U8, T::U16], D::Vec2)?,
            S::Colors(0) => check("the COLOR_0", acc.clone(), &[T::F32, T::U8, T::U16], D::Vec4)
                .or_else(|_| check("the COLOR_0", acc, &[T::F32, T::U8, T::U16], D::Vec3))?,
            _ => {}
        }
    }
    Ok(())
}

/// Loads a glTF or GLB file.
pub fn load(path: &Path, options: &LoadOptions) -> Result<(Scene, ImportReport), SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::Parse { path: path.to_path_buf(), message: e.to_string() })?;
    load_bytes(path, &bytes, options)
}

/// Loads glTF or GLB `bytes` that were read from `path` (the name errors give; the folder its
/// relative buffer and image uris are read from). A browser's file picker gives bytes and a
/// name: a GLB, or a glTF whose buffers and images are embedded.
pub(crate) fn load_bytes(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<(Scene, ImportReport), SceneError> {
    let gltf = parse_and_validate(path, bytes)?;
    let raw = raw_json(bytes);
    let base = path.parent().unwrap_or(Path::new("."));
    let mut report = ImportReport::default();
    let buffers = load_buffers(path, base, &gltf)?;
    notes::collect(&gltf.document, &raw, &mut report);
    let source = Source { path, doc: &gltf.document, raw: &raw, base, buffers: &buffers };
    let (mut materials, textures) = load_materials(&source, options.textures, &mut report);
    let FileMeshes { mut meshes, primitives_of_mesh, mesh_primitive } = read_meshes(&source, &mut materials, &mut report)?;
    let roots = scene_roots(path, &gltf.document, options.gltf_scene.as_deref(), &mut report)?;
    let mut placed = walk_nodes(path, roots, &primitives_of_mesh, &mut report)?;
    let rig_input = super::gltf_animation::RigInput { doc: &gltf.document, buffers: &buffers, mesh_primitive: &mesh_primitive };
    let rig = read_rig(path, &rig_input, &mut meshes, &mut placed, &mut report)?;
    if placed.instances.is_empty() && meshes.is_empty() {
        return Err(SceneError::Empty { path: path.to_path_buf() });
    }
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    let mut scene = Scene {
        name,
        meshes: meshes.into_iter().map(Into::into).collect(),
        materials: materials.into(),
        instances: placed.instances.into(),
        textures,
        camera: Camera::default(),
        presets: Vec::new(),
        light: super::Light::default(),
        point_light: None,
        lights: placed.lights,
        rig: rig.map(std::sync::Arc::new),
        posed: None,
        environment: None,
    };
    // Skinned meshes are placed by their joints and morph targets take the nodes' weights.
    scene.pose(None, 0.0);
    let file = file_cameras(path, &placed.cameras, scene.bounds(), &mut report);
    report.file_cameras = file.len();
    (scene.camera, scene.presets) = camera_presets(&scene, file);
    Ok((scene, report))
}

/// The file being read: its name (for messages), its document and JSON, the folder its
/// relative uris are read from, and its buffers.
#[derive(Clone, Copy)]
struct Source<'a> {
    path: &'a Path,
    doc: &'a gltf::Document,
    /// The JSON as a tree ([`raw_json`]), for what the `gltf` crate does not read.
    raw: &'a Value,
    base: &'a Path,
    buffers: &'a [gltf::buffer::Data],
}

/// The file's materials, and the textures their slots use (none unless `load`).
fn load_materials(source: &Source, load: bool, report: &mut ImportReport) -> (Vec<Material>, Vec<TextureImage>) {
    let (doc, raw) = (source.doc, source.raw);
    let mut loader = TextureLoader { source: *source, load, textures: Vec::new(), loaded: HashMap::new(), checker: HashMap::new() };
    let materials: Vec<Material> = doc.materials().map(|m| loader.material(&m, report)).collect();
    for m in materials.iter().filter(|m| m.lobes.textures[crate::scene::LOBE_TRANSMISSION].is_some() && !m.transmission_texture_drawn()) {
        report.ignored_features.push(format!(
            "material `{}`: KHR_materials_transmission transmissionTexture (drawn only where it reads the base colour's uv, TEXCOORD_0 through the same transform; transmissionFactor alone is read)",
            m.name
        ));
    }
    report.images_used = Some(images_used(doc, raw));
    (materials, loader.textures)
}

/// The file's meshes: one raygraph mesh per glTF triangle primitive.
struct FileMeshes {
    meshes: Vec<Mesh>,
    /// Per glTF mesh, its primitives as (scene mesh, material).
    primitives_of_mesh: Vec<Vec<(usize, usize)>>,
    /// Per scene mesh, the (glTF mesh, primitive) it came from.
    mesh_primitive: Vec<(usize, usize)>,
}

/// Reads every triangle primitive (skipping others with a warning); a primitive without a
/// material gets a `default` one, added to `materials` the first time.
fn read_meshes(source: &Source, materials: &mut Vec<Material>, report: &mut ImportReport) -> Result<FileMeshes, SceneError> {
    let path = source.path;
    let mut out = FileMeshes { meshes: Vec::new(), primitives_of_mesh: Vec::new(), mesh_primitive: Vec::new() };
    let mut default_material = None; // added for the first primitive without a material
    for mesh in source.doc.meshes() {
        let mut prims = Vec::new();
        let mesh_name = mesh.name().map(str::to_string).unwrap_or_else(|| format!("mesh {}", mesh.index()));
        for prim in mesh.primitives() {
            let mode = prim.mode();
            if !matches!(mode, gltf::mesh::Mode::Triangles | gltf::mesh::Mode::TriangleStrip | gltf::mesh::Mode::TriangleFan) {
                report.skipped_primitives += 1;
                report.warn(format!("{}: mesh `{mesh_name}` primitive {}: mode {:?} is not triangles; skipped", path.display(), prim.index(), prim.mode()));
                continue;
            }
            let prim_err = |message: String| SceneError::Primitive { path: path.to_path_buf(), mesh: mesh_name.clone(), primitive: prim.index(), message };
            let material = match prim.material().index() {
                Some(m) => m,
                None => *default_material.get_or_insert_with(|| {
                    report.default_material = true;
                    materials.push(Material::diffuse("default", [0.8, 0.8, 0.8, 1.0], None));
                    materials.len() - 1
                }),
            };
            let (m, non_finite) = primitive_mesh(&prim, source.buffers, materials[material].normal_texture.is_some()).map_err(prim_err)?;
            report.non_finite_triangles += non_finite;
            report.degenerate_triangles += count_degenerate(&m.vertices, &m.indices);
            out.meshes.push(Mesh { name: format!("{mesh_name}/{}", prim.index()), ..m });
            out.mesh_primitive.push((mesh.index(), prim.index()));
            prims.push((out.meshes.len() - 1, material));
        }
        out.primitives_of_mesh.push(prims);
    }
    if report.non_finite_triangles > 0 {
        report.warn(format!("{}: dropped {} triangles with NaN or infinite positions", path.display(), report.non_finite_triangles));
    }
    if report.degenerate_triangles > 0 {
        report.warn(format!("{}: {} zero-area triangles (left out of acceleration structures)", path.display(), report.degenerate_triangles));
    }
    Ok(out)
}

/// The file's rig, where it has one (its repairs logged and counted in `report`); a rig error
/// becomes the file's.
fn read_rig(
    path: &Path,
    input: &super::gltf_animation::RigInput,
    meshes: &mut Vec<Mesh>,
    placed: &mut Placed,
    report: &mut ImportReport,
) -> Result<Option<super::animation::Rig>, SceneError> {
    match super::gltf_animation::rig(input, meshes, &mut placed.instances, &placed.instance_nodes) {
        Ok(Some((rig, repairs))) => {
            for w in repairs.warnings() {
                report.warn(format!("{}: {w}", path.display()));
            }
            report.rig_repairs = repairs;
            Ok(Some(rig))
        }
        Ok(None) => Ok(None),
        Err(super::gltf_animation::RigError::Rig(message)) => Err(SceneError::Rig { path: path.to_path_buf(), message }),
        Err(super::gltf_animation::RigError::Primitive { mesh, primitive, message }) => {
            Err(SceneError::Primitive { path: path.to_path_buf(), mesh, primitive, message })
        }
    }
}

/// The file's JSON as a tree (for extensions the `gltf` crate drops); `Null` if unreadable
/// (the typed parse has succeeded by then, so this does not happen for a valid file).
fn raw_json(bytes: &[u8]) -> Value {
    let json: Option<Value> = if bytes.starts_with(b"glTF") {
        gltf::binary::Glb::from_slice(bytes).ok().and_then(|glb| gltf::json::deserialize::from_slice(&glb.json).ok())
    } else {
        gltf::json::deserialize::from_slice(bytes).ok()
    };
    json.unwrap_or(Value::Null)
}

/// Every buffer, each checked so the error names it, then every buffer view and accessor
/// checked to lie inside them before anything reads through them.
fn load_buffers(path: &Path, base: &Path, gltf: &gltf::Gltf) -> Result<Vec<gltf::buffer::Data>, SceneError> {
    let parse_err = |message: String| SceneError::Parse { path: path.to_path_buf(), message };
    let mut blob = gltf.blob.clone();
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let uri = match buffer.source() {
            gltf::buffer::Source::Uri(u) => {
                if u.starts_with("data:") {
                    "embedded data uri".to_string()
                } else {
                    u.to_string()
                }
            }
            gltf::buffer::Source::Bin => "GLB binary chunk".to_string(),
        };
        let data = gltf::buffer::Data::from_source_and_blob(buffer.source(), Some(base), &mut blob).map_err(|e| SceneError::Buffer {
            path: path.to_path_buf(),
            buffer: buffer.index(),
            uri: uri.clone(),
            message: e.to_string(),
        })?;
        if data.len() < buffer.length() {
            return Err(SceneError::Buffer {
                path: path.to_path_buf(),
                buffer: buffer.index(),
                uri,
                message: format!("{} bytes, but the file declares {}", data.len(), buffer.length()),
            });
        }
        buffers.push(data);
    }
    for view in gltf.document.views() {
        let len = buffers[view.buffer().index()].len();
        if view.offset() + view.length() > len {
            return Err(parse_err(format!(
                "bufferView {} ends at byte {} but buffer {} has {len} bytes",
                view.index(),
                view.offset() + view.length(),
                view.buffer().index()
            )));
        }
    }
    for acc in gltf.document.accessors() {
        if let Some(view) = acc.view() {
            let elem = acc.size();
            let stride = view.stride().unwrap_or(elem);
            let need = acc.offset() + if acc.count() == 0 { 0 } else { stride * (acc.count() - 1) + elem };
            if need > view.length() {
                return Err(parse_err(format!("accessor {} needs {need} bytes but bufferView {} has {}", acc.index(), view.index(), view.length())));
            }
        }
    }
    Ok(buffers)
}

/// One triangle primitive as a mesh (unnamed), and how many triangles were dropped for
/// non-finite positions. Normals are generated where missing, tangents where a normal map
/// needs them and the file has none.
fn primitive_mesh(prim: &gltf::Primitive, buffers: &[gltf::buffer::Data], normal_mapped: bool) -> Result<(Mesh, usize), String> {
    check_accessor_types(prim)?;
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or_else(|| "has no POSITION attribute".to_string())?.collect();
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
    let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
    let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = triangle_list(prim.mode(), indices);
    for (what, len) in [("NORMAL", normals.as_ref().map(Vec::len)), ("TEXCOORD_0", uvs.as_ref().map(Vec::len)), ("TANGENT", tangents.as_ref().map(Vec::len))] {
        if let Some(len) = len {
            if len != positions.len() {
                return Err(format!("{what} has {len} elements but POSITION has {}", positions.len()));
            }
        }
    }
    if !indices.len().is_multiple_of(3) {
        return Err(format!("{} indices is not a multiple of 3", indices.len()));
    }
    if let Some((i, bad)) = indices.iter().enumerate().find(|(_, v)| **v as usize >= positions.len()) {
        return Err(format!("index {bad} (at position {i}) is out of range: the primitive has {} vertices", positions.len()));
    }
    // Drop triangles with non-finite positions.
    let finite = |v: u32| positions[v as usize].iter().all(|c| c.is_finite());
    let mut kept = Vec::with_capacity(indices.len());
    let mut dropped = 0;
    for tri in indices.chunks_exact(3) {
        if tri.iter().all(|v| finite(*v)) {
            kept.extend_from_slice(tri);
        } else {
            dropped += 1;
        }
    }
    let mut vertices: Vec<Vertex> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| Vertex {
            position: if p.iter().all(|c| c.is_finite()) { *p } else { [0.0; 3] },
            normal: normals.as_ref().map(|n| n[i]).unwrap_or([0.0, 0.0, 0.0]),
            uv: uvs.as_ref().map(|u| u[i]).unwrap_or([0.0, 0.0]),
        })
        .collect();
    if normals.is_none() {
        generate_normals(&mut vertices, &kept);
    }
    for v in vertices.iter_mut() {
        let n = Vec3::from(v.normal);
        v.normal = if n.is_finite() && n.length_squared() > 1e-20 { n.normalize().into() } else { [0.0, 1.0, 0.0] };
        if !v.uv.iter().all(|c| c.is_finite()) {
            v.uv = [0.0, 0.0];
        }
    }
    let tangents = match tangents {
        Some(t) => Some(t),
        None if normal_mapped => Some(generate_tangents(&vertices, &kept)),
        None => None,
    };
    let extras = vertex_extras(&reader, positions.len())?;
    Ok((Mesh { name: String::new(), vertices, indices: kept, tangents, extras }, dropped))
}

/// The primitive's colours (`COLOR_0`, any component type, rgb or rgba, in linear space) and
/// second texture coordinates (`TEXCOORD_1`), where it has either; non-finite values become
/// white and 0.
fn vertex_extras<'a, 's, F>(reader: &gltf::mesh::Reader<'a, 's, F>, count: usize) -> Result<Option<Vec<VertexExtra>>, String>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let colors: Option<Vec<[f32; 4]>> = reader.read_colors(0).map(|c| c.into_rgba_f32().collect());
    let uv1: Option<Vec<[f32; 2]>> = reader.read_tex_coords(1).map(|t| t.into_f32().collect());
    if colors.is_none() && uv1.is_none() {
        return Ok(None);
    }
    for (what, len) in [("COLOR_0", colors.as_ref().map(Vec::len)), ("TEXCOORD_1", uv1.as_ref().map(Vec::len))] {
        if let Some(len) = len.filter(|l| *l != count) {
            return Err(format!("{what} has {len} elements but POSITION has {count}"));
        }
    }
    let finite_or = |v: f32, default: f32| if v.is_finite() { v } else { default };
    Ok(Some(
        (0..count)
            .map(|i| VertexExtra {
                uv1: uv1.as_ref().map_or([0.0; 2], |u| u[i].map(|c| finite_or(c, 0.0))),
                color: colors.as_ref().map_or([1.0; 4], |c| c[i].map(|c| finite_or(c, 1.0))),
                _pad: [0.0; 2],
            })
            .collect(),
    ))
}

/// Loads each image once and fills material texture slots, with the slot's fallback where an
/// image cannot be loaded (see [`TextureSlot::fallback`]).
struct TextureLoader<'a> {
    /// The file (its JSON for `KHR_texture_transform`, which the `gltf` crate does not read on
    /// every slot).
    source: Source<'a>,
    /// Whether to load textures at all (the active graph samples some).
    load: bool,
    textures: Vec<TextureImage>,
    /// Per image: its texture, or why it could not be loaded.
    loaded: HashMap<usize, Result<usize, String>>,
    /// Per image that could not be loaded: its magenta checker (made for base-colour slots).
    checker: HashMap<usize, usize>,
}

impl TextureLoader<'_> {
    fn material(&mut self, m: &gltf::Material, report: &mut ImportReport) -> Material {
        let name = material_name(m);
        let pbr = m.pbr_metallic_roughness();
        let mut mat = Material::diffuse(m.name().unwrap_or("material"), pbr.base_color_factor(), None);
        mat.metallic = pbr.metallic_factor();
        mat.roughness = pbr.roughness_factor();
        mat.normal_scale = m.normal_texture().map_or(mat.normal_scale, |n| n.scale());
        mat.occlusion_strength = m.occlusion_texture().map_or(mat.occlusion_strength, |o| o.strength());
        let strength = m.emissive_strength().unwrap_or(1.0);
        mat.emissive = m.emissive_factor().map(|c| c * strength);
        let (doc, raw) = (self.source.doc, self.source.raw);
        let material_json = m.index().map_or(&Value::Null, |i| &raw["materials"][i]);
        mat.lobes = material_lobes(material_json);
        for (slot, texture, tex_coord) in material_slots(m).into_iter().chain(lobe_slots(doc, material_json)) {
            let transform = &notes::slot_json(material_json, slot)["extensions"]["KHR_texture_transform"];
            // The transform's texCoord, where it has one, replaces the slot's.
            let set = transform["texCoord"].as_u64().map_or(tex_coord, |n| n as u32);
            mat.sampling[slot as usize] = SlotSampling { tex_coord: if set <= 1 { set } else { 0 }, ..slot_sampling(&texture, transform) };
            let fallbacks = report.texture_fallbacks.len();
            let t = self.slot(&name, slot, texture, report);
            fill_slot(&mut mat, slot, t, report.texture_fallbacks.len() > fallbacks);
        }
        mat.alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        mat.double_sided = m.double_sided();
        mat.unlit = m.unlit();
        mat
    }

    /// The texture for one slot: the image's, the magenta checker for a base-colour slot
    /// whose image cannot be loaded, or `None` (other slots then, or textures not loaded).
    fn slot(&mut self, material: &str, slot: TextureSlot, tex: gltf::Texture, report: &mut ImportReport) -> Option<usize> {
        if !self.load {
            report.textures_not_loaded += 1;
            return None;
        }
        let image = tex.source();
        let reason = match self.image(&image, report) {
            Ok(t) => return Some(t),
            Err(reason) => reason,
        };
        let name = image_name(self.source.doc, &image);
        report.warn(format!(
            "{}: material {material} {} texture: image `{name}` {reason}; fallback: {}",
            self.source.path.display(),
            slot.name(),
            slot.fallback()
        ));
        report.texture_fallbacks.push(TextureFallback { material: material.to_string(), slot, image: name.clone(), reason });
        if slot != TextureSlot::BaseColor {
            return None;
        }
        let textures = &mut self.textures;
        Some(*self.checker.entry(image.index()).or_insert_with(|| {
            textures.push(fallback_texture(&name));
            textures.len() - 1
        }))
    }

    /// The texture of `image`, loaded the first time; or why it cannot be loaded.
    fn image(&mut self, image: &gltf::Image, report: &mut ImportReport) -> Result<usize, String> {
        if let Some(r) = self.loaded.get(&image.index()) {
            return r.clone();
        }
        let name = image_name(self.source.doc, image);
        // glTF requires a uri or a bufferView with a mimeType; `Image::source` unwraps them.
        let json = self.source.doc.as_json().images.get(image.index());
        let result = if !json.is_some_and(|j| j.uri.is_some() || j.buffer_view.is_some() && j.mime_type.is_some()) {
            Err("has neither a uri nor a bufferView with a mimeType".to_string())
        } else {
            match gltf::image::Data::from_source(image.source(), Some(self.source.base), self.source.buffers) {
                Ok(data) => {
                    use gltf::image::Format as F;
                    if matches!(data.format, F::R16 | F::R16G16 | F::R16G16B16 | F::R16G16B16A16) {
                        report.approximated.push(format!("image `{name}`: 16-bit channels rounded to 8 bits (textures are stored as RGBA8)"));
                    }
                    if matches!(data.format, F::R32G32B32FLOAT | F::R32G32B32A32FLOAT) {
                        report.approximated.push(format!("image `{name}`: float channels clamped to 0..1 and rounded to 8 bits"));
                    }
                    to_rgba8(&name, &data).map_err(|why| format!("has {why}"))
                }
                Err(e) => Err(format!("cannot be loaded ({e})")),
            }
        };
        let result = result.map(|img| {
            self.textures.push(img);
            self.textures.len() - 1
        });
        if result.is_err() {
            report.missing_images += 1;
        }
        self.loaded.insert(image.index(), result.clone());
        result
    }
}

/// Puts texture `t` in `slot` of `mat`; `fell_back`: its image could not be loaded.
fn fill_slot(mat: &mut Material, slot: TextureSlot, t: Option<usize>, fell_back: bool) {
    match slot {
        TextureSlot::BaseColor => mat.texture = t,
        TextureSlot::MetallicRoughness => mat.metallic_roughness_texture = t,
        TextureSlot::Normal => mat.normal_texture = t,
        TextureSlot::Occlusion => mat.occlusion_texture = t,
        TextureSlot::Emissive => {
            mat.emissive_texture = t;
            // An emissive image that cannot be loaded means no emission at all.
            if fell_back {
                mat.emissive = [0.0; 3];
            }
        }
        lobe => mat.lobes.textures[lobe as usize - 5] = t,
    }
}

/// How a slot samples texture `tex`: the texture's sampler and the slot's
/// `KHR_texture_transform` (`transform`, its JSON; `Null` without one). A transform with
/// numbers that are not finite is left out.
fn slot_sampling(tex: &gltf::Texture, transform: &Value) -> SlotSampling {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let sampler = tex.sampler();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
    };
    let min = sampler.min_filter();
    let mipmaps = match min {
        Some(MinFilter::Nearest | MinFilter::Linear) => Mipmaps::None,
        Some(MinFilter::NearestMipmapNearest | MinFilter::LinearMipmapNearest) => Mipmaps::Nearest,
        _ => Mipmaps::Linear,
    };
    SlotSampling {
        wrap_s: wrap(sampler.wrap_s()),
        wrap_t: wrap(sampler.wrap_t()),
        mag_nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
        min_nearest: matches!(min, Some(MinFilter::Nearest | MinFilter::NearestMipmapNearest | MinFilter::NearestMipmapLinear)),
        mipmaps,
        tex_coord: 0,
        transform: uv_transform(transform),
    }
}

/// The rows of `KHR_texture_transform`'s matrix, translation x rotation x scale (`None` without
/// the extension, or with numbers that are not finite).
fn uv_transform(json: &Value) -> Option<[[f32; 3]; 2]> {
    if !json.is_object() {
        return None;
    }
    let pair = |key: &str, default: f64| [0, 1].map(|k| json[key][k].as_f64().unwrap_or(default));
    let [ox, oy] = pair("offset", 0.0);
    let [sx, sy] = pair("scale", 1.0);
    let (sin, cos) = json["rotation"].as_f64().unwrap_or(0.0).sin_cos();
    let rows = [[sx * cos, sy * sin, ox], [-sx * sin, sy * cos, oy]].map(|r| r.map(|v| v as f32));
    rows.iter().flatten().all(|v| v.is_finite()).then_some(rows)
}

/// A material as messages name it: "`name`" or "3" (its index).
fn material_name(m: &gltf::Material) -> String {
    match (m.name(), m.index()) {
        (Some(n), _) => format!("`{n}`"),
        (None, Some(i)) => i.to_string(),
        (None, None) => "default".into(),
    }
}

/// An image as messages name it: its name, its file, or "image N".
fn image_name(doc: &gltf::Document, image: &gltf::Image) -> String {
    image.name().map(str::to_string).unwrap_or_else(|| match doc.as_json().images.get(image.index()).and_then(|j| j.uri.as_deref()) {
        Some(uri) if !uri.starts_with("data:") => uri.to_string(),
        _ => format!("image {}", image.index()),
    })
}

/// The texture infos of a material's five slots, with the slot each fills.
fn material_slots<'a>(m: &gltf::Material<'a>) -> Vec<(TextureSlot, gltf::Texture<'a>, u32)> {
    let pbr = m.pbr_metallic_roughness();
    let mut out = Vec::new();
    if let Some(t) = pbr.base_color_texture() {
        out.push((TextureSlot::BaseColor, t.texture(), t.tex_coord()));
    }
    if let Some(t) = pbr.metallic_roughness_texture() {
        out.push((TextureSlot::MetallicRoughness, t.texture(), t.tex_coord()));
    }
    if let Some(t) = m.normal_texture() {
        out.push((TextureSlot::Normal, t.texture(), t.tex_coord()));
    }
    if let Some(t) = m.occlusion_texture() {
        out.push((TextureSlot::Occlusion, t.texture(), t.tex_coord()));
    }
    if let Some(t) = m.emissive_texture() {
        out.push((TextureSlot::Emissive, t.texture(), t.tex_coord()));
    }
    out
}

/// The lobe extensions' texture infos of material `m` (its JSON `json`), with the slot each
/// fills; an index naming no texture is left out (the validator's error, not drawn).
fn lobe_slots<'a>(doc: &'a gltf::Document, json: &Value) -> Vec<(TextureSlot, gltf::Texture<'a>, u32)> {
    TextureSlot::ALL[5..]
        .iter()
        .filter_map(|&slot| {
            let info = notes::slot_json(json, slot);
            let texture = doc.textures().nth(info["index"].as_u64()? as usize)?;
            Some((slot, texture, info["texCoord"].as_u64().unwrap_or(0) as u32))
        })
        .collect()
}

/// Distinct images the materials' texture slots use.
fn images_used(doc: &gltf::Document, raw: &Value) -> usize {
    doc.materials()
        .flat_map(|m| {
            let json = m.index().map_or(&Value::Null, |i| &raw["materials"][i]);
            material_slots(&m).into_iter().chain(lobe_slots(doc, json)).map(|(_, t, _)| t.source().index()).collect::<Vec<_>>()
        })
        .collect::<BTreeSet<_>>()
        .len()
}

/// What the node hierarchy places: mesh instances, lights, and cameras (with their node's
/// world transform), the last two in the order of their nodes in the file.
struct Placed<'a> {
    instances: Vec<Instance>,
    /// Per instance, the node that places it.
    instance_nodes: Vec<usize>,
    lights: Vec<PunctualLight>,
    cameras: Vec<(gltf::Node<'a>, gltf::Camera<'a>, Mat4)>,
}

/// The root nodes of the scene to draw: `asked` (an index or a name), else the file's default
/// scene, else its first, else every node of a file without scenes; the file's scenes are
/// listed in `report.scenes`.
fn scene_roots<'a>(path: &Path, doc: &'a gltf::Document, asked: Option<&str>, report: &mut ImportReport) -> Result<Vec<gltf::Node<'a>>, SceneError> {
    let label = |s: &gltf::Scene| format!("{} `{}`", s.index(), s.name().unwrap_or("unnamed"));
    let chosen = match asked {
        Some(a) => Some(doc.scenes().find(|s| a.parse::<usize>().ok() == Some(s.index()) || s.name() == Some(a)).ok_or_else(|| SceneError::NoSuchScene {
            path: path.to_path_buf(),
            asked: a.to_string(),
            scenes: if doc.scenes().len() == 0 { "none".into() } else { doc.scenes().map(|s| label(&s)).collect::<Vec<_>>().join(", ") },
        })?),
        None => doc.default_scene().or_else(|| doc.scenes().next()),
    };
    let default = doc.default_scene().map(|s| s.index());
    report.scenes = doc
        .scenes()
        .map(|s| {
            let drawn = chosen.as_ref().is_some_and(|c| c.index() == s.index());
            let tags: Vec<&str> = [drawn.then_some("drawn"), (default == Some(s.index())).then_some("the file's default")].into_iter().flatten().collect();
            format!("{} {} nodes{}", label(&s), s.nodes().len(), if tags.is_empty() { String::new() } else { format!(" ({})", tags.join(", ")) })
        })
        .collect();
    Ok(match chosen {
        Some(s) => s.nodes().collect(),
        None => doc.nodes().collect(),
    })
}

/// Walks the node hierarchy from `roots`.
fn walk_nodes<'a>(
    path: &Path,
    roots: Vec<gltf::Node<'a>>,
    primitives_of_mesh: &[Vec<(usize, usize)>],
    report: &mut ImportReport,
) -> Result<Placed<'a>, SceneError> {
    let mut instances = Vec::new();
    let mut instance_nodes = Vec::new();
    let mut lights = Vec::new();
    let mut cameras = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(SceneError::Parse { path: path.to_path_buf(), message: "node hierarchy deeper than 256 levels (a cycle?)".into() });
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            report.warn(format!("{}: node {} has a non-finite transform; skipped", path.display(), node.index()));
            continue;
        }
        if let Some(mesh) = node.mesh() {
            for (m, mat) in &primitives_of_mesh[mesh.index()] {
                instances.push(Instance { mesh: *m, material: *mat, transform: world });
                instance_nodes.push(node.index());
            }
        }
        if let Some(light) = node.light() {
            lights.push((node.index(), punctual_light(&node, &light, world)));
        }
        if let Some(camera) = node.camera() {
            cameras.push((node.clone(), camera, world));
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    lights.sort_by_key(|(n, _)| *n);
    cameras.sort_by_key(|(n, _, _)| n.index());
    Ok(Placed { instances, instance_nodes, lights: lights.into_iter().map(|(_, l)| l).collect(), cameras })
}

/// A `KHR_lights_punctual` light in world space: at the node's origin, shining along its -Z.
fn punctual_light(node: &gltf::Node, light: &gltf::khr_lights_punctual::Light, world: Mat4) -> PunctualLight {
    use gltf::khr_lights_punctual::Kind;
    let kind = match light.kind() {
        Kind::Directional => LightKind::Directional,
        Kind::Point => LightKind::Point { range: light.range() },
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            LightKind::Spot { range: light.range(), inner_cone: inner_cone_angle, outer_cone: outer_cone_angle }
        }
    };
    let name = light.name().or(node.name()).map(str::to_string).unwrap_or_else(|| format!("light{}", light.index()));
    PunctualLight {
        name,
        kind,
        position: world.transform_point3(Vec3::ZERO),
        direction: world.transform_vector3(Vec3::NEG_Z).normalize_or(Vec3::NEG_Z),
        color: Vec3::from(light.color()),
        intensity: light.intensity(),
    }
}

/// The file's cameras (perspective and orthographic) as named presets (camera name, node name
/// or `camera{N}`, made unique), in world space. A camera's near plane is the file's `znear`;
/// its far plane the file's `zfar`, or where none is given (perspective's infinite far plane)
/// just past the scene's far side. Ones with unusable numbers are skipped with a warning.
fn file_cameras(path: &Path, cameras: &[(gltf::Node, gltf::Camera, Mat4)], bounds: Bounds, report: &mut ImportReport) -> Vec<(String, Camera)> {
    let mut presets: Vec<(String, Camera)> = Vec::new();
    for (node, camera, world) in cameras {
        let base = camera.name().or(node.name()).map(str::to_string).unwrap_or_else(|| format!("camera{}", camera.index()));
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y);
        let up = (up - forward * forward.dot(up)).normalize_or_zero();
        let fitted = Camera { position, ..Camera::default() }.fit_clip_planes(bounds);
        let to_center = if bounds.is_empty() { 1.0 } else { position.distance(bounds.center()) };
        let (fov_y, near, far, orthographic, aspect_ratio) = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let far = p.zfar().unwrap_or(fitted.far.max(p.znear() * 2.0));
                if p.zfar().is_none() {
                    report
                        .approximated
                        .push(format!("camera `{base}`: infinite far plane drawn with a far plane at {far:.3} (just past the scene's far side)"));
                }
                (p.yfov(), p.znear(), far, None, p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0))
            }
            gltf::camera::Projection::Orthographic(o) => {
                let aspect = (o.xmag() / o.ymag()).abs();
                (Camera::default().fov_y, o.znear(), o.zfar(), Some(o.ymag().abs()), (aspect.is_finite() && aspect > 0.0).then_some(aspect))
            }
        };
        let usable = fov_y.is_finite() && fov_y > 0.0 && fov_y < std::f32::consts::PI && near.is_finite() && near >= 0.0 && far.is_finite() && far > near;
        let ortho_usable = orthographic.is_none_or(|h| h.is_finite() && h > 0.0);
        if !usable || !ortho_usable || forward == Vec3::ZERO || up == Vec3::ZERO || (orthographic.is_none() && near == 0.0) {
            report.warn(format!("{}: camera `{base}` has an unusable yfov, xmag/ymag, znear, zfar or transform; skipped", path.display()));
            continue;
        }
        let name = unique_name(&presets, &base);
        let target = position + forward * to_center.max(near);
        presets.push((name, Camera { position, target, up, fov_y, near, far, orthographic, aspect_ratio }));
    }
    presets
}

/// `base`, or `base-2`, `base-3`, ... : the first that no preset of `presets` is called.
fn unique_name(presets: &[(String, Camera)], base: &str) -> String {
    let mut name = base.to_string();
    let mut n = 2;
    while presets.iter().any(|(p, _)| *p == name) {
        name = format!("{base}-{n}");
        n += 1;
    }
    name
}

/// The file's cameras first (the first of them is the default view), then the built-in
/// `front`, `top` and `side` presets framing the scene's bounds over its whole animation (the
/// default view of a file without cameras: `front`); a file camera of the same name takes a
/// built-in preset's place (so a file raygraph exported reads back with the same presets).
fn camera_presets(scene: &Scene, file: Vec<(String, Camera)>) -> (Camera, Vec<(String, Camera)>) {
    let bounds = animated_bounds(scene);
    let mut presets = file;
    let default = presets.first().map(|(_, c)| *c).unwrap_or_else(|| Camera::framing(bounds));
    for (name, camera) in Camera::presets_for(bounds) {
        if !presets.iter().any(|(n, _)| *n == name) {
            presets.push((name, camera));
        }
    }
    (default, presets)
}

/// The scene's bounds over every clip: the rest pose's, grown by the pose at 16 times spread
/// over each clip (the deforming meshes deformed on the CPU).
pub fn animated_bounds(scene: &Scene) -> Bounds {
    let mut bounds = scene.bounds();
    let Some(rig) = scene.rig.clone().filter(|r| r.is_animated()) else { return bounds };
    let mut posed = scene.clone();
    for (clip, anim) in rig.animations.iter().enumerate() {
        for k in 0..16 {
            posed.pose(Some(clip), anim.duration * k as f32 / 16.0);
            let b = posed.bounds();
            if !b.is_empty() {
                bounds = bounds.union(&b);
            }
        }
    }
    bounds
}

/// What a file uses that raygraph approximates or ignores, per extension, material, texture,
/// mesh and document, as lines of [`ImportReport::approximated`] and `ignored_features`.
mod notes {
    use super::{lobe_slots, material_name, material_slots, ImportReport, TextureSlot, SUPPORTED_EXTENSIONS};
    use gltf::json::Value;
    use std::collections::{BTreeMap, BTreeSet};

    pub(super) fn collect(doc: &gltf::Document, raw: &Value, report: &mut ImportReport) {
        for ext in doc.extensions_used() {
            if !SUPPORTED_EXTENSIONS.contains(&ext) {
                report.ignored_features.push(format!("extension {ext} (not read)"));
            }
        }
        for m in doc.materials() {
            material(doc, &m, raw, report);
        }
        meshes(doc, report);
    }

    /// The JSON of `slot`'s texture info in material `m`.
    pub(super) fn slot_json(m: &Value, slot: TextureSlot) -> &Value {
        slot.json_path().iter().fold(m, |v, key| &v[*key])
    }

    fn extension_names(v: &Value) -> Vec<&str> {
        v["extensions"].as_object().map(|o| o.keys().map(String::as_str).collect()).unwrap_or_default()
    }

    fn material(doc: &gltf::Document, m: &gltf::Material, raw: &Value, report: &mut ImportReport) {
        let name = material_name(m);
        let json = m.index().map(|i| &raw["materials"][i]).unwrap_or(&Value::Null);
        if extension_names(json).contains(&"KHR_materials_unlit") {
            let unread: Vec<&str> = [
                (m.pbr_metallic_roughness().metallic_roughness_texture().is_some(), "metallic-roughness"),
                (m.normal_texture().is_some(), "normal"),
                (m.occlusion_texture().is_some(), "occlusion"),
                (m.emissive_texture().is_some() || m.emissive_factor() != [0.0; 3], "emission"),
            ]
            .into_iter()
            .filter_map(|(has, what)| has.then_some(what))
            .collect();
            if !unread.is_empty() {
                report.ignored_features.push(format!("material {name}: {} (KHR_materials_unlit draws the base colour only)", unread.join(", ")));
            }
        }
        if m.alpha_mode() == gltf::material::AlphaMode::Blend {
            report.approximated.push(format!(
                "material {name}: alphaMode BLEND is blended in hybrid and full RT (up to 8 surfaces a ray, in depth order), in raster after the opaque surfaces with instances sorted back to front (not the triangles of one mesh), screen-door in raster shadow maps"
            ));
        }
        for ext in extension_names(json).into_iter().filter(|e| !SUPPORTED_EXTENSIONS.contains(e)) {
            report.ignored_features.push(format!("material {name}: {ext}"));
        }
        for slot in TextureSlot::ALL[5..].iter().filter(|s| !slot_json(json, **s).is_null()) {
            let index = slot_json(json, *slot)["index"].as_u64();
            if index.is_none_or(|i| i as usize >= doc.textures().len()) {
                report.ignored_features.push(format!("material {name} {} texture: its index names no texture of the file", slot.name()));
            }
        }
        for (slot, _, tex_coord) in material_slots(m).into_iter().chain(lobe_slots(doc, json)) {
            if tex_coord > 1 {
                report.ignored_features.push(format!("material {name} {} texture: texCoord {tex_coord} (TEXCOORD_0 is read instead)", slot.name()));
            }
            for ext in extension_names(slot_json(json, slot)).into_iter().filter(|e| !SUPPORTED_EXTENSIONS.contains(e)) {
                report.ignored_features.push(format!("material {name} {} texture: {ext}", slot.name()));
            }
            if let Some(n) = slot_json(json, slot)["extensions"]["KHR_texture_transform"]["texCoord"].as_u64().filter(|n| *n > 1) {
                report
                    .ignored_features
                    .push(format!("material {name} {} texture: KHR_texture_transform texCoord {n} (TEXCOORD_0 is read instead)", slot.name()));
            }
        }
    }

    fn meshes(doc: &gltf::Document, report: &mut ImportReport) {
        let (mut colours, mut uv_sets) = (Vec::new(), BTreeMap::<u32, Vec<String>>::new());
        for mesh in doc.meshes() {
            let name = mesh.name().map(|n| format!("`{n}`")).unwrap_or_else(|| mesh.index().to_string());
            if mesh.primitives().any(|p| p.attributes().any(|(s, _)| matches!(s, gltf::Semantic::Colors(1..)))) {
                colours.push(name.clone());
            }
            let sets: BTreeSet<u32> = mesh
                .primitives()
                .flat_map(|p| p.attributes().filter_map(|(s, _)| if let gltf::Semantic::TexCoords(n @ 2..) = s { Some(n) } else { None }))
                .collect();
            for n in sets {
                uv_sets.entry(n).or_default().push(name.clone());
            }
        }
        if !colours.is_empty() {
            report.ignored_features.push(format!("vertex colours past COLOR_0 on mesh {}", colours.join(", ")));
        }
        for (n, meshes) in uv_sets {
            report.ignored_features.push(format!("attribute TEXCOORD_{n} on mesh {} (TEXCOORD_0 and TEXCOORD_1 are read)", meshes.join(", ")));
        }
    }
}

/// Strips and fans as a triangle list (counter-clockwise kept: every other strip triangle
/// is flipped, as glTF specifies).
fn triangle_list(mode: gltf::mesh::Mode, i: Vec<u32>) -> Vec<u32> {
    match mode {
        gltf::mesh::Mode::TriangleStrip => {
            (2..i.len()).flat_map(|k| if k % 2 == 0 { [i[k - 2], i[k - 1], i[k]] } else { [i[k - 1], i[k - 2], i[k]] }).collect()
        }
        gltf::mesh::Mode::TriangleFan => (2..i.len()).flat_map(|k| [i[0], i[k - 1], i[k]]).collect(),
        _ => i,
    }
}

/// An image of any pixel format glTF images decode to as RGBA8: grey (L) spread to rgb, grey
/// and alpha (LA) as grey rgb with that alpha, missing alpha opaque. 16-bit channels (stored
/// native-endian) are rounded to 8 bits, float channels clamped to 0..1 and scaled.
fn to_rgba8(name: &str, data: &gltf::image::Data) -> Result<TextureImage, String> {
    use gltf::image::Format as F;
    let (w, h) = (data.width, data.height);
    let n = (w * h) as usize;
    let (channels, bytes_per_channel) = match data.format {
        F::R8 => (1, 1),
        F::R8G8 => (2, 1),
        F::R8G8B8 => (3, 1),
        F::R8G8B8A8 => (4, 1),
        F::R16 => (1, 2),
        F::R16G16 => (2, 2),
        F::R16G16B16 => (3, 2),
        F::R16G16B16A16 => (4, 2),
        F::R32G32B32FLOAT => (3, 4),
        F::R32G32B32A32FLOAT => (4, 4),
    };
    let texel_bytes = channels * bytes_per_channel;
    if data.pixels.len() < n * texel_bytes || n == 0 {
        return Err("too little pixel data".into());
    }
    let channel = |b: &[u8]| -> u8 {
        match bytes_per_channel {
            1 => b[0],
            2 => ((u16::from_ne_bytes([b[0], b[1]]) as u32 * 255 + 32767) / 65535) as u8,
            _ => (f32::from_ne_bytes([b[0], b[1], b[2], b[3]]).clamp(0.0, 1.0) * 255.0 + 0.5) as u8,
        }
    };
    let mut rgba = Vec::with_capacity(n * 4);
    for texel in data.pixels[..n * texel_bytes].chunks_exact(texel_bytes) {
        let c: Vec<u8> = texel.chunks_exact(bytes_per_channel).map(channel).collect();
        let out = match channels {
            1 => [c[0], c[0], c[0], 255],
            2 => [c[0], c[0], c[0], c[1]],
            3 => [c[0], c[1], c[2], 255],
            _ => [c[0], c[1], c[2], c[3]],
        };
        rgba.extend_from_slice(&out);
    }
    Ok(TextureImage { name: name.into(), width: w, height: h, rgba: rgba.into() })
}

/// Area-weighted vertex normals.
pub(crate) fn generate_normals(vertices: &mut [Vertex], indices: &[u32]) {
    let mut acc = vec![Vec3::ZERO; vertices.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(vertices[i as usize].position));
        let n = (b - a).cross(c - a);
        for i in t {
            acc[*i as usize] += n;
        }
    }
    for (v, n) in vertices.iter_mut().zip(acc) {
        v.normal = n.normalize_or(Vec3::Y).into();
    }
}

/// Per-vertex tangents from UV gradients (accumulated per triangle, Gram-Schmidt against the
/// normal, handedness in w).
pub(crate) fn generate_tangents(vertices: &[Vertex], indices: &[u32]) -> Vec<[f32; 4]> {
    let mut tan = vec![Vec3::ZERO; vertices.len()];
    let mut bit = vec![Vec3::ZERO; vertices.len()];
    for t in indices.chunks_exact(3) {
        let v = [t[0], t[1], t[2]].map(|i| vertices[i as usize]);
        let (p0, p1, p2) = (Vec3::from(v[0].position), Vec3::from(v[1].position), Vec3::from(v[2].position));
        let (d1, d2) = (p1 - p0, p2 - p0);
        let (s1, t1) = (v[1].uv[0] - v[0].uv[0], v[1].uv[1] - v[0].uv[1]);
        let (s2, t2) = (v[2].uv[0] - v[0].uv[0], v[2].uv[1] - v[0].uv[1]);
        let det = s1 * t2 - s2 * t1;
        if det.abs() < 1e-20 {
            continue;
        }
        let r = 1.0 / det;
        let sdir = (d1 * t2 - d2 * t1) * r;
        let tdir = (d2 * s1 - d1 * s2) * r;
        for i in t {
            tan[*i as usize] += sdir;
            bit[*i as usize] += tdir;
        }
    }
    vertices
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let n = Vec3::from(v.normal);
            let t = (tan[i] - n * n.dot(tan[i])).normalize_or(n.any_orthonormal_vector());
            let w = if n.cross(t).dot(bit[i]) < 0.0 { -1.0 } else { 1.0 };
            [t.x, t.y, t.z, w]
        })
        .collect()
}

/// Triangles whose area is zero (in f32).
pub(crate) fn count_degenerate(vertices: &[Vertex], indices: &[u32]) -> usize {
    indices
        .chunks_exact(3)
        .filter(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(vertices[i as usize].position));
            (b - a).cross(c - a).length_squared() == 0.0
        })
        .count()
}
