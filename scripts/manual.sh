#!/usr/bin/env bash
# Builds the user manual (docs/manual, an mdBook) into target/manual/.
# Installs the pinned mdbook into target/tools with `cargo install --locked`
# when it is missing (about 5-10 minutes of compiling on two cores, once per
# target/ directory). The chapters are plain Markdown: without mdbook they
# still read fine on a code host, and `make manual-test` runs their code.
#   bash scripts/manual.sh            build target/manual/index.html
#   MDBOOK=/path/to/mdbook bash scripts/manual.sh   use another mdbook
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
version="0.5.4"
tools="$root/target/tools"
mdbook="${MDBOOK:-$tools/bin/mdbook}"

if ! "$mdbook" --version 2>/dev/null | grep -q "v$version"; then
    if [ -n "${MDBOOK:-}" ]; then
        echo "manual: $MDBOOK is not mdbook v$version" >&2
        exit 1
    fi
    echo "manual: installing mdbook $version into $tools (cargo install, once)"
    nice -n 10 cargo install mdbook --locked --version "$version" --no-default-features --features search \
        --root "$tools" --quiet
fi
"$mdbook" build "$root/docs/manual"
echo "manual: $root/target/manual/index.html"
