"""What a launch file's nodes will read as their frames, without starting them: the node's frame
parameters from the launch's parameter tree, frame_prefix and shared_frames found as the node
finds them (the master's searchParam from the node's private namespace upwards, run on the same
tree), resolved by minibot3d_ros.frames (the rules the C++ nodes share, by a common case table).
For the tests of the launch files' robot argument and of launch/fleet.launch."""
import rosmaster.paramserver

from minibot3d_ros.frames import FrameNames, parse_list

# Each node type's frame parameters, relative to its private namespace.
FRAME_PARAMS = {
    'amcl': ['base_frame_id', 'odom_frame_id', 'global_frame_id'],
    'slam_gmapping': ['base_frame', 'odom_frame', 'map_frame'],
    'explore': ['global_frame', 'robot_base_frame'],
    'map_server': ['frame_id'],
    'move_base': ['global_costmap/global_frame', 'global_costmap/robot_base_frame',
                  'local_costmap/global_frame', 'local_costmap/robot_base_frame'],
}
# The nodes' defaults where a config leaves a frame out (their option tables').
DEFAULTS = {'explore': {'global_frame': 'map'}, 'map_server': {'frame_id': 'map'}}


def node_name(node):
    return (node.namespace.rstrip('/') + '/' + node.name) if node.namespace != '/' else \
        '/' + node.name


def resolved_frames(config, node):
    """{parameter: frame as the node resolves it} for `node` (a roslaunch Node of `config`, a
    roslaunch config); move_base's observation sources' sensor_frame included."""
    tree = rosmaster.paramserver.ParamDictionary(None)
    for key, p in config.params.items():
        tree.set_param(key, p.value)
    me = node_name(node)
    options = {}
    for name in ('frame_prefix', 'shared_frames'):
        key = tree.search_param(me, name)
        if key is not None:
            options[name] = tree.get_param(key)
    frames = FrameNames(str(options.get('frame_prefix', '')).strip(),
                        parse_list(options.get('shared_frames', ['map'])))
    wanted = list(FRAME_PARAMS.get(node.type, []))
    if node.type == 'move_base':
        for costmap in ('global_costmap', 'local_costmap'):
            for source in str(tree.get_param(me + '/' + costmap + '/observation_sources')).split():
                if tree.has_param('%s/%s/%s/sensor_frame' % (me, costmap, source)):
                    wanted.append('%s/%s/sensor_frame' % (costmap, source))
    out = {}
    for param in wanted:
        key = me + '/' + param
        value = tree.get_param(key) if tree.has_param(key) else \
            DEFAULTS.get(node.type, {}).get(param)
        out[param] = frames.resolve(value)
    return out
