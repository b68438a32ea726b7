"""minibot3d_navigation.wanderer (seek_openings=True) on scans cast in hand-made rooms: it heads for the door of a closed room, keeps
going along a corridor, turns in place when blocked, and copes with NaN / inf readings and a laser
mounted backwards."""
import math
from types import SimpleNamespace

from minibot3d_navigation.wanderer import Wanderer


def cast(segments, x, y, yaw, laser_yaw=0.0, beams=360, range_max=12.0):
    """A full-circle scan from (x, y, yaw) against line segments ((x0, y0), (x1, y1))."""
    ranges = []
    for i in range(beams):
        a = yaw + laser_yaw - math.pi + 2.0 * math.pi * i / beams
        dx, dy = math.cos(a), math.sin(a)
        best = float('inf')
        for (x0, y0), (x1, y1) in segments:
            ex, ey = x1 - x0, y1 - y0
            den = dx * ey - dy * ex
            if abs(den) < 1e-12:
                continue
            t = ((x0 - x) * ey - (y0 - y) * ex) / den
            u = ((x0 - x) * dy - (y0 - y) * dx) / den
            if t > 0 and 0 <= u <= 1:
                best = min(best, t)
        ranges.append(best if best <= range_max else float('inf'))
    return SimpleNamespace(ranges=ranges, angle_min=-math.pi, angle_increment=2.0 * math.pi / beams,
                           range_min=0.15, range_max=range_max)


def room_with_door(door_x0, door_x1):
    """A 4 m x 4 m room ([-2, 2]^2) with a door in its north wall, a corridor beyond (y 2..4)."""
    return [((-2, -2), (2, -2)), ((-2, -2), (-2, 2)), ((2, -2), (2, 2)),
            ((-2, 2), (door_x0, 2)), ((door_x1, 2), (2, 2)),
            ((-8, 4), (8, 4)), ((-8, 2), (-2, 2)), ((2, 2), (8, 2))]


def test_heads_for_the_door_of_a_closed_room():
    segs = room_with_door(0.6, 1.6)  # door centre (1.1, 2)
    for yaw in (0.0, math.pi / 2, -2.5):
        scan = cast(segs, 0.0, 0.0, yaw)
        b = Wanderer(laser_yaw=0.0, seek_openings=True)._deepest_opening(scan)
        door = math.atan2(2.0, 1.1) - yaw
        err = abs(math.atan2(math.sin(b - door), math.cos(b - door)))
        if abs(math.atan2(math.sin(door), math.cos(door))) < math.radians(100):
            assert err < math.radians(15), (yaw, math.degrees(b), math.degrees(door))


def test_a_door_too_narrow_to_pass_does_not_attract():
    segs = room_with_door(1.0, 1.2)  # 0.2 m wide: the robot does not fit
    facing = math.atan2(2.0, 1.1)   # straight at it
    b = Wanderer(laser_yaw=0.0, seek_openings=True)._deepest_opening(cast(segs, 0.0, 0.0, facing))
    assert abs(b) > math.radians(10), math.degrees(b)
    # The same room with a 1 m door there: straight through it.
    b = Wanderer(laser_yaw=0.0, seek_openings=True)._deepest_opening(cast(room_with_door(0.6, 1.6), 0.0, 0.0, facing))
    assert abs(b) < math.radians(10), math.degrees(b)


def test_keeps_going_along_a_corridor():
    segs = [((-20, -1), (20, -1)), ((-20, 1), (20, 1))]
    w = Wanderer(laser_yaw=0.0, seek_openings=True)
    v, omega = w.command(cast(segs, 0.0, 0.0, 0.05))
    assert v > 0.2 and abs(omega) < 0.2


def test_turns_in_place_when_blocked_and_with_a_backwards_laser():
    segs = [((0.3, -3), (0.3, 3)), ((-3, -3), (0.3, -3)), ((-3, 3), (0.3, 3)), ((-3, -3), (-3, 3))]
    scan = cast(segs, 0.0, 0.0, 0.0, laser_yaw=math.pi)
    v, omega = Wanderer(laser_yaw=math.pi, seek_openings=True).command(scan)
    assert v == 0.0 and abs(omega) > 0.5


def test_nan_and_inf_readings():
    scan = cast([((-20, -1), (20, -1)), ((-20, 1), (20, 1))], 0.0, 0.0, 0.0)
    scan.ranges = [float('nan') if i % 3 == 0 else r for i, r in enumerate(scan.ranges)]
    v, omega = Wanderer(laser_yaw=0.0, seek_openings=True).command(scan)
    assert v > 0.2 and math.isfinite(omega)
    empty = SimpleNamespace(ranges=[float('nan')] * 10, angle_min=-math.pi,
                            angle_increment=0.6, range_min=0.15, range_max=12.0)
    assert Wanderer(laser_yaw=0.0, seek_openings=True)._deepest_opening(empty) is None


def test_default_wanderer_steers_towards_the_side_with_more_room():
    # A corridor with the robot near its right wall, heading along it: it drifts left.
    segs = [((-20, -0.4), (20, -0.4)), ((-20, 1.6), (20, 1.6))]
    v, omega = Wanderer(laser_yaw=0.0).command(cast(segs, 0.0, 0.0, 0.0))
    assert v > 0.2 and omega > 0.1


def test_wall_end_beside_the_bumper_blocks_the_way():
    # A wall ending 0.3 m ahead and 0.15 m to the left: outside the 25 deg front cone, but in
    # the robot's swept path (0.23 m wide): driving on would catch the bumper on it.
    segs = [((0.3, 0.15), (0.3, 3.0)), ((-20, -2), (20, -2)), ((-20, 3), (20, 3))]
    v, omega = Wanderer(laser_yaw=0.0, seek_openings=True).command(cast(segs, 0.0, 0.0, 0.0))
    assert v == 0.0 and omega != 0.0


def test_turns_one_way_to_the_opening_without_dithering():
    # Blocked ahead, more room on the left, and the way ahead clear when facing 40..80 deg
    # left or near the opening 50 deg right: the blocked turn and the turn to the opening once
    # disagreed (left until clear at 40 deg, then right towards the opening, blocked again,
    # left...: minutes on the spot in the default world). It must turn right, one way, and go.
    opening = math.radians(-50)
    w = Wanderer(laser_yaw=0.0, seek_openings=True)
    heading = 0.0

    def wrap(a):
        return math.atan2(math.sin(a), math.cos(a))

    def front(h):
        clear = math.radians(40) <= h <= math.radians(80) or abs(wrap(h - opening)) < math.radians(20)
        return 2.0 if clear else 0.3
    w._sectors = lambda scan: (front(heading), 3.0, 1.0)
    w._deepest_opening = lambda scan: wrap(opening - heading)
    signs = set()
    for _ in range(300):
        v, omega = w.command(object())
        if v > 0.0:
            break
        signs.add(math.copysign(1.0, omega))
        heading = wrap(heading + omega * w.dt)
    assert v > 0.0, 'still turning on the spot after 30 s'
    assert signs == {-1.0}, 'turned both ways'
    assert abs(wrap(heading - opening)) < math.radians(30)


# ---- mount_yaw: where the laser looks, from a robot description ---------------------------------

def urdf(*joints):
    links = {'base_footprint'} | {j[1] for j in joints} | {j[2] for j in joints}
    text = ''.join('<link name="%s"/>' % n for n in sorted(links))
    for name, parent, child, rpy in joints:
        origin = '' if rpy is None else '<origin xyz="0.1 0 0.2" rpy="%s"/>' % rpy
        text += ('<joint name="%s" type="fixed"><parent link="%s"/><child link="%s"/>%s</joint>'
                 % (name, parent, child, origin))
    return '<robot name="r">%s</robot>' % text


def test_mount_yaw_composes_the_joints_up_to_the_base():
    from minibot3d_navigation.wanderer import mount_yaw
    r = urdf(('a', 'base_footprint', 'base_link', '0 0 0'), ('b', 'base_link', 'chassis', None),
             ('c', 'chassis', 'laser', '0 0 3.141592653589793'),
             ('d', 'base_link', 'side', '0 0 0.5'), ('e', 'side', 'side_laser', '0 0 0.25'),
             ('f', 'base_link', 'tilted', '0 0.3 1.0'),
             ('g', 'base_link', 'flipped', '3.141592653589793 0 0'))
    # minibot3d's mounting (backwards) gives exactly pi, as the wanderer was given before.
    assert mount_yaw(r, 'base_footprint', 'laser') == math.pi
    assert mount_yaw(r, 'base_footprint', '/laser') == math.pi  # a tf1-style frame name
    assert abs(mount_yaw(r, 'base_footprint', 'side_laser') - 0.75) < 1e-12
    assert abs(mount_yaw(r, 'side', 'side_laser') - 0.25) < 1e-12  # on another frame
    assert abs(mount_yaw(r, 'base_link', 'tilted') - 1.0) < 1e-12  # pitch does not turn it
    assert mount_yaw(r, 'laser', 'laser') == 0.0
    for frame, said in (('flipped', 'upside down'), ('camera', 'not a link')):
        try:
            mount_yaw(r, 'base_footprint', frame)
        except ValueError as e:
            assert said in str(e) and frame in str(e)
        else:
            raise AssertionError('no ValueError for %s' % frame)
