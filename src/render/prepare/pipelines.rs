//! Each view's trace pipeline ([`prepare_manifold_pipelines`]):
//! specialised to the view's scene and target, and while that compiles,
//! the pipeline the view was last drawn with.

use super::super::extract::ExtractedManifoldView;
use super::super::pipeline::{TracePipeline, TracePipelineKey};
use super::super::upscale::HISTORY_FORMAT;
use super::cache::{ManifoldBufferCache, ViewPipeline};
use super::scenes::ManifoldPackedScenes;
use crate::camera::ManifoldRenderScale;
use bevy::camera::CompositingSpace;
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::{PipelineCache, SpecializedRenderPipelines};
use bevy::render::view::{ExtractedView, Msaa};

/// Specialises the trace pipeline for each manifold view, and picks the
/// one it is drawn with this frame.
pub fn prepare_manifold_pipelines(
    views: Query<(
        Entity,
        &ExtractedManifoldView,
        &ExtractedView,
        &ExtractedCamera,
        Option<&Msaa>,
    )>,
    pipeline: Res<TracePipeline>,
    mut pipelines: ResMut<SpecializedRenderPipelines<TracePipeline>>,
    pipeline_cache: Res<PipelineCache>,
    mut cache: ResMut<ManifoldBufferCache>,
    packed: Res<ManifoldPackedScenes>,
) {
    let cache = &mut *cache;
    for (entity, view, extracted, camera, msaa) in &views {
        let viewport = UVec2::new(extracted.viewport.z, extracted.viewport.w);
        let accumulate = view.samples > 1;
        let traced =
            Some(ManifoldRenderScale(view.scale).traced_size(viewport)).filter(|t| *t != viewport || accumulate);
        let samples = msaa.map_or(1, Msaa::samples);
        let encode_srgb = camera.compositing_space == Some(CompositingSpace::Srgb);
        // What the packed objects decide (TraceDefs::for_objects).
        let defs = packed
            .get(view.root)
            .map_or(view.defs, |(_, o)| view.defs.for_objects(o));
        // Traced into textures of its own: linear colour, one sample; the
        // upscale encodes and writes the view target's samples.
        let key = match traced {
            Some(_) => TracePipelineKey {
                defs,
                format: HISTORY_FORMAT,
                samples: 1,
                encode_srgb: false,
            },
            None => TracePipelineKey {
                defs,
                format: extracted.target_format,
                samples,
                encode_srgb,
            },
        };
        let mut id = pipelines.specialize(&pipeline_cache, &pipeline, key);
        if let bevy::render::render_resource::CachedPipelineState::Err(e) = pipeline_cache.get_render_pipeline_state(id)
            && cache.failed.insert(id)
        {
            error!("the manifold tracer pipeline for {:?} failed: {e}", key.defs.names());
        }
        let entry = cache.pipelines.entry(entity).or_insert(ViewPipeline {
            id,
            traced,
            samples,
            encode_srgb,
            drawn: None,
        });
        // Switching between drawing straight into the target and into
        // textures of its own (a render scale crossing 1) needs the other
        // pipeline: until it is compiled the view is drawn the way it was
        // last drawn, if that pipeline is ready, rather than not at all.
        let mut traced = traced;
        let mut drawn_key = key;
        if pipeline_cache.get_render_pipeline(id).is_none()
            && let Some((own, last, last_key)) = entry.drawn
            && pipeline_cache.get_render_pipeline(last).is_some()
        {
            if own != traced.is_some() {
                id = last;
                drawn_key = last_key;
                traced = own.then_some(viewport);
            } else if last_key.defs.same_but_ball_tree(&key.defs)
                && (TracePipelineKey {
                    defs: key.defs,
                    ..last_key
                }) == key
            {
                // Balls came or went across a doubling of the ball tree's
                // leaves (the shooter's shots): the last pipeline draws
                // the new scene, testing every ball or only the leaves it
                // has, until the new one is compiled.
                id = last;
                drawn_key = last_key;
            }
        }
        entry.id = id;
        entry.traced = traced;
        entry.samples = samples;
        entry.encode_srgb = encode_srgb;
        if packed.get(view.root).is_some() && pipeline_cache.get_render_pipeline(id).is_some() {
            entry.drawn = Some((traced.is_some(), id, drawn_key));
        }
    }
    cache.pipelines.retain(|e, _| views.contains(*e));
}
