#!/usr/bin/env bash
# SLAM accuracy in the simulator (part of make bench): drives a route in a shipped world while
# recording /scan and /tf to a bag and the true pose to a file, runs slam_offline on the bag, makes
# relations from the true poses at the scan times (Kümmerle et al. 2009) and scores the SLAM
# trajectory with them.
#   tools/bench/slam_sim_bench.sh NAME WORLD MAP X Y YAW "WAYPOINTS" [LAPS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source tools/ros_env.sh
name=$1 world=$(realpath "$2") map=$(realpath "$3") x=$4 y=$5 yaw=$6 waypoints=$7 laps=${8:-1}
out=build/bench/slam_$name
rm -rf "$out" && mkdir -p "$out"
ros_start_core
setsid roslaunch minibot3d_sim minibot3d_gazebo.launch world:="$world" x:="$x" \
  y:="$y" yaw:="$yaw" real_time_factor:=10 > "$out/sim.log" 2>&1 &
sim=$!
rec=
cleanup() {
  ros_stop_groups "$rec" "$sim"  # SIGINT first: rosbag record closes the bag
  ros_stop_core
}
trap cleanup EXIT
ros_wait_launch 60
setsid rosbag record -q -O "$out/drive.bag" /scan /tf /tf_static > "$out/record.log" 2>&1 &
rec=$!
# rosbag record subscribes asynchronously: wait until it is connected to /scan.
for _ in $(seq 1 100); do
  rostopic info /scan 2>/dev/null | grep -q record && break
  sleep 0.1
done
status=0
rosrun minibot3d_sim route_driver.py --map "$map" --waypoints "$waypoints" --laps "$laps" \
  --speed 0.3 --timeout 900 --record "$out/truth_all.txt" || status=$?
cleanup
trap - EXIT
[ $status -eq 0 ] || { echo "slam_sim_bench $name: the drive failed" >&2; exit 1; }
# True poses at the scan times (multiples of 0.1 s of sim time).
awk '{ t = $1 * 10; if (t - int(t + 0.5) < 1e-6 && int(t + 0.5) - t < 1e-6) print }' \
  "$out/truth_all.txt" > "$out/truth.txt"
devel/lib/minibot3d_slam/slam_offline --bag "$out/drive.bag" --scan-topic /scan \
  --base-frame base_footprint --out "$out" --quiet --param-file config/gmapping.yaml \
  | tail -1 | sed "s/^/slam_sim_bench $name: /"
devel/lib/minibot3d_slam/make_relations "$out/truth.txt" "$out/truth.relations" > /dev/null
devel/lib/minibot3d_slam/evaluate_relations "$out/trajectory.txt" "$out/truth.relations" \
  | head -1 | sed "s/^/slam_sim_bench $name: /"
