#!/usr/bin/env python3
"""ctest "view: ...": `sva view` pages in a real browser (Debian's chromium, headless, software WebGL).

A tiny scene is simulated and trained, `sva eval` writes its per-reading CSV, and `sva view` writes the page of one
of its trials. Chromium then loads the page with "#selftest" (the page moves its own slider over every reading and
reports what it shows) and takes a screenshot. Checked: no console or script errors; the counts of meshes, contacts
and hypotheses at every reading; the top object's probability at every reading equals the eval CSV's; the
screenshot is not blank.

Hostile names (docs/view.md, "Names are text"): a scene whose scene and object names are event-handler markup,
"</script>", "<!--<script>", quotes and an RTL override, and a sessions file whose id holds control characters.
Each page (`sva eval --html`'s page of a trial and its index, and `sva view`'s page of the session) is loaded with
a probe around it: a script first in <head> that records dialogs, script errors and console errors, and one last
in <body> that reports what the page shows. Checked: nothing ran (no data-xss attribute, no dialog, no error, no
element the page does not make itself), and every name's text on the page is the name exactly as written.

Exit 77 (skipped) when no chromium is installed.

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


# Each payload, if it ran, marks the page (data-xss on <body>) or opens a dialog; the probe reports both.
MARK = "document.body.setAttribute('data-xss','{}')"
HOSTILE_OBJECTS = [
    '<img src=x onerror="' + MARK.format("img") + '">',
    "</script><script>" + MARK.format("script") + "</script>",
    "\"'><svg onload=\"" + MARK.format("attribute") + "\"> &amp; &lt;b&gt; ' \" `${alert(1)}`",
    "\u202egnp.exe die \u2013 \u043c\u044f\u0447 \u26bd",  # an RTL override, a dash, Cyrillic, an emoji
]
HOSTILE_SCENE = "<b onmouseover=alert(2)>scene</b><!--<script>"
# Scene names refuse control characters (docs/scene-format.md); a sessions file's id is any JSON string.
HOSTILE_ID = "id\u0007\u001b[31m\u0000<script>alert(3)</script>\u202e\u007f'\""

# First in <head>: dialogs, script errors and console errors, and a record of every element that the document
# gains with an "on..." attribute or of a tag the viewer never makes.
PROBE_HEAD = """<script>
window.__probe = { dialogs: [], errors: [], foreign: [] };
for (const f of ["alert", "confirm", "prompt", "print"])
  window[f] = (...a) => { window.__probe.dialogs.push(f + ": " + a.join(" ")); };
window.addEventListener("error", (e) => window.__probe.errors.push(String(e.message)), true);
const __consoleError = console.error.bind(console);
console.error = (...a) => { window.__probe.errors.push(a.map(String).join(" ")); __consoleError(...a); };
const __allowed = new Set(["SCRIPT", "CANVAS", "DIV", "SPAN", "B", "BR", "H1", "H2", "PRE", "INPUT", "MAIN", "ASIDE",
  "HEADER", "FOOTER", "BODY", "STYLE", "TITLE", "META", "HEAD", "HTML", "TABLE", "TBODY", "TR", "TD", "TH", "A",
  "IMG"]);
new MutationObserver((records) => {
  for (const r of records)
    for (const n of r.addedNodes) {
      if (n.nodeType !== 1) continue;
      for (const e of [n, ...n.querySelectorAll("*")])
        if (!__allowed.has(e.tagName) || [...e.attributes].some((a) => a.name.startsWith("on")))
          window.__probe.foreign.push(e.outerHTML.slice(0, 200));
    }
}).observe(document, { childList: true, subtree: true });
</script>"""

# Last in <body>: what the page shows, read from the DOM as text.
PROBE_TAIL = """<script>
const __text = (sel) => [...document.querySelectorAll(sel)].map((e) => e.textContent);
window.__probe.xss = document.body.getAttribute("data-xss");
window.__probe.out = {
  bar_names: __text("#bars .bar .name"),
  bar_titles: [...document.querySelectorAll("#bars .bar .name")].map((e) => e.getAttribute("title")),
  errors: __text("#errors"), estimate: __text("#errors b"), hypotheses: __text("#hypotheses"),
  title: __text("#title"), meta: __text("#meta"), h1: __text("h1"), cells: __text("td"),
  images: document.querySelectorAll("img").length,
};
const __pre = document.createElement("pre");
__pre.id = "sva-probe";
document.body.appendChild(__pre);
setTimeout(() => { __pre.textContent = JSON.stringify(window.__probe); }, 1000);
</script>"""


def probe(exe, page):
    """What a copy of PAGE with the probe around it reports after loading (and any load events having fired)."""
    text = page.read_text(encoding="utf-8")
    head, body = text.index("<head>") + len("<head>"), text.rindex("</body>")
    probed = page.with_name(page.stem + "-probed.html")
    probed.write_text(text[:head] + PROBE_HEAD + text[head:body] + PROBE_TAIL + text[body:], encoding="utf-8")
    dom = browser(exe, "--dump-dom", probed.as_uri()).stdout
    found = re.search(r'<pre id="sva-probe">(.*?)</pre>', dom, re.S)
    # No report: the probe never ran, e.g. a name ended the data's <script> early or left one open.
    assert found and found.group(1).strip(), f"{page.name}: the probe reported nothing:\n{dom[-1500:]}"
    report = json.loads(html.unescape(found.group(1)))
    assert report["xss"] is None, f"{page.name}: a name ran as script (data-xss={report['xss']!r})"
    assert report["dialogs"] == [], f"{page.name}: a name opened a dialog: {report['dialogs']}"
    assert report["errors"] == [], f"{page.name}: script or console errors: {report['errors']}"
    assert report["foreign"] == [], f"{page.name}: elements a name made: {report['foreign']}"
    return report["out"]


def hostile_names(sva, exe, work):
    """Names from files show as text, exactly as written, and run nothing: in the viewer and eval's index."""
    work.mkdir()
    objects = Path(os.environ.get("SVA_ASSETS", Path(__file__).resolve().parents[2] / "assets")) / "objects"
    meshes = ["die", "brick", "cube_r6", "cone"]
    scene = {"name": HOSTILE_SCENE, "objects": [{"name": n, "mesh": str(objects / f"{m}.glb"), "size_mm": 60}
                                                for n, m in zip(HOSTILE_OBJECTS, meshes)],
             "protocol": {"kind": "paper3d"}}
    (work / "scene.json").write_text(json.dumps(scene), encoding="utf-8")
    run(sva, "simulate", "--scene", work / "scene.json", "--seed", "3", "--train", "20", "--test", "4", "--out", work)
    run(sva, "train", "--data", work / "train.svad", "--out", work / "map.svam")
    common = ["--map", work / "map.svam", "--data", work / "test.svad", "--max-readings", "5", "--seed", "2",
              "--backend", "cpu"]
    run(sva, "eval", *common, "--trials", "2", "--csv", work / "eval.csv", "--html", work / "html")
    # The true object of each trial by its id (the names themselves are the subject here, not the CSV's quoting).
    truth = {int(r["trial"]): HOSTILE_OBJECTS[int(r["object"])] for r in csv.DictReader(open(work / "eval.csv", encoding="utf-8"))}

    # `sva eval --html`'s page of a trial (`sva view` writes the same): the scene's names in the title, the bars,
    # the estimate and the hypotheses.
    shown = probe(exe, work / "html" / "trial-0.html")
    assert shown["title"] == [f"{HOSTILE_SCENE} trial 0: {truth[0]}"], shown["title"]
    assert shown["meta"][0].startswith(f"scene {HOSTILE_SCENE} \u00b7 map "), shown["meta"]
    assert sorted(shown["bar_names"]) == sorted(HOSTILE_OBJECTS + ["none of these"]), shown["bar_names"]
    assert shown["bar_titles"] == shown["bar_names"], shown["bar_titles"]
    assert len(shown["estimate"]) == 1 and shown["estimate"][0] in HOSTILE_OBJECTS + ["no answer yet"], shown
    assert shown["errors"][0].startswith(f"estimate: {shown['estimate'][0]} (truth: {truth[0]})error: "), shown
    # "1. NAME ■ 41.0%" per hypothesis (lines apart by <br>, which has no text).
    any_name = "|".join(re.escape(n) for n in HOSTILE_OBJECTS)
    assert re.fullmatch(rf"(?:\d+\. (?:{any_name}) \u25a0 \d+\.\d%)+", shown["hypotheses"][0]), shown["hypotheses"]
    assert shown["images"] == 0, shown

    # eval's index: the scene in its heading, each trial's object and estimate in its cells.
    index = probe(exe, work / "html" / "index.html")
    assert index["h1"][0].startswith(f"{HOSTILE_SCENE}: 2 trials of 5 readings"), index["h1"]
    assert truth[0] in index["cells"] and truth[1] in index["cells"], index["cells"]
    assert index["images"] == 1, index  # the accuracy figure alone

    # A sessions file's id, control characters and all, in the page's title.
    run(sva, "recognize", "--write-sessions", work / "sessions.jsonl", "--map", work / "map.svam", "--data",
        work / "test.svad", "--trials", "1", "--max-readings", "5", "--seed", "2")
    session = json.loads((work / "sessions.jsonl").read_text(encoding="utf-8").splitlines()[0])
    session["id"] = HOSTILE_ID
    (work / "sessions.jsonl").write_text(json.dumps(session) + "\n", encoding="utf-8")
    run(sva, "view", "--map", work / "map.svam", "--sessions", work / "sessions.jsonl", "--scene", work / "scene.json",
        "--backend", "cpu", "--out", work / "session.html")
    shown = probe(exe, work / "session.html")
    assert shown["title"] == [f"session {HOSTILE_ID}"], shown["title"]
    assert sorted(shown["bar_names"]) == sorted(HOSTILE_OBJECTS + ["none of these"]), shown["bar_names"]
    print(f"view: {len(HOSTILE_OBJECTS)} hostile object names, a hostile scene name and session id shown as text")


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
    hostile_names(sva, exe, work / "hostile")


if __name__ == "__main__":
    main()
