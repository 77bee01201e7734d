#!/usr/bin/env bash
# The GPU measurements of BENCHMARKS.md ("On a hardware GPU"), in one go, for a machine with
# a real GPU: per-pass GPU timestamps of every layout, resolution, reuse variant, depth
# layer and estimator at 1080p and 4K on the built-in scene, and interleaved many-light
# shading; then, where the shared scenes are at hand, quality against GPU time at 720p.
#
#   bash scripts/gpu-bench.sh [OBSCURA_BINARY] [OUT_DIR] [SCENES_DIR]
#
# Defaults: target/release/obscura, out/gpu, ../shared/scenes (the eval steps are skipped
# where it does not exist; their ray-traced references are cached in OUT_DIR/cache). Each step's output goes to OUT_DIR/STEP.txt
# (and JSON beside it where the command writes one); a failing step is reported and the
# rest still run. The adapter is forced to a hardware GPU (OBSCURA_ADAPTER=gpu) unless the
# caller sets OBSCURA_ADAPTER. OUT_DIR holds about 40 files and cache/ about 170 MB, so the
# script ends by packing OUT_DIR without the cache and the PNGs into OUT_DIR.tgz: one file
# for a tool that brings back only a few.
set -uo pipefail

bin=${1:-target/release/obscura}
out=${2:-out/gpu}
scenes=${3:-../shared/scenes}
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
# A GPU that has idled runs its first frames at low clocks: a few seconds of 4K frames first
# (the eval steps below likewise, after their references are traced).
warm() { "$bin" bench --resolutions 3840x2160 --radii 32 --runs 100 >/dev/null 2>&1; }
warm
step layouts bench --compare layouts --resolutions "$big" --radii 8,32,128,256 --runs 20 \
  --json "$out/layouts.json"
step resolutions bench --compare resolutions --resolutions "$big" --radii 32,128 --runs 20 \
  --json "$out/resolutions.json"
step reuse bench --compare reuse --resolutions 1280x720,"$big" --radii 32 --runs 20 \
  --json "$out/reuse.json"
for e in gtao bitmask; do
  step "layers-$e" bench --estimator "$e" --compare layers --resolutions "$big" \
    --radii 32,128 --runs 20 --json "$out/layers-$e.json"
done
for e in hbao vo vao sao vo-area bitmask; do
  step "estimator-$e" bench --estimator "$e" --compare layouts --resolutions "$big" \
    --radii 32 --runs 20 --json "$out/estimator-$e.json"
done
step lights-720p-256 lights --width 1280 --height 720 --count 256 --periods 2,4,8 --runs 21
step lights-720p-1024 lights --width 1280 --height 720 --count 1024 --periods 2,4,8 --runs 21
step lights-1080p-256 lights --width 1920 --height 1080 --count 256 --periods 2,4,8 --runs 21
step lights-4k-1024 lights --width 3840 --height 2160 --count 1024 --periods 2,4,8 --runs 11
# SSDO after the AO (wall clock around submit + wait, as render times both).
step ssdo-1080p render --width 1920 --height 1080 --runs 21 --out "$out/ao-1080p.png" \
  --ssdo "$out/ssdo-1080p.png"
step ssdo-4k render --width 3840 --height 2160 --runs 21 --out "$out/ao-4k.png" \
  --ssdo "$out/ssdo-4k.png"

if [ -d "$scenes" ]; then
  hd=(eval --all --scenes-dir "$scenes" --cache "$out/cache" --width 1280 --height 720
    --denoise spatial --no-screen-reference --no-pictures)
  # Trace the references (CPU, seconds a view), so that the timed steps do not idle.
  step references-720p "${hd[@]}" --estimators gtao --presets low --runs 1
  warm
  step frontier-720p "${hd[@]}" --estimators gtao --presets low,medium,high,ultra \
    --modes randomized,deinterleaved2 --resolutions full,half --runs 5 --json "$out/frontier-720p.json" \
    --report "$out/frontier-720p" --markdown "$out/frontier-720p.md"
  step layers-720p "${hd[@]}" --estimators gtao,bitmask --presets high \
    --modes randomized,deinterleaved2 --thickness 0.75,1 --second-layer --guard-bands 0,32 --runs 5 \
    --json "$out/layers-720p.json" --report "$out/layers-720p" --markdown "$out/layers-720p.md"
  # The bitmask against GTAO with more steps, with and without a second layer: the frontier
  # that decides whether the bitmask could be the default (docs/thickness.md, "On a GPU").
  step splits-720p "${hd[@]}" --estimators gtao,bitmask --splits 3x5,3x6,3x8 --march-exponents 1.3 \
    --modes randomized,deinterleaved2 --thickness 1 --second-layer --runs 5 \
    --json "$out/splits-720p.json" --report "$out/splits-720p" --markdown "$out/splits-720p.md"
  # More steps at exponent 1.25 (square roots, no pow) against the default's 3 × 6 at 1.3:
  # the candidates for a default with less pattern error (docs/patterns.md, "What is left").
  step steps-720p "${hd[@]}" --estimators gtao --modes deinterleaved2 --splits 3x6,3x7,3x8,3x9 \
    --march-exponents 1.3,1.25 --runs 9 --json "$out/steps-720p.json"
else
  echo "== eval steps skipped: no scenes at $scenes"
fi

tar czf "$out.tgz" --exclude=cache --exclude="*.png" -C "$(dirname "$out")" "$(basename "$out")" &&
  echo "gpu-bench: packed $out.tgz"
echo "gpu-bench: $failed step(s) failed"
[ "$failed" -eq 0 ]
