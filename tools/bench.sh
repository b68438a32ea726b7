#!/usr/bin/env bash
# make bench: prints the performance figures docs/benchmarks.md quotes.
#   [BENCH_LOGS=LIST] tools/bench.sh [CARMEN_LOG]   (the log is for the Intel-style SLAM section; LIST
#   names the real logs of the all-logs section, default tools/bench/real_logs.txt)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source tools/ros_env.sh
log="${1:-}"
bin=devel/lib/minibot3d_sim
world=minibot3d_sim/worlds/default.world
mkdir -p build/bench
urdf=build/bench/minibot3d.urdf
xacro minibot3d_description/urdf/minibot3d.xacro -o "$urdf"
echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
echo "== tree: $(git rev-parse --short HEAD 2>/dev/null || echo 'not a git checkout')$(git diff --quiet HEAD 2>/dev/null || echo ' with uncommitted changes'), started $(date -u '+%Y-%m-%d %H:%M UTC')"
bench_start=$SECONDS

echo "== simulator core (no ROS): 600 s of sim time driving a 1 m square in the default world,"
echo "   lidar 360 beams at 10 Hz, physics step 1 ms, one core"
for physics in kinematic bullet bullet_naive; do
  seconds=600; [ "$physics" = bullet_naive ] && seconds=120
  "$bin/sim_bench" "$urdf" "$world" --physics "$physics" --seconds "$seconds" --x -3 --y -1.5
done

echo "== the other shipped robots in the simulator core, the same square: quadbot (four wheels under a"
echo "   diff_drive_controller, two 541-beam lasers at 10 Hz) and diffbot (diff drive plugin, 360-beam"
echo "   laser, depth camera; every frame rendered) at its camera's 640x480 / 15 Hz, at 320x240 / 15 Hz"
echo "   and at 1920x1080 / 30 Hz (62 M rays per sim second)"
xacro minibot3d_description/urdf/quadbot.xacro -o build/bench/quadbot.urdf
for physics in kinematic bullet; do
  "$bin/sim_bench" build/bench/quadbot.urdf "$world" --physics "$physics" --seconds 300 --x -3 --y -1.5 \
    --controllers config/robots/quadbot/control.yaml
done
for camera in "640 480 15 120" "320 240 15 300" "1920 1080 30 10"; do
  read -r width height rate seconds <<< "$camera"
  xacro minibot3d_description/urdf/diffbot.xacro camera_width:="$width" camera_height:="$height" \
    camera_rate:="$rate" -o build/bench/diffbot.urdf
  "$bin/sim_bench" build/bench/diffbot.urdf "$world" --physics kinematic --seconds "$seconds" \
    --x -3 --y -1.5
done

echo "== several robots in the simulator core, kinematic, the default world: N minibots wandering"
echo "   (arcs while the laser sees nothing within 0.35 m ahead, else a turn in place; back off after a"
echo "   contact), each laser 360 beams at 10 Hz seeing the world and the other robots; mean speed and"
echo "   share of time in contact show the crowd moved"
for n in 1 10 50; do
  "$bin/fleet_bench" "$urdf" "$world" --robots "$n" --seconds 120
done
echo "== people in the simulator core: one minibot as above among 20 pedestrians of the social force"
echo "   model, each walking to and fro along its own straight walk, in the default world (a small"
echo "   apartment, where so many jam) and in the office world"
"$bin/fleet_bench" "$urdf" "$world" --robots 1 --actors 20 --seconds 120
"$bin/fleet_bench" "$urdf" minibot3d_sim/worlds/office.world --robots 1 --actors 20 --seconds 120

echo "== physics step cost (Google Benchmark, ~40 static shapes)"
"$bin/physics_bench" --benchmark_min_time=0.2 2>/dev/null | grep -E "^(BM_|Benchmark|-)" || true
echo "== lidar ray casting (Google Benchmark, default world)"
"$bin/world_slice_bench" --benchmark_min_time=0.2 2>/dev/null | grep -E "^(BM_|Benchmark|-)" || true
echo "== depth camera, 3-D ray casting with Embree (Google Benchmark, default world; rays_per_s and"
echo "   fps are per wall second)"
"$bin/depth_camera_bench" --benchmark_min_time=0.5 2>/dev/null | grep -E "^(BM_|Benchmark|-)" || true

echo "== simulator node (ROS, real_time_factor 0): a constant arc (0.2 m/s, 0.4 rad/s) in the"
echo "   default world with all topics published (odom/tf/joint_states/ground truth 100 Hz,"
echo "   /clock 200 Hz, /scan 10 Hz) and robot_state_publisher running; 3 runs each"
for physics in kinematic kinematic kinematic bullet bullet bullet; do
  ros_start_core
  setsid roslaunch minibot3d_sim minibot3d_gazebo.launch physics:="$physics" \
    real_time_factor:=0 x:=-2.6 y:=-2.1 yaw:=0 cmd_timeout:=1000000 > build/bench/node_$physics.log 2>&1 &
  pid=$!
  ros_wait_launch 60
  rostopic pub /cmd_vel geometry_msgs/Twist '{linear: {x: 0.2}, angular: {z: 0.4}}' > /dev/null 2>&1 &
  pub=$!
  /usr/bin/python3 tools/bench/measure_node_rtf.py "physics=$physics" --warmup 10 --span 600 || true
  kill "$pub" 2>/dev/null || true
  ros_stop_groups "$pid"
  ros_stop_core
done

echo "== simulator node with diffbot (depth camera, laser, IMU; kinematic physics, real_time_factor"
echo "   0), the same arc: the camera at its own 640x480 / 15 Hz and at 320x240 / 15 Hz, with a"
echo "   C++ listener on its depth image and point cloud (cameras render only for a listener), and"
echo "   with nobody listening; one run each"
for camera in "640 480 listened" "320 240 listened" "320 240 unlistened"; do
  read -r width height listen <<< "$camera"
  xacro minibot3d_description/urdf/diffbot.xacro camera_width:="$width" camera_height:="$height" \
    -o build/bench/diffbot_node.urdf
  ros_start_core
  setsid roslaunch minibot3d_sim minibot3d_gazebo.launch physics:=kinematic \
    model:="$PWD/build/bench/diffbot_node.urdf" real_time_factor:=0 x:=-2.6 y:=-2.1 yaw:=0 \
    cmd_timeout:=1000000 > build/bench/node_diffbot.log 2>&1 &
  pid=$!
  ros_wait_launch 60
  sink=
  if [ "$listen" = listened ]; then
    devel/lib/minibot3d_sim/topic_sink /camera/depth/image_raw /camera/depth/points &
    sink=$!
  fi
  rostopic pub /cmd_vel geometry_msgs/Twist '{linear: {x: 0.2}, angular: {z: 0.4}}' > /dev/null 2>&1 &
  pub=$!
  /usr/bin/python3 tools/bench/measure_node_rtf.py "camera=${width}x$height $listen" --warmup 5 \
    --span 60 --timeout 600 || true
  [ -n "$sink" ] && kill -INT "$sink" 2>/dev/null && wait "$sink" || true
  kill "$pub" 2>/dev/null || true
  ros_stop_groups "$pid"
  ros_stop_core
done

tools/bench/lockstep_bench.sh

echo "== AMCL core: one filter update (motion + 60-beam correction + resampling + clustering)"
devel/lib/minibot3d_navigation/amcl_bench --benchmark_min_time=0.2 2>/dev/null | grep -E "^(BM_|Benchmark)" || true

echo "== AMCL in the simulator: tracking (3 laps of the rooms), global localization, kidnapping"
tools/bench/amcl_sim_bench.sh

echo "== AMCL global localization study: seeded random starts, a wanderer, claims vs the truth"
# The office world (tools/generators/office_world.py), the default world and the arena, a
# kidnapping after every start. The office run's picture goes to docs/: start 27, whose kidnapping the look-alike
# check before a claim puts right (README).
KIDNAPS=50 PICTURE_START=27 tools/bench/global_loc_study.sh 50 office default arena
cp build/bench/global_loc/global_loc_office.png docs/global_loc_office.png

echo "== Navigation core: costmap inflation/updates, global planners (A* 2000x2000, OMPL), DWA cycle"
for b in costmap_bench planner_bench dwa_bench; do
  devel/lib/minibot3d_navigation/$b --benchmark_min_time=0.2 --benchmark_counters_tabular=true \
    2>/dev/null | grep -E "^(BM_|Benchmark|-)" || true
done

echo "== move_base in the simulator: 20 random reachable goals in the default world (seed 1)"
tools/bench/nav_sim_bench.sh

echo "== several robots with full stacks (amcl + move_base each, fleet.launch) on lock-step time at"
echo "   full speed: robots swap ends of the default world's corridor (fleet_swap.test; 2 robots,"
echo "   then 3), 3 runs each; per robot reached, time, collisions, and the robots' closest approach"
for scenario in corridor corridor3; do
  for run in 1 2 3; do
    t0=$SECONDS
    rostest --text minibot3d_navigation fleet_swap.test scenario:="$scenario" 2>&1 \
      | grep -E "^fleet_swap:|RESULT" | sed "s/^/  $scenario run $run: /" || true
    echo "  $scenario run $run: $((SECONDS - t0)) s wall, start-up and shut-down included"
  done
done

echo "== a fleet file's robots of three models (config/fleets/mixed.yaml: minibot3d, diffbot,"
echo "   quadbot, tools/fleet.py) crossing the default world at once, each with amcl and move_base,"
echo "   lock-step at full speed (fleet_goals.test), 3 runs"
/usr/bin/python3 tools/fleet.py config/fleets/mixed.yaml --out build/bench/mixed_fleet.launch
for run in 1 2 3; do
  t0=$SECONDS
  rostest --text minibot3d_navigation fleet_goals.test \
    fleet_launch:="$PWD/build/bench/mixed_fleet.launch" names:="scout rover carrier" 2>&1 \
    | grep -E "^fleet_swap:" | sed "s/^/  mixed run $run: /" || true
  echo "  mixed run $run: $((SECONDS - t0)) s wall, start-up and shut-down included"
done

echo "== make demo on the shipped worlds (explore with SLAM until no frontier is left, save the map,"
echo "   localize globally on it, visit the goals; lock-step at full speed): the summary of each"
for spec in "default||" "arena|minibot3d_sim/worlds/arena.world|" \
    "tight_spaces|minibot3d_sim/worlds/tight_spaces.world|DEMO_X=-3 DEMO_Y=-1.2" \
    "office|minibot3d_sim/worlds/office.world|DEMO_X=1.0 DEMO_Y=6.17"; do
  IFS='|' read -r name world_arg env_args <<< "$spec"
  echo "-- $name"
  rm -rf "build/bench/demo_$name/digest"
  # shellcheck disable=SC2086
  env $env_args DEMO_OUT="build/bench/demo_$name" \
    MINIBOT3D_LOCKSTEP_DIGEST="$PWD/build/bench/demo_$name/digest" tools/demo.sh $world_arg \
    > "build/bench/demo_$name.txt" 2>&1 || true
  sed -n '/== make demo summary/,$p' "build/bench/demo_$name.txt" | grep -v "^== make demo summary"
done

echo "== make demo on the 12 generated houses (tools/generators/house_world.py; rooms behind doors"
echo "   0.40-0.90 m wide, pockets behind shelves): share of the reachable free area mapped,"
echo "   exploration sim time, goals reached, rooms holding a reached goal, map accuracy"
for w in minibot3d_sim/worlds/houses/house_*.world; do
  name="$(basename "$w" .world)"
  DEMO_OUT="build/bench/demo_$name" tools/demo.sh "$w" > "build/bench/demo_$name.txt" 2>&1 || true
done
/usr/bin/python3 tools/bench/house_table.py minibot3d_sim/worlds/houses build/bench

echo "== lock-step determinism over 300 s of sim time: an exploration (SLAM, move_base, explore) at"
echo "   real_time_factor 1 against one at 0, and two at 0, one beside two busy processes; digests"
echo "   compared tick for tick (test_lockstep_loop.py at full length)"
MINIBOT3D_EXPLORE_SIM_S=300 MINIBOT3D_PACED_SIM_S=300 /usr/bin/python3 -m pytest -q \
  -p no:cacheprovider minibot3d_lockstep/test/test_lockstep_loop.py -k exploration 2>&1 | tail -1

echo "== lock-step digest cost: the closed loop (simulator, amcl, move_base, a goal client; two goals,"
echo "   real_time_factor 0) 5 times with MINIBOT3D_LOCKSTEP_DIGEST set and 5 times without"
/usr/bin/python3 minibot3d_lockstep/test/digest_cost.py 5

echo "== lock-step determinism: the office demo again beside two busy processes; its lock-step"
echo "   digest compared tick for tick with the run above (tools/lockstep_digest.py), and its summary"
rm -rf build/bench/demo_office_busy
busy=()
for _ in 1 2; do /usr/bin/python3 -c 'while True: pass' & busy+=($!); done
env DEMO_X=1.0 DEMO_Y=6.17 DEMO_OUT=build/bench/demo_office_busy \
  MINIBOT3D_LOCKSTEP_DIGEST="$PWD/build/bench/demo_office_busy/digest" \
  tools/demo.sh minibot3d_sim/worlds/office.world > build/bench/demo_office_busy.txt 2>&1 || true
kill "${busy[@]}"
wait "${busy[@]}" 2>/dev/null || true
/usr/bin/python3 tools/lockstep_digest.py compare build/bench/demo_office/digest \
  build/bench/demo_office_busy/digest || true
summary() {  # the summary without its wall-clock figures
  sed -n '/== make demo summary/,$p' "$1" | sed -E 's/,? [0-9.]+ s wall.*//'
}
if diff <(summary build/bench/demo_office.txt) <(summary build/bench/demo_office_busy.txt) \
    > /dev/null; then
  echo "summaries: identical but for wall times"
else
  echo "summaries: DIFFER (build/bench/demo_office.txt, build/bench/demo_office_busy.txt)"
fi

echo "== mapless navigation through the 50 shipped clutter worlds (mapless_navigation.launch,"
echo "   lock-step at full speed, the goal 5.5 m ahead in odom, 150 s of sim time each)"
rm -rf build/bench/mapless
OUT=build/bench/mapless TIMEOUT=150 tools/bench/mapless_smoke.sh $(seq 0 49) \
  > build/bench/mapless.txt 2>&1 || true
/usr/bin/python3 tools/bench/mapless_bench.py build/bench/mapless \
  --picture docs/mapless_hardest.png || true

echo "== navigation among people: mapless_navigation.launch through tools/generators/crowd_world.py's"
echo "   bench worlds (50 mixed: corridor / hall with social-force pedestrians, hall with DynaBARN-style"
echo "   scripted obstacles, 0.1-0.5 m/s; 10 corridors 2 m wide with 3 people head-on at 0.8-1.2 m/s),"
echo "   the goal 10 m ahead, 120 s of sim time each, without and with moving_obstacles:=true (the"
echo "   obstacle tracker and the DWA's moving-obstacle critic); robot at fault: moving at the onset"
rm -rf build/bench/crowd_worlds build/bench/crowds_off build/bench/crowds_on
/usr/bin/python3 tools/generators/crowd_world.py bench --out build/bench/crowd_worlds > /dev/null
for mode in off on; do
  echo "-- moving_obstacles $mode"
  flag=false
  [ "$mode" = on ] && flag=true
  LAUNCH_ARGS="moving_obstacles:=$flag" OUT=build/bench/crowds_$mode TIMEOUT=120 \
    tools/bench/mapless_smoke.sh build/bench/crowd_worlds/*.world > build/bench/crowds_$mode.txt 2>&1 || true
  picture=()
  [ "$mode" = on ] && picture=(--picture docs/crowd_hardest.png)
  /usr/bin/python3 tools/bench/crowd_bench.py build/bench/crowds_$mode build/bench/crowd_worlds \
    "${picture[@]}" || true
done

echo "== a doorway shut by someone standing in it: amcl_navigation.launch on the map of each of 10"
echo "   doorway worlds of tools/generators/crowd_world.py (seeds 1-10: the hall cut by a wall with one"
echo "   0.9 m door, someone standing in it for 20-40 s, then stepping aside), the goal 10 m ahead"
echo "   beyond it, with the shipped move_base parameters (the wait recovery) and with wait_duration 0"
echo "   (move_base's own recovery list)"
rm -rf build/bench/doorway_worlds build/bench/doorway_wait build/bench/doorway_no_wait
for seed in $(seq 1 10); do
  /usr/bin/python3 tools/generators/crowd_world.py one --kind doorway --seed "$seed" --people 1 \
    --speed 0.5 1.0 --name "$(printf 'doorway_%02d' "$seed")" --out build/bench/doorway_worlds \
    > /dev/null
done
sed 's/^wait_duration:.*/wait_duration: 0.0/' config/move_base_params.yaml \
  > build/bench/move_base_no_wait.yaml
for mode in wait no_wait; do
  echo "-- $mode"
  args=""
  [ "$mode" = no_wait ] && args="move_base_params:=$PWD/build/bench/move_base_no_wait.yaml"
  ON_MAP=1 LAUNCH_ARGS="$args" OUT=build/bench/doorway_$mode TIMEOUT=120 \
    tools/bench/mapless_smoke.sh build/bench/doorway_worlds/*.world > build/bench/doorway_$mode.txt 2>&1 || true
  /usr/bin/python3 tools/bench/crowd_bench.py build/bench/doorway_$mode build/bench/doorway_worlds || true
done

echo "== SLAM on a CARMEN log (slam_offline, gmapping defaults, 30 particles, loop closure on, the"
echo "   readings between processed scans placed by odometry between the processed poses and matched"
echo "   against the final map): 5 seeds, scored against the log's relations"
echo "   (Kuemmerle et al. 2009) when LOG.relations is beside it; load average before each run"
if [ -n "$log" ] && [ -f "$log" ]; then
  relations="${log%.clf}.relations"
  rm -f build/bench/carmen_seeds.txt
  for seed in 1 2 3 4 5; do
    out="build/bench/carmen_s$seed"
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -f "time %e %M" -o "$out.time" devel/lib/minibot3d_slam/slam_offline \
      --log "$log" --out "$out" --quiet --param seed="$seed" > "$out.line"
    score="no relations"
    if [ -f "$relations" ]; then
      score=$(devel/lib/minibot3d_slam/evaluate_relations "$out/trajectory.txt" "$relations" | head -1)
    fi
    echo "seed $seed: $(cat "$out.time") | $score | $(tail -1 "$out.line") | load $load" | tee -a build/bench/carmen_seeds.txt
  done
  /usr/bin/python3 - build/bench/carmen_seeds.txt <<'PY'
import re, statistics as st, sys
rows = [l for l in open(sys.argv[1]) if l.startswith('seed')]
wall = [float(re.search(r'time ([0-9.]+) ([0-9]+)', l).group(1)) for l in rows]
peak = [int(re.search(r'time ([0-9.]+) ([0-9]+)', l).group(2)) / 1024 for l in rows]
tr = [float(m.group(1)) for l in rows for m in [re.search(r'translation_m ([0-9.]+)', l)] if m]
rot = [float(m.group(1)) for l in rows for m in [re.search(r'rotation_deg ([0-9.]+)', l)] if m]
if tr:
    print('Intel, 5 seeds: translation %.4f +- %.4f m, rotation %.3f +- %.3f deg (mean +- std over '
          'seeds); wall %.1f s (%.1f-%.1f); peak %.0f MB'
          % (st.mean(tr), st.stdev(tr), st.mean(rot), st.stdev(rot), st.mean(wall), min(wall),
             max(wall), max(peak)))
    print('published (Intel): GMapping 0.070 m (Kuemmerle 2009); graph mapping 0.031 m, 1.3 deg '
          '(ibid.); Cartographer 0.0229 m, 0.45 deg (Hess et al. 2016)')
else:
    print('wall %.1f s (%.1f-%.1f); peak %.0f MB; no relations to score against'
          % (st.mean(wall), min(wall), max(wall), max(peak)))
PY
  for particles in 10 100; do
    printf 'particles=%s ' "$particles"
    devel/lib/minibot3d_slam/slam_offline --log "$log" --out "build/bench/carmen_$particles" \
      --particles "$particles" --quiet | tail -1
  done
  /usr/bin/python3 minibot3d_slam/scripts/plot_map.py build/bench/carmen_s1/map.yaml \
    build/bench/carmen_s1/trajectory.txt build/bench/carmen_s1/map.png
  cp build/bench/carmen_s1/map.png docs/intel_map.png
  echo "map with trajectory: build/bench/carmen_s1/map.png (README: docs/intel_map.png)"
else
  echo "skipped: no CARMEN log at '${log}' (make bench BENCH_LOG=path/to/log.clf)"
fi

echo "== SLAM on every real log listed in ${BENCH_LOGS:-tools/bench/real_logs.txt} (slam_offline defaults,"
echo "   seeds 1-5, mean +- std): consistency between passes (map_consistency), relations where the"
echo "   log has them, wall time and peak memory; raw odometry's consistency and a reference's beside"
tools/bench/real_logs_bench.sh "${BENCH_LOGS:-tools/bench/real_logs.txt}" build/bench/real_logs || true

echo "== AMCL global localization on real buildings: floor plans from SLAM maps of the same logs"
echo "   (0.05 m and 0.1 m), 10 seeded random starts each; at 0.1 m also with amcl reading 3.5 m"
tools/bench/real_maps_global_loc.sh "${BENCH_LOGS:-tools/bench/real_logs.txt}" 10 \
  build/bench/real_maps_global_loc || true

echo "== SLAM round building-sized loops of long corridors (synthetic logs with their truth,"
echo "   tools/generators/make_building_log.py; slam_offline defaults, seeds 1-3: no loop closure,"
echo "   a fixed window, corridor constraints on, the default)"
tools/bench/building_slam_bench.sh build/bench/building
cp build/bench/building/large.png docs/building_map.png
echo "README: docs/building_map.png"

echo "== SLAM in the simulator (relations from the true pose, Kümmerle et al. 2009; config/gmapping.yaml)"
tools/bench/slam_sim_bench.sh default minibot3d_sim/worlds/default.world maps/default_world.yaml -3 -1.5 0 \
  "-2.1,0.6 -2.4,3.0 -2.1,0.6 -0.3,2.0 0.45,0.6 2.5,-1.0 0.8,-2.15 -3,-1.5" 2
tools/bench/slam_sim_bench.sh arena minibot3d_sim/worlds/arena.world maps/arena.yaml 0 0 0 \
  "1.2,-1.2 1.2,1.0 -1.0,1.2 -1.2,-1.2 0,0" 3

echo "== Trajectory-planner tuning: the six default settings x 3 repeats"
echo "   (min_vel_x {0.01, 0.1} x max_vel_x {0.1, 0.5, 1.0}, the long route, --jobs 2)"
rm -rf build/bench/tune
start=$SECONDS
/usr/bin/python3 minibot3d_tuning/scripts/tune_planner --out build/bench/tune --no-progress \
  || echo "tune_planner: not every setting reached the goal without a collision (see the table)"
echo "wall time of the study: $((SECONDS - start)) s; plots: build/bench/tune/*.png"

echo "== tune_planner on lock-step time: the same trials at real-time factor 1 and at the default 0"
echo "   (min_vel_x 0.1, max_vel_x {0.5, 1.0}, 2 noise seeds each; the results must be identical)"
for rtf in 1 0; do
  rm -rf "build/bench/tune_rtf$rtf"
  /usr/bin/python3 minibot3d_tuning/scripts/tune_planner --out "build/bench/tune_rtf$rtf" \
    --no-progress --rtf "$rtf" --repeats 2 --set min_vel_x=0.1 --set max_vel_x=0.5,1.0 \
    || echo "tune_planner at RTF $rtf: not every trial reached the goal (see build/bench/tune_rtf$rtf)"
done
/usr/bin/python3 - build/bench/tune_rtf1/results.csv build/bench/tune_rtf0/results.csv <<'PY'
import csv, sys
skip = {'key', 'trial', 'rtf', 'wall_time', 'achieved_rtf'}  # how it ran, not what it did
def rows(path):
    with open(path) as f:
        return sorted(tuple((k, v) for k, v in r.items() if k not in skip) for r in csv.DictReader(f))
a, b = rows(sys.argv[1]), rows(sys.argv[2])
print('RTF 1 and RTF 0: %s (%d trials each)' % ('identical results' if a == b else 'RESULTS DIFFER',
                                               len(a)))
PY

echo "== make bench took $(( (SECONDS - bench_start) / 60 )) min wall"
