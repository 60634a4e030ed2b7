//! The wgpu renderer: device, pipelines, render targets and read-back.

use crate::RenderError;
use crate::camera::Camera;
use crate::frame::Frame;
use crate::mesh::{self, Vertex};
use crate::snapshot::{HullMesh, MeshKind, Snapshot};
use bytemuck::{Pod, Zeroable};
use std::ops::Range;
use std::sync::Arc;
use wgpu::util::DeviceExt;

/// Multisampling: 4 samples, the count every adapter supports.
const SAMPLES: u32 = 4;
const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The background, linear RGB.
const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.93,
    g: 0.94,
    b: 0.96,
    a: 1.0,
};

/// Which adapter to render on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AdapterChoice {
    /// The CPU (Mesa's lavapipe or llvmpipe): the same pictures on every machine.
    #[default]
    Software,
    /// A real GPU when there is one (the software adapter otherwise).
    Gpu,
}

impl AdapterChoice {
    /// `KINETIC_RENDER_ADAPTER=gpu` picks [`AdapterChoice::Gpu`]; anything else, software.
    pub fn from_env() -> AdapterChoice {
        match std::env::var("KINETIC_RENDER_ADAPTER").as_deref() {
            Ok("gpu") => AdapterChoice::Gpu,
            _ => AdapterChoice::Software,
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
    up: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct InstanceRaw {
    model: [[f32; 4]; 4],
    colour: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LineVertex {
    position: [f32; 3],
    colour: [f32; 4],
}

/// Size-dependent textures and the read-back buffer.
struct Targets {
    width: u32,
    height: u32,
    msaa: wgpu::TextureView,
    depth: wgpu::TextureView,
    resolve: wgpu::Texture,
    readback: wgpu::Buffer,
    padded_row: u32,
}

/// A buffer that grows to fit.
struct Growable {
    buffer: Option<wgpu::Buffer>,
    usage: wgpu::BufferUsages,
}

impl Growable {
    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        let fits = self
            .buffer
            .as_ref()
            .is_some_and(|b| b.size() >= bytes.len() as u64);
        if !fits {
            let size = (bytes.len() as u64).next_power_of_two().max(256);
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size,
                usage: self.usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(b) = &self.buffer {
            queue.write_buffer(b, 0, bytes);
        }
    }
}

/// Hull meshes uploaded: the list they came from, their vertices, each mesh's range.
type HullBuffer = (Arc<Vec<HullMesh>>, wgpu::Buffer, Vec<Range<u32>>);

/// A headless renderer: snapshots in, RGBA frames out.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    mesh_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    globals: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    targets: Targets,
    /// Balls at 3, 2 and 1 subdivisions, the cube and the quad, one after another.
    base: wgpu::Buffer,
    base_ranges: [Range<u32>; 5],
    /// The hull meshes of the last snapshot (uploaded again when the `Arc` changes).
    hulls: Option<HullBuffer>,
    instances: Growable,
    lines: Growable,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("adapter", &self.adapter())
            .field("size", &(self.targets.width, self.targets.height))
            .finish_non_exhaustive()
    }
}

impl Renderer {
    /// A renderer for `width` x `height` pictures on the chosen adapter.
    pub fn new(width: u32, height: u32, choice: AdapterChoice) -> Result<Renderer, RenderError> {
        // Vulkan first: asking GL too would probe EGL displays (and print their complaints)
        // even when lavapipe answers.
        let tries = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::VULKAN, wgpu::Backends::GL],
        };
        let fallbacks: &[bool] = match choice {
            AdapterChoice::Software => &[true],
            AdapterChoice::Gpu => &[false, true],
        };
        let mut failures = Vec::new();
        let mut found = None;
        'search: for &fallback in fallbacks {
            for &backends in &tries {
                let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
                    backends,
                    ..wgpu::InstanceDescriptor::new_without_display_handle()
                });
                match pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    force_fallback_adapter: fallback,
                    compatible_surface: None,
                    ..Default::default()
                })) {
                    Ok(adapter) => {
                        found = Some(adapter);
                        break 'search;
                    }
                    Err(e) => failures.push(format!("{backends:?}: {e}")),
                }
            }
        }
        let adapter = found.ok_or_else(|| RenderError::NoAdapter {
            detail: failures.join("; "),
        })?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("kinetic-render"),
            required_limits:
                wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| RenderError::Device(e.to_string()))?;

        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: None,
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let mesh_pipeline = pipeline(
            &device,
            &pipeline_layout,
            include_str!("mesh.wgsl"),
            &[
                Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                }),
                Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<InstanceRaw>() as u64,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &wgpu::vertex_attr_array![
                        2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4
                    ],
                }),
            ],
            wgpu::PrimitiveTopology::TriangleList,
        );
        let line_pipeline = pipeline(
            &device,
            &pipeline_layout,
            include_str!("lines.wgsl"),
            &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<LineVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
            })],
            wgpu::PrimitiveTopology::LineList,
        );

        let parts = [
            mesh::ball(3),
            mesh::ball(2),
            mesh::ball(1),
            mesh::cube(),
            mesh::quad(),
        ];
        let mut all = Vec::new();
        let mut ranges: [Range<u32>; 5] = Default::default();
        for (range, part) in ranges.iter_mut().zip(&parts) {
            let start = all.len() as u32;
            all.extend_from_slice(part);
            *range = start..all.len() as u32;
        }
        let base = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("meshes"),
            contents: bytemuck::cast_slice(&all),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let targets = targets(&device, width, height)?;
        Ok(Renderer {
            device,
            queue,
            info,
            mesh_pipeline,
            line_pipeline,
            globals,
            bind_group,
            targets,
            base,
            base_ranges: ranges,
            hulls: None,
            instances: Growable {
                buffer: None,
                usage: wgpu::BufferUsages::VERTEX,
            },
            lines: Growable {
                buffer: None,
                usage: wgpu::BufferUsages::VERTEX,
            },
        })
    }

    /// The adapter in words: name, backend and type (e.g. `llvmpipe (LLVM 15.0.6, 256 bits)
    /// on Gl (Cpu)`).
    pub fn adapter(&self) -> String {
        format!(
            "{} on {:?} ({:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// The picture size.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }

    /// Renders later pictures at `width` x `height`.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        if (width, height) != self.size() {
            self.targets = targets(&self.device, width, height)?;
        }
        Ok(())
    }

    /// Renders `snapshot` from `camera` and reads the picture back.
    pub fn render(&mut self, snapshot: &Snapshot, camera: &Camera) -> Result<Frame, RenderError> {
        let (width, height) = self.size();
        let eye = camera.eye;
        let up = camera.up.normalize_or(glam::Vec3::Z);
        // Key light from over the camera's left shoulder.
        let view = (camera.target - eye).normalize_or(glam::Vec3::X);
        let left = up.cross(view).normalize_or(glam::Vec3::X);
        let light = (-view + up * 1.2 + left * 0.6).normalize();
        let g = Globals {
            view_proj: camera
                .view_projection(width as f32 / height as f32)
                .to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            light: light.extend(0.0).to_array(),
            up: up.extend(0.0).to_array(),
        };
        self.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
        self.upload_hulls(&snapshot.hulls);

        // Instances grouped by mesh, in snapshot order within a group (deterministic).
        let balls = snapshot
            .instances
            .iter()
            .filter(|i| i.mesh == MeshKind::Ball)
            .count();
        let ball_mesh = match balls {
            // Fewer triangles per ball as balls get many (and small on screen): 1280, 320, 80.
            0..=100 => 0,
            101..=2000 => 1,
            _ => 2,
        };
        let mut order: Vec<usize> = (0..snapshot.instances.len()).collect();
        order.sort_by_key(|&i| snapshot.instances[i].mesh);
        let raw: Vec<InstanceRaw> = order
            .iter()
            .map(|&i| InstanceRaw {
                model: snapshot.instances[i].transform.to_cols_array_2d(),
                colour: snapshot.instances[i].colour,
            })
            .collect();
        let mut draws: Vec<(Range<u32>, Range<u32>, bool)> = Vec::new();
        let mut start = 0;
        while start < order.len() {
            let kind = snapshot.instances[order[start]].mesh;
            let end = start
                + order[start..]
                    .iter()
                    .take_while(|&&i| snapshot.instances[i].mesh == kind)
                    .count();
            let (vertices, hull) = match kind {
                MeshKind::Ball => (self.base_ranges[ball_mesh].clone(), false),
                MeshKind::Cuboid => (self.base_ranges[3].clone(), false),
                MeshKind::Quad => (self.base_ranges[4].clone(), false),
                MeshKind::Hull(h) => {
                    match self.hulls.as_ref().and_then(|(_, _, r)| r.get(h as usize)) {
                        Some(r) => (r.clone(), true),
                        None => {
                            return Err(RenderError::Snapshot(format!(
                                "instance refers to hull {h}, the snapshot has {}",
                                snapshot.hulls.len()
                            )));
                        }
                    }
                }
            };
            draws.push((vertices, start as u32..end as u32, hull));
            start = end;
        }
        if !raw.is_empty() {
            self.instances
                .write(&self.device, &self.queue, bytemuck::cast_slice(&raw));
        }
        let line_vertices: Vec<LineVertex> = snapshot
            .lines
            .iter()
            .flat_map(|l| {
                [l.a, l.b].map(|p| LineVertex {
                    position: p.to_array(),
                    colour: l.colour,
                })
            })
            .collect();
        if !line_vertices.is_empty() {
            self.lines.write(
                &self.device,
                &self.queue,
                bytemuck::cast_slice(&line_vertices),
            );
        }

        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        let resolve_view = self
            .targets
            .resolve
            .create_view(&wgpu::TextureViewDescriptor::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.targets.msaa,
                    depth_slice: None,
                    resolve_target: Some(&resolve_view),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(BACKGROUND),
                        store: wgpu::StoreOp::Discard,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.bind_group, &[]);
            if let Some(instances) = &self.instances.buffer
                && !raw.is_empty()
            {
                pass.set_pipeline(&self.mesh_pipeline);
                pass.set_vertex_buffer(1, instances.slice(..));
                for (vertices, range, hull) in &draws {
                    let source = match (&self.hulls, hull) {
                        (Some((_, buffer, _)), true) => buffer,
                        _ => &self.base,
                    };
                    pass.set_vertex_buffer(0, source.slice(..));
                    pass.draw(vertices.clone(), range.clone());
                }
            }
            if let Some(lines) = &self.lines.buffer
                && !line_vertices.is_empty()
            {
                pass.set_pipeline(&self.line_pipeline);
                pass.set_vertex_buffer(0, lines.slice(..));
                pass.draw(0..line_vertices.len() as u32, 0..1);
            }
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.targets.resolve,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.targets.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.targets.padded_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.queue.submit([encoder.finish()]);
        self.read_back()
    }

    fn upload_hulls(&mut self, hulls: &Arc<Vec<HullMesh>>) {
        if hulls.is_empty()
            || self
                .hulls
                .as_ref()
                .is_some_and(|(h, _, _)| Arc::ptr_eq(h, hulls))
        {
            return;
        }
        let mut all = Vec::new();
        let mut ranges = Vec::with_capacity(hulls.len());
        for h in hulls.iter() {
            let start = all.len() as u32;
            all.extend(mesh::hull(h));
            ranges.push(start..all.len() as u32);
        }
        if all.is_empty() {
            all.push(Vertex {
                position: [0.0; 3],
                normal: [0.0, 0.0, 1.0],
            });
        }
        let buffer = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("hulls"),
                contents: bytemuck::cast_slice(&all),
                usage: wgpu::BufferUsages::VERTEX,
            });
        self.hulls = Some((hulls.clone(), buffer, ranges));
    }

    fn read_back(&self) -> Result<Frame, RenderError> {
        let t = &self.targets;
        let slice = t.readback.slice(..);
        let (send, receive) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = send.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Device(e.to_string()))?;
        receive
            .recv()
            .map_err(|e| RenderError::Device(e.to_string()))?
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let row = t.width as usize * 4;
        let mut rgba = Vec::with_capacity(row * t.height as usize);
        {
            let view = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Device(e.to_string()))?;
            for y in 0..t.height as usize {
                let start = y * t.padded_row as usize;
                rgba.extend_from_slice(&view[start..start + row]);
            }
        }
        t.readback.unmap();
        Ok(Frame::new(t.width, t.height, rgba))
    }
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    source: &str,
    buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
    topology: wgpu::PrimitiveTopology,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: SAMPLES,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOUR,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

fn targets(device: &wgpu::Device, width: u32, height: u32) -> Result<Targets, RenderError> {
    let max = device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::Size { width, height, max });
    }
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = |samples: u32, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size,
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let msaa = texture(SAMPLES, COLOUR, wgpu::TextureUsages::RENDER_ATTACHMENT)
        .create_view(&wgpu::TextureViewDescriptor::default());
    let depth = texture(SAMPLES, DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT)
        .create_view(&wgpu::TextureViewDescriptor::default());
    let resolve = texture(
        1,
        COLOUR,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    // Rows copied to a buffer must be padded to a multiple of 256 bytes.
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let padded_row = (width * 4).div_ceil(align) * align;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded_row as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    Ok(Targets {
        width,
        height,
        msaa,
        depth,
        resolve,
        readback,
        padded_row,
    })
}
