"""The tiny scene gives the same bytes on every x86-64 CPU: every Embree ISA
this CPU supports, glibc's function variants off, and other CPU models under
QEMU's user-mode emulator (docs/reliability.md, "Same answers on every
machine").

usage: variants.py --sva BUILD/sva --work DIR [--only NAME ...] [--list]
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pipeline  # noqa: E402

ALL = pipeline.STAGES


def cpu_flags():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("flags"):
                return set(line.split(":", 1)[1].split())
    return set()


def variants():
    """(name, environment, command prefix, stages) of every variant this machine can run."""
    flags = cpu_flags()
    isas = [("sse2", "sse2"), ("sse4.2", "sse4_2"), ("avx", "avx"), ("avx2", "avx2"), ("avx512", "avx512bw")]
    out = []
    # Embree's kernels enter the simulation, and the recognition and the eval through the nearest triangle of a mesh
    # (the surface check, the pose errors): every stage reruns.
    for isa, flag in isas:
        if flag in flags:
            out.append((f"embree isa={isa}", {"SVA_EMBREE_ISA": isa}, [], ALL))
    out.append(("glibc variants off", {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX,-AVX512F"}, [], ALL))
    qemu = shutil.which("qemu-x86_64")
    if not qemu:
        raise SystemExit("qemu-x86_64 not found: scripts/setup.sh installs qemu-user")
    # Nehalem: SSE4.2, no AVX (Embree's sse4.2 kernels, glibc's SSE2 functions).
    out.append(("qemu -cpu Nehalem", {}, [qemu, "-cpu", "Nehalem"], ALL))
    # Haswell: AVX2 and FMA (Embree's avx2 kernels, glibc's FMA functions) on a CPU that may have neither.
    out.append(("qemu -cpu Haswell-v4", {}, [qemu, "-cpu", "Haswell-v4"], ALL))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sva", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--only", action="append", help="run only the variants whose name contains this")
    args = ap.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    # A forced ISA that Embree does not have is refused by name, not ignored.
    bad = subprocess.run([args.sva, "simulate", "--scene", "tiny", "--out", os.path.join(args.work, "bad")],
                         env=dict(os.environ, SVA_EMBREE_ISA="sse9"), capture_output=True, text=True)
    if bad.returncode == 0 or "SVA_EMBREE_ISA=sse9" not in bad.stderr:
        print(f"FAILED: SVA_EMBREE_ISA=sse9 gave exit {bad.returncode} and: {bad.stderr[-500:]}")
        return 1
    log = []
    t0 = time.monotonic()
    want = pipeline.run(args.sva, os.path.join(args.work, "native"), log=log)
    print(f"native ({time.monotonic() - t0:.1f} s): " + ", ".join(f"{k} {v[:12]}" for k, v in want.items()))
    failures = []
    for i, (name, env, prefix, stages) in enumerate(variants()):
        if args.only and not any(o in name for o in args.only):
            continue
        t0 = time.monotonic()
        got = pipeline.run(args.sva, os.path.join(args.work, f"v{i}"), env, prefix, stages, log)
        bad = pipeline.first_difference(want, got)
        print(f"{name} ({time.monotonic() - t0:.1f} s): " + ("same bytes" if not bad else f"DIFFERS from {bad} on"))
        if bad:
            failures.append(f"{name}: {bad} differs from the native run ({got[bad][:12]} against {want[bad][:12]})")
    print("\n".join(log))
    if failures:
        print("FAILED: the results depend on the machine:\n  " + "\n  ".join(failures))
        return 1
    shutil.rmtree(args.work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
