//! The product spaces' tracer (`shaders/product.wgsl`) run on the device:
//! [`GpuTracer::render_product`], the GPU twin of the core's
//! [`render`](bevy_manifold_core::trace::product::render), and
//! [`GpuTracer::time_product`] for the benchmarks.

use super::GpuTracer;
use super::timing::TraceTiming;
use crate::GpuError;
use crate::product::{GpuProductCells, GpuProductPixel, GpuProductScene, ProductShaderDefs, storage_bytes};
use bevy_manifold_core::space::cell_id::CellId;
use bevy_manifold_core::space::product::ProductSpace;
use bevy_manifold_core::space::product_cells::{
    DEFAULT_PRODUCT_TABLE_CELLS, ProductCellTable, ProductCells, ProductElement,
};
use bevy_manifold_core::trace::product::{ProductPixel, ProductScene};
use wgpu::util::DeviceExt;

/// The product tracer's bind group layout and compute pipeline.
pub(super) struct ProductPipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// A product space with its exact cells and their table, kept by the
/// tracer between traces of that space.
pub(super) type ProductCellsKept = (ProductSpace, Option<(ProductCells, ProductCellTable)>);

/// A product scene uploaded and bound.
struct ProductBound {
    defs: ProductShaderDefs,
    bind: wgpu::BindGroup,
    pixels: wgpu::Buffer,
    count: usize,
    size: (u32, u32),
}

/// Most balls (images included) the product tracer takes: each pixel
/// looks at every one per segment.
pub const MAX_PRODUCT_BALLS: usize = 4096;

impl GpuTracer {
    /// Traces `scene` in the product space `space` on the GPU, `width x
    /// height` pixels, rows from the top: the twin of the core's
    /// [`render`](bevy_manifold_core::trace::product::render), in f32.
    ///
    /// ```no_run
    /// use bevy_manifold_core::space::product::ProductSpace;
    /// use bevy_manifold_core::trace::product::ProductScene;
    /// use bevy_manifold_gpu::GpuTracer;
    ///
    /// let mut gpu = GpuTracer::new()?;
    /// let space = ProductSpace::s2_x_s1(2.0);
    /// let image = gpu.render_product(&space, &ProductScene::default_for(&space), 320, 180)?;
    /// assert_eq!(image.len(), 320 * 180);
    /// # Ok::<(), bevy_manifold_gpu::GpuError>(())
    /// ```
    ///
    /// # Errors
    /// [`GpuError::Settings`] for a space that does not validate, an empty
    /// image, a view that is not finite or too many balls; otherwise as
    /// [`GpuTracer::render`].
    pub fn render_product(
        &mut self,
        space: &ProductSpace,
        scene: &ProductScene,
        width: u32,
        height: u32,
    ) -> Result<Vec<ProductPixel>, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bound = self.bind_product(space, scene, (width, height), true)?;
        let bytes = (bound.count * std::mem::size_of::<GpuProductPixel>()) as u64;
        let readback = self.readback_buffer(bytes);
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("product trace"),
        });
        self.encode_product(&mut encoder, &bound, None);
        encoder.copy_buffer_to_buffer(&bound.pixels, 0, &readback, 0, bytes);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Validation(e.to_string()));
        }
        let raw: Vec<GpuProductPixel> = bytemuck::pod_collect_to_vec(&self.finish(encoder, &readback)?);
        Ok(raw
            .iter()
            .map(|p| ProductPixel {
                object: p.object,
                distance: if p.object == 0 {
                    f64::INFINITY
                } else {
                    f64::from(p.color[3])
                },
                crossings: p.crossings as usize,
                cell: CellId(u64::from(p.cell[0]) | (u64::from(p.cell[1]) << 32)),
                color: [p.color[0], p.color[1], p.color[2]],
            })
            .collect())
    }

    /// How long tracing `scene` takes on the device, as
    /// [`GpuTracer::time_trace`] times the tracer of E3, H3 and S3 (the
    /// same warm-up, `repeats` passes in one submission, the median pass
    /// by timestamps where the adapter has them). As the Bevy pass draws
    /// it: with a table of cells only where the view shades by cell.
    ///
    /// # Errors
    /// As [`GpuTracer::render_product`].
    pub fn time_product(
        &mut self,
        space: &ProductSpace,
        scene: &ProductScene,
        (width, height): (u32, u32),
        repeats: u32,
    ) -> Result<TraceTiming, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bound = self.bind_product(space, scene, (width, height), scene.view.tint.is_some())?;
        self.timed(scope, repeats, |gpu, encoder, timestamps| {
            gpu.encode_product(encoder, &bound, timestamps);
        })
    }

    /// The product pipeline specialised on `defs`, built on first use.
    fn product_pipeline(&mut self, defs: ProductShaderDefs) -> Result<&ProductPipeline, GpuError> {
        if self.product[defs.index()].is_none() {
            let module = Self::compose_modules(&[crate::CELL_TINT_WGSL], crate::PRODUCT_WGSL, &defs.names(), &[])?;
            let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let shader = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("product.wgsl"),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
            });
            let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let read = wgpu::BufferBindingType::Storage { read_only: true };
            let layout = self.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("product trace"),
                entries: &[
                    entry(0, wgpu::BufferBindingType::Uniform),
                    entry(1, read),
                    entry(2, read),
                    entry(3, wgpu::BufferBindingType::Storage { read_only: false }),
                    entry(4, read),
                    entry(5, read),
                    entry(6, read),
                    entry(7, read),
                ],
            });
            let pipeline_layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("product trace"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("product trace"),
                layout: Some(&pipeline_layout),
                module: &shader,
                entry_point: Some("product_trace"),
                compilation_options: Default::default(),
                cache: None,
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(GpuError::Validation(e.to_string()));
            }
            self.product[defs.index()] = Some(ProductPipeline { layout, pipeline });
        }
        Ok(self.product[defs.index()].as_ref().expect("built above"))
    }

    /// The table of cells about the eye's copy `eye` in `space`: the
    /// space's exact cells and table are grown on its first trace and
    /// kept while the same space is traced (a tour's frames, a benchmark's
    /// repeats); none where it has no exact cells.
    fn product_cells(&mut self, space: &ProductSpace, eye: Option<&ProductElement>) -> GpuProductCells {
        if self.product_cells.as_ref().is_none_or(|(kept, _)| kept != space) {
            let exact = ProductCells::of(space).map(|cells| {
                let table = ProductCellTable::grow(&cells, DEFAULT_PRODUCT_TABLE_CELLS);
                (cells, table)
            });
            self.product_cells = Some((space.clone(), exact));
        }
        match &self.product_cells {
            Some((_, Some((cells, table)))) => GpuProductCells::pack(cells, table, eye),
            _ => GpuProductCells::none(),
        }
    }

    /// Checks, packs and uploads a product scene, its pipeline built; with
    /// its table of cells where `table`.
    fn bind_product(
        &mut self,
        space: &ProductSpace,
        scene: &ProductScene,
        (width, height): (u32, u32),
        table: bool,
    ) -> Result<ProductBound, GpuError> {
        space.validate().map_err(|e| GpuError::Settings(e.to_string()))?;
        let view = &scene.view;
        let numbers = [view.fov_y_degrees, view.max_distance, view.fog];
        let frame = view
            .frame
            .iter()
            .flat_map(|t| [t.surface.x, t.surface.y, t.surface.z, t.height]);
        let eye = [
            view.eye.surface.x,
            view.eye.surface.y,
            view.eye.surface.z,
            view.eye.height,
        ];
        if numbers.iter().chain(&eye).copied().chain(frame).any(|x| !x.is_finite()) {
            return Err(GpuError::Settings(
                "the product view's eye, frame, field of view, distance or fog is not finite".into(),
            ));
        }
        if let Some(e) = scene.edges
            && !(e.radius.is_finite() && e.radius >= 0.0 && e.color.iter().all(|c| c.is_finite()))
        {
            return Err(GpuError::Settings(format!(
                "the product scene's edges (radius {}, colour {:?}) are not finite and non-negative",
                e.radius, e.color
            )));
        }
        if view.frustum.is_some_and(|f| !f.is_valid()) {
            return Err(GpuError::Settings(
                "the product view's frustum is not finite or has no width or height".into(),
            ));
        }
        if width == 0 || height == 0 {
            return Err(GpuError::Settings(format!(
                "an image of {width}x{height} pixels is empty"
            )));
        }
        for (k, mesh) in scene.meshes.iter().enumerate() {
            mesh.check(space.geometry)
                .map_err(|e| GpuError::Settings(format!("the product scene's mesh {k} (id {}): {e}", mesh.id)))?;
        }
        let lights = self.product_lights.get(space, scene);
        let mut gpu = GpuProductScene::pack_lit(space, scene, lights, (width, height));
        let cells = if table {
            self.product_cells(space, view.cell.as_ref())
        } else {
            GpuProductCells::none()
        };
        gpu.params.cell_count = cells.count;
        let defs = ProductShaderDefs::of(&gpu.params);
        let data_bytes = (gpu.mesh_data.words.len() * 16) as u64;
        if data_bytes > self.device.limits().max_storage_buffer_binding_size || gpu.meshes.len() > MAX_PRODUCT_BALLS {
            return Err(GpuError::Settings(format!(
                "the scene's meshes make {} images and {data_bytes} bytes of triangles, more than the product tracer takes ({MAX_PRODUCT_BALLS} images, {} bytes)",
                gpu.meshes.len(),
                self.device.limits().max_storage_buffer_binding_size
            )));
        }
        if gpu.balls.len() > MAX_PRODUCT_BALLS {
            return Err(GpuError::Settings(format!(
                "the scene makes {} balls with their images, more than the {MAX_PRODUCT_BALLS} the product tracer takes",
                gpu.balls.len()
            )));
        }
        let count = (u64::from(width) * u64::from(height)) as usize;
        let bytes = count * std::mem::size_of::<GpuProductPixel>();
        let limit = self.device.limits().max_storage_buffer_binding_size;
        if bytes as u64 > limit {
            return Err(GpuError::Settings(format!(
                "the pixels need a {bytes}-byte buffer, more than the {limit} bytes this adapter binds"
            )));
        }
        let layout = self.product_pipeline(defs)?.layout.clone();
        let d = &self.device;
        let storage = |label, contents: &[u8]| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let params = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("product params"),
            contents: bytemuck::bytes_of(&gpu.params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let faces = storage("product faces", &storage_bytes(&gpu.faces));
        let balls = storage("product balls", &storage_bytes(&gpu.balls));
        let table = storage("product cells", &storage_bytes(&cells.words));
        let lights = storage("product lights", &storage_bytes(&gpu.lights));
        let meshes = storage("product meshes", &storage_bytes(&gpu.meshes));
        let mesh_data = storage("product mesh data", &storage_bytes(&gpu.mesh_data.words));
        let pixels = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("product pixels"),
            size: bytes as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("product trace"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: faces.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: balls.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: pixels.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: table.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: meshes.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: mesh_data.as_entire_binding(),
                },
            ],
        });
        Ok(ProductBound {
            defs,
            bind,
            pixels,
            count,
            size: (width, height),
        })
    }

    /// Records one product pass over every pixel of `bound`.
    fn encode_product(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bound: &ProductBound,
        timestamps: Option<(&wgpu::QuerySet, u32)>,
    ) {
        let Some(product) = &self.product[bound.defs.index()] else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("product trace"),
            timestamp_writes: timestamps.map(|(query_set, at)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(at),
                end_of_pass_write_index: Some(at + 1),
            }),
        });
        pass.set_pipeline(&product.pipeline);
        pass.set_bind_group(0, &bound.bind, &[]);
        pass.dispatch_workgroups(bound.size.0.div_ceil(8), bound.size.1.div_ceil(8), 1);
    }
}
