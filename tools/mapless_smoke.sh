#!/usr/bin/env bash
# Closed-loop smoke check of mapless navigation (issue 18): for each clutter world named, starts
# mapless_navigation.launch on lock-step time at full speed on a private master, sends the goal 5.5 m
# ahead in odom with simple_navi_goals.py, and prints one line per world: reached or not, sim time,
# collisions, and the world's narrowest gap. Exits 0 whatever the outcome (it reports, the
# rostest asserts).
#   tools/mapless_smoke.sh [INDEX ...]      (default: 0 12 25 37 49)
#   TIMEOUT=150 tools/mapless_smoke.sh 30   # sim seconds for the goal
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck disable=SC1091
source tools/ros_env.sh
OUT="${OUT:-out/mapless_smoke}"
TIMEOUT="${TIMEOUT:-120}"
mkdir -p "$OUT"
indices=("$@")
[ ${#indices[@]} -eq 0 ] && indices=(0 12 25 37 49)
launch_pid=""
cleanup() { [ -n "$launch_pid" ] && kill -INT "$launch_pid" 2>/dev/null && wait "$launch_pid" 2>/dev/null; }
trap cleanup EXIT

for i in "${indices[@]}"; do
  name=$(printf 'clutter_%02d' "$i")
  world="minibot3d_sim/worlds/clutter/$name.world"
  gap=$(/usr/bin/python3 -c "import json; print(json.load(open('minibot3d_sim/worlds/clutter/$name.json'))['achieved_gap'])")
  ROS_PORT=$(ros_free_port)
  export ROS_MASTER_URI="http://127.0.0.1:${ROS_PORT}"
  roslaunch -p "$ROS_PORT" minibot3d_navigation mapless_navigation.launch world:="$PWD/$world" \
      lockstep:=true real_time_factor:=0 lockstep_participants:="/move_base /simple_navi_goals" \
      > "$OUT/$name.launch.log" 2>&1 &
  launch_pid=$!
  wait_for_master 30
  start=$SECONDS
  rosrun minibot3d_navigation simple_navi_goals.py --frame odom 5.5 0 0 --timeout "$TIMEOUT" \
      > "$OUT/$name.goal.log" 2>&1
  rc=$?
  wall=$((SECONDS - start))
  collisions=$(timeout 20 rostopic echo -n 1 /minibot3d_sim/status/collisions 2>/dev/null | head -1)
  result=$(grep -o 'Result: [A-Z]*[^[]*' "$OUT/$name.goal.log" | tail -1)
  [ -z "$result" ] && result=$(grep -o 'Goal not reached.*\|No action server.*' "$OUT/$name.goal.log" | tail -1)
  truth=$(timeout 20 rostopic echo -n 1 /ground_truth/odom/pose/pose/position 2>/dev/null | tr '\n' ' ')
  printf '%s gap %.3f m: %s, exit %d, collisions %s, %d s wall, final true position %s\n' \
      "$name" "$gap" "${result:-no result}" "$rc" "${collisions:-?}" "$wall" "$truth"
  cleanup
  launch_pid=""
done
