"""minibot3d_lockstep.digest and tools/lockstep_digest.py on digests written by hand: two runs
that agree, a message that differs (named with its tick, node, topic and publisher, and the
publisher's last tick before it), a node ticked in one run only, a phase stopped later in one run,
and what is left out by default (wall-clock topics, nodes that do not take part)."""
import os
import subprocess
import sys

import pytest
from minibot3d_lockstep import digest

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, '..', '..', 'tools', 'lockstep_digest.py')


class Stamp(object):
    def __init__(self, t):
        self.secs, self.nsecs = int(t), int(round((t - int(t)) * 1e9))


def write_run(directory, map_crc=0xaaaaaaaa, extra_tick=False, stop=3.0, status_crc=0x11111111,
              rsp_crc=0x22222222, run_id='run-1', to_slam_early=0, to_slam_late=0):
    """A phase with three processes: the simulator, /slam (publishes /map) and /explore (receives
    it, and /tf from robot_state_publisher, a non-participant)."""
    sim = digest.DigestWriter(str(directory), '/minibot3d_sim', run_id, pid=1, wall=100.0)
    sim.tick(2, '0.101000000', {('/cmd_vel', '/explore'): (1, 0xcccccccc)})
    sim.close()
    slam = digest.DigestWriter(str(directory), '/slam', run_id, pid=2, wall=100.1)
    slam.tick(1, '0.001000000', {('/scan', '/minibot3d_sim'): (1, 0x0000aaaa)})
    slam.acknowledged([('/map', '/explore', 1)], '0.101000000')
    slam.tick(3, '0.101000000', {('/scan', '/minibot3d_sim'): (2, 0x0000bbbb)})
    slam.acknowledged([('/map', '/explore', 2)], '0.000000000')
    slam.close()
    ex = digest.DigestWriter(str(directory), '/explore', run_id, pid=3, wall=100.2)
    ex.tick(2, '0.101000000', {('/map', '/slam'): (1, 0x12345678),
                               ('/minibot3d_sim/status', '/minibot3d_sim'): (1, status_crc),
                               ('/tf', '/robot_state_publisher'): (1, rsp_crc)})
    ex.acknowledged([('/cmd_vel', '/minibot3d_sim', 1), ('/hint', '/slam', to_slam_early)],
                    '0.201000000')
    ex.tick(4, '0.201000000', {('/map', '/slam'): (2, map_crc)})
    # /slam's last tick was at 0.101: it has left the loop.
    ex.acknowledged([('/cmd_vel', '/minibot3d_sim', 1),
                     ('/hint', '/slam', to_slam_early + to_slam_late)], '0.301000000')
    if extra_tick:
        ex.tick(5, '0.251000000', {})
        ex.acknowledged([], '0.301000000')
    ex.tick(6, '%.9f' % stop, {})
    ex.acknowledged([], '0.000000000')
    ex.close()


def compare(tmp_path, **b):
    write_run(tmp_path / 'a')
    write_run(tmp_path / 'b', **b)
    return digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b'))


def test_identical_runs_agree_even_on_wall_clock_topics_and_non_participants(tmp_path):
    # Breakage caught: the comparison failing to leave out /minibot3d_sim/status (its measured
    # real-time factor) or robot_state_publisher's tf, which differ in every run.
    r = compare(tmp_path, status_crc=0x99999999, rsp_crc=0x88888888)
    assert r.identical, digest.report(r, 'a', 'b')
    assert r.sections == 3 and r.ticks > 0
    lines = digest.report(r, 'a', 'b')
    assert lines[0].startswith('identical')
    # With every node compared, robot_state_publisher's tf is a difference.
    r = digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b'), all_nodes=True)
    assert not r.identical
    assert '/robot_state_publisher' in r.differences[0].details[0]


def test_a_differing_message_is_named_with_its_tick_topic_publisher_and_the_publishers_tick(
        tmp_path):
    # Breakage caught: a comparison that misses a CRC difference, or names the wrong node.
    r = compare(tmp_path, map_crc=0xbbbbbbbb)
    assert not r.identical
    first = r.differences[0]
    assert first.key == (1, '/explore', 0)
    assert first.stamp == '0.201000000'
    assert 'received /map from /slam' in first.details[0]
    assert 'message 2, CRC aaaaaaaa' in first.details[0]
    assert 'message 2, CRC bbbbbbbb' in first.details[0]
    # /slam's last tick before it (tick 3 at 0.101) agreed: it computed something different.
    assert any('/slam published it at or before its tick at 0.101000000 (tick 3)' in d
               for d in first.details), first.details
    text = '\n'.join(digest.report(r, 'a', 'b'))
    assert 'first difference (phase 1): /explore at sim time 0.201000000 (tick 4)' in text


def test_a_tick_in_one_run_only_is_a_difference(tmp_path):
    # Breakage caught: comparing ticks by position only, without their times.
    r = compare(tmp_path, extra_tick=True)
    assert not r.identical
    assert r.differences[0].what == '/explore is ticked at 0.251000000 (tick 5) only in run b'


def test_ticks_after_the_earlier_stop_are_not_compared(tmp_path):
    # Run b's stack was stopped later (a wall-clock moment): its later ticks are left out.
    r = compare(tmp_path, stop=9.0)
    assert r.identical, digest.report(r, 'a', 'b')
    assert 'stopped at' in '\n'.join(digest.report(r, 'a', 'b'))


def test_what_is_sent_to_a_node_after_it_left_is_not_compared(tmp_path):
    # Breakage caught, both ways: a message to a participant that has left (its connection closes
    # at a wall-clock moment, so one run counts it and the other not) reported as a difference;
    # and one sent while it still takes part left out.
    r = compare(tmp_path, to_slam_late=1)
    assert r.identical, digest.report(r, 'a', 'b')
    r = compare(tmp_path / 'early', to_slam_early=1)
    assert not r.identical
    assert r.differences[0].details[0] == 'sent /hint to /slam: a 0 messages so far, b 1'


def test_until_limits_the_comparison_to_a_sim_time(tmp_path):
    # Breakage caught: --until ignored (the map that differs at 0.201 reported all the same).
    write_run(tmp_path / 'a')
    write_run(tmp_path / 'b', map_crc=0xbbbbbbbb)
    r = digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b'), until=0.2)
    assert r.identical and r.last_stamp[1] == '0.101000000', digest.report(r, 'a', 'b')
    assert not digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b'), until=0.201).identical


def test_sections_are_matched_by_phase_whatever_the_run_ids(tmp_path):
    write_run(tmp_path / 'a', run_id='first-master')
    write_run(tmp_path / 'b', run_id='another-master')
    assert digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b')).identical


def test_a_truncated_last_line_is_dropped_and_a_bad_line_named(tmp_path):
    write_run(tmp_path / 'a')
    with open(str(tmp_path / 'a' / 'explore.digest'), 'a') as f:
        f.write('T 7 0.30')  # a killed process
    assert len(digest.read_file(str(tmp_path / 'a' / 'explore.digest'))[0].ticks) == 3
    with open(str(tmp_path / 'a' / 'explore.digest'), 'a') as f:
        f.write('\nX what\n')
    with pytest.raises(ValueError, match=r'explore.digest:\d+: not a lock-step digest line'):
        digest.read_file(str(tmp_path / 'a' / 'explore.digest'))


def test_an_empty_directory_says_what_to_set(tmp_path):
    (tmp_path / 'empty').mkdir()
    with pytest.raises(ValueError, match=digest.DIGEST_ENV):
        digest.read(str(tmp_path / 'empty'))


def test_the_tool_exits_0_1_2_and_prints_the_first_difference(tmp_path):
    write_run(tmp_path / 'a')
    write_run(tmp_path / 'b')
    write_run(tmp_path / 'c', map_crc=0xbbbbbbbb)
    run = lambda *a: subprocess.run([sys.executable, TOOL] + list(a), stdout=subprocess.PIPE,  # noqa: E731
                                    stderr=subprocess.STDOUT, universal_newlines=True)
    same = run('compare', str(tmp_path / 'a'), str(tmp_path / 'b'))
    assert same.returncode == 0 and same.stdout.startswith('identical'), same.stdout
    differ = run('compare', str(tmp_path / 'a'), str(tmp_path / 'c'))
    assert differ.returncode == 1, differ.stdout
    assert 'received /map from /slam' in differ.stdout
    # The topic left out on request: then they agree.
    ignored = run('compare', str(tmp_path / 'a'), str(tmp_path / 'c'), '--ignore', '/map')
    assert ignored.returncode == 0, ignored.stdout
    missing = run('compare', str(tmp_path / 'a'), str(tmp_path / 'nowhere'))
    assert missing.returncode == 2 and 'not a directory' in missing.stdout


def write_goal_run(directory, stamp, whole=True, msg_type='std_msgs/Header'):
    """/move_base receives one message on /move_base/goal from /explore (a std_msgs/Header, for
    brevity), written whole when `whole`."""
    from std_msgs.msg import Header
    import io
    buf = io.BytesIO()
    Header(seq=5, stamp=Stamp(stamp), frame_id='map').serialize(buf)
    data = buf.getvalue()
    ex = digest.DigestWriter(str(directory), '/explore', 'run-1', pid=1, wall=100.0)
    ex.tick(1, '10.000000000', {})
    ex.acknowledged([('/move_base/goal', '/move_base', 1)], '0.000000000')
    ex.close()
    mb = digest.DigestWriter(str(directory), '/move_base', 'run-1', pid=2, wall=100.1)
    mb.tick(2, '10.001000000', {('/move_base/goal', '/explore'): (1, digest.chain_crc(0, data))},
            [('/move_base/goal', '/explore', 1, msg_type, data)] if whole else [])
    mb.acknowledged([], '0.000000000')
    mb.tick(3, '10.100000000', {})  # the phase goes on after it: the tick above is compared
    mb.acknowledged([], '0.000000000')
    mb.close()


def test_a_message_written_whole_is_compared_field_by_field(tmp_path):
    # Breakage caught: M lines not read back, or the report not naming the differing field.
    write_goal_run(tmp_path / 'a', 10.0)
    write_goal_run(tmp_path / 'b', 10.001)
    sections = digest.read(str(tmp_path / 'a'))
    mb = [s for s in sections if s.node == '/move_base'][0]
    assert list(mb.ticks[0].messages) == [('/move_base/goal', '/explore', 1)]
    text = '\n'.join(digest.report(digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b')),
                                   'a', 'b'))
    assert 'message 1 of /move_base/goal from /explore (std_msgs/Header)' in text, text
    assert 'field stamp.nsecs: a 0, b 1000000' in text, text
    assert 'field seq' not in text and 'field frame_id' not in text, text


def test_without_whole_messages_the_report_says_how_to_get_them(tmp_path):
    write_goal_run(tmp_path / 'a', 10.0, whole=False)
    write_goal_run(tmp_path / 'b', 10.001, whole=False)
    text = '\n'.join(digest.report(digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b')),
                                   'a', 'b'))
    assert 'run both again with MINIBOT3D_LOCKSTEP_DIGEST_MESSAGES=/move_base/goal' in text, text


def test_a_type_that_cannot_be_imported_gives_the_bytes(tmp_path):
    write_goal_run(tmp_path / 'a', 10.0, msg_type='no_such_pkg/Goal')
    write_goal_run(tmp_path / 'b', 10.001, msg_type='no_such_pkg/Goal')
    text = '\n'.join(digest.report(digest.compare(str(tmp_path / 'a'), str(tmp_path / 'b')),
                                   'a', 'b'))
    assert 'bytes; ' in text and 'differ, from byte 8 to' in text, text
    assert 'the message type no_such_pkg/Goal can be imported' in text, text


def test_closing_writes_the_last_tick_and_later_calls_write_nothing(tmp_path):
    # A participant closes its digest when it leaves, after a tick it may not acknowledge (a
    # script whose result came): that tick's lines are on disk. Breakage caught: the tick lost
    # by close(), or a later call raising on the closed file.
    w = digest.DigestWriter(str(tmp_path), '/script', 'run-1', pid=1, wall=1.0)
    w.tick(7, '1.000000000', {('/result', '/server'): (1, 0xabcdef01)})
    w.close()
    w.tick(8, '1.100000000', {})
    w.acknowledged([], '0.000000000')
    ticks = digest.read_file(str(tmp_path / 'script.digest'))[0].ticks
    assert [(t.seq, t.received) for t in ticks] == [
        (7, {('/result', '/server'): (1, 'abcdef01')})]
