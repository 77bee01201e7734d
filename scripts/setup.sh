#!/usr/bin/env bash
# Installs what obscura needs on a fresh Debian/Ubuntu machine, idempotently:
# Mesa's software Vulkan driver (lavapipe), so obscura runs without a GPU, and the
# rustfmt/clippy components used by CI. Rust itself (stable >= 1.87) must already be
# installed (rustup); Debian's own cargo package is too old for wgpu.
set -euo pipefail

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "setup: need root (or sudo) to run: $*" >&2; exit 1
  fi
}

if ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
  echo "setup: installing mesa-vulkan-drivers (lavapipe)" >&2
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update -qq
  as_root apt-get install -y -qq mesa-vulkan-drivers >/dev/null
fi

if ! command -v cargo >/dev/null; then
  echo "setup: cargo not found. Install Rust stable (>= 1.87) with rustup, then run this again." >&2
  exit 1
fi
if command -v rustup >/dev/null; then
  rustup component add rustfmt clippy >/dev/null 2>&1 || true
fi
