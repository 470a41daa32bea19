#!/usr/bin/env python3
"""The margins of the suite's statistical tests (docs/reliability.md, "Margins").

Every statistical assertion (accuracy, pose errors, readings to decide) prints
its statistic and threshold as a "margin:" line (tests/test_support.hpp). This
runs each such test at SEEDS seeds (SVA_TEST_SEED=0 is the checked-in one) and,
for those that simulate, under every Embree ISA the CPU has and with glibc's
variants off; it prints, per statistic, the threshold, the checked-in value,
the worst value seen and the margin the worst leaves.

usage: bench/reliability/test_margins.py [--build build-ci] [--seeds 6] [--no-variants] [--only TEXT]
"""
import argparse
import collections
import os
import re
import subprocess
import sys

# (test binary, Catch2 test name, simulates with Embree)
TESTS = [
    ("sva_tests_sim", "errors: three objects are recognised and localised with the realistic errors on", True),
    ("sva_tests_sim", "controller: converges on tiny's objects with errors on, settling near, not on, the true normal", True),
    ("sva_tests_recognition",
     "fine pose end to end: on the simulated tiny scene, refinement lowers the angle error", True),
    ("sva_tests_planning",
     "Touch planner: touching where the plan says decides the object in fewer readings than at random", False),
]
LINE = re.compile(r"^margin: (.*) = (\S+) \(asserted (<=|>=|<|>) (\S+)\)$")


def variants(simulates, with_variants):
    out = [("", {})]
    if not (simulates and with_variants):
        return out
    flags = open("/proc/cpuinfo").read()
    for isa, flag in [("sse2", "sse2"), ("sse4.2", "sse4_2"), ("avx", " avx "), ("avx2", "avx2"),
                      ("avx512", "avx512bw")]:
        if flag in flags:
            out.append((f"isa={isa}", {"SVA_EMBREE_ISA": isa}))
    out.append(("glibc off", {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX,-AVX512F"}))
    return out


def run(binary, name, env_extra):
    env = dict(os.environ, **env_extra)
    # Catch2 reads a comma as the end of a test name; a backslash keeps it.
    p = subprocess.run([binary, name.replace(",", "\\,")], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    found = [LINE.match(l.strip()) for l in p.stdout.splitlines()]
    found = [m.groups() for m in found if m]
    if not found:
        sys.exit(f"{binary} \"{name}\" printed no margin line (exit {p.returncode}):\n{p.stdout[-2000:]}")
    return p.returncode == 0, found


def margin(value, relation, threshold):
    """How far the value is from its threshold, as a share of the threshold (negative: it fails)."""
    gap = threshold - value if relation.startswith("<") else value - threshold
    return gap / abs(threshold) if threshold else gap


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build-ci")
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--no-variants", action="store_true")
    ap.add_argument("--only", help="run only the tests whose name contains this")
    a = ap.parse_args()
    rows = collections.OrderedDict()
    for binary, name, simulates in TESTS:
        if a.only and a.only not in name:
            continue
        path = os.path.join(a.build, "tests", binary)
        for k in range(a.seeds):
            for vname, env in variants(simulates, not a.no_variants):
                ok, found = run(path, name, dict(env, SVA_TEST_SEED=str(k)))
                label = f"seed {k}" + (f" {vname}" if vname else "")
                print(f"{label:22s} {'pass' if ok else 'FAIL'}  {name[:70]}", flush=True)
                for stat, value, rel, thr in found:
                    rows.setdefault((name, stat, rel, float(thr)), []).append((label, float(value)))
    print()
    print(f"{'statistic':64s} {'asserted':>12s} {'seed 0':>9s} {'worst':>9s} {'margin':>7s}  runs")
    for (name, stat, rel, thr), vals in rows.items():
        worst = min(vals, key=lambda lv: margin(lv[1], rel, thr))
        base = next((v for l, v in vals if l == "seed 0"), float("nan"))
        print(f"{stat[:64]:64s} {rel + ' ' + format(thr, '.4g'):>12s} {base:9.4g} {worst[1]:9.4g} "
              f"{100 * margin(worst[1], rel, thr):6.0f}%  {len(vals)} (worst: {worst[0]})")


if __name__ == "__main__":
    main()
