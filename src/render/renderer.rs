//! The renderer: owns the pipelines and every GPU buffer, takes a [`Mesh`]
//! with a camera, ghosts and overlays, and draws them into an
//! [`OffscreenTarget`]. It knows nothing of windows or egui: the editor
//! calls [`Renderer::prepare`] and [`Renderer::encode`] from its paint
//! callback, headless code through [`Renderer::render`].

use std::ops::Deref;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use super::camera::OrbitCamera;
use super::gpu_mesh::GpuMesh;
use super::ink::{InkEdges, InkLine};
use super::overlay::Overlay;
use super::pipelines::{Pipelines, SHADOW_FORMAT};
use super::solids::{SolidTexture, Solids};
use super::style::Style;
use super::target::OffscreenTarget;
use super::textures;
use super::uniforms::{FrameUniform, MaterialUniform, SHADOW_MAP_PX, shadow_clip_from_world};
use crate::look;
use crate::mesh::Mesh;
use crate::scene::ClothTexture;

/// How the cloth and its surroundings look. Colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub texture: ClothTexture,
    pub front_tint: [f32; 3],
    pub back_tint: [f32; 3],
    pub wireframe: bool,
    pub wire_color: [f32; 4],
    pub ground: Option<Ground>,
    pub background: [f32; 3],
    /// Clears to transparent black instead of `background`, for renders with
    /// alpha: what is drawn is opaque, the rest alpha 0 (the resolved
    /// picture's edges come premultiplied).
    pub transparent: bool,
    /// Lit, or toon with its bands, ink and colours (which replace the tints where given).
    pub style: Style,
    /// Draws only the cloth's shadow on the ground, as black with alpha over
    /// transparency (a compositing pass): no cloth, grid, solids or overlays.
    /// Needs `ground` and `transparent`.
    pub shadow_only: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            texture: ClothTexture::Plain,
            front_tint: look::PLAIN_FRONT_TINT,
            back_tint: look::PLAIN_BACK_TINT,
            wireframe: false,
            wire_color: [0.02, 0.02, 0.03, 0.55],
            ground: Some(Ground::default()),
            background: [0.028, 0.031, 0.036],
            transparent: false,
            style: Style::Lit,
            shadow_only: false,
        }
    }
}

impl RenderOptions {
    /// Tints that suit a texture (see [`look`]).
    pub fn with_texture(mut self, texture: ClothTexture) -> Self {
        self.texture = texture;
        if texture != ClothTexture::Plain {
            self.front_tint = look::TEXTURED_FRONT_TINT;
            self.back_tint = look::TEXTURED_BACK_TINT;
        }
        self
    }
}

/// Where the ground is and how much of it is drawn. The shadow covers the
/// square of half size `shadow_half_m` round `center`; the grid fades out at
/// `half_size_m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    pub height_m: f32,
    pub center: Vec2,
    pub half_size_m: f32,
    pub shadow_half_m: f32,
    pub grid_spacing_m: f32,
}

impl Default for Ground {
    fn default() -> Self {
        Ground { height_m: 0.0, center: Vec2::ZERO, half_size_m: 6.0, shadow_half_m: 2.0, grid_spacing_m: 0.25 }
    }
}

impl Ground {
    /// A ground under the box `min..max`: at height 0, or just below the box
    /// when it reaches under 0, with a grid spacing of 1, 2.5 or 5 × 10ⁿ metres
    /// giving about ten lines across the box.
    pub fn under(min: Vec3, max: Vec3) -> Ground {
        let extent_m = (max - min).max_element().max(0.1);
        let center = Vec2::new(min.x + max.x, min.z + max.z) * 0.5;
        let horizontal_m = (max.x - min.x).max(max.z - min.z).max(0.1);
        let wanted = extent_m / 10.0;
        let decade = 10f32.powf(wanted.log10().floor());
        let grid_spacing_m = [1.0, 2.5, 5.0, 10.0].iter().map(|m| m * decade).find(|s| *s >= wanted).unwrap_or(decade);
        Ground {
            height_m: min.y.min(0.0) - if min.y < 0.0 { 0.005 * extent_m } else { 0.0 },
            center,
            half_size_m: extent_m * 4.0,
            shadow_half_m: horizontal_m * 0.5 + extent_m * 0.25,
            grid_spacing_m,
        }
    }

    /// Whether the box `min..max` lies above this ground and inside its square.
    pub fn covers(&self, min: Vec3, max: Vec3) -> bool {
        let inside = |v: f32, c: f32| (v - c).abs() <= self.half_size_m;
        min.y >= self.height_m && [min, max].iter().all(|p| inside(p.x, self.center.x) && inside(p.z, self.center.y))
    }
}

/// A translucent copy of the cloth at another time (onion skin). `M` holds
/// the mesh: a reference for one picture ([`FrameInput`]), an `Arc` where the
/// ghost is kept between frames (the editor's viewport).
#[derive(Clone, Copy, Debug)]
pub struct Ghost<M> {
    pub mesh: M,
    /// Linear RGB.
    pub tint: [f32; 3],
    pub opacity: f32,
}

impl<M: Deref<Target = Mesh>> Ghost<M> {
    /// The same ghost with its mesh borrowed, as [`FrameInput`] takes it.
    pub fn borrowed(&self) -> Ghost<&Mesh> {
        Ghost { mesh: &self.mesh, tint: self.tint, opacity: self.opacity }
    }
}

/// Everything one picture needs.
#[derive(Clone, Copy)]
pub struct FrameInput<'a> {
    pub mesh: &'a Mesh,
    pub camera: &'a OrbitCamera,
    pub options: &'a RenderOptions,
    pub ghosts: &'a [Ghost<&'a Mesh>],
    pub overlay: &'a Overlay,
    /// Drawn with the cloth, each set in its own colour (colliders, each
    /// referenced file's meshes); empty for none.
    pub solids: &'a [Solids],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SegmentInstance {
    a: [f32; 3],
    width_px: f32,
    b: [f32; 3],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct MarkerInstance {
    center: [f32; 3],
    radius_px: f32,
    fill: [f32; 4],
    ring: [f32; 4],
}

/// A buffer that grows (doubling) but is otherwise rewritten in place.
struct GrowingBuffer {
    buffer: wgpu::Buffer,
    label: &'static str,
    usage: wgpu::BufferUsages,
}

impl GrowingBuffer {
    fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages, size: u64) -> GrowingBuffer {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        });
        GrowingBuffer { buffer, label, usage }
    }

    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        if bytes.len() as u64 > self.buffer.size() {
            let size = (bytes.len() as u64).next_power_of_two();
            *self = GrowingBuffer::new(device, self.label, self.usage, size);
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// The solids' triangles and their material, written again only when
/// the solids differ from the last ones written.
struct SolidBuffers {
    /// What the buffers hold now (`None`: nothing, or not yet).
    written: Option<Solids>,
    positions: GrowingBuffer,
    normals: GrowingBuffer,
    uvs: GrowingBuffer,
    indices: GrowingBuffer,
    index_count: u32,
    opaque: bool,
    /// The toon bands the material holds (0: lit).
    bands: u32,
    material: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// The texture `bind_group` samples (none: the plain white one).
    texture: Option<SolidTexture>,
}

impl SolidBuffers {
    fn new(device: &wgpu::Device, renderer: &Renderer) -> SolidBuffers {
        let material = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solids material"),
            size: std::mem::size_of::<MaterialUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = renderer.material_bind_group(device, &material, ClothTexture::Plain);
        let vertex = wgpu::BufferUsages::VERTEX;
        SolidBuffers {
            written: None,
            positions: GrowingBuffer::new(device, "solid positions", vertex, 4096),
            normals: GrowingBuffer::new(device, "solid normals", vertex, 4096),
            uvs: GrowingBuffer::new(device, "solid uvs", vertex, 4096),
            indices: GrowingBuffer::new(device, "solid indices", wgpu::BufferUsages::INDEX, 4096),
            index_count: 0,
            opaque: true,
            bands: 0,
            material,
            bind_group,
            texture: None,
        }
    }

    /// Whether it draws anything, and opaque.
    fn draws_opaque(&self) -> bool {
        self.index_count > 0 && self.opaque
    }

    /// Writes `solids` unless they are what the buffers hold already, in
    /// the toon style's `bands` (0: lit).
    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, solids: &Solids, bands: u32) {
        let valid = solids.normals.len() == solids.positions.len()
            && solids.indices.iter().all(|&i| (i as usize) < solids.positions.len());
        if !valid || solids.is_empty() || !(solids.opacity > 0.0) {
            self.index_count = 0;
            self.written = None;
            return;
        }
        // A viewport repaints the same colliders many times (orbiting, hovering).
        if self.written.as_ref() == Some(solids) && self.bands == bands {
            return;
        }
        self.written = Some(solids.clone());
        self.bands = bands;
        self.positions.write(device, queue, bytemuck::cast_slice(&solids.positions));
        self.normals.write(device, queue, bytemuck::cast_slice(&solids.normals));
        let textured = solids.texture.is_some() && solids.uvs.len() == solids.positions.len();
        if textured {
            self.uvs.write(device, queue, bytemuck::cast_slice(&solids.uvs));
        } else {
            self.uvs.write(device, queue, bytemuck::cast_slice(&vec![[0.0f32; 2]; solids.positions.len()]));
        }
        self.indices.write(device, queue, bytemuck::cast_slice(&solids.indices));
        self.index_count = solids.indices.len() as u32;
        self.opaque = solids.opacity >= 1.0;
        let mut material = MaterialUniform::flat(solids.color, solids.opacity);
        if textured {
            material.params[0] = 1.0;
        }
        material.params[3] = bands as f32;
        queue.write_buffer(&self.material, 0, bytemuck::bytes_of(&material));
    }

    fn draw(&self, pass: &mut wgpu::RenderPass) {
        let vertices = [&self.positions.buffer, &self.normals.buffer, &self.uvs.buffer];
        draw_lit(pass, &self.bind_group, vertices, &self.indices.buffer, self.index_count);
    }
}

/// A mesh with its own material: the cloth, or one ghost.
struct MeshSlot {
    mesh: GpuMesh,
    material: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    texture: ClothTexture,
}

pub struct Renderer {
    pipelines: Pipelines,
    frame_uniform: wgpu::Buffer,
    frame_bind_group: wgpu::BindGroup,
    sampler: wgpu::Sampler,
    texture_views: [(ClothTexture, wgpu::TextureView); 3],
    shadow_view: wgpu::TextureView,
    shadow_bind_group: wgpu::BindGroup,
    cloth: Option<MeshSlot>,
    ghosts: Vec<MeshSlot>,
    ghost_count: usize,
    segments: GrowingBuffer,
    segment_count: u32,
    markers: GrowingBuffer,
    marker_count: u32,
    /// The toon style's ink: the cloth's edges, this frame's lines and their segments.
    ink_edges: InkEdges,
    ink_lines: Vec<InkLine>,
    ink: GrowingBuffer,
    ink_count: u32,
    toon: bool,
    /// Grown to the most sets of solids asked for; the first `solid_count` drawn.
    solids: Vec<SolidBuffers>,
    solid_count: usize,
    wireframe: bool,
    ground: bool,
    shadow_only: bool,
    background: wgpu::Color,
}

impl Renderer {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Renderer {
        let pipelines = Pipelines::new(device);
        let frame_uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniform"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let frame_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &pipelines.frame_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: frame_uniform.as_entire_binding() }],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("linear"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let texture_views = [ClothTexture::Plain, ClothTexture::Carpet, ClothTexture::Checker].map(|texture| {
            let image = textures::builtin_image(texture);
            let gpu = textures::upload(device, queue, &image, "cloth texture");
            (texture, gpu.create_view(&Default::default()))
        });
        let shadow_map = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d { width: SHADOW_MAP_PX, height: SHADOW_MAP_PX, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let shadow_view = shadow_map.create_view(&Default::default());
        let clamp_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let shadow_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow map"),
            layout: &pipelines.shadow_map_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&shadow_view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&clamp_sampler) },
            ],
        });
        Renderer {
            solids: Vec::new(),
            solid_count: 0,
            frame_uniform,
            frame_bind_group,
            sampler,
            texture_views,
            shadow_view,
            shadow_bind_group,
            cloth: None,
            ghosts: Vec::new(),
            ghost_count: 0,
            segments: GrowingBuffer::new(device, "overlay segments", wgpu::BufferUsages::VERTEX, 4096),
            segment_count: 0,
            markers: GrowingBuffer::new(device, "overlay markers", wgpu::BufferUsages::VERTEX, 1024),
            marker_count: 0,
            ink_edges: InkEdges::default(),
            ink_lines: Vec::new(),
            ink: GrowingBuffer::new(device, "ink segments", wgpu::BufferUsages::VERTEX, 4096),
            ink_count: 0,
            toon: false,
            wireframe: false,
            ground: true,
            shadow_only: false,
            background: wgpu::Color::BLACK,
            pipelines,
        }
    }

    fn mesh_slot(&self, device: &wgpu::Device, mesh: &Mesh, texture: ClothTexture) -> MeshSlot {
        let material = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("material"),
            size: std::mem::size_of::<MaterialUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = self.material_bind_group(device, &material, texture);
        MeshSlot { mesh: GpuMesh::new(device, mesh), material, bind_group, texture }
    }

    fn material_bind_group(
        &self,
        device: &wgpu::Device,
        material: &wgpu::Buffer,
        texture: ClothTexture,
    ) -> wgpu::BindGroup {
        let view = &self.texture_views.iter().find(|(t, _)| *t == texture).expect("every texture is uploaded").1;
        self.material_bind_group_with_view(device, material, view)
    }

    fn material_bind_group_with_view(
        &self,
        device: &wgpu::Device,
        material: &wgpu::Buffer,
        view: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("material"),
            layout: &self.pipelines.material_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: material.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        })
    }

    /// Uploads one picture's data for a target of `size_px`. Buffers are
    /// rewritten in place; they are only reallocated when the grid or the
    /// number of ghosts or overlay items grows.
    pub fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, size_px: (u32, u32), input: FrameInput) {
        let options = input.options;
        self.wireframe = options.wireframe;
        self.ground = options.ground.is_some();
        self.shadow_only = options.shadow_only;
        let [r, g, b] = options.background;
        self.background = if options.transparent {
            wgpu::Color::TRANSPARENT
        } else {
            wgpu::Color { r: r as f64, g: g as f64, b: b as f64, a: 1.0 }
        };
        queue.write_buffer(&self.frame_uniform, 0, bytemuck::bytes_of(&frame_uniform(input.camera, options, size_px)));

        let mut cloth = match self.cloth.take() {
            Some(slot) => slot,
            None => self.mesh_slot(device, input.mesh, options.texture),
        };
        self.update_slot(device, queue, &mut cloth, input.mesh, options.texture);
        let textured = if options.texture == ClothTexture::Plain { 0.0 } else { 1.0 };
        let toon = options.style.toon();
        let front = toon.and_then(|look| look.front).unwrap_or(options.front_tint);
        let back = toon.and_then(|look| look.back).unwrap_or(options.back_tint);
        let material = MaterialUniform {
            front_tint: [front[0], front[1], front[2], 1.0],
            back_tint: [back[0], back[1], back[2], 1.0],
            params: [textured, 1.0, 1.0, options.style.bands() as f32],
        };
        queue.write_buffer(&cloth.material, 0, bytemuck::bytes_of(&material));
        self.cloth = Some(cloth);

        let mut ghosts = std::mem::take(&mut self.ghosts);
        for (index, ghost) in input.ghosts.iter().enumerate() {
            if index == ghosts.len() {
                ghosts.push(self.mesh_slot(device, ghost.mesh, ClothTexture::Plain));
            }
            let slot = &mut ghosts[index];
            self.update_slot(device, queue, slot, ghost.mesh, ClothTexture::Plain);
            let material = MaterialUniform::flat(ghost.tint, ghost.opacity);
            queue.write_buffer(&slot.material, 0, bytemuck::bytes_of(&material));
        }
        self.ghosts = ghosts;
        self.ghost_count = input.ghosts.len();

        let segments: Vec<SegmentInstance> = input
            .overlay
            .segments
            .iter()
            .map(|s| SegmentInstance { a: s.a.to_array(), width_px: s.width_px, b: s.b.to_array(), color: s.color })
            .collect();
        self.segments.write(device, queue, bytemuck::cast_slice(&segments));
        self.segment_count = segments.len() as u32;
        let markers: Vec<MarkerInstance> = input
            .overlay
            .markers
            .iter()
            .map(|m| MarkerInstance { center: m.center.to_array(), radius_px: m.radius_px, fill: m.fill, ring: m.ring })
            .collect();
        self.markers.write(device, queue, bytemuck::cast_slice(&markers));
        self.marker_count = markers.len() as u32;
        self.prepare_solids(device, queue, input.solids, options.style.bands());
        self.prepare_ink(device, queue, input);
    }

    /// The toon style's ink lines on this frame's cloth, seen from the camera.
    fn prepare_ink(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, input: FrameInput) {
        self.toon = input.options.style.toon().is_some();
        self.ink_count = 0;
        let Some(look) = input.options.style.toon().filter(|look| look.ink_width_px > 0.0) else {
            return;
        };
        let mesh = input.mesh;
        if !self.ink_edges.is_for(&mesh.indices, mesh.positions.len()) {
            self.ink_edges = InkEdges::new(&mesh.indices, mesh.positions.len());
        }
        self.ink_edges.lines(&mesh.positions, input.camera.eye(), look.crease_deg, &mut self.ink_lines);
        let [r, g, b] = look.ink_color;
        let width_px = look.ink_width_px;
        let segments: Vec<SegmentInstance> = self
            .ink_lines
            .iter()
            .map(|l| SegmentInstance { a: l.a.to_array(), width_px, b: l.b.to_array(), color: [r, g, b, 1.0] })
            .collect();
        self.ink.write(device, queue, bytemuck::cast_slice(&segments));
        self.ink_count = segments.len() as u32;
    }

    fn prepare_solids(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, sets: &[Solids], bands: u32) {
        while self.solids.len() < sets.len() {
            let buffers = SolidBuffers::new(device, self);
            self.solids.push(buffers);
        }
        for (index, set) in sets.iter().enumerate() {
            // A new texture (or none, after one): uploaded once, its own bind group.
            if self.solids[index].texture != set.texture {
                let material = &self.solids[index].material;
                let bind_group = match &set.texture {
                    Some(texture) => {
                        let uploaded = textures::upload(device, queue, &texture.0, "solid texture");
                        let view = uploaded.create_view(&wgpu::TextureViewDescriptor::default());
                        self.material_bind_group_with_view(device, material, &view)
                    }
                    None => self.material_bind_group(device, material, ClothTexture::Plain),
                };
                self.solids[index].bind_group = bind_group;
                self.solids[index].texture = set.texture.clone();
            }
            self.solids[index].write(device, queue, set, bands);
        }
        self.solid_count = sets.len();
    }

    fn update_slot(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        slot: &mut MeshSlot,
        mesh: &Mesh,
        texture: ClothTexture,
    ) {
        slot.mesh.update(device, queue, mesh);
        if slot.texture != texture {
            slot.bind_group = self.material_bind_group(device, &slot.material, texture);
            slot.texture = texture;
        }
    }

    /// Records the shadow pass and the main pass into `encoder`, drawing what
    /// the last [`Renderer::prepare`] uploaded into `target`.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, target: &OffscreenTarget) {
        let Some(cloth) = &self.cloth else {
            return;
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("contact shadow"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.shadow_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if self.ground {
                pass.set_pipeline(&self.pipelines.shadow);
                pass.set_bind_group(0, &self.frame_bind_group, &[]);
                pass.set_vertex_buffer(0, cloth.mesh.positions.slice(..));
                pass.set_index_buffer(cloth.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..cloth.mesh.index_count, 0, 0..1);
                for solids in self.solids[..self.solid_count].iter().filter(|s| s.draws_opaque()) {
                    pass.set_vertex_buffer(0, solids.positions.buffer.slice(..));
                    pass.set_index_buffer(solids.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..solids.index_count, 0, 0..1);
                }
            }
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target.msaa_view(),
                depth_slice: None,
                resolve_target: Some(target.resolved_view()),
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(self.background), store: wgpu::StoreOp::Discard },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: target.depth_view(),
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.frame_bind_group, &[]);
        if self.shadow_only {
            if self.ground {
                pass.set_pipeline(&self.pipelines.ground_shadow);
                pass.set_bind_group(1, &self.shadow_bind_group, &[]);
                pass.draw(0..6, 0..1);
            }
            return;
        }
        if self.ground {
            pass.set_pipeline(&self.pipelines.ground);
            pass.set_bind_group(1, &self.shadow_bind_group, &[]);
            pass.draw(0..6, 0..1);
        }
        let draw_mesh = |pass: &mut wgpu::RenderPass, slot: &MeshSlot| {
            let m = &slot.mesh;
            draw_lit(pass, &slot.bind_group, [&m.positions, &m.normals, &m.uvs], &m.indices, m.index_count);
        };
        let solids = &self.solids[..self.solid_count];
        pass.set_pipeline(if self.toon { &self.pipelines.cloth_toon } else { &self.pipelines.cloth });
        for set in solids.iter().filter(|s| s.draws_opaque()) {
            set.draw(&mut pass);
        }
        draw_mesh(&mut pass, cloth);
        if self.wireframe {
            pass.set_pipeline(&self.pipelines.wire);
            pass.set_vertex_buffer(0, cloth.mesh.positions.slice(..));
            pass.set_index_buffer(cloth.mesh.wire_indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..cloth.mesh.wire_index_count, 0, 0..1);
        }
        // Ink over the cloth it outlines, tested against its depth (hidden behind it), under the ghosts.
        if self.ink_count > 0 {
            pass.set_pipeline(&self.pipelines.segment);
            pass.set_vertex_buffer(0, self.ink.buffer.slice(..));
            pass.draw(0..6, 0..self.ink_count);
        }
        // Ghosts after the opaque cloth: they are hidden behind it, and blend over what is behind them.
        pass.set_pipeline(&self.pipelines.ghost);
        for slot in &self.ghosts[..self.ghost_count] {
            draw_mesh(&mut pass, slot);
        }
        for set in solids.iter().filter(|s| s.index_count > 0 && !s.opaque) {
            set.draw(&mut pass);
        }
        if self.segment_count > 0 {
            pass.set_pipeline(&self.pipelines.segment);
            pass.set_vertex_buffer(0, self.segments.buffer.slice(..));
            pass.draw(0..6, 0..self.segment_count);
        }
        if self.marker_count > 0 {
            pass.set_vertex_buffer(0, self.markers.buffer.slice(..));
            pass.set_pipeline(&self.pipelines.marker_hidden);
            pass.draw(0..6, 0..self.marker_count);
            pass.set_pipeline(&self.pipelines.marker);
            pass.draw(0..6, 0..self.marker_count);
        }
    }

    /// Prepares, draws and submits one picture into `target`.
    pub fn render(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, target: &OffscreenTarget, input: FrameInput) {
        self.prepare(device, queue, target.size_px(), input);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("drape frame") });
        self.encode(&mut encoder, target);
        queue.submit([encoder.finish()]);
    }
}

/// One lit mesh with the pipeline already set: its material, its positions,
/// normals and UVs, and its triangles.
fn draw_lit(
    pass: &mut wgpu::RenderPass,
    material: &wgpu::BindGroup,
    vertices: [&wgpu::Buffer; 3],
    indices: &wgpu::Buffer,
    index_count: u32,
) {
    pass.set_bind_group(1, material, &[]);
    for (slot, buffer) in vertices.into_iter().enumerate() {
        pass.set_vertex_buffer(slot as u32, buffer.slice(..));
    }
    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
    pass.draw_indexed(0..index_count, 0, 0..1);
}

fn frame_uniform(camera: &OrbitCamera, options: &RenderOptions, size_px: (u32, u32)) -> FrameUniform {
    let (w, h) = (size_px.0.max(1) as f32, size_px.1.max(1) as f32);
    let ground = options.ground.unwrap_or_default();
    let shadow_center = Vec3::new(ground.center.x, ground.height_m, ground.center.y);
    let [r, g, b] = options.background;
    FrameUniform {
        clip_from_world: camera.clip_from_world(size_px).to_cols_array_2d(),
        shadow_clip_from_world: shadow_clip_from_world(shadow_center, ground.shadow_half_m).to_cols_array_2d(),
        eye_world: camera.eye().extend(1.0).to_array(),
        viewport_px: [w, h, 1.0 / w, 1.0 / h],
        ground: [ground.height_m, ground.grid_spacing_m, ground.half_size_m, options.ground.is_some() as u32 as f32],
        ground_center: [ground.center.x, 0.0, ground.center.y, 0.0],
        // Fully faded at about a third of the shadow square's width; blur ~1.5% of it.
        shadow: [(ground.shadow_half_m * 0.6).max(0.05), 0.012, 0.55, 0.0],
        background: [r, g, b, 1.0],
        wire_color: options.wire_color,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::pipelines::{MARKER_INSTANCE, SEGMENT_INSTANCE};

    #[test]
    fn a_ground_covers_what_it_was_laid_under_and_not_a_cloth_flown_past_it() {
        let (min, max) = (Vec3::new(-0.5, 0.8, -1.6), Vec3::new(0.5, 1.2, 0.0));
        let ground = Ground::under(min, max);
        assert!(ground.covers(min, max));
        assert!(!ground.covers(min + Vec3::Z * 10.0, max + Vec3::Z * 10.0), "flown 10 m on");
        assert!(!ground.covers(min - Vec3::Y * 2.0, max), "dropped below the ground");
        let wider = Ground::under(min.min(min + Vec3::Z * 10.0), max.max(max + Vec3::Z * 10.0));
        assert!(wider.covers(min + Vec3::Z * 10.0, max + Vec3::Z * 10.0));
    }

    #[test]
    fn instance_structs_match_their_vertex_layouts() {
        assert_eq!(std::mem::size_of::<SegmentInstance>() as u64, SEGMENT_INSTANCE.array_stride);
        assert_eq!(std::mem::size_of::<MarkerInstance>() as u64, MARKER_INSTANCE.array_stride);
        // The colour is the last attribute and ends the struct.
        assert_eq!(SEGMENT_INSTANCE.attributes[3].offset, 28);
        assert_eq!(MARKER_INSTANCE.attributes[3].offset, 32);
    }

    #[test]
    fn ground_sits_at_zero_unless_the_cloth_goes_below() {
        let above = Ground::under(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
        assert_eq!(above.height_m, 0.0);
        assert_eq!(above.grid_spacing_m, 0.25);
        let below = Ground::under(Vec3::new(-1.0, -0.5, -1.0), Vec3::new(1.0, 2.0, 1.0));
        assert!(below.height_m < -0.5);
    }
}
