#!/bin/bash
# Global localization on real buildings (part of make bench): each real log in LIST is mapped by
# slam_offline (defaults, seed 1) at 0.05 m and at 0.1 m per cell, and each map becomes a
# floor-plan world for tools/bench/global_loc_study.sh (STARTS seeded random starts, a wanderer,
# every amcl_pose scored against the truth: a claim more than 1 m or 30 deg off is false). The
# 0.1 m maps are studied twice: amcl reading the robot's 12 m lidar, and reading only its first
# 3.5 m (laser_max_range, the range of a TurtleBot3-class lidar), which leaves corridors' ends and
# halls' far walls out of sight. Prints one summary line per map and setting.
#
#   tools/bench/real_maps_global_loc.sh LIST [STARTS] [OUT_DIR]
#     LIST: as tools/bench/real_logs_bench.sh's ("NAME LOG [REFERENCE_LOG]"; missing logs are
#     skipped); STARTS: per map and setting (default 10); OUT_DIR: build/bench/real_maps_global_loc
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
list="$(realpath -m "${1:?usage: real_maps_global_loc.sh LIST [STARTS] [OUT_DIR]}")"
starts="${2:-10}"
out="$(realpath -m "${3:-$root/build/bench/real_maps_global_loc}")"
cd "$root"
if ! [[ "$starts" =~ ^[1-9][0-9]*$ ]]; then
  echo "real_maps_global_loc.sh: STARTS='$starts' must be a positive integer" >&2
  exit 2
fi
mkdir -p "$out"
short="$out/amcl_3.5m_lidar.yaml"
echo "laser_max_range: 3.5" > "$short.tmp" && mv "$short.tmp" "$short"
source tools/bench/log_list.sh
read_log_list real_maps_global_loc.sh "$list"
for entry in "${LOGS[@]}"; do
  read -r name log _ <<< "$entry"
  for delta in 0.05 0.1; do
    dir="$out/${name}_$delta"
    devel/lib/minibot3d_slam/slam_offline --log "$log" --out "$dir" --quiet --param seed=1 \
      --param delta="$delta" > /dev/null
    settings=("12 m lidar:")
    [ "$delta" = 0.1 ] && settings+=("3.5 m lidar:$short")
    for setting in "${settings[@]}"; do
      label=${setting%%:*}
      params=${setting#*:}
      log_file="$out/${name}_${delta}_${label// /_}.log"
      OUT="$dir/study_${label// /_}" AMCL_PARAMS="$params" \
        tools/bench/global_loc_study.sh "$starts" "$dir/map.yaml" > "$log_file" 2>&1 || true
      summary=$(grep -E '^global_loc_study map.yaml: ' "$log_file" | sed 's/^global_loc_study map.yaml: //' \
        || echo "no summary (see $log_file)")
      echo "$name, $delta m map, $label: $summary"
    done
  done
done
