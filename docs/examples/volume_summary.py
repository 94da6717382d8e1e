#!/usr/bin/env python3
"""Summarise the sets of docs/examples/verify_volume.sh: what `vrv verify` said, set by set.

    /usr/bin/python3 volume_summary.py OUT_DIR   -> Markdown on stdout, OUT_DIR/summary.json

Per set (OUT_DIR/<set>/): verify's exit code, verdict and orders (verify.json), the RMS per
region and step and the local orders between successive steps (verify/errors.json), the three
nearest of vrv's models (verify.json "diagnosis"), the faults and conventions named and the best
fitted fault,
and the largest relative difference of numpy's recomputation (figures.json, vtk_figures.py).
Nothing is computed here that verify or vtk_figures.py did not already write, except the local
orders log(e_k / e_k+1) / log(h_k / h_k+1).
"""
import json
import math
import sys
from pathlib import Path


def local_orders(steps, errors):
    return [math.log(a / b) / math.log(g / k) if a > 0 and b > 0 else None
            for a, b, g, k in zip(errors, errors[1:], steps, steps[1:])]


def model(m):
    return {"placement": m["placement"], "rule": m["rule"], "opacity": m["opacity"], "color": m["color"],
            "table": m["table"], "rms": m["rms"]}


def summarise(d):
    v = json.loads((d / "verify.json").read_text())
    errors = json.loads((d / "verify" / "errors.json").read_text())
    steps = sorted({r["step"] for r in errors}, reverse=True)
    regions = {}
    for region in ("all", "interior", "silhouette"):
        rms = [next(r["rms"] for r in errors if r["step"] == h and r["region"] == region) for h in steps]
        regions[region] = {"rms": rms, "local_orders": local_orders(steps, rms)}
    orders = {o["kind"]: o["order"] for o in v["orders"]}
    fits = sorted(v["fault_fits"], key=lambda f: -(f["confirmed"] if f["confirmed"] is not None else -1e9))
    figures = json.loads((d / "figures.json").read_text())
    return {
        "set": d.name,
        "exit": int((d / "verify.exit").read_text()),
        "verdict": v["verdict"],
        "reason": v["verdict_reason"],
        "order": orders.get("reference"),
        "self_order": orders.get("self"),
        "steps": steps,
        "regions": regions,
        "pixels": {r: next(x["pixels"] for x in errors if x["region"] == r) for r in ("interior", "silhouette")},
        "reference_max_error_estimate": v["reference"]["max_error_estimate"],
        "nearest_models": [model(m) for m in v["diagnosis"][:3]],
        "faults": [{"name": f["name"], "behaves_like": f["behaves_like"], "evidence": f["evidence"]} for f in v["faults"]],
        "conventions": [{"name": c["name"], "evidence": c["evidence"]} for c in v["conventions"]],
        "best_fault_fit": {k: fits[0][k] for k in ("id", "description", "value", "explained", "confirmed")} if fits else None,
        "numpy_largest_relative_difference": figures["largest_relative_difference"],
    }


def fmt(x):
    return "–" if x is None else f"{x:.3g}"


def markdown(s):
    lines = [f"## {s['set']}", "",
             f"- verify exit {s['exit']}: **{s['verdict']}** ({s['reason']})",
             f"- order (whole-image RMS) {fmt(s['order'])}, self-convergence order {fmt(s['self_order'])}",
             f"- reference: max error estimate {s['reference_max_error_estimate']:.2g}; numpy recomputation: "
             f"largest relative difference {s['numpy_largest_relative_difference']:.1e}", "",
             "| H (mm) | " + " | ".join(f"{h:g}" for h in s["steps"]) + " |",
             "| :-- | " + " | ".join("--:" for _ in s["steps"]) + " |"]
    for region, r in s["regions"].items():
        count = f" ({s['pixels'][region]} px)" if region in s["pixels"] else ""
        lines.append(f"| RMS {region}{count} | " + " | ".join(fmt(x) for x in r["rms"]) + " |")
        lines.append(f"| local order {region} | – | " + " | ".join(fmt(x) for x in r["local_orders"]) + " |")
    lines += ["", "Nearest of vrv's models (RMS over the images):"]
    lines += [f"{k + 1}. `{m['placement']}`, `{m['rule']}`, {m['opacity']}, colour {m['color']}, table {m['table']}: "
              f"{m['rms']:.4g}" for k, m in enumerate(s["nearest_models"])]
    lines += ["", "Faults named:" if s["faults"] else "Faults named: none"]
    lines += [f"- *{f['name']}*: {f['evidence']}" for f in s["faults"]]
    lines += ["", "Conventions named (against the expected order):" if s["conventions"] else "Conventions named: none"]
    lines += [f"- *{c['name']}*: {c['evidence']}" for c in s["conventions"]]
    if s["best_fault_fit"]:
        b = s["best_fault_fit"]
        lines.append(f"\nBest fitted fault: {b['description']} (`{b['id']}`, value {fmt(b['value'])}), explains "
                     f"{fmt(b['explained'])} on the fitted pixels, {fmt(b['confirmed'])} on all")
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) != 1:
        sys.exit(__doc__)
    out = Path(argv[0])
    sets = [summarise(d) for d in sorted(out.iterdir()) if (d / "verify.json").is_file()]
    (out / "summary.json").write_text(json.dumps(sets, indent=1) + "\n")
    print("\n".join(markdown(s) for s in sets))


if __name__ == "__main__":
    main(sys.argv[1:])
