//! A stable LSD radix sort of (u32 key, u32 value) pairs on the GPU
//! (`shaders/accel/radix_sort.wgsl`): four passes of 8 bits, onesweep-style (one histogram
//! dispatch for all passes, then one dispatch per pass that ranks each tile of 2048 keys in
//! workgroup memory and finds its digits' places by decoupled look-back). Keys equal in value
//! keep their input order, so with values in index order the result is what sorting by (key,
//! value) gives; the GPU builder sorts its Morton codes with it ([`crate::accel::gpu_build`]).

use crate::gpu_util::compute_pipeline_with;
use wgpu::util::DeviceExt;

/// The sort's WGSL.
pub(crate) const RADIX_SORT_WGSL: &str = concat!(include_str!("../../shaders/common/lookback.wgsl"), include_str!("../../shaders/accel/radix_sort.wgsl"));

/// Invocations of a workgroup (the WGSL's `GROUP`).
const GROUP: u64 = 256;
/// Keys per tile by default (the WGSL's `TILE`, `GROUP * PER_THREAD`);
/// `RAYGRAPH_SORT_TILE=256|512|1024|2048|4096` picks another, for comparing.
const DEFAULT_TILE: u64 = 2048;
/// The largest tile the WGSL takes.
const MAX_TILE: u64 = 4096;
/// Most passes of 8 bits (the WGSL's `PASSES`, the histograms it counts): a job sorts by as many
/// as its keys' bits need; after an odd number the result is copied back into the input.
const PASSES: u64 = 4;
/// Words of the sort state: the histograms, the tickets, the count (the WGSL's `COUNT`) and
/// padding.
const STATE_WORDS: usize = 1032;
const COUNT_WORD: u64 = 1028;
const PARAMS_STRIDE: u64 = 256;
/// Most pairs one sort takes (the tiles of one dispatch row; the look-back's 30-bit counts).
pub const MAX_RADIX_SORT_PAIRS: u32 = 1 << 26;

/// The sort's pipelines, made once per device.
pub struct GpuRadixSort {
    layout: wgpu::BindGroupLayout,
    /// Keys per tile.
    tile: u64,
    histogram: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    copy: wgpu::ComputePipeline,
}

/// One sort of pairs held in a key and a value buffer: its parameters, its state (histograms,
/// tickets, the count to sort; zero but for the count when it is made, as the tiles' status
/// is, so a job sorts once) and the other key and value arrays the passes write to by turns.
pub struct RadixSortJob {
    state: wgpu::Buffer,
    bind: [wgpu::BindGroup; 2],
    tiles: u32,
    /// Passes of 8 bits: enough for the keys' bits.
    passes: u64,
}

impl RadixSortJob {
    /// The buffer and byte offset of the word that says how many pairs to sort, for a count
    /// known only on the GPU (copied there before the sort).
    pub fn count_word(&self) -> (&wgpu::Buffer, u64) {
        (&self.state, 4 * COUNT_WORD)
    }
}

impl GpuRadixSort {
    /// Keys per tile.
    pub fn tile(&self) -> u64 {
        self.tile
    }

    /// Compiles the sort (with tiles of 2,048 keys, or `RAYGRAPH_SORT_TILE`'s where the device's
    /// workgroup memory holds them).
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device
            .create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("radix_sort.wgsl"), source: wgpu::ShaderSource::Wgsl(RADIX_SORT_WGSL.into()) });
        let entry = |binding: u32| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: if binding == 0 { wgpu::BufferBindingType::Uniform } else { wgpu::BufferBindingType::Storage { read_only: false } },
                has_dynamic_offset: binding == 0,
                min_binding_size: None,
            },
            count: None,
        };
        let entries: Vec<_> = (0..7).map(entry).collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("radix sort"), entries: &entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("radix sort"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let tile = fitting_tile(tile_from_env(), device.limits().max_compute_workgroup_storage_size);
        let constants = [("PER_THREAD", (tile / GROUP) as f64)];
        let pipeline = |name: &str| compute_pipeline_with(device, name, &pipeline_layout, &module, name, &constants);
        Self { histogram: pipeline("radix_histogram"), scatter: pipeline("radix_scatter"), copy: pipeline("radix_copy"), layout, tile }
    }

    /// A sort of the first `count` pairs of `keys` and `vals` (storage buffers of u32 with room
    /// for `capacity` pairs, `count <= capacity <= MAX_RADIX_SORT_PAIRS`) by their keys' low
    /// `key_bits` bits (1 to 32; the keys hold no others), sorted in place.
    pub fn job(&self, device: &wgpu::Device, keys: &wgpu::Buffer, vals: &wgpu::Buffer, (capacity, count): (u32, u32), key_bits: u32) -> RadixSortJob {
        let capacity = capacity.clamp(1, MAX_RADIX_SORT_PAIRS) as u64;
        let tiles = capacity.div_ceil(self.tile);
        let storage = wgpu::BufferUsages::STORAGE;
        let mut params = vec![0u8; (PARAMS_STRIDE * PASSES) as usize];
        for pass in 0..PASSES {
            let record = [8 * pass as u32, pass as u32, tiles as u32, 0];
            params[(pass * PARAMS_STRIDE) as usize..][..16].copy_from_slice(bytemuck::cast_slice(&record));
        }
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("radix sort params"),
            contents: &params,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut state = [0u32; STATE_WORDS];
        state[COUNT_WORD as usize] = count.min(capacity as u32);
        let state = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("radix sort state"),
            contents: bytemuck::cast_slice(&state),
            usage: storage | wgpu::BufferUsages::COPY_DST,
        });
        // wgpu clears a buffer made without contents before its first use.
        let buffer =
            |label: &str, size: u64| device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage: storage, mapped_at_creation: false });
        let (alt_keys, alt_vals) = (buffer("radix sort keys", 4 * capacity), buffer("radix sort values", 4 * capacity));
        let status = buffer("radix sort tile status", 4 * PASSES * tiles * 256);
        let bind = |from: [&wgpu::Buffer; 2], to: [&wgpu::Buffer; 2]| {
            let resources = [from[0], from[1], to[0], to[1], &state, &status];
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding { buffer: &params, offset: 0, size: wgpu::BufferSize::new(16) }),
            }];
            entries.extend(resources.iter().enumerate().map(|(b, r)| wgpu::BindGroupEntry { binding: 1 + b as u32, resource: r.as_entire_binding() }));
            device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("radix sort"), layout: &self.layout, entries: &entries })
        };
        let bind = [bind([keys, vals], [&alt_keys, &alt_vals]), bind([&alt_keys, &alt_vals], [keys, vals])];
        RadixSortJob { state, bind, tiles: tiles as u32, passes: u64::from(key_bits.clamp(1, 32)).div_ceil(8) }
    }

    /// Records `job`'s dispatches into `pass`: the histograms, the job's passes, and after an
    /// odd number of them the copy back into the input.
    pub fn record(&self, pass: &mut wgpu::ComputePass, job: &RadixSortJob) {
        pass.set_bind_group(0, &job.bind[0], &[0]);
        pass.set_pipeline(&self.histogram);
        pass.dispatch_workgroups(job.tiles, 1, 1);
        pass.set_pipeline(&self.scatter);
        for p in 0..job.passes {
            pass.set_bind_group(0, &job.bind[(p % 2) as usize], &[(p * PARAMS_STRIDE) as u32]);
            pass.dispatch_workgroups(job.tiles, 1, 1);
        }
        if job.passes % 2 == 1 {
            pass.set_bind_group(0, &job.bind[1], &[0]);
            pass.set_pipeline(&self.copy);
            pass.dispatch_workgroups(job.tiles, 1, 1);
        }
    }
}

/// Bytes of workgroup memory the scatter uses with tiles of `tile` keys: a key and a value a
/// key, the 1,024 counts, the 2,048 packed scan words, two 256-entry starts and one word.
fn workgroup_bytes(tile: u64) -> u64 {
    8 * tile + 4 * (1024 + 2048 + 2 * 256 + 1)
}

/// `tile`, or the largest smaller tile whose workgroup memory fits the device's `limit`.
fn fitting_tile(tile: u64, limit: u32) -> u64 {
    let mut fitting = tile;
    while fitting > GROUP && workgroup_bytes(fitting) > limit as u64 {
        fitting /= 2;
    }
    if fitting != tile {
        log::info!("radix sort: tiles of {tile} keys need {} bytes of workgroup memory, the device has {limit}: tiles of {fitting}", workgroup_bytes(tile));
    }
    fitting
}

/// The tile size `RAYGRAPH_SORT_TILE` names (a power of two from 256 to 4096), else the default.
fn tile_from_env() -> u64 {
    match std::env::var("RAYGRAPH_SORT_TILE") {
        Ok(value) => match value.parse::<u64>() {
            Ok(tile) if tile.is_power_of_two() && (GROUP..=MAX_TILE).contains(&tile) => tile,
            _ => {
                log::warn!("RAYGRAPH_SORT_TILE={value}: not 256, 512, 1024, 2048 or 4096; the radix sort keeps tiles of {DEFAULT_TILE} keys");
                DEFAULT_TILE
            }
        },
        Err(_) => DEFAULT_TILE,
    }
}
