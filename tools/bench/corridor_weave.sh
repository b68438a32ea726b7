#!/usr/bin/env bash
# Weaving on a long straight drive: starts the navigation stack on lock-step time at full speed on
# a master of its own and runs tools/bench/corridor_weave.py, which sends a goal straight down a
# corridor along +x and prints the lateral deviation, heading oscillation, angular-velocity sign changes per
# metre and mean speed / max_vel_x.
#   MODE=mapless (default): mapless_navigation.launch in minibot3d_sim/worlds/corridor.world
#     (1.5 m wide, 22 m long), start (0, 0), goal (19.5, 0) in odom, the global costmap widened to 48 m.
#   MODE=explore: explore.launch (SLAM + frontier exploration) in the office world from (3, 19.5) in
#     corridor B, no goal sent: records RECORD_S (120) s of sim time.
#   MODE=office: amcl_navigation.launch in the office world on its map, along corridor B (y = 19.5,
#     2 m wide) from (3, 19.5) to (27, 19.5), the goal in map.
#   tools/bench/corridor_weave.sh [OUT_JSON]         (default out/corridor_weave.json)
#   SPAWN="0 0.3 0.2" tools/bench/corridor_weave.sh /tmp/offset.json   # start off the centre line
#   MODE=office tools/bench/corridor_weave.sh /tmp/office.json
#   LAUNCH_ARGS="physics:=kinematic cmd_wheel_separation_multiplier:=1.0" \
#     tools/bench/corridor_weave.sh
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
# shellcheck disable=SC1091
source tools/ros_env.sh
OUT="${1:-out/corridor_weave.json}"
MODE="${MODE:-mapless}"
mkdir -p "$(dirname "$OUT")"
costmap=$(mktemp /tmp/corridor_costmap.XXXXXX.yaml)
launch_pid=""
cleanup() {
  [ -n "$launch_pid" ] && kill -INT "$launch_pid" 2>/dev/null && wait "$launch_pid" 2>/dev/null
  ros_stop_core
  rm -f "$costmap"
}
trap cleanup EXIT
ros_start_core || exit 1
if [ "$MODE" = explore ]; then
  read -r sx sy syaw <<< "${SPAWN:-3 19.5 0}"
  gx=0; gy=0
  range="${RANGE:-5 25}"
  roslaunch minibot3d_navigation explore.launch \
      world:="$PWD/minibot3d_sim/worlds/office.world" x:="$sx" y:="$sy" yaw:="$syaw" \
      lockstep:=true real_time_factor:=0 lockstep_clients:="/corridor_weave" ${LAUNCH_ARGS:-} \
      > "${OUT%.json}.launch.log" 2>&1 &
  frame=map
  WEAVE_ARGS="--record-only ${RECORD_S:-120} ${WEAVE_ARGS:-}"
elif [ "$MODE" = office ]; then
  read -r sx sy syaw <<< "${SPAWN:-3 19.5 0}"
  read -r gx gy <<< "${GOAL:-27 19.5}"
  range="${RANGE:-5 25}"
  roslaunch minibot3d_navigation amcl_navigation.launch \
      world:="$PWD/minibot3d_sim/worlds/office.world" map_file:="$PWD/maps/office.yaml" \
      x:="$sx" y:="$sy" yaw:="$syaw" lockstep:=true real_time_factor:=0 \
      lockstep_participants:="/amcl /move_base /corridor_weave" ${LAUNCH_ARGS:-} \
      > "${OUT%.json}.launch.log" 2>&1 &
  frame=map
else
  read -r sx sy syaw <<< "${SPAWN:-0 0 0}"
  read -r gx gy <<< "${GOAL:-19.5 0}"
  range="${RANGE:-2 17}"
  # The mapless global costmap (24 m square round the start) widened to 48 m for the corridor.
  sed -e 's/width: 24.0/width: 48.0/; s/height: 24.0/height: 48.0/' \
      -e 's/origin_x: -12.0/origin_x: -24.0/; s/origin_y: -12.0/origin_y: -24.0/' \
      minibot3d_bringup/config/global_costmap_mapless_params.yaml > "$costmap"
  roslaunch minibot3d_navigation mapless_navigation.launch \
      world:="${WORLD:-$PWD/minibot3d_sim/worlds/corridor.world}" global_costmap_params:="$costmap" \
      x:="$sx" y:="$sy" yaw:="$syaw" lockstep:=true real_time_factor:=0 \
      lockstep_participants:="/move_base /corridor_weave" ${LAUNCH_ARGS:-} \
      > "${OUT%.json}.launch.log" 2>&1 &
  frame=odom
fi
launch_pid=$!
ros_wait_launch 30
read -r x0 x1 <<< "$range"
/usr/bin/python3 tools/bench/corridor_weave.py "$gx" "$gy" "$OUT" --spawn "$sx" "$sy" "$syaw" \
    --frame "$frame" --from "$x0" --to "$x1" ${WEAVE_ARGS:-}
