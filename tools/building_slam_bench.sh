#!/bin/bash
# SLAM round building-sized loops of long corridors, on synthetic logs with a known truth
# (tools/make_building_log.py): slam_offline with gmapping's defaults, seed 1, three ways — the
# plain RBPF (loopClosure=0), loop closure with a fixed search window (loopDriftRate=0), and the
# defaults (the window grows with the path driven since the submap). Each trajectory is scored
# against relations made from the truth: over ≤ 10 s (local accuracy) and over any span (the map's
# global consistency: a bent corridor or a loop left open shows there).
#
#   tools/building_slam_bench.sh [OUT_DIR]     (default build/bench/building; run from the repo root)
# Writes OUT_DIR/NAME_{open,fixed,default}/ and, for the large building, the maps with the fixed
# window and the default one, one above the other, in OUT_DIR/large.png.
set -euo pipefail
out="${1:-build/bench/building}"
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
  echo "$name: $(/usr/bin/python3 tools/make_building_log.py "$out/$name.clf" "$out/$name.truth" $args) [$args]"
  "$bin/make_relations" "$out/$name.truth" "$out/$name.rel" > /dev/null
  "$bin/make_relations" "$out/$name.truth" "$out/$name.long.rel" --max-span 100000 --every 5 > /dev/null
  for variant in "open loopClosure=0" "fixed loopDriftRate=0" "default seed=1"; do
    tag="${variant%% *}"
    dir="$out/${name}_$tag"
    /usr/bin/time -f "%e %M" -o "$dir.time" "$bin/slam_offline" --log "$out/$name.clf" --out "$dir" --quiet \
      --param seed=1 --param "${variant#* }" > "$dir.line"
    local_score=$("$bin/evaluate_relations" "$dir/trajectory.txt" "$out/$name.rel" | head -1)
    global_score=$("$bin/evaluate_relations" "$dir/trajectory.txt" "$out/$name.long.rel" | head -1)
    read -r wall kb < "$dir.time"
    closures=$(sed -n 's/.*loop_closures \([0-9]*\).*/\1/p' "$dir.line")
    printf '  %-8s ≤10 s: %s | any span: %s | closures %s, wall %s s, peak %d MB\n' "$tag" \
      "$(echo "$local_score" | cut -d' ' -f3-8)" "$(echo "$global_score" | cut -d' ' -f3-8)" "$closures" "$wall" \
      $((kb / 1024))
  done
done
/usr/bin/python3 minibot3d_slam/scripts/plot_map.py "$out/large_default/map.yaml" "$out/large_default/trajectory.txt" \
  "$out/large_default.png"
/usr/bin/python3 minibot3d_slam/scripts/plot_map.py "$out/large_fixed/map.yaml" "$out/large_fixed/trajectory.txt" \
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
