"""The in-trial client (run by the tool as a subprocess, with the trial's ROS_MASTER_URI): waits
until the stack is ready, sends the goals one after the other with actionlib, and writes
result.json and trajectory.csv (atomically) into the trial directory.

  python3 -m minibot3d_navigation.tuning.driver --dir=TRIAL_DIR --start=X,Y,YAW
      --goals="x,y[,yaw] ..." --timeout=SIM_S [--ready-timeout=WALL_S]

Ready means: the simulator publishes its status, move_base's action server is up, and ~make_plan
returns a path from the robot to the first goal (so the map, amcl's map->odom and the global
costmap are there).  A goal without a yaw gets the heading of the leg that leads to it.

Sim times come from message stamps, never from this node's clock (see run()): time to goal is
from move_base's ~current_goal stamp of the first goal (its acceptance) to the stamp of the last
result; the trajectory is /ground_truth/odom, recorded by `rosbag record`; collisions are the
change of the simulator's status count from just before the first goal to one sim second
after the last result.  --timeout is in sim seconds for the whole route, from the first goal.
Exit status 0 whatever the outcome (it is in result.json), 3 if the stack never became ready.
"""
import argparse
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time

import actionlib
import rosgraph
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from minibot3d_sim.msg import SimStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.srv import GetPlan

RECORD_PERIOD = 0.05  # sim s between recorded poses
STATE_NAMES = {GoalStatus.ABORTED: 'aborted', GoalStatus.REJECTED: 'rejected',
               GoalStatus.PREEMPTED: 'preempted', GoalStatus.RECALLED: 'recalled',
               GoalStatus.LOST: 'lost'}


def parse_route(start, goals):
    """'x,y,yaw' and 'x,y[,yaw] ...' -> start tuple, [(x, y, yaw)] with leg headings filled in."""
    sx, sy, syaw = (float(v) for v in start.split(','))
    route, px, py = [], sx, sy
    for token in goals.split():
        v = [float(t) for t in token.split(',')]
        if len(v) not in (2, 3):
            raise ValueError('goal %r: expected x,y or x,y,yaw' % token)
        yaw = v[2] if len(v) == 3 else math.atan2(v[1] - py, v[0] - px)
        route.append((v[0], v[1], yaw))
        px, py = v[0], v[1]
    if not route:
        raise ValueError('no goals')
    return (sx, sy, syaw), route


def pose_stamped(x, y, yaw):
    p = PoseStamped()
    p.header.frame_id = 'map'
    p.pose.position.x, p.pose.position.y = x, y
    p.pose.orientation.z, p.pose.orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
    return p


class SimClock(object):
    """Sim time and collision count from the simulator's 1 Hz (sim) status: cheap to follow."""

    def __init__(self):
        self.lock = threading.Lock()
        self.sim_time = None
        self.collisions = None
        self.count = 0
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status, queue_size=5)

    def on_status(self, m):
        with self.lock:
            self.sim_time, self.collisions = m.sim_time, m.collisions
            self.count += 1

    def get(self):
        with self.lock:
            return self.sim_time, self.collisions, self.count

    def wait_messages(self, n, wall_timeout):
        """Waits until n more status messages have arrived (bounded); returns the last values."""
        first = self.get()[2]
        deadline = time.monotonic() + wall_timeout
        while self.get()[2] < first + n and time.monotonic() < deadline:
            time.sleep(0.05)
        return self.get()


def write_atomic(path, text):
    with open(path + '.tmp', 'w') as f:
        f.write(text)
    os.replace(path + '.tmp', path)


def wait_ready(client, clock, first_goal, deadline, log):
    """True once the sim runs and move_base can plan to the first goal; False at the deadline."""
    while clock.get()[0] is None:
        if time.monotonic() > deadline:
            log('no /minibot3d_sim/status: the simulator is not running')
            return False
        time.sleep(0.05)
    while not client.wait_for_server(rospy.Duration(1.0)):
        if time.monotonic() > deadline:
            log('no move_base action server')
            return False
    make_plan = rospy.ServiceProxy('/move_base/make_plan', GetPlan)
    while True:
        try:
            make_plan.wait_for_service(timeout=max(0.1, deadline - time.monotonic()))
            if len(make_plan(PoseStamped(), pose_stamped(*first_goal), 0.0).plan.poses) > 1:
                return True
        except (rospy.ROSException, rospy.ServiceException) as e:
            log('make_plan: %s' % e)
        if time.monotonic() > deadline:
            log('move_base never planned to the first goal')
            return False
        time.sleep(0.5)


def read_bag(path):
    """Goal acceptance and result stamps, and the true trajectory (every RECORD_PERIOD sim s)."""
    import rosbag
    accepted, results, rows = [], [], []
    with rosbag.Bag(path) as bag:
        for topic, m, _ in bag.read_messages(
                topics=['/move_base/current_goal', '/move_base/result', '/ground_truth/odom']):
            if topic == '/move_base/current_goal':
                accepted.append(m.header.stamp.to_sec())
            elif topic == '/move_base/result':
                results.append((m.header.stamp.to_sec(), m.status.status))
            else:
                t = m.header.stamp.to_sec()
                if rows and t - rows[-1][0] < RECORD_PERIOD - 1e-6:
                    continue
                q = m.pose.pose.orientation
                yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
                rows.append((t, m.pose.pose.position.x, m.pose.pose.position.y, yaw))
    return accepted, results, rows


def run(args):
    start, route = parse_route(args.start, args.goals)
    os.makedirs(args.dir, exist_ok=True)

    def log(text):
        print('driver: %s' % text, flush=True)

    deadline = time.monotonic() + args.ready_timeout
    while not rosgraph.is_master_online():
        if time.monotonic() > deadline:
            log('no ROS master at %s' % os.environ.get('ROS_MASTER_URI'))
            return 3
        time.sleep(0.1)
    # This client runs on the wall clock on purpose: following /clock (200 Hz of sim time, so
    # 800 messages a second at real-time factor 4) and the 100 Hz ground truth starves a Python
    # node on a loaded machine, and its sim time then lags by tens of seconds.  Every sim time
    # below comes from message stamps: the status topic (1 Hz sim) here, and a `rosbag record`
    # (C++) of the ground truth, move_base's current_goal and result stamps.
    rospy.impl.simtime._is_use_simtime = lambda: False
    rospy.init_node('tune_planner_driver', anonymous=True, disable_signals=True)
    clock = SimClock()
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
    wall0 = time.monotonic()
    if not wait_ready(client, clock, route[0], deadline, log):
        return 3
    bag_path = os.path.join(args.dir, 'run.bag')
    bag = subprocess.Popen(['rosbag', 'record', '--quiet', '--tcpnodelay', '-O', bag_path,
                            '/ground_truth/odom', '/move_base/current_goal', '/move_base/result',
                            '/minibot3d_sim/status'],
                           stdout=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
    try:
        # Recording starts once rosbag has subscribed to the ground truth.
        while not _subscribed('/ground_truth/odom'):
            if time.monotonic() > deadline or bag.poll() is not None:
                log('rosbag record did not start')
                return 3
            time.sleep(0.1)
        sim0, collisions0, _ = clock.wait_messages(1, 30.0)
        log('ready after %.1f wall s' % (time.monotonic() - wall0))

        result = dict(status='reached', reason='', goals_reached=0, goals=len(route))
        wall_start = time.monotonic()
        for i, (x, y, yaw) in enumerate(route):
            goal = MoveBaseGoal()
            goal.target_pose = pose_stamped(x, y, yaw)  # stamp 0: the latest transform
            client.send_goal(goal)
            done = False
            while True:
                if client.wait_for_result(rospy.Duration(0.2)):
                    done = True
                    break
                if clock.get()[0] - sim0 >= args.timeout:
                    break
            if not done:
                client.cancel_goal()
                client.wait_for_result(rospy.Duration(10.0))
                result.update(status='timeout', reason='not reached within %g sim s (at goal '
                              '%d of %d)' % (args.timeout, i + 1, len(route)))
                break
            state = client.get_state()
            if state != GoalStatus.SUCCEEDED:
                result.update(status='aborted', reason='goal %d %s: %s' % (
                    i + 1, STATE_NAMES.get(state, 'state %d' % state),
                    client.get_goal_status_text()))
                break
            result['goals_reached'] = i + 1
        wall_end = time.monotonic()
        # Collisions up to the end: two more status messages (1 sim s apart) cover it.
        _, collisions1, _ = clock.wait_messages(2, 30.0)
    finally:
        if bag.poll() is None:
            bag.send_signal(signal.SIGINT)  # closes the bag properly
        try:
            bag.wait(30.0)
        except subprocess.TimeoutExpired:
            bag.kill()
            bag.wait()
    accepted, results, rows = read_bag(bag_path)
    t0 = accepted[0] if accepted else sim0
    t1 = results[-1][0] if results else (rows[-1][0] if rows else t0)
    rows = [r for r in rows if t0 - RECORD_PERIOD <= r[0] <= t1 + RECORD_PERIOD]
    result.update(time_to_goal=t1 - t0 if result['status'] == 'reached' else None,
                  elapsed=t1 - t0, collisions=int(collisions1 - collisions0),
                  goal_times=[r[0] - a for a, r in zip(accepted, results)],
                  wall_time=wall_end - wall_start,
                  achieved_rtf=(t1 - t0) / max(wall_end - wall_start, 1e-9),
                  final_pose=list(rows[-1][1:]) if rows else None, goal=list(route[-1]))
    write_atomic(os.path.join(args.dir, 'trajectory.csv'),
                 't,x,y,yaw\n' + ''.join('%.3f,%.4f,%.4f,%.4f\n' % r for r in rows))
    write_atomic(os.path.join(args.dir, 'result.json'), json.dumps(result, indent=1))
    os.remove(bag_path)
    log('%s in %.1f sim s (%.1f wall s), %d collisions %s' % (
        result['status'], result['elapsed'], result['wall_time'], result['collisions'],
        result['reason']))
    return 0


def _subscribed(topic):
    """True once the node with this pid subscribes to topic (asks the master)."""
    try:
        import rosgraph.masterapi
        master = rosgraph.masterapi.Master('/tune_planner_driver')
        for t, nodes in master.getSystemState()[1]:
            if t == topic and any(n.startswith('/record') for n in nodes):
                return True
    except Exception:  # master not answering yet: not subscribed
        pass
    return False


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--dir', required=True)
    parser.add_argument('--start', required=True)
    parser.add_argument('--goals', required=True)
    parser.add_argument('--timeout', type=float, required=True, help='sim s for the whole route')
    parser.add_argument('--ready-timeout', type=float, default=180.0, help='wall s')
    args = parser.parse_args(argv)
    try:
        return run(args)
    finally:
        if rospy.core.is_initialized():
            rospy.signal_shutdown('done')


if __name__ == '__main__':
    sys.exit(main())
