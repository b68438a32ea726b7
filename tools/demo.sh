#!/usr/bin/env bash
# make demo: the project's main job, headless, on one world.
#   1. explore it with SLAM (sim + slam_gmapping + move_base + explore) until no frontier is left;
#   2. save the map to out/demo_map.{pgm,yaml};
#   3. restart the simulator with amcl + move_base on that map from another start pose, localize
#      globally, and visit a list of goals with simple_navi_goals.py;
#   4. print the summary table and write out/demo.png.
#   tools/demo.sh [--robot NAME | --config DIR [--model XACRO]] [WORLD]
# The robot: minibot3d (config/) by default; --robot NAME a shipped one (config/robots/NAME);
# --config DIR a user's config set (its robot.yaml names the model, topics and controllers: see
# config/robot.yaml), --model XACRO replacing robot.yaml's model (it needs --config or --robot).
# tools/robot_config.py reads robot.yaml; its args (model, config_dir, robot_params, scan_topic,
# cmd_vel_topic, odom_topic, the skid-steer calibration) go to both phases' roslaunch.
# Environment: DEMO_X, DEMO_Y, DEMO_YAW (exploration spawn), DEMO_NAV_X, DEMO_NAV_Y, DEMO_NAV_YAW
# (navigation start), DEMO_GOALS ("x,y,yaw ..." in the world frame), DEMO_REAL_TIME_FACTOR (0: as
# fast as the CPU allows), DEMO_LOCKSTEP (1: lock-step time, the same result on every run; 0: the
# free-running loop), DEMO_OUT (where the maps, logs and picture go; default out/),
# DEMO_EXPLORE_TIMEOUT (the exploration's sim-time budget, s; default 2.5 s per m^2 of reachable
# free area, at least 2,400), DEMO_LOG_FILTER (which exploration log lines to show; a grep -E
# pattern), DEMO_ROBOT, DEMO_CONFIG, DEMO_MODEL (as --robot, --config, --model), DEMO_ODOM_ERROR
# (the simulator's odometry error in both phases, a YAML of odom_error_* values; default
# minibot3d_sim/config/typical_odometry_error.yaml, a typical small indoor robot's; none: the
# drive's odometry exactly).
# For the default world all have defaults; for another world the spawn defaults to its origin and
# the goals are sampled from the saved map.
set -euo pipefail
usage="usage: tools/demo.sh [--robot NAME | --config DIR [--model XACRO]] [WORLD]"
robot="${DEMO_ROBOT:-}"; config="${DEMO_CONFIG:-}"; model="${DEMO_MODEL:-}"
while [ $# -gt 0 ]; do
  case "$1" in
    --robot) robot="${2:?$usage}"; shift 2 ;;
    --config) config="${2:?$usage}"; shift 2 ;;
    --model) model="${2:?$usage}"; shift 2 ;;
    -h|--help) echo "$usage"; exit 0 ;;
    -*) echo "demo: unknown option $1; $usage" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -le 1 ] || { echo "demo: one WORLD at most; $usage" >&2; exit 2; }
# Paths given relative to where demo.sh was started.
[ -z "$config" ] || config="$(realpath -m "$config")"
[ -z "$model" ] || model="$(realpath -m "$model")"
world_arg="${1:+$(realpath -m "$1")}"
odom_error="${DEMO_ODOM_ERROR:-}"
[ -z "$odom_error" ] || [ "$odom_error" = none ] || odom_error="$(realpath -m "$odom_error")"
out="$(realpath -m "${DEMO_OUT:-$(dirname "${BASH_SOURCE[0]}")/../out}")"
cd "$(dirname "${BASH_SOURCE[0]}")/.."
if [ -n "$robot" ] && [ -n "$config" ]; then
  echo "demo: ROBOT=$robot and CONFIG=$config both name a config set: give one" >&2
  exit 2
fi
if [ -n "$model" ] && [ -z "$robot$config" ]; then
  echo "demo: MODEL=$model needs CONFIG=path/to/config_dir (tools/demo.sh --config DIR): the" \
    "robot's config set, gmapping.yaml, amcl.yaml, ... as in config/, and a robot.yaml for its" \
    "topics and controllers (see config/robot.yaml)" >&2
  exit 2
fi
if [ -n "$robot" ]; then
  config="$(pwd)/config/robots/$robot"
  if [ ! -d "$config" ]; then
    echo "demo: no shipped robot $robot (config/robots/$robot); the shipped ones:" \
      "$(cd config/robots && echo */ | tr -d /)" >&2
    exit 2
  fi
fi
config="${config:-$(pwd)/config}"
source tools/ros_env.sh
# The robot's launch args, one name:=value a line (robot_config.py names what is wrong).
robot_args=()
while IFS= read -r line; do robot_args+=("$line"); done \
  < <(/usr/bin/python3 tools/robot_config.py "$config" ${model:+--model "$model"} || echo FAILED)
if [ "${#robot_args[@]}" = 0 ] || [ "${robot_args[${#robot_args[@]} - 1]}" = FAILED ]; then
  echo "demo: the robot's config set $config is not usable (above)" >&2
  exit 2
fi
robot_arg() {  # the value of one of robot_args
  local a
  for a in "${robot_args[@]}"; do [ "${a%%:=*}" != "$1" ] || { echo "${a#*:=}"; return; }; done
}
default_world="$(pwd)/minibot3d_sim/worlds/default.world"
world="$(realpath "${world_arg:-$default_world}")"
if [ "$world" = "$default_world" ]; then
  x="${DEMO_X:--3.0}"; y="${DEMO_Y:--1.5}"; yaw="${DEMO_YAW:-0.0}"
  nx="${DEMO_NAV_X:-2.5}"; ny="${DEMO_NAV_Y:--1.0}"; nyaw="${DEMO_NAV_YAW:-1.57}"
  goals="${DEMO_GOALS:--2.1,0.6,1.57 -0.3,2.0,0 2.5,-1.0,-1.57 0.8,-2.15,3.14 -3.0,-1.5,0}"
else
  # Another world: spawn at DEMO_X/Y/YAW (default the origin, which must then be free); navigation
  # starts there turned round unless DEMO_NAV_* say otherwise; goals are sampled from the saved
  # map unless DEMO_GOALS lists them.
  x="${DEMO_X:-0.0}"; y="${DEMO_Y:-0.0}"; yaw="${DEMO_YAW:-0.0}"
  nx="${DEMO_NAV_X:-$x}"; ny="${DEMO_NAV_Y:-$y}"
  nyaw="${DEMO_NAV_YAW:-$(/usr/bin/python3 -c "import math; print(math.remainder($yaw + math.pi, 2 * math.pi))")}"
  goals="${DEMO_GOALS:-}"
fi
odom_error="${odom_error:-$(pwd)/minibot3d_sim/config/typical_odometry_error.yaml}"
if [ "$odom_error" != none ] && [ ! -f "$odom_error" ]; then
  echo "demo: DEMO_ODOM_ERROR=$odom_error: no such file (a YAML of odom_error_* values, or none)" >&2
  exit 2
fi
lockstep="${DEMO_LOCKSTEP:-1}"
if [ "$lockstep" = 1 ]; then ls_arg=true; else ls_arg=false; fi
rtf="${DEMO_REAL_TIME_FACTOR:-$([ "$lockstep" = 1 ] && echo 0 || echo 5)}"
mkdir -p "$out"
rm -f "$out"/demo_explore.json "$out"/demo_nav.json

if [ "$world" = "$default_world" ]; then
  truth="$(pwd)/maps/default_world.yaml"
else
  devel/lib/minibot3d_sim/render_world_map "$world" "$out/demo_truth" > /dev/null
  truth="$out/demo_truth.yaml"
fi

launch_pid=
stop_stack() {
  ros_stop_groups "$launch_pid"
  launch_pid=
  ros_stop_core
}
trap stop_stack EXIT
start=$SECONDS

# The exploration's sim-time budget grows with the world: 2.5 s per m^2 of free area reachable
# from the spawn (the office world, 2,654 m^2, gets 6,636 s), at least 2,400 s.
budget="${DEMO_EXPLORE_TIMEOUT:-$(/usr/bin/python3 tools/demo_report.py --reachable-area --out "$out" \
  --truth-map "$truth" --spawn="$x,$y,$yaw" --config-dir "$config" \
  | awk '{b = 2.5 * $1; print (b > 2400 ? int(b) : 2400)}')}"
echo "demo: robot $(robot_arg model) with the config set $config, odometry error $odom_error"
echo "demo: 1/4 exploring $world from ($x, $y, $yaw) with SLAM at real-time factor $rtf," \
  "lock-step $ls_arg, for at most $budget s of sim time (log: $out/demo_explore.log)"
ros_start_core
setsid roslaunch minibot3d_navigation explore.launch explore:=false world:="$world" \
  x:="$x" y:="$y" yaw:="$yaw" real_time_factor:="$rtf" lockstep:="$ls_arg" \
  lockstep_clients:=/demo_explore odom_error_params:="$odom_error" "${robot_args[@]}" \
  > "$out/demo_explore.log" 2>&1 &
launch_pid=$!
ros_wait_launch 60
status=0
/usr/bin/python3 tools/demo_phase.py explore --out "$out" --timeout "$budget" \
  --config-dir "$config" 2>&1 \
  | grep --line-buffered -E "${DEMO_LOG_FILTER:-explore: .*(m\^2|complete)|demo:|map_saver}" || true
[ -f "$out/demo_explore.json" ] || status=1
stop_stack
echo "demo: 2/4 map saved: $out/demo_map.pgm, $out/demo_map.yaml"

echo "demo: 3/4 navigating on the saved map from ($nx, $ny, $nyaw), global localization" \
  "(log: $out/demo_nav.log)"
ros_start_core
setsid roslaunch minibot3d_navigation amcl_navigation.launch world:="$world" \
  map_file:="$out/demo_map.yaml" x:="$nx" y:="$ny" yaw:="$nyaw" initial_pose_x:=0 \
  initial_pose_y:=0 initial_pose_a:=0 real_time_factor:="$rtf" lockstep:="$ls_arg" \
  lockstep_participants:="/amcl /move_base /demo_navigate" odom_error_params:="$odom_error" \
  "${robot_args[@]}" \
  > "$out/demo_nav.log" 2>&1 &
launch_pid=$!
ros_wait_launch 60
# The wanderer drives on the robot's command topic and reads its laser (ROS remappings).
/usr/bin/python3 tools/demo_phase.py navigate --out "$out" --spawn="$x,$y,$yaw" --goals "$goals" \
  --timeout 300 --config-dir "$config" scan:="$(robot_arg scan_topic)" \
  cmd_vel:="$(robot_arg cmd_vel_topic)" || status=1
stop_stack

echo "demo: 4/4 report"
/usr/bin/python3 tools/demo_report.py --out "$out" --truth-map "$truth" --spawn="$x,$y,$yaw" \
  --config-dir "$config" || status=1
echo "demo: $((SECONDS - start)) s wall in all"
exit $status
