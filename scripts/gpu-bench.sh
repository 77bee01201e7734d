#!/usr/bin/env bash
# The GPU measurements of BENCHMARKS.md ("On a hardware GPU"), in one go, for a machine with
# a real GPU: per-pass GPU timestamps of every layout, resolution, reuse variant and
# estimator at 1080p and 4K on the built-in scene, and interleaved many-light shading.
#
#   bash scripts/gpu-bench.sh [OBSCURA_BINARY] [OUT_DIR]
#
# Defaults: target/release/obscura, out/gpu. Each step's output goes to OUT_DIR/STEP.txt
# (and JSON beside it where the command writes one); a failing step is reported and the
# rest still run. The adapter is forced to a hardware GPU (OBSCURA_ADAPTER=gpu) unless the
# caller sets OBSCURA_ADAPTER.
set -uo pipefail

bin=${1:-target/release/obscura}
out=${2:-out/gpu}
mkdir -p "$out"
export OBSCURA_ADAPTER=${OBSCURA_ADAPTER:-gpu}
failed=0

step() {
  local name=$1
  shift
  echo "== $name: obscura $*"
  local t0=$SECONDS
  if ! "$bin" "$@" >"$out/$name.txt" 2>&1; then
    echo "   FAILED (see $out/$name.txt)"
    failed=$((failed + 1))
  fi
  cat "$out/$name.txt"
  echo "   ($((SECONDS - t0)) s)"
}

big=1920x1080,3840x2160
step layouts bench --compare layouts --resolutions "$big" --radii 8,32,128,256 --runs 20 \
  --json "$out/layouts.json"
step resolutions bench --compare resolutions --resolutions "$big" --radii 32,128 --runs 20 \
  --json "$out/resolutions.json"
step reuse bench --compare reuse --resolutions 1280x720,"$big" --radii 32 --runs 20 \
  --json "$out/reuse.json"
for e in hbao vo vao sao vo-area; do
  step "estimator-$e" bench --estimator "$e" --compare layouts --resolutions "$big" \
    --radii 32 --runs 20 --json "$out/estimator-$e.json"
done
step lights-720p-256 lights --width 1280 --height 720 --count 256 --periods 2,4,8 --runs 21
step lights-720p-1024 lights --width 1280 --height 720 --count 1024 --periods 2,4,8 --runs 21
step lights-1080p-256 lights --width 1920 --height 1080 --count 256 --periods 2,4,8 --runs 21
step lights-4k-1024 lights --width 3840 --height 2160 --count 1024 --periods 2,4,8 --runs 11

echo "gpu-bench: $failed step(s) failed"
[ "$failed" -eq 0 ]
