"""The teleop core without ROS: every key, the speed keys, parameter checks, the smoother's ramps
and when a tick publishes."""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))
from minibot3d_teleop import keymap  # noqa: E402
from minibot3d_teleop.keymap import Velocity, ZERO  # noqa: E402

DEFAULTS = keymap.options_from_params({})


def teleop(**params):
    return keymap.Teleop(keymap.options_from_params(params))


def settle(t, ticks=1000):
    """Ticks until the command reaches the target (bounded); returns the number of ticks."""
    for n in range(ticks):
        if t.command == t.target:
            return n
        t.tick()
    raise AssertionError('command %s never reached target %s' % (t.command, t.target))


# -- keys ------------------------------------------------------------------------------------------

@pytest.mark.parametrize('key, linear, angular', [
    ('u', 0.5, 1.5), ('i', 0.5, 0.0), ('o', 0.5, -1.5),
    ('j', 0.0, 1.5), ('k', 0.0, 0.0), ('l', 0.0, -1.5),
    ('m', -0.5, -1.5), (',', -0.5, 0.0), ('.', -0.5, 1.5),
])
def test_every_move_key_sets_its_target(key, linear, angular):
    t = teleop()
    t.on_key('i' if key == 'k' else 'k')  # start elsewhere so that every key changes something
    assert t.on_key(key) in (keymap.MOVE, keymap.STOP)
    assert t.target == Velocity(linear, angular)


@pytest.mark.parametrize('key', [' ', 'k'])
def test_space_and_k_stop(key):
    t = teleop()
    t.on_key('u')
    settle(t)
    assert t.on_key(key) == keymap.STOP
    assert t.target == ZERO
    settle(t)
    assert t.command == ZERO


@pytest.mark.parametrize('key', ['\x03', '\x04'])
def test_ctrl_c_and_ctrl_d_quit(key):
    t = teleop()
    t.on_key('i')
    assert t.on_key(key) == keymap.QUIT
    assert t.target == Velocity(0.5, 0.0)  # the node, not the key, sends the final zero


@pytest.mark.parametrize('key', ['a', 'I', 'K', '\x1b', '[', 'A', '\n', '\ufffd'])
def test_other_keys_change_nothing(key):
    t = teleop()
    t.on_key('o')
    assert t.on_key(key) == keymap.IGNORED
    assert t.target == Velocity(0.5, -1.5)
    assert (t.speed_linear, t.speed_angular) == (0.5, 1.5)


@pytest.mark.parametrize('key, linear, angular', [
    ('q', 1.1, 1.1), ('z', 0.9, 0.9),
    ('w', 1.1, 1.0), ('x', 0.9, 1.0),
    ('e', 1.0, 1.1), ('c', 1.0, 0.9),
])
def test_speed_keys_scale_by_ten_percent(key, linear, angular):
    t = teleop(scale_linear=0.4, scale_angular=2.0)
    t.on_key('u')
    assert t.on_key(key) == keymap.SPEED
    assert t.speed_linear == pytest.approx(0.4 * linear)
    assert t.speed_angular == pytest.approx(2.0 * angular)
    # The direction is kept: the current motion is rescaled at once.
    assert t.target == (pytest.approx(0.4 * linear), pytest.approx(2.0 * angular))


def test_speed_changes_compound_and_survive_a_stop():
    t = teleop()
    for key in 'qqq':
        t.on_key(key)
    t.on_key('k')
    t.on_key(',')
    assert t.target.linear == pytest.approx(-0.5 * 1.1 ** 3)
    for key in 'zzz':
        t.on_key(key)
    assert t.target.linear == pytest.approx(-0.5 * 1.1 ** 3 * 0.9 ** 3)


def test_scale_params_set_the_speeds():
    t = teleop(scale_linear=0.2, scale_angular=0.7)
    t.on_key('.')
    assert t.target == Velocity(-0.2, 0.7)


# -- parameters ------------------------------------------------------------------------------------

def test_defaults():
    assert DEFAULTS == keymap.Options(scale_linear=0.5, scale_angular=1.5, accel_linear=1.0,
                                      accel_angular=3.0, rate=20.0)


def test_integers_are_accepted():
    assert keymap.options_from_params({'rate': 10, 'scale_linear': 1}).rate == 10.0


@pytest.mark.parametrize('name', list(keymap.PARAMS))
@pytest.mark.parametrize('value', [0, 0.0, -1.0, float('nan'), float('inf'), -float('inf'),
                                   '0.5', True, None, [1.0]])
def test_bad_values_are_refused_naming_the_param(name, value):
    with pytest.raises(keymap.ConfigError) as error:
        keymap.options_from_params({name: value})
    assert '~' + name in str(error.value)
    assert repr(value) in str(error.value)


def test_unknown_params_are_reported():
    assert keymap.unknown_params(['scale_linear', 'scale_linaer', 'speed', 'rate']) == [
        'scale_linaer', 'speed']
    assert keymap.unknown_params([]) == []


# -- smoother --------------------------------------------------------------------------------------

def test_ramp():
    assert keymap.ramp(0.0, 1.0, 0.3) == 0.3
    assert keymap.ramp(0.0, -1.0, 0.3) == -0.3
    assert keymap.ramp(0.9, 1.0, 0.3) == 1.0
    assert keymap.ramp(1.0, 1.0, 0.3) == 1.0
    assert keymap.ramp(0.5, -0.5, 0.3) == pytest.approx(0.2)
    # Rounding left over from earlier steps still ends exactly on the target.
    assert keymap.ramp(0.05 + 6.9e-17, 0.0, 0.05) == 0.0


def test_smoother_limits_each_component_per_step():
    s = keymap.VelocitySmoother(accel_linear=1.0, accel_angular=4.0)
    assert s.step(Velocity(0.5, -1.5), 0.1) == (pytest.approx(0.1), pytest.approx(-0.4))
    assert s.step(Velocity(0.5, -1.5), 0.1) == (pytest.approx(0.2), pytest.approx(-0.8))
    assert s.step(Velocity(0.5, -1.5), 0.1) == (pytest.approx(0.3), pytest.approx(-1.2))
    assert s.step(Velocity(0.5, -1.5), 0.1) == (pytest.approx(0.4), -1.5)
    assert s.step(Velocity(0.5, -1.5), 0.1) == (0.5, -1.5)
    s.reset()
    assert s.command == ZERO


@pytest.mark.parametrize('keys', ['i', 'u', 'm', 'j', 'il', 'i.', 'ik', 'q', 'iqqqzz'])
def test_ramps_stay_within_the_acceleration_limits(keys):
    t = teleop(accel_linear=0.8, accel_angular=2.0, rate=10.0)
    max_linear = 0.8 / 10.0 * (1 + 1e-6)
    max_angular = 2.0 / 10.0 * (1 + 1e-6)
    previous = ZERO
    for key in keys:
        t.on_key(key)
        for _ in range(40):  # 4 s: long enough to reach any target here
            command = t.tick() or ZERO
            assert abs(command.linear - previous.linear) <= max_linear
            assert abs(command.angular - previous.angular) <= max_angular
            previous = command
        assert t.command == t.target


def test_time_to_full_speed_follows_accel_and_rate():
    t = teleop(scale_linear=0.5, accel_linear=1.0, rate=20.0)
    t.on_key('i')
    assert settle(t) == 10  # 0.5 m/s at 1 m/s^2 = 0.5 s = 10 ticks of 50 ms
    t = teleop(scale_linear=0.5, accel_linear=0.25, rate=20.0)
    t.on_key('i')
    assert settle(t) == 40


def test_stop_is_ramped_too():
    t = teleop(rate=20.0)  # defaults: 1 m/s^2, 3 rad/s^2
    t.on_key('u')
    settle(t)
    t.on_key(' ')
    assert t.tick() == (pytest.approx(0.45), pytest.approx(1.35))
    assert settle(t) == 9


def test_reversing_passes_through_zero_at_the_ramp_rate():
    t = teleop(accel_linear=1.0, rate=10.0)
    t.on_key('i')
    settle(t)
    t.on_key(',')
    values = [t.tick().linear for _ in range(10)]
    assert values == pytest.approx([0.4, 0.3, 0.2, 0.1, 0.0, -0.1, -0.2, -0.3, -0.4, -0.5])


# -- what a tick publishes -------------------------------------------------------------------------

def test_idle_teleop_publishes_nothing():
    t = teleop()
    assert [t.tick() for _ in range(5)] == [None] * 5
    t.on_key('k')
    assert t.tick() is None


def test_moving_publishes_every_tick_then_one_zero_then_nothing():
    t = teleop()
    t.on_key('i')
    published = [t.tick() for _ in range(15)]
    assert None not in published
    assert published[-1] == Velocity(0.5, 0.0)
    t.on_key('k')
    published = [t.tick() for _ in range(15)]
    assert published[9] == ZERO
    assert published[:9] == [Velocity(pytest.approx(0.5 - 0.05 * n), 0.0) for n in range(1, 10)]
    assert published[10:] == [None] * 5
    t.on_key('j')
    assert t.tick() == Velocity(0.0, pytest.approx(0.15))


def test_status_line_shows_speeds_and_command():
    t = teleop()
    t.on_key('w')
    t.on_key('o')
    t.tick()
    line = t.status_line()
    assert '0.55 m/s' in line and '1.50 rad/s' in line
    assert '+0.05 m/s' in line and '-0.15 rad/s' in line
    assert '\n' not in line


def test_help_lists_every_key():
    for key in list(keymap.MOVE_BINDINGS) + list(keymap.SPEED_BINDINGS):
        assert key in keymap.HELP
    assert 'space' in keymap.HELP and 'not a terminal' in keymap.HELP
    assert not any(math.isnan(v) for v in DEFAULTS)
