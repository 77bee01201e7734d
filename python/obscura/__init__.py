"""Screen-space ambient occlusion of depth maps, on any GPU wgpu reaches or on the CPU
(lavapipe). Depth in, AO out (float32, 1 = unoccluded); the same rules and messages as
`obscura render --depth`.

- `ambient_occlusion(depth, fx=, fy=, cx=, cy=)`: one map.
- `Renderer(...)`: one device for many maps (`render`, `render_many`); threads may share it.
- `save_ao(path, ao)`: .npy, .exr or 16-bit .png, written atomically.
- `obscura.dask`: a folder or list of depth files over a Dask cluster (needs
  `dask[distributed]`).
"""

from ._obscura import DeviceError, Renderer, __version__, ambient_occlusion, save_ao

__all__ = ["DeviceError", "Renderer", "__version__", "ambient_occlusion", "save_ao"]
