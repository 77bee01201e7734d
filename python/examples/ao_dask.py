"""AO for every depth map in a folder on a Dask cluster, with progress; reruns skip the
outputs that are complete, and maps that fail are listed at the end.

    python python/examples/ao_dask.py DEPTH_DIR OUT_DIR --intrinsics data/intrinsics/redwood.json \\
        [--workers 2 | --scheduler tcp://host:8786] [--output .npy|.exr|.png] [--preset high]

Needs `pip install "./python[dask]"` (dask[distributed] and Pillow).
"""

import argparse
import sys

from obscura.dask import ao_files


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("depth_dir")
    ap.add_argument("out_dir")
    ap.add_argument("--intrinsics", required=True, help="the JSON `obscura render --depth` reads")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster workers (threads, one device each)")
    ap.add_argument("--scheduler", default=None, help="a running scheduler's address instead")
    ap.add_argument("--output", default=".npy", choices=[".npy", ".exr", ".png"])
    ap.add_argument("--preset", default="high", choices=["low", "medium", "high", "ultra"])
    ap.add_argument("--radius", type=float, default=None, help="scene units (default: 3%% of each map's extent)")
    args = ap.parse_args()
    try:
        report = ao_files(args.depth_dir, args.out_dir, intrinsics=args.intrinsics,
                          output=args.output, scheduler=args.scheduler, workers=args.workers,
                          radius=args.radius, preset=args.preset)
    except (ValueError, OSError) as e:
        sys.exit(f"error: {e}")
    print(report, file=sys.stderr)
    if report.failed:
        sys.exit(1)


if __name__ == "__main__":
    main()
