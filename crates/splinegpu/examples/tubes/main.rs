//! Thousands of animated tubes (strands swaying on a grid) made on the GPU straight into a
//! renderer's vertex buffer by a `GeometryRecording`, moving curves refitted each frame without
//! reallocating, drawn with a depth buffer and lit by the crate's exact surface normals, off
//! screen; above them a panel of 2-D strokes (every join and cap, a width per point, dashes and
//! dots, one of them swaying) recorded the same way into the same vertex layout, and among them
//! the Utah teapot, its
//! certified mesh written into its own vertex buffer by a `SurfaceRecording`. The last frame is
//! saved as a PNG and the frame time printed.
//!
//! `cargo run --release -p splinegpu --example tubes -- docs/tubes.png` (lavapipe works).

use std::error::Error;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use splinegpu::geometry::{Cap, Dash, Geometry, GeometryJob, Join, Stroke, Tube, Width};
use splinegpu::surface::{SurfaceJob, SurfaceSampling};
use splinegpu::{
    Basis, Curve, CurveKind, Derivatives, EndCondition, Ends, GeometryRecording, GpuContext,
    Points, Sampling,
};
use wgpu::util::DeviceExt;

#[path = "../common/teapot.rs"]
mod teapot;

use teapot::teapot;

const SIZE: u32 = 768;
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The depth test every pipeline of the scene draws with: nearer wins, written.
fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// The uniform. WGSL twin: `Camera` in tubes.wgsl.
#[derive(Clone, Copy, Debug, Zeroable, Pod)]
#[repr(C)]
struct Camera {
    view_proj: [[f32; 4]; 4],
    light: [f32; 4],
}

/// Strand (i, j) of a `grid` x `grid` field at time `time`: a natural spline through 6 points
/// rising from (i, j, 0), swaying with the time and its place, with a radius that thins
/// toward its tip (one more coordinate of the same spline).
fn strand(i: usize, j: usize, grid: usize, time: f64) -> Curve {
    let (x, y) = (i as f64 - grid as f64 / 2.0, j as f64 - grid as f64 / 2.0);
    let phase = 0.7 * x + 0.4 * y + 1.7 * time;
    let points: Vec<f64> = (0..6)
        .flat_map(|k| {
            let h = k as f64 / 5.0;
            let sway = 0.8 * h * h;
            [
                x + sway * phase.sin(),
                y + sway * (0.8 * phase).cos(),
                3.0 * h + 0.2 * (phase + h).sin(),
            ]
        })
        .collect();
    let kind = CurveKind::Interpolating {
        condition: EndCondition::Natural,
        t: None,
    };
    Curve::new(kind, Points::new(3, points).expect("6 points")).expect("a strand")
}

/// The strands' geometry: radius 0.16 at the root thinning to 0.04, 8 sides, capped.
fn tube() -> Geometry {
    Geometry::Tube(Tube {
        radius: Width::PerPoint(vec![0.16, 0.14, 0.12, 0.09, 0.06, 0.04]),
        sides: Some(8),
        caps: true,
        ..Tube::default()
    })
}

/// Everything drawn: the recording, the renderer's vertex and index buffers, the pipeline.
struct Scene {
    job: GeometryJob,
    recording: GeometryRecording,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    pipeline: wgpu::RenderPipeline,
    camera_layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    color: wgpu::Texture,
    depth: wgpu::Texture,
    panel: Option<Panel>,
    teapot: Option<Teapot>,
}

/// The teapot: its certified mesh's positions and normals (two planes of one buffer, as the
/// surface recording lays them out), its indices, a camera with its model transform, and a
/// pipeline that reads the two planes and lights both sides.
struct Teapot {
    vertices: wgpu::Buffer,
    normals_at: u64,
    indices: wgpu::Buffer,
    index_count: u32,
    bind_group: wgpu::BindGroup,
    pipeline: wgpu::RenderPipeline,
}

/// The strokes panel: its job and recording (the wave of growing width sways), its vertex
/// buffer in the tubes' layout, its indices and its orthographic camera.
struct Panel {
    job: GeometryJob,
    recording: GeometryRecording,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    bind_group: wgpu::BindGroup,
}

/// The panel's stroke space, [0, 12] x [0, PANEL_HEIGHT], drawn across the image's top.
const PANEL_WIDTH: f32 = 12.0;
const PANEL_HEIGHT: f32 = 3.36;

/// A polyline through `corners` as cubic Bezier pieces with their control points a third and
/// two thirds along each side (straight: its corners are the stroke's joints).
fn polyline(corners: &[[f64; 2]]) -> Curve {
    let mut points = vec![corners[0][0], corners[0][1]];
    for pair in corners.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        for k in 1..=3 {
            let s = f64::from(k) / 3.0;
            points.extend([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]);
        }
    }
    Curve::new(CurveKind::Bezier, Points::new(2, points).expect("points")).expect("a polyline")
}

/// `n` points of a wave from x0, `amplitude` high.
fn wave(x0: f64, n: usize, amplitude: f64) -> Vec<f64> {
    (0..n)
        .flat_map(|k| {
            let x = x0 + 1.6 * k as f64 / (n - 1) as f64;
            [x, 1.7 + amplitude * (2.4 * k as f64).sin()]
        })
        .collect()
}

fn curve(points: Vec<f64>) -> Curve {
    let catmull = CurveKind::Uniform {
        basis: Basis::CatmullRom,
        ends: Ends::Repeat,
    };
    Curve::new(catmull, Points::new(2, points).expect("points")).expect("a wave")
}

/// The panel's stroke of growing width at `time`: its wave sways.
fn swaying_wave(time: f64) -> Curve {
    curve(wave(6.6, 7, 0.8 * (1.3 * time).cos()))
}

/// Where the swaying wave is among the panel's strokes.
const SWAYING: usize = 3;

/// The panel's strokes: a zigzag for each join (miter, round, bevel) with each cap (butt,
/// round, square); a wave whose width grows point by point; a dashed curve; a dotted one.
fn panel_strokes() -> Vec<(Curve, Geometry, Sampling)> {
    let stroke = |width, cap, join, dash| {
        Geometry::Stroke(Stroke {
            width,
            cap,
            join,
            dash,
            ..Stroke::default()
        })
    };
    let mut out = Vec::new();
    for (i, (join, cap)) in [
        (Join::Miter, Cap::Butt),
        (Join::Round, Cap::Round),
        (Join::Bevel, Cap::Square),
    ]
    .into_iter()
    .enumerate()
    {
        // Interior angles of 39 degrees: a miter ratio of 3, within the limit of 4.
        let x = 0.4 + 2.0 * i as f64;
        let zigzag = polyline(&[[x, 2.5], [x + 0.6, 0.8], [x + 1.2, 2.5], [x + 1.8, 0.8]]);
        out.push((
            zigzag,
            stroke(Width::Constant(0.28), cap, join, None),
            Sampling::PerSegment(4),
        ));
    }
    out.push((
        swaying_wave(0.0),
        stroke(
            Width::PerPoint((0..7).map(|k| 0.05 + 0.07 * f64::from(k)).collect()),
            Cap::Round,
            Join::Round,
            None,
        ),
        Sampling::PerSegment(12),
    ));
    let dashes = |lengths: Vec<f64>| {
        Some(Dash {
            lengths,
            offset: 0.0,
        })
    };
    out.push((
        curve(wave(8.5, 7, 0.9)),
        stroke(
            Width::Constant(0.16),
            Cap::Round,
            Join::Round,
            dashes(vec![0.35, 0.2]),
        ),
        Sampling::ArcLength(200),
    ));
    out.push((
        curve(wave(10.35, 7, 0.9)),
        stroke(
            Width::Constant(0.2),
            Cap::Round,
            Join::Round,
            dashes(vec![0.0, 0.3]),
        ),
        Sampling::ArcLength(200),
    ));
    out
}

impl Panel {
    /// The strokes' recording, writing the tubes' vertex layout (position, normal +z) into
    /// the panel's vertex buffer each frame; their indices uploaded once.
    fn new(gpu: &GpuContext, layout: &wgpu::BindGroupLayout) -> Result<Self, Box<dyn Error>> {
        let device = gpu.device();
        let mut job = GeometryJob::new();
        job.push_many(&panel_strokes())?;
        let recording = gpu.geometry_recording(&job)?;
        let indices = recording.indices().to_vec();
        // Stroke space onto the panel's viewport, at depth 0: in front of every tube.
        let projection = Mat4::from_cols(
            glam::Vec4::new(2.0 / PANEL_WIDTH, 0.0, 0.0, 0.0),
            glam::Vec4::new(0.0, 2.0 / PANEL_HEIGHT, 0.0, 0.0),
            glam::Vec4::ZERO,
            glam::Vec4::new(-1.0, -1.0, 0.0, 1.0),
        );
        let light = Vec3::new(0.3, -0.3, 0.9).normalize();
        let camera = Camera {
            view_proj: projection.to_cols_array_2d(),
            light: [light.x, light.y, light.z, 0.0],
        };
        let init = |label, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let uniform = init(
            "panel camera",
            bytemuck::bytes_of(&camera),
            wgpu::BufferUsages::UNIFORM,
        );
        let vertices = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("panel vertices"),
            size: recording.layout().bytes.max(4),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
            mapped_at_creation: false,
        });
        Ok(Self {
            job,
            recording,
            vertices,
            indices: init(
                "panel indices",
                bytemuck::cast_slice(&indices),
                wgpu::BufferUsages::INDEX,
            ),
            index_count: indices.len() as u32,
            bind_group: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("panel camera"),
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                }],
            }),
        })
    }
}

impl Scene {
    fn new(
        gpu: &GpuContext,
        grid: usize,
        camera: &Camera,
        size: u32,
    ) -> Result<Self, Box<dyn Error>> {
        let device = gpu.device();
        let mut job = GeometryJob::new();
        let work: Vec<_> = (0..grid * grid)
            .map(|s| {
                (
                    strand(s % grid, s / grid, grid, 0.0),
                    tube(),
                    Sampling::PerSegment(12),
                )
            })
            .collect();
        job.push_many(&work)?;
        let recording = gpu.geometry_recording(&job)?;
        let vertices = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tube vertices"),
            size: recording.layout().bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
            mapped_at_creation: false,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("tube indices"),
            contents: bytemuck::cast_slice(recording.indices()),
            usage: wgpu::BufferUsages::INDEX,
        });
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("camera"),
            contents: bytemuck::bytes_of(camera),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("camera"),
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
            label: Some("camera"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tubes.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("tubes.wgsl").into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("tubes"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("tubes"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: recording.layout().stride,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                })],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            primitive: wgpu::PrimitiveState {
                // The crate's triangles are counter-clockwise seen from outside.
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: Some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(depth_test()),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        let target = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        Ok(Self {
            index_count: recording.indices().len() as u32,
            job,
            recording,
            vertices,
            indices,
            pipeline,
            camera_layout: layout,
            bind_group,
            color: target("color", FORMAT, attachment | wgpu::TextureUsages::COPY_SRC),
            depth: target("depth", DEPTH, attachment),
            panel: None,
            teapot: None,
        })
    }

    /// Adds the teapot, `scale` times its size at `at`: meshed within 1e-3 of its extent and
    /// recorded into its vertex buffer once (it does not move).
    fn add_teapot(
        &mut self,
        gpu: &GpuContext,
        camera: &Camera,
        scale: f32,
        at: Vec3,
    ) -> Result<(), Box<dyn Error>> {
        let device = gpu.device();
        let surface = teapot()?;
        let tolerance = 1e-3 * surface.net().extent();
        let mut job = SurfaceJob::new(Derivatives::None, true);
        job.push(surface.fit(), SurfaceSampling::Tolerance(tolerance))?;
        let recording = gpu.surface_recording(&job)?;
        let layout = recording.layout();
        let vertices = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("teapot vertices"),
            size: layout.bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        recording.record_into(gpu, &mut encoder, &vertices, 0)?;
        gpu.queue().submit([encoder.finish()]);
        let model = Mat4::from_translation(at) * Mat4::from_scale(Vec3::splat(scale));
        let placed = Camera {
            view_proj: (Mat4::from_cols_array_2d(&camera.view_proj) * model).to_cols_array_2d(),
            light: camera.light,
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("teapot camera"),
            contents: bytemuck::bytes_of(&placed),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("teapot camera"),
            layout: &self.camera_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tubes.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("tubes.wgsl").into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("teapot"),
            bind_group_layouts: &[Some(&self.camera_layout)],
            immediate_size: 0,
        });
        let plane = |location| wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: if location == 0 {
                &wgpu::vertex_attr_array![0 => Float32x3]
            } else {
                &wgpu::vertex_attr_array![1 => Float32x3]
            },
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("teapot"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(plane(0)), Some(plane(1))],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_two_sided"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            primitive: Default::default(),
            depth_stencil: Some(depth_test()),
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        });
        self.teapot = Some(Teapot {
            normals_at: layout.normals.ok_or("the teapot's normals")?,
            index_count: recording.indices().len() as u32,
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("teapot indices"),
                contents: bytemuck::cast_slice(recording.indices()),
                usage: wgpu::BufferUsages::INDEX,
            }),
            vertices,
            bind_group,
            pipeline,
        });
        Ok(())
    }

    /// Adds the strokes panel across the image's top.
    fn add_panel(&mut self, gpu: &GpuContext) -> Result<(), Box<dyn Error>> {
        self.panel = Some(Panel::new(gpu, &self.camera_layout)?);
        Ok(())
    }

    /// One frame at `time`: the strands (and the panel's swaying stroke) refitted on the host
    /// and uploaded in place, the kernel recorded into the vertex buffers, the meshes drawn;
    /// submitted and waited for.
    fn frame(&mut self, gpu: &GpuContext, grid: usize, time: f64) -> Result<(), Box<dyn Error>> {
        for s in 0..grid * grid {
            self.job.refit(s, &strand(s % grid, s / grid, grid, time))?;
        }
        self.recording.refit(gpu, &self.job)?;
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        self.recording
            .record_into(gpu, &mut encoder, &self.vertices, 0)?;
        if let Some(panel) = &mut self.panel {
            panel.job.refit(SWAYING, &swaying_wave(time))?;
            panel.recording.refit(gpu, &panel.job)?;
            panel
                .recording
                .record_into(gpu, &mut encoder, &panel.vertices, 0)?;
        }
        {
            let color = self.color.create_view(&Default::default());
            let depth = self.depth.create_view(&Default::default());
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tubes"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.02,
                            g: 0.02,
                            b: 0.03,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_vertex_buffer(0, self.vertices.slice(..));
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
            if let Some(teapot) = &self.teapot {
                pass.set_pipeline(&teapot.pipeline);
                pass.set_bind_group(0, &teapot.bind_group, &[]);
                pass.set_vertex_buffer(0, teapot.vertices.slice(..teapot.normals_at));
                pass.set_vertex_buffer(1, teapot.vertices.slice(teapot.normals_at..));
                pass.set_index_buffer(teapot.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..teapot.index_count, 0, 0..1);
                pass.set_pipeline(&self.pipeline);
            }
            if let Some(panel) = &self.panel {
                let width = self.color.width() as f32;
                pass.set_viewport(
                    0.0,
                    0.0,
                    width,
                    width * PANEL_HEIGHT / PANEL_WIDTH,
                    0.0,
                    1.0,
                );
                pass.set_bind_group(0, &panel.bind_group, &[]);
                pass.set_vertex_buffer(0, panel.vertices.slice(..));
                pass.set_index_buffer(panel.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..panel.index_count, 0, 0..1);
            }
        }
        gpu.queue().submit([encoder.finish()]);
        gpu.device().poll(wgpu::PollType::wait_indefinitely())?;
        Ok(())
    }

    /// The image's pixels, RGBA8, row after row from the top.
    fn read_rgba(&self, gpu: &GpuContext) -> Result<Vec<u8>, Box<dyn Error>> {
        let (width, height) = (self.color.width(), self.color.height());
        let row = 4 * width;
        let padded = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let download = gpu.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("image download"),
            size: u64::from(padded * height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.color.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &download,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(height),
                },
            },
            self.color.size(),
        );
        gpu.queue().submit([encoder.finish()]);
        download.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        gpu.device().poll(wgpu::PollType::wait_indefinitely())?;
        let rgba = download
            .get_mapped_range(..)?
            .chunks_exact(padded as usize)
            .flat_map(|r| &r[..row as usize])
            .copied()
            .collect();
        download.unmap();
        Ok(rgba)
    }
}

/// The view matrix of a camera at `eye` looking at `target` with `up` (right-handed).
fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let f = (target - eye).normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        glam::Vec4::new(s.x, u.x, -f.x, 0.0),
        glam::Vec4::new(s.y, u.y, -f.y, 0.0),
        glam::Vec4::new(s.z, u.z, -f.z, 0.0),
        glam::Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// A perspective projection of vertical field of view `fov` (radians), square, depth 0 at
/// `near` and 1 at `far` (wgpu's clip space).
fn perspective(fov: f32, near: f32, far: f32) -> Mat4 {
    let h = 1.0 / (0.5 * fov).tan();
    let r = far / (near - far);
    Mat4::from_cols(
        glam::Vec4::new(h, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, h, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, r, -1.0),
        glam::Vec4::new(0.0, 0.0, r * near, 0.0),
    )
}

/// Looking down at the field from a corner, lit from above and behind the camera.
fn camera(grid: usize) -> Camera {
    let g = grid as f32;
    let eye = Vec3::new(0.85 * g, -1.1 * g, 0.8 * g);
    let view = look_at(eye, Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
    let projection = perspective(0.62, 0.5, 4.0 * g);
    let light = Vec3::new(0.4, -0.6, 0.7).normalize();
    Camera {
        view_proj: (projection * view).to_cols_array_2d(),
        light: [light.x, light.y, light.z, 0.0],
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let output = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "out/tubes.png".to_string());
    let gpu = GpuContext::new()?;
    // 2,500 strands: 5 segments of 12 rings of 8 a strand, capped: 1.22 M vertices.
    let grid = 50;
    let mut scene = Scene::new(&gpu, grid, &camera(grid), SIZE)?;
    scene.add_panel(&gpu)?;
    scene.add_teapot(&gpu, &camera(grid), 3.2, Vec3::new(4.0, -8.0, 0.0))?;
    let frames = 6;
    scene.frame(&gpu, grid, 0.0)?;
    let start = Instant::now();
    for f in 1..=frames {
        scene.frame(&gpu, grid, 0.25 * f64::from(f))?;
    }
    let per_frame = start.elapsed().as_secs_f64() / f64::from(frames);
    let rgba = scene.read_rgba(&gpu)?;
    if let Some(dir) = std::path::Path::new(&output).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut encoder = png::Encoder::new(
        std::io::BufWriter::new(std::fs::File::create(&output)?),
        SIZE,
        SIZE,
    );
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(&rgba)?;
    let info = gpu.adapter_info();
    println!(
        "{} strands, {} vertices, {} triangles a frame: {:.1} ms a frame (refit on the host, \
         recorded, drawn, waited for) on {}; the last frame in {output}",
        scene.job.len(),
        scene.job.vertex_count(),
        scene.job.triangle_count(),
        per_frame * 1e3,
        info.name
    );
    Ok(())
}

/// The drawing reads what the recording wrote (`cargo test --example tubes`): one strand seen
/// from the side lights pixels only where the f64 reference's vertices project, brightest
/// where its normals face the light; and the uniform matches its WGSL twin.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_uniform_matches_its_wgsl_twin() {
        let module = naga::front::wgsl::parse_str(include_str!("tubes.wgsl")).unwrap();
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some("Camera"))
            .expect("struct Camera in tubes.wgsl");
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("Camera is not a struct");
        };
        assert_eq!(*span as usize, size_of::<Camera>());
        let offsets: Vec<u32> = members.iter().map(|m| m.offset).collect();
        assert_eq!(
            offsets,
            [
                std::mem::offset_of!(Camera, view_proj) as u32,
                std::mem::offset_of!(Camera, light) as u32
            ]
        );
    }

    #[test]
    fn a_drawn_strand_is_lit_where_it_projects_brightest_facing_the_light() {
        let Ok(gpu) = GpuContext::new() else {
            eprintln!("no GPU adapter: skipped");
            return;
        };
        // One strand (grid 1) at time 0, seen from straight ahead (-y), lit from the camera.
        let size = 96;
        let view = look_at(Vec3::new(0.0, -8.0, 1.5), Vec3::new(0.0, 0.0, 1.5), Vec3::Z);
        let projection = perspective(0.7, 0.5, 40.0);
        let camera = Camera {
            view_proj: (projection * view).to_cols_array_2d(),
            light: [0.0, -1.0, 0.0, 0.0],
        };
        let mut scene = Scene::new(&gpu, 1, &camera, size).unwrap();
        scene.frame(&gpu, 1, 0.0).unwrap();
        let rgba = scene.read_rgba(&gpu).unwrap();
        let brightness = |x: u32, y: u32| u32::from(rgba[(4 * (y * size + x)) as usize]);
        let background = brightness(0, 0);
        // Where the f64 reference's vertices project, in pixels (y down).
        let reference = scene.job.evaluate_cpu();
        let (mut low, mut high) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in reference.points.chunks_exact(3) {
            let clip =
                (projection * view) * glam::Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, 1.0);
            let pixel = [
                (clip.x / clip.w + 1.0) / 2.0 * size as f32,
                (1.0 - clip.y / clip.w) / 2.0 * size as f32,
            ];
            for k in 0..2 {
                low[k] = low[k].min(pixel[k]);
                high[k] = high[k].max(pixel[k]);
            }
        }
        let mut lit = 0;
        for y in 0..size {
            for x in 0..size {
                if brightness(x, y) > background + 20 {
                    lit += 1;
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    assert!(
                        px >= low[0] - 2.0
                            && px <= high[0] + 2.0
                            && py >= low[1] - 2.0
                            && py <= high[1] + 2.0,
                        "pixel ({x}, {y}) lit outside the strand's box {low:?}..{high:?}"
                    );
                }
            }
        }
        assert!(lit > 100, "only {lit} pixels lit");
        // Facing the light, the middle is brighter than the rim (the normals turn away).
        let row = size / 2;
        let rim = (0..size)
            .filter(|&x| brightness(x, row) > background + 20)
            .collect::<Vec<_>>();
        let (first, last) = (rim[0], rim[rim.len() - 1]);
        assert!(brightness((first + last) / 2, row) > brightness(first, row));
    }
}
