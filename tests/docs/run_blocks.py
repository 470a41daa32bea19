#!/usr/bin/env python3
"""The docs test: every shell, Python and C++ block of a document runs (or compiles) on the tiny scene.

    run_blocks.py --sva BIN --python-path DIR --cxx-flags FILE --work DIR DOC
    run_blocks.py --list DOC                      # the blocks and what the test does with each

DOC is a Markdown file (README.md, docs/*.md) or "docstrings" (the Python package's docstrings). The rules, and how
to mark a block that only illustrates, are in docs/docs-test.md. Every failure names the block as FILE:LINE.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SHELL, PYTHON, CPP = "sh", "python", "cpp"
LANGS = {"sh": SHELL, "bash": SHELL, "python": PYTHON, "cpp": CPP}
# Markdown: an HTML comment on the line just before the fence. Docstrings: a comment as the block's first line.
MD_MARKER = re.compile(r"^\s*<!--\s*illustration:\s*(\S.*?)\s*-->\s*$")
DOC_MARKER = re.compile(r"^\s*(#|//)\s*illustration:\s*(\S.*)$")
BLOCK_TIMEOUT_S = 300

# What the test changes in a block's text before it runs it, each for the reason given (docs/docs-test.md). Nothing
# else is changed: a block that fails after these is stale.
SUBSTITUTIONS = [
    (re.compile(r"--scene (paper3d|letters2d)(-ideal)?\b"), "--scene tiny",
     "the built-in full-size scenes take minutes to simulate; tiny has their format and protocol"),
    (re.compile(r"(?<![\w.])/tmp/"), "tmp/",
     "a scratch folder of the test's own, so that parallel runs and other users' files never meet"),
]


@dataclass
class Block:
    file: str  # as shown in messages: a path relative to the repository, or a module for a docstring
    line: int  # of the block's first code line
    lang: str
    code: str
    illustration: str | None  # the marker's reason, or None when the block runs

    @property
    def where(self) -> str:
        return f"{self.file}:{self.line}"


def markdown_blocks(path: Path) -> list[Block]:
    lines = path.read_text().split("\n")
    rel = path.resolve().relative_to(REPO).as_posix() if path.resolve().is_relative_to(REPO) else str(path)
    blocks, i = [], 0
    while i < len(lines):
        m = re.match(r"^(\s*)```\s*([\w+-]*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        indent, lang = m.group(1), m.group(2)
        end = i + 1
        while end < len(lines) and not re.match(r"^\s*```\s*$", lines[end]):
            end += 1
        if end == len(lines):
            raise SystemExit(f"{rel}:{i + 1}: a code fence that never closes")
        if lang in LANGS:
            body = [ln[len(indent):] if ln.startswith(indent) else ln.lstrip() for ln in lines[i + 1:end]]
            marker = MD_MARKER.match(lines[i - 1]) if i > 0 else None
            blocks.append(Block(rel, i + 2, LANGS[lang], "\n".join(body) + "\n", marker.group(1) if marker else None))
        i = end + 1
    return blocks


def docstring_blocks() -> list[Block]:
    """The literal blocks (a paragraph ending in "::", then an indented block) of every docstring in the package sva,
    which must be importable. They are Python, unless a first-line marker says otherwise."""
    import importlib
    import inspect
    import pkgutil

    import sva

    seen, docs = set(), []  # (shown name, docstring, source file or None, first line of the object in it)

    def visit(obj, name):
        if id(obj) in seen:
            return
        seen.add(id(obj))
        doc = obj.__doc__ if isinstance(getattr(obj, "__doc__", None), str) else None
        src, first = None, 1
        try:
            src = inspect.getsourcefile(obj)
            first = 1 if inspect.ismodule(obj) else inspect.getsourcelines(obj)[1]
        except (TypeError, OSError):
            pass
        if doc:
            docs.append((name, doc, src, first))
        if inspect.ismodule(obj) or inspect.isclass(obj):
            for attr, value in vars(obj).items():
                if attr.startswith("_") and attr != "__init__":
                    continue
                owner = getattr(value, "__module__", None) or getattr(getattr(value, "fget", None), "__module__", "")
                if inspect.ismodule(obj) and not str(owner).startswith("sva"):
                    continue  # names imported from elsewhere (typing, pathlib, ...)
                target = value.fget if isinstance(value, property) else value
                visit(target, f"{name}.{attr}")

    visit(sva, "sva")
    for info in pkgutil.iter_modules(sva.__path__):
        visit(importlib.import_module(f"sva.{info.name}"), f"sva.{info.name}")

    blocks = []
    for name, doc, src, first in docs:
        lines = inspect.cleandoc(doc).split("\n")
        i = 0
        while i < len(lines):
            if not lines[i].rstrip().endswith("::") or lines[i].strip().startswith(".."):
                i += 1
                continue
            base = len(lines[i]) - len(lines[i].lstrip())
            j = i + 1
            while j < len(lines) and not lines[j].strip():
                j += 1
            start, body = j, []
            while j < len(lines) and (not lines[j].strip() or len(lines[j]) - len(lines[j].lstrip()) > base):
                body.append(lines[j])
                j += 1
            while body and not body[-1].strip():
                body.pop()
            if body:
                code = textwrap.dedent("\n".join(body)) + "\n"
                marker = DOC_MARKER.match(code.split("\n")[0])
                where, line = f"docstring of {name}", start + 1
                if src:  # the block's line in the source file, found by its first line after the object's start
                    # A build tree's copy of a package file (python/CMakeLists.txt copies them) is named by its source.
                    source = REPO / "python" / "sva" / Path(src).name
                    if source.is_file() and source.read_bytes() == Path(src).read_bytes():
                        src = str(source)
                    text = Path(src).read_text().split("\n")
                    for k in range(first - 1, len(text)):
                        if text[k].strip() == body[0].strip():
                            rel = Path(src).resolve()
                            where = rel.relative_to(REPO).as_posix() if rel.is_relative_to(REPO) else str(rel)
                            where, line = f"{where} ({name})", k + 1
                            break
                blocks.append(Block(where, line, PYTHON, code, marker.group(2) if marker else None))
            i = j
    return blocks


def substitute(code: str) -> str:
    for pattern, replacement, _ in SUBSTITUTIONS:
        code = pattern.sub(replacement, code)
    return code


class Runner:
    def __init__(self, args):
        self.sva = Path(args.sva).resolve()
        self.python_path = Path(args.python_path).resolve()
        self.cxx_flags = Path(args.cxx_flags).resolve()
        self.work = Path(args.work).resolve()
        self.fixture = Path(args.fixture).resolve() if args.fixture else None
        self.cxx = os.environ.get("CXX", "c++")

    def prepare(self):
        """A fresh folder laid out like the repository root after the README's two commands: build/sva (the default
        preset's), build-ci/sva and build-ci/python (the ci preset's) are this build's, the source folders are the
        repository's, and the tiny scene's files are at hand."""
        shutil.rmtree(self.work, ignore_errors=True)
        (self.work / "build").mkdir(parents=True)
        (self.work / "build-ci").mkdir()
        (self.work / "tmp").mkdir()
        (self.work / "build" / "sva").symlink_to(self.sva)
        (self.work / "build-ci" / "sva").symlink_to(self.sva)
        (self.work / "build-ci" / "python").symlink_to(self.python_path)
        for name in (".venv", "scripts", "bench", "python", "examples", "assets", "docs", "tests"):
            (self.work / name).symlink_to(REPO / name)
        if self.fixture:
            for f in ("train.svad", "test.svad", "map.svam"):
                shutil.copy(self.fixture / f, self.work / f)
        self.env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(self.python_path),
                        PATH=f"{self.sva.parent}{os.pathsep}{os.environ.get('PATH', '')}")
        self.env.pop("PYTHONHOME", None)

    def shell(self, b: Block) -> str | None:
        # Padded so that bash's line numbers are the document's: the trap names the command that failed.
        script = self.work / "tmp" / f"block_{b.line}.sh"
        trap = f"trap 'echo \"docs test: the command at {b.file}:$LINENO exited $?\" >&2' ERR"
        script.write_text(trap + "\n" * (b.line - 1) + substitute(b.code))
        r = subprocess.run(["bash", "-e", "-o", "pipefail", str(script)], cwd=self.work, env=self.env,
                           capture_output=True, text=True, timeout=BLOCK_TIMEOUT_S)
        if r.returncode != 0:
            return f"exit {r.returncode}\n{tail(r.stdout)}{tail(r.stderr)}"
        return None

    def cpp(self, b: Block) -> str | None:
        src = self.work / "tmp" / f"block_{b.line}.cpp"
        src.write_text(f'#line {b.line} "{b.file}"\n' + b.code)  # the compiler's messages name the document's lines
        r = subprocess.run([self.cxx, "-std=c++20", "-fsyntax-only", f"@{self.cxx_flags}", str(src)], cwd=self.work,
                           capture_output=True, text=True, timeout=BLOCK_TIMEOUT_S)
        if r.returncode != 0:
            return f"does not compile\n{tail(r.stderr)}"
        return None

    def python(self, blocks: list[Block], shared: bool) -> dict[str, str]:
        """One interpreter for the document's Python blocks, in order, as a reader runs them one after the other
        (shared namespace), or each on its own (docstrings). Tracebacks name the document's lines."""
        spec = self.work / "tmp" / "python_blocks.json"
        spec.write_text(json.dumps([{"file": b.file, "line": b.line, "code": substitute(b.code)} for b in blocks]))
        r = subprocess.run([sys.executable, "-c", PY_DRIVER, str(spec), "shared" if shared else "own"], cwd=self.work,
                           env=self.env, capture_output=True, text=True, timeout=BLOCK_TIMEOUT_S * max(1, len(blocks)))
        passed = set(re.findall(r"^BLOCK-OK (\S+:\d+)$", r.stdout, re.M))
        failed = dict(re.findall(r"^BLOCK-FAILED (\S+:\d+)\n(.*?)^BLOCK-END$", r.stdout, re.S | re.M))
        result = {}
        for b in blocks:
            key = f"{b.file.split(' (')[0]}:{b.line}"
            if key in failed:
                result[key] = failed[key]
            elif key not in passed:  # after a failed block of a shared run, or the interpreter died
                result[key] = ("not run: an earlier Python block failed" if failed else
                               f"the interpreter exited {r.returncode}\n{tail(r.stdout)}{tail(r.stderr)}")
        return result


# Runs the blocks of a JSON file in one interpreter; a block's code is compiled under the document's name with its
# line numbers, so a traceback points into the document.
PY_DRIVER = r"""
import json, sys, traceback
blocks, mode = json.load(open(sys.argv[1])), sys.argv[2]
ns = {"__name__": "__main__"}
for b in blocks:
    if mode == "own":
        ns = {"__name__": "__main__"}
    try:
        exec(compile("\n" * (b["line"] - 1) + b["code"], b["file"].split(" (")[0], "exec"), ns)
        print(f"BLOCK-OK {b['file'].split(' (')[0]}:{b['line']}", flush=True)
    except BaseException:
        print(f"BLOCK-FAILED {b['file'].split(' (')[0]}:{b['line']}\n{traceback.format_exc()}BLOCK-END", flush=True)
        if mode == "shared":
            break
"""


def tail(text: str, lines: int = 40) -> str:
    t = text.strip().split("\n")
    return ("\n".join(t[-lines:]) + "\n") if text.strip() else ""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("doc")
    ap.add_argument("--list", action="store_true", help="list the blocks and what the test does with each")
    ap.add_argument("--sva", help="the sva command line under test")
    ap.add_argument("--python-path", help="the folder holding the Python package sva under test")
    ap.add_argument("--cxx-flags", help="a response file of the compiler flags for C++ blocks (include folders)")
    ap.add_argument("--work", help="a scratch folder (emptied first)")
    ap.add_argument("--fixture", help="a folder with the tiny scene's train.svad, test.svad and map.svam")
    args = ap.parse_args()

    if args.doc == "docstrings":
        if args.python_path:
            sys.path.insert(0, str(Path(args.python_path).resolve()))
        blocks = docstring_blocks()
    else:
        blocks = markdown_blocks(Path(args.doc) if Path(args.doc).is_absolute() else REPO / args.doc)
    if args.list:
        for b in blocks:
            print(f"{b.where}: {b.lang}: " + (f"illustration ({b.illustration})" if b.illustration else "runs"))
        return 0
    missing = [o for o in ("sva", "python_path", "cxx_flags", "work") if not getattr(args, o)]
    if missing:
        ap.error("to run the blocks: --" + ", --".join(m.replace("_", "-") for m in missing))

    runner = Runner(args)
    runner.prepare()
    failures, ran = [], 0
    py = [b for b in blocks if b.lang == PYTHON and not b.illustration]
    py_failed = runner.python(py, shared=args.doc != "docstrings") if py else {}
    for b in blocks:
        if b.illustration:
            continue
        ran += 1
        if b.lang == PYTHON:
            why = py_failed.get(f"{b.file.split(' (')[0]}:{b.line}")  # absent: it ran and passed
        else:
            try:
                why = runner.shell(b) if b.lang == SHELL else runner.cpp(b)
            except subprocess.TimeoutExpired:
                why = f"still running after {BLOCK_TIMEOUT_S} s"
        print(f"{'FAIL' if why else 'ok  '} {b.where} ({b.lang})", flush=True)
        if why:
            failures.append((b, why))
    shown = len(blocks) - ran
    print(f"{args.doc}: {ran} blocks run, {len(failures)} failed; {shown} marked as illustrations")
    for b, why in failures:
        print(f"\n{b.where}: the {b.lang} block fails: {why}", end="")
        print("  (fix the block, or mark it as an illustration with a reason: docs/docs-test.md)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
