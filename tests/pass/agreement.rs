//! The pass against the headless tracer and the CPU reference: every space,
//! a viewport, the paper's scene as entities, per-cell tints, exact cells
//! and walls far from the origin copy; and ordinary cameras untouched.

use super::support::*;
use bevy::camera::{RenderTarget, Viewport};
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy_manifold::prelude::*;
use bevy_manifold::render::{ManifoldBufferCache, offscreen};
use bevy_manifold::trace::FlatScene;
use bevy_manifold_gpu::{GpuObjects, GpuTracer};
use bevy_manifold_test_support::compare::rgba8_agreement;

pub fn the_pass_draws_what_the_tracer_computes_in_every_space() {
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let mut gpu = GpuTracer::new().expect("adapter");
    for (i, name) in catalog::NAMES.iter().enumerate() {
        let space = catalog::by_name(name).expect("catalog");
        // Fog and per-cell shading on every other space.
        let (fog, cells) = (i % 2 == 1, i % 2 == 1);
        let (root, shown, scene) = shown_default_scene(&mut app, &space, &image, (fog, cells));
        let reference = Scene::default_for(&space);
        assert_eq!(
            scene.balls, reference.balls,
            "{name}: the ECS scene is the default scene"
        );
        assert_eq!(scene.edge_radius, reference.edge_radius);
        assert_eq!(scene.lights.len(), 1);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 8,
            cell_colors: cells,
            ..TraceSettings::default()
        };
        let compute = gpu.render(&space, &scene, &settings).expect("headless trace");
        let cpu = render::<f64>(&space, &scene, &settings);
        let vs_compute = rgba8_agreement(&shown, &compute, 1);
        let vs_cpu = rgba8_agreement(&shown, &cpu, 2);
        let lit = lit_pixels(&shown);
        eprintln!(
            "{name:<22} fog {fog:<5} cells {cells:<5}: pass vs headless compute (±1/255): {:.3}%, vs CPU f64 (±2/255): {:.3}%, {lit} lit pixels",
            vs_compute * 100.0,
            vs_cpu * 100.0
        );
        assert!(lit > (W * H / 4) as usize, "{name}: the view is mostly black");
        assert!(vs_compute >= 0.995, "{name}: the pass differs from the headless trace");
        assert!(vs_cpu >= 0.99, "{name}: the pass differs from the CPU reference");
        // Switching spaces: the old hierarchy goes, its buffers with it.
        app.world_mut().entity_mut(root).despawn();
        app.update();
        app.update();
        assert_eq!(
            app.sub_app(RenderApp).world().resource::<ManifoldBufferCache>().len(),
            0
        );
    }
}

pub fn a_viewport_shows_the_same_trace_as_a_whole_target() {
    let mut app = headless_app(true);
    let space = catalog::torus(1.0);
    let whole = target(&mut app, 64, 48);
    let big = target(&mut app, 100, 80);
    let (_, _) = spawn_view(&mut app, &space, &whole, false, false);
    let (_, inset) = spawn_view(&mut app, &space, &big, false, false);
    app.world_mut().get_mut::<Camera>(inset).unwrap().viewport = Some(Viewport {
        physical_position: UVec2::new(30, 20),
        physical_size: UVec2::new(64, 48),
        ..default()
    });
    wait_for_pipelines(&mut app);
    let a = capture(&mut app, &whole);
    let b = capture(&mut app, &big);
    let mut same = 0;
    for y in 0..48 {
        for x in 0..64 {
            let pa = &a[(y * 64 + x) * 4..][..4];
            let pb = &b[((y + 20) * 100 + x + 30) * 4..][..4];
            same += usize::from(pa == pb);
        }
    }
    assert_eq!(
        same,
        64 * 48,
        "the inset viewport differs from the whole-target trace (lit pixels: whole {}, inset target {})",
        lit_pixels(&a),
        lit_pixels(&b)
    );
}

pub fn the_papers_scene_as_entities_matches_the_tracers() {
    use bevy_manifold::drawables::paper::{paper_camera, spawn_paper_scene};
    use bevy_manifold::trace::PaperOptions;
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let space = catalog::mirrored_cube(1.0);
    let root = app.world_mut().spawn(ManifoldSpace::new(space.clone())).id();
    let (placement, projection) = paper_camera(&space);
    let camera = app
        .world_mut()
        .spawn((
            ChildOf(root),
            ManifoldCamera::default(),
            placement,
            projection,
            RenderTarget::Image(image.clone().into()),
        ))
        .id();
    let mut commands = app.world_mut().commands();
    let spawned = spawn_paper_scene(&mut commands, root, camera, &space, PaperOptions::default());
    app.world_mut().flush();
    let meshes_of = |app: &App| app.world().get::<ManifoldMeshes>(root).map_or(0, |m| m.meshes.len());
    for _ in 0..200 {
        app.update();
        if meshes_of(&app) == 3 {
            break;
        }
    }
    assert_eq!(meshes_of(&app), 3, "Suzanne and the two hands");
    let gathered = &app.world().get::<ManifoldMeshes>(root).unwrap();
    let body = gathered
        .entities
        .iter()
        .position(|e| Some(*e) == spawned.suzanne)
        .expect("Suzanne is gathered");
    assert!(gathered.meshes[body].attached, "Suzanne is the camera's body");
    assert_eq!(
        gathered.meshes.iter().filter(|m| m.attached).count(),
        1,
        "the hands are drawn in the home copy too"
    );
    wait_for_pipelines(&mut app);
    let shown = capture(&mut app, &image);
    // Against the tracer's own version of the paper's scene: the same
    // layout, the hands placed through the camera's chart instead of by an
    // isometry (exact in the flat cube).
    let reference = Scene::paper_default(&space);
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 8,
        ..TraceSettings::default()
    };
    let cpu = render::<f64>(&space, &reference, &settings);
    let mesh_pixels = cpu.pixels.iter().filter(|p| p.object >= 1 && p.object < 100).count();
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!(
        "paper's scene as entities in the mirrored cube: {mesh_pixels} mesh pixels, {:.3}% within 2/255 of Scene::paper_default on the CPU",
        close * 100.0
    );
    assert!(mesh_pixels > 500, "the hands and Suzanne's images are in view");
    assert!(close >= 0.99);
    // The camera moves, and the body and hands with it: their instances
    // are uploaded again, their BVHs are not.
    let scene = app.world().get::<ManifoldScene>(root).unwrap().scene();
    let packed = GpuObjects::pack(&FlatScene::<f32>::new(&space, scene));
    let mesh_bytes = (packed.mesh_data.len() * 16) as u64;
    let before = uploads(&app);
    app.world_mut().get_mut::<Placement>(camera).unwrap().isometry *=
        isometry::translation(space.geometry(), glam::DVec3::X * 0.05);
    app.update();
    app.update();
    let after = uploads(&app);
    eprintln!(
        "moving the camera: {} object uploads, {} bytes (the meshes' data is {mesh_bytes} bytes)",
        after.objects - before.objects,
        after.bytes - before.bytes
    );
    assert!(after.objects > before.objects, "the attached meshes moved");
    assert!(
        after.bytes - before.bytes < mesh_bytes / 4,
        "the BVHs were not uploaded again"
    );
    // In another copy, two mirrors away: the body's home (the copy not
    // drawn) is the camera's copy there, so the picture is the CPU's from
    // that copy, not one from inside Suzanne.
    let word = vec![0, 2];
    app.world_mut()
        .entity_mut(camera)
        .insert(bevy_manifold::placement::DomainCell::new(
            &space,
            space.cell_of_word(&word),
        ));
    for _ in 0..3 {
        app.update();
    }
    let shown = capture(&mut app, &image);
    let mut scene = gathered_scene(&app, &space, root, false);
    scene.camera.isometry = app.world().get::<Placement>(camera).unwrap().isometry;
    scene.camera.cell = word;
    let cpu = render::<f64>(&space, &scene, &settings);
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!("the same two mirrors away: {:.3}% within 2/255", close * 100.0);
    assert!(close >= 0.99, "{close}");
}

pub fn cell_tints_agree_between_the_pass_and_the_cpu() {
    use bevy_manifold::space::cells::CellTint;
    let space = catalog::torus(1.0);
    let lattice = |x, y, z| CellId::from_lattice(glam::IVec3::new(x, y, z));
    for (shading, tint) in [
        (
            CellShading::Highlight {
                cell: lattice(0, 0, -1).0,
            },
            CellTint::Highlight(lattice(0, 0, -1)),
        ),
        (
            CellShading::Pattern { on_fraction: 0.4 },
            CellTint::Pattern { on_fraction: 0.4 },
        ),
    ] {
        let mut app = headless_app(true);
        let image = target(&mut app, W, H);
        let camera = (ManifoldCamera { levels: 6, ..default() }, shading);
        let (root, _) = offscreen::spawn_view(&mut app, &space, &Scene::default_for(&space), &image, camera);
        wait_for_pipelines(&mut app);
        let shown = capture(&mut app, &image);
        let scene = gathered_scene(&app, &space, root, false);
        let settings = TraceSettings {
            width: W,
            height: H,
            levels: 6,
            cell_colors: true,
            cell_tint: tint,
            ..TraceSettings::default()
        };
        let cpu = render::<f64>(&space, &scene, &settings);
        let plain = render::<f64>(
            &space,
            &scene,
            &TraceSettings {
                cell_colors: false,
                ..settings.clone()
            },
        );
        let tinted = cpu
            .pixels
            .iter()
            .zip(&plain.pixels)
            .filter(|(a, b)| a.color != b.color)
            .count();
        let close = rgba8_agreement(&shown, &cpu, 2);
        eprintln!(
            "{tint:?}: {tinted} of {} pixels tinted on the CPU; the pass within 2/255 of it: {:.3}%",
            cpu.pixels.len(),
            close * 100.0
        );
        assert!(tinted > 100, "{tint:?} changes some copies");
        assert!(tinted < cpu.pixels.len(), "{tint:?} leaves some pixels alone");
        assert!(close >= 0.995, "{tint:?}");
    }
}

/// A camera 20 crossings from the origin copy of Seifert-Weber, under
/// walls and per-cell colour: the pass centres its table of exact ids on
/// the camera's exact cell (recentred off the frame) and draws what the
/// CPU f64 reference draws from that cell. Three levels keep every ray in
/// the table (radius 4).
pub fn the_pass_draws_exact_cells_and_walls_far_from_the_origin_copy() {
    use bevy_manifold::placement::DomainCell;
    use bevy_manifold::space::rule::{CellRule, Walls};
    let space = catalog::seifert_weber();
    let word: Vec<usize> = (0..20).map(|k| (k * 5 + k / 3) % 12).collect();
    let rule = CellRule {
        hidden: None,
        walls: Some(Walls { density: 0.3, seed: 5 }),
    };
    let mut app = headless_app(true);
    let image = target(&mut app, W, H);
    let camera = (ManifoldCamera { levels: 3, ..default() }, CellShading::ByCell);
    let (root, cam) = offscreen::spawn_view(&mut app, &space, &Scene::default_for(&space), &image, camera);
    app.world_mut().get_mut::<ManifoldSpace>(root).unwrap().set_rule(rule);
    let far = DomainCell::new(&space, space.cell_of_word(&word));
    assert!(!far.id.is_far());
    app.world_mut().entity_mut(cam).insert(far);
    wait_for_pipelines(&mut app);
    // The recentred table arrives from the async pool within a few frames.
    for _ in 0..20 {
        app.update();
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let shown = capture(&mut app, &image);
    let mut scene = gathered_scene(&app, &space, root, false);
    scene.camera.cell = word;
    let settings = TraceSettings {
        width: W,
        height: H,
        levels: 3,
        cell_colors: true,
        cell_rule: rule,
        ..TraceSettings::default()
    };
    let cpu = render::<f64>(&space, &scene, &settings);
    let walls = cpu
        .pixels
        .iter()
        .filter(|p| p.object == bevy_manifold::space::rule::WALL_OBJECT)
        .count();
    let close = rgba8_agreement(&shown, &cpu, 2);
    eprintln!(
        "far camera, walls: {walls} wall pixels on the CPU; the pass within 2/255: {:.3}%",
        close * 100.0
    );
    assert!(walls > 100);
    assert!(close >= 0.99, "{close}");
}

pub fn cameras_without_the_marker_render_exactly_as_before() {
    let shots: Vec<Vec<u8>> = [false, true]
        .into_iter()
        .map(|with_manifold| {
            let mut app = headless_app(with_manifold);
            let image = target(&mut app, 96, 64);
            plain_scene(&mut app, &image);
            if with_manifold {
                // A manifold camera in the same app, drawing elsewhere.
                let other = target(&mut app, 32, 32);
                spawn_view(&mut app, &catalog::poincare(), &other, true, true);
            }
            wait_for_pipelines(&mut app);
            capture(&mut app, &image)
        })
        .collect();
    let lit = shots[0].chunks_exact(4).filter(|p| p[0] > 20).count();
    assert!(lit > 500, "the plain scene shows its cube ({lit} lit pixels)");
    assert!(
        shots[0] == shots[1],
        "the plain camera's image changed when the plugin was added"
    );
}
