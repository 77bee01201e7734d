"""The peers table: mean error over the shared views of each peer's images and of obscura's
variants on its quality-versus-time frontier (and its default), from one `obscura eval
--score-images` JSON, with each peer's own timing (times.json beside its images) and the
cost ratio at equal error.

    python3 peers/table.py EVAL_JSON PEER_DIR...
"""

import json
import pathlib
import sys
from collections import defaultdict


def main():
    records = json.loads(pathlib.Path(sys.argv[1]).read_text())["records"]
    peer_dirs = [pathlib.Path(d) for d in sys.argv[2:]]
    by = defaultdict(list)
    for r in records:
        by[r["variant"]].append(r)

    def mean(rows, key):
        values = [r[key] for r in rows if r.get(key) is not None]
        return sum(values) / len(values) if values else None

    ours = {name: rows for name, rows in by.items() if rows[0]["estimator"] == "gtao"}
    rows = []
    for name, rs in ours.items():
        rows.append((name, mean(rs, "rmse"), mean(rs, "bias"), mean(rs, "band_rmse"),
                     mean(rs, "median_ms")))
    for d in peer_dirs:
        name = f"image {d.name}"
        if name not in by:
            sys.exit(f"no rows for {name} in {sys.argv[1]}")
        times = json.loads((d / "times.json").read_text())["views"]
        ms = sum(t["ssao_ms"] for t in times.values()) / len(times)
        rs = by[name]
        rows.append((f"VTK vtkSSAOPass, kernel {d.name.split('-k')[-1]}", mean(rs, "rmse"),
                     mean(rs, "bias"), mean(rs, "band_rmse"), ms))
    # obscura's rows: its frontier (no faster variant is more accurate) and the default.
    timed = [(n, r, m) for n, r, _, _, m in rows if n in ours and m is not None]
    front = {n for n, r, m in timed
             if not any(m2 < m and r2 < r for n2, r2, m2 in timed if n2 != n)}
    default = "gtao deinterleaved2 high full spatial"
    rows = [row for row in rows if row[0] not in ours or row[0] in front or row[0] == default]
    print("| AO | RMSE | bias | band RMSE | AO ms per frame (llvmpipe: Vulkan for obscura, OpenGL for VTK) | the fastest obscura variant at ≤ this RMSE: its time ÷ this one's |")
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


if __name__ == "__main__":
    main()
