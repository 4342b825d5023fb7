#!/usr/bin/env bash
# Sim to sim: the command-to-velocity response of the same robot, the same
# gait and the same file, in this testbed and in MuJoCo. At each of the
# paper's commands (at the robot's scale, as `measure_action` walks them),
# `peer_trace` records the walk's servo targets in this testbed and
# `mujoco_peer.py` replays them in MuJoCo (a robot read from MJCF is built
# from the MJCF itself, as MuJoCo reads it); each side's speed is its torso's
# over the second half of the 10 s walk. Writes target/peer/NAME/response.csv
# and response.png (both curves, with this testbed's stopwatch beside them),
# and prints the RMS difference in % of this testbed's range.
#
#   bash scripts/peer/response.sh assets/robots/menagerie/unitree_go2/go2.xml
#   bash scripts/peer/response.sh ers7
#
# Installs mujoco==4.0.0 and matplotlib==3.10.7 into target/mujoco-venv on
# first use (not part of the required tests).
set -euo pipefail
cd "$(dirname "$0")/../.."
robot=${1:-ers7}
name=$(basename "$robot")
out=target/peer/${name%.*}
venv=target/mujoco-venv
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import mujoco, matplotlib" 2> /dev/null; then
    python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check mujoco==4.0.0 matplotlib==3.10.7
fi
robot_flag=()
[ "$robot" != ers7 ] && robot_flag=(--robot "$robot")
cargo build --quiet --release --example peer_trace --example measure_action
mkdir -p "$out"
target/release/examples/measure_action "${robot_flag[@]}" --out "$out" > "$out/measure_action.txt"
: > "$out/response.jsonl"
tail -n +2 "$out/measured_action.csv" | while IFS=, read -r command stopwatch _; do
    dir="$out/at-$command"
    target/release/examples/peer_trace "${robot_flag[@]}" --command="$command" --repeats 1 --out "$dir" > /dev/null
    mj=$("$venv/bin/python" scripts/peer/mujoco_peer.py "$dir" --repeats 1)
    python3 - "$dir/peer.json" "$mj" "$stopwatch" >> "$out/response.jsonl" <<'PY'
import json, sys
ours, mj = json.load(open(sys.argv[1])), json.loads(sys.argv[2])
print(json.dumps({"command": ours["command"], "stopwatch_mm_s": float(sys.argv[3]),
                  "ours_mm_s": ours["second_half_mm_s"], "mujoco_mm_s": mj["second_half_mm_s"],
                  "ours_upright": ours["upright"], "mujoco_upright": mj["upright"],
                  "mujoco_model": mj["model"]}))
PY
    printf '.'
done
echo
"$venv/bin/python" - "$out" "$robot" <<'PY'
import json, os, subprocess, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
out, robot = sys.argv[1], sys.argv[2]
rows = [json.loads(l) for l in open(os.path.join(out, "response.jsonl"))]
with open(os.path.join(out, "response.csv"), "w") as f:
    f.write("command,stopwatch_mm_s,ours_mm_s,mujoco_mm_s,ours_upright,mujoco_upright\n")
    for r in rows:
        f.write(f"{r['command']},{r['stopwatch_mm_s']},{r['ours_mm_s']},{r['mujoco_mm_s']},"
                f"{str(r['ours_upright']).lower()},{str(r['mujoco_upright']).lower()}\n")
ours = [r["ours_mm_s"] for r in rows]
span = max(ours) - min(ours)
rms = (sum((r["mujoco_mm_s"] - r["ours_mm_s"]) ** 2 for r in rows) / len(rows)) ** 0.5
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
c = [r["command"] for r in rows]
plt.figure(figsize=(7, 4.5))
plt.plot(c, ours, "o-", label="this testbed (the walk's second half)")
plt.plot(c, [r["stopwatch_mm_s"] for r in rows], "x:", label="this testbed, stopwatch (measure_action)")
plt.plot(c, [r["mujoco_mm_s"] for r in rows], "s-", label=f"MuJoCo 4.0.0, same gait, {rows[0]['mujoco_model']}")
plt.xlabel("walk command")
plt.ylabel("velocity, mm/s")
plt.title(f"{robot}: RMS difference {100 * rms / span:.1f} % of the range ({commit})", fontsize=9)
plt.grid(alpha=0.3)
plt.legend(fontsize=8)
plt.tight_layout()
plt.savefig(os.path.join(out, "response.png"), dpi=110)
falls = sum(not r["mujoco_upright"] for r in rows)
print(f"{robot}: {len(rows)} commands; range {span:.0f} mm/s here; MuJoCo differs by "
      f"{rms:.1f} mm/s RMS ({100 * rms / span:.1f} % of the range); MuJoCo fell at {falls} commands; "
      f"{out}/response.csv and response.png (commit {commit})")
PY
