//! The CPU scene (meshes, materials, instances, textures, camera, light), the built-in
//! default scene, and which parts of it a compiled plan reads ([`usage`]). No GPU: the upload
//! is the runtime's (`runtime::scene_upload`).

pub mod animation;
pub mod builtin;
pub mod camera;
pub mod duplicate;
pub mod emitters;
pub mod environment;
pub mod export;
pub mod export_mitsuba;
pub mod fly;
pub mod gltf_animation;
pub mod gltf_import;
pub mod info;
pub mod load;
pub mod memo;
pub mod posing;
pub mod procedural;
pub mod texture_pool;
pub mod topology;
pub mod track;
pub mod usage;
pub mod vertex;

use glam::{Mat4, Vec3};

pub use camera::Camera;
pub use gltf_import::{ImportReport, LoadOptions, SceneError};
pub use load::open;
pub use vertex::{Vertex, VertexExtra};

/// A triangle mesh in object space.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// The mesh's name (from the file, or made up for generated meshes).
    pub name: String,
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// Three indices into `vertices` per triangle, counter-clockwise front faces.
    pub indices: Vec<u32>,
    /// Per-vertex tangents (xyz, w = handedness), present where a normal map needs them.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// Per-vertex colours and second texture coordinates, where the mesh has either (one per
    /// vertex).
    pub extras: Option<Vec<VertexExtra>>,
}

impl Mesh {
    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// How a material's alpha is interpreted (glTF `alphaMode`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    /// Every texel is opaque.
    #[default]
    Opaque,
    /// Alpha-tested: texels with alpha below the cutoff are not there.
    Mask(f32),
    /// Blended by alpha.
    Blend,
}

/// How a texture coordinate outside 0..1 wraps (glTF sampler `wrapS`, `wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Wrap {
    /// The texture repeats.
    #[default]
    Repeat,
    /// The edge texels extend.
    ClampToEdge,
    /// The texture repeats, every other copy mirrored.
    MirroredRepeat,
}

impl Wrap {
    /// Texel index `f` (a whole number) of an axis `n` texels long, wrapped
    /// (`alpha_texel_index` in `shaders/common/alpha_read.wgsl`).
    pub fn texel_index(self, f: f64, n: usize) -> usize {
        let n = n as f64;
        let k = match self {
            Wrap::Repeat => f.rem_euclid(n),
            Wrap::ClampToEdge => f.clamp(0.0, n - 1.0),
            Wrap::MirroredRepeat => {
                let k = f.rem_euclid(2.0 * n);
                if k >= n {
                    2.0 * n - 1.0 - k
                } else {
                    k
                }
            }
        };
        (k.max(0.0) as usize).min(n as usize - 1)
    }
}

/// Which mip levels minification reads (from glTF's `minFilter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mipmaps {
    /// The two nearest levels, blended (`*_MIPMAP_LINEAR`, and no `minFilter`).
    #[default]
    Linear,
    /// The nearest level (`*_MIPMAP_NEAREST`).
    Nearest,
    /// Level 0 only (`NEAREST`, `LINEAR`).
    None,
}

/// How one texture slot of a material is sampled: its texture's glTF sampler and its
/// `KHR_texture_transform`. The default is glTF's default sampler without a transform.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SlotSampling {
    /// Wrap along u (`wrapS`).
    pub wrap_s: Wrap,
    /// Wrap along v (`wrapT`).
    pub wrap_t: Wrap,
    /// Magnification picks the nearest texel (`magFilter` NEAREST).
    pub mag_nearest: bool,
    /// Minification picks the nearest texel of a level (`minFilter` NEAREST*).
    pub min_nearest: bool,
    /// The mip levels minification reads.
    pub mipmaps: Mipmaps,
    /// The texture coordinate set the slot reads: 0 (`TEXCOORD_0`) or 1 (`TEXCOORD_1`).
    pub tex_coord: u32,
    /// The two rows of the 2x3 matrix the uv goes through (`KHR_texture_transform`: translation
    /// x rotation x scale); `None`: the identity.
    pub transform: Option<[[f32; 3]; 2]>,
}

impl SlotSampling {
    /// The uv through the transform.
    pub fn apply(&self, uv: [f32; 2]) -> [f32; 2] {
        match self.transform {
            Some([a, b]) => [a[0] * uv[0] + a[1] * uv[1] + a[2], b[0] * uv[0] + b[1] * uv[1] + b[2]],
            None => uv,
        }
    }

    /// The wrap modes alone: [`SlotSampling::sampler_bits`]' bits 0-3 (what the alpha test
    /// reads).
    pub(crate) fn wrap_bits(&self) -> u32 {
        self.sampler_bits() & 15
    }

    /// The sampler as 8 bits (`shaders/common/texture_sampling.wgsl`): bits 0-1 wrap S, 2-3
    /// wrap T (0 repeat, 1 clamp, 2 mirror), 4 magnification NEAREST, 5 minification NEAREST,
    /// 6-7 the mipmap mode (0 linear, 1 nearest, 2 none). 0 is glTF's default sampler.
    pub(crate) fn sampler_bits(&self) -> u32 {
        let wrap = |w: Wrap| match w {
            Wrap::Repeat => 0,
            Wrap::ClampToEdge => 1,
            Wrap::MirroredRepeat => 2,
        };
        let mipmaps = match self.mipmaps {
            Mipmaps::Linear => 0,
            Mipmaps::Nearest => 1,
            Mipmaps::None => 2,
        };
        wrap(self.wrap_s) | wrap(self.wrap_t) << 2 | u32::from(self.mag_nearest) << 4 | u32::from(self.min_nearest) << 5 | mipmaps << 6
    }
}

/// A PBR metallic-roughness material. Texture fields index [`Scene::textures`].
#[derive(Debug, Clone)]
pub struct Material {
    /// The material's name.
    pub name: String,
    /// Linear base colour and alpha (times `texture`).
    pub base_color: [f32; 4],
    /// Base-colour texture.
    pub texture: Option<usize>,
    /// Metalness, 0..1 (times the metallic-roughness texture's blue channel).
    pub metallic: f32,
    /// Perceptual roughness, 0..1 (times its green channel).
    pub roughness: f32,
    /// Metallic-roughness texture.
    pub metallic_roughness_texture: Option<usize>,
    /// Tangent-space normal map.
    pub normal_texture: Option<usize>,
    /// Scale of the normal map's xy.
    pub normal_scale: f32,
    /// Emitted radiance (glTF `emissiveFactor` times `KHR_materials_emissive_strength`).
    pub emissive: [f32; 3],
    /// Emissive texture (sRGB, times `emissive`).
    pub emissive_texture: Option<usize>,
    /// Ambient-occlusion texture (its red channel), and how much of it applies.
    pub occlusion_texture: Option<usize>,
    /// How much of the occlusion texture applies, 0..1.
    pub occlusion_strength: f32,
    /// How alpha is interpreted.
    pub alpha_mode: AlphaMode,
    /// Both faces are lit and neither is culled.
    pub double_sided: bool,
    /// Unlit (glTF `KHR_materials_unlit`): the surface shows its base colour (factor times
    /// texture), whatever the lights; it reflects and emits nothing else.
    pub unlit: bool,
    /// How each texture slot is sampled, in the order of [`gltf_import::TextureSlot`] (base
    /// colour, metallic-roughness, normal, occlusion, emissive, then the lobe extensions' six:
    /// [`Lobes::textures`]).
    pub sampling: [SlotSampling; TEXTURE_SLOTS],
    /// The specular lobes of the glTF PBR extensions (`KHR_materials_ior`,
    /// `KHR_materials_specular`, `KHR_materials_clearcoat`).
    pub lobes: Lobes,
}

/// A material's texture slots: glTF's five (base colour, metallic-roughness, normal, occlusion,
/// emissive) and the six of the lobe extensions ([`Lobes::textures`]).
pub(crate) const TEXTURE_SLOTS: usize = crate::uniforms::MATERIAL_TEXTURE_SLOTS;

/// The slots of [`Lobes::textures`], counted from the first lobe slot (slot 5 of a material).
pub(crate) const LOBE_SPECULAR: usize = 0;
/// `specularColorTexture` (sRGB).
pub const LOBE_SPECULAR_COLOR: usize = 1;
/// `clearcoatTexture` (red).
pub const LOBE_CLEARCOAT: usize = 2;
/// `clearcoatRoughnessTexture` (green).
pub(crate) const LOBE_CLEARCOAT_ROUGHNESS: usize = 3;
/// `clearcoatNormalTexture` (tangent space, like the normal map).
pub const LOBE_CLEARCOAT_NORMAL: usize = 4;
/// `transmissionTexture` (red).
pub const LOBE_TRANSMISSION: usize = 5;

/// The factors and textures of `KHR_materials_ior`, `KHR_materials_specular`,
/// `KHR_materials_clearcoat` and `KHR_materials_transmission`. The default is glTF's core
/// material: index of refraction 1.5 (a dielectric reflects 4% at normal incidence), no coat.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lobes {
    /// Index of refraction of the dielectric part.
    pub ior: f32,
    /// `specularFactor`: the strength of the dielectric specular lobe (its reflectance at
    /// grazing angles, and a scale of its reflectance at normal incidence).
    pub specular: f32,
    /// `specularColorFactor`: the tint of the dielectric reflectance at normal incidence.
    pub specular_color: [f32; 3],
    /// `clearcoatFactor`: the weight of a clear dielectric coat (ior 1.5) over the material.
    pub clearcoat: f32,
    /// `clearcoatRoughnessFactor`: the coat's perceptual roughness.
    pub clearcoat_roughness: f32,
    /// `transmissionFactor` (KHR_materials_transmission): the share of the dielectric part's
    /// light that passes through, tinted by the base colour (thin-walled: no refraction).
    pub transmission: f32,
    /// The scale of the coat's normal map's xy (`clearcoatNormalTexture.scale`).
    pub clearcoat_normal_scale: f32,
    /// Textures indexing [`Scene::textures`], each multiplying its factor: `specularTexture`
    /// (alpha), `specularColorTexture` (rgb, sRGB), `clearcoatTexture` (red),
    /// `clearcoatRoughnessTexture` (green), `clearcoatNormalTexture` (the coat's own normal
    /// map; without one the coat follows the surface's normal before the base's normal map),
    /// `transmissionTexture` (red); indexed by `LOBE_SPECULAR` and the constants after it.
    pub textures: [Option<usize>; 6],
}

impl Default for Lobes {
    fn default() -> Self {
        Self {
            ior: 1.5,
            specular: 1.0,
            specular_color: [1.0; 3],
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            transmission: 0.0,
            clearcoat_normal_scale: 1.0,
            textures: [None; 6],
        }
    }
}

impl Lobes {
    /// ((ior - 1) / (ior + 1))² x specular colour: the dielectric part's reflectance at normal
    /// incidence (KHR_materials_specular; 0.04 by default) before the clamp to 1 and the specular
    /// factor, which the shaders apply with the lobe textures' texels.
    pub(crate) fn tinted_reflectance(&self) -> [f64; 3] {
        let r = ((self.ior as f64 - 1.0) / (self.ior as f64 + 1.0)).powi(2);
        self.specular_color.map(|c| r * c as f64)
    }
}

impl Material {
    /// Whether light passes through it: BLEND, or transmissive (`KHR_materials_transmission`).
    /// Translucent surfaces are composited (docs/ARCHITECTURE.md, "Blended surfaces").
    pub fn translucent(&self) -> bool {
        self.alpha_mode == AlphaMode::Blend || self.lobes.transmission > 0.0
    }

    /// The cutoff of an alpha-tested material, `None` for an opaque one: MASK's own; BLEND's
    /// [`BLEND_MIN_COVERAGE`] (a texel below it is empty); 0 for a transmissive one whatever its
    /// alpha mode (its surface is always hit: even one that lets everything through reflects).
    pub(crate) fn alpha_cutoff(&self) -> Option<f32> {
        match self.alpha_mode {
            AlphaMode::Blend => Some(BLEND_MIN_COVERAGE),
            _ if self.lobes.transmission > 0.0 => Some(0.0),
            AlphaMode::Opaque => None,
            AlphaMode::Mask(c) => Some(c),
        }
    }

    /// Whether the transmission texture is drawn: a transmissive material whose
    /// `transmissionTexture` reads the base colour slot's uv (TEXCOORD_0 through the same
    /// transform), where the coverage records keep their uvs. Another one is kept but not drawn
    /// (`scene info` says so).
    pub fn transmission_texture_drawn(&self) -> bool {
        let (base, t) = (&self.sampling[0], &self.sampling[5 + LOBE_TRANSMISSION]);
        self.lobes.transmission > 0.0
            && self.lobes.textures[LOBE_TRANSMISSION].is_some()
            && t.tex_coord == 0
            && base.tex_coord == 0
            && t.transform == base.transform
    }

    /// The share of the light that passes a transmissive surface where its transmission
    /// texel is 1: transmission x (1 - metallic); 0 for other materials.
    pub(crate) fn transmitted_share(&self) -> f32 {
        self.lobes.transmission * (1.0 - self.metallic)
    }

    /// The factor of a translucent surface's coverage (what it hides of what lies behind it;
    /// times the base texture's alpha): `base_color.a` x (1 - transmission x (1 - metallic)),
    /// and where the transmission texture is drawn, `base_color.a` (the texel then scales the
    /// transmitted share: [`Material::transmission_texture_drawn`]).
    pub(crate) fn coverage_factor(&self) -> f32 {
        if self.transmission_texture_drawn() {
            return self.base_color[3];
        }
        self.base_color[3] * (1.0 - self.lobes.transmission * (1.0 - self.metallic))
    }

    /// Every slot's texture in the order of [`gltf_import::TextureSlot`] and of
    /// [`Material::sampling`]: base colour, metallic-roughness, normal, occlusion, emissive,
    /// then [`Lobes::textures`].
    pub(crate) fn slot_textures(&self) -> [Option<usize>; TEXTURE_SLOTS] {
        let core = [self.texture, self.metallic_roughness_texture, self.normal_texture, self.occlusion_texture, self.emissive_texture];
        std::array::from_fn(|slot| if slot < 5 { core[slot] } else { self.lobes.textures[slot - 5] })
    }

    /// A plain diffuse material.
    pub fn diffuse(name: &str, base_color: [f32; 4], texture: Option<usize>) -> Self {
        Self {
            name: name.into(),
            base_color,
            texture,
            metallic: 0.0,
            roughness: 0.8,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: [0.0; 3],
            emissive_texture: None,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            unlit: false,
            sampling: Default::default(),
            lobes: Lobes::default(),
        }
    }
}

/// The least coverage (`base_color.a` x texture alpha) a BLEND texel needs to be hit at all:
/// below it the texel is empty (under one 8-bit step of what it would add).
pub(crate) const BLEND_MIN_COVERAGE: f32 = 1.0 / 256.0;

/// One placement of a mesh.
#[derive(Debug, Clone)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Object to world space.
    pub transform: Mat4,
}

/// An RGBA8 sRGB image.
#[derive(Debug, Clone)]
pub struct TextureImage {
    /// The image's name (from the file, or made up).
    pub name: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height` RGBA8 texels, row by row (shared: a scene's copies, such as one posed
    /// on the CPU, do not copy its images).
    pub rgba: std::sync::Arc<Vec<u8>>,
}

impl TextureImage {
    /// The image as PNG bytes, RGBA or (without `alpha`) RGB; the error names the texture.
    pub(crate) fn png(&self, alpha: bool) -> Result<Vec<u8>, String> {
        let wrong = || format!("texture `{}` has the wrong amount of pixel data", self.name);
        let img: image::DynamicImage = if alpha {
            image::RgbaImage::from_raw(self.width, self.height, self.rgba.to_vec()).ok_or_else(wrong)?.into()
        } else {
            let rgb = self.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
            image::RgbImage::from_raw(self.width, self.height, rgb).ok_or_else(wrong)?.into()
        };
        let mut png = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).map_err(|e| format!("texture `{}`: {e}", self.name))?;
        Ok(png)
    }
}

/// A directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Unit direction from surfaces towards the light.
    pub direction: Vec3,
    /// Linear RGB colour.
    pub color: Vec3,
    /// Radiance scale of the colour.
    pub intensity: f32,
    /// Intensity of the sky's ambient light.
    pub ambient: f32,
}

/// A scene on the CPU: meshes, materials, instances, textures, cameras and lights.
///
/// Its parts are read through accessors and edited through methods: meshes, materials and
/// instances only through [`Scene::mesh_mut`], [`Scene::materials_mut`],
/// [`Scene::instances_mut`] and the setters that replace them, so that an edited part is always
/// a new allocation and change detection ([`memo`]) can compare pointers.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The scene's name (built-in name or file stem).
    name: String,
    /// The meshes instances place, each behind an `Arc`: edit one through [`Scene::mesh_mut`]
    /// (`Arc::make_mut`), so that an edited mesh is a new allocation ([`memo`]).
    meshes: Vec<std::sync::Arc<Mesh>>,
    /// The materials instances use, behind one `Arc`: edit them through
    /// [`Scene::materials_mut`], so that the same pointer means the same materials.
    materials: std::sync::Arc<Vec<Material>>,
    /// Placements of meshes with a material, behind one `Arc`: edit them through
    /// [`Scene::instances_mut`] (a moved instance is a new allocation of the list).
    instances: std::sync::Arc<Vec<Instance>>,
    /// Images that materials index.
    textures: Vec<TextureImage>,
    /// The default view.
    camera: Camera,
    /// Named static views (the paper's static-camera tests); the first is `camera`.
    presets: Vec<(String, Camera)>,
    /// The default sun and sky, lighting scenes without lights of their own.
    light: Light,
    /// An optional point light (besides the directional `light`).
    point_light: Option<PointLight>,
    /// The file's own lights (glTF `KHR_lights_punctual`), in world space. Empty: the scene is
    /// lit by `light` (and `point_light`); see [`Scene::effective_lights`].
    lights: Vec<PunctualLight>,
    /// The file's node hierarchy, clips, skins and deforming meshes, where it has clips or
    /// deforming meshes ([`Scene::pose`]); `None` for a scene that never moves by itself.
    rig: Option<std::sync::Arc<animation::Rig>>,
    /// The time the rig was last posed at, and whether the deforming meshes' vertices here
    /// hold that pose (`None`: never posed since loading, or no rig).
    posed: Option<animation::PoseTime>,
    /// The environment map that lights the scene in place of the default sun and sky
    /// (`--env`); `None`: the sun and the analytic sky.
    environment: Option<std::sync::Arc<environment::Environment>>,
}

/// What kind of punctual light, with the parameters only that kind has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// Lights the whole scene from one direction.
    Directional,
    /// `range`: distance at which the light's influence ends (`None`: infinite).
    Point {
        /// Distance at which the light's influence ends (`None`: infinite).
        range: Option<f32>,
    },
    /// Cone angles in radians from the axis (glTF `innerConeAngle`, `outerConeAngle`).
    Spot {
        /// Distance at which the light's influence ends (`None`: infinite).
        range: Option<f32>,
        /// Angle from the axis inside which the light is at full intensity.
        inner_cone: f32,
        /// Angle from the axis outside which there is no light.
        outer_cone: f32,
    },
}

/// A light of the file (`KHR_lights_punctual`) or the scene's default sun, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct PunctualLight {
    /// The light's name in the file.
    pub name: String,
    /// Its kind and the parameters of that kind.
    pub kind: LightKind,
    /// World-space position (unused for directional lights).
    pub position: Vec3,
    /// Unit world-space direction the light shines in (from the light towards the scene; for
    /// directional and spot lights).
    pub direction: Vec3,
    /// Linear RGB colour.
    pub color: Vec3,
    /// glTF units: lux for directional lights, candela for point and spot lights.
    pub intensity: f32,
}

/// A point light with inverse-square falloff.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// Linear RGB colour.
    pub color: Vec3,
    /// Radiant intensity: irradiance at 1 unit, facing the light.
    pub intensity: f32,
}

impl Default for Light {
    fn default() -> Self {
        Self { direction: Vec3::new(-0.4, 0.8, 0.45).normalize(), color: Vec3::new(1.0, 0.96, 0.9), intensity: 3.0, ambient: 0.35 }
    }
}

/// Axis-aligned bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// The smallest corner.
    pub min: Vec3,
    /// The largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// Bounds of nothing: growing them by a point gives that point.
    pub(crate) const EMPTY: Bounds = Bounds { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    /// Whether no point was added.
    pub(crate) fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }

    /// Grows the bounds to contain `p`.
    pub(crate) fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// Bounds containing both.
    pub(crate) fn union(&self, o: &Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// The centre point.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// The length of the diagonal (0 when empty).
    pub fn diagonal(&self) -> f32 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).length()
        }
    }
}

impl Mesh {
    /// Bounds of the vertices the indices use.
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::EMPTY;
        for i in &self.indices {
            b.grow(Vec3::from(self.vertices[*i as usize].position));
        }
        b
    }
}

impl Scene {
    /// An empty scene called `name`, seen from `camera`: no meshes, materials, instances,
    /// textures, presets or lights of its own, lit by the default sun ([`Light::default`]).
    /// Parts are added through [`Scene::push_mesh`], [`Scene::materials_mut`] and
    /// [`Scene::instances_mut`].
    pub fn new(name: impl Into<String>, camera: Camera) -> Self {
        Self {
            name: name.into(),
            meshes: Vec::new(),
            materials: Default::default(),
            instances: Default::default(),
            textures: Vec::new(),
            camera,
            presets: Vec::new(),
            light: Light::default(),
            point_light: None,
            lights: Vec::new(),
            rig: None,
            posed: None,
            environment: None,
        }
    }

    /// The scene's name (built-in name or file stem).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Renames the scene.
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }

    /// The meshes instances place, each behind an `Arc` (edit one through [`Scene::mesh_mut`]).
    pub fn meshes(&self) -> &[std::sync::Arc<Mesh>] {
        &self.meshes
    }

    /// Mesh `index`, for editing: a copy when it is shared ([`memo`]).
    pub fn mesh_mut(&mut self, index: usize) -> &mut Mesh {
        std::sync::Arc::make_mut(&mut self.meshes[index])
    }

    /// Replaces every mesh (instances keep their mesh indices); a mesh given as an `Arc` is
    /// shared, not copied.
    pub fn set_meshes<M: Into<std::sync::Arc<Mesh>>>(&mut self, meshes: impl IntoIterator<Item = M>) {
        self.meshes = meshes.into_iter().map(Into::into).collect();
    }

    /// Adds `mesh` after the others and returns its index.
    pub fn push_mesh(&mut self, mesh: impl Into<std::sync::Arc<Mesh>>) -> usize {
        self.meshes.push(mesh.into());
        self.meshes.len() - 1
    }

    /// Removes the last mesh and returns it (an instance still placing it then places
    /// nothing).
    pub fn pop_mesh(&mut self) -> Option<std::sync::Arc<Mesh>> {
        self.meshes.pop()
    }

    /// The materials instances use (edit them through [`Scene::materials_mut`]).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The materials, for editing: a copy when the list is shared (with a memo or a copy of
    /// the scene), so that whoever kept the old `Arc` sees the change as a new pointer.
    pub fn materials_mut(&mut self) -> &mut Vec<Material> {
        std::sync::Arc::make_mut(&mut self.materials)
    }

    /// Placements of meshes with a material (edit them through [`Scene::instances_mut`]).
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// The instances, for editing (moved, added, removed): a copy when the list is shared, as
    /// [`Scene::materials_mut`].
    pub fn instances_mut(&mut self) -> &mut Vec<Instance> {
        std::sync::Arc::make_mut(&mut self.instances)
    }

    /// Replaces every instance.
    pub fn set_instances(&mut self, instances: Vec<Instance>) {
        self.instances = instances.into();
    }

    /// The instances' `Arc`: a clone of it kept until the next frame tells whether they moved
    /// (an edit through [`Scene::instances_mut`] makes a new one).
    pub(crate) fn instances_arc(&self) -> &std::sync::Arc<Vec<Instance>> {
        &self.instances
    }

    /// Images that materials index.
    pub fn textures(&self) -> &[TextureImage] {
        &self.textures
    }

    /// The images, for editing (a material's texture index must stay in range).
    pub fn textures_mut(&mut self) -> &mut Vec<TextureImage> {
        &mut self.textures
    }

    /// The default view.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The default view, for editing.
    pub fn camera_mut(&mut self) -> &mut Camera {
        &mut self.camera
    }

    /// Named static views (the paper's static-camera tests); the first is the default view.
    pub fn presets(&self) -> &[(String, Camera)] {
        &self.presets
    }

    /// The named static views, for editing.
    pub fn presets_mut(&mut self) -> &mut Vec<(String, Camera)> {
        &mut self.presets
    }

    /// The default sun and sky, lighting scenes without lights of their own.
    pub fn light(&self) -> &Light {
        &self.light
    }

    /// The default sun and sky, for editing.
    pub fn light_mut(&mut self) -> &mut Light {
        &mut self.light
    }

    /// The environment map that lights the scene in place of the default sun and sky.
    pub fn environment(&self) -> Option<&std::sync::Arc<environment::Environment>> {
        self.environment.as_ref()
    }

    /// Lights the scene by `environment` in place of the default sun and sky (`None`: the sun
    /// and sky again). The file's own punctual lights stay.
    pub fn set_environment(&mut self, environment: Option<environment::Environment>) {
        self.environment = environment.map(std::sync::Arc::new);
    }

    /// An optional point light (besides the directional [`Scene::light`]).
    pub fn point_light(&self) -> Option<&PointLight> {
        self.point_light.as_ref()
    }

    /// Sets the optional point light (`None`: removes it).
    pub fn set_point_light(&mut self, light: Option<PointLight>) {
        self.point_light = light;
    }

    /// The file's own lights (glTF `KHR_lights_punctual`), in world space. Empty: the scene is
    /// lit by [`Scene::light`] (and [`Scene::point_light`]); see [`Scene::effective_lights`].
    pub fn lights(&self) -> &[PunctualLight] {
        &self.lights
    }

    /// The scene's own lights, for editing.
    pub fn lights_mut(&mut self) -> &mut Vec<PunctualLight> {
        &mut self.lights
    }

    /// The file's node hierarchy, clips, skins and deforming meshes, where it has clips or
    /// deforming meshes ([`Scene::pose`]); `None` for a scene that never moves by itself.
    pub fn rig(&self) -> Option<&std::sync::Arc<animation::Rig>> {
        self.rig.as_ref()
    }

    /// Replaces the rig (`None`: the scene no longer moves by itself); the meshes keep their
    /// vertices until the scene is posed again.
    pub fn set_rig(&mut self, rig: Option<std::sync::Arc<animation::Rig>>) {
        self.rig = rig;
    }

    /// The time the rig was last posed at, and whether the deforming meshes' vertices here
    /// hold that pose (`None`: never posed since loading, or no rig).
    pub fn posed(&self) -> Option<animation::PoseTime> {
        self.posed
    }

    /// The preset called `name`, or an error listing the presets there are.
    pub fn preset(&self, name: &str) -> Result<Camera, String> {
        self.presets.iter().find(|(n, _)| n == name).map(|(_, c)| *c).ok_or_else(|| {
            let names: Vec<&str> = self.presets.iter().map(|(n, _)| n.as_str()).collect();
            format!("scene `{}` has no camera preset `{name}`; its presets are: {}", self.name, names.join(", "))
        })
    }

    /// Drops every texture and every material's reference to one (for graphs that sample
    /// none).
    pub(crate) fn strip_textures(&mut self) {
        self.textures.clear();
        for m in self.materials_mut().iter_mut() {
            m.texture = None;
            m.metallic_roughness_texture = None;
            m.normal_texture = None;
            m.emissive_texture = None;
            m.occlusion_texture = None;
        }
    }

    /// How many lights [`Scene::effective_lights`] returns (without building them).
    pub(crate) fn effective_light_count(&self) -> usize {
        if self.lights.is_empty() {
            usize::from(self.environment.is_none()) + usize::from(self.point_light.is_some())
        } else {
            self.lights.len()
        }
    }

    /// The lights that light the scene: the file's own lights, or, when it has none, the
    /// default sun (`light`; not with an environment map, which holds its own sun) and the
    /// optional `point_light`.
    pub fn effective_lights(&self) -> Vec<PunctualLight> {
        if !self.lights.is_empty() {
            return self.lights.clone();
        }
        let sun = PunctualLight {
            name: "sun".into(),
            kind: LightKind::Directional,
            position: Vec3::ZERO,
            direction: -self.light.direction,
            color: self.light.color,
            intensity: self.light.intensity,
        };
        let mut out: Vec<PunctualLight> = self.environment.is_none().then_some(sun).into_iter().collect();
        if let Some(p) = self.point_light {
            out.push(PunctualLight {
                name: "point".into(),
                kind: LightKind::Point { range: None },
                position: p.position,
                direction: Vec3::NEG_Y,
                color: p.color,
                intensity: p.intensity,
            });
        }
        out
    }

    /// Triangles over all instances (a mesh placed twice counts twice).
    pub fn triangle_count(&self) -> usize {
        self.instances.iter().map(|i| self.meshes[i.mesh].triangle_count()).sum()
    }

    /// The meshes the rig deforms (skinned or morphed), in increasing order; empty without a rig.
    pub fn deforming_meshes(&self) -> Vec<usize> {
        let mut m: Vec<usize> = self.rig.as_ref().map(|r| r.deformers.iter().map(|d| d.mesh).collect()).unwrap_or_default();
        m.sort_unstable();
        m.dedup();
        m
    }

    /// World-space bounds of all instances.
    pub fn bounds(&self) -> Bounds {
        self.bounds_from(&self.meshes.iter().map(|m| m.bounds()).collect::<Vec<_>>())
    }

    /// World-space bounds of all instances, given each mesh's bounds (`mesh_bounds`, one per
    /// mesh, as [`Mesh::bounds`] gives them; a memo of them spares reading the vertices).
    pub(crate) fn bounds_from(&self, mesh_bounds: &[Bounds]) -> Bounds {
        let mut b = Bounds::EMPTY;
        for inst in self.instances.iter() {
            let Some(&mb) = mesh_bounds.get(inst.mesh) else { continue };
            if mb.is_empty() {
                continue;
            }
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { mb.min.x } else { mb.max.x },
                    if i & 2 == 0 { mb.min.y } else { mb.max.y },
                    if i & 4 == 0 { mb.min.z } else { mb.max.z },
                );
                b.grow(inst.transform.transform_point3(c));
            }
        }
        b
    }
}
