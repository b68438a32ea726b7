"""The simulator's collision count as a closed-loop test reads it: SimStatusWatch.

minibot3d_sim publishes its status (minibot3d_sim/SimStatus, latched) once a second of sim time
and at each collision onset, with the collisions so far. A test that only keeps the latest count
passes when no status ever arrived (another topic name, a simulator that stopped publishing), and
one that reads it as soon as its run is over may read a status from before the last moments of
the run. SimStatusWatch counts the messages, and at the end waits for a status stamped at or
after the end of the run::

    from minibot3d_testing.sim_status import SimStatusWatch
    rospy.init_node('my_test')
    status = SimStatusWatch()                  # before the lock-step Participant, as subscribers
    lockstep = Participant(...)
    ...                                        # the run
    self.assertEqual([], status.problems_at_end(lockstep))

Needs rospy and minibot3d_sim's messages (imported when a watch is made): for the tests of
packages that run the simulator.
"""
import threading

STATUS_TOPIC = '/minibot3d_sim/status'


class SimStatusWatch(object):
    """Subscribes to the simulator's status; .messages received, .collisions and .stamp (a
    rospy.Time) of the latest, .first_collision_stamp of the first that counted a collision."""

    def __init__(self, topic=STATUS_TOPIC):
        import rospy
        from minibot3d_sim.msg import SimStatus
        self.topic = topic
        self._lock = threading.Lock()
        self.messages = 0
        self.collisions = 0
        self.stamp = None
        self.first_collision_stamp = None
        rospy.Subscriber(topic, SimStatus, self._on_status, queue_size=10)

    def _on_status(self, msg):
        with self._lock:
            self.messages += 1
            self.collisions = int(msg.collisions)
            self.stamp = msg.header.stamp
            if self.collisions and self.first_collision_stamp is None:
                self.first_collision_stamp = msg.header.stamp

    def problems_at_end(self, participant, timeout=3.0, end=None):
        """What is wrong with the run's collisions, as strings (empty: none, and that is known).

        Call once the run's motion is over: waits, with `participant` (the test's lock-step
        Participant, so sim time moves; anything with its wait_for(predicate, timeout, poll=S))
        for a status stamped at or after `end` (a rospy.Time, default now), at most `timeout` s of
        sim time (the simulator sends one each second), so a collision in the last second of the
        run is counted. Reports no status at all, none after the end, and any collision."""
        import rospy
        if end is None:
            end = rospy.get_rostime()

        def after_end():
            with self._lock:
                return self.stamp is not None and self.stamp >= end
        participant.wait_for(after_end, timeout, poll=0.1)
        with self._lock:
            messages, collisions, stamp = self.messages, self.collisions, self.stamp
            first = self.first_collision_stamp
        if messages == 0:
            return ['no message on %s during the run: the collisions were not checked (is the '
                    'simulator up and publishing its status?)' % self.topic]
        problems = []
        if stamp < end:
            problems.append('no status on %s stamped after the end of the run (t=%.3f s) within '
                            '%g s of sim time; the last was at t=%.3f s' % (
                                self.topic, end.to_sec(), timeout, stamp.to_sec()))
        if collisions:
            problems.append('the simulator reported %d collision(s), the first by t=%.3f s (its '
                            'log names the object)' % (collisions, first.to_sec()))
        return problems
