//! glTF 2.0 import (`.gltf` with external or embedded buffers, `.glb`): node hierarchy with
//! transforms, meshes and primitives, PBR metallic-roughness materials and images. Bad input
//! becomes a [`SceneError`] naming the file, or a counted warning where loading can go on.

use super::{AlphaMode, Camera, Instance, Light, Material, Mesh, Scene, TextureImage, Vertex};
use glam::{Mat4, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: not a readable glTF file: {message}\n  help: give a .gltf or .glb file (glTF 2.0)")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: buffer {buffer} ({uri}) cannot be loaded: {message}\n  help: put the buffer file next to the .gltf or fix its uri")]
    Buffer { path: PathBuf, buffer: usize, uri: String, message: String },
    #[error("{path}: mesh `{mesh}` primitive {primitive}: {message}")]
    Primitive { path: PathBuf, mesh: String, primitive: usize, message: String },
    #[error("{path}: the file has no scene and no nodes to draw")]
    Empty { path: PathBuf },
    #[error("unknown scene `{0}`; built-in scenes are: {1}\n  help: give a built-in scene name or a .gltf/.glb path")]
    UnknownScene(String, String),
    #[error("could not write {path}: {message}")]
    Write { path: PathBuf, message: String },
}

/// What import noticed but could work around.
#[derive(Debug, Clone, Default)]
pub struct ImportReport {
    pub warnings: Vec<String>,
    /// Triangles dropped because a vertex position was NaN or infinite.
    pub non_finite_triangles: usize,
    /// Zero-area triangles (kept for drawing, left out of acceleration structures).
    pub degenerate_triangles: usize,
    /// Primitives skipped because their mode is not triangles.
    pub skipped_primitives: usize,
    /// Images that failed to load and were replaced by the fallback texture.
    pub missing_images: usize,
    /// glTF features in the file that raygraph does not use.
    pub ignored_features: Vec<String>,
    /// Texture references not loaded because the active graph samples no textures.
    pub textures_not_loaded: usize,
}

impl ImportReport {
    fn warn(&mut self, w: String) {
        log::warn!("{w}");
        self.warnings.push(w);
    }
}

/// A magenta/black checker that marks a texture that could not be loaded.
pub fn fallback_texture(name: &str) -> TextureImage {
    super::builtin::checker(&format!("missing: {name}"), 64, 8, [255, 0, 255], [0, 0, 0])
}

/// Loads a glTF or GLB file.
/// `gltf::Gltf::from_slice` with one check first: gltf-json 1.4's validator reads the accessor
/// a primitive's `POSITION` names without a bounds check, so a file naming a missing accessor
/// would panic inside it instead of failing validation.
fn parse_and_validate(bytes: &[u8]) -> Result<gltf::Gltf, String> {
    use gltf::json::validation::Validate;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| e.to_string())?;
    let root = gltf.document.as_json();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    return Err(format!(
                        "meshes[{m}].primitives[{p}].attributes: {} names accessor {}, but the file has {} accessors",
                        match semantic {
                            gltf::json::validation::Checked::Valid(s) => s.to_string(),
                            gltf::json::validation::Checked::Invalid => "an unknown attribute".to_string(),
                        },
                        accessor.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| errors.push((path(), error)));
    if !errors.is_empty() {
        return Err(gltf::Error::Validation(errors).to_string());
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
            S::TexCoords(0) => check("the TEXCOORD_0", acc, &[T::F32, T::U8, T::U16], D::Vec2)?,
            _ => {}
        }
    }
    Ok(())
}

pub fn load(path: &Path, options: &super::LoadOptions) -> Result<(Scene, ImportReport), SceneError> {
    let parse_err = |message: String| SceneError::Parse { path: path.to_path_buf(), message };
    let bytes = std::fs::read(path).map_err(|e| parse_err(e.to_string()))?;
    let gltf = parse_and_validate(&bytes).map_err(parse_err)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut report = ImportReport::default();

    // Buffers, each checked so the error names it.
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
    // Buffer views must lie inside their buffers before anything reads through them.
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

    for ext in gltf.document.extensions_used() {
        report.ignored_features.push(format!("extension {ext}"));
    }
    if gltf.document.animations().next().is_some() {
        report.ignored_features.push("animations".into());
    }
    if gltf.document.skins().next().is_some() {
        report.ignored_features.push("skins".into());
    }
    if gltf.document.cameras().next().is_some() {
        report.ignored_features.push("cameras (raygraph uses its own)".into());
    }

    // Images are loaded only when a material references them.
    let mut textures: Vec<TextureImage> = Vec::new();
    let mut texture_of_image: HashMap<usize, usize> = HashMap::new();
    let mut texture_index = |tex: gltf::Texture, report: &mut ImportReport, textures: &mut Vec<TextureImage>| -> usize {
        let image = tex.source();
        if let Some(t) = texture_of_image.get(&image.index()) {
            return *t;
        }
        // glTF requires a uri or a bufferView with a mimeType; `Image::source` unwraps them.
        let usable = gltf.document.as_json().images.get(image.index()).is_some_and(|j| j.uri.is_some() || j.buffer_view.is_some() && j.mime_type.is_some());
        if !usable {
            let name = image.name().map(str::to_string).unwrap_or_else(|| format!("image {}", image.index()));
            report.missing_images += 1;
            report.warn(format!("{}: image `{name}` has neither a uri nor a bufferView with a mimeType; using the fallback texture", path.display()));
            textures.push(fallback_texture(&name));
            texture_of_image.insert(image.index(), textures.len() - 1);
            return textures.len() - 1;
        }
        let name = image.name().map(str::to_string).unwrap_or_else(|| match image.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => uri.to_string(),
            _ => format!("image {}", image.index()),
        });
        let img = match gltf::image::Data::from_source(image.source(), Some(base), &buffers) {
            Ok(data) => to_rgba8(&name, &data).unwrap_or_else(|why| {
                report.missing_images += 1;
                report.warn(format!("{}: image `{name}` has {why}; using the fallback texture", path.display()));
                fallback_texture(&name)
            }),
            Err(e) => {
                report.missing_images += 1;
                report.warn(format!("{}: image `{name}` cannot be loaded ({e}); using the fallback texture", path.display()));
                fallback_texture(&name)
            }
        };
        textures.push(img);
        texture_of_image.insert(image.index(), textures.len() - 1);
        textures.len() - 1
    };

    let mut materials: Vec<Material> = Vec::new();
    let mut texture_index = |tex: gltf::Texture, report: &mut ImportReport, textures: &mut Vec<TextureImage>| -> Option<usize> {
        if options.textures {
            Some(texture_index(tex, report, textures))
        } else {
            report.textures_not_loaded += 1;
            None
        }
    };
    for m in gltf.document.materials() {
        let pbr = m.pbr_metallic_roughness();
        let mut mat = Material::diffuse(m.name().unwrap_or("material"), pbr.base_color_factor(), None);
        mat.texture = pbr.base_color_texture().and_then(|t| texture_index(t.texture(), &mut report, &mut textures));
        mat.metallic = pbr.metallic_factor();
        mat.roughness = pbr.roughness_factor();
        mat.metallic_roughness_texture = pbr.metallic_roughness_texture().and_then(|t| texture_index(t.texture(), &mut report, &mut textures));
        if let Some(n) = m.normal_texture() {
            mat.normal_scale = n.scale();
            mat.normal_texture = texture_index(n.texture(), &mut report, &mut textures);
        }
        mat.emissive = m.emissive_factor();
        mat.emissive_texture = m.emissive_texture().and_then(|t| texture_index(t.texture(), &mut report, &mut textures));
        mat.alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        mat.double_sided = m.double_sided();
        materials.push(mat);
    }
    let default_material = materials.len();
    materials.push(Material::diffuse("default", [0.8, 0.8, 0.8, 1.0], None));

    // Meshes: one raygraph mesh per glTF primitive.
    let mut meshes: Vec<Mesh> = Vec::new();
    let mut primitives_of_mesh: Vec<Vec<(usize, usize)>> = Vec::new(); // (mesh, material)
    for mesh in gltf.document.meshes() {
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
            check_accessor_types(&prim).map_err(prim_err)?;
            let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let positions: Vec<[f32; 3]> = reader.read_positions().ok_or_else(|| prim_err("has no POSITION attribute".into()))?.collect();
            let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
            let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
            let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let indices = triangle_list(mode, indices);
            for (what, len) in
                [("NORMAL", normals.as_ref().map(Vec::len)), ("TEXCOORD_0", uvs.as_ref().map(Vec::len)), ("TANGENT", tangents.as_ref().map(Vec::len))]
            {
                if let Some(len) = len {
                    if len != positions.len() {
                        return Err(prim_err(format!("{what} has {len} elements but POSITION has {}", positions.len())));
                    }
                }
            }
            if indices.len() % 3 != 0 {
                return Err(prim_err(format!("{} indices is not a multiple of 3", indices.len())));
            }
            if let Some((i, bad)) = indices.iter().enumerate().find(|(_, v)| **v as usize >= positions.len()) {
                return Err(prim_err(format!("index {bad} (at position {i}) is out of range: the primitive has {} vertices", positions.len())));
            }
            // Drop triangles with non-finite positions.
            let finite = |v: u32| positions[v as usize].iter().all(|c| c.is_finite());
            let mut kept = Vec::with_capacity(indices.len());
            for tri in indices.chunks_exact(3) {
                if tri.iter().all(|v| finite(*v)) {
                    kept.extend_from_slice(tri);
                } else {
                    report.non_finite_triangles += 1;
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
            report.degenerate_triangles += count_degenerate(&vertices, &kept);
            let material = prim.material().index().unwrap_or(default_material);
            let tangents = match tangents {
                Some(t) => Some(t),
                None if materials[material].normal_texture.is_some() => Some(generate_tangents(&vertices, &kept)),
                None => None,
            };
            meshes.push(Mesh { name: format!("{mesh_name}/{}", prim.index()), vertices, indices: kept, tangents });
            prims.push((meshes.len() - 1, material));
        }
        primitives_of_mesh.push(prims);
    }
    if report.non_finite_triangles > 0 {
        report.warn(format!("{}: dropped {} triangles with NaN or infinite positions", path.display(), report.non_finite_triangles));
    }
    if report.degenerate_triangles > 0 {
        report.warn(format!("{}: {} zero-area triangles (left out of acceleration structures)", path.display(), report.degenerate_triangles));
    }

    // Instances from the node hierarchy; one mesh under several nodes stays shared.
    let mut instances = Vec::new();
    let roots: Vec<gltf::Node> = match gltf.document.default_scene().or_else(|| gltf.document.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => gltf.document.nodes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(parse_err("node hierarchy deeper than 256 levels (a cycle?)".into()));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            report.warn(format!("{}: node {} has a non-finite transform; skipped", path.display(), node.index()));
            continue;
        }
        if let Some(mesh) = node.mesh() {
            for (m, mat) in &primitives_of_mesh[mesh.index()] {
                instances.push(Instance { mesh: *m, material: *mat, transform: world });
            }
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    if instances.is_empty() && meshes.is_empty() {
        return Err(SceneError::Empty { path: path.to_path_buf() });
    }
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    let mut scene = Scene {
        name,
        meshes,
        materials,
        instances,
        textures,
        camera: Camera::default(),
        presets: Vec::new(),
        light: Light::default(),
        point_light: None,
        lights: Vec::new(),
    };
    scene.camera = Camera::framing(scene.bounds());
    scene.presets = Camera::presets_for(scene.bounds());
    Ok((scene, report))
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

fn to_rgba8(name: &str, data: &gltf::image::Data) -> Result<TextureImage, String> {
    use gltf::image::Format as F;
    let (w, h) = (data.width, data.height);
    let n = (w * h) as usize;
    let px = &data.pixels;
    let channels = match data.format {
        F::R8 => 1,
        F::R8G8 => 2,
        F::R8G8B8 => 3,
        F::R8G8B8A8 => 4,
        F::R16 => 2,
        F::R16G16 => 4,
        F::R16G16B16 => 6,
        F::R16G16B16A16 => 8,
        other => return Err(format!("an unsupported pixel format {other:?}")),
    };
    if px.len() < n * channels || n == 0 {
        return Err("too little pixel data".into());
    }
    let mut rgba = Vec::with_capacity(n * 4);
    for i in 0..n {
        let p = &px[i * channels..(i + 1) * channels];
        let c = match data.format {
            F::R8 => [p[0], p[0], p[0], 255],
            F::R8G8 => [p[0], p[1], 0, 255],
            F::R8G8B8 => [p[0], p[1], p[2], 255],
            F::R8G8B8A8 => [p[0], p[1], p[2], p[3]],
            // 16-bit channels are little-endian; keep the high byte.
            F::R16 => [p[1], p[1], p[1], 255],
            F::R16G16 => [p[1], p[3], 0, 255],
            F::R16G16B16 => [p[1], p[3], p[5], 255],
            _ => [p[1], p[3], p[5], p[7]],
        };
        rgba.extend_from_slice(&c);
    }
    Ok(TextureImage { name: name.into(), width: w, height: h, rgba })
}

/// Area-weighted vertex normals.
pub fn generate_normals(vertices: &mut [Vertex], indices: &[u32]) {
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
pub fn generate_tangents(vertices: &[Vertex], indices: &[u32]) -> Vec<[f32; 4]> {
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
pub fn count_degenerate(vertices: &[Vertex], indices: &[u32]) -> usize {
    indices
        .chunks_exact(3)
        .filter(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(vertices[i as usize].position));
            (b - a).cross(c - a).length_squared() == 0.0
        })
        .count()
}
