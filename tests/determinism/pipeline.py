"""The tiny scene's pipeline (simulate, train, eval) run as one variant of the
machine, and the digests of what each stage wrote.

A variant is an environment (SVA_EMBREE_ISA forces Embree's kernels,
GLIBC_TUNABLES turns glibc's FMA/AVX2 function variants off) and a command
prefix (qemu-x86_64 -cpu MODEL runs the binary as another x86-64 CPU). The
stages are compared in data-flow order, so a failure names the first stage
whose bytes differ: later ones follow from it.
"""
import hashlib
import json
import os
import subprocess
import time

SCENE = "tiny"
SEED = "1"
EVAL = ["--trials", "4", "--max-readings", "6", "--backend", "cpu"]
STAGES = ["train.svad", "test.svad", "map.svam", "eval.json"]
# A dataset records its scene, whose mesh paths name the folder the repository lies in; that folder is no result, so
# the digest of a binary file (docs/dataset-format.md) is taken over its magic, its version and its payload with that
# folder replaced by one placeholder (the header's size and checksum follow from the payload).
ASSETS = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets"))


def canonical_eval(path):
    """The eval JSON without what may differ between two runs of the same computation: timings."""
    def strip(v):
        if isinstance(v, dict):
            return {k: strip(x) for k, x in v.items() if not (k.endswith("_ms") or "_ms_" in k)}
        if isinstance(v, list):
            return [strip(x) for x in v]
        return v
    with open(path) as f:
        return json.dumps(strip(json.load(f)), sort_keys=True).encode()


def canonical_binary(path):
    b = open(path, "rb").read()
    head, payload = b[:12], b[32:]
    if head[:8] == b"SVADATA1":  # the payload starts with the scene JSON as a u64-length string
        n = int.from_bytes(payload[:8], "little")
        scene = payload[8:8 + n].replace(ASSETS.encode(), b"<assets>")
        return head + scene + payload[8 + n:]
    return head + payload


def digest(path):
    data = canonical_eval(path) if path.endswith(".json") else canonical_binary(path)
    return hashlib.sha256(data).hexdigest()


def run_stage(sva, args, env, prefix, log):
    cmd = prefix + [sva] + args
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900)
    log.append(f"  {' '.join(cmd)}  ({time.monotonic() - t0:.1f} s)")
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stdout[-3000:]}")


def run(sva, work, env_extra=None, prefix=None, stages=STAGES, log=None):
    """Runs the pipeline up to the last of `stages` in `work`; returns {stage file: sha256}."""
    log = [] if log is None else log
    prefix = prefix or []
    # Each variant forces only what it names: a forced ISA or tunable from the caller's environment would also
    # reach the native run and the emulated CPUs (which may lack it).
    env = {k: v for k, v in os.environ.items() if k not in ("SVA_EMBREE_ISA", "GLIBC_TUNABLES")}
    env.update(env_extra or {})
    os.makedirs(work, exist_ok=True)
    p = lambda name: os.path.join(work, name)
    run_stage(sva, ["simulate", "--scene", SCENE, "--out", work, "--seed", SEED], env, prefix, log)
    if "map.svam" in stages or "eval.json" in stages:
        run_stage(sva, ["train", "--data", p("train.svad"), "--out", p("map.svam")], env, prefix, log)
    if "eval.json" in stages:
        run_stage(sva, ["eval", "--map", p("map.svam"), "--data", p("test.svad"), "--json", p("eval.json")] + EVAL,
                  env, prefix, log)
    return {s: digest(p(s)) for s in stages}


def first_difference(want, got):
    """The first stage, in data-flow order, whose digest differs; None when all agree."""
    for s in STAGES:
        if s in want and s in got and want[s] != got[s]:
            return s
    return None
