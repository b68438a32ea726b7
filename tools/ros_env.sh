# Sourced by the tools and by hand: the workspace's ROS environment under the system Python, on
# loopback only, and ROS masters of the tools' own, so a run never talks to (or disturbs) another
# roscore on this machine. By hand, ROS_PORT set beforehand picks the master every terminal uses
# (e.g. ROS_PORT=11311); the tools start their own with ros_start_core.
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME
# Also sourced in an interactive shell (docs/getting_started.md): restore the caller's -u.
case $- in *u*) _ros_env_u=1 ;; *) _ros_env_u=0 ;; esac
set +u
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../devel/setup.bash"
[ "$_ros_env_u" = 1 ] && set -u
unset _ros_env_u
# Loopback only (docs/security.md): ROS_IP, not ROS_HOSTNAME=127.0.0.1, because roscpp binds its
# TCPROS server to 127.0.0.1 only for ROS_IP=127.* or ROS_HOSTNAME=localhost; rosmaster and rospy
# bind loopback for either. roscpp's XML-RPC server binds 0.0.0.0 whatever is set.
export ROS_IP=127.0.0.1
unset ROS_HOSTNAME
# By hand: the master on ROS_PORT. In the tools: set by ros_start_core, which a script calls before
# roslaunch or any node.
if [ -n "${ROS_PORT:-}" ]; then
  export ROS_MASTER_URI="http://127.0.0.1:${ROS_PORT}"
else
  unset ROS_MASTER_URI
fi

# ros_start_core: rosmaster and rosout (what roscore starts), each in a process group of its own, on
# a port no other process holds: minibot3d_testing.RosCore keeps a port only once the master there
# answers as its own, and tries another when it is taken. Exports ROS_MASTER_URI; a roslaunch then
# finds the master up and starts only its nodes. ros_stop_core stops them (scripts call it when done
# and from their EXIT trap); a second ros_start_core stops the first core.
ros_core_groups=
ros_start_core() {
  ros_stop_core
  local started
  started="$(/usr/bin/python3 -m minibot3d_testing start-core)" || return 1
  read -r ROS_MASTER_URI ros_core_groups <<< "$started"
  export ROS_MASTER_URI
}
ros_stop_core() {
  # shellcheck disable=SC2086
  [ -z "$ros_core_groups" ] || ros_stop_groups $ros_core_groups
  ros_core_groups=
}
# Waits (bounded: $1 s, default 60) until a roslaunch on this master has set its parameters, which
# nodes read when they start (/use_sim_time in rospy.init_node, /use_lockstep): every launch file
# of the workspace sets /use_sim_time, and roslaunch sets all of a file's parameters in one call
# before it starts a node.
ros_wait_launch() {
  local deadline=$((SECONDS + ${1:-60}))
  until rosparam get /use_sim_time > /dev/null 2>&1; do
    if [ $SECONDS -ge $deadline ]; then
      echo "no roslaunch set its parameters on $ROS_MASTER_URI within ${1:-60} s" >&2
      return 1
    fi
    sleep 0.2
  done
}
# Stops process groups (a `setsid roslaunch ... &`'s, given its PID): SIGINT, then SIGKILL to what
# is left after 15 s; returns once none of their processes is alive. Empty arguments are skipped.
ros_stop_groups() {
  local groups=()
  local g
  for g in "$@"; do [ -z "$g" ] || groups+=("$g"); done
  [ ${#groups[@]} -eq 0 ] || /usr/bin/python3 -m minibot3d_testing stop --grace 15 "${groups[@]}" \
    || true
}
