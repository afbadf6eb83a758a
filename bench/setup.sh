#!/usr/bin/env bash
# Creates bench/.venv and installs the pinned peer engines of bench/requirements.txt.
# Idempotent: re-running only installs what is missing. Each requirement is installed on
# its own so that one peer failing to install (no wheel for this platform) does not stop
# the others; the outcome is written to bench/.venv/install-status.json and the harness
# records a missing peer as "not installed".
set -u
here="$(cd "$(dirname "$0")" && pwd)"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
py="$venv/bin/python"
"$py" -m pip install --quiet --upgrade pip >/dev/null 2>&1 || true
status="{"
first=1
while read -r line; do
    req="${line%%#*}"
    req="$(echo "$req" | tr -d '[:space:]')"
    [ -z "$req" ] && continue
    name="${req%%==*}"
    if "$py" -m pip install --quiet --prefer-binary "$req"; then ok=true; else ok=false; echo "setup.sh: could not install $req" >&2; fi
    [ $first -eq 1 ] || status="$status,"
    first=0
    status="$status\"$name\": $ok"
done < "$here/requirements.txt"
status="$status}"
echo "$status" > "$venv/install-status.json"
echo "setup.sh: $status"
