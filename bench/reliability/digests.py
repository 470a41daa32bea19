"""Digests of every result the pipeline writes for one scene: dataset, map, eval JSON (CPU and Vulkan backends),
batch sessions and estimates, and the CSV/PLY export. Run it before and after a change that must not change
behaviour (a refactor) and compare the two lists:

    python3 bench/reliability/digests.py --sva build-ci/sva --scene tiny --out /tmp/d-before
    python3 bench/reliability/digests.py --sva build-ci/sva --scene paper3d --out /tmp/p-before

Timings are removed from the JSON outputs before hashing (tests/determinism/pipeline.py canonicalises them)."""
import argparse
import hashlib
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "determinism"))
import pipeline  # noqa: E402


def strip_times(line):
    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if not (k.endswith("_ms") or "_ms_" in k or k.endswith("_s"))}
        if isinstance(v, list):
            return [strip(x) for x in v]
        return v
    return json.dumps(strip(json.loads(line)), sort_keys=True)


def jsonl_digest(path):
    with open(path) as f:
        return hashlib.sha256("\n".join(strip_times(l) for l in f if l.strip()).encode()).hexdigest()


def file_digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sva", required=True)
    ap.add_argument("--scene", default="tiny")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--trials", default="6")
    ap.add_argument("--readings", default="10")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    p = lambda n: os.path.join(a.out, n)
    run = lambda *args: subprocess.run([a.sva, "--quiet", *args], check=True, stdout=subprocess.DEVNULL)
    run("simulate", "--scene", a.scene, "--out", a.out, "--seed", a.seed, "--preview", p("preview.png"))
    run("train", "--data", p("train.svad"), "--out", p("map.svam"))
    ev = ["--trials", a.trials, "--max-readings", a.readings]
    run("eval", "--map", p("map.svam"), "--data", p("test.svad"), "--json", p("eval-cpu.json"), "--backend", "cpu",
        "--plot", p("eval.png"), *ev)
    run("eval", "--map", p("map.svam"), "--data", p("test.svad"), "--json", p("eval-vulkan.json"), "--backend",
        "vulkan", *ev)
    run("recognize", "--map", p("map.svam"), "--data", p("test.svad"), "--write-sessions", p("sessions.jsonl"),
        "--trials", a.trials, "--max-readings", a.readings)
    run("recognize", "--map", p("map.svam"), "--batch", p("sessions.jsonl"), "--out", p("results.jsonl"),
        "--backend", "cpu")
    run("export", "--data", p("test.svad"), "--out", p("export"))
    digests = {
        "train.svad": pipeline.digest(p("train.svad")),
        "test.svad": pipeline.digest(p("test.svad")),
        "map.svam": pipeline.digest(p("map.svam")),
        "eval-cpu.json": pipeline.digest(p("eval-cpu.json")),
        "eval-vulkan.json": pipeline.digest(p("eval-vulkan.json")),
        "sessions.jsonl": jsonl_digest(p("sessions.jsonl")),
        "results.jsonl": jsonl_digest(p("results.jsonl")),
    }
    for name in ("preview.png", "eval.png"):
        digests[name] = file_digest(p(name))
    for name in sorted(os.listdir(p("export"))):
        digests["export/" + name] = file_digest(os.path.join(p("export"), name))
    for k, v in digests.items():
        print(f"{v}  {a.scene}/{k}")


if __name__ == "__main__":
    main()
