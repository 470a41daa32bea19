#!/usr/bin/env python3
"""ctest "view: ...": `sva view` pages in a real browser (Debian's chromium, headless, software WebGL).

A tiny scene is simulated and trained, `sva eval` writes its per-reading CSV, and `sva view` writes the page of one
of its trials. Chromium then loads the page with "#selftest" (the page moves its own slider over every reading and
reports what it shows) and takes a screenshot. Checked: no console or script errors; the counts of meshes, contacts
and hypotheses at every reading; the top object's probability at every reading equals the eval CSV's; the
screenshot is not blank. Exit 77 (skipped) when no chromium is installed.

    usage: browser_test.py SVA_BIN WORK_DIR
"""

import csv
import html
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

SKIP = 77


def run(*args, **kw):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=300, **kw)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} failed ({r.returncode}):\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return r


def chromium():
    exe = os.environ.get("SVA_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        print("view: no chromium (scripts/setup.sh installs Debian's): skipped")
        sys.exit(SKIP)
    return exe


def browser(exe, *args):
    # Root in a container needs --no-sandbox; WebGL runs on SwiftShader (no GPU).
    flags = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
             "--disable-dev-shm-usage", "--virtual-time-budget=20000", "--window-size=1100,700"]
    return run(exe, *flags, *args)


def selftest(exe, page):
    """What the page reports after moving its slider over every reading (its #selftest hook)."""
    dom = browser(exe, "--dump-dom", page.as_uri() + "#selftest").stdout
    found = re.search(r'<pre id="sva-selftest">(.*?)</pre>', dom, re.S)
    assert found and found.group(1).strip(), f"{page.name} reported nothing:\n{dom[-1500:]}"
    return json.loads(html.unescape(found.group(1)))


def png_pixels(path):
    import matplotlib.image

    return matplotlib.image.imread(str(path))


def main():
    sva, work = Path(sys.argv[1]), Path(sys.argv[2])
    exe = chromium()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    run(sva, "simulate", "--scene", "tiny", "--seed", "3", "--train", "12", "--test", "5", "--out", work)
    run(sva, "train", "--data", work / "train.svad", "--out", work / "map.svam")
    common = ["--map", work / "map.svam", "--data", work / "test.svad", "--max-readings", "6", "--seed", "2",
              "--backend", "cpu"]
    run(sva, "eval", *common, "--trials", "2", "--csv", work / "eval.csv", "--html", work / "html")
    page = work / "trial1.html"
    run(sva, "view", *common, "--trial", "1", "--out", page)

    report = selftest(exe, page)
    # sva eval --html: the same trial's page shows the same, and the index links every trial's.
    assert selftest(exe, work / "html" / "trial-1.html") == report
    index = (work / "html" / "index.html").read_text()
    assert 'href="trial-0.html"' in index and 'href="trial-1.html"' in index and "accuracy.png" in index
    assert (work / "html" / "accuracy.png").stat().st_size > 1000 and (work / "html" / "accuracy.svg").is_file()
    assert report["errors"] == [], f"console or script errors: {report['errors']}"
    # Hovering over a touch shows its pressure image.
    assert report["hover"]["text"].startswith("touch 6:"), report["hover"]
    assert report["hover"]["coloured"] > 1000, report["hover"]
    rows = [r for r in csv.DictReader(open(work / "eval.csv")) if r["trial"] == "1"]
    assert len(report["steps"]) == len(rows) == 6, (len(report["steps"]), len(rows))
    for step, row in zip(report["steps"], rows):
        i = step["reading"]
        counts = step["counts"]
        assert counts["contacts"] == i, step
        assert counts["meshes"] == 1 + counts["hypotheses"], step  # the truth's ghost and the hypotheses shown
        assert (counts["hypotheses"] >= 1) == (row["pose_valid"] == "1"), (step, row["pose_valid"])
        assert step["bars"] >= 2, step  # every object's bar and "none of these"
        # The probabilities the slider shows are the evaluation's, reading by reading.
        assert abs(step["top_probability"] - float(row["top_probability"])) <= 1e-8, (i, step, row)
        assert abs(step["p_unknown"] - float(row["p_unknown"])) <= 1e-8, (i, step, row)

    shot = work / "trial1.png"
    browser(exe, f"--screenshot={shot}", page.as_uri())
    pixels = png_pixels(shot)
    spread = float(pixels[..., :3].std())
    assert spread > 0.05, f"the screenshot is nearly blank (pixel spread {spread:.4f})"
    # The 3-D view itself drew something: its area (left of the side panel) is not one colour.
    view = pixels[80:600, 20:700, :3]
    assert float(view.std()) > 0.02, f"the 3-D view is blank (pixel spread {float(view.std()):.4f})"
    print(f"view: {page.stat().st_size} bytes; 6 readings checked against the eval CSV; screenshot spread {spread:.3f}")


if __name__ == "__main__":
    main()
