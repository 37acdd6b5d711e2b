//! Late latching: the render world locates the eyes again just before the
//! frame is drawn (bevy_mod_openxr's `locate_views` in
//! `XrRenderSystems::PreRender`); each eye's manifold view is placed again
//! from that pose, so the traced image uses the same pose as the
//! rasterised overlay and the compositor. An eye in a product space
//! ([`super::product`]) is moved again likewise, where its late pose is
//! still in the same copy of the prism (else it keeps the frame's).

use super::{XrBody, XrEye, XrRecentre};
use crate::placement::tracked;
use crate::placement::{DomainCell, InSpace, Placement};
use crate::product::ProductCamera;
use crate::product::render::{ExtractedProductView, ProductViewBinding};
use crate::render::extract::ExtractedManifoldView;
use crate::render::pass::ManifoldViewBinding;
use crate::space::product::ProductSpace;
use crate::space::product_cells::ProductElement;
use crate::trace::product::ProductView;
use bevy::prelude::*;
use bevy::render::sync_world::RenderEntity;
use bevy::render::{Extract, Render, RenderApp, RenderSystems};
use bevy_mod_openxr::helper_traits::ToTransform;
use bevy_mod_openxr::resources::OxrViews;
use bevy_mod_xr::session::XrRenderSystems;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// An eye's body, copied to the eye's render entity: what the late pose is
/// measured from.
#[derive(Component, Clone, Debug)]
pub struct ExtractedXrEye {
    /// The view index (0 left, 1 right).
    pub index: u32,
    /// The body's placement.
    pub body: Placement,
    /// The body's cell.
    pub cell: DomainCell,
    /// [`XrBody::world_scale`].
    pub world_scale: f64,
    /// [`super::XrHead::recentred`].
    pub recentred: Vec3,
}

/// An eye in a product space, its body's view copied to the eye's render
/// entity: what the late pose is measured from.
#[derive(Component, Clone, Debug)]
pub struct ExtractedProductXrEye {
    /// The view index (0 left, 1 right).
    pub index: u32,
    /// The body's view.
    pub body: ProductView,
    /// The space.
    pub space: Arc<ProductSpace>,
    /// [`XrBody::world_scale`].
    pub world_scale: f64,
    /// What [`XrRecentre`] takes off the tracked positions.
    pub recentred: Vec3,
    /// The copy of the prism the eye was placed in this frame.
    pub cell: Option<ProductElement>,
}

/// Frames the render world traced for the headset: counted once per frame
/// in which both eyes' views were bound to the tracer (shared by the main
/// and render worlds).
#[derive(Resource, Clone, Debug, Default)]
pub struct XrFrameStats {
    both_eyes: Arc<AtomicU64>,
}

impl XrFrameStats {
    /// Frames with both eyes traced so far.
    #[must_use]
    pub fn both_eyes_traced(&self) -> u64 {
        self.both_eyes.load(Ordering::Relaxed)
    }
}

pub(super) fn build(app: &mut App) {
    let stats = XrFrameStats::default();
    app.insert_resource(stats.clone());
    let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
        return;
    };
    render_app
        .insert_resource(stats)
        .add_systems(
            Render,
            count_traced_eyes
                .after(RenderSystems::PrepareResourcesFlush)
                .before(RenderSystems::Render),
        )
        .add_systems(
            ExtractSchedule,
            (
                extract_eyes.after(crate::render::extract::extract_manifold_views),
                extract_product_eyes,
            ),
        )
        .add_systems(
            Render,
            (late_latch_eyes, late_latch_product_eyes)
                .after(XrRenderSystems::PreRender)
                .in_set(RenderSystems::PrepareResources)
                .before(crate::render::ManifoldPrepareSystems::Scenes),
        );
}

#[expect(clippy::type_complexity, reason = "a system's query")]
fn extract_eyes(
    mut commands: Commands,
    bodies: Extract<Query<(&XrBody, &Placement, &DomainCell, Option<&super::XrHead>), With<InSpace>>>,
    eyes: Extract<Query<(&XrEye, &RenderEntity)>>,
) {
    let Ok((body, placement, cell, head)) = bodies.single() else {
        return;
    };
    for (eye, render_entity) in &eyes {
        commands.entity(render_entity.id()).insert(ExtractedXrEye {
            index: eye.0,
            body: *placement,
            cell: cell.clone(),
            world_scale: body.world_scale,
            recentred: head.map_or(Vec3::ZERO, |h| h.recentred),
        });
    }
}

/// Each eye of a product space's body: its body's view, space and scale
/// on its render entity.
#[expect(clippy::type_complexity, reason = "a system's query")]
fn extract_product_eyes(
    mut commands: Commands,
    bodies: Extract<Query<(&XrBody, &ProductCamera, Option<&XrRecentre>), Without<XrEye>>>,
    eyes: Extract<Query<(&XrEye, &ProductCamera, &RenderEntity)>>,
) {
    let Ok((body, camera, recentre)) = bodies.single() else {
        return;
    };
    for (eye, eye_camera, render_entity) in &eyes {
        commands.entity(render_entity.id()).insert(ExtractedProductXrEye {
            index: eye.0,
            body: camera.view,
            space: camera.space.clone(),
            world_scale: body.world_scale,
            recentred: recentre.and_then(|r| r.offset).unwrap_or(Vec3::ZERO),
            cell: eye_camera.view.cell,
        });
    }
}

/// Counts the frame when both eyes are bound to a tracer (the manifold's
/// or, in a product space, the product pass).
fn count_traced_eyes(
    stats: Res<XrFrameStats>,
    eyes: Query<&ExtractedXrEye, With<ManifoldViewBinding>>,
    product_eyes: Query<&ExtractedProductXrEye, With<ProductViewBinding>>,
) {
    let mut seen = [false; 2];
    for index in eyes.iter().map(|e| e.index).chain(product_eyes.iter().map(|e| e.index)) {
        if let Some(s) = seen.get_mut(index as usize) {
            *s = true;
        }
    }
    if seen == [true, true] {
        stats.both_eyes.fetch_add(1, Ordering::Relaxed);
    }
}

/// Both eyes' late-located poses in the room (left, right); `None` until
/// OpenXR has located two views.
fn late_poses(views: Option<Res<OxrViews>>) -> Option<[(Vec3, Quat); 2]> {
    let views = views.filter(|v| v.len() >= 2)?;
    Some([0, 1].map(|i| {
        let t = views[i].pose.to_transform();
        (t.translation, t.rotation)
    }))
}

/// Places each eye's view from the late-located poses.
fn late_latch_eyes(views: Option<Res<OxrViews>>, mut eyes: Query<(&ExtractedXrEye, &mut ExtractedManifoldView)>) {
    let Some(poses) = late_poses(views) else { return };
    for (eye, mut view) in &mut eyes {
        let poses = poses.map(|(t, q)| (t - eye.recentred, q));
        let g = view.space.space().geometry();
        let (_, placed) = tracked::head_and_eyes(g, eye.body.isometry, poses, eye.world_scale);
        let Some(to) = placed.get(eye.index as usize) else {
            continue;
        };
        if !to.is_finite() {
            continue;
        }
        let (p, c) = tracked::tracked_placement(&view.space, &eye.body, &eye.cell, *to);
        view.camera = p.isometry;
        view.element = c.element;
        view.cell = c.cell;
    }
}

/// Moves each product eye's packed view to its late-located pose, where
/// that pose is in the copy of the prism the frame placed the eye in (the
/// table of cells bound is about that copy).
fn late_latch_product_eyes(
    views: Option<Res<OxrViews>>,
    mut eyes: Query<(&ExtractedProductXrEye, &mut ExtractedProductView)>,
) {
    let Some(poses) = late_poses(views) else { return };
    for (eye, mut view) in &mut eyes {
        let poses = poses.map(|(t, q)| (t - eye.recentred, q));
        let (_, placed) = tracked::product_head_and_eyes(&eye.space, &eye.body, poses, eye.world_scale);
        let Some(to) = placed.get(eye.index as usize) else {
            continue;
        };
        let finite = to.eye.surface.is_finite() && to.eye.height.is_finite();
        if finite && to.cell == eye.cell {
            view.packed.params.set_eye(to);
        }
    }
}
