#!/usr/bin/env bash
# MuJoCo and Drake (PyPI packages) on the five rigid-body contact scenes of
# docs/peer-comparison.md; prints markdown tables (progress goes to stderr).
#
#   examples/peer_compare/run.sh [scene-name-filter ...]
#
# The venv lives in ~/.cache/modia3d-peer-compare (override with PEER_VENV); versions are
# pinned to the ones measured. PEER_CAP (wall cap per run [s], default 60) and PEER_RUNS
# (runs per timed setting, default 3) are read by peers.py.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
VENV="${PEER_VENV:-$HOME/.cache/modia3d-peer-compare}"
PINS=(mujoco==4.0.1 drake==1.51.1 numpy==2.4.6)

if [ ! -x "$VENV/bin/python" ]; then
    if ! python3 -c 'import venv, ensurepip' 2>/dev/null; then
        if [ "$(id -u)" = 0 ]; then
            apt-get install -y python3-venv >&2
        else
            echo "python3-venv is missing; install it (apt-get install python3-venv)" >&2
            exit 1
        fi
    fi
    python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check "${PINS[@]}" >&2

echo "versions: $("$VENV/bin/python" - <<'EOF'
import sys
from importlib.metadata import version
print(", ".join(f"{p} {version(p)}" for p in ("mujoco", "drake", "numpy")) + f", python {sys.version.split()[0]}")
EOF
)"
echo

# Drake's warnings (e.g. about half spaces and deformables) go to stderr with the progress.
exec "$VENV/bin/python" -W ignore "$HERE/peers.py" "$@"
