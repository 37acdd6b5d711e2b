//! Tracked poses (a headset's eyes) carried into the manifold: the head
//! from the body, the eyes from the head, along geodesics, wrapped.

use bevy_manifold::placement::{DomainCell, ManifoldSpace, Placement, tracked};
use bevy_manifold::prelude::*;
use bevy_manifold::space::cells::CellId;
use glam::{DMat4, DQuat, DVec3, Quat, Vec3};

/// In Seifert-Weber (curvature -1), eyes 64 mm apart at head height are
/// 64 mm / scale apart along a geodesic through the head, as in the room:
/// the rule measures them from the head. Measured from the body (the
/// room's floor) instead, they would be sinh(d)/d further apart.
#[test]
fn the_eyes_are_as_far_apart_as_in_the_room_wherever_the_head_is() {
    let sw = catalog::seifert_weber();
    let g = sw.geometry();
    let scale = 4.0;
    let body = DMat4::IDENTITY;
    let eyes = [
        (Vec3::new(-0.032, 1.6, 0.0), Quat::IDENTITY),
        (Vec3::new(0.032, 1.6, 0.0), Quat::IDENTITY),
    ];
    let (head, [l, r]) = tracked::head_and_eyes(g, body, eyes, scale);
    let d = |a: DMat4, b: DMat4| g.distance::<f64>(a.w_axis, b.w_axis);
    // The tracker's f32 metres, read exactly.
    let (up, half) = (f64::from(1.6f32) / scale, f64::from(0.032f32) / scale);
    assert!((d(body, head) - up).abs() < 1e-12, "{}", d(body, head));
    assert!((d(l, r) - 2.0 * half).abs() < 1e-12, "{}", d(l, r));
    assert!((d(head, l) - half).abs() < 1e-12 && (d(head, r) - half).abs() < 1e-12);
    // From the floor: wider by about sinh(0.4)/0.4 = 1.027.
    let naive = |t: Vec3| tracked::pose_isometry(g, body, t.as_dvec3(), DQuat::IDENTITY, scale);
    let spread = d(naive(eyes[0].0), naive(eyes[1].0));
    assert!(spread > 2.0 * half * 1.02, "{spread}");
    // Turned heads turn the eyes' line with them: a head turned 90
    // degrees about y puts the left eye ahead (+z is behind, -z ahead).
    let turn = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    let turned = [(turn * eyes[0].0, turn), (turn * eyes[1].0, turn)];
    let (h2, [l2, _]) = tracked::head_and_eyes(g, body, turned, scale);
    let local = bevy_manifold::geometry::isometry::inverse(g, h2) * l2.w_axis;
    assert!((local.x + 0.008).abs() < 1e-6 && local.z.abs() < 1e-9, "{local}");
}

/// An eye past a face is carried through it: its cell is the neighbour's
/// and its chart position inside the domain.
#[test]
fn an_eye_past_a_face_is_wrapped_into_the_next_copy() {
    let space = catalog::torus(1.0);
    let ms = ManifoldSpace::new(space.clone());
    let body = Placement::at(&space, DVec3::new(0.45, 0.0, 0.0));
    let cell = DomainCell::default();
    let to = tracked::pose_isometry(space.geometry(), body.isometry, DVec3::X * 0.2, DQuat::IDENTITY, 1.0);
    let (p, c) = tracked::tracked_placement(&ms, &body, &cell, to);
    assert!((p.position().x - (-0.35)).abs() < 1e-12, "{}", p.position());
    assert_ne!(c.id, CellId(0));
    // Carried back by the cell's element, it is where the pose said.
    let back = c.element * p.isometry;
    assert!((back.w_axis - to.w_axis).length() < 1e-12);
}
