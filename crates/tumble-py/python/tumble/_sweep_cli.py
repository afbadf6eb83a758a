"""``tumble sweep --ray ADDRESS``: the command line hands its checked
arguments here as one JSON object, and this runs :func:`tumble.sweep` with
``backend="ray"``. Exit status as the command line's: 0, 2 bad input, 130
interrupted."""

from __future__ import annotations

import json
import sys

from . import SceneError, TumbleError
from ._sweep import sweep


def main(argv: list[str]) -> int:
    spec = json.loads(argv[0])
    try:
        table = sweep(
            spec["scene"],
            dict(spec["params"]),
            steps=spec.get("steps"),
            duration=spec.get("duration"),
            metrics=spec["metrics"],
            backend="ray",
            address=spec.get("address"),
            out=spec["out"],
            resume=spec.get("resume", False),
            trajectories=spec.get("trajectories"),
            progress=spec.get("progress"),
        )
    except KeyboardInterrupt:
        print("tumble: sweep interrupted; `--resume` runs the rest", file=sys.stderr)
        return 130
    except (SceneError, TumbleError, ValueError) as e:
        print(f"tumble: error: {e}", file=sys.stderr)
        return 2
    status = table.column("status").to_pylist()
    if spec.get("progress"):
        counts = {s: status.count(s) for s in ("ok", "failed", "cancelled")}
        print(
            f"{spec['scene']}: {len(status)} runs on Ray: {counts['ok']} ok, "
            f"{counts['failed']} failed, {counts['cancelled']} cancelled"
        )
        print(f"wrote {spec['out']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
