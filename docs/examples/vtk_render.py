#!/usr/bin/env python3
"""Render a `vrv export` directory with VTK, as a new user would, at a sequence of sample distances.

    xvfb-run -a /usr/bin/python3 vtk_render.py EXPORT_DIR OUT_DIR [--mapper fixed|gpu] H [H ...]
        -> OUT_DIR/<mapper>_H<H>.png  (8-bit grey, row 0 at the top, one per sample distance)
           OUT_DIR/fixed15_H<H>.tiff   (fixed-point mapper only: its own 15-bit ray-cast image)
           OUT_DIR/<mapper>_steps.json (the steps, the mapper, VTK's version, what was set)

What is set, and nothing else (VTK's defaults otherwise):
  - vtkXMLImageDataReader on field_f64.vti (origin and spacing from the file);
  - vtkPiecewiseFunction from transfer_function.json "opacity", vtkColorTransferFunction from
    "color" (grey: r = g = b), SetScalarOpacityUnitDistance(unit_distance), ShadeOff,
    linear interpolation;
  - the camera of camera.json: position = eye, focal point = target, view up = up,
    view angle = fov_degrees (VTK's view angle is the vertical full angle, as vrv's),
    window size = width x height, background = export.json "background";
  - mapper.SetSampleDistance(H) with automatic adjustment off (and, for the fixed-point mapper,
    image sample distance 1: one ray per pixel).
The framebuffer is 8-bit RGBA (VTK 9.1 has no float read-back for either mapper's final image),
read with vtkWindowToImageFilter, whose row 0 is the bottom: it is flipped to vrv's row 0 = top.
The red channel is written (the colour is grey; the script checks that r = g = b).

The fixed-point mapper casts its rays into an image of its own, 15-bit fixed point (unsigned short,
1.0 = 32767, colour premultiplied by opacity), and then draws that image into the window as a
texture (vtkOpenGLRayCastImageDisplayHelper). VTK's Python wrapping returns that image's pointer
only as a string ("_<hex address>_p_void"), so it is read with ctypes, copied at once, placed at
its origin in the viewport and written as float32 v / 32767 (exact: 15 bits fit a float).
That separates the ray casting from the display step.
"""
import ctypes
import json
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import vtk
from vtk.util import numpy_support


def build(export, mapper_kind):
    tf = json.loads((export / "transfer_function.json").read_text())
    cam = json.loads((export / "camera.json").read_text())
    manifest = json.loads((export / "export.json").read_text())

    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(str(export / "field_f64.vti"))
    opacity = vtk.vtkPiecewiseFunction()
    for v, a in tf["opacity"]:
        opacity.AddPoint(v, a)
    colour = vtk.vtkColorTransferFunction()
    for v, c in tf["color"]:
        colour.AddRGBPoint(v, c, c, c)
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(colour)
    prop.ShadeOff()
    prop.SetInterpolationTypeToLinear()
    prop.SetScalarOpacityUnitDistance(tf["unit_distance"])

    if mapper_kind == "fixed":
        mapper = vtk.vtkFixedPointVolumeRayCastMapper()
        mapper.SetImageSampleDistance(1.0)
        mapper.SetMinimumImageSampleDistance(1.0)
        mapper.SetMaximumImageSampleDistance(1.0)
    else:
        mapper = vtk.vtkGPUVolumeRayCastMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.AutoAdjustSampleDistancesOff()
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtk.vtkRenderer()
    ren.AddVolume(volume)
    bg = manifest["background"]
    ren.SetBackground(bg, bg, bg)
    camera = ren.GetActiveCamera()
    camera.SetPosition(*cam["eye"])
    camera.SetFocalPoint(*cam["target"])
    camera.SetViewUp(*cam["up"])
    camera.SetViewAngle(cam["fov_degrees"])
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(ren)
    window.SetSize(cam["width"], cam["height"])
    # VTK resets the clipping range on the first render; the volume lies well inside it.
    return mapper, ren, window, (cam["width"], cam["height"])


def grab(window, size):
    """The framebuffer as (height, width, 3) uint8, row 0 at the top."""
    capture = vtk.vtkWindowToImageFilter()
    capture.SetInput(window)
    capture.SetInputBufferTypeToRGB()
    capture.ReadFrontBufferOff()
    capture.Update()
    image = capture.GetOutput()
    w, h, _ = image.GetDimensions()
    if (w, h) != size:
        sys.exit(f"vtk_render.py: framebuffer is {w} x {h}, camera.json asks {size[0]} x {size[1]}")
    pixels = numpy_support.vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    return pixels[::-1]  # vtkImageData row 0 is the bottom; vrv's is the top


def ray_cast_image(mapper, size):
    """The fixed-point mapper's own ray-cast image as (height, width) float, row 0 at the top."""
    image = mapper.GetRayCastImage()
    pointer = image.GetImage()  # "_<hex>_p_void"
    address = int(pointer[1:].split("_")[0], 16)
    mx, my = image.GetImageMemorySize()
    ux, uy = image.GetImageInUseSize()
    ox, oy = image.GetImageOrigin()
    if image.GetImageSampleDistance() != 1.0 or tuple(image.GetImageViewportSize()) != size:
        sys.exit("vtk_render.py: the ray-cast image is not one ray per pixel")
    memory = np.ctypeslib.as_array((ctypes.c_ushort * (mx * my * 4)).from_address(address))
    rgba = memory.reshape(my, mx, 4)[:uy, :ux].astype(np.float64) / 32767.0
    full = np.zeros((size[1], size[0], 4))
    full[oy:oy + uy, ox:ox + ux] = rgba
    if not (np.array_equal(full[..., 0], full[..., 1]) and np.array_equal(full[..., 0], full[..., 2])):
        sys.exit("vtk_render.py: r, g, b of the ray-cast image differ in a grey rendering")
    return full[::-1, :, 0]


def write(path, pixels, fmt):
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 1, fmt)
    writer = oiio.ImageOutput.create(str(path))
    if not writer or not writer.open(str(path), spec) or not writer.write_image(np.ascontiguousarray(pixels[..., None])):
        sys.exit(f"vtk_render.py: {path}: {oiio.geterror()}")
    writer.close()
    print(path, flush=True)


def main(argv):
    mapper_kind = "fixed"
    if "--mapper" in argv:
        i = argv.index("--mapper")
        mapper_kind = argv[i + 1]
        del argv[i:i + 2]
    if len(argv) < 3 or mapper_kind not in ("fixed", "gpu"):
        sys.exit(__doc__)
    export, out = Path(argv[0]), Path(argv[1])
    steps = [float(h) for h in argv[2:]]
    out.mkdir(parents=True, exist_ok=True)
    mapper, ren, window, size = build(export, mapper_kind)
    files = []
    for h in steps:
        mapper.SetSampleDistance(h)
        window.Render()
        rgb = grab(window, size)
        if not (np.array_equal(rgb[..., 0], rgb[..., 1]) and np.array_equal(rgb[..., 0], rgb[..., 2])):
            sys.exit(f"vtk_render.py: H = {h}: r, g, b differ in a grey rendering")
        name = f"{mapper_kind}_H{h:g}.png"
        write(out / name, rgb[..., 0], "uint8")
        files.append(name)
        if mapper_kind == "fixed":
            name = f"fixed15_H{h:g}.tiff"
            write(out / name, ray_cast_image(mapper, size).astype(np.float32), "float")
            files.append(name)
    meta = {
        "vtk_version": vtk.vtkVersion.GetVTKVersion(),
        "mapper": mapper.GetClassName(),
        "opengl": [l.strip() for l in window.ReportCapabilities().splitlines() if "OpenGL renderer" in l or "OpenGL version" in l],
        "steps": steps,
        "files": files,
        "framebuffer": "8-bit RGB via vtkWindowToImageFilter, flipped to row 0 at the top, red channel",
        "ray_cast_image": "fixed15_*.tiff: the fixed-point mapper's 15-bit image, float32 v / 32767" if mapper_kind == "fixed" else None,
        "export": str(export),
    }
    (out / f"{mapper_kind}_steps.json").write_text(json.dumps(meta, indent=2) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
