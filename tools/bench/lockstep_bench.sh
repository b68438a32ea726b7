#!/usr/bin/env bash
# make bench, lock-step section (also runs alone): the achieved real-time factor of the full
# closed loop on lock-step time, and what a rospy node that only listens sees of sim time.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source tools/ros_env.sh
mkdir -p build/bench
probe=minibot3d_lockstep/test/lockstep_probe.py

pid=
trap 'ros_stop_groups "$pid"; ros_stop_core' EXIT

echo "== /clock seen by a listening rospy node: free-running simulator at real_time_factor 5, 20, 0"
echo "   (kinematic physics, a constant arc; /clock throttled to ~pub_clock_frequency 1000 Hz wall)"
for rtf in 5 20 0; do
  ros_start_core
  setsid roslaunch minibot3d_sim minibot3d_gazebo.launch physics:=kinematic \
    real_time_factor:="$rtf" cmd_timeout:=1000000 > "build/bench/lockstep_free$rtf.log" 2>&1 &
  pid=$!
  ros_wait_launch 60
  rostopic pub /cmd_vel geometry_msgs/Twist '{linear: {x: 0.2}, angular: {z: 0.4}}' \
    > /dev/null 2>&1 &
  pub=$!
  /usr/bin/python3 tools/bench/clock_listener_bench.py "free-running, RTF $rtf" --seconds 10 || true
  kill "$pub" 2>/dev/null || true
  ros_stop_groups "$pid"
  pid=
  ros_stop_core
done

echo "== the full loop on lock-step time, real_time_factor 0: simulator (Bullet) + map_server +"
echo "   amcl + move_base + a Python goal client, two goals across the default world; 3 runs"
for run in 1 2 3; do
  ros_start_core
  setsid roslaunch minibot3d_navigation amcl_navigation.launch lockstep:=true \
    real_time_factor:=0 lockstep_participants:="/amcl /move_base /probe_route" \
    > "build/bench/lockstep_loop$run.log" 2>&1 &
  pid=$!
  ros_wait_launch 60
  /usr/bin/python3 tools/bench/clock_listener_bench.py "  listener during run $run" --seconds 3 &
  lis=$!
  start=$(date +%s.%N)
  /usr/bin/python3 "$probe" route "build/bench/lockstep_route$run.json" > /dev/null 2>&1 || true
  end=$(date +%s.%N)
  wait "$lis" || true
  ros_stop_groups "$pid"
  pid=
  ros_stop_core
  /usr/bin/python3 - "$run" "$start" "$end" "build/bench/lockstep_route$run.json" <<'PY'
import hashlib, json, sys
run, start, end, path = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
with open(path) as f:
    r = json.load(f)
sim = r['path'][-1][0] - r['path'][0][0]
wall = end - start
digest = hashlib.sha1(json.dumps(r['path']).encode()).hexdigest()[:12]
print('  run %s: %.1f s sim in %.1f s wall (client start to exit): %.1fx real time; goals %s; '
      'trajectory %s' % (run, sim, wall, sim / wall,
                         ', '.join('%.2f s' % g[1] for g in r['goals']), digest))
PY
done
