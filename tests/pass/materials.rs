//! Bevy's materials and lights in a manifold, by default: a mesh with a
//! `StandardMaterial` (metallic, roughness, emission, and a
//! metallic-roughness and an emissive texture made as images) lit by a
//! Bevy `PointLight` is gathered with every one of those fields, and an
//! HDR camera shows what the CPU reference computes for it, with the
//! emission above 1.

use super::support::*;
use bevy::camera::Hdr;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use bevy_manifold::prelude::*;
use bevy_manifold::render::offscreen;

/// A 1 x 1 RGBA8 image of `texel` (kept in the main world, where the
/// tracer reads it).
fn one_texel(texel: [u8; 4], format: TextureFormat) -> Image {
    Image::new(
        Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        texel.to_vec(),
        format,
        bevy::asset::RenderAssetUsages::all(),
    )
}

pub fn bevy_pbr_materials_and_lights_render_as_the_cpu_reference_says() {
    use glam::DVec3;
    let space = catalog::torus(1.0);
    let mut scene = Scene::default_for(&space);
    // The default ball stays; the light is Bevy's, below.
    scene.lights.clear();
    let mut app = headless_app(true);
    let image = hdr_target(&mut app);
    let camera = (ManifoldCamera { levels: 8, ..default() }, CellShading::Off, Hdr);
    let (root, _) = offscreen::spawn_view(&mut app, &space, &scene, &image, camera);
    let (mr, glow) = {
        let mut images = app.world_mut().resource_mut::<Assets<Image>>();
        // Roughness (green) 0.5 of the factor, metallic (blue) full.
        let mr = images.add(one_texel([0, 128, 255, 255], TextureFormat::Rgba8Unorm));
        let glow = images.add(one_texel([255, 255, 255, 255], TextureFormat::Rgba8UnormSrgb));
        (mr, glow)
    };
    let material = app
        .world_mut()
        .resource_mut::<Assets<StandardMaterial>>()
        .add(StandardMaterial {
            base_color: Color::linear_rgb(0.8, 0.3, 0.2),
            metallic: 0.9,
            perceptual_roughness: 0.6,
            metallic_roughness_texture: Some(mr),
            emissive: LinearRgba::rgb(3.0, 2.0, 1.5),
            emissive_texture: Some(glow),
            ..default()
        });
    let cube = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .add(Cuboid::new(1.0, 1.0, 1.0));
    let r = space.inradius();
    app.world_mut().spawn((
        ChildOf(root),
        Mesh3d(cube),
        MeshMaterial3d(material),
        Placement::at(&space, DVec3::new(-0.35, -0.1, 0.1) * r),
        Transform::from_scale(Vec3::splat((0.3 * r) as f32)).with_rotation(Quat::from_rotation_y(0.5)),
    ));
    app.world_mut().spawn((
        ChildOf(root),
        PointLight {
            intensity: 200_000.0,
            range: 2.0,
            ..default()
        },
        Placement::at(&space, DVec3::new(0.1, 0.3, 0.5) * r),
    ));
    let gathered = |app: &App| {
        app.world()
            .get::<ManifoldScene>(root)
            .map(|s| (s.scene().meshes.len(), s.scene().lights.len()))
    };
    for _ in 0..2000 {
        app.update();
        if gathered(&app) == Some((1, 1)) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(gathered(&app), Some((1, 1)), "the cube and the Bevy light are gathered");
    let scene_now = gathered_scene(&app, &space, root, false);
    let m = &scene_now.meshes[0].material;
    assert_eq!(m.base_color, [0.8, 0.3, 0.2]);
    let pbr = m.pbr.expect("the GGX lobe");
    assert_eq!((pbr.metallic, pbr.roughness), (0.9, 0.6));
    assert_eq!(m.emissive, [3.0, 2.0, 1.5]);
    assert!(m.metallic_roughness.is_some() && m.emissive_texture.is_some());
    assert!(m.normal_map.is_none() && m.alpha_cutoff.is_none());
    wait_for_pipelines(&mut app);
    let bytes = capture(&mut app, &image);
    let at = |i: usize| hdr_pixel(&bytes, i);
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    };
    let reference = render::<f64>(&space, &scene_now, &settings);
    let cube_id = scene_now.balls.len() as u32 + 1;
    let (mut cube, mut close, mut above) = (0, 0, 0);
    for (i, p) in reference.pixels.iter().enumerate() {
        if p.object != cube_id {
            continue;
        }
        cube += 1;
        let got = at(i);
        if (0..3).all(|c| (got[c] - p.color[c]).abs() <= 0.02 * p.color[c].max(0.05)) {
            close += 1;
        }
        // Emission 3 (red) at least, lit or not.
        if got[0] > 1.0 {
            above += 1;
        }
    }
    eprintln!("{cube} cube pixels: {close} within 2% of the CPU reference, {above} above 1");
    assert!(cube > 300, "the cube is in view ({cube} pixels)");
    assert!(close as f64 >= 0.98 * cube as f64, "{close} of {cube} agree");
    assert_eq!(above, cube, "the emission shows above 1 in the HDR target");
}
