#!/usr/bin/env bash
# Peers side by side: VTK's vtkSSAOPass and Bevy's SSAO on the shared views, scored by
# `obscura eval --score-images` against the same ray-traced truth as obscura's own
# variants, in one run; then one table (peers/out/table.md). Needs ../shared beside the
# repository and the package registries (PyPI for vtk, numpy, Pillow; crates.io for Bevy).
# Not part of CI or the README's tests.
#
#   bash peers/run.sh [OBSCURA_BINARY]     (default: builds target/release/obscura)
#
# Timing alternates: ROUNDS rounds (default 3), each every VTK kernel, every Bevy quality,
# then obscura's eval, so that all see the same machine; the table takes each one's median
# over the rounds and prints each round's ratio of each peer's default to obscura's.
# A peer that cannot be built or run is named with its error, and the others go on.
set -euo pipefail
cd "$(dirname "$0")/.."
out=peers/out
mkdir -p "$out"
bin=${1:-}
if [ -z "$bin" ]; then
  cargo build --release --locked -p obscura-cli
  bin=target/release/obscura
fi
# Quiets Mesa's device-select layer on headless machines (noise only).
export NODEVICE_SELECT=1

# 1. The views' cameras and radii, as obscura evaluates them.
"$bin" eval --all --export-views "$out/views.json"

# 2. The peers. VTK (PyPI wheel, offscreen through EGL): one folder of AO images per kernel
#    size. Bevy (crates.io, its own workspace in peers/bevy, on Vulkan): one per quality.
if [ ! -x "$out/venv/bin/python" ]; then
  python3 -m venv "$out/venv"
fi
"$out/venv/bin/pip" install --quiet vtk numpy pillow
kernels="16 32 64"
qualities="low medium high ultra"
rounds=${ROUNDS:-3}
dirs=()
for k in $kernels; do
  dirs+=("$out/vtk-k$k")
done
bevy=$out/bevy-target/release/obscura-peer-bevy
if CARGO_TARGET_DIR=$out/bevy-target cargo build --release --locked \
    --manifest-path peers/bevy/Cargo.toml; then
  for q in $qualities; do
    dirs+=("$out/bevy-$q")
  done
  for p in $qualities; do
    dirs+=("$out/obscura-bevy-$p")
  done
else
  echo "peers: Bevy's SSAO could not be built (the error is above); the table goes on without it" >&2
  bevy=
fi
evals=()
for r in $(seq 1 "$rounds"); do
  echo "round $r of $rounds" >&2
  for k in $kernels; do
    "$out/venv/bin/python" peers/vtk/ssao.py "$out/views.json" "$out/vtk-k$k" --kernel "$k" \
      --times "times-r$r.json"
  done
  if [ -n "$bevy" ] && ! "$bevy" "$out/views.json" "$out" --qualities "${qualities// /,}" \
      --obscura "${qualities// /,}" \
      --times "times-r$r.json"; then
    echo "peers: Bevy's SSAO failed to run (the error is above); the table goes on without it" >&2
    bevy=
    kept=()
    for d in "${dirs[@]}"; do
      case $d in */bevy-*|*/obscura-bevy-*) ;; *) kept+=("$d") ;; esac
    done
    dirs=("${kept[@]}")
  fi
  # 3. obscura's default and its presets at full and half resolution, with and without
  #    the denoiser, with every peer's images scored, in one eval run (a report once).
  report=(--no-pictures)
  if [ "$r" = 1 ]; then
    report=(--report "$out/report")
  fi
  "$bin" eval --all --estimators gtao --modes deinterleaved2,randomized \
    --presets low,medium,high,ultra --resolutions full,half --denoise none,spatial --runs 3 \
    --no-screen-reference \
    --score-images "$(IFS=,; echo "${dirs[*]}")" \
    --json "$out/eval-r$r.json" "${report[@]}"
  evals+=("$out/eval-r$r.json")
done

# 4. The table.
python3 peers/table.py "$(IFS=,; echo "${evals[*]}")" "${dirs[@]}" | tee "$out/table.md"
