//! The ray-query kernel's acceleration structure ([`crate::Traversal::RayQuery`]): one bottom
//! level of the scene's triangles, primitive `i` the scene's primitive `i` (so the kernel
//! finishes a hit with the same surface code as its own traversal), under one top-level
//! instance with the identity transform; bound as group 1 (`shaders/accel_ray_query.wgsl`).

use crate::GpuError;
use stratapt_scene::FlatScene;
use wgpu::util::DeviceExt;

/// Group 1 of the ray-query kernel: the top-level acceleration structure.
pub(crate) fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("strata ray queries"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::AccelerationStructure {
                vertex_return: false,
            },
            count: None,
        }],
    })
}

/// A scene's acceleration structures on the device, built, and their bind group.
pub(crate) struct RayStructures {
    pub bind_group: wgpu::BindGroup,
    _blas: wgpu::Blas,
    _tlas: wgpu::Tlas,
    _buffers: [wgpu::Buffer; 2],
}

impl RayStructures {
    /// Build the structures of `scene` (every primitive a static triangle:
    /// [`crate::Traversal::serves`]) and bind them with `layout` ([`bind_group_layout`]).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &FlatScene,
        layout: &wgpu::BindGroupLayout,
    ) -> Result<Self, GpuError> {
        let geometry = &scene.geometry;
        let limits = device.limits();
        let (vertices, triangles) = (geometry.points.len(), geometry.prims.len());
        if vertices as u64 > limits.max_blas_primitive_count as u64
            || triangles as u64 > limits.max_blas_primitive_count as u64
        {
            return Err(GpuError::TooLarge(format!(
                "{triangles} triangles over {vertices} points; the device's acceleration \
                 structures hold at most {}",
                limits.max_blas_primitive_count
            )));
        }
        let indices: Vec<u32> = geometry
            .prims
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        let buffer = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::BLAS_INPUT,
            })
        };
        let vertex_buffer = buffer("ray-query vertices", bytemuck::cast_slice(&geometry.points));
        let index_buffer = buffer("ray-query indices", bytemuck::cast_slice(&indices));
        let size = wgpu::BlasTriangleGeometrySizeDescriptor {
            vertex_format: wgpu::VertexFormat::Float32x3,
            vertex_count: vertices as u32,
            index_format: Some(wgpu::IndexFormat::Uint32),
            index_count: Some(indices.len() as u32),
            flags: wgpu::AccelerationStructureGeometryFlags::OPAQUE,
        };
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let blas = device.create_blas(
            &wgpu::CreateBlasDescriptor {
                label: Some("strata scene"),
                flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                update_mode: wgpu::AccelerationStructureUpdateMode::Build,
            },
            wgpu::BlasGeometrySizeDescriptors::Triangles {
                descriptors: vec![size.clone()],
            },
        );
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("strata scene"),
            max_instances: 1,
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        });
        let identity = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        tlas[0] = Some(wgpu::TlasInstance::new(&blas, identity, 0, 0xff));
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.build_acceleration_structures(
            std::iter::once(&wgpu::BlasBuildEntry {
                blas: &blas,
                geometry: wgpu::BlasGeometries::TriangleGeometries(vec![
                    wgpu::BlasTriangleGeometry {
                        size: &size,
                        vertex_buffer: &vertex_buffer,
                        first_vertex: 0,
                        // The points are vec4s (the kernel's `points` array).
                        vertex_stride: 16,
                        index_buffer: Some(&index_buffer),
                        first_index: Some(0),
                        transform_buffer: None,
                        transform_buffer_offset: None,
                    },
                ]),
            }),
            std::iter::once(&tlas),
        );
        queue.submit([encoder.finish()]);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strata ray queries"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: tlas.as_binding(),
            }],
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(format!(
                "building the acceleration structure: {error}"
            )));
        }
        Ok(Self {
            bind_group,
            _blas: blas,
            _tlas: tlas,
            _buffers: [vertex_buffer, index_buffer],
        })
    }
}
