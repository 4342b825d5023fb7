#!/usr/bin/env bash
# Robots as they are published: the six quadruped URDFs of pybullet's data
# package (pybullet 3.2.7, from PyPI), each given to `measure_action` as it is,
# with no robot file: legs, camera and cadence are found from the URDF. Checks
# that each loads, stays upright at every command and walks faster for a faster
# command, and prints a line per robot. Exits non-zero if any does not.
#
#   bash scripts/public_robots.sh [OUT_DIR]      (default target/public-robots)
#
# The wheel (about 100 MB) is downloaded once into OUT_DIR and reused.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/public-robots}
mkdir -p "$out/measured"
robots="a1/a1.urdf aliengo/aliengo.urdf laikago/laikago_toes_zup.urdf
mini_cheetah/mini_cheetah.urdf quadruped/vision60.urdf quadruped/spirit40.urdf"

if [ ! -d "$out/pybullet_data" ]; then
    if ! ls "$out"/pybullet-3.2.7-*.whl > /dev/null 2>&1; then
        python3 -m pip download --quiet --disable-pip-version-check --no-deps \
            pybullet==3.2.7 -d "$out"
    fi
    # The wheel is a zip archive; only the quadrupeds' folders are taken out.
    python3 - "$out" $robots <<'PY'
import glob, sys, zipfile
out, robots = sys.argv[1], sys.argv[2:]
folders = {"pybullet_data/" + r.split("/")[0] + "/" for r in robots}
with zipfile.ZipFile(glob.glob(out + "/pybullet-3.2.7-*.whl")[0]) as z:
    for name in z.namelist():
        if any(name.startswith(f) for f in folders):
            z.extract(name, out)
PY
fi

cargo build --release --example measure_action --quiet
failed=0
printf '%-32s %s\n' "URDF (unedited, no robot file)" "measure_action"
for r in $robots; do
    dir="$out/measured/$(basename "$r" .urdf)"
    if ! target/release/examples/measure_action --robot "$out/pybullet_data/$r" --out "$dir" \
        > "$dir.log" 2>&1; then
        printf '%-32s REFUSED: %s\n' "$r" "$(grep -m1 -i error "$dir.log" || tail -1 "$dir.log")"
        failed=1
        continue
    fi
    summary=$(python3 - "$dir/measured_action.csv" "$dir.log" <<'PY'
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))
log = open(sys.argv[2]).read()
v = [float(r["velocity_mm_s"]) for r in rows]
upright = all(r["upright"] == "true" for r in rows)
monotone = all(b > a for a, b in zip(v, v[1:]))
a0 = re.search(r"RMSE [0-9.]+ mm/s \(([0-9.]+) % of the range\)", log).group(1)
fits = re.search(r"best line: RMSE ([0-9.]+) mm/s; best quartic: RMSE ([0-9.]+)", log).groups()
periods = re.search(r"gait periods: stepping in place ([0-9.]+) s, fast forwards ([0-9.]+) s, "
                    r"fast backwards ([0-9.]+) s", log).groups()
ok = upright and monotone and len(rows) == 31
print(("ok  " if ok else "FAIL") + f" {len(rows)} commands, {min(v):.0f} to {max(v):.0f} mm/s, "
      f"{'monotone' if monotone else 'NOT monotone'}, {'upright' if upright else 'FELL'}; "
      f"A0 {a0} % of range; line {fits[0]} / quartic {fits[1]} mm/s; "
      f"periods {'/'.join(periods)} s")
PY
)
    printf '%-32s %s\n' "$r" "$summary"
    case "$summary" in ok*) ;; *) failed=1 ;; esac
done
exit $failed
