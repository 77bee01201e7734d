"""Replays lavapipe's recorded frame noise through the scale controller (docs/budget.md,
"The noise floor, replayed"). Standard library only: `python3 docs/budget/noise/replay.py`.

Each CSV here is one pinned-scale Sponza orbit (`obscura render ... --budget-control scale
--budget-ms 100000` for scale 1, `--budget-ms 1` for scale 1/4; 2026-11-25, a866ae1,
llvmpipe, 2 cores). A frame's noise is its time over the median of the nine frames around
it (frames 2..100). The controller below transcribes `obscura::budget::ScaleController::update`
(integral on ln s², gain, dead band); `outliers=True` adds the Hampel-type skip that was
tried and not kept.
"""

import csv
import math
import pathlib
import statistics

HERE = pathlib.Path(__file__).parent
BUDGET = 25.0
FLOOR, FULL = 8.0, 44.0  # the orbit's cost: FLOOR + FULL * s^2 ms
MIN_AREA = 1.0 / 16.0
DEAD_BAND = 0.03


def noise(path):
    ms = [float(r["ms"]) for r in csv.DictReader(open(path))][2:]
    return [ms[i] / statistics.median(ms[max(0, i - 4) : i + 5]) for i in range(len(ms))]


def replay(nz, gain, swing, outliers=False):
    area, recent, held = 0.25, [], 0
    for k, n in enumerate(nz):
        scene = 1.0 + swing * math.sin(2.0 * math.pi * k / 98.0)
        t = (FLOOR + FULL * area) * scene * n
        if k >= 10:
            held += abs(t / BUDGET - 1.0) <= 0.15
        now = (math.log(t), math.log(area))
        skip = False
        if outliers and recent:
            offs = []
            for lt, lx in recent:
                lo, hi = min(0.0, now[1] - lx), max(0.0, now[1] - lx)
                d = now[0] - lt
                offs.append(d - min(max(d, lo), hi))
            skip = abs(statistics.median(offs)) > math.log1p(0.2)
        recent = (recent + [now])[-3:]
        e = math.log(BUDGET / t)
        if not skip and abs(e) > DEAD_BAND:
            area = min(1.0, max(MIN_AREA, area * math.exp(gain * e)))
    return held


def main():
    gains = (0.1, 0.25, 0.5, 1.0, 1.5)
    print("frames 10..98 within ±15% of", BUDGET, "ms, of 88")
    print("sequence | no tracking error | gain", "/".join(map(str, gains)),
          "still | same, view ±25% | outlier skip, still | jumps > 1.15/0.85")
    for path in sorted(HERE.glob("*.csv")):
        nz = noise(path)
        ms = [float(r["ms"]) for r in csv.DictReader(open(path))][2:]
        jumps = sum(1 for a, b in zip(ms, ms[1:]) if max(a, b) / min(a, b) > 1.15 / 0.85)
        ideal = sum(abs(n - 1.0) <= 0.15 for n in nz[10:])
        still = "/".join(str(replay(nz, g, 0.0)) for g in gains)
        swing = "/".join(str(replay(nz, g, 0.25)) for g in gains)
        skip = replay(nz, 0.5, 0.0, outliers=True)
        print(f"{path.stem} | {ideal} | {still} | {swing} | {skip} | {jumps}")


if __name__ == "__main__":
    main()
