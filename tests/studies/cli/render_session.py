"""What the end-to-end render tests share (color_render_test.py, alpha_render_test.py): a small grid
scene with a camera, scene files written into the output folder, vrv run with its exit checked,
and images read back with their channel names through OpenImageIO's Python module."""
import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

HEAD = """[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [9, 8, 7]
source = { kind = "marschner_lobb" }
[camera]
eye = [0.4, 0.7, -3.5]
target = [0.0, 0.1, 0.0]
width = 20
height = 16
"""


def points(pts):
    return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in p) + "]" for p in pts) + "]"


def read(path):
    """An image's pixels as (height, width, channels) doubles, and its channel names."""
    im = oiio.ImageInput.open(str(path))
    assert im, oiio.geterror()
    names = tuple(im.spec().channelnames)
    data = np.asarray(im.read_image(oiio.DOUBLE))
    im.close()
    return data, names


class RenderSession:
    """vrv and an output folder, emptied first."""

    def __init__(self, vrv, out):
        self.vrv, self.out = vrv, Path(out)
        shutil.rmtree(self.out, ignore_errors=True)
        self.out.mkdir(parents=True)

    def scene(self, name, transfer, background=""):
        path = self.out / name
        path.write_text(HEAD + "[transfer]\n" + transfer + background)
        return path

    def run(self, *args, expect=0):
        r = subprocess.run([self.vrv, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == expect, f"{args}: exit {r.returncode} (expected {expect}): {r.stderr}"
        return r

    def render(self, scene_path, name, *how):
        """vrv render of the scene to OUT/name.exr; its JSON line."""
        r = self.run("render", "--scene", scene_path, *how, "--quiet", "-o", self.out / (name + ".exr"))
        return json.loads(r.stdout.splitlines()[-1])
