"""The tiny scene's dataset, map and eval against the digests checked in
beside this file (golden.json): any machine that computes something else
fails, naming the first stage that differs.

A change that is meant to alter results updates them on purpose:
    SVA_UPDATE_GOLDEN=1 ctest --preset ci -R "determinism: golden"
and says why in its commit (docs/reliability.md, "Golden digests").
"""
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pipeline  # noqa: E402

GOLDEN = os.path.join(os.path.dirname(os.path.abspath(__file__)), "golden.json")


def main():
    sva, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    got = pipeline.run(sva, work)
    if os.environ.get("SVA_UPDATE_GOLDEN") == "1":
        with open(GOLDEN, "w") as f:
            json.dump({"scene": pipeline.SCENE, "seed": pipeline.SEED, "eval": pipeline.EVAL, "sha256": got}, f,
                      indent=2)
            f.write("\n")
        print(f"wrote {GOLDEN}")
        return 0
    with open(GOLDEN) as f:
        want = json.load(f)["sha256"]
    bad = pipeline.first_difference(want, got)
    for s in pipeline.STAGES:
        print(f"{s:11s} {got[s]}  {'ok' if want.get(s) == got[s] else 'DIFFERS (golden ' + want.get(s, '?') + ')'}")
    if bad:
        print(f"FAILED: {bad} is not the checked-in one; the later stages follow from it. If the change was meant to "
              "alter results, update the digests (SVA_UPDATE_GOLDEN=1, docs/reliability.md); if not, this machine "
              "or change computes something else.")
        return 1
    shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
