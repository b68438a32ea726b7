# Sourced by the tools: the workspace's ROS environment under the system Python, and a private ROS
# master port so a run never talks to (or disturbs) another roscore on this machine.
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME
set +u
# shellcheck disable=SC1091
source "$(dirname "${BASH_SOURCE[0]}")/../devel/setup.bash"
set -u
ros_free_port() {
  /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
ROS_PORT="${ROS_PORT:-$(ros_free_port)}"
export ROS_MASTER_URI="http://127.0.0.1:${ROS_PORT}"
export ROS_HOSTNAME=127.0.0.1
unset ROS_IP
