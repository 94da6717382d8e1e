#!/usr/bin/python3
"""A study of an RGB scene is its kind's study of each channel (studies/engine/channel_study.h).

- The RGB convergence study (rgb-convergence.toml) passes; each channel's folder holds, byte for
  byte, the tables of the grey study whose transfer function and background are that channel's
  (named as the channel's study is, rgb-convergence-red and so on: its LaTeX labels).
- Its checks are each channel's, named "red: ..." and so on (the runner's reference audit once);
  its plots are each channel's, pointed at that channel's tables; its work estimate is three
  times the grey study's.
- A projections study of an RGB scene is refused in one line (exit 2), nothing written; so is a
  study whose checks hold for the red channel but not the green one, before anything runs, naming
  the channel (and one whose red channel fails them), and a file mixing grey and RGB scenes.

    channel_study_test.py VRV SRC OUT_DIR
"""
import csv
import filecmp
import json
import os
import re
import shutil
import subprocess
import sys

vrv, src, out = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
rgb_file = os.path.join(src, "tests/studies/engine/rgb-convergence.toml")
rgb_text = open(rgb_file).read()
CHANNELS = ("red", "green", "blue")


def run(*args, expect=0):
    r = subprocess.run([vrv, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == expect, (args, r.returncode, r.stderr)
    return r


def column(text, key, c):
    """The grey text of channel c: each [v, r, g, b] point of `key` as [v, channel c]."""
    line = re.search(rf"^{key} = (.*)$", text, re.M)
    points = json.loads(line.group(1))
    grey = [[p[0], p[1 + c]] for p in points]
    return text.replace(line.group(0), f"{key} = {json.dumps(grey)}")


def grey_study(c):
    text = column(rgb_text, "emission", c)
    background = json.loads(re.search(r"^color = (.*)$", text, re.M).group(1))
    text = re.sub(r"^color = .*$", f"intensity = {background[c]!r}", text, flags=re.M)
    text = re.sub(r"^description = .*$", "", text, flags=re.M)
    path = os.path.join(out, f"rgb-convergence-{CHANNELS[c]}.toml")
    open(path, "w").write(text)
    return path


run("study", rgb_file, "--quick", "--no-plots", "--quiet", "--out", out)
rgb = os.path.join(out, "rgb-convergence")
grey_out = os.path.join(out, "grey")  # the grey studies carry the channel's study name (LaTeX labels)
checked = 0
for c, name in enumerate(CHANNELS):
    grey = grey_study(c)
    run("study", grey, "--quick", "--no-plots", "--quiet", "--out", grey_out)
    grey_dir = os.path.join(grey_out, f"rgb-convergence-{name}")
    tables = sorted(f for f in os.listdir(grey_dir) if f not in ("meta.json", "plots.json") and not f.startswith("checks."))
    assert "errors.csv" in tables and "orders.csv" in tables, tables
    assert sorted(os.listdir(os.path.join(rgb, name))) == tables, (name, os.listdir(os.path.join(rgb, name)), tables)
    for f in tables:
        assert filecmp.cmp(os.path.join(grey_dir, f), os.path.join(rgb, name, f), shallow=False), (name, f)
        checked += 1
    # Its checks are the grey study's, named by channel.
    grey_checks = list(csv.DictReader(open(os.path.join(grey_dir, "checks.csv"))))
    rgb_checks = list(csv.DictReader(open(os.path.join(rgb, "checks.csv"))))
    mine = [r for r in rgb_checks if r["check"].startswith(name + ": ")]
    theirs = [r for r in grey_checks if r["check"] != "reference_within_tolerance"]
    assert [r["check"] for r in mine] == [f"{name}: {r['check']}" for r in theirs], (mine, theirs)
    assert [r["value"] for r in mine] == [r["value"] for r in theirs], name
meta = json.load(open(os.path.join(rgb, "meta.json")))
assert [meta["parameters"]["run"]["channels"][n]["channel"] for n in CHANNELS] == [0, 1, 2], meta["parameters"]["run"]
# the three channels differ (else the test above shows nothing)
errors = [open(os.path.join(rgb, n, "errors.csv")).read() for n in CHANNELS]
assert len(set(errors)) == 3, "the channels' tables should differ"
audit = [r for r in csv.DictReader(open(os.path.join(rgb, "checks.csv"))) if not r["check"].split(": ")[0] in CHANNELS]
assert len(audit) == 1, audit

# The plots: each channel's, named by it, on its own tables (drawn from the top folder).
plots = json.load(open(os.path.join(rgb, "plots.json")))["plots"]
assert plots and all(p["name"].split("_")[0] in CHANNELS for p in plots), plots
for p in plots:
    assert p["csv"].startswith(p["name"].split("_")[0] + "/"), p
    assert os.path.exists(os.path.join(rgb, p["csv"])), p
assert not any(os.path.exists(os.path.join(rgb, n, "plots.json")) for n in CHANNELS)

# The work: three times the grey study's.
rgb_work = json.loads(run("study", rgb_file, "--quick", "--estimate").stdout)["evaluations"]
grey_work = json.loads(run("study", grey_study(0), "--quick", "--estimate").stdout)["evaluations"]
assert rgb_work == 3 * grey_work, (rgb_work, grey_work)

# A projections study of an RGB scene: refused, nothing written.
projections = open(os.path.join(src, "studies/projections/projections.toml")).read()
projections = re.sub(r"^emission = .*$", "emission = [[0.0, 0.0, 0.1, 0.2], [1.0, 1.0, 0.5, 0.3]]",
                     projections, count=1, flags=re.M)
bad = os.path.join(out, "rgb-projections.toml")
open(bad, "w").write(projections)
r = run("study", bad, "--quick", "--out", out, expect=2)
assert r.stderr.count("\n") == 1 and "rgb-projections.toml: scene: the scene is RGB" in r.stderr, r.stderr
assert "(studying" not in r.stderr, "an error every channel makes alike names none: " + r.stderr
assert not os.path.exists(os.path.join(out, "rgb-projections"))
# A check of the file that holds for red but not for green: refused before anything runs.
sampling = open(os.path.join(src, "studies/sampling/sampling.toml")).read()
assert "emission = [[0.0, 0.0], [1.0, 1.0]]\n" in sampling
sampling = sampling.replace("emission = [[0.0, 0.0], [1.0, 1.0]]\n", "emission = [[0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 0.5, 0.25]]\n")
bad = os.path.join(out, "rgb-sampling.toml")
open(bad, "w").write(sampling)
r = run("study", bad, "--quick", "--out", out, expect=2)
assert r.stderr.count("\n") == 1 and "checks.closed_form_kappa" in r.stderr and "(studying the scene's green channel)" in r.stderr, r.stderr
assert not os.path.exists(os.path.join(out, "rgb-sampling")) and not os.path.exists(os.path.join(out, ".rgb-sampling.partial"))
# ... and the red channel's own errors name it too.
open(bad, "w").write(sampling.replace("[1.0, 1.0, 0.5, 0.25]", "[1.0, 1.5, 1.0, 1.0]"))
r = run("study", bad, "--quick", "--out", out, expect=2)
assert r.stderr.count("\n") == 1 and "checks.closed_form_kappa" in r.stderr and "(studying the scene's red channel)" in r.stderr, r.stderr

# Grey and RGB scenes in one file (hard-cases' second case RGB): refused naming the case.
hard = open(os.path.join(src, "studies/hard-cases/hard-cases.toml")).read()
grey_points = "emission = [[0.0, 0.0], [0.3, 0.1], [0.5, 1.0], [0.7, 0.2], [1.0, 0.5]]"
first = hard.index(grey_points)
second = hard.index(grey_points, first + 1)
hard = hard[:second] + "emission = [[0.0, 0.0, 0.0, 0.0], [0.3, 0.1, 0.2, 0.1], [0.5, 1.0, 0.5, 0.2], " \
    "[0.7, 0.2, 0.1, 0.4], [1.0, 0.5, 0.5, 0.5]]" + hard[second + len(grey_points):]
bad = os.path.join(out, "mixed-hard-cases.toml")
open(bad, "w").write(hard)
r = run("study", bad, "--quick", "--out", out, expect=2)
assert r.stderr.count("\n") == 1 and "case[1].scene: the scene is RGB and an earlier one grey" in r.stderr, r.stderr
assert not os.path.exists(os.path.join(out, "mixed-hard-cases"))
print(f"channel study: {checked} tables equal to the grey studies' byte for byte; {len(plots)} plots; work x3")
