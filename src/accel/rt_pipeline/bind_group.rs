//! The hal bind groups of a trace pass, made in named steps: the Vulkan handles of the wgpu
//! textures and buffers read (one wgpu guard at a time), a texture view per bound texture and
//! a sampler per sampler binding made, the entries listed in the order of the layout's, and
//! the bind group made over them.

use super::bindings::{AccelBuffers, RtBinding, RtResource};
use super::hal_objects::{count_made, destroyed, hal_error, with_hal, HalAccel, HalBuffer, HalDevice, HalObjects, Vk};
use super::structures::RtAccel;
use crate::error::RuntimeError;
use wgpu::hal;
use wgpu::hal::Device as _;

/// A texture a group binds: the Vulkan image of the wgpu texture, and the view's dimension
/// and uses.
struct BoundImage {
    image: ash::vk::Image,
    texture: wgpu::Texture,
    dimension: wgpu::TextureViewDimension,
    uses: wgpu::TextureUses,
}

/// A hal bind group of layout `layout` over `bindings` (one group's, in the layout's order);
/// `accel` binds the trace module's bindings. Returns the group and the objects made for it
/// (texture views, samplers), which live as long as it.
pub(super) fn make_group(
    device: &wgpu::Device,
    label: &str,
    layout: &hal::vulkan::BindGroupLayout,
    bindings: &[&RtBinding],
    accel: Option<(&RtAccel, &AccelBuffers)>,
) -> Result<(hal::vulkan::BindGroup, HalObjects), RuntimeError> {
    let (images, buffers) = raw_handles(bindings, accel)?;
    with_hal(device, |d| {
        let mut extra = HalObjects::default();
        let made = (|| -> Result<hal::vulkan::BindGroup, RuntimeError> {
            make_views(d, label, &images, &mut extra)?;
            // SAFETY: handles of live wgpu buffers, not owned by the hal objects (which are
            // dropped, never destroyed, after the bind group is made).
            let hal_wgpu_buffers: Vec<HalBuffer> = buffers.iter().map(|&b| unsafe { HalBuffer::from_raw(b) }).collect();
            make_samplers(d, bindings, &mut extra)?;
            let resources = GroupResources { bindings, views: &extra.texture_views, buffers: &hal_wgpu_buffers, accel };
            let entries = resources.entries()?;
            let sampler_refs: Vec<&hal::vulkan::Sampler> = extra.samplers.iter().collect();
            // SAFETY: every resource outlives the bind group (wgpu objects kept in the pass's
            // bindings or by the caller, views and samplers in `extra`, the acceleration
            // structures in the caller's `RtAccel`), and every entry matches its layout entry
            // (same list, same order).
            unsafe {
                d.create_bind_group(&hal::BindGroupDescriptor {
                    label: Some(label),
                    layout,
                    buffers: &entries.buffers,
                    samplers: &sampler_refs,
                    textures: &entries.textures,
                    entries: &entries.entries,
                    acceleration_structures: &entries.accels,
                    external_textures: &[],
                })
            }
            .map(count_made)
            .map_err(|e| hal_error("creating a bind group", e))
        })();
        match made {
            Ok(bg) => Ok((bg, extra)),
            Err(e) => {
                destroy_unbound(d, &mut extra);
                Err(e)
            }
        }
    })
}

/// Destroys the views and samplers made for a bind group that was not made.
fn destroy_unbound(d: &HalDevice, extra: &mut HalObjects) {
    destroyed(extra.texture_views.len() + extra.samplers.len());
    // SAFETY: objects made for a bind group that was not made.
    unsafe {
        for v in extra.texture_views.drain(..) {
            d.destroy_texture_view(v);
        }
        for s in extra.samplers.drain(..) {
            d.destroy_sampler(s);
        }
    }
}

/// The Vulkan handles of the wgpu textures and buffers `bindings` name (the cache's buffers
/// among the trace module's bindings through `accel`), in binding order, one guard at a time
/// (wgpu-core forbids holding two of its hal guards at once).
fn raw_handles(bindings: &[&RtBinding], accel: Option<(&RtAccel, &AccelBuffers)>) -> Result<(Vec<BoundImage>, Vec<ash::vk::Buffer>), RuntimeError> {
    let raw_buffer = |buffer: &wgpu::Buffer| -> Result<ash::vk::Buffer, RuntimeError> {
        // SAFETY: only the handle is read; the wgpu buffer outlives the bind group (kept in
        // the pass's bindings, or the cache's counters owned by the caller).
        unsafe { buffer.as_hal::<Vk>().map(|b| b.raw_handle()) }.ok_or_else(|| hal_error("binding", "not a Vulkan buffer"))
    };
    let raw_image = |texture: &wgpu::Texture| -> Result<ash::vk::Image, RuntimeError> {
        // SAFETY: as above, for the texture's image.
        unsafe { texture.as_hal::<Vk>().map(|t| t.raw_handle()) }.ok_or_else(|| hal_error("binding", "not a Vulkan texture"))
    };
    let mut images: Vec<BoundImage> = Vec::new();
    let mut buffers: Vec<ash::vk::Buffer> = Vec::new();
    for b in bindings {
        match &b.resource {
            RtResource::Texture { texture, uses, .. } => {
                let dimension = match b.entry.ty {
                    wgpu::BindingType::Texture { view_dimension, .. } | wgpu::BindingType::StorageTexture { view_dimension, .. } => view_dimension,
                    _ => wgpu::TextureViewDimension::D2,
                };
                images.push(BoundImage { image: raw_image(texture)?, texture: texture.clone(), dimension, uses: *uses });
            }
            RtResource::Textures(list) => {
                for (t, _) in list {
                    let image = raw_image(t)?;
                    images.push(BoundImage { image, texture: t.clone(), dimension: wgpu::TextureViewDimension::D2Array, uses: wgpu::TextureUses::RESOURCE });
                }
            }
            RtResource::Buffer { buffer, .. } => buffers.push(raw_buffer(buffer)?),
            RtResource::Accel(name) if !RtAccel::owns_binding(name) => {
                let (_, cache) = accel.ok_or_else(|| hal_error("binding", "the trace module's group needs the acceleration structure"))?;
                let (buffer, _, _) = cache(name).ok_or_else(|| RuntimeError::Gpu(format!("the rt-pipeline back-end has no binding `{name}`")))?;
                buffers.push(raw_buffer(&buffer)?);
            }
            RtResource::Sampler(_) | RtResource::Accel(_) => {}
        }
    }
    Ok((images, buffers))
}

/// A view of each of `images` (into `extra`), labelled `label`.
fn make_views(d: &HalDevice, label: &str, images: &[BoundImage], extra: &mut HalObjects) -> Result<(), RuntimeError> {
    for BoundImage { image, texture, dimension, uses } in images {
        let size = texture.size();
        // SAFETY: `image` is the wgpu texture's, described as wgpu made it; the hal
        // texture neither owns the image nor its memory (a no-op drop callback,
        // external memory) and is dropped once the view is made. The view is ours
        // and destroyed with the bind group (`HalObjects`).
        let view = unsafe {
            let hal_texture = d.texture_from_raw(
                *image,
                &hal::TextureDescriptor {
                    label: None,
                    size,
                    mip_level_count: texture.mip_level_count(),
                    sample_count: texture.sample_count(),
                    dimension: texture.dimension(),
                    format: texture.format(),
                    usage: *uses,
                    memory_flags: hal::MemoryFlags::empty(),
                    view_formats: Vec::new(),
                },
                Some(Box::new(|| {})),
                hal::vulkan::TextureMemory::External,
            );
            d.create_texture_view(
                &hal_texture,
                &hal::TextureViewDescriptor {
                    label: Some(label),
                    format: texture.format(),
                    dimension: *dimension,
                    usage: *uses,
                    range: wgpu::ImageSubresourceRange::default(),
                },
            )
        }
        .map(count_made)
        .map_err(|e| hal_error("creating a texture view", e))?;
        extra.texture_views.push(view);
    }
    Ok(())
}

/// A sampler for each sampler binding of `bindings` (into `extra`).
fn make_samplers(d: &HalDevice, bindings: &[&RtBinding], extra: &mut HalObjects) -> Result<(), RuntimeError> {
    for b in bindings {
        if let RtResource::Sampler(desc) = &b.resource {
            // SAFETY: a sampler from a plain descriptor, destroyed with the group.
            let sampler = unsafe {
                d.create_sampler(&hal::SamplerDescriptor {
                    label: desc.label,
                    address_modes: [desc.address_mode_u, desc.address_mode_v, desc.address_mode_w],
                    mag_filter: desc.mag_filter,
                    min_filter: desc.min_filter,
                    mipmap_filter: desc.mipmap_filter,
                    lod_clamp: desc.lod_min_clamp..desc.lod_max_clamp,
                    compare: desc.compare,
                    anisotropy_clamp: desc.anisotropy_clamp,
                    border_color: desc.border_color,
                })
            }
            .map(count_made)
            .map_err(|e| hal_error("creating a sampler", e))?;
            extra.samplers.push(sampler);
        }
    }
    Ok(())
}

/// What one bind group's entries refer to: its `bindings`, the `views` made for its textures
/// and the wgpu `buffers` as hal buffers (both in binding order), and the acceleration
/// structure with the cache's buffers for the trace module's bindings.
struct GroupResources<'a> {
    bindings: &'a [&'a RtBinding],
    views: &'a [hal::vulkan::TextureView],
    buffers: &'a [HalBuffer],
    accel: Option<(&'a RtAccel, &'a AccelBuffers<'a>)>,
}

/// A bind group's entries and the resource arrays they index.
struct GroupEntries<'a> {
    buffers: Vec<hal::BufferBinding<'a, HalBuffer>>,
    textures: Vec<hal::TextureBinding<'a, hal::vulkan::TextureView>>,
    accels: Vec<&'a HalAccel>,
    entries: Vec<hal::BindGroupEntry>,
}

impl<'a> GroupResources<'a> {
    /// An entry per binding, each indexing the resource arrays it adds to.
    fn entries(&self) -> Result<GroupEntries<'a>, RuntimeError> {
        let mut out = GroupEntries { buffers: Vec::new(), textures: Vec::new(), accels: Vec::new(), entries: Vec::new() };
        let (mut vi, mut bi, mut si) = (0, 0, 0);
        for b in self.bindings {
            let (resource_index, count) = match &b.resource {
                RtResource::Texture { uses, .. } => {
                    out.textures.push(hal::TextureBinding { view: &self.views[vi], usage: *uses });
                    vi += 1;
                    (out.textures.len() - 1, 1)
                }
                RtResource::Textures(list) => {
                    let start = out.textures.len();
                    for _ in list {
                        out.textures.push(hal::TextureBinding { view: &self.views[vi], usage: wgpu::TextureUses::RESOURCE });
                        vi += 1;
                    }
                    (start, list.len())
                }
                RtResource::Buffer { offset, size, .. } => {
                    // Offset and size as the executor binds the same buffer for a compute pass.
                    out.buffers.push(hal::BufferBinding::new_unchecked(&self.buffers[bi], *offset, *size));
                    bi += 1;
                    (out.buffers.len() - 1, 1)
                }
                RtResource::Sampler(_) => {
                    si += 1;
                    (si - 1, 1)
                }
                RtResource::Accel(name) => self.accel_entry(name, &mut out, &mut bi)?,
            };
            out.entries.push(hal::BindGroupEntry { binding: b.entry.binding, resource_index: resource_index as u32, count: count as u32 });
        }
        Ok(out)
    }

    /// The trace module's binding `name`: the TLAS, a geometry array of the `RtAccel`, or one
    /// of the cache's buffers (the next of the hal buffers, `bi`). Returns (resource index,
    /// count).
    fn accel_entry(&self, name: &str, out: &mut GroupEntries<'a>, bi: &mut usize) -> Result<(usize, usize), RuntimeError> {
        let (rt, cache) = self.accel.ok_or_else(|| hal_error("binding", "the trace module's group needs the acceleration structure"))?;
        if name == "accel_tlas" {
            out.accels.push(rt.tlas().ok_or_else(|| hal_error("binding", "the TLAS is not built"))?);
            return Ok((out.accels.len() - 1, 1));
        }
        let buffer = match RtAccel::GEOMETRY_BINDINGS.iter().position(|n| *n == name) {
            Some(i) => {
                let buffer = rt.geometry_buffer(i).ok_or_else(|| hal_error("binding", "the geometry arrays are not built"))?;
                hal::BufferBinding::new_unchecked(buffer, 0, None)
            }
            // The cache's buffers (counters, alpha records), found with the handles.
            None => {
                let (_, offset, size) = cache(name).expect("found when the handles were read");
                *bi += 1;
                hal::BufferBinding::new_unchecked(&self.buffers[*bi - 1], offset, size)
            }
        };
        out.buffers.push(buffer);
        Ok((out.buffers.len() - 1, 1))
    }
}
