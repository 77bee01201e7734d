"""AO of many depth files on a Dask cluster: a `LocalCluster` by default, or any scheduler.

    from obscura.dask import ao_files
    report = ao_files("scans/", "ao/", intrinsics="data/intrinsics/redwood.json")

Each worker (a thread by default, so a plain script needs no `if __name__ == "__main__":`;
`processes=True` for processes) keeps one `obscura.Renderer` (a worker plugin), so its
device opens and its passes compile once. Outputs are written atomically (`obscura.save_ao`), so a file that
exists is complete and a rerun skips it. A map that fails is reported with its error and
never stops the run. Needs `dask[distributed]`; depth PNGs need Pillow.

Depth files: 16-bit PNG or uint16 .npy in depth units (times the intrinsics'
`depth_scale`, default 0.001), float .npy in scene units, as `obscura render --depth`
reads them.
"""

from __future__ import annotations

import dataclasses
import json
import os
import pathlib
import sys
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from distributed import Client, LocalCluster, WorkerPlugin, as_completed, get_worker

import obscura

DEPTH_SUFFIXES = (".png", ".npy")
OUTPUT_SUFFIXES = (".npy", ".exr", ".png")
_PLUGIN = "obscura-renderer"

PathLike = Union[str, "os.PathLike[str]"]


@dataclasses.dataclass
class Report:
    """What a run did: outputs written, skipped (already complete) and failed (file,
    error); `seconds` from the first map submitted to the last done, `startup_seconds` for
    the cluster and the workers' renderers before it."""

    written: List[str]
    skipped: List[str]
    failed: List[Tuple[str, str]]
    seconds: float
    startup_seconds: float

    def __str__(self) -> str:
        done = len(self.written) + len(self.failed)
        rate = done / self.seconds if self.seconds > 0 else 0.0
        lines = [
            f"{len(self.written)} written, {len(self.skipped)} skipped (complete), "
            f"{len(self.failed)} failed in {self.seconds:.1f} s ({rate:.2f} maps/s; "
            f"{self.startup_seconds:.1f} s to start)"
        ]
        lines += [f"  {path}: {error}" for path, error in self.failed]
        return "\n".join(lines)


class RendererPlugin(WorkerPlugin):
    """One `obscura.Renderer` per worker, made when the worker starts (or joins)."""

    def __init__(self, options: Dict[str, Any]):
        self.options = dict(options)

    def setup(self, worker) -> None:
        worker.obscura_renderer = obscura.Renderer(**self.options)


def load_depth(path: PathLike) -> np.ndarray:
    """A depth file as the array `Renderer.render` takes: .npy as saved, a PNG as uint16."""
    path = pathlib.Path(path)
    if path.suffix.lower() == ".npy":
        with open(path, "rb") as f:
            if f.read(6) != b"\x93NUMPY":
                raise ValueError(f"{path.name}: not a NumPy .npy file (no .npy header)")
        try:
            return np.load(path, allow_pickle=False)
        except ValueError as e:  # a header numpy cannot read, or object arrays
            raise ValueError(f"{path.name}: not a depth array .npy ({e})") from None
    from PIL import Image, UnidentifiedImageError

    try:
        im = Image.open(path)
    except UnidentifiedImageError:
        raise ValueError(f"{path.name}: not a PNG image") from None
    with im:
        if im.mode not in ("I;16", "I;16B", "I;16L", "I"):
            raise ValueError(f"a depth PNG is 16-bit single-channel, not mode {im.mode}")
        return np.array(im).astype(np.uint16)


def _intrinsics(intrinsics: Union[PathLike, Dict[str, float]]) -> Dict[str, float]:
    if isinstance(intrinsics, dict):
        k = dict(intrinsics)
    else:
        k = json.loads(pathlib.Path(intrinsics).read_text())
    if not isinstance(k, dict):
        raise ValueError("intrinsics: expected an object {fx, fy, cx, cy[, width, height, depth_scale]}")
    missing = [key for key in ("fx", "fy", "cx", "cy") if key not in k]
    if missing:
        raise ValueError(f"intrinsics lack {', '.join(missing)}")
    for key, kind in [("fx", float), ("fy", float), ("cx", float), ("cy", float),
                      ("width", int), ("height", int), ("depth_scale", float)]:
        if key in k and (isinstance(k[key], bool) or not isinstance(k[key], (int, float))
                         or kind is int and not float(k[key]).is_integer()):
            raise ValueError(f"intrinsics `{key}` = {k[key]!r}: expected a number"
                             + (" of pixels" if kind is int else ""))
    if ("width" in k) != ("height" in k):
        raise ValueError("intrinsics give one of width and height; give both or neither")
    return k


_RENDERER_OPTIONS = ("estimator", "preset", "resolution", "denoise", "frames")


def _check(k: Dict[str, float], radius, depth_noise, thickness, options: Dict[str, Any]) -> None:
    """Every setting the maps share, checked before a folder is made or a cluster started
    (`obscura.check_settings`: `render`'s messages)."""
    unknown = sorted(set(options) - set(_RENDERER_OPTIONS))
    if unknown:
        raise TypeError(f"ao_files: unknown renderer option(s) {', '.join(unknown)}; "
                        f"Renderer takes {', '.join(_RENDERER_OPTIONS)}")
    size = {"width": int(k["width"]), "height": int(k["height"])} if "width" in k else {}
    obscura._obscura.check_settings(
        fx=float(k["fx"]), fy=float(k["fy"]), cx=float(k["cx"]), cy=float(k["cy"]), **size,
        radius=radius, depth_scale=k.get("depth_scale"), depth_noise=depth_noise,
        thickness=thickness, **options)


def _render_one(source: str, target: str, k: Dict[str, float], radius: Optional[float],
                depth_noise: Any, thickness: Optional[float]) -> Tuple[str, Optional[str]]:
    """On a worker: the AO of `source` written to `target`; (source, error or None)."""
    try:
        depth = load_depth(source)
        if "width" in k and "height" in k and depth.shape[:2] != (k["height"], k["width"]):
            raise ValueError(
                f"the depth map is {depth.shape[1]}x{depth.shape[0]} but the intrinsics say "
                f"{k['width']}x{k['height']}"
            )
        # As `obscura render --depth`: the intrinsics' scale applies to integer maps only.
        scale = k.get("depth_scale", 0.001) if depth.dtype == np.uint16 else None
        renderer = get_worker().obscura_renderer
        ao = renderer.render(depth, fx=k["fx"], fy=k["fy"], cx=k["cx"], cy=k["cy"],
                             radius=radius, depth_scale=scale, depth_noise=depth_noise,
                             thickness=thickness)
        obscura.save_ao(target, ao)
        return source, None
    except Exception as e:  # every failure is this file's, reported, never the run's
        return source, f"{type(e).__name__}: {e}"


def _sources(files: Union[PathLike, Sequence[PathLike]]) -> List[pathlib.Path]:
    if isinstance(files, (str, os.PathLike)) and pathlib.Path(files).is_dir():
        found = sorted(p for p in pathlib.Path(files).iterdir()
                       if p.suffix.lower() in DEPTH_SUFFIXES)
        if not found:
            raise ValueError(f"no .png or .npy depth maps in {files}")
        return found
    if isinstance(files, (str, os.PathLike)):
        raise ValueError(f"{files}: not a folder (give a folder or a list of files)")
    found = [pathlib.Path(f) for f in files]
    if not found:
        raise ValueError("no depth files given")
    return found


def _progress(done: int, total: int, started: float, stream) -> None:
    width = 30
    filled = width * done // max(total, 1)
    rate = done / max(time.perf_counter() - started, 1e-9)
    stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} {rate:.2f} maps/s")
    stream.flush()


def ao_files(
    files: Union[PathLike, Sequence[PathLike]],
    out_dir: PathLike,
    *,
    intrinsics: Union[PathLike, Dict[str, float]],
    output: str = ".npy",
    scheduler: Union[None, str, Client] = None,
    workers: int = 2,
    processes: bool = False,
    radius: Optional[float] = None,
    depth_noise: Any = None,
    thickness: Optional[float] = None,
    progress: bool = True,
    **renderer_options: Any,
) -> Report:
    """The AO of each depth file (a folder's .png and .npy maps, or a list of files),
    written to `out_dir` as `<stem>_ao<output>` (".npy", ".exr" or 16-bit ".png").

    Args:
        intrinsics: {fx, fy, cx, cy[, width, height, depth_scale]} or the JSON file that
            `obscura render --depth --intrinsics` reads; shared by every map.
        scheduler: None for a `LocalCluster` of `workers` workers (one device each), a
            scheduler address ("tcp://host:8786"), or a `Client`.
        processes: the `LocalCluster`'s workers as processes instead of threads. Threads
            (the default) work from a plain script and start in a fraction of a second;
            the devices release the GIL while they render, so both do about as many maps
            a second. Processes need the call under `if __name__ == "__main__":`.
        radius, depth_noise, thickness: as `Renderer.render`.
        progress: a progress line on stderr.
        renderer_options: `Renderer`'s (estimator, preset, resolution, denoise, frames).

    Outputs that exist are complete (written atomically) and are skipped. Each map that
    fails is in `Report.failed` with its error; the others are written.
    """
    # Everything the maps share is checked before a folder is made or a cluster started.
    if output not in OUTPUT_SUFFIXES:
        raise ValueError(f"output {output!r}: expected one of {', '.join(OUTPUT_SUFFIXES)}")
    if scheduler is None and (isinstance(workers, bool) or not isinstance(workers, int)
                              or workers < 1):
        raise ValueError(f"workers = {workers!r}: a LocalCluster needs an integer >= 1")
    k = _intrinsics(intrinsics)
    _check(k, radius, depth_noise, thickness, renderer_options)
    sources = _sources(files)
    out = pathlib.Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{out}: exists and is not a folder")
    made = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    targets = [out / f"{s.stem}_ao{output}" for s in sources]
    todo = [(str(s), str(t)) for s, t in zip(sources, targets) if not t.exists()]
    skipped = [str(s) for s, t in zip(sources, targets) if t.exists()]

    try:
        return _run(todo, skipped, k, scheduler, workers, processes, radius, depth_noise,
                    thickness, progress, renderer_options)
    except BaseException:
        # Nothing written: leave no empty folder behind (a failed cluster, an interrupt).
        if made and not any(out.iterdir()):
            out.rmdir()
        raise


def _run(todo, skipped, k, scheduler, workers, processes, radius, depth_noise, thickness,
         progress, renderer_options) -> Report:
    """`ao_files` once its settings are checked and its folder exists."""
    begun = time.perf_counter()
    written: List[str] = []
    failed: List[Tuple[str, str]] = []
    cluster = None
    if scheduler is None:
        try:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1,
                                   processes=processes, dashboard_address=None)
        except RuntimeError as e:
            if not processes:
                raise
            raise RuntimeError(
                f"{e} With processes=True, Dask starts worker processes that import the "
                "main script again: call ao_files under `if __name__ == \"__main__\":`, or "
                "leave processes=False (worker threads, each with its own device)"
            ) from e
        client = Client(cluster)
    elif isinstance(scheduler, Client):
        client = scheduler
    else:
        client = Client(scheduler)
    try:
        client.register_plugin(RendererPlugin(renderer_options), name=_PLUGIN)
        started = time.perf_counter()
        futures = [client.submit(_render_one, s, t, k, radius, depth_noise, thickness,
                                 pure=False) for s, t in todo]
        if progress:
            _progress(0, len(todo), started, sys.stderr)
        for i, future in enumerate(as_completed(futures), start=1):
            source, error = future.result()
            if error is None:
                written.append(source)
            else:
                failed.append((source, error))
            if progress:
                _progress(i, len(todo), started, sys.stderr)
        if progress:
            sys.stderr.write("\n")
    finally:
        if client is not scheduler:
            client.close()
        if cluster is not None:
            cluster.close()
    return Report(written=sorted(written), skipped=skipped, failed=sorted(failed),
                  seconds=time.perf_counter() - started, startup_seconds=started - begun)
