//! Shader reflection through naga: loads a WGSL file (with its `//#include` files), validates
//! it, and lists its global bindings, entry points and uniform struct layouts. Bind group
//! layouts are built from this, never written by hand per pass.

use crate::error::{ErrorKind, GraphError, Location};
use naga::common::wgsl::{address_space_str, ToWgsl, TryToWgsl, TypeContext};
use std::path::{Path, PathBuf};

/// Include substitutions chosen by the device and back-end: `//#include "a.wgsl"` reads the
/// file the map gives for `a.wgsl` instead (for example the bindless variant of
/// `common/scene_textures.wgsl`, or the active back-end's `trace/trace.wgsl`).
pub(crate) type IncludeAliases = std::collections::BTreeMap<String, String>;

/// Name of the synthetic segment holding hoisted `enable` directives.
const ENABLE_SEGMENT: &str = "<enable directives>";

/// WGSL text assembled from a file and the files it includes. Included files are appended
/// after the main file, so the main file's line numbers stay as written.
#[derive(Debug, Clone)]
pub struct ShaderSource {
    /// The assembled WGSL.
    text: String,
    /// (file, byte offset where its text starts in `text`)
    segments: Vec<(PathBuf, usize)>,
    /// Every file of it is raygraph's built-in copy, byte for byte ([`ShaderSource::is_builtin`]).
    builtin: bool,
}

impl ShaderSource {
    /// The assembled WGSL.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Reads `path`; lines `//#include "rel/path.wgsl"` name files relative to `shader_root`.
    pub fn load(path: &Path, shader_root: &Path, referenced_from: &Location, aliases: &IncludeAliases) -> Result<Self, GraphError> {
        let mut src = ShaderSource { text: String::new(), segments: Vec::new(), builtin: true };
        let mut included: Vec<PathBuf> = Vec::new();
        let mut enables: Vec<String> = Vec::new();
        src.append(path, shader_root, referenced_from, aliases, &mut included, &mut enables)?;
        if !enables.is_empty() {
            // WGSL wants `enable` directives before every declaration: they are blanked where
            // they were written (offsets and lines stay true) and put in a prefix segment.
            let mut prefix: String = enables.iter().map(|e| format!("{e}\n")).collect();
            let shift = prefix.len();
            prefix.push_str(&src.text);
            src.text = prefix;
            for seg in &mut src.segments {
                seg.1 += shift;
            }
            src.segments.insert(0, (PathBuf::from(ENABLE_SEGMENT), 0));
        }
        Ok(src)
    }

    fn append(
        &mut self,
        path: &Path,
        root: &Path,
        from: &Location,
        aliases: &IncludeAliases,
        seen: &mut Vec<PathBuf>,
        enables: &mut Vec<String>,
    ) -> Result<(), GraphError> {
        if seen.iter().any(|p| p == path) {
            return Ok(());
        }
        seen.push(path.to_path_buf());
        let file = super::files::read(path).map_err(|e| {
            GraphError::new(ErrorKind::Io, from.clone(), format!("cannot read shader {}: {e}", path.display()))
                .help("check the shader path; it is relative to the shaders/ directory")
        })?;
        self.builtin &= file.builtin;
        let text = file.text;
        let start = self.text.len();
        self.segments.push((file.path.clone(), start));
        let mut body = String::with_capacity(text.len());
        for line in text.split_inclusive('\n') {
            let directive = line.trim();
            if directive.starts_with("enable ") && directive.ends_with(';') {
                if !enables.iter().any(|e| e == directive) {
                    enables.push(directive.to_string());
                }
                body.extend(line.chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
            } else {
                body.push_str(line);
            }
        }
        self.text.push_str(&body);
        if !self.text.ends_with('\n') {
            self.text.push('\n');
        }
        for (line_no, line) in text.lines().enumerate() {
            if let Some(rest) = line.trim().strip_prefix("//#include") {
                let rel = rest.trim().trim_matches('"');
                let rel = aliases.get(rel).map(String::as_str).unwrap_or(rel);
                let loc = Location::new(&file.path, line_no as u32 + 1, 1);
                self.append(&root.join(rel), root, &loc, aliases, seen, enables)?;
            }
        }
        Ok(())
    }

    /// Whether the main file and every include are raygraph's built-in copies, byte for byte
    /// (embedded, or files on disk identical to them): part of the program rather than of a
    /// project a user edits.
    pub(crate) fn is_builtin(&self) -> bool {
        self.builtin
    }

    /// File location of a byte offset in the assembled text.
    pub fn locate(&self, offset: usize) -> Location {
        let (file, start) = self.segments.iter().rev().find(|(_, s)| *s <= offset).cloned().unwrap_or_else(|| (PathBuf::new(), 0));
        let end = self.segments.iter().map(|(_, s)| *s).find(|s| *s > start).unwrap_or(self.text.len());
        Location::at_offset(&file, &self.text[start..end], offset - start)
    }

    /// The files the text was assembled from, main file first.
    pub fn files(&self) -> impl Iterator<Item = &Path> {
        self.segments.iter().map(|(p, _)| p.as_path()).filter(|p| *p != Path::new(ENABLE_SEGMENT))
    }

    /// The main file (the one the text was assembled for).
    pub(crate) fn main_file(&self) -> &Path {
        self.files().next().unwrap_or(Path::new(""))
    }
}

/// What a global binding is, as far as a bind group layout cares.
#[derive(Debug, Clone, PartialEq)]
pub enum BindingKind {
    /// A sampled texture (`texture_2d<f32>`, `texture_2d_array<u32>`, ...).
    SampledTexture {
        /// Its dimension.
        dim: naga::ImageDimension,
        /// Whether it is an array texture.
        arrayed: bool,
        /// The sample type.
        kind: naga::ScalarKind,
    },
    /// `binding_array<texture_2d_array<f32>>` (unsized): one array texture per element (the
    /// scene's pooled textures, `crate::scene::texture_pool`).
    TextureBindingArray,
    /// A ray-query acceleration structure.
    AccelerationStructure,
    /// `texture_depth_2d`, or `texture_depth_2d_array` where `arrayed`.
    DepthTexture {
        /// Whether it is an array texture.
        arrayed: bool,
    },
    /// A storage texture.
    StorageTexture {
        /// Its texel format.
        format: naga::StorageFormat,
        /// Read, write or both.
        access: naga::StorageAccess,
    },
    /// A sampler.
    Sampler {
        /// A comparison sampler (`sampler_comparison`).
        comparison: bool,
    },
    /// A uniform buffer.
    Uniform {
        /// The struct's size in bytes.
        size: u32,
        /// The struct's scalar and vector members (the `params` struct is matched by them).
        members: Vec<UniformMember>,
        /// The struct's WGSL name.
        type_name: Option<String>,
    },
    /// A storage buffer.
    Storage {
        /// `var<storage, read>`.
        read_only: bool,
        /// The smallest size a bound buffer may have, in bytes.
        min_size: u32,
    },
    /// Anything else, as WGSL writes its declaration.
    Other(String),
}

impl BindingKind {
    /// The binding's type as WGSL writes it, for messages.
    pub(crate) fn describe(&self) -> String {
        match self {
            BindingKind::SampledTexture { dim, arrayed, kind } => {
                format!("texture_{}{}<{}>", dim.to_wgsl(), if *arrayed { "_array" } else { "" }, sample_type_name(*kind))
            }
            BindingKind::DepthTexture { arrayed } => format!("texture_depth_2d{}", if *arrayed { "_array" } else { "" }),
            BindingKind::TextureBindingArray => "binding_array<texture_2d_array<f32>>".into(),
            BindingKind::AccelerationStructure => "acceleration_structure".into(),
            BindingKind::StorageTexture { format, access } => format!("texture_storage_2d<{}, {}>", format.to_wgsl(), access_name(*access)),
            BindingKind::Sampler { comparison } => if *comparison { "sampler_comparison" } else { "sampler" }.into(),
            BindingKind::Uniform { type_name, .. } => format!("var<uniform> {}", type_name.clone().unwrap_or_default()),
            BindingKind::Storage { read_only, .. } => if *read_only { "var<storage, read>" } else { "var<storage, read_write>" }.into(),
            BindingKind::Other(s) => s.clone(),
        }
    }
}

/// The WGSL sample type of a texture (`texture_2d<f32>`).
fn sample_type_name(kind: naga::ScalarKind) -> &'static str {
    match kind {
        naga::ScalarKind::Sint => "i32",
        naga::ScalarKind::Uint => "u32",
        naga::ScalarKind::Bool => "bool",
        _ => "f32",
    }
}

/// A global variable's declaration as WGSL writes it: `var<private> x: array<u32, 4>`, `var x: sampler`.
fn global_type_name(module: &naga::Module, space: naga::AddressSpace, inner: &naga::TypeInner) -> String {
    let mut ty = String::new();
    if module.to_ctx().write_type_inner(inner, &mut ty).is_err() {
        ty = "an unknown type".into();
    }
    match address_space_str(space) {
        (Some(space), Some(access)) => format!("var<{space}, {access}> {ty}"),
        (Some(space), None) => format!("var<{space}> {ty}"),
        _ => format!("var {ty}"),
    }
}

/// The WGSL access mode of a storage binding (`read`, `write`, `read_write`).
pub(crate) fn access_name(access: naga::StorageAccess) -> &'static str {
    let r = access.contains(naga::StorageAccess::LOAD);
    let w = access.contains(naga::StorageAccess::STORE);
    match (r, w) {
        (true, true) => "read_write",
        (true, false) => "read",
        _ => "write",
    }
}

/// A member of a uniform struct.
#[derive(Debug, Clone, PartialEq)]
pub struct UniformMember {
    /// The member's name.
    pub name: String,
    /// Byte offset in the struct.
    pub offset: u32,
    /// Its scalar type (`None` for matrices, arrays and structs).
    pub scalar: Option<naga::ScalarKind>,
    /// Number of scalar components (1 for scalars, N for vecN); 0 for anything else.
    pub components: u32,
}

/// One `@group(g) @binding(b) var name` of a shader.
#[derive(Debug, Clone)]
pub struct ShaderBinding {
    /// The variable's name.
    pub name: String,
    /// `@group`.
    pub group: u32,
    /// `@binding`.
    pub binding: u32,
    /// What it binds.
    pub kind: BindingKind,
    /// Where it is declared.
    pub location: Location,
}

/// An entry point of a shader.
#[derive(Debug, Clone)]
pub struct EntryPointInfo {
    /// The function's name.
    pub name: String,
    /// Its stage.
    pub stage: naga::ShaderStage,
    /// `@workgroup_size` (compute; 0s otherwise).
    pub workgroup_size: [u32; 3],
    /// Vertex input locations (vertex stage) or colour output locations (fragment stage).
    pub locations: Vec<u32>,
}

/// The reflected interface of one WGSL file.
#[derive(Debug, Clone)]
pub struct ShaderInfo {
    /// The file reflected.
    pub path: PathBuf,
    /// Its assembled text.
    pub source: ShaderSource,
    /// The global bindings.
    pub bindings: Vec<ShaderBinding>,
    /// The entry points.
    pub entry_points: Vec<EntryPointInfo>,
    /// Names of the module's pipeline-overridable constants (WGSL `override`).
    pub overrides: Vec<String>,
    /// The validated IR of a module with ray-tracing pipeline stages (a trace pass compiled for
    /// the `rt-pipeline` back-end), whose compute entry points were made ray-generation
    /// shaders ([`compute_to_ray_generation`]); wgpu-hal compiles every stage from it.
    pub ray_tracing: Option<RayTracingModule>,
}

/// A module's IR and validation result, shared by the passes that use the file.
#[derive(Clone)]
pub struct RayTracingModule {
    /// The IR.
    pub module: std::sync::Arc<naga::Module>,
    /// naga's validation of it.
    pub info: std::sync::Arc<naga::valid::ModuleInfo>,
}

impl std::fmt::Debug for RayTracingModule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let stages: Vec<String> = self.module.entry_points.iter().map(|e| format!("{} {:?}", e.name, e.stage)).collect();
        f.debug_struct("RayTracingModule").field("entry_points", &stages).finish()
    }
}

/// Whether `stage` belongs to a ray-tracing pipeline.
pub(crate) fn is_ray_tracing_stage(stage: naga::ShaderStage) -> bool {
    matches!(stage, naga::ShaderStage::RayGeneration | naga::ShaderStage::Miss | naga::ShaderStage::ClosestHit | naga::ShaderStage::AnyHit)
}

/// Makes every compute entry point of `module` a ray-generation entry point: the stage changes,
/// and `@builtin(global_invocation_id)` becomes `@builtin(ray_invocation_id)` (the same
/// `vec3<u32>`: the launch grid is the pass's dispatch in invocations, one per pixel). This is
/// how a trace pass written as a compute shader runs unchanged as the ray-generation shader of
/// the `rt-pipeline` back-end. Any other compute built-in (workgroup ids, local ids, workgroup
/// counts) has no ray-generation equivalent and is an error naming it.
pub fn compute_to_ray_generation(module: &mut naga::Module) -> Result<(), String> {
    for ep in module.entry_points.iter_mut().filter(|e| e.stage == naga::ShaderStage::Compute) {
        for arg in &mut ep.function.arguments {
            match &mut arg.binding {
                Some(naga::Binding::BuiltIn(b @ naga::BuiltIn::GlobalInvocationId)) => *b = naga::BuiltIn::RayInvocationId,
                Some(naga::Binding::BuiltIn(other)) => {
                    return Err(format!(
                        "entry point `{}` reads @builtin({}), which a ray-generation shader does not have; a trace pass may read only global_invocation_id",
                        ep.name,
                        other.try_to_wgsl().unwrap_or("an unnamed built-in")
                    ))
                }
                None if matches!(module.types[arg.ty].inner, naga::TypeInner::Struct { .. }) => {
                    return Err(format!("entry point `{}` takes its built-ins in a struct; a trace pass takes global_invocation_id as an argument", ep.name))
                }
                _ => {}
            }
        }
        ep.stage = naga::ShaderStage::RayGeneration;
        ep.workgroup_size = [0; 3];
        ep.workgroup_size_overrides = None;
    }
    Ok(())
}

impl ShaderInfo {
    /// Whether the module declares the pipeline-overridable constant `name`.
    pub(crate) fn has_override(&self, name: &str) -> bool {
        self.overrides.iter().any(|o| o == name)
    }

    /// The interface of a pass without a shader (an acceleration-structure build).
    pub fn none() -> Self {
        ShaderInfo {
            path: PathBuf::new(),
            source: ShaderSource { text: String::new(), segments: Vec::new(), builtin: false },
            bindings: Vec::new(),
            entry_points: Vec::new(),
            overrides: Vec::new(),
            ray_tracing: None,
        }
    }

    /// The entry point called `name`.
    pub(crate) fn entry(&self, name: &str) -> Option<&EntryPointInfo> {
        self.entry_points.iter().find(|e| e.name == name)
    }

    /// The binding of the variable called `name`.
    pub fn binding(&self, name: &str) -> Option<&ShaderBinding> {
        self.bindings.iter().find(|b| b.name == name)
    }
}

/// Whether a front-end error is one of syntax (tokens, literals, comments) rather than of
/// names or types, which naga's front end also reports while lowering.
fn is_syntax_error(message: &str) -> bool {
    (message.starts_with("expected ") && message.contains(", found \""))
        || message.starts_with("unterminated")
        || message.starts_with("invalid numeric literal")
}

/// Parses, validates and reflects a WGSL file (includes as written).
pub fn reflect(path: &Path, shader_root: &Path, referenced_from: &Location) -> Result<ShaderInfo, GraphError> {
    reflect_with(path, shader_root, referenced_from, &IncludeAliases::new())
}

/// [`reflect`] with include substitutions.
pub fn reflect_with(path: &Path, shader_root: &Path, referenced_from: &Location, aliases: &IncludeAliases) -> Result<ShaderInfo, GraphError> {
    let source = ShaderSource::load(path, shader_root, referenced_from, aliases)?;
    let mut module = naga::front::wgsl::parse_str(&source.text).map_err(|e| parse_error(&e, &source, referenced_from))?;
    // Compute entry points as written (their workgroup sizes size the dispatch), before a
    // ray-tracing module's are made ray-generation shaders.
    let compute_sizes: Vec<(String, [u32; 3])> =
        module.entry_points.iter().filter(|e| e.stage == naga::ShaderStage::Compute).map(|e| (e.name.clone(), e.workgroup_size)).collect();
    let ray_tracing = module.entry_points.iter().any(|e| is_ray_tracing_stage(e.stage));
    if ray_tracing {
        compute_to_ray_generation(&mut module).map_err(|message| {
            GraphError::new(ErrorKind::ShaderInvalid, Location::file_start(path), message)
                .note(referenced_from.clone(), "shader used by this pass")
                .help("the rt-pipeline back-end runs a trace pass's compute entry point as a ray-generation shader")
        })?;
    }
    let info = validate(&module, &source, referenced_from)?;
    let bindings = reflect_bindings(&module, &source);
    let entry_points = reflect_entry_points(&module, &compute_sizes);
    let overrides = module.overrides.iter().filter_map(|(_, o)| o.name.clone()).collect();
    let ray_tracing = ray_tracing.then(|| RayTracingModule { module: std::sync::Arc::new(module), info: std::sync::Arc::new(info) });
    Ok(ShaderInfo { path: path.to_path_buf(), source, bindings, entry_points, overrides, ray_tracing })
}

/// The error of a WGSL file naga's front end rejects, at the first label's line.
fn parse_error(e: &naga::front::wgsl::ParseError, source: &ShaderSource, referenced_from: &Location) -> GraphError {
    let offset = e.labels().next().and_then(|(span, _)| span.to_range()).map(|r| r.start).unwrap_or(0);
    let labels: Vec<String> = e.labels().map(|(_, l)| l.to_string()).filter(|l| !l.is_empty()).collect();
    let err = GraphError::new(
        ErrorKind::ShaderInvalid,
        source.locate(offset),
        format!(
            "WGSL does not {}: {}{}",
            if is_syntax_error(e.message()) { "parse" } else { "validate" },
            e.message(),
            if labels.is_empty() { String::new() } else { format!(" ({})", labels.join("; ")) }
        ),
    )
    .help("fix the WGSL at this line");
    err.note(referenced_from.clone(), "shader used by this pass")
}

/// naga's validation of `module`; an error names the whole chain of causes, at the first span's line.
fn validate(module: &naga::Module, source: &ShaderSource, referenced_from: &Location) -> Result<naga::valid::ModuleInfo, GraphError> {
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    validator.validate(module).map_err(|e| {
        let offset = e.spans().next().and_then(|(span, _)| span.to_range()).map(|r| r.start).unwrap_or(0);
        let mut chain = e.as_inner().to_string();
        let mut inner: Option<&dyn std::error::Error> = std::error::Error::source(e.as_inner());
        while let Some(s) = inner {
            chain.push_str(": ");
            chain.push_str(&s.to_string());
            inner = s.source();
        }
        GraphError::new(ErrorKind::ShaderInvalid, source.locate(offset), format!("WGSL does not validate: {chain}"))
            .note(referenced_from.clone(), "shader used by this pass")
            .help("fix the WGSL at this line")
    })
}

/// The module's `@group @binding` globals, in declaration order.
fn reflect_bindings(module: &naga::Module, source: &ShaderSource) -> Vec<ShaderBinding> {
    let mut bindings = Vec::new();
    for (handle, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        let name = var.name.clone().unwrap_or_default();
        let span = module.global_variables.get_span(handle);
        let location = source.locate(span.to_range().map(|r| r.start).unwrap_or(0));
        let kind = binding_kind(module, var);
        bindings.push(ShaderBinding { name, group: rb.group, binding: rb.binding, kind, location });
    }
    bindings
}

/// What the global `var` binds.
fn binding_kind(module: &naga::Module, var: &naga::GlobalVariable) -> BindingKind {
    let ty = &module.types[var.ty];
    match (&var.space, &ty.inner) {
        (naga::AddressSpace::Handle, naga::TypeInner::Image { dim, arrayed, class }) => match class {
            naga::ImageClass::Sampled { kind, .. } => BindingKind::SampledTexture { dim: *dim, arrayed: *arrayed, kind: *kind },
            naga::ImageClass::Depth { .. } if *dim == naga::ImageDimension::D2 => BindingKind::DepthTexture { arrayed: *arrayed },
            naga::ImageClass::Storage { format, access } => BindingKind::StorageTexture { format: *format, access: *access },
            _ => BindingKind::Other(global_type_name(module, var.space, &ty.inner)),
        },
        (naga::AddressSpace::Handle, naga::TypeInner::Sampler { comparison }) => BindingKind::Sampler { comparison: *comparison },
        (naga::AddressSpace::Handle, naga::TypeInner::AccelerationStructure { .. }) => BindingKind::AccelerationStructure,
        (naga::AddressSpace::Handle, naga::TypeInner::BindingArray { base, size: naga::ArraySize::Dynamic })
            if matches!(
                module.types[*base].inner,
                naga::TypeInner::Image { dim: naga::ImageDimension::D2, arrayed: true, class: naga::ImageClass::Sampled { kind: naga::ScalarKind::Float, .. } }
            ) =>
        {
            BindingKind::TextureBindingArray
        }
        (naga::AddressSpace::Uniform, inner) => {
            BindingKind::Uniform { size: inner.size(module.to_ctx()), members: uniform_members(module, inner), type_name: ty.name.clone() }
        }
        (naga::AddressSpace::Storage { access }, inner) => BindingKind::Storage {
            read_only: !access.contains(naga::StorageAccess::STORE),
            min_size: match inner {
                naga::TypeInner::Array { size: naga::ArraySize::Dynamic, stride, .. } => *stride,
                other => other.size(module.to_ctx()),
            },
        },
        (space, inner) => BindingKind::Other(global_type_name(module, *space, inner)),
    }
}

/// The scalar and vector members of a uniform struct (none for a uniform of another type).
fn uniform_members(module: &naga::Module, inner: &naga::TypeInner) -> Vec<UniformMember> {
    let mut members = Vec::new();
    if let naga::TypeInner::Struct { members: ms, .. } = inner {
        for m in ms {
            let (scalar, components) = match &module.types[m.ty].inner {
                naga::TypeInner::Scalar(s) => (Some(s.kind), 1),
                naga::TypeInner::Vector { size, scalar } => (Some(scalar.kind), *size as u32),
                _ => (None, 0),
            };
            members.push(UniformMember { name: m.name.clone().unwrap_or_default(), offset: m.offset, scalar, components });
        }
    }
    members
}

/// The module's entry points; a compute one keeps the workgroup size it was written with
/// (`compute_sizes`), also where it became a ray-generation shader.
fn reflect_entry_points(module: &naga::Module, compute_sizes: &[(String, [u32; 3])]) -> Vec<EntryPointInfo> {
    let mut entry_points = Vec::new();
    for ep in &module.entry_points {
        let locations = io_locations(module, ep);
        let workgroup_size = compute_sizes.iter().find(|(n, _)| *n == ep.name).map(|(_, s)| *s).unwrap_or(ep.workgroup_size);
        entry_points.push(EntryPointInfo { name: ep.name.clone(), stage: ep.stage, workgroup_size, locations });
    }
    entry_points
}

/// The vertex input locations of a vertex entry point, or the colour output locations of a
/// fragment one (sorted); none for other stages.
fn io_locations(module: &naga::Module, ep: &naga::EntryPoint) -> Vec<u32> {
    let mut locations = Vec::new();
    let mut collect = |binding: &Option<naga::Binding>, ty: naga::Handle<naga::Type>| {
        if let Some(naga::Binding::Location { location, .. }) = binding {
            locations.push(*location);
        } else if binding.is_none() {
            if let naga::TypeInner::Struct { members, .. } = &module.types[ty].inner {
                for m in members {
                    if let Some(naga::Binding::Location { location, .. }) = &m.binding {
                        locations.push(*location);
                    }
                }
            }
        }
    };
    match ep.stage {
        naga::ShaderStage::Vertex => {
            for arg in &ep.function.arguments {
                collect(&arg.binding, arg.ty);
            }
        }
        naga::ShaderStage::Fragment => {
            if let Some(result) = &ep.function.result {
                collect(&result.binding, result.ty);
            }
        }
        _ => {}
    }
    locations.sort_unstable();
    locations
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(root: &Path) -> ShaderSource {
        let shaders = root.join("shaders");
        ShaderSource::load(&shaders.join("forward/forward.wgsl"), &shaders, &Location::new(Path::new("test"), 1, 1), &IncludeAliases::new()).unwrap()
    }

    #[test]
    fn built_in_only_while_every_file_is_the_built_in_copy() {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        // The repository's files on disk are the built-in copies.
        assert!(load(repo).is_builtin());
        let dir = std::env::temp_dir().join(format!("raygraph_builtin_{}", std::process::id()));
        let shaders = dir.join("shaders");
        // Nothing on disk: the embedded copies.
        std::fs::create_dir_all(shaders.join("common")).unwrap();
        assert!(load(&dir).is_builtin());
        // An include edited on disk makes the module a project's.
        let lighting = std::fs::read_to_string(repo.join("shaders/common/lighting.wgsl")).unwrap();
        std::fs::write(shaders.join("common/lighting.wgsl"), format!("{lighting}\n// edited\n")).unwrap();
        let edited = load(&dir);
        assert!(!edited.is_builtin());
        // Byte for byte the same again: built in.
        std::fs::write(shaders.join("common/lighting.wgsl"), &lighting).unwrap();
        assert!(load(&dir).is_builtin());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
