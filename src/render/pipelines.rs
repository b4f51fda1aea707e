//! Drape's render pipelines and their bind group layouts, built once per device.
//!
//! Each WGSL file in `shaders/` is compiled with `frame.wgsl` in front of it
//! (the shared per-frame uniform); [`SHADER_SOURCES`] lists exactly what is
//! compiled, so the naga test validates the same text the GPU sees.

use super::gpu_mesh::FRONT_FACE;
use super::target::{COLOR_FORMAT, DEPTH_FORMAT, SAMPLE_COUNT};

pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

macro_rules! shader {
    ($file:literal) => {
        concat!(include_str!("../../shaders/frame.wgsl"), "\n", include_str!(concat!("../../shaders/", $file)))
    };
}

/// (name, full WGSL source) of every shader module.
pub const SHADER_SOURCES: [(&str, &str); 5] = [
    ("cloth.wgsl", shader!("cloth.wgsl")),
    ("ground.wgsl", shader!("ground.wgsl")),
    ("shadow.wgsl", shader!("shadow.wgsl")),
    ("wire.wgsl", shader!("wire.wgsl")),
    ("overlay.wgsl", shader!("overlay.wgsl")),
];

pub struct Pipelines {
    pub frame_layout: wgpu::BindGroupLayout,
    pub material_layout: wgpu::BindGroupLayout,
    pub shadow_map_layout: wgpu::BindGroupLayout,
    pub cloth: wgpu::RenderPipeline,
    /// The cloth (and opaque solids) in the toon style's flat bands.
    pub cloth_toon: wgpu::RenderPipeline,
    pub ghost: wgpu::RenderPipeline,
    pub wire: wgpu::RenderPipeline,
    pub ground: wgpu::RenderPipeline,
    /// The ground's contact shadow alone, as black with alpha (`--pass shadow`).
    pub ground_shadow: wgpu::RenderPipeline,
    pub shadow: wgpu::RenderPipeline,
    pub segment: wgpu::RenderPipeline,
    pub marker: wgpu::RenderPipeline,
    /// The same markers where the cloth hides them, faint.
    pub marker_hidden: wgpu::RenderPipeline,
}

const POSITION: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 12,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
};
const NORMAL: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 12,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![1 => Float32x3],
};
const UV: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 8,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![2 => Float32x2],
};
/// `render::renderer::SegmentInstance`: a, width_px, b, color, packed.
pub(crate) const SEGMENT_INSTANCE: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 44,
    step_mode: wgpu::VertexStepMode::Instance,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32x4],
};
/// `render::renderer::MarkerInstance`: center, radius_px, fill, ring.
pub(crate) const MARKER_INSTANCE: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: 48,
    step_mode: wgpu::VertexStepMode::Instance,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x4, 3 => Float32x4],
};

/// How a pipeline uses depth: whether it tests and whether it writes.
#[derive(Clone, Copy)]
enum Depth {
    Write,
    TestOnly,
    /// Draws only where something nearer is already drawn.
    Hidden,
}

struct PipelineSpec<'a> {
    label: &'a str,
    module: &'a wgpu::ShaderModule,
    vertex: &'a str,
    fragment: &'a str,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    layout: &'a wgpu::PipelineLayout,
    topology: wgpu::PrimitiveTopology,
    blend: Option<wgpu::BlendState>,
    depth: Depth,
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A filterable 2D texture at `first_binding` and its sampler at the next binding, for fragment shaders.
pub(crate) fn texture_entries(first_binding: u32) -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        wgpu::BindGroupLayoutEntry {
            binding: first_binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: first_binding + 1,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
    ]
}

impl Pipelines {
    pub fn new(device: &wgpu::Device) -> Pipelines {
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[uniform_entry(0)],
        });
        let [texture, sampler] = texture_entries(1);
        let material_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material"),
            entries: &[uniform_entry(0), texture, sampler],
        });
        let shadow_map_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow map"),
            entries: &texture_entries(0),
        });
        let layout = |label, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let frame_only = layout("frame only", &[Some(&frame_layout)]);
        let with_material = layout("frame + material", &[Some(&frame_layout), Some(&material_layout)]);
        let with_shadow = layout("frame + shadow map", &[Some(&frame_layout), Some(&shadow_map_layout)]);

        let modules: Vec<wgpu::ShaderModule> = SHADER_SOURCES
            .iter()
            .map(|(name, source)| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(name),
                    source: wgpu::ShaderSource::Wgsl((*source).into()),
                })
            })
            .collect();
        let [cloth_module, ground_module, shadow_module, wire_module, overlay_module] = &modules[..] else {
            unreachable!("SHADER_SOURCES has five entries");
        };

        let alpha = Some(wgpu::BlendState::ALPHA_BLENDING);
        let mesh_buffers = [Some(POSITION), Some(NORMAL), Some(UV)];
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let build = |spec: PipelineSpec| build_pipeline(device, spec);
        let cloth = build(cloth_spec(cloth_module, &mesh_buffers, &with_material));
        let cloth_toon = build(PipelineSpec {
            label: "cloth, toon",
            fragment: "fs_cloth_toon",
            ..cloth_spec(cloth_module, &mesh_buffers, &with_material)
        });
        let ghost = build(PipelineSpec {
            label: "ghost",
            fragment: "fs_ghost",
            blend: alpha,
            depth: Depth::TestOnly,
            ..cloth_spec(cloth_module, &mesh_buffers, &with_material)
        });
        let wire = build(PipelineSpec {
            label: "wire",
            module: wire_module,
            vertex: "vs_wire",
            fragment: "fs_wire",
            buffers: &[Some(POSITION)],
            layout: &frame_only,
            topology: wgpu::PrimitiveTopology::LineList,
            blend: alpha,
            depth: Depth::TestOnly,
        });
        let ground = build(PipelineSpec {
            label: "ground",
            module: ground_module,
            vertex: "vs_ground",
            fragment: "fs_ground",
            buffers: &[],
            layout: &with_shadow,
            topology: triangles,
            blend: None,
            depth: Depth::Write,
        });
        let ground_shadow = build(PipelineSpec {
            label: "ground shadow pass",
            module: ground_module,
            vertex: "vs_ground",
            fragment: "fs_ground_shadow",
            buffers: &[],
            layout: &with_shadow,
            topology: triangles,
            blend: None,
            depth: Depth::Write,
        });
        let segment = build(PipelineSpec {
            label: "overlay segments",
            module: overlay_module,
            vertex: "vs_segment",
            fragment: "fs_segment",
            buffers: &[Some(SEGMENT_INSTANCE)],
            layout: &frame_only,
            topology: triangles,
            blend: alpha,
            depth: Depth::TestOnly,
        });
        let marker = build(PipelineSpec {
            label: "overlay markers",
            module: overlay_module,
            vertex: "vs_marker",
            fragment: "fs_marker",
            buffers: &[Some(MARKER_INSTANCE)],
            layout: &frame_only,
            topology: triangles,
            blend: alpha,
            depth: Depth::TestOnly,
        });
        let marker_hidden = build(PipelineSpec {
            label: "overlay markers, hidden",
            module: overlay_module,
            vertex: "vs_marker",
            fragment: "fs_marker_hidden",
            buffers: &[Some(MARKER_INSTANCE)],
            layout: &frame_only,
            topology: triangles,
            blend: alpha,
            depth: Depth::Hidden,
        });
        let shadow = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("contact shadow"),
            layout: Some(&frame_only),
            vertex: wgpu::VertexState {
                module: shadow_module,
                entry_point: Some("vs_shadow"),
                compilation_options: Default::default(),
                buffers: &[Some(POSITION)],
            },
            primitive: wgpu::PrimitiveState { topology: triangles, cull_mode: None, ..Default::default() },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: shadow_module,
                entry_point: Some("fs_shadow"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: SHADOW_FORMAT,
                    // The darkest (lowest) cloth over a spot wins.
                    blend: Some(wgpu::BlendState {
                        color: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::One,
                            dst_factor: wgpu::BlendFactor::One,
                            operation: wgpu::BlendOperation::Max,
                        },
                        alpha: wgpu::BlendComponent::REPLACE,
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Pipelines {
            frame_layout,
            material_layout,
            shadow_map_layout,
            cloth,
            cloth_toon,
            ghost,
            wire,
            ground,
            ground_shadow,
            shadow,
            segment,
            marker,
            marker_hidden,
        }
    }
}

fn cloth_spec<'a>(
    module: &'a wgpu::ShaderModule,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    layout: &'a wgpu::PipelineLayout,
) -> PipelineSpec<'a> {
    PipelineSpec {
        label: "cloth",
        module,
        vertex: "vs_cloth",
        fragment: "fs_cloth",
        buffers,
        layout,
        topology: wgpu::PrimitiveTopology::TriangleList,
        blend: None,
        depth: Depth::Write,
    }
}

fn build_pipeline(device: &wgpu::Device, spec: PipelineSpec) -> wgpu::RenderPipeline {
    let depth_stencil = match spec.depth {
        Depth::Write => Some((true, wgpu::CompareFunction::Less)),
        Depth::TestOnly => Some((false, wgpu::CompareFunction::LessEqual)),
        Depth::Hidden => Some((false, wgpu::CompareFunction::Greater)),
    }
    .map(|(write, compare)| wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: wgpu::StencilState::default(),
        bias: wgpu::DepthBiasState::default(),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(spec.layout),
        vertex: wgpu::VertexState {
            module: spec.module,
            entry_point: Some(spec.vertex),
            compilation_options: Default::default(),
            buffers: spec.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: spec.topology,
            front_face: FRONT_FACE,
            // Cloth has two sides: never cull.
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil,
        multisample: wgpu::MultisampleState { count: SAMPLE_COUNT, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: spec.module,
            entry_point: Some(spec.fragment),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: spec.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
