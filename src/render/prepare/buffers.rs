//! Each space's buffers ([`prepare_manifold_scene_buffers`]): one buffer a
//! binding of [`BINDINGS`] that the space or its objects fill, made once
//! and written in place while the new data fits.

use super::super::extract::ExtractedManifoldView;
use super::cache::{ManifoldBufferCache, ManifoldUploads, SceneBuffers};
use super::scenes::ManifoldPackedScenes;
use bevy::platform::collections::HashSet;
use bevy::prelude::*;
use bevy::render::render_resource::{Buffer, BufferInitDescriptor, BufferUsages};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy_manifold_gpu::bindings::{BINDINGS, Binding, BindingKind, BindingSource};
use bevy_manifold_gpu::{GpuObjects, GpuSpace, binding_bytes};
use std::sync::Arc;

/// Makes or brings up to date the buffers of every space a view looks
/// into, uploading only what changed; drops those of spaces no view looks
/// into any more.
pub fn prepare_manifold_scene_buffers(
    views: Query<&ExtractedManifoldView>,
    packed: Res<ManifoldPackedScenes>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut cache: ResMut<ManifoldBufferCache>,
    mut stats: ResMut<ManifoldUploads>,
) {
    let stats = &mut *stats;
    let mut roots = HashSet::new();
    for view in &views {
        if !roots.insert(view.root) {
            continue;
        }
        let Some((space, objects)) = packed.get(view.root) else {
            continue;
        };
        let space = space.gpu();
        cache
            .scenes
            .entry(view.root)
            .or_insert_with(|| SceneBuffers::new(&device, space, objects, stats))
            .update(&device, &queue, space, objects, stats);
    }
    cache.scenes.retain(|root, _| roots.contains(root));
}

impl SceneBuffers {
    /// The buffers of `space` and `objects`, first made.
    fn new(
        device: &RenderDevice,
        space: &Arc<GpuSpace>,
        objects: &Arc<GpuObjects>,
        stats: &mut ManifoldUploads,
    ) -> Self {
        stats.space += 1;
        stats.objects += 1;
        let buffers = scene_bindings()
            .map(|b| {
                let data = binding_bytes(b, space, objects).unwrap_or_default();
                (b, scene_buffer(device, b, data, stats))
            })
            .collect();
        SceneBuffers {
            space: space.clone(),
            objects: objects.clone(),
            buffers,
            made: 0,
        }
    }

    /// Brings the buffers up to `space` and `objects`, writing in place
    /// where the new data fits and growing (bumping `made`) where it does
    /// not; an unchanged `Arc` uploads nothing.
    fn update(
        &mut self,
        device: &RenderDevice,
        queue: &RenderQueue,
        space: &Arc<GpuSpace>,
        objects: &Arc<GpuObjects>,
        stats: &mut ManifoldUploads,
    ) {
        let new_space = !Arc::ptr_eq(&self.space, space);
        let new_objects = !Arc::ptr_eq(&self.objects, objects);
        stats.space += u64::from(new_space);
        stats.objects += u64::from(new_objects);
        // A moved instance changes its matrix, not its mesh: the BVHs
        // stay uploaded.
        let same_meshes = self.objects.mesh_data == objects.mesh_data;
        let mut grew = false;
        for (b, slot) in &mut self.buffers {
            let write = match b.source {
                BindingSource::Space => new_space,
                BindingSource::Objects => new_objects && !(same_meshes && b.name == "mesh_data"),
                BindingSource::View | BindingSource::Output => false,
            };
            if write {
                let data = binding_bytes(b, space, objects).unwrap_or_default();
                grew |= write_or_grow(device, queue, slot, b, data, stats);
            }
        }
        self.space = space.clone();
        self.objects = objects.clone();
        if grew {
            self.made += 1;
        }
    }

    /// The buffer of `binding`.
    pub(super) fn buffer(&self, binding: &Binding) -> Option<&Buffer> {
        self.buffers
            .iter()
            .find(|(b, _)| b.binding == binding.binding)
            .map(|(_, buffer)| buffer)
    }
}

/// The bindings a space and its objects fill, in binding order.
fn scene_bindings() -> impl Iterator<Item = &'static Binding> {
    BINDINGS
        .iter()
        .filter(|b| matches!(b.source, BindingSource::Space | BindingSource::Objects))
}

/// Smallest storage buffer made, in bytes.
const MIN_BUFFER: u64 = 256;

/// A buffer labelled `manifold_<name>` holding `data` for `binding`, with
/// `COPY_DST` so later data is written in place.
fn scene_buffer(device: &RenderDevice, binding: &Binding, data: &[u8], stats: &mut ManifoldUploads) -> Buffer {
    stats.bytes += data.len() as u64;
    let (size, usage) = match binding.kind {
        // A uniform array (faces, tubes, lights, face groups: BINDINGS) is
        // always its declared length, so every space and scene fits in place.
        BindingKind::Uniform => (binding.bytes_for(data.len()), binding.usage()),
        // Room to grow (a power of two), so the next space or scene that
        // fits is written in place and keeps the bind group (see
        // `write_or_grow`); never past what the device binds, unless the
        // data itself is larger (then binding fails as it would have
        // without the room).
        BindingKind::Storage | BindingKind::StorageReadWrite => {
            let limit = usize::try_from(device.limits().max_storage_buffer_binding_size).unwrap_or(usize::MAX);
            let size = data
                .len()
                .max(MIN_BUFFER as usize)
                .next_power_of_two()
                .min(limit & !3)
                .max(data.len());
            (size, BufferUsages::STORAGE)
        }
    };
    let mut contents = vec![0u8; size];
    contents[..data.len()].copy_from_slice(data);
    device.create_buffer_with_data(&BufferInitDescriptor {
        label: Some(&format!("manifold_{}", binding.name)),
        contents: &contents,
        usage: usage | BufferUsages::COPY_DST,
    })
}

/// Writes `data` into `slot` in place when it fits, else replaces `slot`
/// with a larger buffer holding it; true when replaced (the view's bind
/// group must then be made again). Writing in place lets a view whose
/// space or scene changes keep its buffers and bind group instead of
/// making ten new GPU objects per change. The shader reads only the
/// counts in the params, so a buffer larger than its data is harmless.
fn write_or_grow(
    device: &RenderDevice,
    queue: &RenderQueue,
    slot: &mut Buffer,
    binding: &Binding,
    data: &[u8],
    stats: &mut ManifoldUploads,
) -> bool {
    if data.len() as u64 <= slot.size() {
        if !data.is_empty() {
            queue.write_buffer(slot, 0, data);
        }
        stats.bytes += data.len() as u64;
        false
    } else {
        *slot = scene_buffer(device, binding, data, stats);
        true
    }
}
