"""The docs cannot rot silently: every Python block of the README and of the guide runs as
written, pasted into a plain script (no `if __name__ == "__main__":`), in a folder holding
what the blocks read: a Redwood-sized depth map `depth.npy`, a folder `scans/` of maps, and
the repository's `data/`; and every relative link in the README and docs/ reaches a file
and, where it names one, a heading. (The Rust blocks are doctests of the obscura crate.)"""

import os
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def blocks():
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for m in BLOCK.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            yield pytest.param(m.group(1), id=f"{page.relative_to(ROOT)}:{line}")


def room(size=(480, 640), far=3.0):
    """Metres seen by Redwood's 640×480 camera (fx = fy = 525): a floor, a back wall and a
    box standing on the floor, so the AO has corners to find."""
    h, w = size
    v, u = np.mgrid[0:h, 0:w].astype(np.float32)
    y = (v - (h - 1) / 2) / 525.0  # ray slope, down
    floor = np.where(y > 0.05, 1.2 / np.maximum(y, 1e-3), np.inf)
    depth = np.minimum(floor, far).astype(np.float32)
    box = (np.abs(u - w / 2) < 80) & (v > h * 0.55) & (v < h * 0.8)
    depth[box] = np.minimum(depth[box], far * 0.7)
    return depth


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("docs")
    np.save(d / "depth.npy", room())
    (d / "scans").mkdir()
    for i in range(2):
        mm = (room(far=2.5 + 0.5 * i) * 1000).astype(np.uint16)  # Redwood's millimetres
        np.save(d / "scans" / f"scan{i}.npy", mm)
    (d / "data").symlink_to(ROOT / "data")
    return d


def test_the_pages_have_python_blocks():
    assert len(list(blocks())) >= 2


@pytest.mark.parametrize("code", list(blocks()))
def test_block_runs_as_a_plain_script(code, folder):
    script = folder / "block.py"
    script.write_text(code, encoding="utf-8")
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    run = subprocess.run([sys.executable, str(script)], cwd=folder, env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"stdout:\n{run.stdout}\nstderr:\n{run.stderr}"


def heading_anchors(page):
    """GitHub's anchors of a markdown page's headings (outside code blocks)."""
    anchors, seen, fenced = set(), {}, False
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
        m = None if fenced else re.match(r"#+ (.*)", line)
        if m:
            slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            anchors.add(slug if n == 0 else f"{slug}-{n}")
    return anchors


def test_every_relative_link_reaches_its_file_and_heading():
    pages = [ROOT / "README.md", ROOT / "BENCHMARKS.md", ROOT / "ARCHITECTURE.md",
             *sorted((ROOT / "docs").rglob("*.md"))]
    broken = []
    for page in pages:
        for link in re.findall(r"\]\(([^)\s]+)\)", page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", link):
                continue
            path, _, anchor = link.partition("#")
            target = (page.parent / path).resolve() if path else page
            if not target.exists():
                broken.append(f"{page.relative_to(ROOT)}: {link} (no such file)")
            elif anchor and target.suffix == ".md" and anchor not in heading_anchors(target):
                broken.append(f"{page.relative_to(ROOT)}: {link} (no such heading)")
    assert not broken, "\n".join(broken)
