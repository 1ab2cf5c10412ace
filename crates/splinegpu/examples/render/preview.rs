//! `LinePreview`: draws the curves of a job, as [`GpuContext::record_into`] left them in a
//! vertex buffer, as line strips into an offscreen RGBA8 image: a renderer's use of the
//! samples without any readback, and a way to look at them headless (lavapipe works).
//!
//! [`GpuContext::record_into`]: splinegpu::GpuContext::record_into

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use std::error::Error;

use splinegpu::OutputLayout;

/// `shaders/lines.wgsl`.
const LINES_WGSL: &str = include_str!("lines.wgsl");

/// The image format.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The view uniform. WGSL twin: `View` in `shaders/lines.wgsl`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Zeroable, Pod)]
#[repr(C)]
pub(crate) struct LineView {
    /// Clip position = sample.xy · scale + offset.
    pub(crate) scale: [f32; 2],
    /// See `scale`.
    pub(crate) offset: [f32; 2],
    /// RGBA line colour in [0, 1].
    pub(crate) color: [f32; 4],
}

impl LineView {
    /// The view that maps the rectangle [x0, x1] × [y0, y1] of sample space onto the image
    /// (y up), drawing in `color`.
    #[must_use]
    pub(crate) fn fit(x0: f32, y0: f32, x1: f32, y1: f32, color: [f32; 4]) -> Self {
        let scale = [2.0 / (x1 - x0), 2.0 / (y1 - y0)];
        Self {
            scale,
            offset: [-1.0 - x0 * scale[0], -1.0 - y0 * scale[1]],
            color,
        }
    }
}

/// An offscreen image and the line-strip pipelines that draw into it.
#[derive(Debug)]
pub(crate) struct LinePreview {
    width: u32,
    height: u32,
    texture: wgpu::Texture,
    layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
    /// One pipeline per vertex stride (4 · dim bytes).
    pipelines: HashMap<u64, wgpu::RenderPipeline>,
}

impl LinePreview {
    /// A `width` × `height` image on `device`.
    #[must_use]
    pub(crate) fn new(device: &wgpu::Device, width: u32, height: u32) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("preview"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view"),
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
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lines.wgsl"),
            source: wgpu::ShaderSource::Wgsl(LINES_WGSL.into()),
        });
        Self {
            width,
            height,
            texture,
            layout,
            module,
            pipelines: HashMap::new(),
        }
    }

    /// Records a render pass into `encoder` that clears the image to black and draws every
    /// curve of `layout` (of dimension 2 or more) from `buffer`, written there from byte
    /// `offset` on, as a line strip of its samples' first two coordinates.
    pub(crate) fn draw(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        buffer: &wgpu::Buffer,
        offset: u64,
        layout: &OutputLayout,
        view: LineView,
    ) {
        for &dim in &layout.dims {
            let stride = 4 * u64::from(dim);
            if dim >= 2 && !self.pipelines.contains_key(&stride) {
                let pipeline = self.pipeline(device, stride);
                self.pipelines.insert(stride, pipeline);
            }
        }
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("view"),
            contents: bytemuck::bytes_of(&view),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("view"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let target = self.texture.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("curves"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_bind_group(0, &bind_group, &[]);
        for c in 0..layout.dims.len() {
            let (dim, count) = (layout.dims[c], layout.counts[c]);
            if dim < 2 || count == 0 {
                continue;
            }
            let stride = 4 * u64::from(dim);
            let start = offset + layout.curve_starts[c];
            pass.set_pipeline(&self.pipelines[&stride]);
            pass.set_vertex_buffer(0, buffer.slice(start..start + count * stride));
            // A curve's samples fit one storage binding (record_into checks), so well within u32.
            pass.draw(0..u32::try_from(count).unwrap_or(u32::MAX), 0..1);
        }
    }

    /// The image's pixels, RGBA8, row after row from the top.
    ///
    /// # Errors
    /// A device failure while copying or mapping.
    pub(crate) fn read_rgba(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<u8>, Box<dyn Error>> {
        // Rows of a texture copy are padded to 256 bytes.
        let row = 4 * self.width;
        let padded = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let download = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("preview download"),
            size: u64::from(padded * self.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &download,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded),
                    rows_per_image: Some(self.height),
                },
            },
            self.texture.size(),
        );
        queue.submit([encoder.finish()]);
        download.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        device.poll(wgpu::PollType::wait_indefinitely())?;
        let rgba = download
            .get_mapped_range(..)?
            .chunks_exact(padded as usize)
            .flat_map(|r| &r[..row as usize])
            .copied()
            .collect();
        download.unmap();
        Ok(rgba)
    }

    fn pipeline(&self, device: &wgpu::Device, stride: u64) -> wgpu::RenderPipeline {
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lines"),
            bind_group_layouts: &[Some(&self.layout)],
            immediate_size: 0,
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lines"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: stride,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &[wgpu::VertexAttribute {
                        format: wgpu::VertexFormat::Float32x2,
                        offset: 0,
                        shader_location: 0,
                    }],
                })],
            },
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineStrip,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            multiview_mask: None,
            cache: None,
        })
    }
}
