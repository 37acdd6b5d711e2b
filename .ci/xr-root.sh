#!/usr/bin/env bash
# Builds (once per machine) the Debian trixie root with Monado that the XR
# test runs in (crates/bevy_manifold_app/tests/xr.rs): Monado's null
# compositor and simulated headset, the OpenXR loader and lavapipe. Bookworm
# has no Monado package, hence the root; its glibc is newer, so binaries
# built here run in it. Recipe: ../shared/openxr-headless.md. Prints the
# root's path. Cached under $HOME/.cache, never in the clone (~1.2 GB).
set -euo pipefail
ROOT="${BEVY_MANIFOLD_XR_ROOT:-$HOME/.cache/bevy_manifold/monado-root}"
if [ -x "$ROOT/usr/bin/monado-service" ] && [ -e "$ROOT/usr/lib/x86_64-linux-gnu/libopenxr_loader.so" ]; then
  echo "$ROOT"
  exit 0
fi
sudo_cmd=""
[ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
if ! command -v debootstrap >/dev/null; then
  $sudo_cmd apt-get update -qq >&2
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends debootstrap >&2
fi
# The mirror this machine's apt already uses.
MIRROR=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/*.sources 2>/dev/null || true)
if [ -z "$MIRROR" ]; then
  MIRROR=$(awk '/^deb /{print $2; exit}' /etc/apt/sources.list 2>/dev/null || true)
fi
MIRROR="${MIRROR:-http://deb.debian.org/debian}"
$sudo_cmd rm -rf "$ROOT.tmp"
mkdir -p "$(dirname "$ROOT")"
$sudo_cmd debootstrap --variant=minbase trixie "$ROOT.tmp" "$MIRROR" >&2
$sudo_cmd cp /etc/resolv.conf "$ROOT.tmp/etc/"
$sudo_cmd chroot "$ROOT.tmp" apt-get update -qq >&2
# libopenxr-dev: the unversioned libopenxr_loader.so the openxr crate loads.
$sudo_cmd chroot "$ROOT.tmp" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
  monado-service libopenxr1-monado libopenxr-loader1 libopenxr-dev mesa-vulkan-drivers libvulkan1 >&2
$sudo_cmd chroot "$ROOT.tmp" apt-get clean >&2
$sudo_cmd rm -rf "$ROOT"
$sudo_cmd mv "$ROOT.tmp" "$ROOT"
echo "$ROOT"
