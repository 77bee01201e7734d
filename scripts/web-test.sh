#!/usr/bin/env bash
# The browser tests (crates/obscura/tests/web.rs): obscura compiled to wasm32 and run on
# WebGPU by wasm-bindgen-test in headless Chromium (SwiftShader's Vulkan, a CPU adapter,
# which Chromium offers only with --enable-unsafe-webgpu: crates/obscura/webdriver.json).
# Installs what it needs, idempotently: the wasm32 target, wasm-bindgen-cli at the
# version of wasm-bindgen in Cargo.lock (its test runner must match the library), and
# Debian's chromium + chromium-driver. docs/guide/web.md.
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "web-test: need root (or sudo) to run: $*" >&2; exit 1
  fi
}

rustup target add wasm32-unknown-unknown >/dev/null 2>&1
version=$(grep -A1 '^name = "wasm-bindgen"$' Cargo.lock | sed -n 's/^version = "\(.*\)"$/\1/p')
if ! wasm-bindgen-test-runner --version 2>/dev/null | grep -qF "$version"; then
  echo "web-test: installing wasm-bindgen-cli $version (about 10 minutes on 2 cores)" >&2
  # Not --locked: the CLI's own lock names versions some registry mirrors lack.
  cargo install --quiet wasm-bindgen-cli --version "$version"
fi
if ! command -v chromedriver >/dev/null || ! command -v chromium >/dev/null; then
  echo "web-test: installing chromium and chromium-driver" >&2
  export DEBIAN_FRONTEND=noninteractive
  as_root apt-get update -qq
  as_root apt-get install -y -qq chromium chromium-driver >/dev/null
fi
echo "web-test: $(chromium --version)" >&2

export CHROMEDRIVER
CHROMEDRIVER=$(command -v chromedriver)
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner
# SwiftShader is slow: the default 20 s per test is not enough.
export WASM_BINDGEN_TEST_TIMEOUT=${WASM_BINDGEN_TEST_TIMEOUT:-900}
# The library and the browser tests lint clean on wasm32 too (CI lints the rest natively).
cargo clippy --locked -p obscura --target wasm32-unknown-unknown --lib --test web -- -D warnings
cargo clippy --locked -p obscura-web --target wasm32-unknown-unknown -- -D warnings
cargo test --locked -p obscura --target wasm32-unknown-unknown --test web "$@"
# The built-in scene in the browser against the same view natively (obscura-scene's
# tests/web.rs): the native AO first, on this machine's adapter (lavapipe in CI).
mkdir -p target/web-parity
NODEVICE_SELECT=1 cargo run --locked --quiet -p obscura-cli -- render --width 160 --height 100 \
  --runs 1 --out target/web-parity/courtyard.npy
export OBSCURA_WEB_NATIVE=$PWD/target/web-parity/courtyard.npy
cargo test --locked -p obscura-scene --target wasm32-unknown-unknown --test web "$@"
