#!/usr/bin/env bash
# Installs everything the viewer needs, with nothing installed by hand:
# the npm packages pinned in package-lock.json and Debian's chromium (used
# headless by scripts/test.sh). Idempotent and quiet when all is there.
# VIEWER_SETUP_NO_BROWSER=1 skips chromium (building the page needs only npm).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if [ -z "${VIEWER_SETUP_NO_BROWSER:-}" ] && [ ! -x /usr/bin/chromium ]; then
    echo "viewer setup: installing chromium (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null
fi

# npm ci only when node_modules is missing or older than the lock file.
stamp="$here/node_modules/.package-lock.json"
if [ ! -f "$stamp" ] || [ "$here/package-lock.json" -nt "$stamp" ]; then
    echo "viewer setup: npm ci"
    (cd "$here" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi
