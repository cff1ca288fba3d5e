//! The scene on the GPU ([`GpuScene`]): only the parts a plan reads ([`SceneUsage`]) are
//! uploaded: one vertex and one index buffer for all meshes, storage buffers of instance,
//! material, light and previous-transform records, and the textures (element or layer 0 plain
//! white), pooled where the device has binding arrays (one array texture per size and encoding,
//! `crate::scene::texture_pool`), else the layers of one mipmapped `TEXTURE_SIZE`² texture
//! array. Too many textures, or buffers larger than the device allows, are an error with the
//! numbers ([`SceneLimitError`]), never a panic.
//! Also the records' CPU side (`light_records`), what an upload depends on (`SceneContent`)
//! and the in-place rewrites of a frame.

use crate::runtime::environment_upload::GpuEnvironment;
use crate::scene::texture_pool::{data_textures, texture_ref, texture_refs, TexturePool, POOL_LAYERS, TEXTURE_REF_LAYER_BITS};
use crate::scene::usage::{SceneLimitError, SceneUsage};
use crate::scene::{AlphaMode, Bounds, Mesh, Scene, SlotSampling, TextureImage, Vertex, VertexExtra, TEXTURE_SLOTS};
use crate::uniforms::{
    InstanceUniforms, LightUniforms, MaterialUniforms, MATERIAL_ALPHA_BLEND, MATERIAL_ALPHA_MASK, MATERIAL_DOUBLE_SIDED, MATERIAL_LOBES, MATERIAL_SAMPLERS,
    MATERIAL_TRANSMISSION, MATERIAL_TRANSMISSION_TEXTURE, MATERIAL_UNLIT, MATERIAL_UV_TRANSFORM,
};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

/// One indexed draw per instance.
#[derive(Debug, Clone)]
pub(crate) struct Draw {
    /// The instance's mesh in the index buffer.
    pub(crate) indices: std::ops::Range<u32>,
    /// Added to each index: the mesh's first vertex.
    pub(crate) base_vertex: i32,
    /// The instance's index (`instance_index` in the shader).
    pub(crate) instance: u32,
    /// Centre of the mesh's bounds, object space (for ordering draws by distance).
    pub(crate) local_center: Vec3,
    /// The mesh's object-space bounds (a shadow slot's frustum culls the instances wholly
    /// outside it); `None` for a deforming mesh, whose vertices move, and an empty one.
    pub(crate) local_bounds: Option<Bounds>,
    /// The mesh has `local_bounds` and is closed and wound outwards (`scene::topology`); false
    /// when the plan does not ask (`SceneUsage::closed_meshes`).
    pub(crate) closed: bool,
}

/// The scene's textures as the graph's shaders bind them.
pub enum SceneTextures {
    /// One `texture_2d_array` of 256² layers (layer 0 white).
    Array {
        /// The array texture.
        texture: wgpu::Texture,
        /// Its view.
        view: wgpu::TextureView,
    },
    /// One 2D array texture per element of a `binding_array<texture_2d_array<f32>>`: the
    /// [`TexturePool`]'s arrays (element 0 starts with white), each at its textures' size with
    /// its own mip chain.
    Pooled {
        /// The array textures.
        textures: Vec<wgpu::Texture>,
        /// One view of each, of all its layers.
        views: Vec<wgpu::TextureView>,
    },
}

impl SceneTextures {
    /// Number of layers (textures + the white one) or of elements (pooled arrays).
    pub fn count(&self) -> u32 {
        match self {
            SceneTextures::Array { texture, .. } => texture.depth_or_array_layers(),
            SceneTextures::Pooled { views, .. } => views.len() as u32,
        }
    }
}

/// A scene on the GPU: the parts a plan reads ([`SceneUsage`]), uploaded.
pub struct GpuScene {
    /// Every mesh's vertices, one after another.
    vertices: Option<wgpu::Buffer>,
    /// Every mesh's indices, one after another.
    indices: Option<wgpu::Buffer>,
    /// Instance records (`scene_instances`).
    instances: Option<wgpu::Buffer>,
    /// Material records (`scene_materials`).
    materials: Option<wgpu::Buffer>,
    /// Per mesh: first index, base vertex, index count, where its extras start in the vertex
    /// buffer (`scene_meshes`; `MESH_NO_EXTRAS` without colours or second uvs).
    meshes: Option<wgpu::Buffer>,
    /// The material textures.
    textures: Option<SceneTextures>,
    /// `Scene::effective_lights()` as `LightUniforms` (`scene_lights`), rewritten every frame
    /// by `GpuScene::write_lights`.
    lights: Option<wgpu::Buffer>,
    /// The emissive triangles as lights (`scene_emitters`, `scene::emitters`).
    emitters: Option<wgpu::Buffer>,
    /// The environment map (`scene_environment*`; stand-ins without one), shared with the
    /// scene uploaded before where the map is the same ([`GpuScene::upload`]).
    environment: Option<std::sync::Arc<GpuEnvironment>>,
    /// The previous frame's model matrix per instance (`scene_motion`), rewritten by
    /// `GpuScene::write_motion`.
    motion: Option<wgpu::Buffer>,
    /// One draw per instance, for raster passes.
    draws: Vec<Draw>,
    /// Per mesh, its first vertex in `vertices`.
    base_vertices: Vec<u32>,
    /// What was uploaded.
    usage: SceneUsage,
    /// Bytes uploaded.
    bytes: u64,
}

impl GpuScene {
    /// Every mesh's vertices, one after another.
    pub fn vertices(&self) -> Option<&wgpu::Buffer> {
        self.vertices.as_ref()
    }

    /// Every mesh's indices, one after another.
    pub(crate) fn indices(&self) -> Option<&wgpu::Buffer> {
        self.indices.as_ref()
    }

    /// Instance records (`scene_instances`).
    pub fn instances(&self) -> Option<&wgpu::Buffer> {
        self.instances.as_ref()
    }

    /// Material records (`scene_materials`).
    pub fn materials(&self) -> Option<&wgpu::Buffer> {
        self.materials.as_ref()
    }

    /// Per mesh: first index, base vertex, index count, where its extras start in the vertex
    /// buffer (`scene_meshes`; `MESH_NO_EXTRAS` without colours or second uvs).
    pub fn meshes(&self) -> Option<&wgpu::Buffer> {
        self.meshes.as_ref()
    }

    /// The material textures.
    pub fn textures(&self) -> Option<&SceneTextures> {
        self.textures.as_ref()
    }

    /// `Scene::effective_lights()` as `LightUniforms` (`scene_lights`), rewritten every frame
    /// by `GpuScene::write_lights`.
    pub fn lights(&self) -> Option<&wgpu::Buffer> {
        self.lights.as_ref()
    }

    /// The emissive triangles as lights (`scene_emitters`, `scene::emitters`).
    pub fn emitters(&self) -> Option<&wgpu::Buffer> {
        self.emitters.as_ref()
    }

    /// The environment map (`scene_environment*`).
    pub fn environment(&self) -> Option<&GpuEnvironment> {
        self.environment.as_deref()
    }

    /// The previous frame's model matrix per instance (`scene_motion`), rewritten by
    /// `GpuScene::write_motion`.
    pub fn motion(&self) -> Option<&wgpu::Buffer> {
        self.motion.as_ref()
    }

    /// One draw per instance, for raster passes.
    pub(crate) fn draws(&self) -> &[Draw] {
        &self.draws
    }

    /// Per mesh, its first vertex in `vertices`.
    pub(crate) fn base_vertices(&self) -> &[u32] {
        &self.base_vertices
    }

    /// What was uploaded.
    pub fn usage(&self) -> SceneUsage {
        self.usage
    }

    /// Bytes uploaded.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }
}

/// Side of the square layers of the texture array.
pub(crate) const TEXTURE_SIZE: u32 = 256;
/// Mip levels of the texture array (down to 1x1).
pub const TEXTURE_MIPS: u32 = TEXTURE_SIZE.ilog2() + 1;

/// Bytes `needed` against the device's `allowed`.
fn check(scene: &Scene, what: &str, needed: u64, allowed: u64, help: &str) -> Result<(), SceneLimitError> {
    check_amount(scene, what, needed, allowed, help, true)
}

/// A count `needed` against the device's `allowed`.
fn check_count(scene: &Scene, what: &str, needed: u64, allowed: u64, help: &str) -> Result<(), SceneLimitError> {
    check_amount(scene, what, needed, allowed, help, false)
}

fn check_amount(scene: &Scene, what: &str, needed: u64, allowed: u64, help: &str, bytes: bool) -> Result<(), SceneLimitError> {
    if needed > allowed {
        return Err(SceneLimitError { scene: scene.name().to_string(), what: what.into(), needed, allowed, bytes, help: help.into() });
    }
    Ok(())
}

impl GpuScene {
    /// Uploads the parts of `scene` that `usage` names; the environment map's prefiltered
    /// levels, irradiance grid and table are taken from `before` (the scene uploaded last) where
    /// it was made from the same map.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, usage: SceneUsage, before: Option<&GpuScene>) -> Result<Self, SceneLimitError> {
        let mut upload = Upload { device, queue, scene, limits: device.limits(), bytes: 0 };
        let mut out = GpuScene::empty(usage);
        if usage.geometry || usage.geometry_storage {
            upload.geometry(&mut out)?;
        }
        if usage.instances {
            out.instances = Some(upload.storage_records("instance", instance_records(scene))?);
        }
        if usage.materials {
            let refs = texture_refs(scene, usage.texture_binding_array);
            let materials: Vec<MaterialUniforms> = scene.materials().iter().map(|m| material_uniforms(m, &refs)).collect();
            out.materials = Some(upload.storage_records("material", materials)?);
        }
        if usage.lights {
            let records = vec![LightUniforms::default(); scene.effective_light_count()];
            out.lights = Some(upload.storage_records("light", records)?);
        }
        if usage.emitters {
            out.emitters = Some(upload.storage_records("emitter word", crate::scene::emitters::emitter_table(scene))?);
        }
        if usage.environment {
            if let Some(e) = scene.environment() {
                let help = "give a smaller environment map (`--env`): a 1k or 2k map lights a scene as well";
                check_count(scene, "the environment map's width in texels", e.size().0 as u64, upload.limits.max_texture_dimension_2d as u64, help)?;
            }
            let kept = before.and_then(|b| b.environment.clone()).filter(|e| e.made_from(scene.environment()));
            let env = kept.unwrap_or_else(|| std::sync::Arc::new(GpuEnvironment::upload(device, queue, scene.environment())));
            upload.bytes += env.bytes();
            out.environment = Some(env);
        }
        if usage.motion {
            let records: Vec<[[f32; 4]; 4]> = scene.instances().iter().map(|i| i.transform.to_cols_array_2d()).collect();
            out.motion = Some(upload.storage_records("previous transform", records)?);
        }
        if usage.textures {
            out.textures = Some(upload.textures(usage.texture_binding_array)?);
        }
        out.bytes = upload.bytes;
        Ok(out)
    }

    /// A scene with no part uploaded yet, to be filled for `usage`.
    fn empty(usage: SceneUsage) -> Self {
        GpuScene {
            vertices: None,
            indices: None,
            instances: None,
            materials: None,
            meshes: None,
            textures: None,
            lights: None,
            emitters: None,
            environment: None,
            motion: None,
            draws: Vec::new(),
            base_vertices: Vec::new(),
            usage,
            bytes: 0,
        }
    }
}

/// One upload in progress: the device and its queue, the scene, the device's limits and the
/// bytes uploaded so far.
struct Upload<'a> {
    device: &'a wgpu::Device,
    queue: &'a wgpu::Queue,
    scene: &'a Scene,
    limits: wgpu::Limits,
    bytes: u64,
}

/// Every mesh's vertices and indices one after another, as the vertex and index buffers hold
/// them; where shaders read them, the meshes' colours and second uvs follow all the vertices.
struct PackedGeometry {
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    /// Per mesh: its range in `indices` and its first vertex.
    ranges: Vec<(std::ops::Range<u32>, i32)>,
    /// Per mesh, its `scene_meshes` record: first index, base vertex, index count, where its
    /// extras start (`MESH_NO_EXTRAS` without).
    records: Vec<[u32; 4]>,
    /// Bytes of the vertices, extras included.
    vertex_bytes: u64,
    /// Bytes of the indices.
    index_bytes: u64,
}

impl Upload<'_> {
    /// A buffer holding `contents`.
    fn buffer(&self, label: &str, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    }

    /// The vertex and index buffers (and `scene_meshes` where shaders read the geometry), each
    /// mesh's first vertex and each instance's draw.
    fn geometry(&mut self, out: &mut GpuScene) -> Result<(), SceneLimitError> {
        let (scene, usage) = (self.scene, out.usage);
        let mut packed = self.pack_geometry(usage)?;
        // A deforming mesh's bounds and closedness change from frame to frame: its shadow
        // maps draw both faces.
        let deforming = scene.deforming_meshes();
        out.base_vertices = packed.ranges.iter().map(|r| r.1 as u32).collect();
        out.draws = instance_draws(scene, &packed.ranges, usage.closed_meshes, &deforming);
        // wgpu buffers may not be empty.
        if packed.vertices.is_empty() {
            packed.vertices.push(Vertex::default());
        }
        if packed.indices.is_empty() {
            packed.indices.extend_from_slice(&[0, 0, 0]);
        }
        let storage = if usage.geometry_storage { wgpu::BufferUsages::STORAGE } else { wgpu::BufferUsages::empty() };
        if usage.geometry_storage {
            let limit = self.limits.max_storage_buffer_binding_size;
            check(scene, "the vertex buffer (one storage binding)", packed.vertex_bytes, limit, "use a smaller scene")?;
            check(scene, "the index buffer (one storage binding)", packed.index_bytes, limit, "use a smaller scene")?;
            if packed.records.is_empty() {
                packed.records.push([0; 4]);
            }
            out.meshes = Some(self.buffer("scene meshes", bytemuck::cast_slice(&packed.records), wgpu::BufferUsages::STORAGE));
        }
        // Deforming meshes are rewritten in place every frame they move.
        let rewritten = if deforming.is_empty() {
            wgpu::BufferUsages::empty()
        } else {
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::STORAGE
        };
        let (vertices, indices) = (&packed.vertices, &packed.indices);
        out.vertices = Some(self.buffer("scene vertices", bytemuck::cast_slice(vertices), wgpu::BufferUsages::VERTEX | storage | rewritten));
        out.indices = Some(self.buffer("scene indices", bytemuck::cast_slice(indices), wgpu::BufferUsages::INDEX | storage));
        self.bytes += (vertices.len() * std::mem::size_of::<Vertex>() + indices.len() * 4) as u64;
        Ok(())
    }

    /// The meshes packed one after another, checked against the device's buffer size.
    fn pack_geometry(&self, usage: SceneUsage) -> Result<PackedGeometry, SceneLimitError> {
        let scene = self.scene;
        // Meshes' colours and second uvs follow every mesh's vertices where shaders read them.
        let extras = |m: &Mesh| m.extras.as_ref().filter(|e| usage.geometry_storage && e.len() == m.vertices.len()).map_or(0, Vec::len);
        let vertex_count: usize = scene.meshes().iter().map(|m| m.vertices.len() + extras(m)).sum();
        let index_count: usize = scene.meshes().iter().map(|m| m.indices.len()).sum();
        let vertex_bytes = (vertex_count * std::mem::size_of::<Vertex>()) as u64;
        let help = "use a smaller scene or a lower duplication factor";
        check(scene, "the vertex buffer", vertex_bytes, self.limits.max_buffer_size, help)?;
        check(scene, "the index buffer", index_count as u64 * 4, self.limits.max_buffer_size, help)?;
        check_count(scene, "the vertex count", vertex_count as u64, i32::MAX as u64, help)?;
        let mut vertices = Vec::with_capacity(vertex_count.max(1));
        let mut indices = Vec::with_capacity(index_count.max(3));
        let mut ranges = Vec::new();
        let mut records: Vec<[u32; 4]> = Vec::new();
        for mesh in scene.meshes() {
            records.push([indices.len() as u32, vertices.len() as u32, mesh.indices.len() as u32, MESH_NO_EXTRAS]);
            let first_index = indices.len() as u32;
            let base_vertex = vertices.len() as i32;
            vertices.extend_from_slice(&mesh.vertices);
            indices.extend_from_slice(&mesh.indices);
            ranges.push((first_index..indices.len() as u32, base_vertex));
        }
        for (record, mesh) in records.iter_mut().zip(scene.meshes()) {
            if let Some(e) = mesh.extras.as_ref().filter(|_| extras(mesh) > 0) {
                record[3] = vertices.len() as u32;
                vertices.extend(e.iter().map(|e| bytemuck::cast::<VertexExtra, Vertex>(*e)));
            }
        }
        Ok(PackedGeometry { vertices, indices, ranges, records, vertex_bytes, index_bytes: index_count as u64 * 4 })
    }

    /// A storage buffer of `records` (one zeroed record if there are none: bindings may not be
    /// empty), checked against the device's storage binding limit.
    fn storage_records<T: bytemuck::Pod>(&mut self, what: &str, mut records: Vec<T>) -> Result<wgpu::Buffer, SceneLimitError> {
        let needed = (records.len() * std::mem::size_of::<T>()) as u64;
        let allowed = self.limits.max_storage_buffer_binding_size;
        check(self.scene, &format!("the {what} buffer (one storage binding)"), needed, allowed, &format!("use fewer {what}s"))?;
        if records.is_empty() {
            records.push(T::zeroed());
        }
        self.bytes += needed;
        Ok(self.buffer(&format!("scene {what}s"), bytemuck::cast_slice(&records), wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST))
    }

    /// The material textures: a binding array of the [`TexturePool`]'s arrays (one per size
    /// and encoding) if `binding_array`, else the layers of one texture array (layer 0 plain
    /// white, the scene's textures at their index + 1).
    fn textures(&mut self, binding_array: bool) -> Result<SceneTextures, SceneLimitError> {
        if binding_array {
            return self.pooled_textures();
        }
        let scene = self.scene;
        let images = std::iter::once(image::RgbaImage::from_pixel(1, 1, image::Rgba([255; 4]))).chain(scene.textures().iter().map(to_image));
        // Layer 0 (white) is colour; the scene's textures follow at index + 1.
        let data: Vec<bool> = std::iter::once(false).chain(data_textures(scene)).collect();
        let nearest: Vec<bool> = std::iter::once(false).chain(nearest_textures(scene)).collect();
        self.texture_array(images, &data, &nearest)
    }

    /// One 2D array texture per [`TexturePool`] array, each at its textures' size (at most the
    /// device's largest) with its own mip chain.
    fn pooled_textures(&mut self) -> Result<SceneTextures, SceneLimitError> {
        let pool = TexturePool::of(self.scene);
        let allowed = (self.limits.max_binding_array_elements_per_shader_stage as u64).min(1 << (24 - TEXTURE_REF_LAYER_BITS));
        let what = format!("the texture binding array (one element per texture size and encoding, and per {POOL_LAYERS} textures of one)");
        check_count(self.scene, &what, pool.arrays.len() as u64, allowed, "use fewer texture sizes")?;
        let max = self.limits.max_texture_dimension_2d;
        let (mut textures, mut views) = (Vec::new(), Vec::new());
        for (element, array) in pool.arrays.iter().enumerate() {
            let (width, height) = (array.width.min(max), array.height.min(max));
            let mips = width.max(height).ilog2() + 1;
            let encoding = if array.data { TexelEncoding::Data } else { TexelEncoding::Colour };
            let label = format!("scene textures {element} ({}x{})", array.width, array.height);
            let texture = create_texture(self.device, &label, width, height, array.layers.len() as u32, mips, encoding.format());
            for (layer, t) in array.layers.iter().enumerate() {
                let img = match t {
                    Some(t) => to_image(&self.scene.textures()[*t]),
                    None => image::RgbaImage::from_pixel(1, 1, image::Rgba([255; 4])),
                };
                let img =
                    if img.dimensions() == (width, height) { img } else { image::imageops::resize(&img, width, height, image::imageops::FilterType::Triangle) };
                self.bytes += upload_mips(self.queue, &texture, layer as u32, img, encoding);
            }
            views.push(texture.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() }));
            textures.push(texture);
        }
        Ok(SceneTextures::Pooled { textures, views })
    }

    /// One sRGB texture array of [`TEXTURE_SIZE`]² layers, an image resampled into each
    /// (by nearest texel where `nearest` says so).
    fn texture_array(&mut self, images: impl Iterator<Item = image::RgbaImage>, data: &[bool], nearest: &[bool]) -> Result<SceneTextures, SceneLimitError> {
        let count = self.scene.textures().len() as u32 + 1;
        let allowed = self.limits.max_texture_array_layers as u64;
        check(self.scene, "the texture array (one layer per texture, plus white)", count as u64, allowed, "use fewer textures")?;
        let texture = create_texture(self.device, "scene textures", TEXTURE_SIZE, TEXTURE_SIZE, count, TEXTURE_MIPS, TexelEncoding::Colour.format());
        for (layer, img) in images.enumerate() {
            let encoding = if data[layer] { TexelEncoding::DataInSrgb } else { TexelEncoding::Colour };
            let filter = if nearest[layer] { image::imageops::FilterType::Nearest } else { image::imageops::FilterType::Triangle };
            let img = if img.dimensions() == (TEXTURE_SIZE, TEXTURE_SIZE) { img } else { image::imageops::resize(&img, TEXTURE_SIZE, TEXTURE_SIZE, filter) };
            self.bytes += upload_mips(self.queue, &texture, layer as u32, img, encoding);
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() });
        Ok(SceneTextures::Array { texture, view })
    }
}

/// One draw per instance, with its mesh's centre, its bounds unless the mesh is `deforming`
/// or empty, and, where `closed_meshes` asks, whether such a mesh is closed and wound outwards.
fn instance_draws(scene: &Scene, ranges: &[(std::ops::Range<u32>, i32)], closed_meshes: bool, deforming: &[usize]) -> Vec<Draw> {
    let bounds: Vec<Bounds> = scene.meshes().iter().map(|m| m.bounds()).collect();
    let centers: Vec<Vec3> = bounds.iter().map(|b| if b.is_empty() { Vec3::ZERO } else { b.center() }).collect();
    let local: Vec<Option<Bounds>> = bounds.iter().enumerate().map(|(i, b)| (!deforming.contains(&i) && !b.is_empty()).then_some(*b)).collect();
    let closed: Vec<bool> =
        scene.meshes().iter().zip(&local).map(|(m, b)| closed_meshes && b.is_some() && crate::scene::topology::is_closed_outward(m)).collect();
    scene
        .instances()
        .iter()
        .enumerate()
        .map(|(i, inst)| Draw {
            indices: ranges[inst.mesh].0.clone(),
            base_vertex: ranges[inst.mesh].1,
            instance: i as u32,
            local_center: centers[inst.mesh],
            local_bounds: local[inst.mesh],
            closed: closed[inst.mesh],
        })
        .collect()
}

/// The texture as an image; malformed pixel data becomes the magenta fallback, never a panic.
fn to_image(img: &TextureImage) -> image::RgbaImage {
    match image::RgbaImage::from_raw(img.width, img.height, img.rgba.to_vec()) {
        Some(i) if i.width() > 0 && i.height() > 0 => i,
        _ => {
            let fb = crate::scene::gltf_import::fallback_texture(&img.name);
            image::RgbaImage::from_raw(fb.width, fb.height, fb.rgba.to_vec())
                .unwrap_or_else(|| image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 0, 255, 255])))
        }
    }
}

/// A mesh record's `extras` word for a mesh without colours or second uvs.
const MESH_NO_EXTRAS: u32 = u32::MAX;

/// The slots' sampler bits, four slots to a word (slots 0-3, 4-7, 8-10).
fn sampler_words(sampling: &[SlotSampling; TEXTURE_SLOTS]) -> [u32; 3] {
    let mut words = [0; 3];
    for (slot, s) in sampling.iter().enumerate() {
        words[slot / 4] |= s.sampler_bits() << (8 * (slot % 4));
    }
    words
}

/// The slots' uv transforms as rows (the identity where a slot has none).
fn uv_transform_rows(sampling: &[SlotSampling; TEXTURE_SLOTS]) -> [[f32; 4]; 2 * TEXTURE_SLOTS] {
    let mut rows = [[0.0; 4]; 2 * TEXTURE_SLOTS];
    for (slot, s) in sampling.iter().enumerate() {
        let [a, b] = s.transform.unwrap_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        rows[2 * slot] = [a[0], a[1], a[2], 0.0];
        rows[2 * slot + 1] = [b[0], b[1], b[2], 0.0];
    }
    rows
}

/// Which textures a slot samples with NEAREST filtering (resampled to the texture array's size
/// by nearest texel, so their texels stay sharp).
fn nearest_textures(scene: &Scene) -> Vec<bool> {
    let mut nearest = vec![false; scene.textures().len()];
    for m in scene.materials().iter() {
        for (t, s) in m.slot_textures().iter().zip(&m.sampling) {
            if let Some(t) = t.filter(|t| *t < nearest.len()) {
                nearest[t] |= s.mag_nearest || s.min_nearest;
            }
        }
    }
    nearest
}

/// How a texture's bytes are stored and filtered.
#[derive(Clone, Copy, PartialEq, Eq)]
enum TexelEncoding {
    /// sRGB colour: decoded by the sampler, mips averaged in linear light.
    Colour,
    /// Linear data in an `Rgba8Unorm` texture: read as stored, mips averaged as stored.
    Data,
    /// Linear data in the sRGB texture array of the fallback path (one format for every layer):
    /// mips averaged as stored, then each byte re-encoded so that the sampler's sRGB decode gives
    /// the stored value back (within 0.0045: sRGB steps are coarser near 1).
    DataInSrgb,
}

impl TexelEncoding {
    fn format(self) -> wgpu::TextureFormat {
        match self {
            Self::Data => wgpu::TextureFormat::Rgba8Unorm,
            Self::Colour | Self::DataInSrgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        }
    }
}

fn create_texture(device: &wgpu::Device, label: &str, width: u32, height: u32, layers: u32, mips: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: layers },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// Writes `base` and its mip chain (box-filtered in linear light for colour, as stored for
/// data) into `layer`; returns bytes.
fn upload_mips(queue: &wgpu::Queue, texture: &wgpu::Texture, layer: u32, base: image::RgbaImage, encoding: TexelEncoding) -> u64 {
    let mut level = base;
    let mut bytes = 0;
    for mip in 0..texture.mip_level_count() {
        if mip > 0 {
            level = downsample(&level, encoding == TexelEncoding::Colour);
        }
        let stored = if encoding == TexelEncoding::DataInSrgb { encode_data_as_srgb(&level) } else { level.clone() };
        bytes += stored.as_raw().len() as u64;
        queue.write_texture(
            wgpu::TexelCopyTextureInfo { texture, mip_level: mip, origin: wgpu::Origin3d { x: 0, y: 0, z: layer }, aspect: wgpu::TextureAspect::All },
            stored.as_raw(),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(stored.width() * 4), rows_per_image: Some(stored.height()) },
            wgpu::Extent3d { width: stored.width(), height: stored.height(), depth_or_array_layers: 1 },
        );
    }
    bytes
}

fn linear_to_srgb(l: f32) -> u8 {
    (crate::util::linear_to_srgb(l as f64).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The rgb bytes of linear data re-encoded as sRGB (alpha is never decoded).
fn encode_data_as_srgb(img: &image::RgbaImage) -> image::RgbaImage {
    let mut out = img.clone();
    for p in out.pixels_mut() {
        for c in 0..3 {
            p[c] = linear_to_srgb(p[c] as f32 / 255.0);
        }
    }
    out
}

/// Halves an image with a 2x2 box filter: rgb in linear light if `srgb`, else as stored.
fn downsample(img: &image::RgbaImage, srgb: bool) -> image::RgbaImage {
    let (w, h) = ((img.width() / 2).max(1), (img.height() / 2).max(1));
    image::RgbaImage::from_fn(w, h, |x, y| {
        let mut acc = [0f32; 4];
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let p = img.get_pixel((2 * x + dx).min(img.width() - 1), (2 * y + dy).min(img.height() - 1));
            for c in 0..3 {
                acc[c] += if srgb { crate::util::srgb_to_linear(p[c]) } else { p[c] as f32 };
            }
            acc[3] += p[3] as f32;
        }
        let rgb = |a: f32| if srgb { linear_to_srgb(a / 4.0) } else { (a / 4.0 + 0.5) as u8 };
        image::Rgba([rgb(acc[0]), rgb(acc[1]), rgb(acc[2]), (acc[3] / 4.0 + 0.5) as u8])
    })
}

fn instance_records(scene: &Scene) -> Vec<InstanceUniforms> {
    scene
        .instances()
        .iter()
        .map(|inst| InstanceUniforms {
            model: inst.transform.to_cols_array_2d(),
            normal_matrix: inst.transform.inverse().transpose().to_cols_array_2d(),
            material: inst.material as u32,
            mesh: inst.mesh as u32,
            _pad: [0; 2],
        })
        .collect()
}

impl GpuScene {
    /// Rewrites the instance records in place (transforms changed, nothing else). Returns
    /// false if there is no instance buffer or its size no longer matches.
    pub(crate) fn write_instances(&self, queue: &wgpu::Queue, scene: &Scene) -> bool {
        let Some(buffer) = &self.instances else { return false };
        let records = instance_records(scene);
        let bytes: &[u8] = bytemuck::cast_slice(&records);
        if records.is_empty() || bytes.len() as u64 != buffer.size() {
            return false;
        }
        queue.write_buffer(buffer, 0, bytes);
        true
    }
}

impl GpuScene {
    /// Rewrites the vertices of the meshes `meshes` in place (their vertex counts unchanged).
    /// Returns false if there is no vertex buffer or a mesh no longer fits its range.
    pub(crate) fn write_vertices(&self, queue: &wgpu::Queue, scene: &Scene, meshes: &[usize]) -> bool {
        let Some(buffer) = &self.vertices else { return false };
        let stride = std::mem::size_of::<Vertex>() as u64;
        for &m in meshes {
            let (Some(&base), Some(mesh)) = (self.base_vertices.get(m), scene.meshes().get(m)) else { return false };
            let end = self.base_vertices.get(m + 1).map_or(buffer.size() / stride, |&b| b as u64);
            if base as u64 + mesh.vertices.len() as u64 > end {
                return false;
            }
            if !mesh.vertices.is_empty() {
                queue.write_buffer(buffer, base as u64 * stride, bytemuck::cast_slice(&mesh.vertices));
            }
        }
        true
    }

    /// Rewrites the emitter table (`scene_emitters`: its triangles moved or were deformed, their
    /// count unchanged). True where no table is uploaded; false if its size no longer matches.
    pub(crate) fn write_emitters(&self, queue: &wgpu::Queue, scene: &Scene) -> bool {
        let Some(buffer) = &self.emitters else { return true };
        let words = crate::scene::emitters::emitter_table(scene);
        let bytes: &[u8] = bytemuck::cast_slice(&words);
        if bytes.len() as u64 != buffer.size() {
            return false;
        }
        queue.write_buffer(buffer, 0, bytes);
        true
    }

    /// Rewrites the previous transforms (`scene_motion`). Returns false if there is no such
    /// buffer or its size no longer matches.
    pub(crate) fn write_motion(&self, queue: &wgpu::Queue, transforms: &[Mat4]) -> bool {
        let Some(buffer) = &self.motion else { return false };
        let records: Vec<[[f32; 4]; 4]> = transforms.iter().map(|m| m.to_cols_array_2d()).collect();
        let bytes: &[u8] = bytemuck::cast_slice(&records);
        if records.is_empty() || bytes.len() as u64 != buffer.size() {
            return false;
        }
        queue.write_buffer(buffer, 0, bytes);
        true
    }

    /// Rewrites the light records. Returns false if there is no light buffer or its size no
    /// longer matches.
    pub(crate) fn write_lights(&self, queue: &wgpu::Queue, records: &[LightUniforms]) -> bool {
        let Some(buffer) = &self.lights else { return false };
        let bytes: &[u8] = bytemuck::cast_slice(records);
        if records.is_empty() {
            // No light (an environment map in place of the sun): the buffer's one stand-in
            // record stays, unread (`frame.light_count` is 0).
            return buffer.size() == std::mem::size_of::<LightUniforms>() as u64;
        }
        if bytes.len() as u64 != buffer.size() {
            return false;
        }
        queue.write_buffer(buffer, 0, bytes);
        true
    }
}

/// What an upload depends on, split in two: everything but the instance transforms
/// (`SceneContent::structure`: a change re-uploads the scene) and the transforms alone (a
/// change rewrites the instance records in place). Meshes and materials are hashed by content;
/// a texture by its size and the address of its pixels (a replaced image is seen, pixels
/// edited in place are not).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub(crate) struct SceneContent {
    /// The hash of everything but the instance transforms and the deforming meshes' vertices.
    pub(crate) structure: u64,
    /// The hash of the instance transforms.
    pub(crate) transforms: u64,
    /// The deforming meshes' shape ([`Scene::deformation_key`]).
    pub(crate) deformed: u64,
}

impl SceneContent {
    /// The hashes of `scene`; `memo` keeps each mesh's own two hashes (of its whole content,
    /// and of all but a deforming mesh's vertices) while the mesh is unchanged
    /// ([`crate::scene::memo::MeshMemo`]), so an unchanged mesh's vertices are not read again.
    pub(crate) fn of(scene: &Scene, memo: &mut crate::scene::memo::MeshMemo<[u64; 2]>) -> Self {
        use crate::util::hash_words;
        let deforming = scene.deforming_meshes();
        let mesh_hashes = memo.values(scene.meshes(), |m| {
            // A deforming mesh's vertices are in `deformed`; its vertex count stays here. The
            // indices and tangents are read once for both.
            let indices = hash_words(4, bytemuck::cast_slice(&m.indices));
            let rest = m.tangents.as_ref().map_or(indices, |t| hash_words(indices, bytemuck::cast_slice(t))).to_le_bytes();
            [hash_words(hash_words(1, bytemuck::cast_slice(&m.vertices)), &rest), hash_words(m.vertices.len() as u64, &rest)]
        });
        let meshes: Vec<u64> = mesh_hashes.iter().enumerate().map(|(i, [whole, shape])| if deforming.contains(&i) { *shape } else { *whole }).collect();
        let links: Vec<[u64; 2]> = scene.instances().iter().map(|i| [i.mesh as u64, i.material as u64]).collect();
        let textures: Vec<[u64; 4]> = scene.textures().iter().map(|t| [t.width as u64, t.height as u64, t.rgba.len() as u64, t.rgba.as_ptr() as u64]).collect();
        let mut structure = hash_words(2, bytemuck::cast_slice(&meshes));
        // The materials as the GPU reads them (every field that reaches a pass, texture layers
        // included): hashing their records is cheaper than formatting them. Their texture
        // references as the texture-array path numbers them: the pooled ones follow from those
        // and the textures' sizes, hashed below.
        let refs = texture_refs(scene, false);
        let materials: Vec<MaterialUniforms> = scene.materials().iter().map(|m| material_uniforms(m, &refs)).collect();
        structure = hash_words(structure, bytemuck::cast_slice(&materials));
        structure = hash_words(structure, bytemuck::cast_slice(&links));
        structure = hash_words(structure, bytemuck::cast_slice(&textures));
        structure = hash_words(structure, bytemuck::cast_slice(&deforming.iter().map(|&i| i as u64).collect::<Vec<_>>()));
        // The light buffer's size (its records are rewritten every frame).
        structure = hash_words(structure, &(scene.effective_light_count() as u64).to_le_bytes());
        // The environment map: its size, intensity and rotation, and its texels by their
        // allocation (never edited in place) and a sparse sample of them (a new map freed into
        // the same place).
        if let Some(e) = scene.environment() {
            let sample: Vec<[f32; 3]> = e.texels().iter().step_by(4099).copied().collect();
            let words = [e.size().0 as u64, e.texels().as_ptr() as u64, e.intensity.to_bits() as u64, e.rotation.to_bits() as u64];
            structure = hash_words(hash_words(structure, bytemuck::cast_slice(&words)), bytemuck::cast_slice(&sample));
        }
        let transforms: Vec<[f32; 16]> = scene.instances().iter().map(|i| i.transform.to_cols_array()).collect();
        Self { structure, transforms: hash_words(3, bytemuck::cast_slice(&transforms)), deformed: scene.deformation_key().unwrap_or(0) }
    }
}

/// The GPU record of material `m` (`scene_materials`), its textures named by `refs`
/// ([`texture_refs`]).
fn material_uniforms(m: &crate::scene::Material, refs: &[u32]) -> MaterialUniforms {
    let layer = |t: Option<usize>| texture_ref(refs, t);
    let samplers = sampler_words(&m.sampling);
    let uv_sets = m.sampling.iter().enumerate().map(|(slot, s)| u32::from(s.tex_coord == 1) << slot).sum::<u32>();
    // Translucent materials (BLEND, transmissive) are hit wherever their coverage reaches
    // their cutoff (Material::alpha_cutoff) and composited by the passes.
    let (alpha_flag, cutoff) = match (m.translucent(), m.alpha_mode) {
        (true, _) => (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND, m.alpha_cutoff().unwrap_or(0.0)),
        (false, AlphaMode::Mask(c)) => (MATERIAL_ALPHA_MASK, c),
        (false, _) => (0, 0.0),
    };
    MaterialUniforms {
        base_color: m.base_color,
        emissive: m.emissive,
        metallic: m.metallic,
        roughness: m.roughness,
        normal_scale: m.normal_scale,
        alpha_cutoff: cutoff,
        flags: alpha_flag
            | if m.double_sided { MATERIAL_DOUBLE_SIDED } else { 0 }
            | if m.unlit { MATERIAL_UNLIT } else { 0 }
            | if m.sampling.iter().any(|s| s.transform.is_some()) { MATERIAL_UV_TRANSFORM } else { 0 }
            | if m.sampling.iter().any(|s| s.sampler_bits() != 0) { MATERIAL_SAMPLERS } else { 0 }
            | if m.lobes != crate::scene::Lobes::default() { MATERIAL_LOBES } else { 0 }
            | if m.lobes.transmission > 0.0 { MATERIAL_TRANSMISSION } else { 0 }
            | if m.transmission_texture_drawn() { MATERIAL_TRANSMISSION_TEXTURE } else { 0 },
        base_texture: layer(m.texture),
        metallic_roughness_texture: layer(m.metallic_roughness_texture),
        normal_texture: layer(m.normal_texture),
        emissive_texture: layer(m.emissive_texture),
        occlusion_texture: layer(m.occlusion_texture),
        occlusion_strength: m.occlusion_strength,
        samplers: [samplers[0], samplers[1]],
        lobe_layers: [0, 1, 2, 3].map(|k| layer(m.lobes.textures[k])),
        slot_words: [layer(m.lobes.textures[4]), layer(m.lobes.textures[5]), samplers[2], uv_sets],
        uv_transforms: uv_transform_rows(&m.sampling),
        specular: {
            let [r, g, b] = m.lobes.tinted_reflectance().map(|t| t as f32);
            [r, g, b, m.lobes.specular]
        },
        clearcoat: [m.lobes.clearcoat, m.lobes.clearcoat_roughness, m.lobes.transmission, m.coverage_factor()],
        coat: [m.lobes.clearcoat_normal_scale, 0.0, 0.0, 0.0],
    }
}
