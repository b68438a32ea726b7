#!/bin/bash
# SLAM round building-sized loops of long corridors, on synthetic logs with a known truth
# (tools/generators/make_building_log.py): slam_offline with gmapping's defaults, four ways — the
# plain RBPF (loopClosure=0), loop closure with a fixed search window (loopDriftRate=0), with
# corridor constraints (loopCorridors=1), and the defaults — each with seeds 1, 2 and 3 (one seed's figure
# says little: a closure found a few scans earlier or later moves the result by decimetres). Each
# trajectory is scored against relations made from the truth: over ≤ 10 s (local accuracy) and
# over any span (the map's global consistency: a bent corridor or a loop left open shows there);
# the lines give the mean ± standard deviation over the seeds.
#
#   tools/bench/building_slam_bench.sh [OUT_DIR]     (default build/bench/building in the repo)
# Writes OUT_DIR/NAME_{open,fixed,corridors,default}_sSEED/ and, for the large building with
# seed 1, the maps with the fixed window and the default one, one above the other, in
# OUT_DIR/large.png.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="$(realpath -m "${1:-$root/build/bench/building}")"
cd "$root"
source tools/ros_env.sh  # plot_map.py imports the workspace's Python modules
bin=devel/lib/minibot3d_slam
mkdir -p "$out"
# name | make_building_log.py arguments
buildings=(
  "medium|--width 100 --height 40 --max-range 10 --laps 1 --yaw-bias 0.5 --door-gap 10 25"
  "large|--width 200 --height 80 --max-range 8 --laps 1 --yaw-bias 0.5 --door-gap 20 40"
)
for entry in "${buildings[@]}"; do
  name="${entry%%|*}"
  args="${entry#*|}"
  # shellcheck disable=SC2086  # the arguments are words
  echo "$name: $(/usr/bin/python3 tools/generators/make_building_log.py "$out/$name.clf" \
    "$out/$name.truth" $args) [$args]"
  "$bin/make_relations" "$out/$name.truth" "$out/$name.rel" > /dev/null
  "$bin/make_relations" "$out/$name.truth" "$out/$name.long.rel" --max-span 100000 --every 5 > /dev/null
  for variant in "open loopClosure=0" "fixed loopDriftRate=0" "corridors loopCorridors=1" "default loopClosure=1"; do
    tag="${variant%% *}"
    rm -f "$out/${name}_$tag.scores"
    for seed in 1 2 3; do
      dir="$out/${name}_${tag}_s$seed"
      /usr/bin/time -f "%e %M" -o "$dir.time" "$bin/slam_offline" --log "$out/$name.clf" --out "$dir" --quiet \
        --param seed=$seed --param "${variant#* }" > "$dir.line"
      echo "$("$bin/evaluate_relations" "$dir/trajectory.txt" "$out/$name.rel" | head -1) |" \
        "$("$bin/evaluate_relations" "$dir/trajectory.txt" "$out/$name.long.rel" | head -1) |" \
        "$(cat "$dir.time") | $(cat "$dir.line")" >> "$out/${name}_$tag.scores"
    done
    /usr/bin/python3 - "$out/${name}_$tag.scores" "$tag" <<'PY'
import re, statistics as st, sys
rows = [l.split('|') for l in open(sys.argv[1])]
def col(i, key):
    return [float(re.search(key + r' ([0-9.]+)', r[i]).group(1)) for r in rows]
def ms(v, f):
    return (f + ' +- ' + f) % (st.mean(v), st.stdev(v))
wall = [float(r[2].split()[0]) for r in rows]
peak = max(int(r[2].split()[1]) for r in rows) / 1024
closures = col(3, 'loop_closures')
print('  %-11s <=10 s: %s m, %s deg | any span: %s m, %s deg | closures %s, wall %.1f s, peak %.0f MB'
      % (sys.argv[2], ms(col(0, 'translation_m'), '%.3f'), ms(col(0, 'rotation_deg'), '%.2f'),
         ms(col(1, 'translation_m'), '%.3f'), ms(col(1, 'rotation_deg'), '%.2f'),
         '/'.join('%d' % c for c in closures), st.mean(wall), peak))
print('  %-11s any-span translation per seed: %s' % ('', ', '.join('%.3f' % v for v in col(1, 'translation_m'))))
PY
  done
done
/usr/bin/python3 minibot3d_slam/scripts/plot_map.py "$out/large_default_s1/map.yaml" \
  "$out/large_default_s1/trajectory.txt" "$out/large_default.png"
/usr/bin/python3 minibot3d_slam/scripts/plot_map.py "$out/large_fixed_s1/map.yaml" "$out/large_fixed_s1/trajectory.txt" \
  "$out/large_fixed.png"
# One picture: the fixed window's map above, the default's below.
/usr/bin/python3 - "$out/large_fixed.png" "$out/large_default.png" "$out/large.png" <<'PY'
import os, sys
import matplotlib.image as image
import numpy as np
a, b = image.imread(sys.argv[1]), image.imread(sys.argv[2])
width = max(a.shape[1], b.shape[1])
pad = lambda x: np.pad(x, ((0, 0), (0, width - x.shape[1]), (0, 0)), constant_values=1)
tmp = sys.argv[3] + ".tmp.png"
image.imsave(tmp, np.concatenate([pad(a), pad(b)])[::2, ::2])
os.replace(tmp, sys.argv[3])
PY
echo "maps: $out/large_fixed.png (loopDriftRate=0), $out/large_default.png; both: $out/large.png"
