//! [`RtAccel`]: the `rt-pipeline` back-end's acceleration structures, built through wgpu-hal
//! (see the module docs of [`super`]). An update runs as steps: the geometry arrays uploaded,
//! the changed units' BLAS built, the TLAS's instances written and the TLAS built, all
//! recorded into one command buffer; then what the update made replaces what it retires.

use super::hal_objects::{
    alignments, count_made, device_buffer, hal_error, memory_barrier, record_raw, vk_all_commands, vk_rt_and_build, Alignments, HalAccel, HalBuffer, HalDevice,
    HalObjects,
};
use super::packing::{pack, Geometry, Packed};
use crate::accel::alpha::instance_tested as alpha_tested;
use crate::error::RuntimeError;
use crate::scene::Scene;
use wgpu::hal;
use wgpu::hal::{CommandEncoder as _, Device as _};

/// The acceleration structures of a scene, built through wgpu-hal (see the module docs): a
/// BLAS per unit (mesh, or instance without de-duplication) rebuilt only when its unit
/// changed, and a TLAS and the closest-hit shader's geometry arrays made again on every change.
pub struct RtAccel {
    device: wgpu::Device,
    /// Per unit; `None` for a unit without a valid triangle (its instances are left out).
    blases: Vec<Option<HalAccel>>,
    /// Per unit, the (triangle count, opaque) of each geometry its BLAS was built with.
    blas_kinds: Vec<Option<Vec<(u32, bool)>>>,
    tlas: Option<HalAccel>,
    /// The positions, indices, per-instance first triangles and the merged layout's triangle
    /// owners (`accel_positions`, `accel_indices`, `accel_first_triangle`, `accel_owners`).
    geometry: Vec<HalBuffer>,
    /// Instances in the TLAS (those whose unit has a BLAS and whose transform is finite).
    instance_count: usize,
    /// What the last update replaced, and its staging and scratch memory: destroyed at the
    /// next update or on drop, once the device is idle (the build's command buffer is
    /// submitted by the caller, with the frame).
    retired: HalObjects,
}

/// The custom data of the merged layout's one instance (`MERGED_INSTANCE` in
/// `shaders/trace/rt_pipeline.wgsl`).
const MERGED_INSTANCE: u32 = 0xFF_FFFF;

/// VkGeometryInstanceFlagBitsKHR: FORCE_OPAQUE.
const INSTANCE_FORCE_OPAQUE: u8 = 0x4;

/// How every BLAS and TLAS is built.
const BUILD_FLAGS: hal::AccelerationStructureBuildFlags = hal::AccelerationStructureBuildFlags::PREFER_FAST_TRACE;

/// A TLAS instance (VkAccelerationStructureInstanceKHR) of hit group 0, the one hit group,
/// every ray mask bit, and FORCE_OPAQUE when `force_opaque`; hal's `TlasInstance` has no
/// instance flags, so they are set in the bytes it writes (the top byte of the word at 52).
fn tlas_instance(d: &HalDevice, transform: [f32; 12], custom_data: u32, blas_address: u64, force_opaque: bool) -> Vec<u8> {
    let mut bytes = d.tlas_instance_to_bytes(hal::TlasInstance { transform, custom_data, mask: 0xff, blas_address, pipeline_intersection_data_offset: 0 });
    debug_assert_eq!(bytes.len(), 64, "VkAccelerationStructureInstanceKHR is 64 bytes");
    if force_opaque {
        bytes[55] |= INSTANCE_FORCE_OPAQUE;
    }
    bytes
}

/// The (triangle count, opaque) of each geometry of a unit's BLAS, as [`RtAccel`] keeps them.
fn geometry_kinds(g: &Option<Vec<Geometry>>) -> Option<Vec<(u32, bool)>> {
    g.as_ref().map(|g| g.iter().map(|g| (g.count, g.opaque)).collect::<Vec<_>>())
}

/// Fails for a scene with more instances than the TLAS's 24-bit custom data can tell apart
/// (the largest value marks the merged layout's instance).
fn check_instance_count(scene: &Scene) -> Result<(), RuntimeError> {
    const MAX_CUSTOM_DATA: usize = MERGED_INSTANCE as usize - 1;
    if scene.instances().len() > MAX_CUSTOM_DATA {
        return Err(RuntimeError::Gpu(format!(
            "scene `{}` has {} instances; the rt-pipeline back-end identifies instances in 24 bits (at most {MAX_CUSTOM_DATA}); use --backend compute",
            scene.name(),
            scene.instances().len()
        )));
    }
    Ok(())
}

/// What an update makes and what it retires, carried through its steps.
struct UpdateWork {
    /// Per unit, as after the update (the units rebuilt replaced).
    blases: Vec<Option<HalAccel>>,
    blas_kinds: Vec<Option<Vec<(u32, bool)>>>,
    /// The new TLAS, once built.
    tlas: Option<HalAccel>,
    instance_count: usize,
    /// The new geometry arrays (in `buffers`, in [`RtAccel::GEOMETRY_BINDINGS`]' order).
    fresh: HalObjects,
    /// What the update replaced, and its staging and scratch memory.
    retired: HalObjects,
}

/// What the TLAS's instances are made from: the scene, its units' BLAS and the layout.
struct TlasSource<'a> {
    scene: &'a Scene,
    unit_of_instance: &'a dyn Fn(usize) -> usize,
    merged: bool,
}

impl UpdateWork {
    /// The units to build: those in `changed`, and those with geometry but no BLAS (an
    /// earlier failed update) or whose geometries changed opacity (an instance's material
    /// changed alpha mode). Retires the BLAS of units gone (meshes or instances removed).
    fn units_to_rebuild(&mut self, units: usize, changed: &[usize], spans: &[Option<Vec<Geometry>>]) -> Vec<usize> {
        if self.blases.len() > units {
            self.retired.accels.extend(self.blases.drain(units..).flatten());
        }
        self.blases.resize_with(units, || None);
        let mut rebuild: Vec<usize> = changed.iter().copied().filter(|&u| u < units).collect();
        self.blas_kinds.resize(units, None);
        let (blases, blas_kinds) = (&self.blases, &self.blas_kinds);
        rebuild
            .extend((0..units).filter(|&u| (blases[u].is_none() || blas_kinds[u] != geometry_kinds(&spans[u])) && spans[u].is_some() && !changed.contains(&u)));
        rebuild
    }

    /// Records the whole build into `enc`: the geometry arrays uploaded, the BLAS of the
    /// `rebuild` units, the TLAS's instances and the TLAS.
    fn record(
        &mut self,
        d: &HalDevice,
        enc: &mut hal::vulkan::CommandEncoder,
        packed: &Packed,
        rebuild: &[usize],
        tlas: &TlasSource,
    ) -> Result<(), RuntimeError> {
        let align = alignments(d);
        self.upload_geometry(d, enc, packed)?;
        // The copies above land before the builds read them.
        memory_barrier(d, enc, vk_all_commands(), vk_rt_and_build());
        self.build_blases(d, enc, packed, rebuild, align)?;
        let (instance_bytes, instance_count) = self.tlas_instances(d, tlas);
        self.instance_count += instance_count;
        let instance_buffer =
            device_buffer(d, enc, &mut self.retired, "rt instances", &instance_bytes, wgpu::BufferUses::TOP_LEVEL_ACCELERATION_STRUCTURE_INPUT)?;
        // The BLAS builds and the instance copy before the TLAS build.
        memory_barrier(d, enc, vk_rt_and_build(), vk_rt_and_build());
        self.build_tlas(d, enc, &instance_buffer, align)?;
        self.retired.buffers.push(instance_buffer);
        Ok(())
    }

    /// The geometry arrays into `fresh.buffers`, their staging memory retired.
    fn upload_geometry(&mut self, d: &HalDevice, enc: &mut hal::vulkan::CommandEncoder, packed: &Packed) -> Result<(), RuntimeError> {
        let geometry_use = wgpu::BufferUses::BOTTOM_LEVEL_ACCELERATION_STRUCTURE_INPUT | wgpu::BufferUses::STORAGE_READ_ONLY;
        let read_only = wgpu::BufferUses::STORAGE_READ_ONLY;
        let arrays: [(&str, &[u8], wgpu::BufferUses); 4] = [
            ("rt positions", bytemuck::cast_slice(&packed.positions), geometry_use),
            ("rt indices", bytemuck::cast_slice(&packed.indices), geometry_use),
            ("rt first triangles", bytemuck::cast_slice(&packed.first_triangles), read_only),
            ("rt triangle owners", bytemuck::cast_slice(&packed.owners), read_only),
        ];
        for (label, data, usage) in arrays {
            self.fresh.buffers.push(device_buffer(d, enc, &mut self.retired, label, data, usage)?);
        }
        Ok(())
    }

    /// Builds a BLAS for each of the `rebuild` units with geometry and installs it (the old
    /// one retired); a unit rebuilt without geometry loses its BLAS.
    fn build_blases(
        &mut self,
        d: &HalDevice,
        enc: &mut hal::vulkan::CommandEncoder,
        packed: &Packed,
        rebuild: &[usize],
        align: Alignments,
    ) -> Result<(), RuntimeError> {
        let UpdateWork { blases, blas_kinds, fresh, retired, .. } = self;
        let entries = blas_entries(packed, rebuild, (&fresh.buffers[0], &fresh.buffers[1]));
        // Units rebuilt without geometry lose their BLAS.
        for &u in rebuild {
            if packed.spans[u].is_none() {
                if let Some(old) = blases[u].take() {
                    retired.accels.push(old);
                }
            }
        }
        let made = record_blas_builds(d, enc, &entries, align, retired)?;
        for ((u, _), accel) in entries.iter().zip(made) {
            if let Some(old) = blases[*u].replace(accel) {
                retired.accels.push(old);
            }
            blas_kinds[*u] = geometry_kinds(&packed.spans[*u]);
        }
        Ok(())
    }

    /// The TLAS's instances and their count: one per scene instance whose unit has a BLAS
    /// and whose transform is finite; merged, the one BLAS once.
    fn tlas_instances(&self, d: &HalDevice, source: &TlasSource) -> (Vec<u8>, usize) {
        let TlasSource { scene, unit_of_instance, merged } = *source;
        let mut instance_bytes = Vec::new();
        let mut count = 0;
        if let (true, Some(Some(blas))) = (merged, self.blases.first()) {
            // SAFETY: the address of a BLAS made by this device and alive.
            let blas_address = unsafe { d.get_acceleration_structure_device_address(blas) };
            let identity = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
            // Opacity per geometry (opaque and alpha-tested triangles apart).
            instance_bytes.extend(tlas_instance(d, identity, MERGED_INSTANCE, blas_address, false));
            count += 1;
        }
        for (i, inst) in scene.instances().iter().enumerate().filter(|_| !merged) {
            let Some(Some(blas)) = self.blases.get(unit_of_instance(i)) else { continue };
            if crate::accel::bvh::instance_transform(&inst.transform).is_none() {
                continue;
            }
            let m = inst.transform;
            let rows = [0, 1, 2].map(|r| [m.x_axis[r], m.y_axis[r], m.z_axis[r], m.w_axis[r]]);
            // SAFETY: the address of a BLAS made by this device and alive.
            let blas_address = unsafe { d.get_acceleration_structure_device_address(blas) };
            // An opaque instance of a BLAS that alpha-tested instances share is forced
            // opaque: the any-hit shader runs only for alpha-tested instances.
            instance_bytes.extend(tlas_instance(d, bytemuck::cast(rows), i as u32, blas_address, !alpha_tested(scene, i)));
            count += 1;
        }
        (instance_bytes, count)
    }

    /// Builds the TLAS over the `instance_count` instances in `instance_buffer` (its scratch
    /// memory retired).
    fn build_tlas(&mut self, d: &HalDevice, enc: &mut hal::vulkan::CommandEncoder, instance_buffer: &HalBuffer, align: Alignments) -> Result<(), RuntimeError> {
        let tlas_entries = hal::AccelerationStructureEntries::Instances(hal::AccelerationStructureInstances {
            buffer: Some(instance_buffer),
            offset: 0,
            count: self.instance_count as u32,
        });
        let flags = BUILD_FLAGS;
        // SAFETY: as for the BLAS: a size query, the creation, and one build with its own
        // scratch buffer, recorded after the barrier that orders it after the BLAS builds.
        unsafe {
            let sizes = d.get_acceleration_structure_build_sizes(&hal::GetAccelerationStructureBuildSizesDescriptor { entries: &tlas_entries, flags });
            let tlas = d
                .create_acceleration_structure(&hal::AccelerationStructureDescriptor {
                    label: Some("rt tlas"),
                    size: sizes.acceleration_structure_size,
                    format: hal::AccelerationStructureFormat::TopLevel,
                    allow_compaction: false,
                })
                .map(count_made)
                .map_err(|e| hal_error("creating the TLAS", e))?;
            let scratch = d
                .create_buffer(&hal::BufferDescriptor {
                    label: Some("rt tlas scratch"),
                    size: sizes.build_scratch_size.max(align.scratch_alignment),
                    usage: wgpu::BufferUses::ACCELERATION_STRUCTURE_SCRATCH,
                    memory_flags: hal::MemoryFlags::empty(),
                })
                .map(count_made)
                .map_err(|e| hal_error("creating TLAS scratch memory", e))?;
            enc.build_acceleration_structures(
                1,
                std::iter::once(hal::BuildAccelerationStructureDescriptor {
                    entries: &tlas_entries,
                    mode: hal::AccelerationStructureBuildMode::Build,
                    flags,
                    source_acceleration_structure: None,
                    destination_acceleration_structure: &tlas,
                    scratch_buffer: &scratch,
                    scratch_buffer_offset: 0,
                }),
            );
            self.tlas = Some(tlas);
            self.retired.buffers.push(scratch);
        }
        Ok(())
    }
}

/// The build inputs of the `rebuild` units with geometry, over the packed positions and
/// indices (`geometry`).
fn blas_entries<'a>(
    packed: &Packed,
    rebuild: &[usize],
    (pos_buf, idx_buf): (&'a HalBuffer, &'a HalBuffer),
) -> Vec<(usize, hal::AccelerationStructureEntries<'a, HalBuffer>)> {
    rebuild
        .iter()
        .filter_map(|&u| {
            // Alpha-tested geometry is built without OPAQUE: the any-hit shader runs on it, once a
            // primitive (a transmittance ray takes each BLEND surface out once).
            let geometry = |g: &Geometry| hal::AccelerationStructureTriangles {
                vertex_buffer: Some(pos_buf),
                vertex_format: wgpu::VertexFormat::Float32x3,
                first_vertex: 0,
                vertex_count: packed.positions.len() as u32,
                vertex_stride: 12,
                indices: Some(hal::AccelerationStructureTriangleIndices {
                    format: wgpu::IndexFormat::Uint32,
                    buffer: Some(idx_buf),
                    offset: g.first * 12,
                    count: g.count * 3,
                }),
                transform: None,
                flags: if g.opaque {
                    hal::AccelerationStructureGeometryFlags::OPAQUE
                } else {
                    hal::AccelerationStructureGeometryFlags::NO_DUPLICATE_ANY_HIT_INVOCATION
                },
            };
            Some((u, hal::AccelerationStructureEntries::Triangles(packed.spans[u].as_ref()?.iter().map(geometry).collect())))
        })
        .collect()
}

/// Makes a BLAS for each of `entries` and records their builds, each with its own range of
/// one scratch buffer (retired); the BLAS in the order of `entries`.
fn record_blas_builds(
    d: &HalDevice,
    enc: &mut hal::vulkan::CommandEncoder,
    entries: &[(usize, hal::AccelerationStructureEntries<HalBuffer>)],
    align: Alignments,
    retired: &mut HalObjects,
) -> Result<Vec<HalAccel>, RuntimeError> {
    let flags = BUILD_FLAGS;
    let mut made = Vec::new();
    let mut scratch_offsets = Vec::new();
    let mut scratch_size = 0u64;
    for (_, e) in entries {
        // SAFETY: a size query and the creation of an acceleration structure over
        // buffers made above; nothing is recorded yet.
        let sizes = unsafe { d.get_acceleration_structure_build_sizes(&hal::GetAccelerationStructureBuildSizesDescriptor { entries: e, flags }) };
        // SAFETY: a new acceleration structure of the size just queried; it is built
        // below and destroyed through `HalObjects` or `RtAccel::drop`.
        let accel = unsafe {
            d.create_acceleration_structure(&hal::AccelerationStructureDescriptor {
                label: Some("rt blas"),
                size: sizes.acceleration_structure_size,
                format: hal::AccelerationStructureFormat::BottomLevel,
                allow_compaction: false,
            })
        }
        .map(count_made)
        .map_err(|e| hal_error("creating a BLAS", e))?;
        made.push(accel);
        scratch_offsets.push(scratch_size);
        scratch_size = (scratch_size + sizes.build_scratch_size).next_multiple_of(align.scratch_alignment);
    }
    if entries.is_empty() {
        return Ok(made);
    }
    // SAFETY: a device-local scratch buffer for the builds below.
    let scratch = unsafe {
        d.create_buffer(&hal::BufferDescriptor {
            label: Some("rt blas scratch"),
            size: scratch_size.max(align.scratch_alignment),
            usage: wgpu::BufferUses::ACCELERATION_STRUCTURE_SCRATCH,
            memory_flags: hal::MemoryFlags::empty(),
        })
    }
    .map(count_made)
    .map_err(|e| hal_error("creating BLAS scratch memory", e))?;
    let descriptors: Vec<hal::BuildAccelerationStructureDescriptor<HalBuffer, HalAccel>> = entries
        .iter()
        .zip(&made)
        .zip(&scratch_offsets)
        .map(|(((_, e), a), &offset)| hal::BuildAccelerationStructureDescriptor {
            entries: e,
            mode: hal::AccelerationStructureBuildMode::Build,
            flags,
            source_acceleration_structure: None,
            destination_acceleration_structure: a,
            scratch_buffer: &scratch,
            scratch_buffer_offset: offset,
        })
        .collect();
    // SAFETY: each BLAS is written once, each with its own scratch range; the
    // inputs were copied before the barrier above.
    unsafe { enc.build_acceleration_structures(descriptors.len() as u32, descriptors) };
    retired.buffers.push(scratch);
    Ok(made)
}

impl RtAccel {
    /// No acceleration structure yet (the first [`RtAccel::update`] builds every unit).
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            device: device.clone(),
            blases: Vec::new(),
            blas_kinds: Vec::new(),
            tlas: None,
            geometry: Vec::new(),
            instance_count: 0,
            retired: HalObjects::default(),
        }
    }

    /// Brings the structures up to date with `scene`: units (`unit_meshes[u]` is unit `u`'s
    /// mesh) listed in `changed` get a new BLAS, the TLAS and the geometry arrays are made
    /// again. Returns the number of BLAS built and the build's command buffer, which the caller
    /// submits before any command buffer that traces (the executor between the `Accel` node's
    /// timestamps); what the build replaced is destroyed at the next update, once the device
    /// is idle.
    pub fn update(
        &mut self,
        scene: &Scene,
        unit_meshes: &[usize],
        unit_of_instance: &dyn Fn(usize) -> usize,
        changed: &[usize],
        merged: bool,
    ) -> Result<(usize, wgpu::CommandBuffer), RuntimeError> {
        check_instance_count(scene)?;
        let device = self.device.clone();
        // The previous build has run: the frames that used what it replaced were waited for.
        let mut previous = std::mem::take(&mut self.retired);
        previous.destroy(&device);
        let packed = pack(scene, unit_meshes, unit_of_instance, merged);
        let mut work = UpdateWork {
            blases: std::mem::take(&mut self.blases),
            blas_kinds: std::mem::take(&mut self.blas_kinds),
            tlas: None,
            instance_count: 0,
            fresh: HalObjects::default(),
            retired: HalObjects::default(),
        };
        let rebuild = work.units_to_rebuild(unit_meshes.len(), changed, &packed.spans);
        let source = TlasSource { scene, unit_of_instance, merged };
        let commands = record_raw(&device, "rt-pipeline acceleration structures", |d, enc| work.record(d, enc, &packed, &rebuild, &source));
        let built = rebuild.iter().filter(|&&u| packed.spans[u].is_some()).count();
        match commands {
            Ok(commands) => {
                self.install(work);
                Ok((built, commands))
            }
            Err(e) => {
                self.discard(work);
                Err(e)
            }
        }
    }

    /// Makes what a successful update built the current structures; what they replace is
    /// retired with the update's staging and scratch memory.
    fn install(&mut self, mut work: UpdateWork) {
        work.retired.accels.extend(self.tlas.take());
        work.retired.buffers.append(&mut self.geometry);
        self.tlas = work.tlas;
        self.geometry = work.fresh.buffers.drain(..).collect();
        self.blases = work.blases;
        self.blas_kinds = work.blas_kinds;
        self.instance_count = work.instance_count;
        self.retired = work.retired;
    }

    /// After a failed update, nothing was submitted. The old TLAS may refer to BLAS replaced
    /// by the update, so everything goes, old and new: with no TLAS, binding fails ("not
    /// built") until an update succeeds, and the next update builds every unit.
    fn discard(&mut self, work: UpdateWork) {
        let UpdateWork { blases, tlas, mut fresh, mut retired, .. } = work;
        fresh.accels.extend(tlas);
        fresh.accels.extend(blases.into_iter().flatten());
        fresh.accels.extend(self.tlas.take());
        fresh.buffers.append(&mut self.geometry);
        self.instance_count = 0;
        fresh.destroy(&self.device);
        retired.destroy(&self.device);
    }

    /// The number of BLAS geometries built without the OPAQUE flag (alpha-tested triangles,
    /// the only ones the any-hit shader runs on); 0 for an opaque scene.
    pub fn non_opaque_geometries(&self) -> usize {
        self.blases.iter().zip(&self.blas_kinds).filter(|(b, _)| b.is_some()).flat_map(|(_, k)| k.iter().flatten()).filter(|(_, opaque)| !opaque).count()
    }

    /// The trace module's bindings of [`RtAccel::geometry`], in its order; with `accel_tlas`,
    /// the bindings [`RtPass::bind_accel`](super::RtPass::bind_accel) takes from the `RtAccel`
    /// itself.
    pub(super) const GEOMETRY_BINDINGS: [&'static str; 4] = ["accel_positions", "accel_indices", "accel_first_triangle", "accel_owners"];

    /// Whether [`RtPass::bind_accel`](super::RtPass::bind_accel) takes binding `name` from the
    /// `RtAccel` itself (not from the cache's buffers).
    pub(super) fn owns_binding(name: &str) -> bool {
        name == "accel_tlas" || Self::GEOMETRY_BINDINGS.contains(&name)
    }

    pub(super) fn tlas(&self) -> Option<&HalAccel> {
        self.tlas.as_ref()
    }

    /// The geometry array bound as `GEOMETRY_BINDINGS[i]`, once built.
    pub(super) fn geometry_buffer(&self, i: usize) -> Option<&HalBuffer> {
        self.geometry.get(i)
    }
}

impl Drop for RtAccel {
    fn drop(&mut self) {
        let mut all = std::mem::take(&mut self.retired);
        all.buffers.append(&mut self.geometry);
        all.accels.extend(self.tlas.take());
        all.accels.extend(self.blases.drain(..).flatten());
        all.destroy(&self.device);
    }
}
