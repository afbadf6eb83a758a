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
# The native FCL peer (bench/peers/fcl_native/peer_fcl.cpp): Debian's libfcl-dev and
# nlohmann-json3-dev, then one g++ call into target/release/peer-fcl. Skipped (and the peer
# recorded as not installed) where apt-get or g++ is missing.
fcl_ok=false
if ! pkg-config --exists fcl 2>/dev/null || [ ! -f /usr/include/nlohmann/json.hpp ]; then
    if command -v apt-get >/dev/null; then
        echo "setup.sh: installing libfcl-dev nlohmann-json3-dev pkg-config (apt-get)"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq >/dev/null
        apt-get install -y -qq --no-install-recommends libfcl-dev nlohmann-json3-dev pkg-config >/dev/null \
            || echo "setup.sh: could not install libfcl-dev" >&2
    fi
fi
peer_fcl="$here/../target/release/peer-fcl"
source_fcl="$here/peers/fcl_native/peer_fcl.cpp"
if pkg-config --exists fcl 2>/dev/null && command -v g++ >/dev/null; then
    if [ ! -x "$peer_fcl" ] || [ "$source_fcl" -nt "$peer_fcl" ]; then
        mkdir -p "$(dirname "$peer_fcl")"
        # shellcheck disable=SC2046 # pkg-config's flags are meant to split
        if g++ -O2 -DNDEBUG -std=c++17 -o "$peer_fcl" "$source_fcl" $(pkg-config --cflags --libs fcl) 2>/dev/null; then
            fcl_ok=true
        else
            echo "setup.sh: could not build $peer_fcl" >&2
        fi
    else
        fcl_ok=true
    fi
fi
status="$status, \"fcl-native\": $fcl_ok}"
echo "$status" > "$venv/install-status.json"
echo "setup.sh: $status"
