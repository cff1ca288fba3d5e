//! Writes a [`Scene`] as a Mitsuba 3 scene (`scene export SCENE out.xml`): the XML, one binary
//! PLY per instance (world space: instances flattened), the base-colour and
//! metallic-roughness textures and normal maps as PNG, emissive textures and the sky as PFM (linear radiance),
//! all beside the XML. Materials use the `raygraph` BSDF that `tools/mitsuba/raygraph_bsdf.py`
//! registers (raygraph's own Lambert + GGX model); lights are converted from raygraph's
//! radiance scale (a light of intensity 1 gives irradiance pi). What Mitsuba cannot show the
//! same way is listed in [`MitsubaExport::warnings`] and written as comments in the XML.

use super::gltf_import::SceneError;
use super::{AlphaMode, Camera, LightKind, Material, Mesh, Scene, SlotSampling, Wrap};
use glam::{Mat3, Mat4, Vec3};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What an export wrote.
#[derive(Debug, Default)]
pub struct MitsubaExport {
    /// Every file written, the XML last.
    pub files: Vec<PathBuf>,
    /// One shape per instance.
    pub shapes: usize,
    /// The emitters of the scene's lights (not the sky, not the area emitters).
    pub lights: usize,
    /// What the Mitsuba scene shows differently from raygraph.
    pub warnings: Vec<String>,
}

/// The film size and sample count the XML uses unless given `-D width=...` etc.
const DEFAULT_WIDTH: u32 = 512;
/// Samples per pixel by default (`$spp`).
const DEFAULT_SPP: u32 = 64;
/// The sky bitmap's size: it varies with the direction's height only (one texel per column
/// would do; Mitsuba's envmap wants a few).
const SKY_SIZE: (usize, usize) = (16, 512);
/// The sky's radiance at the horizon's below and above (`sky_color` in
/// shaders/common/lighting.wgsl), before the ambient scale.
const SKY_GROUND: Vec3 = Vec3::new(0.35, 0.3, 0.25);
/// The sky's radiance straight up, before the ambient scale.
const SKY_ZENITH: Vec3 = Vec3::new(0.6, 0.75, 1.0);

/// The files being written and the XML being built.
struct Writer<'a> {
    /// The folder of the XML.
    dir: PathBuf,
    /// The XML's file stem: every other file's name starts with it.
    stem: String,
    /// The XML path, for errors.
    xml_path: &'a Path,
    xml: String,
    out: MitsubaExport,
}

impl Writer<'_> {
    fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::Write { path: self.xml_path.to_path_buf(), message: message.into() }
    }

    /// Writes `bytes` as `{stem}_{name}` beside the XML; returns the file name.
    fn file(&mut self, name: &str, bytes: &[u8]) -> Result<String, SceneError> {
        let file_name = format!("{}_{}", self.stem, name);
        let path = self.dir.join(&file_name);
        crate::util::write_atomic(&path, bytes).map_err(|e| SceneError::Write { path: path.clone(), message: e.to_string() })?;
        self.out.files.push(path);
        Ok(file_name)
    }

    fn warn(&mut self, message: String) {
        let _ = writeln!(self.xml, "    <!-- warning: {} -->", xml_comment(&message));
        self.out.warnings.push(message);
    }
}

/// Writes the scene as a Mitsuba 3 XML at `path`, its meshes and images beside it.
pub fn write_mitsuba(scene: &Scene, path: &Path) -> Result<MitsubaExport, SceneError> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")).to_path_buf();
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into());
    let mut w = Writer { dir, stem: file_safe(&stem), xml_path: path, xml: String::new(), out: MitsubaExport::default() };
    let camera = scene.camera();
    let height = (DEFAULT_WIDTH as f32 / camera.aspect_ratio.unwrap_or(1.0)).round().max(1.0) as u32;
    let _ = writeln!(w.xml, "<?xml version=\"1.0\" encoding=\"utf-8\"?>");
    let _ = writeln!(
        w.xml,
        "<!-- raygraph scene `{}`; load tools/mitsuba/raygraph_bsdf.py first (it registers the `raygraph` BSDF). -->",
        xml_comment(scene.name())
    );
    let _ = writeln!(w.xml, "<scene version=\"3.0.0\">");
    let _ = writeln!(w.xml, "    <default name=\"width\" value=\"{DEFAULT_WIDTH}\"/>\n    <default name=\"height\" value=\"{height}\"/>");
    let _ = writeln!(w.xml, "    <default name=\"spp\" value=\"{DEFAULT_SPP}\"/>\n    <default name=\"seed\" value=\"0\"/>");
    let _ = writeln!(w.xml, "    <default name=\"max_depth\" value=\"-1\"/>");
    let _ = writeln!(w.xml, "    <integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"$max_depth\"/>\n    </integrator>");
    sensor(&mut w, camera)?;
    lights(&mut w, scene);
    sky(&mut w, scene.light().ambient)?;
    let textures = textures(&mut w, scene)?;
    for (i, m) in scene.materials().iter().enumerate() {
        material(&mut w, i, m, &textures);
    }
    shapes(&mut w, scene)?;
    w.xml.push_str("</scene>\n");
    let xml = std::mem::take(&mut w.xml);
    crate::util::write_atomic(path, xml.as_bytes()).map_err(|e| w.error(e.to_string()))?;
    w.out.files.push(path.to_path_buf());
    Ok(w.out)
}

/// The perspective sensor: raygraph's vertical field of view, position, target and up.
fn sensor(w: &mut Writer, c: &Camera) -> Result<(), SceneError> {
    if c.orthographic.is_some() {
        return Err(w.error("the scene's camera is orthographic: the Mitsuba export writes perspective cameras only"));
    }
    let xml = format!(
        r#"    <sensor type="perspective">
        <string name="fov_axis" value="y"/>
        <float name="fov" value="{fov}"/>
        <float name="near_clip" value="{near}"/>
        <float name="far_clip" value="{far}"/>
        <transform name="to_world">
            <lookat origin="{origin}" target="{target}" up="{up}"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
            <integer name="seed" value="$seed"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$width"/>
            <integer name="height" value="$height"/>
            <string name="pixel_format" value="rgb"/>
            <rfilter type="box"/>
        </film>
    </sensor>
"#,
        fov = c.fov_y.to_degrees(),
        near = c.near,
        far = c.far,
        origin = vec3(c.position, ", "),
        target = vec3(c.target, ", "),
        up = vec3(c.up, ", "),
    );
    w.xml.push_str(&xml);
    Ok(())
}

/// The scene's lights (its own, or the default sun and point light). raygraph's intensity is a
/// radiance scale: a light of intensity 1 lights a facing white Lambert surface to radiance 1,
/// i.e. irradiance pi; Mitsuba's `irradiance` and `intensity` are physical.
fn lights(w: &mut Writer, scene: &Scene) {
    for l in scene.effective_lights() {
        let power = l.color * l.intensity * std::f32::consts::PI;
        let range = match l.kind {
            LightKind::Point { range } | LightKind::Spot { range, .. } => range.filter(|r| r.is_finite() && *r > 0.0),
            LightKind::Directional => None,
        };
        if let Some(r) = range {
            w.warn(format!("light `{}` has range {r}: raygraph fades it by clamp(1 - (d/range)^4, 0, 1)^2, Mitsuba's light has no range", l.name));
        }
        let xml = match l.kind {
            LightKind::Directional => format!(
                "    <emitter type=\"directional\">\n        <vector name=\"direction\" value=\"{}\"/>\n        <rgb name=\"irradiance\" value=\"{}\"/>\n    </emitter>\n",
                vec3(l.direction, ", "),
                vec3(power, " ")
            ),
            LightKind::Point { .. } => format!(
                "    <emitter type=\"point\">\n        <point name=\"position\" value=\"{}\"/>\n        <rgb name=\"intensity\" value=\"{}\"/>\n    </emitter>\n",
                vec3(l.position, ", "),
                vec3(power, " ")
            ),
            LightKind::Spot { inner_cone, outer_cone, .. } => {
                w.warn(format!(
                    "spot light `{}`: raygraph's cone falloff is clamp((cos - cos_outer) / (cos_inner - cos_outer), 0, 1)^2, Mitsuba's `spot` falls off linearly in angle between beam_width and cutoff_angle",
                    l.name
                ));
                spot_xml(l.position, l.direction, power, inner_cone, outer_cone)
            }
        };
        w.xml.push_str(&xml);
        w.out.lights += 1;
    }
}

/// A Mitsuba `spot` at `position` shining along `direction`.
fn spot_xml(position: Vec3, direction: Vec3, power: Vec3, inner_cone: f32, outer_cone: f32) -> String {
    let up = if direction.cross(Vec3::Y).length_squared() > 1e-6 { Vec3::Y } else { Vec3::Z };
    format!(
        "    <emitter type=\"spot\">\n        <transform name=\"to_world\">\n            <lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>\n        </transform>\n        <rgb name=\"intensity\" value=\"{}\"/>\n        <float name=\"beam_width\" value=\"{}\"/>\n        <float name=\"cutoff_angle\" value=\"{}\"/>\n    </emitter>\n",
        vec3(position, ", "),
        vec3(position + direction, ", "),
        vec3(up, ", "),
        vec3(power, " "),
        inner_cone.to_degrees(),
        outer_cone.to_degrees().max(inner_cone.to_degrees() + 1e-3),
    )
}

/// The sky as an equirectangular `envmap` (Mitsuba's: y up, row 0 straight up):
/// `ambient x sky_color(d)`. None where the ambient is 0.
fn sky(w: &mut Writer, ambient: f32) -> Result<(), SceneError> {
    if ambient <= 0.0 {
        return Ok(());
    }
    let (width, height) = SKY_SIZE;
    let rows: Vec<Vec3> = (0..height)
        .map(|row| {
            let y = (std::f32::consts::PI * (row as f32 + 0.5) / height as f32).cos();
            ambient * SKY_GROUND.lerp(SKY_ZENITH, 0.5 + 0.5 * y)
        })
        .collect();
    let pixels: Vec<[f32; 3]> = rows.iter().flat_map(|c| std::iter::repeat_n(c.to_array(), width)).collect();
    let file = w.file("sky.pfm", &pfm(width, height, &pixels))?;
    let _ = writeln!(
        w.xml,
        "    <!-- the sky: ambient {ambient} x sky_color (shaders/common/lighting.wgsl) -->\n    <emitter type=\"envmap\">\n        <string name=\"filename\" value=\"{file}\"/>\n    </emitter>"
    );
    Ok(())
}

/// The file names of the textures materials sample as base colour, metallic-roughness or
/// normal map (`None`: not written).
fn textures(w: &mut Writer, scene: &Scene) -> Result<Vec<Option<String>>, SceneError> {
    let used: Vec<bool> = (0..scene.textures().len())
        .map(|i| scene.materials().iter().any(|m| [m.texture, m.metallic_roughness_texture, m.normal_texture].contains(&Some(i))))
        .collect();
    let mut names = Vec::new();
    for (i, t) in scene.textures().iter().enumerate() {
        if !used[i] {
            names.push(None);
            continue;
        }
        let png = t.png(false).map_err(|e| w.error(e))?;
        names.push(Some(w.file(&format!("tex{i}_{}.png", file_safe(&t.name)), &png)?));
    }
    Ok(names)
}

/// Material `i` as a `raygraph` BSDF with id `mat{i}` (its normal map applied by the plugin
/// itself, as raygraph's shaders apply it; inside `twosided` for a double-sided one), and
/// warnings for what it cannot show.
fn material(w: &mut Writer, i: usize, m: &Material, textures: &[Option<String>]) {
    material_warnings(w, m);
    let lobes = &m.lobes;
    let f0 = lobes.tinted_reflectance().map(|r| (r.min(1.0) as f32) * lobes.specular);
    let mut body = format!(
        "            <rgb name=\"base_color\" value=\"{}\"/>\n            <float name=\"metallic\" value=\"{}\"/>\n            <float name=\"roughness\" value=\"{}\"/>\n            <rgb name=\"f0\" value=\"{}\"/>\n            <float name=\"f90\" value=\"{}\"/>\n",
        vec3(Vec3::from_slice(&m.base_color[..3]), " "),
        m.metallic,
        m.roughness,
        vec3(Vec3::from(f0), " "),
        lobes.specular,
    );
    if let Some(file) = m.texture.and_then(|t| textures[t].as_ref()) {
        body += &bitmap_xml("base_color_texture", file, &m.sampling[0], false);
    }
    if let Some(file) = m.metallic_roughness_texture.and_then(|t| textures[t].as_ref()) {
        body += &bitmap_xml("metallic_roughness_texture", file, &m.sampling[1], true);
    }
    if let Some(file) = m.normal_texture.and_then(|t| textures[t].as_ref()) {
        body += &bitmap_xml("normal_texture", file, &m.sampling[2], true);
        let _ = writeln!(body, "            <float name=\"normal_scale\" value=\"{}\"/>", m.normal_scale);
    }
    let mut bsdf = format!("<bsdf type=\"raygraph\">\n{body}</bsdf>");
    if m.double_sided {
        bsdf = format!("<bsdf type=\"twosided\">\n{bsdf}\n</bsdf>");
    }
    let bsdf = bsdf.replacen("<bsdf type=", &format!("<bsdf id=\"mat{i}\" type="), 1);
    let _ = writeln!(w.xml, "    <!-- material `{}` -->\n    {bsdf}", xml_comment(&m.name));
}

/// Warnings for the parts of `m` the export leaves out.
fn material_warnings(w: &mut Writer, m: &Material) {
    let name = &m.name;
    let mut ignored = Vec::new();
    if m.occlusion_texture.is_some() {
        ignored.push("its occlusion texture (a path tracer computes occlusion)");
    }
    if m.alpha_mode != AlphaMode::Opaque {
        ignored.push("its alpha (MASK/BLEND: exported opaque)");
    }
    if m.unlit {
        ignored.push("KHR_materials_unlit (exported lit)");
    }
    if m.lobes.clearcoat > 0.0 || m.lobes.transmission > 0.0 || m.lobes.textures.iter().any(Option::is_some) {
        ignored.push("its clear coat, transmission and lobe textures");
    }
    let slots = [(0, m.texture), (1, m.metallic_roughness_texture), (4, m.emissive_texture)];
    if slots.iter().any(|&(s, t)| t.is_some() && (m.sampling[s].tex_coord != 0 || m.sampling[s].transform.is_some())) {
        ignored.push("a texture's TEXCOORD_1 or KHR_texture_transform (read with TEXCOORD_0, untransformed)");
    }
    if !ignored.is_empty() {
        w.warn(format!("material `{name}`: the Mitsuba export ignores {}", ignored.join(", ")));
    }
}

/// A `bitmap` texture named `name` reading `file` with the slot's wrap and filter (sRGB
/// decoded unless `raw`). Mitsuba has no mipmaps: minification is bilinear.
fn bitmap_xml(name: &str, file: &str, s: &SlotSampling, raw: bool) -> String {
    let wrap = match s.wrap_s {
        Wrap::Repeat => "repeat",
        Wrap::ClampToEdge => "clamp",
        Wrap::MirroredRepeat => "mirror",
    };
    let filter = if s.mag_nearest { "nearest" } else { "bilinear" };
    format!(
        "            <texture type=\"bitmap\" name=\"{name}\">\n                <string name=\"filename\" value=\"{file}\"/>\n                <boolean name=\"raw\" value=\"{raw}\"/>\n                <string name=\"wrap_mode\" value=\"{wrap}\"/>\n                <string name=\"filter_type\" value=\"{filter}\"/>\n            </texture>\n"
    )
}

/// One PLY shape per instance, in world space, with its material and, for an emissive
/// material, an area emitter.
fn shapes(w: &mut Writer, scene: &Scene) -> Result<(), SceneError> {
    for (i, inst) in scene.instances().iter().enumerate() {
        let mesh = scene.meshes().get(inst.mesh).ok_or_else(|| w.error(format!("instance {i} names mesh {} of {}", inst.mesh, scene.meshes().len())))?;
        let m = scene
            .materials()
            .get(inst.material)
            .ok_or_else(|| w.error(format!("instance {i} names material {} of {}", inst.material, scene.materials().len())))?;
        if mesh.triangle_count() == 0 {
            return Err(w.error(format!("instance {i}: mesh `{}` has no triangles (Mitsuba loads no empty mesh)", mesh.name)));
        }
        if mesh.extras.as_ref().is_some_and(|e| e.iter().any(|x| x.color != [1.0; 4])) {
            w.warn(format!("mesh `{}`: its vertex colours are ignored", mesh.name));
        }
        let file = w.file(&format!("instance{i}_{}.ply", file_safe(&mesh.name)), &world_ply(mesh, inst.transform))?;
        let emitter = emitter_xml(w, inst.material, m, scene)?;
        let _ = writeln!(
            w.xml,
            "    <shape type=\"ply\" id=\"instance{i}\">\n        <string name=\"filename\" value=\"{file}\"/>\n        <ref id=\"mat{}\"/>\n{emitter}    </shape>",
            inst.material
        );
        w.out.shapes += 1;
    }
    Ok(())
}

/// The area emitter of an emissive material (empty for others): radiance = the emissive
/// colour (times strength), times the emissive texture, written once per material as PFM.
fn emitter_xml(w: &mut Writer, index: usize, m: &Material, scene: &Scene) -> Result<String, SceneError> {
    let emissive = Vec3::from(m.emissive);
    if emissive == Vec3::ZERO {
        return Ok(String::new());
    }
    let Some(t) = m.emissive_texture.and_then(|t| scene.textures().get(t)) else {
        return Ok(format!("        <emitter type=\"area\">\n            <rgb name=\"radiance\" value=\"{}\"/>\n        </emitter>\n", vec3(emissive, " ")));
    };
    let name = format!("emission{index}.pfm");
    let file = format!("{}_{name}", w.stem);
    if !w.out.files.iter().any(|f| f.file_name().is_some_and(|n| n.to_string_lossy() == file)) {
        let texels: Vec<[f32; 3]> = t.rgba.chunks_exact(4).map(|p| [0, 1, 2].map(|c| crate::util::srgb_to_linear(p[c]) * emissive[c])).collect();
        if texels.len() != (t.width * t.height) as usize {
            return Err(w.error(format!("texture `{}` has the wrong amount of pixel data", t.name)));
        }
        w.file(&name, &pfm(t.width as usize, t.height as usize, &texels))?;
    }
    let texture = bitmap_xml("radiance", &file, &m.sampling[4], true);
    Ok(format!("        <emitter type=\"area\">\n{texture}        </emitter>\n"))
}

/// A binary little-endian PLY of `mesh` through `transform`: positions, unit normals (through
/// the inverse transpose) and uvs; triangles wound counter-clockwise in world space (reversed
/// where the transform mirrors).
fn world_ply(mesh: &Mesh, transform: Mat4) -> Vec<u8> {
    let normal_matrix = Mat3::from_mat4(transform).inverse().transpose();
    let mirrored = transform.determinant() < 0.0;
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment raygraph mesh {}\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.name.replace(['\n', '\r'], " "),
        mesh.vertices.len(),
        mesh.triangle_count()
    );
    let mut bytes = header.into_bytes();
    for v in &mesh.vertices {
        let p = transform.transform_point3(Vec3::from(v.position));
        let n = (normal_matrix * Vec3::from(v.normal)).normalize_or_zero();
        for x in p.to_array().into_iter().chain(n.to_array()).chain(v.uv) {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    for t in mesh.indices.chunks_exact(3) {
        bytes.push(3);
        let order = if mirrored { [t[0], t[2], t[1]] } else { [t[0], t[1], t[2]] };
        for i in order {
            bytes.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    bytes
}

/// A colour PFM (rows bottom to top, little endian) of `width` x `height` pixels given top row
/// first.
fn pfm(width: usize, height: usize, pixels: &[[f32; 3]]) -> Vec<u8> {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for row in pixels.chunks_exact(width).rev() {
        for x in row.iter().flatten() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    bytes
}

/// `x{sep}y{sep}z`.
fn vec3(v: Vec3, sep: &str) -> String {
    format!("{}{sep}{}{sep}{}", v.x, v.y, v.z)
}

/// `s` with only ASCII letters, digits, `-` and `_` (others become `_`), at most 40 of them.
fn file_safe(s: &str) -> String {
    s.chars().take(40).map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect()
}

/// `s` safe inside an XML comment (no `--`) and as text (no `<`, `>`, `&`).
fn xml_comment(s: &str) -> String {
    s.replace("--", "- -").replace('<', "(").replace('>', ")").replace('&', "and")
}
