//! The shader interface check: a pass's entry points, colour attachments and vertex inputs,
//! and every binding of its shader matched by name against the pass's resources and the
//! built-ins ([`crate::graph::builtins`]) with the type each needs.

use super::options::{CompileOptions, Project};
use super::plan::{PlannedResource, ResourceId};
use super::resolve::ResolvedNode;
use super::schedule::PassNode;
use super::source::SourceText;
use crate::error::{ErrorKind, GraphError, Location};
use crate::graph::builtins;
use crate::graph::desc::*;
use crate::graph::reflect::{self, BindingKind, ShaderInfo};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// Reflects the shader of every pass, kept or culled (a broken file is an error either way),
/// each file once, and checks the pass's interface; the shaders in the order of `passes`.
pub(super) fn check_shaders(
    project: &Project,
    options: &CompileOptions,
    nodes: &[ResolvedNode],
    passes: &[PassNode],
    resources: &[PlannedResource],
) -> Result<Vec<Arc<ShaderInfo>>, GraphError> {
    let includes = options.all_includes();
    let mut shader_cache: HashMap<PathBuf, Arc<ShaderInfo>> = HashMap::new();
    let mut shaders: Vec<Arc<ShaderInfo>> = Vec::new();
    for p in passes {
        let node = &nodes[p.node];
        let pass = &node.layer.passes[p.index];
        // Passes without a shader: the `Accel` node's build, and Rust passes (their resources
        // are the ones the layer file declares).
        if matches!(pass.kind, PassKind::AccelBuild | PassKind::Rust) {
            shaders.push(Arc::new(ShaderInfo::none()));
            continue;
        }
        let path = project.shaders_dir.join(&pass.shader);
        let shader_loc = node.layer_src.locate(&["passes", &SourceText::quoted(&pass.name), "shader"]);
        let info = match shader_cache.get(&path) {
            Some(info) => info.clone(),
            None => {
                let info = Arc::new(reflect::reflect_with(&path, &project.shaders_dir, &shader_loc, &includes)?);
                shader_cache.insert(path.clone(), info.clone());
                info
            }
        };
        check_interface(node, pass, p, &info, resources)?;
        shaders.push(info);
    }
    Ok(shaders)
}

/// One pass against its shader: what the interface checks need, and how they report.
struct PassInterface<'a> {
    node: &'a ResolvedNode,
    pass: &'a PassDesc,
    p: &'a PassNode,
    info: &'a ShaderInfo,
    resources: &'a [PlannedResource],
    shader_file: PathBuf,
}

impl PassInterface<'_> {
    /// A `BindingMismatch` at the pass, noting the place in the shader.
    fn mismatch(&self, msg: String, shader_loc: Location, help: &str) -> GraphError {
        GraphError::new(ErrorKind::BindingMismatch, self.p.location.clone(), format!("layer `{}`, pass `{}`: {msg}", self.node.layer_name, self.pass.name))
            .note(shader_loc, format!("in {}", self.shader_file.display()))
            .help(help.to_string())
    }

    fn file_loc(&self) -> Location {
        Location::file_start(&self.shader_file)
    }

    /// Whether the shader has an entry point `name` of `stage`.
    fn stage_ok(&self, name: &str, stage: naga::ShaderStage) -> bool {
        self.info.entry(name).map(|e| e.stage == stage).unwrap_or(false)
    }
}

/// Matches a pass's shader bindings by name against its declared resources and the built-ins.
fn check_interface(node: &ResolvedNode, pass: &PassDesc, p: &PassNode, info: &ShaderInfo, resources: &[PlannedResource]) -> Result<(), GraphError> {
    if matches!(pass.kind, PassKind::AccelBuild | PassKind::Rust) {
        return Ok(());
    }
    let it = PassInterface { node, pass, p, info, resources, shader_file: info.source.main_file().to_path_buf() };
    match pass.kind {
        PassKind::AccelBuild | PassKind::Rust => {}
        PassKind::Compute | PassKind::Trace => check_compute_entry(&it)?,
        PassKind::Fullscreen | PassKind::SceneRaster => check_render_entries(&it)?,
    }
    // Every binding the shader declares must be a declared resource or a built-in.
    for b in &info.bindings {
        check_binding(&it, b)?;
    }
    // Every declared read (and compute write) must be bound by the shader.
    for (local, r) in p.reads.iter().chain(p.writes.iter().filter(|_| pass.kind.is_compute())) {
        if resources[*r].decl != ResourceDecl::Accel && info.binding(local).is_none() {
            return Err(it.mismatch(
                format!("the pass declares `{local}` ({}) but the shader has no binding named `{local}`", resources[*r].name),
                it.file_loc(),
                "declare `@group(0) @binding(N) var <name>: ...` in the shader, or remove it from the pass",
            ));
        }
    }
    Ok(())
}

/// A compute or trace pass: its compute (or ray-generation) entry point, and exactly one
/// acceleration structure read by trace passes only.
fn check_compute_entry(it: &PassInterface) -> Result<(), GraphError> {
    let (pass, file_loc) = (it.pass, it.file_loc());
    let entry = entry_name(pass);
    let accel_reads = it.p.reads.iter().filter(|(_, r)| it.resources[*r].decl == ResourceDecl::Accel).count();
    let binds_trace = it.info.bindings.iter().any(|b| builtins::is_accel_binding(&b.name));
    // The rt-pipeline back-end's trace module makes a trace pass's compute entry point
    // a ray-generation shader (reflect::compute_to_ray_generation).
    let ray_generation = pass.kind == PassKind::Trace && it.stage_ok(&entry, naga::ShaderStage::RayGeneration);
    if !it.stage_ok(&entry, naga::ShaderStage::Compute) && !ray_generation {
        return Err(it.mismatch(
            format!("the shader has no compute entry point `{entry}`"),
            file_loc,
            "add `@compute @workgroup_size(8, 8) fn ...` or set `entry:` in the pass",
        ));
    }
    if pass.kind == PassKind::Trace && (accel_reads != 1 || !binds_trace) {
        return Err(it.mismatch(
            format!(
                "a trace pass reads exactly one acceleration structure and includes the trace module; this one reads {accel_reads} and {} it",
                if binds_trace { "includes" } else { "does not include" }
            ),
            file_loc,
            "add the layer's `Accel` input to `reads` and `//#include \"trace/trace.wgsl\"` to the shader",
        ));
    }
    if pass.kind == PassKind::Compute && accel_reads > 0 {
        return Err(it.mismatch("a compute pass reads an acceleration structure".into(), file_loc, "make it `kind: Trace`"));
    }
    Ok(())
}

/// A fullscreen or scene-raster pass: its vertex and fragment entry points, one fragment
/// output per colour attachment, at most one depth attachment, and the scene's vertex inputs.
fn check_render_entries(it: &PassInterface) -> Result<(), GraphError> {
    let (pass, p, resources, file_loc) = (it.pass, it.p, it.resources, it.file_loc());
    let entry = entry_name(pass);
    let vs = pass.vertex_entry.clone().unwrap_or_else(|| "vs_main".into());
    if !it.stage_ok(&vs, naga::ShaderStage::Vertex) {
        return Err(it.mismatch(
            format!("the shader has no vertex entry point `{vs}`"),
            file_loc,
            "add a `@vertex` function or set `vertex_entry:` in the pass",
        ));
    }
    if !it.stage_ok(&entry, naga::ShaderStage::Fragment) {
        return Err(it.mismatch(
            format!("the shader has no fragment entry point `{entry}`"),
            file_loc,
            "add a `@fragment` function or set `entry:` in the pass",
        ));
    }
    let colors: Vec<&(String, ResourceId)> = p.writes.iter().filter(|(_, r)| !resources[*r].decl.is_depth_texture()).collect();
    let outs = &it.info.entry(&entry).map(|e| e.locations.clone()).unwrap_or_default();
    let expected: Vec<u32> = (0..colors.len() as u32).collect();
    if *outs != expected {
        return Err(it.mismatch(
            format!(
                "the pass writes {} colour attachment(s) ({}), but `{entry}` writes {}",
                colors.len(),
                colors.iter().map(|(l, _)| l.as_str()).collect::<Vec<_>>().join(", "),
                if outs.is_empty() { "no @location".to_string() } else { outs.iter().map(|l| format!("@location({l})")).collect::<Vec<_>>().join(", ") }
            ),
            file_loc,
            "make the fragment outputs @location(0..n) match the order of `writes`",
        ));
    }
    let depth_writes = p.writes.iter().filter(|(_, r)| resources[*r].decl.is_depth_texture()).count();
    if depth_writes > 1 {
        return Err(it.mismatch("the pass writes more than one depth texture".into(), file_loc, "write at most one Depth32Float texture"));
    }
    if pass.translucent && (depth_writes > 0 || colors.is_empty()) {
        return Err(it.mismatch(
            "a translucent pass blends into colour targets and has no depth attachment".into(),
            file_loc,
            "write colour textures only, and read the opaque pass's depth as a texture to test against",
        ));
    }
    if pass.kind == PassKind::SceneRaster {
        let vs_locs = it.info.entry(&vs).map(|e| e.locations.clone()).unwrap_or_default();
        if let Some(bad) = vs_locs.iter().find(|l| **l > 2) {
            return Err(it.mismatch(
                format!("vertex input @location({bad}) does not exist"),
                file_loc,
                "scene vertices provide @location(0) position, (1) normal, (2) uv",
            ));
        }
    }
    Ok(())
}

/// One shader binding: in its group, and a resource of the pass (of the type the resource
/// needs) or a built-in (of the built-in's type).
fn check_binding(it: &PassInterface, b: &reflect::ShaderBinding) -> Result<(), GraphError> {
    let want_group = if b.name == builtins::SCENE_TEXTURES {
        builtins::SCENE_TEXTURES_GROUP
    } else if builtins::is_accel_binding(&b.name) {
        builtins::ACCEL_GROUP
    } else if builtins::is_environment_binding(&b.name) {
        builtins::ENVIRONMENT_GROUP
    } else {
        0
    };
    if b.group != want_group {
        return Err(it.mismatch(
            format!("binding `{}` is in @group({}); it lives in @group({want_group})", b.name, b.group),
            b.location.clone(),
            &format!("use @group({want_group}) (bindings live in @group(0), except `scene_textures`, which is in @group(1): a binding array may not share a group with uniform buffers, the trace module's `accel_*` in @group(2) and the environment map's in @group(3): shaders/common/environment.wgsl)"),
        ));
    }
    let read = it.p.reads.iter().find(|(l, _)| *l == b.name);
    let write = it.p.writes.iter().find(|(l, _)| *l == b.name);
    let expected: Option<String> = if let Some((_, r)) = read {
        expected_for_read(&it.resources[*r].decl, b)
    } else if let Some((_, r)) = write {
        expected_for_write(it.pass.kind, &it.resources[*r].decl, b)
    } else if builtins::is_accel_binding(&b.name) {
        (it.pass.kind != PassKind::Trace).then(|| "no trace-module binding: only `kind: Trace` passes trace rays".to_string())
    } else if builtins::is_builtin(&b.name) {
        check_builtin(it.node, b)?
    } else {
        return Err(it.mismatch(
            format!("shader binding `{}` ({}) is not a resource of this pass", b.name, b.kind.describe()),
            b.location.clone(),
            "add it to the pass's `reads` or `writes` (declared in the layer), or remove it from the shader",
        ));
    };
    if let Some(want) = expected {
        return Err(it.mismatch(
            format!("shader binding `{}` is {}, but the pass's resource needs {want}", b.name, b.kind.describe()),
            b.location.clone(),
            "change the WGSL declaration or the resource's format in the layer file",
        ));
    }
    Ok(())
}

/// What a binding of a resource the pass reads must be, if `b` is not that.
fn expected_for_read(decl: &ResourceDecl, b: &reflect::ShaderBinding) -> Option<String> {
    match decl {
        ResourceDecl::Texture(t) if t.format.is_depth() => {
            let want = BindingKind::DepthTexture { arrayed: t.layers > 1 };
            (b.kind != want).then(|| want.describe())
        }
        ResourceDecl::Texture(t) => {
            let kind = if t.format.is_uint() { naga::ScalarKind::Uint } else { naga::ScalarKind::Float };
            let want = BindingKind::SampledTexture { dim: naga::ImageDimension::D2, arrayed: t.layers > 1, kind };
            (b.kind != want).then(|| want.describe())
        }
        ResourceDecl::Buffer(_) => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read>".to_string()),
        ResourceDecl::Accel => Some("no binding of that name (the trace module binds the acceleration structure)".into()),
    }
}

/// What a binding of a resource a pass of `kind` writes must be, if `b` is not that.
fn expected_for_write(kind: PassKind, decl: &ResourceDecl, b: &reflect::ShaderBinding) -> Option<String> {
    if !kind.is_compute() {
        return Some("no binding (it is a render attachment of this pass)".into());
    }
    match decl {
        ResourceDecl::Texture(t) => match t.format.to_storage() {
            None => Some(format!("nothing: {} cannot be a storage texture", t.format)),
            Some(fmt) => match &b.kind {
                BindingKind::StorageTexture { format, access } if *format == fmt && access.contains(naga::StorageAccess::STORE) => None,
                _ => Some(BindingKind::StorageTexture { format: fmt, access: naga::StorageAccess::STORE }.describe()),
            },
        },
        ResourceDecl::Buffer(_) => (!matches!(b.kind, BindingKind::Storage { read_only: false, .. })).then(|| "var<storage, read_write>".to_string()),
        ResourceDecl::Accel => Some("nothing: only an Accel node writes an acceleration structure".into()),
    }
}

/// Checks a built-in binding's type; `Err` for a hard error, `Ok(Some(expected))` for a mismatch.
fn check_builtin(node: &ResolvedNode, b: &reflect::ShaderBinding) -> Result<Option<String>, GraphError> {
    Ok(match b.name.as_str() {
        builtins::FRAME => match &b.kind {
            BindingKind::Uniform { size, .. } if *size == builtins::frame_uniform_size() => None,
            _ => Some(format!("var<uniform> frame: Frame ({} bytes, from common/frame.wgsl)", builtins::frame_uniform_size())),
        },
        builtins::DEBUG_COUNTERS => {
            (!matches!(b.kind, BindingKind::Storage { read_only: false, .. })).then(|| "var<storage, read_write> array<atomic<u32>>".into())
        }
        builtins::SCENE_INSTANCES => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Instance>".into()),
        builtins::SCENE_MATERIALS => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Material>".into()),
        builtins::SCENE_LIGHTS => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<Light>".into()),
        builtins::SCENE_MOTION => (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> array<mat4x4<f32>>".into()),
        builtins::SCENE_VERTICES | builtins::SCENE_INDICES | builtins::SCENE_MESHES => {
            (!matches!(b.kind, BindingKind::Storage { read_only: true, .. })).then(|| "var<storage, read> (declared in common/scene.wgsl)".into())
        }
        builtins::SCENE_TEXTURES => {
            // The texture array everywhere, or a binding array where the device has them
            // (chosen through the `common/scene_textures.wgsl` include).
            let array = BindingKind::SampledTexture { dim: naga::ImageDimension::D2, arrayed: true, kind: naga::ScalarKind::Float };
            (b.kind != array && b.kind != BindingKind::TextureBindingArray)
                .then(|| format!("var scene_textures: SceneTextures (from common/scene_textures.wgsl), i.e. {}", array.describe()))
        }
        builtins::LINEAR_SAMPLER | builtins::NEAREST_SAMPLER => (b.kind != BindingKind::Sampler { comparison: false }).then(|| "sampler".into()),
        builtins::PARAMS => match &b.kind {
            BindingKind::Uniform { members, .. } => {
                for m in members {
                    if m.name.starts_with('_') {
                        continue;
                    }
                    let Some(decl) = node.layer.params.get(&m.name) else {
                        return Ok(Some(format!(
                            "only members named after the layer's parameters; `{}` is not one (declared: {})",
                            m.name,
                            node.layer.params.keys().cloned().collect::<Vec<_>>().join(", ")
                        )));
                    };
                    let ok = matches!(
                        (decl, m.scalar, m.components),
                        (ParamDecl::Float { .. }, Some(naga::ScalarKind::Float), 1)
                            | (ParamDecl::Int { .. } | ParamDecl::Enum { .. }, Some(naga::ScalarKind::Sint | naga::ScalarKind::Uint), 1)
                            | (ParamDecl::Bool { .. }, Some(naga::ScalarKind::Uint), 1)
                    );
                    if !ok {
                        let want = match decl {
                            ParamDecl::Float { .. } => "f32",
                            ParamDecl::Int { .. } | ParamDecl::Enum { .. } => "i32 or u32",
                            ParamDecl::Bool { .. } => "u32",
                        };
                        return Ok(Some(format!("member `{}` of type {want} (parameter `{}` is a {})", m.name, m.name, decl.type_name())));
                    }
                }
                None
            }
            _ => Some("var<uniform> params: <struct of the layer's parameters>".into()),
        },
        _ => None,
    })
}

/// The pass's entry point: `entry`, or `cs_main` (compute, trace) or `fs_main` (render).
pub(super) fn entry_name(pass: &PassDesc) -> String {
    pass.entry.clone().unwrap_or_else(|| match pass.kind {
        PassKind::Compute | PassKind::Trace => "cs_main".into(),
        // A Rust pass has no default: the executor reports one that names none.
        PassKind::Rust => String::new(),
        _ => "fs_main".into(),
    })
}
