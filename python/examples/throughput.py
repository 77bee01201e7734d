"""Throughput of obscura.Renderer: 100 maps of a 640x480 depth map, timed one by one;
with --threads N, also maps per second from N threads sharing one Renderer against N
threads with a Renderer (a device) each, alternated with the serial loop; with --batch,
render_many against a loop of render.

    python python/examples/throughput.py [DEPTH_PNG] [--maps 100] [--threads 8] [--batch]

Default map: the shared Redwood map (../shared beside the repository), uint16 millimetres
with its published intrinsics. Needs numpy and Pillow. The numbers in BENCHMARKS.md come
from this script.
"""

import argparse
import pathlib
import sys
import time

import numpy as np
from PIL import Image

import obscura

ROOT = pathlib.Path(__file__).resolve().parents[2]
REDWOOD = ROOT.parent / "shared" / "depth" / "redwood" / "redwood_depth_mm.png"


def progress(phase, done, total):
    """One line on stderr, rewritten as a phase advances (the results go to stdout)."""
    sys.stderr.write(f"\r  {phase}: {done}/{total}" + ("\n" if done == total else ""))
    sys.stderr.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("depth", type=pathlib.Path, nargs="?", default=REDWOOD)
    ap.add_argument("--maps", type=int, default=100)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--batch", action="store_true", help="render_many against a loop of render")
    args = ap.parse_args()
    with Image.open(args.depth) as im:
        depth = np.array(im).astype(np.uint16)
    h, w = depth.shape
    k = dict(fx=525.0, fy=525.0, cx=(w - 1) / 2, cy=(h - 1) / 2)

    start = time.perf_counter()
    obscura.ambient_occlusion(depth, **k)
    print(f"one-shot ambient_occlusion (device, passes, one map): {time.perf_counter() - start:.2f} s")
    for noise in ["auto", "none"]:
        renderer = obscura.Renderer()
        for _ in range(3):  # warm-up
            renderer.render(depth, **k, depth_noise=noise)
        times = []
        start = time.perf_counter()
        for i in range(args.maps):
            t = time.perf_counter()
            renderer.render(depth, **k, depth_noise=noise)
            times.append(time.perf_counter() - t)
            if (i + 1) % 10 == 0 or i + 1 == args.maps:
                progress(f"depth_noise={noise!r}", i + 1, args.maps)
        total = time.perf_counter() - start
        print(
            f"depth_noise={noise!r}: {args.maps} maps of {w}x{h} in {total:.2f} s, "
            f"{args.maps / total:.2f} maps/s, median {1e3 * np.median(times):.1f} ms per map"
        )
    print(f"adapter: {renderer.adapter}")
    if args.threads:
        threads(depth, k, args.maps, args.threads)
    if args.batch:
        batch(depth, k, args.maps)


def batch(depth, k, maps, rounds=3):
    """Maps per second: a loop of `render` against one `render_many` over the same maps
    (each a slightly different copy, so no two are alike), alternated `rounds` times."""
    r = obscura.Renderer()
    stack = np.stack([depth + i for i in range(maps)]).astype(np.uint16)
    r.render(stack[0], **k)  # warm-up
    ways = {
        "render in a loop": lambda: [r.render(m, **k) for m in stack],
        "render_many": lambda: r.render_many(stack, **k),
    }
    rates = {name: [] for name in ways}
    for i in range(rounds):
        for j, (name, run) in enumerate(ways.items()):
            start = time.perf_counter()
            run()
            rates[name].append(maps / (time.perf_counter() - start))
            progress("batch rounds", i * len(ways) + j + 1, rounds * len(ways))
    for name, rate in rates.items():
        print(f"{name}: {np.median(rate):.2f} maps/s (median of {rounds})")


def threads(depth, k, maps, n, rounds=3):
    """Maps per second: serial on one Renderer, n threads sharing it, n threads with one
    Renderer each (made before the clock starts); the three alternated, `rounds` times,
    medians printed."""
    from concurrent.futures import ThreadPoolExecutor

    shared = obscura.Renderer()
    own = [obscura.Renderer() for _ in range(n)]
    for r in [shared, *own]:
        r.render(depth, **k)  # warm-up
    each = max(1, maps // n)
    maps = each * n
    ways = {
        "serial, one Renderer": lambda pool: [shared.render(depth, **k) for _ in range(maps)],
        f"{n} threads, one shared Renderer": lambda pool: list(
            pool.map(lambda i: [shared.render(depth, **k) for _ in range(each)], range(n))
        ),
        f"{n} threads, a Renderer each": lambda pool: list(
            pool.map(lambda i: [own[i].render(depth, **k) for _ in range(each)], range(n))
        ),
    }
    rates = {name: [] for name in ways}
    with ThreadPoolExecutor(n) as pool:
        for i in range(rounds):
            for j, (name, run) in enumerate(ways.items()):
                start = time.perf_counter()
                run(pool)
                rates[name].append(maps / (time.perf_counter() - start))
                progress("thread rounds", i * len(ways) + j + 1, rounds * len(ways))
    for name, r in rates.items():
        print(f"{name}: {np.median(r):.2f} maps/s (median of {rounds})")


if __name__ == "__main__":
    main()
