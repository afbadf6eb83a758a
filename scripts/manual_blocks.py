"""Runs the code blocks of the user manual (docs/manual/src/**/*.md) that are
not Rust, so that the manual cannot rot. (Rust blocks are doc-tests of
crates/tumble-manual: `cargo test -p tumble-manual --doc`.)

Every fenced block must name its language; by language:

- ``python``: the blocks of one chapter are joined in order (a chapter reads
  as one session) and run by the project's .venv interpreter from the
  repository root;
- ``toml``: a scene file, written to out/manual-blocks/ and simulated for
  two steps with ``tumble run --steps 2``; a block whose first line is
  ``# path/to/file.toml`` must also equal that file of the repository; a Cargo
  manifest (it has a ``[package]`` table) is parsed and its path dependencies
  must name crates of this repository;
- ``json``: parsed; a scene (it has ``bodies``) is run like a TOML scene;
- ``sh``: each ``tumble run|mass|collide|help|sweep`` line is run with the built
  ``tumble`` from the repository root and must exit 0; ``tumble view``
  (serves until stopped), ``demo`` and ``bench`` lines and other commands
  (installs and builds, run by ``make`` itself) are listed as not run;
- ``text``: output samples and synopses, not run.

Usage: python3 scripts/manual_blocks.py [--tumble PATH] [--python PATH]
The last line reads ``manual blocks: N passed, M failed``; exit status 1 on
any failure.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "docs" / "manual" / "src"
OUT = ROOT / "out" / "manual-blocks"
RUN_VERBS = {"run", "mass", "collide", "help", "sweep"}
SKIP_VERBS = {"view", "demo", "bench"}
LANGUAGES = {"rust", "python", "toml", "json", "sh", "text"}


@dataclass
class Block:
    chapter: Path
    line: int
    lang: str
    text: str

    @property
    def where(self) -> str:
        return f"{self.chapter.relative_to(ROOT)}:{self.line}"


def blocks_of(chapter: Path) -> list[Block]:
    found, current, start, lang = [], None, 0, ""
    for n, line in enumerate(chapter.read_text(encoding="utf-8").splitlines(), 1):
        fence = line.strip().startswith("```")
        if current is None and fence:
            lang = line.strip()[3:].split(",")[0].strip()
            current, start = [], n
        elif current is not None and fence:
            found.append(Block(chapter, start, lang, "\n".join(current) + "\n"))
            current = None
        elif current is not None:
            current.append(line)
    if current is not None:
        raise SystemExit(f"{chapter}:{start}: code block never closed")
    return found


class Runner:
    def __init__(self, tumble: Path, python: Path) -> None:
        self.tumble, self.python = tumble, python
        self.passed, self.failed, self.not_run = 0, [], []

    def ok(self, what: str) -> None:
        self.passed += 1
        print(f"ok   - {what}")

    def fail(self, what: str, why: str) -> None:
        self.failed.append(what)
        print(f"FAIL - {what}: {why.strip()[-2000:]}")

    def command(self, what: str, args: list[str], **kw) -> None:
        try:
            r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, **kw)
        except OSError as e:
            self.fail(what, f"cannot run {args[0]}: {e}")
            return
        if r.returncode == 0:
            self.ok(what)
        else:
            self.fail(what, f"exit {r.returncode}\n{r.stdout}\n{r.stderr}")

    def scene(self, block: Block, text: str, suffix: str) -> None:
        name = re.sub(r"[^A-Za-z0-9]+", "-", block.where).strip("-")
        path = OUT / f"{name}{suffix}"
        path.write_text(text, encoding="utf-8")
        args = [str(self.tumble), "run", "--quiet", "--steps", "2", str(path)]
        self.command(f"{block.where} scene", args)

    def toml(self, block: Block) -> None:
        if re.search(r"^\[package\]", block.text, re.M):
            self.cargo_manifest(block)
            return
        first = block.text.splitlines()[0] if block.text.strip() else ""
        m = re.match(r"#\s*(\S+\.toml)\b", first)
        if m and (ROOT / m.group(1)).is_file():
            if (ROOT / m.group(1)).read_text(encoding="utf-8") != block.text:
                self.fail(f"{block.where} copy", f"differs from {m.group(1)}")
                return
            self.ok(f"{block.where} equals {m.group(1)}")
            # Run where it lies: the files it names are relative to it.
            args = [str(self.tumble), "run", "--quiet", "--steps", "2", str(ROOT / m.group(1))]
            self.command(f"{block.where} scene", args)
            return
        self.scene(block, block.text, ".toml")

    def cargo_manifest(self, block: Block) -> None:
        try:
            import tomllib
        except ModuleNotFoundError:  # Python < 3.11: nothing to parse with
            self.not_run.append(f"{block.where} (Cargo manifest; needs Python 3.11 to check)")
            return
        try:
            manifest = tomllib.loads(block.text)
            deps = manifest["dependencies"]
            for name, spec in deps.items():
                crate = Path(spec["path"]).name
                if crate != name or not (ROOT / "crates" / crate / "Cargo.toml").is_file():
                    raise ValueError(f"dependency {name} -> {spec['path']} is not a crate here")
        except (tomllib.TOMLDecodeError, KeyError, TypeError, ValueError) as e:
            self.fail(f"{block.where} Cargo manifest", str(e))
            return
        self.ok(f"{block.where} Cargo manifest")

    def json(self, block: Block) -> None:
        try:
            value = json.loads(block.text)
        except json.JSONDecodeError as e:
            self.fail(f"{block.where} json", str(e))
            return
        if isinstance(value, dict) and "bodies" in value:
            self.scene(block, block.text, ".json")
        else:
            self.ok(f"{block.where} json parses")

    def sh(self, block: Block) -> None:
        for k, line in enumerate(block.text.splitlines()):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            words = shlex.split(line, comments=True)
            where = f"{block.chapter.relative_to(ROOT)}:{block.line + 1 + k}"
            if words[0] == "tumble" and len(words) > 1 and words[1] in RUN_VERBS:
                self.command(f"{where} {' '.join(words[:2])}", [str(self.tumble), *words[1:]])
            elif words[0] == "tumble" and len(words) > 1 and words[1] in SKIP_VERBS:
                self.not_run.append(f"{where} {line}")
            elif words[0] == "tumble":
                self.fail(where, f"unknown tumble verb in `{line}`")
            else:
                self.not_run.append(f"{where} {line}")

    def python_chapter(self, chapter: Path, blocks: list[Block]) -> None:
        # Each block is marked so that a traceback names the manual's line.
        code = "".join(f"# --- {b.where}\n{b.text}" for b in blocks)
        env = {**os.environ, "MPLBACKEND": "Agg"}
        what = f"{chapter.relative_to(ROOT)} python ({len(blocks)} blocks)"
        self.command(what, [str(self.python), "-c", code], env=env)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tumble", type=Path, default=ROOT / "target" / "release" / "tumble")
    ap.add_argument("--python", type=Path, default=ROOT / ".venv" / "bin" / "python")
    args = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    (ROOT / "out").mkdir(exist_ok=True)
    runner = Runner(args.tumble, args.python)
    chapters = sorted(p for p in SRC.rglob("*.md") if p.name != "SUMMARY.md")
    counts: dict[str, int] = {}
    for chapter in chapters:
        blocks = blocks_of(chapter)
        python = []
        for b in blocks:
            counts[b.lang] = counts.get(b.lang, 0) + 1
            if b.lang not in LANGUAGES:
                expected = ", ".join(sorted(LANGUAGES))
                runner.fail(b.where, f"code block language `{b.lang}`: expected one of {expected}")
            elif b.lang == "python":
                python.append(b)
            elif b.lang == "toml":
                runner.toml(b)
            elif b.lang == "json":
                runner.json(b)
            elif b.lang == "sh":
                runner.sh(b)
        if python:
            runner.python_chapter(chapter, python)
    print("blocks by language: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    rust = counts.get("rust", 0)
    print(f"rust blocks ({rust}) run as doc-tests: cargo test -p tumble-manual --doc")
    for line in runner.not_run:
        print(f"not run: {line}")
    print(f"manual blocks: {runner.passed} passed, {len(runner.failed)} failed")
    return 1 if runner.failed else 0


if __name__ == "__main__":
    sys.exit(main())
