"""VTK's vtkSSAOPass on obscura's shared views, for `obscura eval --score-images`.

    python peers/vtk/ssao.py VIEWS_JSON OUT_DIR [--kernel 32] [--runs 5] [--times times.json]

VIEWS_JSON comes from `obscura eval --all --export-views VIEWS_JSON` (each view's scene,
camera and AO radius). Every surface is white and lit by ambient light only, so a frame is
the AO: VTK's frame with the SSAO pass divided by the same frame without it, per pixel
(where the plain frame is lit). MSAA is off: with it the plain frame pays a resolve the
SSAO frame skips. Writes OUT_DIR/VIEW.png (16-bit grey, 1 = white = unoccluded) and
OUT_DIR/times.json, or the --times name (median wall time of a frame with and without the
pass, after a warm-up, alternated). Offscreen through EGL (Mesa's llvmpipe here).
"""

import argparse
import json
import pathlib
import statistics
import sys
import time

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def load(renderer, scene):
    """The scene's actors in `renderer`, every one white and ambient-only."""
    path = pathlib.Path(scene)
    if path.suffix.lower() in (".glb", ".gltf"):
        importer = vtk.vtkGLTFImporter()
        importer.SetFileName(str(path))
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.AddRenderer(renderer)
        importer.SetRenderWindow(window)
        importer.Update()
        window.RemoveRenderer(renderer)
    elif path.suffix.lower() == ".obj":
        reader = vtk.vtkOBJReader()
        reader.SetFileName(str(path))
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputConnection(reader.GetOutputPort())
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        renderer.AddActor(actor)
    else:
        raise ValueError(f"{scene}: not glTF or OBJ")
    actors = renderer.GetActors()
    actors.InitTraversal()
    for _ in range(actors.GetNumberOfItems()):
        actor = actors.GetNextActor()
        actor.GetMapper().ScalarVisibilityOff()
        actor.SetTexture(None)
        p = actor.GetProperty()
        p.SetInterpolationToGouraud()
        p.SetColor(1, 1, 1)
        p.SetAmbientColor(1, 1, 1)
        p.SetAmbient(1.0)
        p.SetDiffuse(0.0)
        p.SetSpecular(0.0)
        p.RemoveAllTextures()
        p.BackfaceCullingOff()


def frame(window):
    """The window's colour as float rows, top row first."""
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    img = grab.GetOutput()
    w, h, _ = img.GetDimensions()
    rgb = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, 3).astype(np.float32)
    return rgb[::-1, :, 0] / 255.0


def view_ao(v, kernel, runs):
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0, 0, 0)
    # A light must exist for VTK to apply the pass to the ambient term, though with
    # diffuse and specular at 0 it adds nothing to the picture.
    renderer.AutomaticLightCreationOn()
    load(renderer, v["scene"])
    cam = renderer.GetActiveCamera()
    cam.SetPosition(*v["eye"])
    cam.SetFocalPoint(*v["target"])
    cam.SetViewUp(*v["up"])
    cam.SetViewAngle(v["fov_y_deg"])
    cam.SetClippingRange(v["near"], v["far"])
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(v["width"], v["height"])
    window.AddRenderer(renderer)

    plain_pass = vtk.vtkRenderStepsPass()
    ssao = vtk.vtkSSAOPass()
    ssao.SetDelegatePass(vtk.vtkRenderStepsPass())
    ssao.SetRadius(v["radius"])
    ssao.SetKernelSize(kernel)
    ssao.SetBlur(True)
    ssao.SetBias(0.001 * v["radius"])

    def render(with_ssao):
        renderer.SetPass(ssao if with_ssao else plain_pass)
        start = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        return time.perf_counter() - start

    times = {True: [], False: []}
    render(False), render(True)  # warm-up
    for _ in range(runs):
        for with_ssao in (False, True):
            times[with_ssao].append(render(with_ssao))
    render(False)
    plain = frame(window)
    render(True)
    occluded = frame(window)
    ao = np.where(plain > 0.0, occluded / np.maximum(plain, 1e-6), 1.0).clip(0.0, 1.0)
    ms = {k: 1e3 * statistics.median(t) for k, t in times.items()}
    return ao, ms[True] - ms[False], ms


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("views", type=pathlib.Path)
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--kernel", type=int, default=32, help="vtkSSAOPass kernel size (samples)")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--times", default="times.json", help="file name of the timing in OUT_DIR")
    args = ap.parse_args()
    from PIL import Image

    views = json.loads(args.views.read_text())["views"]
    args.out.mkdir(parents=True, exist_ok=True)
    times = {}
    for v in views:
        ao, ssao_ms, ms = view_ao(v, args.kernel, args.runs)
        Image.fromarray(np.round(ao * 65535).astype(np.uint16)).save(args.out / f"{v['name']}.png")
        times[v["name"]] = {"ssao_ms": ssao_ms, "frame_ms": ms[True], "plain_ms": ms[False]}
        print(f"{v['name']}: SSAO {ssao_ms:.1f} ms (frame {ms[True]:.1f}, plain {ms[False]:.1f})",
              file=sys.stderr)
    (args.out / args.times).write_text(json.dumps({"kernel": args.kernel, "views": times}, indent=1))


if __name__ == "__main__":
    main()
