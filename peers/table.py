"""The peers table: mean error over the shared views of each peer's images and of obscura's
variants on its quality-versus-time frontier (and its default), from `obscura eval
--score-images` JSON, with each peer's own timing (times-rN.json, or times.json, beside
its images) and the cost ratio at equal error.

    python3 peers/table.py EVAL_JSON[,EVAL_JSON...] PEER_DIR...

With several eval JSONs (alternated timing rounds, peers/run.sh), each variant's time is
its median over the rounds, each peer's over its times-rN.json; the errors are the first
JSON's (every round scores the same images). Each round's ratio of each peer's default
(VTK's kernel 32, Bevy's high) to obscura's default follows the table.

A peer's folder name says what it is: `vtk-kN` (vtkSSAOPass, kernel N), `bevy-QUALITY`
(Bevy's ScreenSpaceAmbientOcclusion at that quality level), `obscura-bevy-PRESET` (obscura
through its Bevy plugin at that preset, in the same app as Bevy's SSAO).
"""

import json
import pathlib
import statistics
import sys
from collections import defaultdict


DEFAULT = "gtao deinterleaved2 high full spatial"
# Each peer's own default, by folder name.
PEER_DEFAULTS = {"vtk-k32": "VTK kernel 32", "bevy-high": "Bevy high"}


def peer_name(d):
    """The table's name of a peer folder (see the module's text)."""
    if d.name.startswith("obscura-bevy-"):
        return f"obscura in Bevy (plugin), {d.name.removeprefix('obscura-bevy-')}"
    kind, _, setting = d.name.partition("-")
    if kind == "vtk":
        return f"VTK vtkSSAOPass, kernel {setting.removeprefix('k')}"
    if kind == "bevy":
        t = json.loads(next(iter(sorted(d.glob("times*.json")))).read_text())
        return f"Bevy {t.get('bevy', '')} SSAO, {setting}".replace("  ", " ")
    return d.name


def mean(rows, key):
    values = [r[key] for r in rows if r.get(key) is not None]
    return sum(values) / len(values) if values else None


def peer_times(d):
    """Each round's mean over the views of the peer's AO time (times-rN.json by N, or the
    one times.json)."""
    files = sorted(d.glob("times-r*.json"), key=lambda p: int(p.stem.split("-r")[-1]))
    files = files or [d / "times.json"]
    out = []
    for f in files:
        views = json.loads(f.read_text())["views"]
        out.append(sum(t["ssao_ms"] for t in views.values()) / len(views))
    return out


def main():
    rounds = [json.loads(pathlib.Path(p).read_text())["records"] for p in sys.argv[1].split(",")]
    records = rounds[0]
    peer_dirs = [pathlib.Path(d) for d in sys.argv[2:]]
    by = defaultdict(list)
    for r in records:
        by[r["variant"]].append(r)
    # Each variant's mean time in each round.
    round_ms = []
    for recs in rounds:
        b = defaultdict(list)
        for r in recs:
            b[r["variant"]].append(r)
        round_ms.append({n: mean(rs, "median_ms") for n, rs in b.items()})

    ours = {name: rows for name, rows in by.items() if rows[0]["estimator"] == "gtao"}
    rows = []
    for name, rs in ours.items():
        ms = [m[name] for m in round_ms if m.get(name) is not None]
        rows.append((name, mean(rs, "rmse"), mean(rs, "bias"), mean(rs, "band_rmse"),
                     statistics.median(ms) if ms else None))
    for d in peer_dirs:
        name = f"image {d.name}"
        if name not in by:
            sys.exit(f"no rows for {name} in {sys.argv[1]}")
        ms = statistics.median(peer_times(d))
        rs = by[name]
        rows.append((peer_name(d), mean(rs, "rmse"),
                     mean(rs, "bias"), mean(rs, "band_rmse"), ms))
    # obscura's rows: its frontier (no faster variant is more accurate) and the default.
    timed = [(n, r, m) for n, r, _, _, m in rows if n in ours and m is not None]
    front = {n for n, r, m in timed
             if not any(m2 < m and r2 < r for n2, r2, m2 in timed if n2 != n)}
    rows = [row for row in rows if row[0] not in ours or row[0] in front or row[0] == DEFAULT]
    print("| AO | RMSE | bias | band RMSE | AO ms per frame (llvmpipe: Vulkan for obscura and Bevy, OpenGL for VTK) | the fastest obscura variant at ≤ this RMSE: its time ÷ this one's |")
    print("|---|---|---|---|---|---|")
    for name, rmse, bias, band, ms in sorted(rows, key=lambda r: r[1]):
        # The fastest obscura variant at least as accurate, and how much faster it is.
        better = [(o_ms, o) for o, o_rmse, _, _, o_ms in rows
                  if o in ours and o_rmse <= rmse and o_ms is not None]
        if name in ours or not better:
            equal = "–"
        else:
            o_ms, o = min(better)
            equal = f"{o}: {o_ms / ms:.2f}×"
        print(f"| {name} | {rmse:.4f} | {bias:+.4f} | {band:.4f} | {ms:.1f} | {equal} |")
    # Each round's peer default against obscura's default, timed back to back.
    ours_ms = [m.get(DEFAULT) for m in round_ms]
    for d in peer_dirs:
        if len(rounds) < 2 or d.name not in PEER_DEFAULTS:
            continue
        peer = peer_times(d)
        ratios = [f"{p / o:.2f}" for p, o in zip(peer, ours_ms) if o]
        print(f"\n{PEER_DEFAULTS[d.name]} ÷ obscura's default, round by round: {', '.join(ratios)} "
              f"({', '.join(f'{p:.1f}' for p in peer)} ms; obscura "
              f"{', '.join(f'{o:.1f}' for o in ours_ms if o)} ms)")

if __name__ == "__main__":
    main()
