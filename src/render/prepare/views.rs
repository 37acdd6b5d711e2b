//! Each view's own part ([`prepare_manifold_views`]): its params, its
//! bind group, and for a view traced below full scale or accumulating
//! samples while still, its textures, upscale and blend.

use super::super::extract::ExtractedManifoldView;
use super::super::pass::{BlendIn, ManifoldViewBinding, ScaledBinding};
use super::super::pipeline::TracePipeline;
use super::super::upscale::{HISTORY_FORMAT, TracedTextures, UpscaleKey, UpscalePipeline};
use super::cache::{ManifoldBufferCache, ManifoldUploads, SceneBuffers, ViewBuffers};
use super::scenes::ManifoldPackedScenes;
use crate::trace::{Projection, pixel_half_angle};
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntry, Buffer, BufferInitDescriptor, BufferUsages, PipelineCache, SpecializedRenderPipelines,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::view::ExtractedView;
use bevy_manifold_gpu::bindings::{BindingSource, render_bindings};
use bevy_manifold_gpu::{GpuParams, GpuView};
use std::sync::Arc;

/// Brings each manifold view's params up to date (writing them only when
/// they changed), counts its accumulated samples, binds it, and makes the
/// textures of a view traced into textures of its own.
#[expect(clippy::too_many_arguments, reason = "a system's parameters")]
pub fn prepare_manifold_views(
    mut commands: Commands,
    views: Query<(Entity, &ExtractedManifoldView, &ExtractedView)>,
    pipeline: Res<TracePipeline>,
    upscale: Res<UpscalePipeline>,
    mut upscales: ResMut<SpecializedRenderPipelines<UpscalePipeline>>,
    pipeline_cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut cache: ResMut<ManifoldBufferCache>,
    mut stats: ResMut<ManifoldUploads>,
    packed: Res<ManifoldPackedScenes>,
) {
    let cache = &mut *cache;
    let stats = &mut *stats;
    for (entity, view, extracted) in &views {
        let (Some((space, objects)), Some(chosen), Some(shared)) = (
            packed.get(view.root),
            cache.pipelines.get(&entity).copied(),
            cache.scenes.get(&view.root),
        ) else {
            continue;
        };
        let (id, traced, samples, encode_srgb) = (chosen.id, chosen.traced, chosen.samples, chosen.encode_srgb);
        let accumulate = view.samples > 1;
        let params = GpuParams::new(view.space.space(), space, objects, &gpu_view(view, extracted, traced));
        let entry = cache
            .views
            .entry(entity)
            .or_insert_with(|| ViewBuffers::new(&device, params, stats));
        // Accumulation: the same view as last frame (params, space and
        // objects, textures) adds a sample, jittered; anything else starts
        // again from the plain trace.
        let format = HISTORY_FORMAT;
        let scene_key = (Arc::as_ptr(space.gpu()) as usize, Arc::as_ptr(objects) as usize);
        let textures_fit = entry
            .traced
            .as_ref()
            .is_some_and(|t| Some(t.size) == traced && t.format == format && t.history.is_some() == accumulate);
        // A sample counts only if this frame draws it: every pipeline the
        // frame needs must be compiled. (Asked only of accumulating views,
        // so a plain view never compiles the upscale and blend pipelines.)
        let ready = |id| pipeline_cache.get_render_pipeline(id).is_some();
        let blend_key = UpscaleKey {
            format: extracted.target_format,
            samples,
            encode_srgb,
            blend: true,
        };
        let pipelines_ready = accumulate
            && ready(id)
            && ready(upscales.specialize(
                &pipeline_cache,
                &upscale,
                UpscaleKey {
                    blend: false,
                    ..blend_key
                },
            ))
            && ready(upscales.specialize(&pipeline_cache, &upscale, blend_key));
        let still = pipelines_ready
            && textures_fit
            && entry.still.as_ref().is_some_and(|(p, a, b, n)| {
                bytemuck::bytes_of(p) == bytemuck::bytes_of(&params)
                    && (*a, *b, *n) == (scene_key.0, scene_key.1, view.samples)
            });
        entry.samples = if still {
            (entry.samples + 1).min(view.samples)
        } else {
            0
        };
        entry.still = pipelines_ready.then_some((params, scene_key.0, scene_key.1, view.samples));
        let sample = entry.samples;
        let trace = sample < view.samples;
        if let Some(progress) = &view.progress {
            progress.set(if trace { sample + 1 } else { view.samples });
        }
        let params = if accumulate && trace && sample > 0 {
            params.sample(sample)
        } else {
            params
        };
        if entry.bound != Some((view.root, shared.made)) {
            entry.bound = Some((view.root, shared.made));
            entry.bind_group = None;
        }
        if bytemuck::bytes_of(&entry.params) != bytemuck::bytes_of(&params) {
            queue.write_buffer(&entry.params_buffer, 0, bytemuck::bytes_of(&params));
            entry.params = params;
            stats.params += 1;
            stats.bytes += std::mem::size_of::<GpuParams>() as u64;
        }
        let bind_group = entry
            .bind_group
            .get_or_insert_with(|| bind_view(&device, &pipeline_cache, &pipeline, &entry.params_buffer, shared))
            .clone();
        let scaled = traced.map(|size| {
            let textures = match entry.traced.take() {
                Some(t) if textures_fit => t,
                _ => TracedTextures::new(&device, &pipeline_cache, &upscale, size, format, accumulate),
            };
            let textures = entry.traced.insert(textures);
            let key = UpscaleKey {
                format: extracted.target_format,
                samples,
                encode_srgb,
                blend: false,
            };
            let blend = textures.history.as_ref().map(|history| BlendIn {
                pipeline: upscales.specialize(&pipeline_cache, &upscale, UpscaleKey { blend: true, ..key }),
                history: history.view.clone(),
                source: textures.bind_group.clone(),
                first: sample == 0,
            });
            ScaledBinding {
                pipeline: upscales.specialize(&pipeline_cache, &upscale, key),
                color: textures.color.clone(),
                depth: textures.depth.clone(),
                bind_group: textures
                    .history
                    .as_ref()
                    .map_or_else(|| textures.bind_group.clone(), |h| h.bind_group.clone()),
                trace,
                blend: blend.filter(|_| trace),
            }
        });
        if scaled.is_none() {
            entry.traced = None;
        }
        commands.entity(entity).insert(ManifoldViewBinding {
            pipeline: id,
            bind_group,
            scaled,
        });
    }
    cache.views.retain(|e, _| views.contains(*e));
}

impl ViewBuffers {
    /// A view's buffers, its params buffer made with `params`.
    fn new(device: &RenderDevice, params: GpuParams, stats: &mut ManifoldUploads) -> Self {
        stats.params += 1;
        stats.bytes += std::mem::size_of::<GpuParams>() as u64;
        let params_buffer = device.create_buffer_with_data(&BufferInitDescriptor {
            label: Some("manifold_params"),
            contents: bytemuck::bytes_of(&params),
            usage: BufferUsages::STORAGE | BufferUsages::COPY_DST,
        });
        ViewBuffers {
            bound: None,
            params,
            params_buffer,
            bind_group: None,
            traced: None,
            still: None,
            samples: 0,
        }
    }
}

/// A view's bind group: every binding the render pass binds
/// ([`render_bindings`]), the view's params and its space's buffers.
fn bind_view(
    device: &RenderDevice,
    pipeline_cache: &PipelineCache,
    pipeline: &TracePipeline,
    params: &Buffer,
    shared: &SceneBuffers,
) -> BindGroup {
    let entries: Vec<BindGroupEntry> = render_bindings()
        .filter_map(|b| {
            let buffer = match b.source {
                BindingSource::View => Some(params),
                _ => shared.buffer(b),
            }?;
            Some(BindGroupEntry {
                binding: b.binding,
                resource: buffer.as_entire_binding(),
            })
        })
        .collect();
    device.create_bind_group(
        "manifold_trace",
        &pipeline_cache.get_bind_group_layout(&pipeline.layout),
        &entries,
    )
}

/// The off-centre frustum of a view's projection `p` (an OpenXR eye's),
/// `None` for a symmetric one whose aspect is the viewport's (Bevy's
/// perspective), which the tracer makes from `tan_half_fov` exactly as
/// before. A direction `(x_v, y_v, -1)` lands at NDC
/// `x = p.x_axis.x x_v - p.z_axis.x`, so `x_v = (x + p.z_axis.x) / p.x_axis.x`
/// (likewise y).
#[must_use]
pub(crate) fn view_frustum(p: Mat4, width: u32, height: u32) -> Option<[f32; 4]> {
    let aspect = width as f32 / height.max(1) as f32;
    let symmetric =
        p.z_axis.x == 0.0 && p.z_axis.y == 0.0 && (p.x_axis.x * aspect - p.y_axis.y).abs() <= 1e-5 * p.y_axis.y.abs();
    if symmetric || p.x_axis.x == 0.0 || p.y_axis.y == 0.0 {
        return None;
    }
    Some([
        1.0 / p.x_axis.x,
        1.0 / p.y_axis.y,
        p.z_axis.x / p.x_axis.x,
        p.z_axis.y / p.y_axis.y,
    ])
}

/// The per-frame view data of an extracted view, traced at `traced`
/// pixels into textures of its own when given (a render scale below 1),
/// else into its viewport.
fn gpu_view(view: &ExtractedManifoldView, extracted: &ExtractedView, traced: Option<UVec2>) -> GpuView {
    // Bevy's perspective projection: y_axis.y = 1 / tan(fov/2); the near
    // plane sits in w_axis.z (infinite reverse z).
    let p = extracted.clip_from_view;
    let frustum = view_frustum(p, extracted.viewport.z, extracted.viewport.w);
    let (size, origin, frustum) = match traced {
        // The traced size rounds the viewport's, so its aspect is not
        // quite the viewport's: the frustum is given whole, so the view
        // covers what the full-size view covers.
        Some(t) => (
            [t.x, t.y],
            [0, 0],
            frustum.or(Some([1.0 / p.x_axis.x, 1.0 / p.y_axis.y, 0.0, 0.0])),
        ),
        None => (
            [extracted.viewport.z, extracted.viewport.w],
            [extracted.viewport.x, extracted.viewport.y],
            frustum,
        ),
    };
    GpuView {
        camera: view.camera.as_mat4(),
        camera_cell: view.element,
        camera_element: view.cell.clone(),
        tan_half_fov: 1.0 / p.y_axis.y,
        frustum,
        fog: view.fog,
        size,
        origin,
        near: p.w_axis.z,
        levels: view.levels,
        max_distance: view.max_distance,
        flags: 0,
        cell_tint: view.cell_tint,
        cell_rule: view.space.rule().words(),
        projection: bevy_manifold_core::trace::Projection::Perspective.words(),
        // The cones are as wide as the traced pixels.
        footprint: if view.defs.footprint {
            let half_height = frustum.map_or(1.0 / p.y_axis.y, |f| f[1]);
            pixel_half_angle(Projection::Perspective, f64::from(half_height), size[1]) as f32
        } else {
            0.0
        },
        light_sample: [0.0; 2],
        reflections: view.reflections,
        path: [view.path_depth, view.seed, 0],
    }
}

#[cfg(test)]
mod tests {
    use super::view_frustum;
    use bevy::camera::{CameraProjection, PerspectiveProjection};
    use bevy::math::{Mat4, Vec4};

    /// Bevy's own perspective keeps the symmetric path (the desktop image
    /// is traced exactly as before); an OpenXR eye's `glFrustum`-style
    /// matrix gives back its slopes.
    #[test]
    fn the_tracer_reads_off_centre_frusta_and_leaves_the_desktop_alone() {
        for (w, h) in [(1280u32, 720u32), (640, 640), (333, 1000)] {
            let mut p = PerspectiveProjection::default();
            p.update(w as f32, h as f32);
            assert_eq!(view_frustum(p.get_clip_from_view(), w, h), None, "{w}x{h}");
        }
        let (l, r, b, t) = ((-0.87f32).tan(), 0.70f32.tan(), (-0.84f32).tan(), 0.77f32.tan());
        let m = Mat4::from_cols(
            Vec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
            Vec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
            Vec4::new((r + l) / (r - l), (t + b) / (t - b), 0.0, -1.0),
            Vec4::new(0.0, 0.0, 0.1, 0.0),
        );
        let f = view_frustum(m, 320, 240).expect("off-centre");
        let want = [(r - l) / 2.0, (t - b) / 2.0, (r + l) / 2.0, (t + b) / 2.0];
        for k in 0..4 {
            assert!((f[k] - want[k]).abs() < 1e-6, "{f:?} vs {want:?}");
        }
    }
}
