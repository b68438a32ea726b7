"""The ROS-free core of the keyboard teleop: keys -> target velocity, and a velocity smoother.

The key layout and the speed keys are turtlebot_teleop's keyboard teleop
(turtlebot_teleop_key): a key sets a direction (each of linear and angular is -1, 0 or +1) that is
scaled by the current linear and angular speeds; q/z, w/x and e/c change those speeds by 10 %.
The reverse keys m and . mirror the turn as turtlebot's do (m: back with angular -1, .: back with
angular +1), so the robot backs up along the arc a car would.

The smoother ramps the commanded twist towards the target by at most accel * period per tick, for
speeding up and slowing down alike, each component on its own. It is ticked at a fixed period
(1 / rate), so a run is repeatable and its steps are known exactly.

Teleop ties both together: the node feeds it keys and calls tick() once per period; tick() says
what to publish. While the robot moves (or is told to) every tick is published; once it has come
to rest one zero twist is published and then nothing, so an idle teleop does not fight other
sources of cmd_vel (move_base)."""
import collections
import math

Velocity = collections.namedtuple('Velocity', 'linear angular')
ZERO = Velocity(0.0, 0.0)

# key -> (linear direction, angular direction)
MOVE_BINDINGS = {
    'u': (1, 1), 'i': (1, 0), 'o': (1, -1),
    'j': (0, 1), 'k': (0, 0), 'l': (0, -1),
    'm': (-1, -1), ',': (-1, 0), '.': (-1, 1),
}
STOP_KEYS = (' ', 'k')
# key -> (linear speed factor, angular speed factor)
SPEED_BINDINGS = {
    'q': (1.1, 1.1), 'z': (0.9, 0.9),
    'w': (1.1, 1.0), 'x': (0.9, 1.0),
    'e': (1.0, 1.1), 'c': (1.0, 0.9),
}
# In raw mode Ctrl-C and Ctrl-D arrive as characters; both end the teleop.
QUIT_KEYS = ('\x03', '\x04')

# What a key did (Teleop.on_key's return value).
MOVE, SPEED, STOP, QUIT, IGNORED = 'move', 'speed', 'stop', 'quit', 'ignored'

# name -> (default, unit); every one must be a positive finite number.
PARAMS = collections.OrderedDict([
    ('scale_linear', (0.5, 'm/s')),
    ('scale_angular', (1.5, 'rad/s')),
    ('accel_linear', (1.0, 'm/s^2')),
    ('accel_angular', (3.0, 'rad/s^2')),
    ('rate', (20.0, 'Hz')),
])

HELP = """\
Keyboard teleop for minibot3d (publishes geometry_msgs/Twist on ~cmd_vel).
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

q/z : increase/decrease both speeds by 10 %
w/x : increase/decrease only the linear speed by 10 %
e/c : increase/decrease only the angular speed by 10 %
space or k : stop
Ctrl-C or Ctrl-D : stop the robot and quit

The twist is ramped towards the key's target at ~accel_linear / ~accel_angular and
published at ~rate Hz. If stdin is not a terminal, keys are read from it as they come
(pipes, tests); end of input stops the robot and quits.
"""


class ConfigError(ValueError):
    """A parameter has a bad value; the message names it and says what is allowed."""


Options = collections.namedtuple('Options', list(PARAMS))


def options_from_params(params):
    """Options from a dict of private parameters (missing ones take their defaults).

    Raises ConfigError naming the first parameter that is not a positive finite number."""
    values = {}
    for name, (default, unit) in PARAMS.items():
        value = params.get(name, default)
        # bool is an int to Python, but "scale_linear: true" is a typo, not a speed.
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        if not number or not math.isfinite(value) or value <= 0:
            raise ConfigError('~%s must be a positive finite number (%s), got %r'
                              % (name, unit, value))
        values[name] = float(value)
    return Options(**values)


def unknown_params(names):
    """The names in `names` that are not parameters of the teleop (misspellings), sorted."""
    return sorted(set(names) - set(PARAMS))


def ramp(current, target, max_step):
    """current moved towards target by at most max_step (exactly target once within reach).

    "Within reach" allows for rounding: after n steps of 0.05 from 0.5 the remainder may be
    6.9e-17 short of a step, and the robot must then stop, not creep at 1e-17 m/s."""
    if abs(target - current) <= max_step * (1.0 + 1e-9):
        return target
    return current + math.copysign(max_step, target - current)


class VelocitySmoother(object):
    """Limits the change of each twist component to accel * dt per step."""

    def __init__(self, accel_linear, accel_angular):
        self.accel_linear = accel_linear
        self.accel_angular = accel_angular
        self.command = ZERO

    def step(self, target, dt):
        """Moves the command towards `target` (a Velocity) over `dt` seconds; returns it."""
        self.command = Velocity(ramp(self.command.linear, target.linear, self.accel_linear * dt),
                                ramp(self.command.angular, target.angular,
                                     self.accel_angular * dt))
        return self.command

    def reset(self):
        self.command = ZERO


class Teleop(object):
    """Key state (direction, speeds) and the smoother, ticked at options.rate."""

    def __init__(self, options):
        self.options = options
        self.period = 1.0 / options.rate
        self.speed_linear = options.scale_linear
        self.speed_angular = options.scale_angular
        self.direction = (0, 0)
        self.smoother = VelocitySmoother(options.accel_linear, options.accel_angular)
        self._last_published = ZERO

    @property
    def target(self):
        return Velocity(self.direction[0] * self.speed_linear,
                        self.direction[1] * self.speed_angular)

    @property
    def command(self):
        return self.smoother.command

    def on_key(self, key):
        """Applies one key (a one-character string); returns MOVE, SPEED, STOP, QUIT or IGNORED."""
        if key in STOP_KEYS:
            self.direction = (0, 0)
            return STOP
        if key in MOVE_BINDINGS:
            self.direction = MOVE_BINDINGS[key]
            return MOVE
        if key in SPEED_BINDINGS:
            factor_linear, factor_angular = SPEED_BINDINGS[key]
            self.speed_linear *= factor_linear
            self.speed_angular *= factor_angular
            return SPEED
        if key in QUIT_KEYS:
            return QUIT
        return IGNORED

    def tick(self):
        """Advances the smoother one period; returns the Velocity to publish, or None when idle."""
        command = self.smoother.step(self.target, self.period)
        if command == ZERO and self._last_published == ZERO:
            return None
        self._last_published = command
        return command

    def status_line(self):
        return ('speed %.2f m/s %.2f rad/s | command linear %+.2f m/s angular %+.2f rad/s'
                % (self.speed_linear, self.speed_angular, self.command.linear,
                   self.command.angular))
