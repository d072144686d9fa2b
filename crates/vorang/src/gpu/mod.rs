//! The GPU backend (feature `gpu`): `exact linear 0`, `interpolateCoeff linear` and
//! `interpolateColor` in f64 Vulkan compute shaders through wgpu, the same image as the CPU
//! renderer (docs/gpu.md).
//!
//! Image order, exact per pixel: one invocation per pixel enters the mesh at each of the
//! pixel's entries, nearest first ([`frame`]: the CPU lists the boundary faces that hold the
//! pixel by the watertight face rule, and the cells reaching in front of a perspective near
//! plane where its own renderer draws them), and marches cell to cell through the exit face
//! that holds the pixel centre (exact orientation predicates and the top-left rule, as
//! `render::faces`). A face's depth is computed from the face alone, so a cell's exit is its
//! neighbour's entry bit for bit. In each cell the field comes from the cell's barycentric line
//! along the ray, operation for operation as the CPU's per-ray path (`render::cell`); the
//! interval is cut where the field crosses a knot of the transfer function and integrated with
//! the exact linear rule, in the exp-free series of the span kernels: Vulkan defines no f64
//! `exp`, so optically thick segments are cut into thin ones. interpolateColor shades each cell
//! with its Gouraud fan, from the classification the CPU makes per frame ([`color`]). The
//! colour is composited front to back (`render_ftb` stops where the CPU does).
//!
//! Every WGSL function has a Rust twin with the same operations in the same order
//! ([`twin`]); the GPU tests hold them bit-identical on lavapipe, and hold the images to the
//! CPU renderer's within 1e-12 per channel.
//!
//! lavapipe ends every loop of a batch of invocations once all of them together have run 65535
//! iterations: the march finds the transfer function's pieces by bisection and visits only
//! the knots a cell's interval crosses, which keeps the frames tested (up to 256 knots) well
//! inside that; a pixel the driver cut short anyway is marked by the march and marched again
//! by the twin on the CPU (docs/gpu.md).
//!
//! Memory: per cell its four nodes and four neighbours (32 bytes, uploaded once per mesh: the
//! time steps of a series that share a mesh share the upload; split across up to
//! [`MESH_PARTS`] bindings), per node seven f64 per frame (ten for interpolateCoeff), for
//! interpolateColor one word per cell and frame (its fan), per pixel its entries and five f64
//! of result.

pub mod color;
pub mod frame;
pub mod spirv;
pub mod twin;

use std::sync::{Arc, Mutex, Weak};

use wgpu::util::DeviceExt;

use crate::error::Error;
use crate::framebuffer::Framebuffer;
use crate::mapping::Mapping;
use crate::mesh::TetMesh;
use crate::render::{Settings, Stats};
use crate::scene::View;
use crate::volume::Volume;

/// The shader sources, in the order they are joined into one module.
pub const WGSL: &[(&str, &str)] = &[
    ("predicates.wgsl", include_str!("wgsl/predicates.wgsl")),
    ("faces.wgsl", include_str!("wgsl/faces.wgsl")),
    ("linear.wgsl", include_str!("wgsl/linear.wgsl")),
    ("march.wgsl", include_str!("wgsl/march.wgsl")),
    ("color.wgsl", include_str!("wgsl/color.wgsl")),
];

/// The entry points the tests call: each function of the shaders on a batch of inputs.
const PROBE_WGSL: &str = include_str!("wgsl/probe.wgsl");

/// The shader module's source: every file of [`WGSL`].
pub fn source() -> String {
    WGSL.iter().map(|(_, s)| *s).collect::<Vec<_>>().join("\n")
}

/// `Stats::sort` of a GPU frame (the timing line reads it: `bin` is then the upload).
pub const GPU_SORT: &str = "none (GPU march)";

/// The most buffers a mesh is split across (`mesh`, `mesh1` … `mesh3` in `march.wgsl`).
pub const MESH_PARTS: usize = 4;

/// A mesh's cells on the device: per cell its nodes, then its neighbours, split into parts of
/// `rows` rows where one binding cannot hold them all.
struct Uploaded {
    /// The mesh uploaded (a time step with the same points and cells shares it).
    cells_of: Weak<TetMesh>,
    parts: Vec<wgpu::Buffer>,
    rows: usize,
    /// The binding size the parts were cut for.
    limit: u64,
}

/// An opened device with the march compiled: what `backend gpu` holds.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    march: Kernel,
    /// The shaders go to the device as our own SPIR-V, every float operation NoContraction.
    passthrough: bool,
    /// The adapter's name, driver and kind.
    name: String,
    /// The device's `fma` on f64 rounds once (lavapipe's does not: it multiplies and adds).
    exact_fma: bool,
    uploaded: Mutex<Option<Uploaded>>,
    /// The most bytes one buffer binding may hold (the device's limit).
    binding_limit: u64,
    /// The most bytes one binding of the mesh holds (the device's limit, or less for tests).
    mesh_limit: std::sync::atomic::AtomicU64,
    /// Held from an error scope's push to its pop: the device's scopes must be popped in the
    /// reverse order of their pushes, which threads sharing the device would interleave.
    scopes: Mutex<()>,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Gpu({})", self.name)
    }
}

/// Runs a future to its end (wgpu's calls that wait on the device).
fn block<F: std::future::Future>(f: F) -> F::Output {
    pollster::block_on(f)
}

impl Gpu {
    /// Opens the first Vulkan adapter with 64-bit floats in shaders, or says what is missing.
    pub fn open() -> Result<Gpu, String> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapters = block(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        if adapters.is_empty() {
            return Err("no Vulkan adapter found (install a Vulkan driver, e.g. Debian's mesa-vulkan-drivers for the software one, lavapipe)".into());
        }
        let Some(adapter) = adapters
            .iter()
            .filter(|a| a.features().contains(wgpu::Features::SHADER_F64))
            .min_by_key(|a| match a.get_info().device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Cpu => 3,
                wgpu::DeviceType::Other => 4,
            })
        else {
            let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
            return Err(format!(
                "no Vulkan adapter offers 64-bit floats in shaders (SHADER_F64); found: {}",
                names.join(", ")
            ));
        };
        let info = adapter.get_info();
        // SPIR-V of our own (with NoContraction, see [`spirv`]) where the adapter takes it.
        let passthrough = adapter
            .features()
            .contains(wgpu::Features::PASSTHROUGH_SHADERS);
        let mut features = wgpu::Features::SHADER_F64;
        if passthrough {
            features |= wgpu::Features::PASSTHROUGH_SHADERS;
        }
        let (device, queue) = block(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("vorang"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| format!("the Vulkan device {} did not open: {e}", info.name))?;
        let limits = device.limits();
        let binding_limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let march = Kernel::new(&device, passthrough, &source(), "march", (8, 8, 1), &MARCH)
            .map_err(|e| format!("the shaders did not compile on {}: {e}", info.name))?;
        let mut gpu = Gpu {
            device,
            queue,
            march,
            passthrough,
            name: format!(
                "{} ({}, {:?})",
                info.name, info.driver_info, info.device_type
            ),
            exact_fma: false,
            uploaded: Mutex::new(None),
            binding_limit,
            mesh_limit: std::sync::atomic::AtomicU64::new(binding_limit),
            scopes: Mutex::new(()),
        };
        gpu.exact_fma = gpu.probe_fma()?;
        Ok(gpu)
    }

    /// The adapter: name, driver, kind.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The most bytes one buffer binding holds.
    pub fn binding_limit(&self) -> u64 {
        self.binding_limit
    }

    /// Lowers the bytes one binding of the mesh may hold (to test meshes split across
    /// bindings); never above the device's limit.
    pub fn limit_mesh_bindings(&self, bytes: u64) {
        let b = bytes.clamp(64, self.binding_limit);
        self.mesh_limit
            .store(b, std::sync::atomic::Ordering::Relaxed);
    }

    /// Whether the device's f64 `fma` rounds once.
    pub fn exact_fma(&self) -> bool {
        self.exact_fma
    }

    /// `fma(1 + 2⁻³⁰, 1 + 2⁻³⁰, −(1 + 2⁻²⁹))` is 2⁻⁶⁰ fused and 0 as a product and a sum.
    fn probe_fma(&self) -> Result<bool, String> {
        let e = 1.0 + (0.5f64).powi(30);
        let out = self.run_probe("fma_probe", &[e, e, -(1.0 + (0.5f64).powi(29))], 3, 1)?;
        Ok(out[0] != 0.0)
    }

    /// Runs entry point `entry` of the probe shader (`wgsl/probe.wgsl`, joined to the shaders'
    /// functions) with `stride` input numbers and `outputs` results per invocation, for the
    /// twin tests.
    pub fn run_probe(
        &self,
        entry: &str,
        input: &[f64],
        stride: usize,
        outputs: usize,
    ) -> Result<Vec<f64>, String> {
        let d = &self.device;
        let _scopes = self.scopes.lock().unwrap_or_else(|e| e.into_inner());
        let src = format!(
            "{}\n{}\n{}\n{}",
            WGSL[0].1, WGSL[1].1, WGSL[2].1, PROBE_WGSL
        );
        let kernel = Kernel::new(d, self.passthrough, &src, entry, (64, 1, 1), &PROBE)?;
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let count = input.len() / stride.max(1);
        let inputs = self.storage(bytemuck::cast_slice(input));
        let size = (outputs.max(1) * count.max(1) * 8) as u64;
        let out = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe out"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let params = self.storage(bytemuck::cast_slice(&[f64::from(u8::from(self.exact_fma))]));
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &kernel.group,
            entries: &[
                entry_of(0, &inputs),
                entry_of(1, &out),
                entry_of(2, &params),
            ],
        });
        if let Some(e) = block(scope.pop()) {
            return Err(format!("probe {entry}: {e:?}"));
        }
        let result = self.dispatch(
            &kernel.pipeline,
            &group,
            [count.div_ceil(64) as u32, 1],
            &out,
            size,
        )?;
        Ok(result)
    }

    fn storage(&self, bytes: &[u8]) -> wgpu::Buffer {
        // A binding may not be empty.
        let padded;
        let contents = if bytes.is_empty() {
            padded = [0u8; 16];
            &padded[..]
        } else {
            bytes
        };
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
    }

    /// Dispatches `groups` workgroups and reads `out` back as f64.
    fn dispatch(
        &self,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        groups: [u32; 2],
        out: &wgpu::Buffer,
        size: u64,
    ) -> Result<Vec<f64>, String> {
        let d = &self.device;
        let read = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = d.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups(groups[0], groups[1], 1);
        }
        encoder.copy_buffer_to_buffer(out, 0, &read, 0, size);
        self.queue.submit([encoder.finish()]);
        let slice = read.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        d.poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| format!("the GPU did not finish: {e}"))?;
        let view = slice
            .get_mapped_range()
            .map_err(|e| format!("the GPU's result could not be read: {e}"))?;
        let out = bytemuck::cast_slice::<u8, f64>(&view).to_vec();
        Ok(out)
    }

    /// The volume's cells on the device, uploaded once per mesh: the buffers and the rows
    /// each holds (all but the last full). A mesh that needs more than [`MESH_PARTS`]
    /// bindings is refused.
    fn mesh_of(&self, vol: &Arc<Volume>) -> Result<(Vec<wgpu::Buffer>, usize), String> {
        let limit = self.mesh_limit.load(std::sync::atomic::Ordering::Relaxed);
        let mut uploaded = self.uploaded.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(u) = uploaded.as_ref()
            && u.limit == limit
            && u.cells_of
                .upgrade()
                .is_some_and(|m| Arc::ptr_eq(&m, &vol.mesh))
        {
            return Ok((u.parts.clone(), u.rows));
        }
        let mesh = &vol.mesh;
        let cells = cell_rows(mesh);
        // 16 bytes a row.
        let rows = usize::try_from(limit / 16).unwrap_or(usize::MAX).max(1);
        let parts = cells.len().div_ceil(rows).max(1);
        if parts > MESH_PARTS {
            return Err(format!(
                "the mesh's {} cells need {} GPU buffers of at most {} bytes (32 bytes a cell), more than the {MESH_PARTS} the backend binds; use 'backend cpu'",
                mesh.tet_count(),
                parts,
                limit
            ));
        }
        let buffers: Vec<wgpu::Buffer> = cells
            .chunks(rows)
            .map(|c| self.storage(bytemuck::cast_slice(c)))
            .collect();
        let buffers = if buffers.is_empty() {
            vec![self.storage(&[])]
        } else {
            buffers
        };
        *uploaded = Some(Uploaded {
            cells_of: Arc::downgrade(&vol.mesh),
            parts: buffers.clone(),
            rows,
            limit,
        });
        Ok((buffers, rows))
    }

    /// Renders one frame.
    pub fn render(
        &self,
        vol: &Arc<Volume>,
        mapping: &Mapping,
        view: &View,
        settings: &Settings,
    ) -> Result<(Framebuffer, Stats), Error> {
        let started = std::time::Instant::now();
        let data = frame::prepare(vol, mapping, view, settings, self.exact_fma)?;
        let setup = started.elapsed();
        // The cells go to the device once per mesh: the first frame of a volume pays for it.
        let uploading = std::time::Instant::now();
        self.mesh_of(vol).map_err(Error::Invalid)?;
        let upload = uploading.elapsed();
        let drawing = std::time::Instant::now();
        let mut image = self.march(vol, &data).map_err(Error::Invalid)?;
        redo_cut_pixels(vol, &data, &mut image);
        let segments: f64 = image.chunks(5).map(|p| p[4]).sum();
        let fb = frame::finish(&data, &image, settings)?;
        let non_finite = fb
            .pixels
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()));
        let stats = Stats {
            cells: vol.mesh.tet_count(),
            drawn: 0,
            fragments: segments as u64,
            lane_fragments: 0,
            sort: GPU_SORT,
            convex: vol.mesh.is_convex(),
            cycle_cells: 0,
            per_pixel: true,
            most_runs: 0,
            non_finite: fb
                .pixels
                .iter()
                .filter(|p| !p.iter().all(|v| v.is_finite()))
                .count(),
            first_non_finite: non_finite.map(|i| (i % fb.width, i / fb.width)),
            overlap_pixels: 0,
            overlap_cells: Vec::new(),
            opaque_pixels: 0,
            ranks: Vec::new(),
            // On the GPU `bin` is the upload of the cells (zero once they are there).
            timing: crate::render::Timing {
                setup,
                bin: upload,
                draw: drawing.elapsed(),
                ..Default::default()
            },
        };
        Ok((fb, stats))
    }

    /// The march over every pixel: colour, transparency and the cells passed per pixel
    /// ([`twin::LOOPS_CUT`] where the driver cut the pixel's loops short; [`Gpu::render`]
    /// marches those again with the twin).
    pub fn march(&self, vol: &Arc<Volume>, data: &frame::FrameData) -> Result<Vec<f64>, String> {
        let (mesh, rows) = self.mesh_of(vol)?;
        let limit = self.binding_limit();
        let node_bytes = 8 * data.nodes.len() as u64;
        if node_bytes > limit {
            return Err(format!(
                "the mesh's {} nodes need {node_bytes} bytes on the GPU, more than one buffer binding holds ({limit}); use 'backend cpu'",
                vol.mesh.node_count()
            ));
        }
        let list_bytes = 4 * data.lists.len() as u64;
        if list_bytes > limit {
            return Err(format!(
                "the frame's entry lists (and interpolateColor's fans) need {list_bytes} bytes on the GPU, more than one buffer binding holds ({limit}); use 'backend cpu'"
            ));
        }
        let mut consts = data.consts.clone();
        consts[twin::slot::PART_ROWS] = rows as f64;
        let d = &self.device;
        let scopes = self.scopes.lock().unwrap_or_else(|e| e.into_inner());
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let nodes = self.storage(bytemuck::cast_slice(&data.nodes));
        let lists = self.storage(bytemuck::cast_slice(&data.lists));
        let lines = self.storage(bytemuck::cast_slice(data.lines.as_deref().unwrap_or(&[])));
        let consts = self.storage(bytemuck::cast_slice(&consts));
        let unused = self.storage(&[]);
        let part = |k: usize| mesh.get(k).unwrap_or(&unused);
        let size = (5 * data.width * data.height * 8) as u64;
        let image = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("image"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("march"),
            layout: &self.march.group,
            entries: &[
                entry_of(0, part(0)),
                entry_of(1, &nodes),
                entry_of(2, &lists),
                entry_of(3, &lines),
                entry_of(4, &consts),
                entry_of(5, &image),
                entry_of(6, part(1)),
                entry_of(7, part(2)),
                entry_of(8, part(3)),
            ],
        });
        if let Some(e) = block(scope.pop()) {
            return Err(format!("the GPU refused the frame's buffers: {e:?}"));
        }
        drop(scopes);
        let groups = [
            data.width.div_ceil(8) as u32,
            data.height.div_ceil(8) as u32,
        ];
        self.dispatch(&self.march.pipeline, &group, groups, &image, size)
    }
}

/// The mesh as the march reads it: per cell its nodes, then its neighbours.
fn cell_rows(mesh: &TetMesh) -> Vec<[u32; 4]> {
    let mut cells = Vec::with_capacity(2 * mesh.tet_count());
    for (t, nb) in mesh.tets().iter().zip(mesh.neighbors()) {
        cells.push(*t);
        cells.push(*nb);
    }
    cells
}

/// The pixels whose march the driver cut short ([`twin::LOOPS_CUT`]: lavapipe ends every loop
/// of a batch of invocations once they have run 65535 iterations together, docs/gpu.md)
/// marched again by the twin on the CPU: the same operations in the same order, so the bits
/// the march would have written.
fn redo_cut_pixels(vol: &Volume, data: &frame::FrameData, image: &mut [f64]) {
    use rayon::prelude::*;
    let cut: Vec<usize> = (0..data.width * data.height)
        .filter(|&p| image[5 * p + 4] == twin::LOOPS_CUT)
        .collect();
    if cut.is_empty() {
        return;
    }
    let cells = cell_rows(&vol.mesh);
    let b = twin::Buffers {
        mesh: &cells,
        nodes: &data.nodes,
        lists: &data.lists,
        lines: data.lines.as_deref().unwrap_or(&[]),
        consts: &data.consts,
    };
    let width = data.width;
    let redone: Vec<[f64; 5]> = cut
        .par_iter()
        .map(|&p| b.pixel((p % width) as u32, (p / width) as u32))
        .collect();
    for (&p, r) in cut.iter().zip(redone) {
        image[5 * p..5 * p + 5].copy_from_slice(&r);
    }
}

/// The march's bindings: the mesh (0, and 6–8 for a split mesh), nodes, entry lists, grid
/// lines, the frame's numbers, and the image it writes (5).
const MARCH: Bindings = Bindings {
    count: 9,
    output: 5,
};

/// The probes' bindings: input, output (1), parameters.
const PROBE: Bindings = Bindings {
    count: 3,
    output: 1,
};

/// Storage buffers `0 … count − 1`, all read-only but `output`.
struct Bindings {
    count: u32,
    output: u32,
}

/// A compiled entry point with its layout.
struct Kernel {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroupLayout,
}

impl Kernel {
    fn new(
        device: &wgpu::Device,
        passthrough: bool,
        source: &str,
        entry: &str,
        workgroup: (u32, u32, u32),
        bindings: &Bindings,
    ) -> Result<Kernel, String> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = if passthrough {
            let words = spirv::compile(source)?;
            // SAFETY: the SPIR-V is naga's translation of shaders naga validated; the added
            // decorations only forbid the driver to rewrite arithmetic.
            unsafe {
                device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
                    label: Some(entry),
                    entry_points: vec![wgpu::PassthroughShaderEntryPoint {
                        name: entry.into(),
                        workgroup_size: workgroup,
                    }]
                    .into(),
                    spirv: Some(words.into()),
                    ..Default::default()
                })
            }
        } else {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        };
        let output = bindings.output;
        let entries: Vec<wgpu::BindGroupLayoutEntry> = (0..bindings.count)
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: b != output,
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let group = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(entry),
            entries: &entries,
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(entry),
            bind_group_layouts: &[Some(&group)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        if let Some(e) = block(scope.pop()) {
            return Err(format!("{entry}: {e:?}"));
        }
        Ok(Kernel { pipeline, group })
    }
}

fn entry_of(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
