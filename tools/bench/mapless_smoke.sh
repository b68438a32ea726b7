#!/usr/bin/env bash
# Closed-loop smoke check of mapless navigation: for each world named, starts
# mapless_navigation.launch on lock-step time at full speed on a master of its own and runs
# tools/bench/mapless_run.py, which sends the world's goal (in odom, from the world's JSON) with
# simple_navi_goals.py and records the true path: one line per world (reached or not, sim time,
# collisions; the clutter world's narrowest gap; in a world with people the closest approach, the
# time within 0.45 m and the collisions with them) and OUT/NAME.json for
# tools/bench/mapless_bench.py and tools/bench/crowd_bench.py.
# A world is a clutter world's index or a .world file with NAME.json beside it (the generators'
# worlds). Exits 0 whatever the outcome (it reports, the rostest asserts).
# ON_MAP=1 runs the same on the world's own map instead (NAME.yaml beside it, as the generators
# write it): amcl_navigation.launch, the robot localized by amcl, the goal sent in map.
#   tools/bench/mapless_smoke.sh [INDEX|WORLD ...]      (default: 0 12 25 37 49)
#   TIMEOUT=150 tools/bench/mapless_smoke.sh 30   # sim seconds for the goal
#   tools/bench/mapless_smoke.sh minibot3d_sim/worlds/crowds/corridor_01.world
set -uo pipefail
caller_dir=$PWD
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
# shellcheck disable=SC1091
source tools/ros_env.sh
OUT="${OUT:-out/mapless_smoke}"
TIMEOUT="${TIMEOUT:-120}"
mkdir -p "$OUT"
indices=("$@")
[ ${#indices[@]} -eq 0 ] && indices=(0 12 25 37 49)
launch_pid=""
cleanup() {
  [ -n "$launch_pid" ] && kill -INT "$launch_pid" 2>/dev/null && wait "$launch_pid" 2>/dev/null
  launch_pid=""
  ros_stop_core
}
trap cleanup EXIT

for i in "${indices[@]}"; do
  if [[ "$i" == *.world ]]; then
    case "$i" in /*) world="$i" ;; *) world="$caller_dir/$i" ;; esac
    name=$(basename "$i" .world)
  else
    name=$(printf 'clutter_%02d' "$i")
    world="minibot3d_sim/worlds/clutter/$name.world"
  fi
  if [ ! -f "$world" ] || [ ! -f "${world%.world}.json" ]; then
    echo "$name: no $world with its ${world%.world}.json" >&2
    continue
  fi
  ros_start_core || exit 1
  case "$world" in /*) ;; *) world="$PWD/$world" ;; esac
  if [ "${ON_MAP:-0}" = 1 ]; then
    if [ ! -f "${world%.world}.yaml" ]; then
      echo "$name: ON_MAP=1 but no map ${world%.world}.yaml beside the world" >&2
      ros_stop_core
      continue
    fi
    roslaunch minibot3d_navigation amcl_navigation.launch world:="$world" \
        map_file:="${world%.world}.yaml" x:=0 y:=0 yaw:=0 lockstep:=true real_time_factor:=0 \
        lockstep_participants:="/amcl /move_base /mapless_run" ${LAUNCH_ARGS:-} \
        > "$OUT/$name.launch.log" 2>&1 &
    frame=map
  else
    roslaunch minibot3d_navigation mapless_navigation.launch world:="$world" \
        lockstep:=true real_time_factor:=0 lockstep_participants:="/move_base /mapless_run" \
        ${LAUNCH_ARGS:-} > "$OUT/$name.launch.log" 2>&1 &
    frame=odom
  fi
  launch_pid=$!
  ros_wait_launch 30
  start=$SECONDS
  if ! /usr/bin/python3 tools/bench/mapless_run.py "${world%.world}.json" \
      "$OUT/$name.json" --timeout "$TIMEOUT" --frame "$frame" > "$OUT/$name.run.log" 2>&1; then
    echo "$name: mapless_run.py failed (see $OUT/$name.run.log)"
  fi
  grep "^$name " "$OUT/$name.run.log" | sed "s/\$/, $((SECONDS - start)) s wall/"
  cleanup
done
