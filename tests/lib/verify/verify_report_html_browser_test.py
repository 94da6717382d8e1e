"""vrv verify --report in a real browser (Debian's chromium, headless): CTest `browser.verify_report`.

A renderer with a floor fault (vrv's own raycaster with early termination at opacity 0.5, so the
fitted fault catalogue names it with its parameter) is rendered at four steps into files whose
names hold HTML ("<b id=injected>..."), verified with --report, and the page is loaded headless
with a small script added to a copy of it that writes what the browser shows into the DOM
(--dump-dom): the verdict text, the named fault, how many error maps were decoded
(naturalWidth > 0), the plot's points, which resources were requested.  The checks are then run on
broken copies of the page (an image's data cut, an external image, the verdict removed) and must
fail there: a checker that passes anything proves nothing.

Usage: verify_report_html_browser_test.py VRV SOURCE_DIR WORK_DIR CHROMIUM
"""
import html
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

VRV, SRC, WORK, CHROMIUM = (Path(a) for a in sys.argv[1:5])
SCENE = SRC / "studies" / "gate" / "ml-oblique.toml"
STEPS = [0.1, 0.05, 0.025, 0.0125]
HOSTILE = "<b id=injected>&'h"  # a file name that is HTML: the page must show it, not run it

PROBE = """<script>
window.addEventListener("load", () => {
  const maps = [...document.querySelectorAll("img.error-map")];
  const text = id => { const e = document.getElementById(id); return e ? e.innerText : null; };
  const result = {
    verdict: text("verdict-text"),
    fault: text("named-fault"),
    maps: maps.length,
    decoded: maps.filter(i => i.complete && i.naturalWidth > 0).length,
    widths: maps.map(i => i.naturalWidth),
    reference_decoded: [...document.querySelectorAll("img.reference")].filter(i => i.naturalWidth > 0).length,
    plot_points: document.querySelectorAll("#convergence-plot circle").length,
    catalogue_rows: document.querySelectorAll("#catalogue-ranking tbody tr").length,
    sections: [...document.querySelectorAll("header, section")].map(e => e.id),
    resources: performance.getEntriesByType("resource").map(e => e.name).filter(n => !n.startsWith("data:")),
    injected: document.getElementById("injected") !== null,
    body: document.body.innerText,
  };
  const out = document.createElement("pre");
  out.id = "vrv-probe";
  out.textContent = JSON.stringify(result);
  document.body.appendChild(out);
});
</script>"""


def run(cmd, ok=(0,)):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600)
    if p.returncode not in ok:
        sys.exit(f"FAIL: {' '.join(map(str, cmd))} exited {p.returncode}\n{p.stderr}")
    return p


def browse(page: Path) -> dict:
    """What chromium shows of `page` (with the probe added to a copy of it)."""
    probed = page.with_name(page.stem + ".probed.html")
    probed.write_text(page.read_text(encoding="utf-8").replace("</body>", PROBE + "</body>"), encoding="utf-8")
    profile = WORK / "chromium-profile"
    shutil.rmtree(profile, ignore_errors=True)
    p = run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             f"--user-data-dir={profile}", "--virtual-time-budget=5000", "--dump-dom", probed.resolve().as_uri()])
    m = re.search(r'<pre id="vrv-probe">(.*?)</pre>', p.stdout, re.S)
    if not m:
        return {"probe": "missing"}
    return json.loads(html.unescape(m.group(1)))


def problems(page: Path, expect_maps: int, fault_words: list):
    """Everything wrong with the page as the browser shows it (empty for a good page), and what it showed."""
    text = page.read_text(encoding="utf-8")
    bad = []
    # Static: nothing the page could fetch (the SVG's namespace is a name, not a request).
    for attr, url in re.findall(r'\b(src|href)\s*=\s*"([^"]*)"', text):
        if not url.startswith("data:image/png;base64,") and not url.startswith("#"):
            bad.append(f"{attr} {url[:60]} is not inline")
    if re.search(r"<(script|link|iframe|object)\b", text, re.I):
        bad.append("the page has a script, link, iframe or object")
    seen = browse(page)
    if seen.get("probe") == "missing":
        return bad + ["the probe wrote nothing"], seen
    if not seen["verdict"]:
        bad.append("no verdict shown")
    if not seen["fault"] or not all(w in seen["fault"] for w in fault_words):
        bad.append(f"the named fault shown is {seen['fault']!r}, not {fault_words}")
    if seen["maps"] != expect_maps or seen["decoded"] != expect_maps:
        bad.append(f"{seen['decoded']} of {seen['maps']} error maps decoded, {expect_maps} expected")
    if seen["reference_decoded"] != 1:
        bad.append("the reference image not decoded")
    if seen["plot_points"] < 2 * len(STEPS) - 1:
        bad.append(f"the plot shows {seen['plot_points']} points")
    if seen["resources"]:
        bad.append(f"requests: {seen['resources']}")
    if seen["injected"] or HOSTILE not in seen["body"]:
        bad.append("a file name was not escaped (or not shown)")
    order = ["verdict", "convergence", "error-maps", "regions", "catalogue", "reproduce"]
    if [s for s in seen["sections"] if s in order] != order:
        bad.append(f"sections in the order {seen['sections']}")
    return bad, seen


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    images = []
    for h in STEPS:
        image = WORK / f"{HOSTILE}{h}.exr"
        run([VRV, "render", "--scene", SCENE, "--method", "alpha", "--strategy", "inviwo", "--step", h,
             "--termination", "0.5", "-o", image, "--quiet"])
        images.append(image)
    page = WORK / "report.html"
    p = run([VRV, "verify", "--scene", SCENE, *images, "--steps", ",".join(map(str, STEPS)), "--expected-order", 2,
             "--cache-dir", WORK / "cache", "--report", page, "--quiet"], ok=(1,))
    summary = json.loads(p.stdout)
    named = [f["behaves_like"] for f in summary["faults"] if f["name"] == "fitted fault"]
    assert named and "early termination" in named[0], summary["faults"]
    fault_words = ["early termination", "0.5"]
    first = page.read_text(encoding="utf-8").index("<b>Fault: ")
    assert page.read_text(encoding="utf-8").startswith("<b>Fault: early termination", first), "the fitted fault is not first"

    bad, seen = problems(page, len(STEPS), fault_words)
    assert not bad, f"the good page: {bad}"
    assert seen["verdict"] == summary["verdict"], seen["verdict"]
    assert seen["catalogue_rows"] == len(summary["fault_fits"]) > 0, seen["catalogue_rows"]
    print(f"good page: verdict {seen['verdict']!r}; fault {seen['fault'].splitlines()[0]!r}; "
          f"{seen['decoded']} error maps decoded, widths {seen['widths']}; no requests")

    # Broken copies: each must be caught.
    text = page.read_text(encoding="utf-8")
    first = text.index("data:image/png;base64,") + len("data:image/png;base64,")
    broken = {
        "cut image": text[:first + 40] + text[text.index('"', first):],
        "external image": text.replace("</body>", '<img src="http://127.0.0.1:9/x.png"></body>'),
        "no verdict": text.replace('id="verdict-text"', 'id="something-else"'),
    }
    for name, body in broken.items():
        copy = WORK / f"broken-{name.replace(' ', '-')}.html"
        copy.write_text(body, encoding="utf-8")
        found, _ = problems(copy, len(STEPS), fault_words)
        assert found, f"the checks pass a page with {name}"
        print(f"broken page ({name}): caught: {found[0]}")
    print("PASS")


if __name__ == "__main__":
    main()
