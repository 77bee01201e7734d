"""Screen-space ambient occlusion of depth maps, on any GPU wgpu reaches or on the CPU
(lavapipe). Depth in, AO out (float32, 1 = unoccluded); the same rules and messages as
`obscura render --depth`."""

import os
from typing import List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

DepthNoise = Union[str, Tuple[float, float, float], Sequence[float], None]

def save_ao(path: Union[str, "os.PathLike[str]"], ao: npt.NDArray[np.float32]) -> None:
    """Writes a 2-D float32 AO array by extension, as `obscura render --out`: .npy float32,
    .exr float32, .png 16-bit grey. Atomic (written beside, then renamed). ValueError for
    another array or extension, an empty array, or a value outside [0, 1] (NaN and
    infinities included); OSError when the write fails."""

def check_settings(
    *,
    fx: float,
    fy: float,
    cx: float,
    cy: float,
    width: Optional[int] = None,
    height: Optional[int] = None,
    radius: Optional[float] = None,
    depth_scale: Optional[float] = None,
    depth_noise: DepthNoise = None,
    thickness: Optional[float] = None,
    estimator: Optional[str] = None,
    preset: str = "high",
    resolution: str = "full",
    denoise: str = "spatial",
    frames: int = 1,
) -> None:
    """Checks settings many maps will share before any map is read or device opened: the
    renderer's options, the intrinsics (all of them with the maps' width and height, else
    what needs no size) and the shared parameters. ValueError with `render`'s message."""

class DeviceError(RuntimeError):
    """No usable GPU or software adapter, or the device failed (out of memory, lost)."""

def ambient_occlusion(
    depth: npt.NDArray[Union[np.float16, np.float32, np.float64, np.uint16]],
    *,
    fx: float,
    fy: float,
    cx: float,
    cy: float,
    radius: Optional[float] = None,
    normals: Optional[npt.NDArray[np.floating]] = None,
    normals_frame: str = "opencv",
    depth_scale: Optional[float] = None,
    depth_noise: DepthNoise = None,
    thickness: Optional[float] = None,
    estimator: Optional[str] = None,
    preset: str = "high",
    resolution: str = "full",
    denoise: str = "spatial",
    frames: int = 1,
) -> npt.NDArray[np.float32]:
    """Ambient occlusion of a depth map: a float32 (height, width) array, 1 = unoccluded.

    depth: (height, width), float16/32/64 in scene units (metres) or uint16 in depth
        units times `depth_scale`; 0, NaN and inf are missing. Any order or strides.
    fx, fy, cx, cy: pinhole intrinsics in pixels (OpenCV: pixel centres at integers).
    radius: AO radius in scene units; default 3% of the diagonal of the scene's bounds
        (1st to 99th percentile).
    normals: (height, width, 3 or 4) float view-space normals in `normals_frame`: "opencv"
        (x right, y down, z into the scene) or "opengl" (y up, z towards the viewer).
    depth_scale: scene units per depth unit; default 0.001 for uint16 (millimetres),
        none for floats (scene units already), and a scale given applies to floats too.
    depth_noise: "auto" (estimated from the map; the default), "none", "kinect"
        (sigma = 1.5 mm z^2), or (C, L, Q): sigma(z) = C + L z + Q z^2 in scene units;
        "kinect" and (C, L, Q) add a uint16 map's quantisation terraces.
    thickness: the bitmask estimator's thickness prior, times the radius (> 0, or
        float("inf"): infinitely thick, as GTAO assumes); default 1. A depth map shows
        only the front of each object: this assumes every object is that deep behind each
        pixel, along its ray, and the part of it within the radius occludes
        (docs/thickness.md). Other estimators ignore it.
    estimator: "bitmask" (None, the default: the library's estimator for depth maps,
        more accurate than GTAO from depth alone at about 1.35x its time), "gtao", "hbao",
        "vo", "vao", "sao" or "vo-area".
    preset: "low", "medium", "high" or "ultra" (8, 16, 32, 96 samples per pixel;
        high with GTAO or the bitmask at full or randomized half resolution: 36, three
        slices of six steps crowded toward the centre).
    resolution: "full", "half" or "quarter".
    denoise: "spatial", "none", "box" or "tent".
    frames: still-camera frames accumulated, 1..=100000 (1: one frame); each call starts
        the accumulation anew, so the same map gives the same AO.

    Creates a device and compiles the passes on each call; use `Renderer` in loops.
    Raises ValueError on bad input, DeviceError when no adapter can be used.
    """

class Renderer:
    """One device and one set of compiled passes for many depth maps. Threads may share
    one: calls are serialized inside it, with the GIL released while a map waits for or
    runs on the device."""

    def __init__(
        self,
        *,
        estimator: Optional[str] = None,
        preset: str = "high",
        resolution: str = "full",
        denoise: str = "spatial",
        frames: int = 1,
    ) -> None: ...
    @property
    def adapter(self) -> str:
        """The adapter's name, type and driver."""
    def render(
        self,
        depth: npt.NDArray[Union[np.float16, np.float32, np.float64, np.uint16]],
        *,
        fx: float,
        fy: float,
        cx: float,
        cy: float,
        radius: Optional[float] = None,
        normals: Optional[npt.NDArray[np.floating]] = None,
        normals_frame: str = "opencv",
        depth_scale: Optional[float] = None,
        depth_noise: DepthNoise = None,
        thickness: Optional[float] = None,
    ) -> npt.NDArray[np.float32]:
        """The AO of one depth map; arguments as `ambient_occlusion`. Releases the GIL
        while the device works."""
    @overload
    def render_many(
        self,
        maps: npt.NDArray[Union[np.float16, np.float32, np.float64, np.uint16]],
        *,
        fx: Union[float, Sequence[float]],
        fy: Union[float, Sequence[float]],
        cx: Union[float, Sequence[float]],
        cy: Union[float, Sequence[float]],
        radius: Union[None, float, Sequence[float]] = None,
        normals: Optional[Sequence[Optional[npt.NDArray[np.floating]]]] = None,
        normals_frame: str = "opencv",
        depth_scale: Optional[float] = None,
        depth_noise: DepthNoise = None,
        thickness: Optional[float] = None,
    ) -> npt.NDArray[np.float32]: ...
    @overload
    def render_many(
        self,
        maps: Sequence[npt.NDArray[Union[np.float16, np.float32, np.float64, np.uint16]]],
        *,
        fx: Union[float, Sequence[float]],
        fy: Union[float, Sequence[float]],
        cx: Union[float, Sequence[float]],
        cy: Union[float, Sequence[float]],
        radius: Union[None, float, Sequence[float]] = None,
        normals: Optional[Sequence[Optional[npt.NDArray[np.floating]]]] = None,
        normals_frame: str = "opencv",
        depth_scale: Optional[float] = None,
        depth_noise: DepthNoise = None,
        thickness: Optional[float] = None,
    ) -> List[npt.NDArray[np.float32]]:
        """The AO of many maps: an (N, H, W) array gives an (N, H, W) array, a sequence of
        2-D maps (sizes may differ) a list. Intrinsics and radius: one number or N. Maps
        are prepared on a second thread while the device renders, grouped by size;
        results equal `render` on each. A bad map raises ValueError("map i: ...")."""
