#!/usr/bin/env bash
# This testbed's full step beside MuJoCo's physics-only step, on the same robot
# and the same motion, one after the other so that the ratio holds on a noisy
# machine: `peer_trace` records a walk's servo targets and times this build on
# it; `mujoco_peer.py` replays the targets in MuJoCo and times its C rollout.
#
#   bash scripts/peer/compare.sh [ROBOT] [COMMAND]     # ROBOT: ers7 (default), trotter, a robot file, a URDF
#   ROUNDS=5 bash scripts/peer/compare.sh              # more rounds on a noisy machine (default 3)
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
# Rounds of (this build, MuJoCo), one after the other, each side's best kept:
# a burst of load on a shared machine then costs a round, not the ratio.
rounds=${ROUNDS:-3}
# This build with the `speed` profile (Cargo.toml: release with fat LTO and one
# codegen unit; the same floating-point results as release).
cargo build --quiet --profile speed --example peer_trace
for round in $(seq 1 "$rounds"); do
    echo "round $round of $rounds"
    target/speed/examples/peer_trace "${robot_flag[@]}" --command "$command" --out "$out"
    cp "$out/peer.json" "$out/peer-$round.json"
    "$venv/bin/python" scripts/peer/mujoco_peer.py "$out" > "$out/mujoco-$round.json"
done
"$venv/bin/python" - "$out" "$rounds" <<'PY'
import json, sys, os
d, rounds = sys.argv[1], int(sys.argv[2])
runs = [(json.load(open(os.path.join(d, f"peer-{r}.json"))),
         json.load(open(os.path.join(d, f"mujoco-{r}.json")))) for r in range(1, rounds + 1)]
ours = min((o for o, _ in runs), key=lambda o: o["us_per_step"])
mj = min((m for _, m in runs), key=lambda m: m["us_per_step"])
ours["us_per_step_by_multibody"] = {
    name: min(o["us_per_step_by_multibody"][name] for o, _ in runs)
    for name in ours.get("us_per_step_by_multibody", {})
}
ours["us_per_step"] = ours["us_per_step_by_multibody"].get(ours["multibody"], ours["us_per_step"])
json.dump({"ours": ours, "mujoco": mj, "rounds": rounds}, open(os.path.join(d, "compare.json"), "w"), indent=1)
print(f"\n{'':36} {'us/step':>8} {'x real time':>12} {'contacts/step':>14} {'walked':>8}")
print(f"{'this testbed, full step (' + ours['multibody'] + ')':36} {ours['us_per_step']:8.1f} "
      f"{ours['dt_s'] * 1e6 / ours['us_per_step']:12.0f} {ours['contacts_per_step']:14.2f} "
      f"{ours['travelled_m']:7.2f}m")
for name, us in ours.get("us_per_step_by_multibody", {}).items():
    if name != ours["multibody"]:
        print(f"{'  with physics.multibody = ' + name:36} {us:8.1f} {ours['dt_s'] * 1e6 / us:12.0f}")
print(f"{'MuJoCo ' + mj['mujoco'] + ' ' + mj['integrator'] + ', physics only':36} "
      f"{mj['us_per_step']:8.1f} {ours['dt_s'] * 1e6 / mj['us_per_step']:12.0f} "
      f"{mj['contacts_per_step']:14.2f} {mj['travelled_m']:7.2f}m")
ratios = ", ".join(f"{us / mj['us_per_step']:.2f}x with physics.multibody = {name}"
                   for name, us in (ours.get("us_per_step_by_multibody") or
                                    {ours["multibody"]: ours["us_per_step"]}).items())
print(f"\nratio (this testbed / MuJoCo): {ratios}; "
      f"{ours['steps']} steps of {ours['dt_s'] * 1e3:g} ms at command {ours['command']:g}; "
      f"each side's best of {rounds} rounds ({d}/compare.json)")
PY
