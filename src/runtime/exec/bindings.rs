//! A pass's bindings from shader reflection: the layout entry of every binding, the resource
//! each is bound to (a declared resource, a built-in buffer, the scene, a sampler), the bind
//! groups made of them, one per `@group`, and the pipeline layout. Shared by every kind of
//! pass that has a shader.

use super::params::create_params_buffer;
use super::{AccelLayout, Executor};
use crate::error::{ErrorKind, GraphError, RuntimeError};
use crate::graph::builtins;
use crate::graph::compile::{PlannedPass, ResourceId};
use crate::graph::desc::{PassKind, ResourceDecl};
use crate::graph::reflect::{BindingKind, ShaderBinding, UniformMember};
use crate::runtime::gpu::Gpu;
use crate::runtime::scene_upload::SceneTextures;

/// The `linear_sampler` built-in.
pub(super) fn linear_sampler() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor {
        label: Some("linear"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    }
}

/// The `nearest_sampler` built-in.
pub(super) fn nearest_sampler() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor { label: Some("nearest"), ..Default::default() }
}

/// The resource a pass binds under `name`: one of its declared reads or writes.
pub(super) fn resource_of(pass: &PlannedPass, name: &str) -> Option<ResourceId> {
    pass.reads.iter().chain(&pass.writes).find(|(l, _)| l == name).map(|(_, r)| *r)
}

/// What a pass's shader binds, from reflection: a layout entry per binding (by `@group`) and
/// the resource behind each binding that has one here (samplers are added with the groups;
/// the trace module's group is bound per frame).
pub(super) struct PassBindings {
    pub layout_entries: Vec<(u32, wgpu::BindGroupLayoutEntry)>,
    pub views: Vec<((u32, u32), wgpu::TextureView)>,
    pub view_arrays: Vec<((u32, u32), Vec<wgpu::TextureView>)>,
    pub buffers: Vec<((u32, u32), wgpu::Buffer)>,
    pub params_buffer: Option<((u32, u32), wgpu::Buffer)>,
    pub params_members: Option<(u64, Vec<UniformMember>)>,
}

impl PassBindings {
    /// The layout entries of each bind group, group `g` at index `g` (a group with no
    /// bindings is empty).
    pub(crate) fn layout_groups(&self) -> Vec<Vec<wgpu::BindGroupLayoutEntry>> {
        let count = self.layout_entries.iter().map(|(g, _)| g + 1).max().unwrap_or(0);
        (0..count).map(|g| self.layout_entries.iter().filter(|(lg, _)| *lg == g).map(|(_, e)| *e).collect()).collect()
    }

    /// The pass's `params` uniform and its members, for [`Executor::set_param`].
    pub fn params(&self) -> Option<(wgpu::Buffer, u64, Vec<UniformMember>)> {
        self.params_buffer.as_ref().zip(self.params_members.clone()).map(|((_, buf), (size, members))| (buf.clone(), size, members))
    }
}

/// A pass's bind groups and pipeline layout.
pub(super) struct PassLayout {
    pub layout: wgpu::PipelineLayout,
    pub bind_groups: Vec<wgpu::BindGroup>,
    pub accel_layout: Option<AccelLayout>,
}

impl Executor {
    /// The built-in samplers (linear, nearest).
    pub(super) fn samplers(device: &wgpu::Device) -> (wgpu::Sampler, wgpu::Sampler) {
        (device.create_sampler(&linear_sampler()), device.create_sampler(&nearest_sampler()))
    }

    /// Layout entries and resources of `pass`'s bindings, from reflection, with the textures of
    /// history pairs `swapped` or not (`history`).
    pub(super) fn reflect_bindings(&self, gpu: &Gpu, pass: &PlannedPass, swapped: bool) -> Result<PassBindings, RuntimeError> {
        let visibility = if pass.kind.is_compute() { wgpu::ShaderStages::COMPUTE } else { wgpu::ShaderStages::VERTEX_FRAGMENT };
        let mut out = PassBindings {
            layout_entries: Vec::new(),
            views: Vec::new(),
            view_arrays: Vec::new(),
            buffers: Vec::new(),
            params_buffer: None,
            params_members: None,
        };
        for b in &pass.shader.bindings {
            let ty = self.binding_type(pass, b)?;
            let count = match b.kind {
                BindingKind::TextureBindingArray => {
                    Some(std::num::NonZeroU32::new(self.scene_part(|s| s.textures())?.count()).expect("white texture is always there"))
                }
                _ => None,
            };
            out.layout_entries.push((b.group, wgpu::BindGroupLayoutEntry { binding: b.binding, visibility, ty, count }));

            if let Some(r) = resource_of(pass, &b.name) {
                match &self.plan.resources[r].decl {
                    ResourceDecl::Texture(_) => out.views.push(((b.group, b.binding), self.texture_view_at(r, swapped))),
                    ResourceDecl::Buffer(_) => out.buffers.push(((b.group, b.binding), self.buffer(r).clone())),
                    ResourceDecl::Accel => {} // bound through the trace module's group
                }
                continue;
            }
            self.bind_builtin(gpu, pass, b, &mut out)?;
        }
        Ok(out)
    }

    /// The layout entry's type of binding `b`.
    fn binding_type(&self, pass: &PlannedPass, b: &ShaderBinding) -> Result<wgpu::BindingType, RuntimeError> {
        Ok(match &b.kind {
            BindingKind::SampledTexture { arrayed, kind, .. } => {
                let filterable = match resource_of(pass, &b.name) {
                    Some(r) => matches!(&self.plan.resources[r].decl, ResourceDecl::Texture(t) if t.format.is_filterable()),
                    None => true,
                };
                wgpu::BindingType::Texture {
                    sample_type: match kind {
                        naga::ScalarKind::Uint => wgpu::TextureSampleType::Uint,
                        naga::ScalarKind::Sint => wgpu::TextureSampleType::Sint,
                        _ => wgpu::TextureSampleType::Float { filterable },
                    },
                    view_dimension: if *arrayed { wgpu::TextureViewDimension::D2Array } else { wgpu::TextureViewDimension::D2 },
                    multisampled: false,
                }
            }
            BindingKind::TextureBindingArray => wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2Array,
                multisampled: false,
            },
            BindingKind::AccelerationStructure => wgpu::BindingType::AccelerationStructure { vertex_return: false },
            BindingKind::DepthTexture { arrayed } => wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: if *arrayed { wgpu::TextureViewDimension::D2Array } else { wgpu::TextureViewDimension::D2 },
                multisampled: false,
            },
            BindingKind::StorageTexture { access, .. } => {
                let r = resource_of(pass, &b.name).expect("checked by the compiler");
                let ResourceDecl::Texture(t) = &self.plan.resources[r].decl else { unreachable!() };
                let load = access.contains(naga::StorageAccess::LOAD);
                wgpu::BindingType::StorageTexture {
                    access: if load { wgpu::StorageTextureAccess::ReadWrite } else { wgpu::StorageTextureAccess::WriteOnly },
                    format: t.format.to_wgpu(),
                    view_dimension: wgpu::TextureViewDimension::D2,
                }
            }
            BindingKind::Sampler { comparison } => wgpu::BindingType::Sampler(if *comparison {
                wgpu::SamplerBindingType::Comparison
            } else if b.name == builtins::NEAREST_SAMPLER {
                wgpu::SamplerBindingType::NonFiltering
            } else {
                wgpu::SamplerBindingType::Filtering
            }),
            BindingKind::Uniform { .. } => {
                wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None }
            }
            BindingKind::Storage { read_only, .. } => {
                wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: *read_only }, has_dynamic_offset: false, min_binding_size: None }
            }
            BindingKind::Other(what) => {
                return Err(GraphError::new(ErrorKind::Unsupported, b.location.clone(), format!("binding `{}` of kind {what} is not supported", b.name)).into());
            }
        })
    }

    /// The resource behind built-in binding `b` (the frame uniforms, the debug counters, the
    /// pass's `params`, a part of the scene); samplers and unknown names are left out.
    fn bind_builtin(&self, gpu: &Gpu, pass: &PlannedPass, b: &ShaderBinding, out: &mut PassBindings) -> Result<(), RuntimeError> {
        let at = (b.group, b.binding);
        match b.name.as_str() {
            builtins::FRAME => out.buffers.push((at, self.frame_uniforms.clone())),
            builtins::DEBUG_COUNTERS => out.buffers.push((at, self.debug_counters.clone())),
            builtins::PARAMS => {
                let BindingKind::Uniform { size, members, .. } = &b.kind else { unreachable!() };
                let buf = create_params_buffer(gpu.device(), pass, members, *size as u64);
                out.params_members = Some((*size as u64, members.clone()));
                out.params_buffer = Some((at, buf));
            }
            builtins::SCENE_INSTANCES => out.buffers.push((at, self.scene_part(|s| s.instances())?.clone())),
            builtins::SCENE_MATERIALS => out.buffers.push((at, self.scene_part(|s| s.materials())?.clone())),
            builtins::SCENE_VERTICES => out.buffers.push((at, self.scene_part(|s| s.vertices())?.clone())),
            builtins::SCENE_INDICES => out.buffers.push((at, self.scene_part(|s| s.indices())?.clone())),
            builtins::SCENE_MESHES => out.buffers.push((at, self.scene_part(|s| s.meshes())?.clone())),
            builtins::SCENE_LIGHTS => out.buffers.push((at, self.scene_part(|s| s.lights())?.clone())),
            builtins::SCENE_EMITTERS => out.buffers.push((at, self.scene_part(|s| s.emitters())?.clone())),
            builtins::SCENE_MOTION => out.buffers.push((at, self.scene_part(|s| s.motion())?.clone())),
            builtins::SCENE_ENVIRONMENT => out.views.push((at, self.scene_part(|s| s.environment())?.radiance().1.clone())),
            builtins::SCENE_ENVIRONMENT_IRRADIANCE => out.views.push((at, self.scene_part(|s| s.environment())?.irradiance().1.clone())),
            builtins::SCENE_ENVIRONMENT_PARAMS => out.buffers.push((at, self.scene_part(|s| s.environment())?.params().clone())),
            builtins::SCENE_ENVIRONMENT_TABLE => out.buffers.push((at, self.scene_part(|s| s.environment())?.table().clone())),
            builtins::SCENE_TEXTURES => match self.scene_part(|s| s.textures())? {
                SceneTextures::Array { view, .. } if b.kind != BindingKind::TextureBindingArray => out.views.push((at, view.clone())),
                SceneTextures::Pooled { views: v, .. } if b.kind == BindingKind::TextureBindingArray => out.view_arrays.push((at, v.clone())),
                _ => return Err(RuntimeError::Gpu(format!("pass {}: scene textures were uploaded in the other layout than the shader binds", pass.name))),
            },
            _ => {}
        }
        Ok(())
    }

    /// One bind group per `@group` the shader uses (group 1 holds the scene's texture binding
    /// array, which may not share a group with uniform buffers), but a trace pass's trace
    /// module group, bound per frame from the acceleration-structure cache; and the pipeline
    /// layout over them.
    pub(super) fn create_bind_groups(&self, gpu: &Gpu, pass: &PlannedPass, bindings: &PassBindings) -> PassLayout {
        let device = gpu.device();
        let shader = &pass.shader;
        let group_count = shader.bindings.iter().map(|b| b.group + 1).max().unwrap_or(0);
        let entries = self.binding_resources(pass, bindings);
        let view_refs: Vec<((u32, u32), Vec<&wgpu::TextureView>)> = bindings.view_arrays.iter().map(|(k, v)| (*k, v.iter().collect())).collect();
        let array_entries = view_refs.iter().map(|(k, a)| (*k, wgpu::BindingResource::TextureViewArray(a)));
        let entries: Vec<((u32, u32), wgpu::BindingResource)> = array_entries.chain(entries).collect();
        let mut layouts = Vec::new();
        let mut bind_groups = Vec::new();
        let mut accel_layout = None;
        let mut layout_groups = bindings.layout_groups();
        layout_groups.resize(group_count as usize, Vec::new());
        for (g, layout_g) in (0..group_count).zip(layout_groups) {
            let bgl =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(&format!("{} group {g}", pass.name)), entries: &layout_g });
            if pass.kind == PassKind::Trace && g == builtins::ACCEL_GROUP {
                // Bound per frame from the acceleration-structure cache.
                let names = layout_g
                    .iter()
                    .map(|e| shader.bindings.iter().find(|b| b.group == g && b.binding == e.binding).map(|b| b.name.clone()).unwrap_or_default())
                    .collect();
                accel_layout = Some((bgl.clone(), layout_g, names));
            } else {
                let entries_g: Vec<wgpu::BindGroupEntry> = entries
                    .iter()
                    .filter(|((eg, _), _)| *eg == g)
                    .map(|((_, binding), r)| wgpu::BindGroupEntry { binding: *binding, resource: r.clone() })
                    .collect();
                bind_groups.push(device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("{} group {g}", pass.name)),
                    layout: &bgl,
                    entries: &entries_g,
                }));
            }
            layouts.push(bgl);
        }
        let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some(&pass.name), bind_group_layouts: &layout_refs, immediate_size: 0 });
        PassLayout { layout, bind_groups, accel_layout }
    }

    /// The bind group entries of views, buffers, the `params` uniform and the samplers, by
    /// (group, binding), in that order.
    fn binding_resources<'a>(&'a self, pass: &PlannedPass, bindings: &'a PassBindings) -> Vec<((u32, u32), wgpu::BindingResource<'a>)> {
        let mut entries: Vec<((u32, u32), wgpu::BindingResource)> = Vec::new();
        entries.extend(bindings.views.iter().map(|(k, v)| (*k, wgpu::BindingResource::TextureView(v))));
        entries.extend(bindings.buffers.iter().chain(bindings.params_buffer.iter()).map(|(k, buf)| (*k, buf.as_entire_binding())));
        let (linear, nearest) = &self.samplers;
        for b in &pass.shader.bindings {
            match b.name.as_str() {
                builtins::LINEAR_SAMPLER => entries.push(((b.group, b.binding), wgpu::BindingResource::Sampler(linear))),
                builtins::NEAREST_SAMPLER => entries.push(((b.group, b.binding), wgpu::BindingResource::Sampler(nearest))),
                builtins::ENVIRONMENT_SAMPLER => {
                    if let Some(env) = self.scene.as_ref().and_then(|s| s.environment()) {
                        entries.push(((b.group, b.binding), wgpu::BindingResource::Sampler(env.sampler())));
                    }
                }
                _ => {}
            }
        }
        entries
    }
}

/// The module of `pass`'s shader, with the runtime checks of where it comes from: a trace
/// pass's module is built on the project's traversal (`ShaderOrigin::TracePass`); a layer's
/// shader made only of built-in files is part of the program (`ShaderOrigin::BuiltInLayer`);
/// anything else is a project file with every check (`ShaderOrigin::Project`).
pub(super) fn shader_module(gpu: &Gpu, pass: &PlannedPass) -> wgpu::ShaderModule {
    use crate::gpu_util::ShaderOrigin;
    let origin = match pass.kind {
        PassKind::Trace => ShaderOrigin::TracePass,
        _ if pass.shader.source.is_builtin() => ShaderOrigin::BuiltInLayer,
        _ => ShaderOrigin::Project,
    };
    gpu.shader_module(&pass.shader.path.display().to_string(), pass.shader.source.text(), origin)
}
