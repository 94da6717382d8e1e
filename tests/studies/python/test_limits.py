"""Issue 22 item 12: the module refuses work above max_work up front, with the command line's
default (1e9) and its --max-work message word for word, and Ctrl-C (SIGINT) interrupts a long
C++ call between pixels: KeyboardInterrupt within a second or two, nothing written."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import vrv

VRV = os.environ.get("VRV_EXE", "vrv")


def cli_error(*args):
    p = subprocess.run([VRV, *args], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    prefix = "vrv: error: "
    assert p.stderr.startswith(prefix), p.stderr
    return p.stderr[len(prefix):].strip()


def test_render_refused_with_vrv_renders_message(tmp_path):
    scene = vrv.Scene.default()
    with pytest.raises(ValueError) as e:
        scene.render(width=1024, height=1024, method="alpha", step=1e-5)
    assert str(e.value) == cli_error("render", "--method", "alpha", "--step", "1e-05", "--width", "1024",
                                     "--height", "1024", "-o", str(tmp_path / "x.exr"))
    assert "above the work limit of 1e+09" in str(e.value)  # the same default
    with pytest.raises(ValueError) as e:
        scene.render(width=64, height=64, tol=1e-12, max_work=1000)
    assert str(e.value) == cli_error("render", "--reference", "--width", "64", "--height", "64",
                                     "--max-work", "1000", "-o", str(tmp_path / "x.exr"))
    assert scene.render(width=4, height=4, method="alpha", step=0.1, max_work=1e6).shape == (4, 4)
    # As --tol with --method: a tolerance the discrete render would ignore is refused.
    with pytest.raises(ValueError, match=r"^tol: applies to the reference only, not to method$"):
        scene.render(width=4, height=4, method="alpha", step=0.1, tol=1e-2)


def test_rays_refused(tmp_path):
    scene = vrv.Scene.default()
    o, d = scene.rays(width=8, height=8)
    with pytest.raises(ValueError, match=r"^--step 0\.001: about .* samples on 64 rays, above the work limit of 100; "
                                         r"coarsen the sampling or allow it with --max-work "):
        scene.discrete(o, d, method="alpha", step=1e-3, max_work=100)
    with pytest.raises(ValueError, match=r"^--max-work: about .* field evaluations of the reference on 64 rays, "
                                         r"above the work limit of 100; "):
        scene.reference(o, d, max_work=100)
    with pytest.raises(ValueError, match=r"^max_work: must be positive, got 0$"):  # the keyword, as written
        scene.reference(o, d, max_work=0)
    assert scene.reference(o, d, max_work=1e9)["value"].shape == (8, 8)


def test_a_volume_without_end_is_refused_from_file(tmp_path):
    """A VTI file that never ends (/dev/zero) was read until MemoryError; it is refused naming the
    file, under max_memory (GiB), whose own bad values are named as the keyword."""
    (tmp_path / "endless.vti").symlink_to("/dev/zero")
    (tmp_path / "endless.toml").write_text('[field]\nkind = "volume"\nfile = "endless.vti"\n[transfer]\n'
                                           'emission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 1.0]]\n')
    with pytest.raises(ValueError, match=r"endless\.vti: \(file\): its XML text, held while its arrays are read, "
                                         r"is longer than the 1073741 bytes allowed"):
        vrv.Scene.from_file(str(tmp_path / "endless.toml"), max_memory=0.001)
    with pytest.raises(ValueError, match=r"^max_memory: must be a positive number of GiB, got 0"):
        vrv.Scene.from_file(str(tmp_path / "endless.toml"), max_memory=0)


def test_verify_refused_with_vrv_verifys_message(tmp_path):
    scene = vrv.Scene.default()
    steps = [0.02, 0.01]
    files = []
    for h in steps:
        files.append(str(tmp_path / f"zero_{h}.npy"))
        np.save(files[-1], np.zeros((256, 256)))
    with pytest.raises(ValueError) as e:
        vrv.verify(scene, [np.zeros((256, 256))] * 2, steps, max_work=1e5, out=str(tmp_path / "out"))
    assert str(e.value) == cli_error("verify", *files, "--steps", "0.02,0.01", "--max-work", "1e5", "--no-cache")
    assert not (tmp_path / "out").exists()
    big = [np.zeros((8192, 8192), dtype=np.float32)] * 2  # the default limit: the CLI's; refused uncopied
    with pytest.raises(ValueError, match=r"^--max-work: about .* \(the reference on 8192 x 8192 pixels at --tol "
                                         r"1e-10: .*\), above the work limit of 1e\+09; "):
        vrv.verify(scene, big, steps)


CHILD = textwrap.dedent("""
    import sys, vrv
    import numpy as np
    scene = vrv.Scene.default()
    call = sys.argv[1]
    print("started", flush=True)
    try:
        if call == "render":
            scene.render(width=1024, height=1024, method="alpha", step=1e-4, max_work=1e15)
        else:
            images = [np.zeros((512, 512))] * 2
            vrv.verify(scene, images, [0.02, 0.01], out=sys.argv[2], max_work=1e15)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
        sys.exit(3)
    print("finished", flush=True)
""")


@pytest.mark.parametrize("call", ["render", "verify"])
def test_ctrl_c_interrupts_a_long_call(call, tmp_path):
    out = tmp_path / "out"
    child = subprocess.Popen([sys.executable, "-c", CHILD, call, str(out)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(1.0)  # inside the C++ call (it takes minutes)
    assert child.poll() is None, child.communicate()
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    stdout, stderr = child.communicate(timeout=30)
    elapsed = time.monotonic() - sent
    assert child.returncode == 3 and stdout.strip() == "KeyboardInterrupt", (child.returncode, stdout, stderr)
    # Interrupted between chunks (0.2-0.3 s on an idle machine), not when the minutes of work end;
    # the margin is for a CI machine shared with other jobs.
    assert elapsed < 10.0, elapsed
    assert not out.exists()  # nothing written
