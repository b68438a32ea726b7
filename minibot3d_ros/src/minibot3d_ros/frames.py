"""The frames of one robot among several on one tf tree, for rospy nodes: the same parameters
and rules as the C++ nodes' minibot3d_ros/frames.h (a test runs one table of cases through both).

Robot NAME's frames are NAME/odom, NAME/base_footprint, ... while the frames all robots share
(``shared_frames``, by default the map) keep their names. A node takes its frame names unprefixed,
as the robot's config gives them, and resolves each once::

    frames = load_frame_names()          # ~frame_prefix, ~shared_frames, searched upwards
    goal.header.frame_id = frames.resolve('base_link')   # 'robot1/base_link' in robot1's stack

resolve(frame): '' stays ''; '/name' is a full name, used as 'name' and never prefixed; a shared
frame stays; any other frame becomes 'PREFIX/frame' (unchanged without a prefix).
"""
import re

_SEGMENT = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')
DEFAULT_SHARED = ('map',)


def frame_prefix_problem(prefix):
    """'' when `prefix` is usable, else why not (a ROS name; outer slashes are ignored)."""
    p = prefix.strip('/')
    if not p:
        return ''
    for segment in p.split('/'):
        if not segment:
            return "'%s' has an empty segment (two slashes)" % prefix
        if not segment[0].isalpha() or not segment[0].isascii():
            return "'%s' is not a ROS name: '%s' does not start with a letter" % (prefix, segment)
        if not _SEGMENT.match(segment):
            return ("'%s' is not a ROS name: '%s' holds a character other than letters, digits "
                    "and _" % (prefix, segment))
    return ''


def shared_frames_problem(frames):
    """'' when every shared frame is usable, else why not."""
    for f in frames:
        if not f.strip('/'):
            return 'a shared frame is empty'
        if any(c.isspace() for c in f):
            return "shared frame '%s' holds white space" % f
    return ''


def parse_list(value):
    """A list parameter as the C++ option tables read it: a list, or comma-separated text."""
    if isinstance(value, (list, tuple)):
        items = [str(v) for v in value]
    else:
        text = str(value).strip()
        if text.startswith('[') and text.endswith(']'):
            text = text[1:-1]
        items = text.split(',')
    return [i.strip().strip('\'"') for i in items if i.strip().strip('\'"')]


class FrameNames(object):
    """Resolves a robot's frame names. Raises ValueError naming frame_prefix or shared_frames when
    one is unusable."""

    def __init__(self, frame_prefix='', shared_frames=DEFAULT_SHARED):
        shared_frames = list(shared_frames)
        why = frame_prefix_problem(frame_prefix)
        if why:
            raise ValueError('frame_prefix: ' + why)
        why = shared_frames_problem(shared_frames)
        if why:
            raise ValueError('shared_frames: ' + why)
        self.prefix = frame_prefix.strip('/')
        self.shared = [f.lstrip('/') for f in shared_frames]

    def resolve(self, frame):
        if not frame:
            return frame
        if frame.startswith('/'):
            return frame.lstrip('/')
        if not self.prefix or frame in self.shared:
            return frame
        return self.prefix + '/' + frame


def load_frame_names():
    """FrameNames from frame_prefix and shared_frames, each from the nearest namespace that has
    it, searching from the node's private namespace upwards (rospy.search_param). Raises
    ValueError naming the full parameter of a bad value."""
    import rospy
    values = {}
    for name in ('frame_prefix', 'shared_frames'):
        key = rospy.search_param(name)
        if key is not None:
            values[name] = (key, rospy.get_param(key))
    prefix, shared = '', list(DEFAULT_SHARED)
    if 'frame_prefix' in values:
        key, value = values['frame_prefix']
        if not isinstance(value, str):
            raise ValueError('%s: a name is expected, got %r' % (key, value))
        prefix = value.strip()
        why = frame_prefix_problem(prefix)
        if why:
            raise ValueError('%s: %s' % (key, why))
    if 'shared_frames' in values:
        key, value = values['shared_frames']
        shared = parse_list(value)
        why = shared_frames_problem(shared)
        if why:
            raise ValueError('%s: %s' % (key, why))
    return FrameNames(prefix, shared)
