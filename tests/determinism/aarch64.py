"""The aarch64 build against x86-64's bytes (issue 54): the tiny scene's pipeline (simulate, train, eval) run by the
cross-built `sva` under qemu-aarch64 must give the checked-in golden digests (golden.json), and `sva recognize` on
a sessions file the same results, byte for byte, as this machine's own build.

    python3 tests/determinism/aarch64.py --sva-aarch64 build-aarch64/sva --sva build-ci/sva --work DIR

Both run the CPU backend (lavapipe under emulation is left to the robot's own GPU: docs/reliability.md). Prints
each stage's digest and time; exit 1 naming the first stage that differs.
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pipeline  # noqa: E402
from golden import GOLDEN  # noqa: E402

QEMU = ["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu"]
# One thread under emulation: oneTBB's worker start spins under qemu-user (the engine's pool and Embree's alike), and
# the results do not depend on the thread count (docs/reliability.md).
ONE_THREAD = {"SVA_THREADS": "1"}


def recognize(prefix, sva, map_path, data_path, sessions, out):
    """`sva recognize` of the test set's trials, written by this machine's build once (the same input for both)."""
    if not os.path.exists(sessions):
        subprocess.run([sva, "recognize", "--write-sessions", sessions, "--map", map_path, "--data", data_path,
                        "--trials", "4", "--max-readings", "6", "--seed", "1"], check=True, stdout=subprocess.DEVNULL)
    t0 = time.monotonic()
    subprocess.run(prefix + [sva, "recognize", "--map", map_path, "--batch", sessions, "--out", out, "--backend",
                             "cpu"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env={**os.environ, **(ONE_THREAD if prefix else {})})
    return hashlib.sha256(open(out, "rb").read()).hexdigest(), time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sva-aarch64", required=True, help="the cross-built sva (build-aarch64/sva)")
    ap.add_argument("--sva", required=True, help="this machine's sva, for the sessions file and the batch results")
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    if shutil.which(QEMU[0]) is None:
        ap.error("qemu-aarch64 not found: scripts/setup.sh installs qemu-user")
    for path in (a.sva_aarch64, a.sva):
        if not os.access(path, os.X_OK):
            ap.error(f"{path}: not an executable (build it: cmake --build --preset aarch64, or --preset ci)")
    shutil.rmtree(a.work, ignore_errors=True)
    log = []
    t0 = time.monotonic()
    got = pipeline.run(a.sva_aarch64, os.path.join(a.work, "aarch64"), env_extra=ONE_THREAD, prefix=QEMU, log=log)
    print("\n".join(log))
    print(f"pipeline under qemu-aarch64: {time.monotonic() - t0:.1f} s")
    with open(GOLDEN) as f:
        want = json.load(f)["sha256"]
    for s in pipeline.STAGES:
        print(f"{s:11s} {got[s]}  {'ok' if want.get(s) == got[s] else 'DIFFERS (x86-64 ' + want.get(s, '?') + ')'}")
    bad = pipeline.first_difference(want, got)
    if bad:
        print(f"FAILED: aarch64's {bad} is not x86-64's; the later stages follow from it")
        return 1
    w = os.path.join(a.work, "aarch64")
    m, d, sessions = os.path.join(w, "map.svam"), os.path.join(w, "test.svad"), os.path.join(a.work, "sessions.jsonl")
    native, _ = recognize([], a.sva, m, d, sessions, os.path.join(a.work, "native.jsonl"))
    emulated, secs = recognize(QEMU, a.sva_aarch64, m, d, sessions, os.path.join(a.work, "aarch64.jsonl"))
    print(f"recognize   {emulated}  {'ok' if emulated == native else 'DIFFERS (x86-64 ' + native + ')'} "
          f"({secs:.1f} s under qemu)")
    if emulated != native:
        print("FAILED: aarch64's batch results are not x86-64's")
        return 1
    shutil.rmtree(a.work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
