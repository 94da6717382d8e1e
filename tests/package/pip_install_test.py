#!/usr/bin/env python3
"""`pip install .` (setup.py), offline with Debian's setuptools and pip, into a scratch --target that
is then moved; from there, with the build tree out of reach, `import vrv; vrv.verify(...)` and the
installed command `vrv verify` load the installed image module (LD_DEBUG names what is loaded) and draw
the plot with the installed script.  VRV_PIP_BUILD_DIR makes pip reuse BUILD_DIR (CI builds once);
the source tree is left as it was.

    pip_install_test.py SOURCE_DIR BUILD_DIR PYTHON
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

source, build, python = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve(), sys.argv[3]
# Outside the build tree (code inside it may load the build tree's image module) and the source.
scratch = Path(tempfile.mkdtemp(prefix="vrv-pip-"))
clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VRV_IMAGE_MODULE", "VRV_STUDY_PATH")}


def run(what, command, env=None, expect=0):
    p = subprocess.run([str(c) for c in command], cwd=scratch, env=env or clean, capture_output=True, text=True)
    if p.returncode != expect:
        sys.exit(f"{what}: exit {p.returncode}, expected {expect}\n{p.stdout}\n{p.stderr}")
    return p


def untracked():
    p = subprocess.run(["git", "-C", str(source), "status", "--porcelain", "--ignored"], capture_output=True, text=True)
    return set(p.stdout.splitlines()) if p.returncode == 0 else set()


before = untracked()
start = time.monotonic()
run("pip install", [python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps",
                    "--target", scratch / "staged", source], env={**clean, "VRV_PIP_BUILD_DIR": str(build)})
print(f"pip install: {time.monotonic() - start:.1f} s")
if untracked() != before:
    sys.exit(f"pip install left files in the source tree: {sorted(untracked() - before)}")

target = scratch / "moved"
(scratch / "staged").rename(target)
package = target / "vrv"
module = sorted(package.glob("vrv.*.so"))
for f in [package / "__init__.py", package / "__main__.py", package / "vrv", package / "libvrv_image.so",
          package / "plot_study.py", target / "bin" / "vrv"]:
    if not f.is_file():
        sys.exit(f"pip install: {f} was not installed")
if not module:
    sys.exit(f"pip install: no Python module in {package}")
for f in (package / "vrv", target / "bin" / "vrv"):
    if not os.access(f, os.X_OK):
        sys.exit(f"pip install: {f} is not executable")

steps = [0.1, 0.05, 0.025, 0.0125]
script = f"""
import sys
sys.path.insert(0, {str(target)!r})
import vrv
assert vrv.__file__.startswith({str(target)!r}), vrv.__file__
scene = vrv.Scene.default()
steps = {steps!r}
images = [scene.render(method="alpha", strategy="inviwo", step=h, width=16, height=16) for h in steps]
for h, image in zip(steps, images):
    import numpy as np
    np.save(f"alpha_{{h}}.npy", image)
r = vrv.verify(scene, images, steps, expected_order=2, diagnose=False, out="pv", plots=True)
assert r["pass"], r["verdict_reason"]
print(r["verdict"])
"""
# -I: no PYTHONPATH, no user site, not the current folder: only the sys.path entry above.
p = run("python", [python, "-I", "-c", script], env={**clean, "LD_DEBUG": "files"})
if f"file={target}/vrv/libvrv_image.so" not in p.stderr or f"file={build}/" in p.stderr:
    sys.exit(f"python: the image module was not loaded from {target}/vrv:\n{p.stderr[-3000:]}")
if p.stdout.strip() != "converges" or not (scratch / "pv" / "reference.exr").is_file():
    sys.exit(f"python: {p.stdout}\n{p.stderr[-3000:]}")
if not (scratch / "pv" / "error_vs_step.png").is_file():
    sys.exit(f"python: the plot was not drawn:\n{p.stderr[-3000:]}")

# The command pip wrote runs the package's program (PYTHONPATH: a --target is not on sys.path).
files = [f"alpha_{h}.npy" for h in steps]
p = run("vrv verify", [target / "bin" / "vrv", "verify", *files, "--steps", ",".join(map(str, steps)),
                       "--expected-order", "2", "--no-cache", "--no-diagnosis", "--out", "cv", "--plots", "--quiet"],
        env={**clean, "LD_DEBUG": "files", "PYTHONPATH": str(target)})
if f"file={package}/libvrv_image.so" not in p.stderr or f"file={build}/" in p.stderr:
    sys.exit(f"vrv verify: the image module was not loaded from {package}:\n{p.stderr[-3000:]}")
if not (scratch / "cv" / "error_vs_step.png").is_file():
    sys.exit("vrv verify: the plot was not drawn")
shutil.rmtree(scratch)
print("ok")
