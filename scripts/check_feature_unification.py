#!/usr/bin/env python3
"""Checks that every cargo build `make test` and `make demo` run compiles the
engine's dependencies with the same features as the workspace's test build.

Why: cargo unifies a dependency's features over the packages one build selects,
so `cargo build -p tumble-cli` alone could enable fewer features of, say,
`num-traits` than `cargo test --workspace`; every crate above it (parquet,
tumble-collide, tumble) was then compiled again, once per selection. A fresh
clone's `make test` compiled the engine five times over (about 8 of its 20
minutes). crates/tumble-workspace-hack, written by `cargo hakari generate`
(config: .config/hakari.toml), depends on those crates with the union of their
features, so that every selection gets the same; this check fails when a new
dependency or feature makes the selections differ again.

For each selection it compares, package by package, the features `cargo tree`
resolves against those of the whole workspace with its dev-dependencies
(except the command-line parser's, left out of the hack on purpose: see
.config/hakari.toml). It needs cargo only (no build) and takes a second.

Exit 0 when all agree; 1 with the differing packages and the fix otherwise.
"""

import subprocess
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# The cargo selections of the Makefile's targets and the scripts they call
# (viewer/scripts/test.sh, bench/run.py, scripts/python-env.sh via maturin),
# with whether the build includes dev-dependencies (tests and examples do).
SELECTIONS = {
    "cargo build -p tumble-cli": (["-p", "tumble-cli"], False),
    "cargo build -p tumble-cli -p tumble-bench": (
        ["-p", "tumble-cli", "-p", "tumble-bench"],
        False,
    ),
    "maturin (cargo build -p tumble-py)": (["-p", "tumble-py"], False),
    "cargo run -p tumble --example ...": (["-p", "tumble"], True),
}

# Left out of crates/tumble-workspace-hack (.config/hakari.toml's
# final-excludes): a build that resolves them otherwise recompiles only
# tumble-cli or tumble-bench.
EXEMPT = {"clap", "clap_builder"}


def tree(args: list[str]) -> dict[str, set[str]]:
    """Each package of `cargo tree` with `args`: the feature lists it is built with
    (a package built for the host and for the target may have two)."""
    out = subprocess.run(
        ["cargo", "tree", "--quiet", "--prefix", "none", "-e", "features", "-f", "{p}|{f}", *args],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    features: dict[str, set[str]] = defaultdict(set)
    for line in out.splitlines():
        if "|" not in line:
            continue  # a feature node ("serde feature \"derive\""), not a package
        package, listed = line.split("|", 1)
        features[package.strip()].add(listed.removesuffix("(*)").strip())
    return features


def main() -> int:
    workspace = tree(["--workspace"])
    failures = []
    for name, (args, dev) in SELECTIONS.items():
        selected = tree(args + ([] if dev else ["-e", "no-dev"]))
        for package in sorted(selected):
            if package.split()[0] in EXEMPT:
                continue
            if selected[package] != workspace.get(package):
                failures.append(
                    f"{name}: {package} built with {sorted(selected[package])}, "
                    f"the workspace with {sorted(workspace.get(package, []))}"
                )
    if failures:
        print("feature unification: these builds would compile crates again:", file=sys.stderr)
        for f in failures:
            print(f"  {f}", file=sys.stderr)
        print(
            "fix: cargo install cargo-hakari --locked, then"
            " cargo hakari generate && cargo hakari manage-deps",
            file=sys.stderr,
        )
        return 1
    print(
        f"feature unification: {len(SELECTIONS)} builds resolve their packages"
        " as the workspace does"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
