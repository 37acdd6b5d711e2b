#!/usr/bin/env bash
# Renders the README's pictures: each example's paper figure at 640x360,
# headlessly (any Vulkan/Metal/DX12 adapter; lavapipe will do).
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --examples
bin="${CARGO_TARGET_DIR:-target}/release/examples"
out=docs/images
"$bin/torus" --screenshot "$out/torus.png"
"$bin/torus" --fog --screenshot "$out/torus_fog.png"
"$bin/torus" --mirror --screenshot "$out/torus_mirror.png"
"$bin/seifert_weber" --screenshot "$out/seifert_weber.png"
"$bin/poincare" --screenshot "$out/poincare.png"
"$bin/mirrored_cube" --screenshot "$out/mirrored_cube.png"
"$bin/mirrored_dodecahedron" --screenshot "$out/mirrored_dodecahedron.png"
"$bin/mirrored_dodecahedron" --no-edges --screenshot "$out/mirrored_dodecahedron_no_edges.png"
# A Bevy scene placed by its transforms (manual, "The examples").
"$bin/bevy_scene" --screenshot "$out/bevy_scene.png"
# The lighting seam of the README's "Known limits of the picture" (CPU f64).
cargo build --release -p bevy_manifold_app
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" render --space torus --scene "$out/lighting_seam.scene.json" \
    --cpu --width 480 --height 270 --levels 4 --out "$out/lighting_seam.png"
# Soft shadows of a light with a radius (manual, "Light and its images").
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" render --space torus --scene "$out/soft_shadows_torus.scene.json" \
    --samples 32 --width 480 --height 270 --out "$out/soft_shadows_torus.png"
# Path-traced stills of the paper's spaces (manual, "Path tracing"): 64
# samples of 6 bounces each, on the GPU.
for s in torus seifert-weber poincare mirrored-cube mirrored-dodecahedron; do
    "${CARGO_TARGET_DIR:-target}/release/bevy_manifold" render --space "$s" --path-trace --depth 6 --samples 64 \
        --width 480 --height 270 --out "$out/path_$s.png"
done
# Walls and hidden cells (README "Exact cells").
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" render --space seifert-weber --walls 0.3 --hidden 0.6 --cells \
    --rule-seed 2 --out "$out/maze.png"
# The shooter, a game in progress in four spaces (README "The shooter"; the manual's examples).
"$bin/shooter" --space torus --screenshot "$out/shooter_torus.png"
"$bin/shooter" --space seifert-weber --screenshot "$out/shooter_seifert_weber.png"
"$bin/shooter" --space poincare --screenshot "$out/shooter_poincare.png"
"$bin/shooter" --space genus2xs1 --screenshot "$out/shooter_genus2xs1.png"
# Billiards, the break in two spaces (manual, "Billiards").
"$bin/billiards" --space torus --screenshot "$out/billiards_torus.png"
"$bin/billiards" --space seifert-weber --screenshot "$out/billiards_seifert_weber.png"
# A level of 4,000 props (manual, "The examples": instances).
"$bin/instances" --screenshot "$out/instances_torus.png"
# The product geometries on the CPU (spaces.md, "The product geometries").
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space genus2xs1 --out "$out/product_genus2xs1.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space s2xs1 --out "$out/product_s2xs1.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space mirrored-prism --out "$out/product_mirrored_prism.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space s2xs1 --lights --out "$out/product_s2xs1_lit.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space genus2xs1 --lights --out "$out/product_genus2xs1_lit.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space genus2xs1 --lights --edges 0.03 --out "$out/product_genus2xs1_edges.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space genus2xs1 --lights --meshes --out "$out/product_genus2xs1_meshes.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space mirrored-prism --cells --out "$out/product_mirrored_prism_cells.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space twisted-genus2xs1 --cells --out "$out/product_twisted_genus2xs1_cells.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --space twisted-s2xs1 --cells --out "$out/product_twisted_s2xs1_cells.png"
"${CARGO_TARGET_DIR:-target}/release/bevy_manifold" product --tour assets/tours/s2xs1.product-tour.json --time 8 --out "$out/product_tour_s2xs1.png"
# Animated glTF characters (manual, "The examples": animated).
"$bin/animated" --screenshot "$out/animated_seifert_weber.png"
