#!/usr/bin/env python3
"""Runs a docs page's commands as a newcomer would: every fenced ```sh or ```python block preceded by
an HTML comment `<!-- test: run [exit=N] [expect="text"] ... -->`, in order, in a fresh scratch
folder that holds `build` (the build tree) and `docs` (the source tree's) as the page's commands
name them.  Each block must exit N (default 0) and print (stdout or stderr) every `expect` text.

    docs_page_test.py PAGE BUILD_DIR SOURCE_DIR SCRATCH_DIR PYTHON

`python3` in the blocks is PYTHON (the interpreter the build's module is for).
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

MARK = re.compile(r"<!-- test: run(?P<args>[^>]*)-->\s*\n```(?P<lang>sh|python)\n(?P<code>.*?)\n```", re.S)


def blocks(page):
    found = []
    for m in MARK.finditer(page):
        args = shlex.split(m["args"])
        exit_code = next((int(a[5:]) for a in args if a.startswith("exit=")), 0)
        expects = [a[7:] for a in args if a.startswith("expect=")]
        line = page[:m.start()].count("\n") + 1
        found.append((line, m["lang"], m["code"], exit_code, expects))
    return found


def main():
    page_path, build, source, scratch, python = sys.argv[1:6]
    page = Path(page_path).read_text()
    scratch = Path(scratch)
    shutil.rmtree(scratch, ignore_errors=True)
    (scratch / "bin").mkdir(parents=True)
    os.symlink(Path(build).resolve(), scratch / "build")
    os.symlink((Path(source) / "docs").resolve(), scratch / "docs")
    os.symlink(python, scratch / "bin" / "python3")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VRV_IMAGE_MODULE")}
    env["PATH"] = f"{scratch / 'bin'}:{env.get('PATH', '/usr/bin:/bin')}"
    env["XDG_CACHE_HOME"] = str(scratch / "cache")  # no reference cache shared with other runs
    todo = blocks(page)
    if not todo:
        sys.exit(f"{page_path}: no block marked <!-- test: run -->")
    start = time.monotonic()
    for line, lang, code, exit_code, expects in todo:
        command = ["bash", "-e", "-o", "pipefail", "-c", code] if lang == "sh" else [python, "-c", code]
        began = time.monotonic()
        p = subprocess.run(command, cwd=scratch, env=env, capture_output=True, text=True)
        said = p.stdout + p.stderr
        if p.returncode != exit_code:
            sys.exit(f"{page_path}:{line}: exit {p.returncode}, the page expects {exit_code}\n{said}")
        for text in expects:
            if text not in said:
                sys.exit(f"{page_path}:{line}: the output lacks {text!r}\n{said}")
        print(f"{page_path}:{line}: {lang} block ok (exit {p.returncode}, {time.monotonic() - began:.1f} s)")
    print(f"{len(todo)} blocks in {time.monotonic() - start:.1f} s")


if __name__ == "__main__":
    main()
