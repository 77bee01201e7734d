"""AO for every depth map in a folder, written as 8-bit PNGs beside a progress bar.

    python python/examples/ao_folder.py DEPTH_DIR OUT_DIR --intrinsics data/intrinsics/redwood.json

Depth maps: 16-bit PNG (depth units, times the intrinsics' depth_scale) or .npy (uint16
likewise, floats in scene units). Intrinsics: the JSON that `obscura render --depth` reads
({fx, fy, cx, cy, width, height, depth_scale}). Needs numpy and Pillow.
"""

import argparse
import json
import pathlib
import sys
import time

import numpy as np
from PIL import Image

import obscura


def load_depth(path):
    if path.suffix.lower() == ".npy":
        return np.load(path)
    with Image.open(path) as im:
        if im.mode not in ("I;16", "I;16B", "I"):
            raise ValueError(f"{path}: a depth PNG is 16-bit single-channel, not mode {im.mode}")
        return np.array(im).astype(np.uint16)


def progress(done, total, started, name):
    width = 30
    filled = width * done // total
    rate = done / max(time.perf_counter() - started, 1e-9)
    sys.stderr.write(
        f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} {rate:.1f} maps/s {name[:40]:<40}"
    )
    sys.stderr.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("depth_dir", type=pathlib.Path)
    ap.add_argument("out_dir", type=pathlib.Path)
    ap.add_argument("--intrinsics", type=pathlib.Path, required=True)
    ap.add_argument("--radius", type=float, default=None, help="scene units (default: 3%% of each map's extent)")
    ap.add_argument("--preset", default="high", choices=["low", "medium", "high", "ultra"])
    args = ap.parse_args()

    k = json.loads(args.intrinsics.read_text())
    maps = sorted(p for p in args.depth_dir.iterdir() if p.suffix.lower() in (".png", ".npy"))
    if not maps:
        sys.exit(f"no .png or .npy depth maps in {args.depth_dir}")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    renderer = obscura.Renderer(preset=args.preset)  # one device, passes compiled once
    print(f"adapter: {renderer.adapter}", file=sys.stderr)
    started = time.perf_counter()
    failed = 0
    for i, path in enumerate(maps):
        progress(i, len(maps), started, path.name)
        try:
            depth = load_depth(path)
            if depth.shape != (k["height"], k["width"]):
                raise ValueError(
                    f"the depth map is {depth.shape[1]}x{depth.shape[0]} but the intrinsics say "
                    f"{k['width']}x{k['height']}"
                )
            # As `obscura render --depth`: the depth scale applies to integer maps only.
            scale = k.get("depth_scale", 0.001) if depth.dtype == np.uint16 else None
            ao = renderer.render(
                depth,
                fx=k["fx"], fy=k["fy"], cx=k["cx"], cy=k["cy"],
                radius=args.radius,
                depth_scale=scale,
            )
        except ValueError as e:
            failed += 1
            print(f"\n{path.name}: {e}", file=sys.stderr)
            continue
        out = args.out_dir / (path.stem + "_ao.png")
        Image.fromarray(np.round(ao * 255).astype(np.uint8)).save(out)
    progress(len(maps), len(maps), started, "done")
    print(file=sys.stderr)
    if failed:
        sys.exit(f"{failed} of {len(maps)} maps failed")


if __name__ == "__main__":
    main()
