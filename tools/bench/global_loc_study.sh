#!/usr/bin/env bash
# Global-localization study (part of make bench): for each world, the simulator + map_server +
# amcl on lock-step time (full speed) and tools/bench/global_loc_study.py: N seeded random starts,
# each carried there, /global_localization called once, driven by minibot3d_navigation's wanderer
# (src/minibot3d_navigation/wanderer.py).
# OUT=DIR: where logs and pictures go (build/bench/global_loc); AMCL_PARAMS=YAML: loaded over
# config/amcl.yaml; WANDERER=openings: the wanderer heads for the deepest opening.
# With KIDNAPS=N the first N starts of each world are followed by a kidnapping (see the .py);
# PICTURE_START=K draws start K instead of start 0; TRACE=FILE writes one line per amcl_pose (the .py's --trace).
#   [KIDNAPS=N] tools/bench/global_loc_study.sh [STARTS] [WORLD ...]
#     (default: 10 starts; the default world and the arena)
# Writes build/bench/global_loc/global_loc_WORLD.png: the map, the candidates, the paths of one start.
# Worlds: default, arena, office (minibot3d_sim/worlds/office.world, made by
# tools/generators/office_world.py), or a map_server map (PATH.yaml): the simulator loads it as a
# floor plan (its occupied cells become walls) and amcl the same map, so a SLAM map of a real
# building (slam_offline's map.yaml) is a world too. Its spawn is the most open cell of its largest
# free region (global_loc_study.py --pick-spawn); its outputs are named after the file's directory
# and name (DIR_NAME).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source tools/ros_env.sh
starts=${1:-10}
shift || true
worlds=("$@")
[ ${#worlds[@]} -gt 0 ] || worlds=(default arena)
out=${OUT:-build/bench/global_loc} && mkdir -p "$out"
for w in "${worlds[@]}"; do
  case "$w" in
    default) world_file=minibot3d_sim/worlds/default.world; map=maps/default_world.yaml
      spawn=(-3.0 -1.5 0.0) ;;
    arena) world_file=minibot3d_sim/worlds/arena.world; map=maps/arena.yaml
      spawn=(0.0 0.0 0.0) ;;
    office) world_file=minibot3d_sim/worlds/office.world; map=maps/office.yaml
      spawn=(1.0 6.1667 0.0) ;;
    *.yaml)
      if [ ! -f "$w" ]; then
        echo "global_loc_study.sh: no map at '$w'" >&2
        exit 2
      fi
      map=$w
      read -r sx sy < <(/usr/bin/python3 tools/bench/global_loc_study.py --map "$map" --pick-spawn)
      spawn=("$sx" "$sy" 0.0)
      world_file=$(realpath "$map")
      w=$(basename "$(dirname "$world_file")")_$(basename "$world_file" .yaml) ;;
    *) echo "global_loc_study.sh: unknown world '$w' (default, arena, office or a map's .yaml)" >&2
       exit 2 ;;
  esac
  map=$(realpath "$map")
  ros_start_core
  setsid roslaunch minibot3d_sim minibot3d_gazebo.launch \
    world:="$(realpath "$world_file")" x:=${spawn[0]} y:=${spawn[1]} yaw:=${spawn[2]} \
    real_time_factor:=0 lockstep:=true lockstep_participants:="/amcl /global_loc_study" \
    > "$out/sim_$w.log" 2>&1 &
  sim=$!
  amcl=
  trap 'ros_stop_groups "$amcl" "$sim"; ros_stop_core' EXIT
  ros_wait_launch 60  # amcl reads /use_lockstep, which the simulator's launch sets
  setsid roslaunch minibot3d_navigation amcl_bench_stack.launch map:="$map" \
    x:=${spawn[0]} y:=${spawn[1]} yaw:=${spawn[2]} amcl_params:="${AMCL_PARAMS:-}" \
    > "$out/amcl_$w.log" 2>&1 &
  amcl=$!
  /usr/bin/python3 tools/bench/global_loc_study.py --map "$map" --starts "$starts" --seed 1 \
    --spawn="${spawn[0]},${spawn[1]}"  --kidnaps "${KIDNAPS:-0}" --wanderer "${WANDERER:-sides}" --picture "$out/global_loc_$w.png" --picture-start "${PICTURE_START:-0}" ${TRACE:+--trace "$TRACE"} || true
  ros_stop_groups "$amcl" "$sim"
  ros_stop_core
  trap - EXIT
done
