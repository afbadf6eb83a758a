#!/usr/bin/env bash
# Creates .venv at the repository root with the machine's python3, installs
# the pinned tools of crates/tumble-py/requirements-dev.txt, and builds and
# installs the `tumble` package (`pip install .`, cargo incremental in
# target/). Idempotent: each part is skipped while its inputs are unchanged,
# so a second run takes about a second.
#   PYTHON=python3.12 scripts/python-env.sh   picks another interpreter.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
req="$root/crates/tumble-py/requirements-dev.txt"
python="${PYTHON:-python3}"

if [ ! -x "$venv/bin/python" ]; then
    echo "python-env: creating $venv with $("$python" --version 2>&1)"
    "$python" -m venv "$venv"
fi
pip=("$venv/bin/python" -m pip --disable-pip-version-check)

# Tools: reinstalled when the requirements file changes.
want="$(sha256sum "$req" | cut -d' ' -f1)"
if [ "$(cat "$venv/.requirements.sha256" 2>/dev/null || true)" != "$want" ]; then
    echo "python-env: installing pinned tools"
    "${pip[@]}" install -q --only-binary=:all: -r "$req"
    echo "$want" >"$venv/.requirements.sha256"
fi

# The package: rebuilt when a source it is made of changes.
sources="$(
    cd "$root" &&
        find Cargo.toml Cargo.lock pyproject.toml rust-toolchain.toml .cargo/config.toml crates/tumble-collide crates/tumble crates/tumble-py \
            -type f \( -name '*.rs' -o -name '*.toml' -o -name '*.py' -o -name '*.pyi' -o -name 'py.typed' \) \
            -not -path '*/tests/*' -not -path '*/benches/*' -not -path '*/__pycache__/*' |
        LC_ALL=C sort | xargs sha256sum | sha256sum | cut -d' ' -f1
)"
if [ "$(cat "$venv/.tumble-build.sha256" 2>/dev/null || true)" != "$sources" ] ||
    ! "$venv/bin/python" -c "import tumble" 2>/dev/null; then
    echo "python-env: building and installing tumble (pip install .)"
    # No build isolation: maturin comes pinned from the venv, and cargo reuses
    # target/ between builds.
    (cd "$root" && PATH="$venv/bin:$PATH" nice -n 10 "${pip[@]}" install -q --no-build-isolation --no-deps --force-reinstall .)
    echo "$sources" >"$venv/.tumble-build.sha256"
fi
echo "python-env: ready ($("$venv/bin/python" -c 'import tumble; print("tumble", tumble.__version__)'))"
