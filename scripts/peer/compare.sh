#!/usr/bin/env bash
# This testbed's full step beside MuJoCo's physics-only step, on the same robot
# and the same motion, one after the other so that the ratio holds on a noisy
# machine: `peer_trace` records a walk's servo targets and times this build on
# it; `mujoco_peer.py` replays the targets in MuJoCo and times its C rollout.
#
#   bash scripts/peer/compare.sh [ROBOT] [COMMAND]     # ROBOT: ers7 (default), trotter, a robot file, a URDF
#
# Installs mujoco==4.0.0 into target/mujoco-venv on first use (not part of
# the required tests). Run it on an idle machine.
set -euo pipefail
cd "$(dirname "$0")/../.."
robot=${1:-ers7}
command=${2:-300}
name=$(basename "$robot")
out=target/peer/${name%.*}
venv=target/mujoco-venv
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import mujoco" 2> /dev/null; then
    python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check mujoco==4.0.0
fi
robot_flag=()
[ "$robot" != ers7 ] && robot_flag=(--robot "$robot")
cargo run --quiet --release --example peer_trace -- "${robot_flag[@]}" --command "$command" --out "$out"
"$venv/bin/python" scripts/peer/mujoco_peer.py "$out" > "$out/mujoco.json"
"$venv/bin/python" - "$out" <<'PY'
import json, sys, os
d = sys.argv[1]
ours = json.load(open(os.path.join(d, "peer.json")))
mj = json.load(open(os.path.join(d, "mujoco.json")))
print(f"\n{'':36} {'us/step':>8} {'x real time':>12} {'contacts/step':>14} {'walked':>8}")
rows = [
    ("this testbed, full step", ours, ""),
    (f"MuJoCo {mj['mujoco']} {mj['integrator']}, physics only", mj, ""),
]
for name, r, _ in rows:
    print(f"{name:36} {r['us_per_step']:8.1f} {ours['dt_s'] * 1e6 / r['us_per_step']:12.0f} "
          f"{r['contacts_per_step']:14.2f} {r['travelled_m']:7.2f}m")
print(f"\nratio (this testbed / MuJoCo): {ours['us_per_step'] / mj['us_per_step']:.2f}x, "
      f"{ours['steps']} steps of {ours['dt_s'] * 1e3:g} ms at command {ours['command']:g}")
PY
