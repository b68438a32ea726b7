# Sourced by the tools: the workspace's ROS environment under the system Python, and a private ROS
# master port so a run never talks to (or disturbs) another roscore on this machine. ROS_PORT set
# beforehand picks the port (e.g. ROS_PORT=11311 in every terminal used by hand).
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME
# Also sourced by hand in an interactive shell (docs/getting_started.md): restore the caller's -u.
case $- in *u*) _ros_env_u=1 ;; *) _ros_env_u=0 ;; esac
set +u
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../devel/setup.bash"
[ "$_ros_env_u" = 1 ] && set -u
unset _ros_env_u
ros_free_port() {
  /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
ROS_PORT="${ROS_PORT:-$(ros_free_port)}"
export ROS_MASTER_URI="http://127.0.0.1:${ROS_PORT}"
# Loopback only (docs/security.md): ROS_IP, not ROS_HOSTNAME=127.0.0.1, because roscpp binds its
# TCPROS server to 127.0.0.1 only for ROS_IP=127.* or ROS_HOSTNAME=localhost; rosmaster and rospy
# bind loopback for either. roscpp's XML-RPC server binds 0.0.0.0 whatever is set.
export ROS_IP=127.0.0.1
unset ROS_HOSTNAME
# Waits (bounded) until the master at ROS_MASTER_URI answers.
wait_for_master() {
  local deadline=$((SECONDS + ${1:-30}))
  until /usr/bin/python3 -c 'import rosgraph, sys; sys.exit(0 if rosgraph.is_master_online() else 1)' 2>/dev/null; do
    if [ $SECONDS -ge $deadline ]; then echo "no ROS master at $ROS_MASTER_URI" >&2; return 1; fi
    sleep 0.2
  done
}
