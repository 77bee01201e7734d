"""Tests of the Python package against analytic answers, the CLI's float output and the
shared depth maps (../shared beside the repository, as for the Rust tests)."""

import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import obscura

ROOT = pathlib.Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared" / "depth"
MOTO = SHARED / "middlebury2014_motorcycle" / "depth_mm.png"
MOTO_K = dict(fx=994.978, fy=994.978, cx=311.193, cy=254.877)  # data/intrinsics/
REDWOOD = SHARED / "redwood" / "redwood_depth_mm.png"
REDWOOD_K = dict(fx=525.0, fy=525.0, cx=319.5, cy=239.5)


def png16(path):
    from PIL import Image

    with Image.open(path) as im:
        return np.array(im, dtype=np.uint16)


@pytest.fixture(scope="module")
def renderer():
    return obscura.Renderer()


def plane(size=128, depth=2.0):
    return np.full((size, size), depth, np.float32)


def valley(size=128, far=3.0):
    """Two walls at 45 degrees to the view meeting in a 90-degree crease at the centre
    column: view depth d = far - |X|, X = (u - cx) / fx * d."""
    t = np.abs((np.arange(size) - (size - 1) / 2) / size)
    row = far / (1.0 + t)
    return np.tile(row.astype(np.float32), (size, 1))


def centred(size=128):
    return dict(fx=float(size), fy=float(size), cx=(size - 1) / 2, cy=(size - 1) / 2)


def test_depth_maps_take_the_bitmask_by_default():
    """The package's default estimator is the library's for depth maps (the bitmask,
    obscura::DEPTH_MAP_ESTIMATOR): a strip before a wall renders the same with
    estimator="bitmask" and differently with "gtao", by function and by Renderer."""
    d = plane(depth=2.0)
    d[:, 60:66] = 1.8
    k = dict(centred(), radius=0.4)
    default = obscura.ambient_occlusion(d, **k)
    assert np.array_equal(default, obscura.ambient_occlusion(d, **k, estimator="bitmask"))
    gtao = obscura.ambient_occlusion(d, **k, estimator="gtao")
    # The same estimator gives the same AO bit for bit; the two differ by up to 0.0096 here
    # (High's 3 × 6 steps).
    assert np.abs(default - gtao).max() > 0.005
    assert np.array_equal(obscura.Renderer().render(d, **k), default)


def test_a_plane_is_unoccluded_and_a_crease_darkens(renderer):
    k = centred()
    ao_plane = renderer.render(plane(), **k, radius=0.2)
    assert ao_plane.dtype == np.float32 and ao_plane.shape == (128, 128)
    assert ao_plane.mean() > 0.99, ao_plane.mean()
    ao = renderer.render(valley(), **k, radius=0.2)
    crease = ao[16:-16, 60:68].mean()
    open_walls = np.concatenate([ao[16:-16, 8:24], ao[16:-16, -24:-8]]).mean()
    # A 90-degree crease sees half of the hemisphere's cosine-weighted sky at its line;
    # walls a radius away see all of it.
    assert crease < open_walls - 0.1, (crease, open_walls)
    assert open_walls > 0.95, open_walls


def test_dtypes_orders_and_strides_give_the_same_ao(renderer):
    k = centred()
    d = valley()
    want = renderer.render(d, **k, radius=0.2, depth_noise="none")
    for variant in [
        d.astype(np.float64),
        np.asfortranarray(d),
        np.asfortranarray(d.astype(np.float64)),
        np.repeat(d, 2, axis=1)[:, ::2],  # a strided view
    ]:
        got = renderer.render(variant, **k, radius=0.2, depth_noise="none")
        np.testing.assert_array_equal(got, want)
    # float16 rounds the depth; the AO stays close.
    got = renderer.render(d.astype(np.float16), **k, radius=0.2, depth_noise="none")
    assert np.abs(got - want).mean() < 0.01
    # uint16 millimetres with the default scale are the same metres.
    mm = np.round(d * 1000).astype(np.uint16)
    got = renderer.render(mm, **k, radius=0.2, depth_noise="none")
    # (the library scales in float32: units × 0.001)
    metres = mm.astype(np.float32) * np.float32(0.001)
    np.testing.assert_array_equal(got, renderer.render(metres, **k, radius=0.2, depth_noise="none"))


def test_accumulated_frames_are_reproducible():
    k = centred()
    r = obscura.Renderer(frames=4)
    first = r.render(valley(), **k, radius=0.2)
    np.testing.assert_array_equal(r.render(valley(), **k, radius=0.2), first)
    # Four rotated frames differ from one.
    one = obscura.Renderer().render(valley(), **k, radius=0.2)
    assert np.abs(first - one).max() > 1e-4


def test_given_normals_are_used():
    k = centred()
    # Normals of a wall facing the camera, in OpenCV axes (z into the scene: -1).
    n = np.zeros((128, 128, 3), np.float32)
    n[..., 2] = -1.0
    ao = obscura.ambient_occlusion(plane(), **k, normals=n, radius=0.2)
    assert ao.mean() > 0.99
    # A fourth channel, as the CLI's normal maps may have, is ignored.
    n4 = np.concatenate([n, np.full((128, 128, 1), 7.0, np.float32)], axis=2)
    np.testing.assert_array_equal(obscura.ambient_occlusion(plane(), **k, normals=n4, radius=0.2), ao)
    # The same normals read in OpenGL axes face away: a different, wrong picture, warned.
    with pytest.warns(UserWarning, match="face away"):
        wrong = obscura.ambient_occlusion(
            plane(), **k, normals=n, normals_frame="opengl", radius=0.2
        )
    assert np.abs(wrong - ao).max() > 0.05


def cli():
    """The CLI of this checkout: $OBSCURA_CLI (CI sets it to the binary its tests built),
    else built here (a no-op when up to date), so it is never a stale one."""
    if os.environ.get("OBSCURA_CLI"):
        return pathlib.Path(os.environ["OBSCURA_CLI"])
    subprocess.run(["cargo", "build", "-p", "obscura-cli", "--locked"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "obscura"


def test_middlebury_equals_the_cli_float_output(renderer):
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "moto.npy"
        subprocess.run(
            [
                str(cli()), "render", "--depth", str(MOTO),
                "--intrinsics", str(ROOT / "data" / "intrinsics" / "middlebury2014_motorcycle.json"),
                "--runs", "1", "--out", str(out),
            ],
            check=True,
            env=dict(os.environ, NODEVICE_SELECT="1"),
            capture_output=True,
        )
        want = np.load(out)
    got = renderer.render(png16(MOTO), **MOTO_K)
    assert got.shape == want.shape == (500, 741)
    assert np.abs(got - want).max() <= 1e-6


@pytest.mark.parametrize("path,k", [(MOTO, MOTO_K), (REDWOOD, REDWOOD_K)])
def test_shared_depth_maps_round_trip(renderer, path, k):
    depth = png16(path)
    ao = renderer.render(depth, **k)
    assert ao.shape == depth.shape and ao.dtype == np.float32
    assert np.isfinite(ao).all() and ao.min() >= 0.0 and ao.max() <= 1.0
    valid = depth > 0
    # Real rooms and objects have creases: some AO, not everywhere.
    assert 0.5 < ao[valid].mean() < 0.999
    assert (ao[~valid] == 1.0).all()


@pytest.mark.parametrize(
    "depth,k,says",
    [
        (np.full((8, 8), np.nan, np.float32), centred(8), "no valid depth"),
        (np.zeros((0, 5), np.float32), centred(5), "each side must be in"),
        (np.ones((8, 8, 2), np.float32), centred(8), "2-D"),
        (np.ones((8, 8), np.int32), centred(8), "not supported"),
        ([[1.0, 2.0], [3.0, 4.0]], centred(2), "numpy array"),
        (np.ones((8, 8), np.float32), dict(centred(8), cx=100.0), "outside"),
        (np.ones((8, 8), np.float32), dict(centred(8), fx=0.0), "fx"),
        (np.ones((8, 8), np.float32), dict(centred(8), fx=1e30), "field of view"),
        (np.ones((8, 8), np.float32), dict(centred(8), fy=1e-6), "field of view"),
        (np.where(np.eye(8) * np.eye(8)[3], 2.0, 0.0), centred(8), "span no extent"),
    ],
)
def test_bad_input_raises_value_error(renderer, depth, k, says):
    with pytest.raises(ValueError, match=says):
        renderer.render(depth, **k)
    with pytest.raises(ValueError, match=says):
        obscura.ambient_occlusion(depth, **k)


def test_bad_options_and_normals_raise_value_error(renderer):
    k = centred(8)
    d = np.ones((8, 8), np.float32)
    with pytest.raises(ValueError, match="the normals are 7x8 but the depth map is 8x8"):
        renderer.render(d, **k, normals=np.zeros((8, 7, 3), np.float32))
    with pytest.raises(ValueError, match="normals_frame"):
        renderer.render(d, **k, normals=np.zeros((8, 8, 3), np.float32), normals_frame="up")
    with pytest.raises(ValueError, match="3 numbers"):
        renderer.render(d, **k, depth_noise=(1.0, 2.0))
    with pytest.raises(ValueError, match="expected auto, none, kinect"):
        renderer.render(d, **k, depth_noise="loud")
    with pytest.raises(ValueError, match="radius"):
        renderer.render(d, **k, radius=-1.0)
    with pytest.raises(ValueError, match="depth_scale"):
        renderer.render(d, **k, depth_scale=0.0)
    with pytest.raises(ValueError, match="numpy array"):
        renderer.render(d, **k, normals=[[0.0, 0.0, -1.0]] * 64)
    # The library's rule, as `render --normals-file` applies it: normals of which none is
    # a vector are a broken array, not a request for normals from depth (that is None).
    for broken in [np.full((8, 8, 3), np.nan, np.float32), np.zeros((8, 8, 4), np.float32)]:
        with pytest.raises(ValueError, match="not one is a finite, non-zero vector"):
            renderer.render(d, **k, normals=broken)
    # Normals facing away from the camera: the CLI's warning, as a UserWarning.
    away = np.zeros((8, 8, 3), np.float32)
    away[..., 2] = 1.0  # OpenCV: z into the scene, so facing away
    with pytest.warns(UserWarning, match="face away from the camera"):
        renderer.render(d, **k, normals=away)
    bad_options = [
        dict(estimator="ssao"), dict(preset="max"), dict(resolution="double"),
        dict(frames=0), dict(frames=-1), dict(frames=10**6),
    ]
    for bad in bad_options:
        with pytest.raises(ValueError):
            obscura.Renderer(**bad)


def test_the_bitmask_thickness_prior_lightens_behind_a_thin_strip():
    """A strip 0.2 in front of a wall at 2: taken as infinitely deep it shadows the wall
    beside it like a fin; taken as 0.1 radius deep it blocks only the sectors between its
    front and back, so the wall beside it is brighter. The default prior (1 radius, 0.4)
    reaches past the wall, so it shadows the wall about as the infinite one does (within
    0.02; not darker or brighter by rule: its solids occlude with their part within the
    radius, even from fronts beyond it, which infinite thickness ignores), and no more
    than a thin one lets through. Bad priors are ValueErrors."""
    d = plane(depth=2.0)
    d[:, 60:66] = 1.8
    k = centred()
    r = obscura.Renderer(estimator="bitmask", denoise="none")
    thin = r.render(d, **k, radius=0.4, thickness=0.1)
    thick = r.render(d, **k, radius=0.4, thickness=float("inf"))
    wall = np.r_[48:60, 66:78]
    assert thick[32:96, wall].mean() < 0.9
    assert thin[32:96, wall].mean() > thick[32:96, wall].mean() + 0.05
    # The default prior is the library's (1 radius).
    default = r.render(d, **k, radius=0.4)
    assert thin[32:96, wall].mean() > default[32:96, wall].mean() + 0.05
    assert abs(default[32:96, wall].mean() - thick[32:96, wall].mean()) < 0.02
    for bad in [0.0, -1.0, float("nan")]:
        with pytest.raises(ValueError, match="thickness"):
            r.render(d, **k, thickness=bad)
        with pytest.raises(ValueError, match="thickness"):
            obscura.ambient_occlusion(d, **k, thickness=bad)


def test_no_adapter_is_a_device_error():
    old = os.environ.get("OBSCURA_ADAPTER")
    os.environ["OBSCURA_ADAPTER"] = "no-such-adapter-anywhere"
    try:
        with pytest.raises(obscura.DeviceError):
            obscura.Renderer()
    finally:
        if old is None:
            del os.environ["OBSCURA_ADAPTER"]
        else:
            os.environ["OBSCURA_ADAPTER"] = old
    assert issubclass(obscura.DeviceError, RuntimeError)


def test_the_gil_is_released_while_the_device_works(renderer):
    """Whether another thread runs during a render, decided by order, not by rates: with
    forced GIL switches turned off, a waiting thread gets the GIL only when the rendering
    thread lets it go. A render that releases it lets the probe run while the map is on
    the device; one that held it would let the probe run only after it returned."""
    import sys
    import threading

    depth = png16(REDWOOD)
    started, done = threading.Event(), threading.Event()
    seen = []

    def render():
        started.set()
        renderer.render(depth, **REDWOOD_K)
        done.set()

    def probe():
        started.wait()
        seen.append(done.is_set())

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    try:
        threads = [threading.Thread(target=render), threading.Thread(target=probe)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
    finally:
        sys.setswitchinterval(interval)
    assert done.is_set(), "the render finished"
    assert seen == [False], "the probe ran only after the render returned: the GIL was held"


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_a_thousand_calls_hold_memory_flat(renderer):
    k = centred(64)
    d = valley(64)
    for _ in range(100):
        renderer.render(d, **k, radius=0.2)
    before = rss_bytes()
    for _ in range(1000):
        renderer.render(d, **k, radius=0.2)
    grown = rss_bytes() - before
    # A leak of one 64x64 float AO image per call alone would be 16 MB.
    assert grown < 8 << 20, f"resident memory grew {grown / 2**20:.1f} MiB over 1000 calls"


def test_threads_share_one_renderer_with_serial_results():
    """Eight threads on one Renderer (a thread pool's use) give exactly the serial results:
    calls wait for the device in turn instead of raising 'Already borrowed'."""
    from concurrent.futures import ThreadPoolExecutor

    r = obscura.Renderer()
    maps = [valley(64, far=2.0 + 0.25 * i) for i in range(8)]
    k = centred(64)
    serial = [r.render(m, **k) for m in maps]
    with ThreadPoolExecutor(8) as pool:
        for _ in range(3):
            shared = list(pool.map(lambda m: r.render(m, **k), maps))
            for a, b in zip(shared, serial):
                np.testing.assert_array_equal(a, b)
    assert any(not np.array_equal(serial[0], s) for s in serial[1:]), "maps differ"


def quiet_probe(env_extra):
    """stderr of a fresh interpreter that imports obscura and opens a device, with no
    display server (XDG_RUNTIME_DIR unset) and `env_extra`, and what it saw of
    NODEVICE_SELECT."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("NODEVICE_SELECT", "XDG_RUNTIME_DIR", "OBSCURA_DEVICE_SELECT")}
    env.update(env_extra)
    code = "import os, obscura; obscura.Renderer(); print(os.environ.get('NODEVICE_SELECT'))"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stderr, out.stdout.strip()


def test_the_device_is_quiet_on_a_headless_machine():
    # Mesa's device-select layer prints "error: XDG_RUNTIME_DIR is invalid" twice per
    # device here (measured before the fix); obscura turns the layer off as the CLI does.
    err, seen = quiet_probe({})
    assert "XDG_RUNTIME_DIR" not in err and "error" not in err.lower(), err
    assert seen == "1"
    # OBSCURA_DEVICE_SELECT keeps the layer (and its messages) for diagnosis, and a
    # NODEVICE_SELECT the user set is left as it is.
    assert quiet_probe({"OBSCURA_DEVICE_SELECT": "1"})[1] == "None"
    assert quiet_probe({"NODEVICE_SELECT": "yes"})[1] == "yes"


def test_render_many_equals_render_on_each_map(renderer):
    """A stack, a list of mixed sizes (returned in order), per-map intrinsics and radii,
    per-map normals: each result equals `render` on that map exactly."""
    k = centred(64)
    stack = np.stack([valley(64, far=2.0 + 0.3 * i) for i in range(4)])
    many = renderer.render_many(stack, **k)
    assert many.shape == (4, 64, 64) and many.dtype == np.float32
    for m, a in zip(stack, many):
        np.testing.assert_array_equal(a, renderer.render(m, **k))
    # Mixed sizes and per-map intrinsics, interleaved so the grouping by size reorders.
    maps = [valley(64), plane(48, 1.5), valley(96, far=2.5), plane(48, 3.0), valley(64, 2.2)]
    fx = [64.0, 40.0, 96.0, 60.0, 70.0]
    cx = [(m.shape[1] - 1) / 2 for m in maps]
    cy = [(m.shape[0] - 1) / 2 for m in maps]
    radius = [0.3, 0.2, 0.4, 0.2, 0.3]
    got = renderer.render_many(maps, fx=fx, fy=fx, cx=cx, cy=cy, radius=radius)
    assert isinstance(got, list) and len(got) == len(maps)
    for i, (m, a) in enumerate(zip(maps, got)):
        want = renderer.render(m, fx=fx[i], fy=fx[i], cx=cx[i], cy=cy[i], radius=radius[i])
        np.testing.assert_array_equal(a, want)
    # Normals per map.
    n = np.zeros((64, 64, 3), np.float32)
    n[..., 2] = -1.0
    with_normals = renderer.render_many([valley(64), valley(64)], **k, normals=[n, None])
    np.testing.assert_array_equal(with_normals[0], renderer.render(valley(64), **k, normals=n))
    np.testing.assert_array_equal(with_normals[1], renderer.render(valley(64), **k))
    assert renderer.render_many([], **k) == []


def test_render_many_names_the_bad_map(renderer):
    k = centred(16)
    good = plane(16)
    cases = [
        (([good, good, np.full((16, 16), np.nan, np.float32)], k), "map 2: .*no valid depth"),
        (([good, [[1.0]]], k), "map 1: depth must be a numpy array"),
        (([good, good], dict(k, fx=[16.0])), "fx: 1 values for 2 maps"),
        (([good, good], dict(k, fy="wide")), "fy: expected a number or a sequence"),
        ((good, k), "render_many takes"),
        ((5, k), "maps: expected"),
        (([good, good], dict(k, normals=[None])), "normals: 1 arrays for 2 maps"),
    ]
    for (maps, kw), says in cases:
        with pytest.raises(ValueError, match=says):
            renderer.render_many(maps, **kw)


def test_an_empty_batch_checks_what_it_was_given(renderer):
    """No map to check per map: the intrinsics, the stack's dtype and the shared
    parameters are checked all the same, as for the first map of a full batch."""
    k = dict(fx=16.0, fy=16.0, cx=7.5, cy=7.5)
    stack = np.zeros((0, 16, 16), np.float32)
    cases = [
        (([], dict(k, fx=0.0)), "fx` = 0"),
        (([], dict(k, cy=float("nan"))), "cy` = NaN"),
        ((stack, dict(k, fx=0.0)), "fx` = 0"),
        ((stack, dict(k, fx=1e30)), "field of view"),
        ((np.zeros((0, 16, 16), np.complex64), k), "dtype complex64"),
        (([], dict(k, depth_scale=-1.0)), "depth_scale"),
        (([], dict(k, depth_noise="loud")), "depth noise `loud`"),
        (([], dict(k, thickness=0.0)), "thickness"),
        (([], dict(k, radius=float("inf"))), "radius"),
        (([], dict(k, fx=[16.0])), "fx: 1 values for 0 maps"),
    ]
    for (maps, kw), says in cases:
        with pytest.raises(ValueError, match=says):
            renderer.render_many(maps, **kw)
    # What is well formed stays an empty result.
    assert renderer.render_many([], **k) == []
    assert renderer.render_many(stack, **k).shape == (0, 16, 16)


def within(seconds, fn):
    """fn() on a daemon thread: its result or exception, or a failure after `seconds`
    instead of a hang."""
    import threading

    box = {}

    def run():
        try:
            box["value"] = fn()
        except BaseException as e:  # noqa: B902 - handed back to the caller
            box["error"] = e

    t = threading.Thread(target=run, daemon=True)
    t.start()
    t.join(seconds)
    assert not t.is_alive(), f"still running after {seconds} s"
    if "error" in box:
        raise box["error"]
    return box["value"]


def test_ao_files_refuses_bad_settings_before_it_starts(tmp_path):
    """Every shared setting is checked before a folder is made or a cluster started:
    a ValueError (TypeError for an unknown option) within seconds, nothing left behind;
    workers=0 used to wait forever for a worker."""
    pytest.importorskip("distributed")
    from obscura.dask import ao_files

    src = tmp_path / "depth"
    src.mkdir()
    np.save(src / "a.npy", plane(16))
    k = dict(fx=16.0, fy=16.0, cx=7.5, cy=7.5)
    cases = [
        (dict(workers=0), ValueError, "workers = 0"),
        (dict(workers=-1), ValueError, "workers = -1"),
        (dict(workers=1.5), ValueError, "workers = 1.5"),
        (dict(intrinsics=dict(k, fx=0.0)), ValueError, "fx` = 0"),
        (dict(intrinsics=dict(k, fx="wide")), ValueError, "fx` = 'wide'"),
        (dict(intrinsics=dict(k, width=16)), ValueError, "width and height"),
        (dict(intrinsics=dict(k, width=16, height=16, fx=1e30)), ValueError, "field of view"),
        (dict(estimator="nope"), ValueError, "estimator"),
        (dict(preset="max"), ValueError, "preset `max`"),
        (dict(frames=0), ValueError, "frames = 0"),
        (dict(depth_noise="loud"), ValueError, "depth noise `loud`"),
        (dict(thickness=-1.0), ValueError, "thickness"),
        (dict(radius=float("nan")), ValueError, "radius"),
        (dict(output=".tiff"), ValueError, "output '.tiff'"),
        (dict(files=[]), ValueError, "no depth files"),
        (dict(files=src / "a.npy"), ValueError, "not a folder"),
        (dict(colour="red"), TypeError, "unknown renderer option"),
    ]
    for kw, kind, says in cases:
        out = tmp_path / "out"
        args = dict(files=src, out_dir=out, intrinsics=k, workers=1, progress=False)
        args.update(kw)
        files, out_dir = args.pop("files"), args.pop("out_dir")
        with pytest.raises(kind, match=says):
            within(60, lambda: ao_files(files, out_dir, **args))
        assert not out.exists(), kw


def test_a_file_that_is_not_a_depth_map_is_reported_plainly(tmp_path):
    """Random bytes named .npy or .png fail that file with a plain message (not numpy's
    about pickled data), and the others are written."""
    pytest.importorskip("distributed")
    from obscura.dask import ao_files, load_depth

    src = tmp_path / "depth"
    src.mkdir()
    np.save(src / "good.npy", plane(16))
    (src / "noise.npy").write_bytes(bytes(range(256)) * 4)
    (src / "noise.png").write_bytes(bytes(range(256)) * 4)
    with pytest.raises(ValueError, match="noise.npy: not a NumPy .npy file"):
        load_depth(src / "noise.npy")
    k = dict(fx=16.0, fy=16.0, cx=7.5, cy=7.5)
    report = within(120, lambda: ao_files(src, tmp_path / "ao", intrinsics=k, workers=1,
                                          progress=False))
    assert [pathlib.Path(p).name for p in report.written] == ["good.npy"]
    failed = dict((pathlib.Path(p).name, e) for p, e in report.failed)
    assert "not a NumPy .npy file" in failed["noise.npy"], failed
    assert "not a PNG image" in failed["noise.png"], failed


def test_dask_writes_what_one_renderer_writes_and_reports_the_bad_file(tmp_path):
    """Two LocalCluster workers over maps made here: every output equals a single-process
    Renderer's exactly, in each format; a corrupt file is reported and skipped, the others
    written; a rerun skips every complete output."""
    pytest.importorskip("distributed")
    from PIL import Image

    from obscura.dask import ao_files, load_depth

    src = tmp_path / "depth"
    src.mkdir()
    k = dict(fx=48.0, fy=48.0, cx=31.5, cy=23.5, width=64, height=48, depth_scale=0.001)
    for i in range(5):
        mm = (valley(64, far=2.0 + 0.2 * i)[:48] * 1000).astype(np.uint16)
        if i % 2:
            np.save(src / f"map{i}.npy", mm.astype(np.float32) / 1000)  # metres
        else:
            Image.fromarray(mm).save(src / f"map{i}.png")  # millimetres, 16-bit
    (src / "broken.png").write_bytes(b"\x89PNG not really")
    out = tmp_path / "ao"
    report = ao_files(src, out, intrinsics=k, workers=2, output=".npy", progress=False)
    assert sorted(pathlib.Path(p).name for p in report.written) == [
        f"map{i}{'.npy' if i % 2 else '.png'}" for i in range(5)
    ]
    assert [pathlib.Path(p).name for p, _ in report.failed] == ["broken.png"]
    assert report.skipped == []
    r = obscura.Renderer()
    for i in range(5):
        depth = load_depth(next(src.glob(f"map{i}.*")))
        scale = 0.001 if depth.dtype == np.uint16 else None
        want = r.render(depth, fx=48.0, fy=48.0, cx=31.5, cy=23.5, depth_scale=scale)
        np.testing.assert_array_equal(np.load(out / f"map{i}_ao.npy"), want)
    # A rerun skips the complete outputs and tries the broken file again.
    # Worker processes (the file is imported, not run, so no main guard is needed here).
    again = ao_files(src, out, intrinsics=k, workers=1, processes=True, progress=False)
    assert len(again.skipped) == 5 and again.written == [] and len(again.failed) == 1
    # The other formats: 16-bit PNG and EXR hold the same AO (PNG within half a step).
    for suffix in [".png", ".exr"]:
        fmt = ao_files([src / "map0.png"], out, intrinsics=k, output=suffix, workers=1,
                       progress=False)
        assert len(fmt.written) == 1, fmt
    want = np.load(out / "map0_ao.npy")
    with Image.open(out / "map0_ao.png") as im:
        assert im.mode.startswith("I;16")
        png = np.array(im).astype(np.float32) / 65535
    assert np.abs(png - want).max() <= 0.5 / 65535 + 1e-7
    assert (out / "map0_ao.exr").read_bytes()[:4] == b"\x76\x2f\x31\x01"  # EXR magic
    # No partial files are left behind.
    assert not list(out.glob("*.partial"))
    # Bad Renderer options fail the run at once, with the Renderer's message.
    with pytest.raises(ValueError, match="preset `max`"):
        ao_files(src, tmp_path / "none", intrinsics=k, workers=1, preset="max", progress=False)


def test_save_ao_refuses_what_it_cannot_write(tmp_path):
    ao = np.ones((4, 4), np.float32)
    with pytest.raises(ValueError, match="expected .npy, .exr or .png"):
        obscura.save_ao(tmp_path / "ao.tiff", ao)
    with pytest.raises(ValueError, match="2-D float32"):
        obscura.save_ao(tmp_path / "ao.npy", np.ones((4, 4, 2), np.float32))
    with pytest.raises(OSError, match="cannot write"):
        obscura.save_ao(tmp_path / "no" / "such" / "dir" / "ao.npy", ao)
    # AO is a fraction with at least one pixel: NaN, infinities, values outside [0, 1]
    # and empty arrays are refused in every format, and no file is left.
    for bad, says in [(np.nan, "the first, NaN"), (np.inf, "the first, inf"),
                      (-0.5, "the first, -0.5"), (5.0, "the first, 5")]:
        a = ao.copy()
        a[2, 3] = bad
        for suffix in [".npy", ".exr", ".png"]:
            with pytest.raises(ValueError, match=rf"{says}.*row 2, column 3"):
                obscura.save_ao(tmp_path / f"bad{suffix}", a)
    for shape in [(0, 5), (5, 0), (0, 0)]:
        for suffix in [".npy", ".exr", ".png"]:
            with pytest.raises(ValueError, match="at least one pixel"):
                obscura.save_ao(tmp_path / f"empty{suffix}", np.ones(shape, np.float32))
    obscura.save_ao(tmp_path / "ao.npy", ao[:, ::2])  # any strides
    np.testing.assert_array_equal(np.load(tmp_path / "ao.npy"), ao[:, ::2])
    assert [p.name for p in tmp_path.iterdir()] == ["ao.npy"]
