#!/usr/bin/env python3
"""Every repository path that README.md and docs/ name exists (issue 53: a dozen pointed to folders that had moved).

    check_paths.py [DOC ...]        # default: README.md and every docs/**/*.md

A path is a word in backticks, or a Markdown link's target, that starts at a top folder of the repository (TOP),
or names a source file (one of EXTENSIONS, a glob such as `votes/pose_space.*` allowed) or a folder (a trailing
slash). Placeholders (`OUT_DIR/...`, `<harness>`) are not paths. It is looked for from the repository's root,
then from each source root (ROOTS: the docs name files in host/src as `estimate/verify.cpp`, as the code includes
them). Words that are no repository path are left alone: URLs, absolute and home paths, build outputs (BUILD_DIRS),
and a user's own files (a dataset, a map, a figure: their extensions are not in EXTENSIONS). Each missing path is
printed as FILE:LINE: `path`, and the exit status is 1.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EXTENSIONS = (".hpp", ".cpp", ".h", ".c", ".py", ".sh", ".md", ".comp", ".glsl", ".cmake", ".toml", ".yaml",
              ".yml", ".txt", ".json", ".gltf", ".in", ".clang-format", ".supp")
# Where a path that does not start at the root may start: the include folders of the code, and each library's own.
ROOTS = ("host/src", "host/eval", "host/base", "host/io", "sim", "host/include", "host/include/sva", "host/eval/src", "host/eval/include", "host/cli",
         "host/base/include", "host/base/src", "host/io/src", "host/io/include", "sim/src", "sim/include",
         "sim/include/sva/sim", "drivers", "drivers/src", "python", "python/src", "python/sva", "tests", "shaders",
         "bench", "scripts", "docs")
# A word starting at one of these is a path whatever its ending (`tests/vulkan`, `bench/roofline`).
TOP = ("host", "sim", "tests", "bench", "docs", "scripts", "drivers", "python", "shaders", "examples", "cmake",
       "assets", ".ci")
BUILD_DIRS = ("build", "build-ci", "build-asan", "build-fuzz", "build-pip", "build-py", "build-aarch64", ".venv",
              "shared", "../shared")
SPAN = re.compile(r"`([^`\s]+)`")
LINK = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def candidates(doc: Path) -> list[tuple[int, str]]:
    """(line, word) for each backticked word and link target outside code blocks (blocks run in tests/docs)."""
    out, fenced = [], False
    for n, line in enumerate(doc.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        out += [(n, m.group(1)) for m in SPAN.finditer(line)]
        out += [(n, m.group(1)) for m in LINK.finditer(line)]
    return out


def is_path(word: str) -> bool:
    """A word that names a repository file or folder (not a URL, option, absolute, home or build path)."""
    if "/" not in word or "://" in word or word.startswith(("/", "~", "$", "-", "<", "http")):
        return False
    if any(word == d or word.startswith(d + "/") for d in BUILD_DIRS):
        return False
    if any(c in word for c in "=,;:()'\"{}|") or ".." in word.replace("../shared", ""):
        return False
    first = word.split("/", 1)[0]
    if "<" in word or re.fullmatch(r"[A-Z_]+", first):  # a placeholder: `OUT_DIR/run-tests.sh`, `fuzz_<parser>.cpp`
        return False
    name = word.rstrip("/").rsplit("/", 1)[-1]
    return first in TOP or word.endswith("/") or name.endswith(EXTENSIONS) or name.endswith(".*")


def exists(word: str, doc: Path) -> bool:
    word = word.removeprefix("./")
    bases = [doc.parent, REPO] + [REPO / r for r in ROOTS]
    for base in bases:
        if "*" in word or "?" in word:
            if any(base.glob(word)):
                return True
        elif (base / word).exists():
            return True
    return False


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("docs", nargs="*", type=Path)
    a = ap.parse_args()
    docs = a.docs or [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
    missing = 0
    for doc in docs:
        doc = doc.resolve()
        if not doc.is_file():
            print(f"{doc}: no such document", file=sys.stderr)
            return 2
        for line, word in candidates(doc):
            if is_path(word) and not exists(word, doc):
                shown = doc.relative_to(REPO) if doc.is_relative_to(REPO) else doc
                print(f"{shown}:{line}: `{word}` names no file or folder of the repository")
                missing += 1
    checked = len(docs)
    if missing:
        print(f"{missing} missing path(s) in {checked} document(s)", file=sys.stderr)
        return 1
    print(f"every repository path named in {checked} document(s) exists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
