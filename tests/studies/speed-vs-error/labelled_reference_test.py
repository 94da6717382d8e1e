#!/usr/bin/python3
"""A labelled reference in a speed_vs_error study keeps its checks (a defect found by hand: the
checks knew the reference by its series name, so `label = "tight"` dropped its 14 checks (12 per tolerance, 2 per target) and
counted it as a discrete method reaching a target).

- With the label the reference's rows are still checked (within its estimate, its tolerance met,
  each target reached), under the label's name, and the discrete target is met by discrete
  methods alone.
- With a discrete target no discrete method reaches (1e-6), the study fails on it although the
  labelled reference reaches it.

    labelled_reference_test.py VRV STUDY_TOML OUT_DIR
"""
import csv
import shutil
import subprocess
import sys
from pathlib import Path

vrv, study, out = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)
text = study.read_text()
REFERENCE = 'method = "reference"\n'
assert text.count(REFERENCE) == 1, f"{study}: expected one reference method"
labelled = text.replace(REFERENCE, REFERENCE + 'label = "tight"\n')


def run(name, text):
    path = out / f"{name}.toml"
    path.write_text(text)
    r = subprocess.run([vrv, "study", str(path), "--quick", "--quiet", "--no-plots", "--out", str(out / name)],
                       capture_output=True, text=True, timeout=300)
    return r, out / name / name / "checks.csv"


r, checks_csv = run("labelled", labelled)
assert r.returncode == 0, f"labelled study: exit {r.returncode}\n{r.stderr}"
checks = {row["check"]: row for row in csv.DictReader(checks_csv.open())}
for tol in ["0.01", "0.0001", "1e-06", "1e-08", "1e-10", "1e-12"]:
    for what in ["error within its estimate", "meets its tolerance"]:
        name = f"tight tol={tol}: {what}"
        assert name in checks, f"missing check '{name}'; have {sorted(checks)}"
        assert checks[name]["pass"] == "true", checks[name]
assert any(c.startswith("target 0.001: tight tol=") for c in checks), sorted(checks)
discrete = checks["target 0.001: reached by a discrete method"]
assert "tight" not in discrete["detail"], f"the reference counted as a discrete method: {discrete['detail']}"

target = "discrete_targets = [1e-3]"
assert target in labelled
r, _ = run("tightened", labelled.replace(target, "discrete_targets = [1e-6]"))
assert r.returncode == 1, f"tightened study: expected exit 1, got {r.returncode}\n{r.stderr}"
assert "FAILED" in r.stderr and "target 1e-06: reached by a discrete method" in r.stderr, r.stderr
print("labelled reference: its 12 tolerance checks and its target checks kept; a 1e-6 discrete target fails although the reference reaches it")
