"""The in-trial client (run by the tool as a subprocess, with the trial's ROS_MASTER_URI): waits
until the stack is ready, sends the goals one after the other with actionlib, records the true
trajectory itself, and writes trajectory.csv then result.json (each atomically: temp file +
rename, and only once the run is over) into the trial directory.

  python3 -m minibot3d_tuning.driver --dir=TRIAL_DIR --start=X,Y,YAW
      --goals="x,y[,yaw] ..." --timeout=SIM_S [--ready-timeout=WALL_S] [--lockstep|--no-lockstep]

The node is /tune_planner_driver (tuning.DRIVER_NODE).  Under lock-step time (/use_lockstep, which
the tool sets by default) it is a participant of the simulator's loop (minibot3d_lockstep), listed
in the stack's lockstep_participants so that it joins before sim time starts: sim time moves only
while it waits (Participant.wait_for), and every message sent to it before a tick has been handled
by its callbacks when it looks, so the same trial gives the same figures in every run.  Without
lock-step the same waits fall back to rospy on sim time.

Ready means: the simulator publishes its status, move_base's action server is connected, and
~make_plan returns a path from the robot to the first goal (so the map, amcl's map->odom and the
global costmap are there).  A goal without a yaw gets the heading of the leg that leads to it.

Sim times come from message stamps: time to goal is from move_base's ~current_goal stamp of the
first goal (its acceptance) to the stamp of the last result; the trajectory is /ground_truth/odom
(every RECORD_PERIOD sim s), appended by a subscriber callback; collisions are the change of the
simulator's status count from the first goal to one sim second after the last result.  --timeout
is in sim seconds for the whole route, from the first goal.  Exit status 0 whatever the outcome
(it is in result.json), 3 if the stack never became ready, 4 if the simulator dropped the driver
from its lock-step loop (DROPPED; the tool reruns the trial); the reason is printed.
"""
import argparse
import json
import math
import os
import sys
import threading
import time

# Before rospy.init_node: counts messages on the connections made after it (lock-step delivery).
from minibot3d_lockstep import (LOCKSTEP_PARAM, PARTICIPANTS_TOPIC, Participant,  # noqa: I100
                                action_server_ready)

import actionlib
import rosgraph
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from minibot3d_lockstep.msg import Participants
from minibot3d_sim.msg import SimStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseActionResult, MoveBaseGoal
from nav_msgs.msg import Odometry
from nav_msgs.srv import GetPlan

from minibot3d_tuning import DRIVER_NODE as NODE_NAME  # in lockstep_participants

DROPPED = 4  # exit status: dropped from the lock-step loop (study.DRIVER_DROPPED)
RECORD_PERIOD = 0.05  # sim s between recorded poses
READY_SIM_TIMEOUT = 120.0  # sim s after time starts for the stack to plan to the first goal
PLAN_RETRY = 0.5  # sim s between make_plan attempts while waiting for the stack
COLLISION_MARGIN = 1.0  # sim s after the last result still counted for collisions
CANCEL_TIMEOUT = 10.0  # sim s for move_base to confirm a cancelled goal
# Advertised by the simulator in both modes once it is up; roslaunch has set every parameter
# (/use_sim_time, /use_lockstep) before it starts any node.
SIM_SERVICE = '/minibot3d_sim/reset'
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


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class Recorder(object):
    """What the result is computed from, filled in by subscriber callbacks: the true trajectory
    (one pose every RECORD_PERIOD sim s of /ground_truth/odom, by stamp), move_base's goal
    acceptances (~current_goal stamps) and results (stamps and states), and the simulator's
    latest status (sim time and collision count).  Under lock-step every message sent before
    a tick has been through these callbacks when the driver looks, so the record is complete."""

    def __init__(self):
        self.lock = threading.Lock()
        self.rows = []       # (t, x, y, yaw)
        self.accepted = []   # stamps
        self.results = []    # (stamp, status)
        self.status = None   # the latest SimStatus
        self._subs = []

    def subscribe(self):
        self._subs = [
            rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, tcp_nodelay=True),
            rospy.Subscriber('/move_base/current_goal', PoseStamped, self.on_goal,
                             tcp_nodelay=True),
            rospy.Subscriber('/move_base/result', MoveBaseActionResult, self.on_result,
                             tcp_nodelay=True),
            rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status,
                             tcp_nodelay=True)]

    def on_truth(self, m):
        t = m.header.stamp.to_sec()
        with self.lock:
            if self.rows and t - self.rows[-1][0] < RECORD_PERIOD - 1e-6:
                return
            p = m.pose.pose
            self.rows.append((t, p.position.x, p.position.y, yaw_of(p.orientation)))

    def on_goal(self, m):
        with self.lock:
            self.accepted.append(m.header.stamp.to_sec())

    def on_result(self, m):
        with self.lock:
            self.results.append((m.header.stamp.to_sec(), m.status.status))

    def on_status(self, m):
        with self.lock:
            self.status = m

    def latest_status(self):
        with self.lock:
            return self.status

    def snapshot(self):
        with self.lock:
            return list(self.accepted), list(self.results), list(self.rows)


def summarize(outcome, route, accepted, results, rows, sim0, collisions0, collisions1, wall):
    """result.json's dict and the trajectory rows inside the route's time span.
    outcome: dict(status, reason, goals_reached); sim0: sim s when the first goal was sent."""
    t0 = accepted[0] if accepted else sim0
    t1 = results[-1][0] if results else (rows[-1][0] if rows else t0)
    rows = [r for r in rows if t0 - RECORD_PERIOD <= r[0] <= t1 + RECORD_PERIOD]
    result = dict(status=outcome['status'], reason=outcome['reason'],
                  goals_reached=outcome['goals_reached'], goals=len(route))
    result.update(time_to_goal=t1 - t0 if result['status'] == 'reached' else None,
                  elapsed=t1 - t0, collisions=int(collisions1 - collisions0),
                  goal_times=[r[0] - a for a, r in zip(accepted, results)],
                  wall_time=wall, achieved_rtf=(t1 - t0) / max(wall, 1e-9),
                  final_pose=list(rows[-1][1:]) if rows else None, goal=list(route[-1]))
    return result, rows


def write_atomic(path, text):
    """Readers see the old file or the whole new one, never a part."""
    tmp = path + '.tmp'
    try:
        with open(tmp, 'w') as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def write_outputs(trial_dir, result, rows):
    """trajectory.csv first, result.json last: a result.json means the trial's files are whole."""
    write_atomic(os.path.join(trial_dir, 'trajectory.csv'),
                 't,x,y,yaw\n' + ''.join('%.3f,%.4f,%.4f,%.4f\n' % r for r in rows))
    write_atomic(os.path.join(trial_dir, 'result.json'), json.dumps(result, indent=1))


def log(text):
    print('driver: %s' % text, flush=True)


def wait_for_simulator(wall_deadline):
    """Before rospy.init_node (which reads /use_sim_time): waits, polling the master, until the
    simulator node has advertised its services.  None when it has, else why not."""
    master = rosgraph.Master('/' + NODE_NAME)
    what = 'no ROS master at %s' % os.environ.get('ROS_MASTER_URI')
    while time.monotonic() < wall_deadline:
        try:
            master.lookupService(SIM_SERVICE)
            return None
        except rosgraph.MasterError:
            what = 'the simulator never advertised %s (did minibot3d_sim start? see stack.log)' \
                % SIM_SERVICE
        except Exception:  # noqa: BLE001 - master not answering yet
            pass
        time.sleep(0.1)
    return what


class Membership(object):
    """Under lock-step: notices the simulator dropping this driver from its loop (no answer within
    its ~lockstep_timeout: a starved or stalled process).  No tick comes after that, and
    Participant.wait_for would wait for one for ever; this shuts rospy down instead, which ends
    the wait, and `dropped` says why."""

    def __init__(self):
        self.dropped = None
        self._joined = self._leaving = False
        self._sub = rospy.Subscriber(PARTICIPANTS_TOPIC, Participants, self._on_participants,
                                     queue_size=10)  # as Participant's own subscription

    def leaving(self):
        self._leaving = True

    def _on_participants(self, msg):
        if rospy.get_name() in msg.names:
            self._joined = True
        elif self._joined and not self._leaving and self.dropped is None:
            self.dropped = ('the simulator dropped this driver from its lock-step loop at sim '
                            'time %.3f (no answer within ~lockstep_timeout: the process was '
                            'starved or stalled; see stack.log)' % msg.stamp.to_sec())
            rospy.signal_shutdown(self.dropped)


class Readiness(object):
    """wait_for predicate: the stack can take the first goal.  `missing` says what is not there
    yet; make_plan is asked at most every PLAN_RETRY sim s."""

    def __init__(self, recorder, client, first_goal):
        self.recorder, self.client = recorder, client
        self.goal = pose_stamped(*first_goal)
        self.make_plan = rospy.ServiceProxy('/move_base/make_plan', GetPlan)
        self.missing = 'sim time never started (no tick / clock from the simulator)'
        self._last_try = None

    def __call__(self):
        if self.recorder.latest_status() is None:
            self.missing = 'no /minibot3d_sim/status from the simulator'
            return False
        if not action_server_ready(self.client):
            self.missing = 'move_base action server not connected'
            return False
        now = rospy.get_rostime().to_sec()
        if self._last_try is not None and now - self._last_try < PLAN_RETRY - 1e-9:
            return False
        self._last_try = now
        try:
            n = len(self.make_plan(PoseStamped(), self.goal, 0.0).plan.poses)
        except (rospy.ROSException, rospy.ServiceException) as e:
            self.missing = 'move_base ~make_plan failed: %s' % e
            return False
        if n > 1:
            return True
        self.missing = 'move_base ~make_plan returned no path to the first goal %.2f,%.2f' % (
            self.goal.pose.position.x, self.goal.pose.position.y)
        return False


def drive(route, client, lockstep, timeout):
    """Sends the goals one after the other; dict(status, reason, goals_reached)."""
    outcome = dict(status='reached', reason='', goals_reached=0)
    end = rospy.get_rostime() + rospy.Duration(timeout)
    done = lambda: client.simple_state == actionlib.SimpleGoalState.DONE  # noqa: E731
    for i, (x, y, yaw) in enumerate(route):
        goal = MoveBaseGoal()
        goal.target_pose = pose_stamped(x, y, yaw)  # stamp 0: the latest transform
        client.send_goal(goal)
        remaining = (end - rospy.get_rostime()).to_sec()
        if remaining <= 0 or not lockstep.wait_for(done, remaining):
            if rospy.is_shutdown():  # not a timeout: the wait was cut short (see run)
                outcome.update(status='error', reason='shut down at goal %d' % (i + 1))
                break
            client.cancel_goal()
            if not lockstep.wait_for(done, CANCEL_TIMEOUT):
                log('move_base did not confirm the cancelled goal within %g sim s'
                    % CANCEL_TIMEOUT)
            outcome.update(status='timeout', reason='not reached within %g sim s (at goal %d '
                           'of %d)' % (timeout, i + 1, len(route)))
            break
        state = client.get_state()
        if state != GoalStatus.SUCCEEDED:
            outcome.update(status='aborted', reason='goal %d %s: %s' % (
                i + 1, STATE_NAMES.get(state, 'state %d' % state), client.get_goal_status_text()))
            break
        outcome['goals_reached'] = i + 1
    return outcome


def run(args):
    start, route = parse_route(args.start, args.goals)
    os.makedirs(args.dir, exist_ok=True)
    wall0 = time.monotonic()
    why = wait_for_simulator(wall0 + args.ready_timeout)
    if why:
        log(why)
        return 3
    try:
        lockstep_on = bool(rosgraph.Master('/' + NODE_NAME).getParam(LOCKSTEP_PARAM))
    except rosgraph.MasterError:  # not set: free-running
        lockstep_on = False
    if args.lockstep is not None and lockstep_on != args.lockstep:
        log('the stack runs with %s=%s, the tool asked for %s' % (
            LOCKSTEP_PARAM, lockstep_on, args.lockstep))
        return 3
    rospy.init_node(NODE_NAME, disable_signals=True)
    recorder = Recorder()
    recorder.subscribe()
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
    ready = Readiness(recorder, client, route[0])
    membership = Membership() if lockstep_on else None

    def dropped():
        return membership is not None and membership.dropped is not None
    # Woken by results (a goal is done) and by the simulator's 1 Hz status (collision counts, and
    # the pace of the readiness checks); every other wait has a sim-time deadline.
    lockstep = Participant(wake_topics=['/move_base/result', '/minibot3d_sim/status'])
    try:
        if not lockstep.wait_for(ready, READY_SIM_TIMEOUT):
            if dropped():
                log(membership.dropped)
                return DROPPED
            log('the stack was not ready within %g sim s: %s' % (READY_SIM_TIMEOUT, ready.missing))
            return 3
        sim0 = rospy.get_rostime().to_sec()
        log('ready after %.1f wall s (sim time %.2f s%s)' % (
            time.monotonic() - wall0, sim0, ', lock-step' if lockstep.enabled else ''))
        collisions0 = recorder.latest_status().collisions
        wall_start = time.monotonic()
        outcome = drive(route, client, lockstep, args.timeout)
        wall = time.monotonic() - wall_start
        # Collisions up to COLLISION_MARGIN sim s after the end: the first status stamped then.
        _, results, _ = recorder.snapshot()
        t_end = (results[-1][0] if results else rospy.get_rostime().to_sec()) + COLLISION_MARGIN
        if not lockstep.wait_for(lambda: recorder.latest_status().sim_time >= t_end - 1e-9,
                                 t_end - rospy.get_rostime().to_sec() + 2.0) \
                and not rospy.is_shutdown():
            log('no simulator status %g sim s after the last result: collisions counted up to '
                '%.2f' % (COLLISION_MARGIN, recorder.latest_status().sim_time))
        collisions1 = recorder.latest_status().collisions
        accepted, results, rows = recorder.snapshot()
        if rospy.is_shutdown():  # the waits above ended early: no result rather than a wrong one
            if dropped():
                log(membership.dropped)
                return DROPPED
            log('rospy shut down before the route was over')
            return 3
    finally:
        if membership is not None:
            membership.leaving()
        lockstep.close()  # leave the loop: the stack's time no longer waits for this script
    result, rows = summarize(outcome, route, accepted, results, rows, sim0, collisions0,
                             collisions1, wall)
    write_outputs(args.dir, result, rows)
    log('%s in %.2f sim s (%.1f wall s), %d collisions %s' % (
        result['status'], result['elapsed'], result['wall_time'], result['collisions'],
        result['reason']))
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--dir', required=True)
    parser.add_argument('--start', required=True)
    parser.add_argument('--goals', required=True)
    parser.add_argument('--timeout', type=float, required=True, help='sim s for the whole route')
    parser.add_argument('--ready-timeout', type=float, default=180.0,
                        help='wall s for the simulator to come up')
    parser.add_argument('--lockstep', action=argparse.BooleanOptionalAction, default=None,
                        help='check that the stack runs with (or without) lock-step time')
    args = parser.parse_args(argv)
    try:
        return run(args)
    finally:
        if rospy.core.is_initialized():
            rospy.signal_shutdown('done')


if __name__ == '__main__':
    sys.exit(main())
