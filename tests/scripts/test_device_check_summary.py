#!/usr/bin/env python3
"""ctest "scripts: device-check-summary.py ...": the summary of a device check (scripts/device-check-summary.py) on
made-up checks whose figures are known: each goal met or not by its own arithmetic, the same from the folder and from
its archive, a host of 2 cores named as measuring nothing of the 16-core goals, parts the check did not reach named
as not run, and bad input refused with the file and the fault.
  usage: test_device_check_summary.py SOURCE_DIR WORK_DIR
"""
import io
import json
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

source, work = Path(sys.argv[1]), Path(sys.argv[2])
script = source / "scripts" / "device-check-summary.py"
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def summary(target):
    p = subprocess.run([sys.executable, str(script), str(target)], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def point(readings, **figures):
    return {"readings": readings, **figures}


def make_check(folder, cores, benches, texts):
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / "device.txt").write_text(f"cores: {cores}\nNVIDIA H200\n")
    for name, body in texts.items():
        (folder / name).write_text(body)
    with tarfile.open(folder / "details.tgz", "w:gz") as tar:
        for name, report in benches.items():
            raw = report if isinstance(report, bytes) else json.dumps(report).encode()
            info = tarfile.TarInfo(f".suite/bench-{name}.json")
            info.size = len(raw)
            tar.addfile(info, io.BytesIO(raw))


def run(sessions, curve, **extra):
    return {"sessions_per_submission": sessions, "device": "NVIDIA H200", "curve": curve, **extra}


# The batch's kernels at 30 readings: ten pipelines of 1..10 ms, one dispatch each, but "p9" of 64: the 8 longest
# listed, the 2 shortest (1 and 2 ms, 2 dispatches) summed.
pipelines = {f"p{i}": {"ms": float(i), "dispatches": 64.0 if i == 9 else 1.0} for i in range(1, 11)}
benches = {
    # A touch at 30 readings 1.0 + 0.4 ms (goal 1.5: met), at 100 3 + 2 ms (goal 4: not met); the vote kernel 4e6
    # votes in 1 ms at 100 readings: 4e9 votes/s (goal 3e9: met).
    "vulkan": {"runs": [run(1, [point(30, update_ms=1.0, estimate_ms=0.4, accuracy=1.0, translation_error_mm=0.5),
                                point(100, update_ms=3.0, estimate_ms=2.0, accuracy=1.0, translation_error_mm=0.4,
                                      votes_per_update=4e6,
                                      kernel_ms_by_pipeline={"match_votes": {"dispatches": 1, "ms": 1.0},
                                                             "belief_reduce:table_histogram": {"dispatches": 1,
                                                                                               "ms": 0.25},
                                                             "belief_reduce:table_select": {"dispatches": 1,
                                                                                            "ms": 0.5}})])]},
    # One session with light estimates: 0.9 + 0.3 ms at 30 readings (met), 2.5 + 0.5 at 100 (met).
    "vulkan-light": {"runs": [run(1, [point(30, update_ms=0.9, estimate_ms=0.3, accuracy=1.0, translation_error_mm=0.7),
                                      point(100, update_ms=2.5, estimate_ms=0.5, accuracy=1.0,
                                            translation_error_mm=0.6)])]},
    # 64 sessions: at 10 readings 0.05 + 0.04 ms a session (11,111/s: met), at 30 0.2 + 0.05 (4,000/s: not met).
    "vulkan-batch": {"runs": [run(1, []), run(64, [point(10, update_ms=0.05, estimate_ms=0.04,
                                                         session_updates_per_second=20000.0),
                                                   point(30, update_ms=0.2, estimate_ms=0.05,
                                                         session_updates_per_second=5000.0,
                                                         update_split_ms={"kernels": 12.0, "recording": 0.5},
                                                         kernel_ms_by_pipeline=pipelines)])]},
    # 64 sessions with light estimates, the device's bare hash scatter 4e9 votes/s: at 10 readings 0.5 M votes a
    # session-update (the table's bound 8,000/s, the restated goal half of it, 4,000/s), 0.1 + 0.05 ms (6,667/s: met);
    # at 30 readings 2 M votes (bound 2,000/s, goal 1,000/s), 1.5 + 0.1 ms (625/s: not met).
    "vulkan-batch-light": {"roofline": {"hash_votes_per_second": 4e9},
                           "runs": [run(64, [point(10, update_ms=0.1, estimate_ms=0.05, votes_per_update=5e5),
                                             point(30, update_ms=1.5, estimate_ms=0.1, votes_per_update=2e6)],
                                        estimate="light")]},
    # One session on the CPU: 8 / 5 ms at 30 readings (1.6x: met), 50 / 40 at 100 (1.25x: not met).
    "cpu-t8": {"runs": [run(1, [point(30, update_ms=8.0), point(100, update_ms=50.0)])]},
    "cpu-t16": {"runs": [run(1, [point(30, update_ms=5.0), point(100, update_ms=40.0)])]},
}
texts = {
    "agreement.txt": "vulkan: 3 passed, 0 failed, 0 skipped (1 s)\nvulkan: 2 passed, 1 failed, 0 skipped (1 s)\n",
    "suite.txt": "io: 21 passed, 0 failed, 0 skipped (1 s)\n",
    "batch-span.txt": "64 sessions x 10 readings, top 1, full, 16 thread(s): 1200.0 session-updates/s (...)\n"
                      "under a span probe, its loops split for 16 thread(s), ...: 9000 as scheduled (a model)\n"
                      "64 sessions x 10 readings, top 1, full, 2 thread(s): 150.0 session-updates/s (...)\n",
}
folder = work / "check"
make_check(folder, 16, benches, texts)
rc, out, err = summary(folder)
check(rc == 0, f"the full check: rc {rc}, {err}")
for line in ["- agreement: 5 passed, 1 failed, 0 skipped", "- suite: 21 passed, 0 failed, 0 skipped",
             "| 30 | 1 | 0.4 | 1.4 | <= 1.5 (met) | 1 | 0.5 |", "| 100 | 3 | 2 | 5 | <= 4.0 (not met) | 1 | 0.4 |",
             "4e+09 votes/s, goal >= 3e+09 at 100 (met)",
             "- at 100 readings: 0.75 of 1.75 ms of kernels per submission",
             "## One session, light estimates: the touch goal restated (bench-vulkan-light)", "| 30 | 0.9 | 0.3 | 1.2 | <= 1.5 (met) | 1 | 0.7 |",
             "| 100 | 2.5 | 0.5 | 3 | <= 4.0 (met) | 1 | 0.6 |",
             "| vulkan-batch (64) | 10 | 2e+04 | 1.11e+04 | >= 10,000 (met) | n/a |  |",
             "| vulkan-batch (64) | 30 | 5e+03 | 4e+03 | >= 10,000 (not met) | n/a |  |",
             "| vulkan-batch-light (64) | 10 | n/a | 6.67e+03 | >= 10,000 (not met) | 8e+03 | >= 4,000 (met) |",
             "| vulkan-batch-light (64) | 30 | n/a | 625 | >= 10,000 (not met) | 2e+03 | >= 1,000 (not met) |",
             "## Where an update's time goes at 30 readings (ms per submission)",
             "bench-vulkan-batch (64 per submission): kernels 12, recording 0.5",
             "| p10 | 10 | 1 |\n| p9 | 9 | 64 |", "| p3 | 3 | 1 |\n| 2 more | 3 | 2 |",
             "one session at 30 readings: 8 threads 8 ms, 16 threads 5 ms: 1.6x, goal >= 1.6x (met)",
             "one session at 100 readings: 8 threads 50 ms, 16 threads 40 ms: 1.25x, goal >= 1.6x (not met)",
             "16 threads 1200.0, 2 threads 150.0 session-updates/s: 8.00x, goal >= 6.0x (met)",
             "Models (the span probe's, not measurements):", "9000 as scheduled (a model)"]:
    check(line in out, f"the full check's summary lacks {line!r}:\n{out}")

# The archive (ARCHIVE=FILE: the folder under its name) gives the same summary.
archive = work / "check.tgz"
with tarfile.open(archive, "w:gz") as tar:
    tar.add(folder, arcname="check")
rc, from_archive, err = summary(archive)
check(rc == 0 and from_archive == out, f"the archive's summary differs (rc {rc}, {err})")

# A 2-core host (lavapipe's machine): no 16-core goal measured, the parts not reached named.
make_check(folder, 2, {"vulkan": benches["vulkan"]}, {"batch-span.txt": texts["batch-span.txt"]})
rc, out, err = summary(folder)
check(rc == 0, f"the 2-core check: rc {rc}, {err}")
for line in ["- agreement: not run", "| not run |", "16 against 8 threads: not run",
             "## Where an update's time goes at 30 readings (ms per submission)\n\nnot measured",
             "## One session, light estimates: the touch goal restated (bench-vulkan-light)\n\nnot run",
             "the host has 2 cores, so its 16 threads measure nothing of the goal"]:
    check(line in out, f"the 2-core summary lacks {line!r}:\n{out}")
check("8.00x" not in out, "a 2-core host's 16 threads counted as the goal's measurement")

# Bad input: the file and the fault, exit 1; no arguments: the usage, exit 2.
make_check(folder, 16, {"vulkan": b"{ not json"}, {})
for target, expected in [(folder, "bench-vulkan.json: not JSON"), (work / "absent", "absent: no such folder"),
                         (source / "README.md", "README.md: neither a check's folder nor its archive"),
                         (source / "scripts", "scripts: no device.txt")]:
    rc, out, err = summary(target)
    check(rc == 1 and expected in err and "Traceback" not in err, f"{target}: rc {rc}, {err!r}")
p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
check(p.returncode == 2 and "usage" not in p.stdout and "CHECK" in p.stderr, f"no arguments: rc {p.returncode}")

if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
print("device-check-summary.py: every check passed")
