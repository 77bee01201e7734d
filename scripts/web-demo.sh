#!/usr/bin/env bash
# obscura's demo page (crates/obscura-web): builds it for the browser into target/web (with
# a link to ../shared/scenes, for Sponza, where it exists) and serves it on http://127.0.0.1:${PORT:-8137}/ (Ctrl-C stops). `--build-only` stops after
# the build. Needs the wasm32 target and wasm-bindgen-cli, which scripts/web-test.sh
# installs. docs/guide/web.md.
set -euo pipefail
cd "$(dirname "$0")/.."
rustup target add wasm32-unknown-unknown >/dev/null 2>&1
cargo build --locked --release -p obscura-web --target wasm32-unknown-unknown
rm -rf target/web
mkdir -p target/web
wasm-bindgen --target web --no-typescript --out-dir target/web/pkg \
  target/wasm32-unknown-unknown/release/obscura_web.wasm
cp crates/obscura-web/web/index.html target/web/
# The shared scenes (Sponza), linked beside the page when they are beside the repository;
# never copied (several are non-commercial).
if [ -d ../shared/scenes ]; then
  ln -s "$(cd ../shared/scenes && pwd)" target/web/scenes
fi
echo "web-demo: built target/web ($(du -sh target/web | cut -f1))" >&2
if [ "${1:-}" = "--build-only" ]; then exit 0; fi
port=${PORT:-8137}
echo "web-demo: open http://127.0.0.1:$port/ in a browser with WebGPU" >&2
exec python3 -m http.server "$port" --bind 127.0.0.1 --directory target/web
