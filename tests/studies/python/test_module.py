"""`import vrv` (studies/python/module.cpp): arrays in and out, the command line's numbers and
messages.  Run by CTest as `python` with PYTHONPATH at the built module and VRV_EXE at the
program."""
import json
import os
import re
import subprocess

import numpy as np
import pytest

import vrv
import numpy_raycaster

VRV = os.environ.get("VRV_EXE", "vrv")

RAYS = [  # origin, direction: through the middle, oblique, from inside, a miss, a corner
    ((-3, 0.5, 0), (1, 0, 0)),
    ((-3, 0.2, 0.1), (1, 0.1, -0.05)),
    ((0.1, 0.2, 0.3), (0.3, -1, 2)),
    ((-3, 5, 0), (1, 0, 0)),
    ((-2, -2, -2), (1, 1, 1)),
]


def cli(*args):
    """stdout of `vrv ARGS`, or the one-line error (without 'vrv: error: ') and exit code."""
    p = subprocess.run([VRV, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr.strip().removeprefix("vrv: error: ")


def cli_rays(tmp_path, *args):
    """`vrv ray --rays FILE ARGS` over RAYS (one process): one parsed JSON line per ray."""
    path = tmp_path / "rays.jsonl"
    path.write_text("".join(json.dumps({"origin": o, "direction": d}) + "\n" for o, d in RAYS))
    code, out, err = cli("ray", "--rays", str(path), *args)
    assert code == 0, err
    return [json.loads(line) for line in out.splitlines()]


ORIGINS = np.array([o for o, _ in RAYS], dtype=float)
DIRECTIONS = np.array([d for _, d in RAYS], dtype=float)


def test_reference_is_bitwise_vrv_ray_json(tmp_path):
    r = vrv.Scene.default().reference(ORIGINS, DIRECTIONS, tol=1e-10)
    lines = cli_rays(tmp_path, "--tol", "1e-10")
    assert len(lines) == len(RAYS)
    for i, line in enumerate(lines):
        assert r["value"][i] == line["value"]
        assert r["error_estimate"][i] == line["error_estimate"]
        assert r["evaluations"][i] == line["evaluations"]
        assert r["optical_depth"][i] == line["optical_depth"]
        assert bool(r["hit"][i]) == (line["t_entry"] is not None)
        if line["t_entry"] is not None:
            assert (r["t_entry"][i], r["t_exit"][i]) == (line["t_entry"], line["t_exit"])
        else:
            assert np.isnan(r["t_entry"][i]) and np.isnan(r["t_exit"][i])


def test_discrete_is_bitwise_vrv_ray_method(tmp_path):
    options = dict(method="alpha", strategy="vtk", step=0.01, oversample=2, correction="lacroute")
    r = vrv.Scene.default().discrete(ORIGINS, DIRECTIONS, **options)
    lines = cli_rays(tmp_path, *[f"--{k}={v}" for k, v in options.items()])
    assert len(lines) == len(RAYS)
    for i, line in enumerate(lines):
        assert (r["value"][i], r["samples"][i]) == (line["value"], line["samples"])


def test_discrete_bound_is_vrv_ray_bound_and_holds(tmp_path):
    """bound=True: the a-priori bound per ray, bitwise `vrv ray --bound`, and above the error against
    the reference (docs/error-bounds.md); refused with the reason where none is derived."""
    scene = vrv.Scene.default()
    options = dict(method="trapezoid", strategy="step", step=0.02)
    r = scene.discrete(ORIGINS, DIRECTIONS, bound=True, **options)
    lines = cli_rays(tmp_path, "--bound", *[f"--{k}={v}" for k, v in options.items()])
    assert list(r["error_bound"]) == [line["error_bound"] for line in lines]
    assert list(r["error_estimate"]) == [line["error_estimate"] for line in lines]
    assert list(r["asymptotic"]) == [line["asymptotic"] for line in lines]
    reference = scene.reference(ORIGINS, DIRECTIONS, tol=1e-13)
    signed = r["value"] - reference["value"]
    error = np.abs(signed)
    assert np.all(error <= r["error_bound"] + reference["error_estimate"])
    # Where the steps resolve the field, the estimate is the error's leading term (within 2% of
    # the ray's error scale at the 99th percentile; here, every asymptotic ray within 10% of |error|
    # or of 1e-9).
    near = np.abs(r["error_estimate"] - signed) <= 0.1 * error + 1e-9
    assert np.all(near[r["asymptotic"]])
    assert r["error_bound"][3] == 0  # the miss: the background, exactly
    assert "error_bound" not in scene.discrete(ORIGINS, DIRECTIONS, **options)
    with pytest.raises(ValueError, match=r"^bound: no a-priori bound is derived for a strategy with a partial step"):
        scene.discrete(ORIGINS, DIRECTIONS, method="alpha", strategy="partial", step=0.02, bound=True)
    with pytest.raises(ValueError, match=r"^bound: must be True or False"):
        scene.discrete(ORIGINS, DIRECTIONS, method="alpha", step=0.02, bound=1)


def test_plan_is_vrv_plan_and_its_choice_meets_the_target():
    """vrv.plan: the rules `vrv plan --json` ranks, at the same steps; the chosen step's image meets
    the target against the reference (docs/error-bounds.md)."""
    scene = vrv.Scene.default()
    p = vrv.plan(scene, 1e-3, width=12, height=12)
    code, out, err = cli("plan", "--target", "1e-3", "--width", "12", "--height", "12", "--json")
    assert code == 0, err
    cli_plan = json.loads(out)
    # The steps are the same; the order may differ where two rules' measured seconds are close.
    assert sorted((r["rule"], r["step"]) for r in p["ranked"]) == sorted((r["rule"], r["step"]) for r in cli_plan["ranked"])
    chosen = p["ranked"][0]
    assert chosen["met"]
    origins, directions = scene.rays(width=12, height=12)
    reference = scene.reference(origins, directions, tol=1e-12)["value"]
    image = scene.discrete(origins, directions, method=chosen["rule"], strategy=chosen["strategy"],
                           step=chosen["step"])["value"]
    assert np.max(np.abs(image - reference)) <= 1e-3
    with pytest.raises(ValueError, match=r"^metric: unknown value 'p99'"):
        vrv.plan(scene, 1e-3, metric="p99")
    with pytest.raises(ValueError, match=r"^rules: unknown rule 'simpson'"):
        vrv.plan(scene, 1e-3, rules="moreland,simpson")
    with pytest.raises(ValueError, match=r"^rules: 'riemann' listed twice$"):
        vrv.plan(scene, 1e-3, rules="riemann,riemann")
    # The work limit spelled as the keyword (it said --max-work to a Python user).
    with pytest.raises(ValueError, match=r"^max_work: one estimate of this camera takes about .*allow it with max_work$"):
        vrv.plan(scene, 1e-3, max_work=10)


@pytest.mark.parametrize("keyword, value, expected", [
    ("step", "0.1", "a number"), ("oversample", 1.5, "a whole number within a C int"),
    ("table_size", 10**12, "a whole number within a C int"), ("method", 1, "a string"),
])
def test_a_keyword_of_the_wrong_type_is_named(keyword, value, expected):
    """pybind11's RuntimeError 'Unable to cast Python instance to C++ type' named neither."""
    scene = vrv.Scene.default()
    o, d = scene.rays(width=2, height=2)
    options = {"method": "alpha", "step": 0.1, keyword: value}
    with pytest.raises(TypeError, match=rf"^{keyword}: expected {expected}, got {re.escape(repr(value))}$"):
        scene.discrete(o, d, **options)


def test_opacity_colour_conventions_are_bitwise_vrv_ray(tmp_path):
    """The renderer conventions of `vrv ray` (--opacity-unit, --color, --table-size, --table-lookup)
    as keywords, named as on the command line."""
    path = tmp_path / "oc.toml"
    path.write_text("""
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
opacity = [[0.0, 0.05], [1.0, 0.4]]
color = [[0.0, 1.0], [1.0, 0.2]]
unit_length = 0.25
""")
    scene = vrv.Scene.from_file(str(path))
    options = dict(method="alpha", strategy="inviwo", step=0.02, opacity_unit="distance", color="premultiplied",
                   table_size=256, table_lookup="uncentred")
    r = scene.discrete(ORIGINS, DIRECTIONS, **options)
    lines = cli_rays(tmp_path, "--scene", str(path), *[f"--{k.replace('_', '-')}={v}" for k, v in options.items()])
    assert [line["value"] for line in lines] == list(r["value"])
    plain = scene.discrete(ORIGINS, DIRECTIONS, method="alpha", strategy="inviwo", step=0.02)
    assert not np.array_equal(r["value"], plain["value"])
    with pytest.raises(ValueError, match=r"^opacity_unit: unknown value 'metre'"):
        scene.discrete(ORIGINS, DIRECTIONS, method="alpha", opacity_unit="metre")


def test_arrays_of_any_shape():
    scene = vrv.Scene.default()
    origins, directions = scene.rays(width=7, height=5)
    assert origins.shape == directions.shape == (5, 7, 3)
    r = scene.reference(origins, directions, tol=1e-8)
    assert r["value"].shape == (5, 7) and r["evaluations"].dtype == np.int64
    one = scene.reference(origins[2, 3], directions[2, 3], tol=1e-8)
    assert one["value"].shape == () and one["value"] == r["value"][2, 3]
    empty = scene.reference(np.zeros((0, 3)), np.zeros((0, 3)))
    assert empty["value"].shape == (0,)
    image = scene.render(width=7, height=5, tol=1e-8)
    assert image.shape == (5, 7)
    np.testing.assert_allclose(image, r["value"], rtol=0, atol=1e-12)
    assert np.all(r["error_estimate"] <= 1e-8) and np.all(r["tolerance_met"])


def test_scene_from_toml_and_file(tmp_path):
    text = """
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "linear_ramp"
gradient = [0.5, 0.0, 0.0]
offset = 0.5
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 0.5]]
"""
    path = tmp_path / "ramp.toml"
    path.write_text(text)
    a = vrv.Scene.from_toml(text)
    b = vrv.Scene.from_file(str(path))
    assert a.box == {"min": (-1.0, -1.0, -1.0), "max": (1.0, 1.0, 1.0)}
    o, d = np.array([[-3.0, 0.1, 0.2]]), np.array([[1.0, 0.0, 0.0]])
    assert a.reference(o, d)["value"][0] == b.reference(o, d)["value"][0]
    assert a.reference(o, d)["evaluations"][0] == 2  # linear along the ray: one exact panel


def as_keywords(message):
    """The command line's message with each --flag spelled as the Python keyword (--table-size: table_size)."""
    return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), message)


# keywords: an option's message names the keyword the caller wrote (tol=, method=, ...: issue 19),
# the others (files) are the command line's word for word.
@pytest.mark.parametrize("call, args, error, keywords", [
    (lambda: vrv.Scene.from_file("no/such/scene.toml"), ["--scene", "no/such/scene.toml"], FileNotFoundError, False),
    (lambda: vrv.Scene.from_file("/"), ["--scene", "/"], IsADirectoryError, False),
    (lambda: vrv.Scene.default().reference([0, 0, -3], [0, 0, 1], tol=-1), ["--tol", "-1"], ValueError, True),
    (lambda: vrv.Scene.default().discrete([0, 0, -3], [0, 0, 1], method="alpah"), ["--method", "alpah"], ValueError,
     True),
    (lambda: vrv.Scene.default().discrete([0, 0, -3], [0, 0, 1], method="riemann", correction="lacroute"),
     ["--method", "riemann", "--correction", "lacroute"], ValueError, True),
    (lambda: vrv.Scene.default().discrete([0, 0, -3], [0, 0, 1], method="alpha", strategy="step"),
     ["--method", "alpha", "--strategy", "step"], ValueError, True),
    (lambda: vrv.Scene.default().discrete([0, 0, -3], [0, 0, 1], method="alpha", table_lookup="uncentred"),
     ["--method", "alpha", "--table-lookup", "uncentred"], ValueError, True),
])
def test_bad_input_raises_the_command_lines_message(call, args, error, keywords):
    code, _, expected = cli("ray", "--origin=0,0,-3", "--direction=0,0,1", *args)
    assert code == 2 and expected
    with pytest.raises(error) as e:
        call()
    assert str(e.value) == (as_keywords(expected) if keywords else expected)
    if keywords:
        assert "--" not in str(e.value) and "--" in expected


def test_bad_scene_text_and_rays_raise_value_error():
    with pytest.raises(ValueError, match=r"^<toml>: field: missing"):
        vrv.Scene.from_toml("[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n")
    scene = vrv.Scene.default()
    with pytest.raises(ValueError, match=r"^rays\[1\]: ray direction is zero$"):
        scene.reference([[0, 0, -3], [0, 0, -3]], [[0, 0, 1], [0, 0, 0]])
    with pytest.raises(ValueError, match=r"^origins: expected an array of shape \(\.\.\., 3\)$"):
        scene.reference(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"^directions: shape differs"):
        scene.reference(np.zeros((4, 3)), np.ones((5, 3)))
    with pytest.raises(ValueError, match=r"^rays\[0\]: ray origin is not finite$"):
        scene.reference([np.nan, 0, 0], [1, 0, 0])
    # numpy cast a complex ray to its real part (a warning only) and booleans to 0 and 1.
    with pytest.raises(ValueError, match=r"^origins: dtype complex128 is not real numbers"):
        scene.reference(np.array([0, 0, -3 + 1j]), [0, 0, 1])
    with pytest.raises(ValueError, match=r"^directions: dtype bool is not real numbers"):
        scene.discrete([0, 0, -3], np.array([False, False, True]), method="trapezoid", step=0.1)
    # What numpy converts to numbers is taken: object arrays of numbers, integers past int64.
    assert scene.reference(np.array([0, 0, -3], dtype=object), [0, 0, 1])["value"] == \
        scene.reference([0.0, 0.0, -3.0], [0, 0, 1])["value"]
    assert np.isfinite(scene.reference([[-10**20, 0, 0]], [[1, 0, 0]])["value"]).all()
    with pytest.raises(TypeError, match=r"^origins: expected an array of numbers, got str$"):
        scene.reference("abc", [0, 0, 1])
    with pytest.raises(ValueError, match=r"^origins: expected an array of shape"):
        scene.reference(None, [0, 0, 1])
    with pytest.raises(ValueError, match=r"^width: must be in \[1, 16384\], got 0$"):
        scene.render(width=0)
    with pytest.raises(ValueError, match=r"^rate: applies to a discrete raycast only; add method "):
        scene.render(rate=2)
    with pytest.raises(TypeError):
        scene.render(method="riemann", sped=0.1)
    # A misspelt keyword is refused even when None (it was dropped unread, as if never given).
    with pytest.raises(TypeError, match=r"^unexpected keyword argument 'sped'$"):
        scene.discrete([0, 0, -3], [0, 0, 1], method="riemann", step=0.1, sped=None)


def errors_and_order(images, reference, steps):
    rms = [np.sqrt(np.mean((image - reference) ** 2)) for image in images]
    return rms, np.polyfit(np.log(steps), np.log(rms), 1)[0]


def test_numpy_raycaster_is_second_order_and_a_half_step_offset_is_caught():
    scene = vrv.Scene.default()
    origins, directions = scene.rays(width=24, height=24)
    reference = scene.render(width=24, height=24, tol=1e-10)
    steps = [0.08, 0.04, 0.02, 0.01]
    rms, order = errors_and_order([numpy_raycaster.render(origins, directions, h) for h in steps], reference, steps)
    assert 1.8 < order < 2.2, (rms, order)
    assert rms[-1] < 1e-4
    planted = [numpy_raycaster.render(origins, directions, h, offset=0.0) for h in steps]
    rms_planted, order_planted = errors_and_order(planted, reference, steps)
    assert order_planted < 1.2, (rms_planted, order_planted)  # caught: first order, not second


def keyword_defaults(function):
    """{keyword: default text} from a pybind11 function's signature line."""
    signature = function.__doc__.splitlines()[0]
    return dict(re.findall(r"(\w+): [^=,]+(?:\[[^\]]*\])? = ('[^']*'|[^,)]+)", signature))


def flag_defaults(command):
    """{--flag: default text} from `vrv COMMAND --help` (CLI11's FLAG TYPE=default)."""
    code, out, err = cli(command, "--help")
    assert code == 0, err
    return dict(re.findall(r"^\s+(--[\w-]+) [A-Z]+=(\S+)", out, re.MULTILINE))


@pytest.mark.parametrize("function, command, pairs", [
    (vrv.verify, "verify", {"tol": "--tol", "order_tolerance": "--order-tolerance", "order_metric": "--order-metric",
                            "alpha": "--alpha", "max_work": "--max-work"}),
    (vrv.plan, "plan", {"metric": "--metric", "rules": "--rules", "strategy": "--strategy", "width": "--width",
                        "height": "--height", "max_work": "--max-work"}),
    (vrv.Scene.reference, "ray", {"tol": "--tol", "max_work": "--max-work"}),
    (vrv.Scene.render, "render", {"tol": "--tol"}),
])
def test_keyword_defaults_are_the_command_lines(function, command, pairs):
    # Both adapters take their defaults from the library's option structs: a default spelled again
    # in either would drift.  (render's tol is None, so that it is refused with a method: its
    # docstring states the default.)
    keywords, flags = keyword_defaults(function), flag_defaults(command)
    if function is vrv.Scene.render:
        keywords["tol"] = re.search(r"to tol, default ([^;]+);", function.__doc__).group(1)
    for keyword, flag in pairs.items():
        python, shell = keywords[keyword], flags[flag]
        if python.startswith("'"):
            assert python.strip("'") == shell, (keyword, python, shell)
        else:
            assert float(python) == float(shell), (keyword, python, shell)


@pytest.mark.parametrize("command, flag, call, offered", [
    ("verify", "--alpha", lambda: vrv.verify(vrv.Scene.default(), [], [], alpha="bogus"), r"is not one of (.*)$"),
    ("plan", "--strategy", lambda: vrv.plan(vrv.Scene.default(), 1e-3, strategy="bogus"), r"\((.*)\)$"),
])
def test_help_offers_the_parsers_choices(command, flag, call, offered):
    # The choices a refusal offers come from the option's name table; its help is prose that must
    # name each of them too.
    with pytest.raises(ValueError) as e:
        call()
    choices = re.search(offered, str(e.value)).group(1).split(", ")
    code, out, err = cli(command, "--help")
    assert code == 0, err
    line = next(l for l in out.splitlines() if l.strip().startswith(flag + " "))
    for choice in choices:
        assert re.search(rf"\b{choice}\b", line), (flag, choice, line)
