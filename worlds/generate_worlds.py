#!/usr/bin/env python3
"""Generates the shipped Cairn simulator worlds: office.{pgm,yaml}, collapsed.{pgm,yaml} and the large
rubble_site.{pgm,yaml} (rubble_site.py), and the
robots' scripted routes apart from them, routes/office.yaml and routes/collapsed.yaml (the world files
hold no waypoints: their robots obey velocity commands unless cairn_sim is given --routes).

Plain Python 3 (no numpy). Floor plans are drawn in world metres on a grid whose row 0 is at the
bottom (y = 0); the PGM is written top row first (0 = wall, 254 = free), origin = lower-left corner.
Run from anywhere:  python3 worlds/generate_worlds.py   (output is deterministic).
The script checks what the C++ tests check again: every route segment, inflated by the robot
radius, is free; every object is clear of walls and routes and is in some robot's view < 4 m.
"""
import math
import os
import random

RES = 0.05
ROBOT_RADIUS = 0.2
HERE = os.path.dirname(os.path.abspath(__file__))

RED, ORANGE, YELLOW, GREEN = (220, 30, 30), (240, 120, 20), (230, 210, 20), (30, 190, 60)


class Grid:
    def __init__(self, width_m, height_m):
        self.w = int(round(width_m / RES))
        self.h = int(round(height_m / RES))
        self.cells = bytearray(self.w * self.h)  # 1 = wall

    def wall(self, c, r):
        return 0 <= c < self.w and 0 <= r < self.h and self.cells[r * self.w + c] == 1

    def set(self, c, r, v):
        if 0 <= c < self.w and 0 <= r < self.h:
            self.cells[r * self.w + c] = v

    def rect(self, x0, y0, x1, y1, v=1):
        for r in range(int(math.floor(min(y0, y1) / RES)), int(math.ceil(max(y0, y1) / RES))):
            for c in range(int(math.floor(min(x0, x1) / RES)), int(math.ceil(max(x0, x1) / RES))):
                self.set(c, r, v)

    def _near(self, a, b, radius, v, pred=None):
        """Sets every cell whose centre is within radius of segment a-b."""
        x0, x1 = min(a[0], b[0]) - radius, max(a[0], b[0]) + radius
        y0, y1 = min(a[1], b[1]) - radius, max(a[1], b[1]) + radius
        for r in range(int(y0 / RES) - 1, int(y1 / RES) + 2):
            for c in range(int(x0 / RES) - 1, int(x1 / RES) + 2):
                p = ((c + 0.5) * RES, (r + 0.5) * RES)
                if seg_dist(p, a, b) <= radius:
                    self.set(c, r, v)

    def line(self, a, b, width):
        self._near(a, b, width / 2.0, 1)

    def disc(self, p, radius, v=1):
        self._near(p, p, radius, v)

    def clear_segment(self, a, b, radius):
        self._near(a, b, radius, 0)

    def write_pgm(self, path):
        with open(path, "wb") as f:
            f.write(b"P5\n%d %d\n255\n" % (self.w, self.h))
            for r in range(self.h - 1, -1, -1):
                row = self.cells[r * self.w:(r + 1) * self.w]
                f.write(bytes(0 if v else 254 for v in row))


def seg_dist(p, a, b):
    ax, ay = b[0] - a[0], b[1] - a[1]
    L2 = ax * ax + ay * ay
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / L2))
    dx, dy = a[0] + t * ax - p[0], a[1] + t * ay - p[1]
    return math.hypot(dx, dy)


def disc_free(g, p, radius):
    c0, c1 = int(math.floor((p[0] - radius) / RES)), int(math.floor((p[0] + radius) / RES))
    r0, r1 = int(math.floor((p[1] - radius) / RES)), int(math.floor((p[1] + radius) / RES))
    if c0 < 0 or r0 < 0 or c1 >= g.w or r1 >= g.h:
        return False
    for r in range(r0, r1 + 1):
        for c in range(c0, c1 + 1):
            if g.cells[r * g.w + c]:
                qx = min(max(p[0], c * RES), (c + 1) * RES)
                qy = min(max(p[1], r * RES), (r + 1) * RES)
                if math.hypot(qx - p[0], qy - p[1]) < radius:
                    return False
    return True


def route_points(robot):
    return [robot["start"][:2]] + robot["waypoints"]


def check_routes(g, robots):
    for rb in robots:
        pts = route_points(rb)
        for a, b in zip(pts, pts[1:]):
            n = max(1, int(math.ceil(math.dist(a, b) / (0.25 * RES))))
            for i in range(n + 1):
                p = (a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n)
                if not disc_free(g, p, ROBOT_RADIUS):
                    raise SystemExit("robot %d: segment %s-%s blocked near %s" % (rb["id"], a, b, p))


def mission_time_s(robot):
    pts = route_points(robot)
    t, yaw = 0.0, robot["start"][2]
    for a, b in zip(pts, pts[1:]):
        heading = math.atan2(b[1] - a[1], b[0] - a[0])
        turn = abs(math.atan2(math.sin(heading - yaw), math.cos(heading - yaw)))
        t += turn / 1.0 + math.dist(a, b) / (0.95 * robot["max_speed_mps"])
        yaw = heading
    return t


def object_clearance(o):
    """Radius of the object's footprint (half the width for boxes lying along a route)."""
    if o["shape"] != "box":
        return 0.5 * o["size"][0]
    return o.get("route_clearance", 0.5 * math.hypot(o["size"][0], o["size"][1]))


def check_objects(g, robots, objects):
    for o in objects:
        p = o["pose"][:2]
        if not footprint_free(g, o):
            raise SystemExit("object %d touches a wall" % o["id"])
        for rb in robots:
            pts = route_points(rb)
            for a, b in zip(pts, pts[1:]):
                if seg_dist(p, a, b) < object_clearance(o) + ROBOT_RADIUS + 0.1:
                    raise SystemExit("object %d is on robot %d's route" % (o["id"], rb["id"]))
        if not seen(g, robots, o):
            raise SystemExit("object %d is not in view of any robot within 4 m" % o["id"])


def line_of_sight(g, a, b):
    n = int(math.dist(a, b) / (0.5 * RES)) + 1
    for i in range(n + 1):
        x = a[0] + (b[0] - a[0]) * i / n
        y = a[1] + (b[1] - a[1]) * i / n
        if g.wall(int(x / RES), int(y / RES)):
            return False
    return True


def seen(g, robots, o, max_m=3.6, half_fov_rad=math.radians(28)):
    p = o["pose"][:2]
    for rb in robots:
        pts = route_points(rb)
        for a, b in zip(pts, pts[1:]):
            heading = math.atan2(b[1] - a[1], b[0] - a[0])
            n = int(math.dist(a, b) / 0.2) + 1
            for i in range(n + 1):
                q = (a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n)
                d = math.dist(p, q)
                bearing = math.atan2(p[1] - q[1], p[0] - q[0]) - heading
                bearing = math.atan2(math.sin(bearing), math.cos(bearing))
                if 1.2 < d < max_m and abs(bearing) < half_fov_rad and line_of_sight(g, q, p):
                    return True
    return False


def fmt(v):
    return ("%.4f" % v).rstrip("0").rstrip(".") if isinstance(v, float) else str(v)


def write_yaml(path, name, image, size_m, duration_s, seed, robots, objects, comment):
    L = ["# %s (generated by generate_worlds.py; edit the generator, not this file)" % comment,
         "name: %s" % name,
         "map: {image: %s, resolution_m: %s, origin_m: [0.0, 0.0], wall_height_m: 2.0}" % (image, RES),
         "sim: {seed: %d, dt_s: 0.05, duration_s: %d}" % (seed, duration_s),
         "sensors:",
         "  odometry: {rate_hz: 20, trans_noise_per_m: 0.05, rot_noise_rad_per_m: 0.02, rot_noise_per_rad: 0.05}",
         "  laser: {rate_hz: 10, beams: 360, fov_deg: 360, max_range_m: 12, noise_sd_m: 0.01}",
         "  camera: {rate_hz: 2, width: 320, height: 240, hfov_deg: 70, max_depth_m: 6, height_m: 0.5,"
         " pitch_deg: 0, depth_noise_sd_m: 0.005}",
         "robots:"]
    for rb in robots:
        L.append("  - {id: %d, start: [%s], max_speed_mps: %s, max_turn_radps: 1.2}"
                 % (rb["id"], ", ".join(fmt(float(v)) for v in rb["start"]), fmt(rb["max_speed_mps"])))
    L.append("objects:")
    for o in objects:
        L.append("  - {id: %d, class: %s, shape: %s, color: [%d, %d, %d], size_m: [%s], pose: [%s]}"
                 % (o["id"], o["class"], o["shape"], o["color"][0], o["color"][1], o["color"][2],
                    ", ".join(fmt(float(v)) for v in o["size"]), ", ".join(fmt(float(v)) for v in o["pose"])))
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def write_routes(path, name, robots, comment):
    L = ["# %s: the robots' scripted routes (generated by generate_worlds.py; edit the generator, not this"
         " file)" % comment,
         "#   cairn_sim --world worlds/%s.yaml --routes worlds/routes/%s.yaml" % (name, name),
         "routes:"]
    for rb in robots:
        wps = ", ".join("[%s, %s]" % (fmt(float(x)), fmt(float(y))) for x, y in rb["waypoints"])
        L.append("  - {robot: %d, waypoints: [%s]}" % (rb["id"], wps))
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def obj(i, cls, shape, color, size, pose):
    return {"id": i, "class": cls, "shape": shape, "color": color, "size": size, "pose": pose}


def finish(name, g, robots, objects, duration_s, seed, comment, time_range):
    check_routes(g, robots)
    check_objects(g, robots, objects)
    times = [mission_time_s(rb) for rb in robots]
    if not (time_range[0] <= max(times) <= time_range[1]):
        raise SystemExit("%s: estimated mission time %.0f s outside %s" % (name, max(times), time_range))
    g.write_pgm(os.path.join(HERE, name + ".pgm"))
    write_yaml(os.path.join(HERE, name + ".yaml"), name, name + ".pgm", (g.w * RES, g.h * RES),
               duration_s, seed, robots, objects, comment)
    os.makedirs(os.path.join(HERE, "routes"), exist_ok=True)
    write_routes(os.path.join(HERE, "routes", name + ".yaml"), name, robots, comment)
    print("%s: %dx%d px, %d robots (est. %s s), %d objects"
          % (name, g.w, g.h, len(robots), ", ".join("%.0f" % t for t in times), len(objects)))


def footprint_free(g, o, margin=0.03):
    """True when no wall cell lies under the object's footprint (plus margin)."""
    x, y, _, yaw = o["pose"]
    if o["shape"] != "box":
        return disc_free(g, (x, y), o["size"][0] / 2 + margin)
    hx, hy = o["size"][0] / 2 + margin, o["size"][1] / 2 + margin
    c, s = math.cos(yaw), math.sin(yaw)
    n = int(2 * max(hx, hy) / (0.5 * RES)) + 1
    for i in range(n + 1):
        for j in range(n + 1):
            u, v = -hx + 2 * hx * i / n, -hy + 2 * hy * j / n
            px, py = x + c * u - s * v, y + s * u + c * v
            if g.wall(int(math.floor(px / RES)), int(math.floor(py / RES))):
                return False
    return True


def office():
    """~20 m x 15 m office: a corridor with pillars, four rooms below, three above, furniture."""
    g = Grid(20.0, 15.0)
    t = 0.15
    g.rect(0, 0, 20, 0.2); g.rect(0, 14.8, 20, 15); g.rect(0, 0, 0.2, 15); g.rect(19.8, 0, 20, 15)
    g.rect(0, 6.4, 20, 6.4 + t); g.rect(0, 8.5, 20, 8.5 + t)                 # corridor walls
    for x in (5.0, 10.0, 15.0):
        g.rect(x, 0, x + t, 6.5)                                               # lower room walls
    for x in (7.0, 13.0):
        g.rect(x, 8.5, x + t, 15)                                              # upper room walls
    for x in (2.5, 7.5, 12.5, 17.5):
        g.rect(x - 0.6, 6.3, x + 0.6, 6.7, 0)                                  # lower doorways
    for x in (3.5, 10.0, 16.5):
        g.rect(x - 0.6, 8.4, x + 0.6, 8.8, 0)                                  # upper doorways
    for x0, y0 in ((4.0, 6.55), (8.6, 8.2), (13.6, 6.55), (18.4, 8.2), (6.0, 8.2), (11.2, 6.55)):
        g.rect(x0, y0, x0 + 0.3, y0 + 0.3)                                     # corridor pillars
    for r in ((0.6, 4.6, 1.8, 5.2), (4.3, 3.5, 4.85, 5.5), (5.6, 4.8, 6.6, 5.6), (9.3, 3.0, 9.85, 5.0),
              (10.6, 1.0, 11.8, 1.6), (13.8, 4.5, 14.6, 5.2), (15.6, 4.6, 16.2, 5.8),
              (0.6, 9.2, 1.6, 9.9), (7.6, 13.6, 8.6, 14.4), (11.8, 9.2, 12.5, 10.4),
              (18.8, 9.2, 19.5, 10.8), (13.6, 13.8, 14.6, 14.5)):
        g.rect(*r)                                                             # furniture
    robots = [
        {"id": 0, "start": [1.2, 7.5, 0.0], "max_speed_mps": 0.6,
         "waypoints": [[2.5, 7.5], [2.5, 4.0], [1.2, 2.5], [3.8, 2.5], [2.5, 4.0], [2.5, 7.5], [7.5, 7.5],
                       [7.5, 2.8], [7.5, 7.5], [10.0, 7.5], [10.0, 11.5]]},
        {"id": 1, "start": [18.8, 7.5, math.pi], "max_speed_mps": 0.6,
         "waypoints": [[17.5, 7.5], [17.5, 3.5], [16.3, 1.8], [18.6, 2.2], [17.5, 3.5], [17.5, 7.5],
                       [12.5, 7.5], [12.5, 3.5], [12.5, 7.5], [16.5, 7.5], [16.5, 11.5]]},
        {"id": 2, "start": [10.0, 12.5, -math.pi / 2], "max_speed_mps": 0.6,
         "waypoints": [[10.0, 7.5], [3.5, 7.5], [3.5, 11.5], [1.5, 11.5], [1.5, 13.5], [5.5, 13.5],
                       [5.5, 10.5]]},
    ]
    objects = [
        obj(0, "victim", "box", RED, [1.6, 0.5, 0.3], [2.6, 1.0, 0.15, 0.0]),
        obj(1, "hazard", "cylinder", YELLOW, [0.6, 0.6, 0.9], [8.6, 1.0, 0.45, 0.0]),
        obj(2, "hazard", "sphere", YELLOW, [0.5, 0.5, 0.5], [12.9, 1.0, 0.25, 0.0]),
        obj(3, "victim", "cylinder", ORANGE, [0.5, 0.5, 1.0], [19.2, 2.0, 0.5, 0.0]),
        obj(4, "exit", "box", GREEN, [1.0, 0.12, 2.0], [10.0, 14.6, 1.0, 0.0]),
        obj(5, "exit", "box", GREEN, [1.0, 0.12, 2.0], [0.3, 11.5, 1.0, math.pi / 2]),
        obj(6, "victim", "box", RED, [1.6, 0.5, 0.3], [17.8, 13.6, 0.15, 0.4]),
    ]
    finish("office", g, robots, objects, 300, 7, "Office floor, 20 m x 15 m", (55, 95))


def zigzag(x_from, x_to, y_a, y_b, step):
    """Waypoints alternating between y_a and y_b while x goes from x_from to x_to."""
    pts, x, i = [], x_from, 0
    sign = 1 if x_to > x_from else -1
    while (x - x_to) * sign <= 1e-9:
        pts.append([round(x, 2), y_a if i % 2 == 0 else y_b])
        x += sign * step
        i += 1
    return pts


def broken_wall(g, rng, a, b, width=0.2):
    """A wall from a to b in ~1.5 m slabs: some missing, some tilted or shifted (collapsed)."""
    L = math.dist(a, b)
    n = max(1, int(L / 1.5))
    ux, uy = (b[0] - a[0]) / L, (b[1] - a[1]) / L
    for i in range(n):
        if rng.random() < 0.22:
            continue  # a gap
        s0, s1 = i * L / n, (i + 1) * L / n
        p = (a[0] + ux * s0, a[1] + uy * s0)
        q = (a[0] + ux * s1, a[1] + uy * s1)
        if rng.random() < 0.35:  # tilted / pushed slab
            jx, jy = rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)
            q = (q[0] + jx * abs(uy) + jy * 0.3 * abs(ux), q[1] + jy * abs(ux) + jx * 0.3 * abs(uy))
        g.line(p, q, width)


def rubble(g, rng, count, width_m, height_m):
    for _ in range(count):
        cx, cy = rng.uniform(0.8, width_m - 0.8), rng.uniform(0.8, height_m - 0.8)
        for _ in range(rng.randint(1, 4)):
            g.disc((cx + rng.uniform(-0.6, 0.6), cy + rng.uniform(-0.6, 0.6)), rng.uniform(0.12, 0.6))


def place_objects(robots, specs):
    """Objects beside route segments, ahead of where the robot drives (seen from ~3 m)."""
    objects = []
    for i, (rid, seg, cls, shape, color, size, z) in enumerate(specs):
        pts = route_points(robots[rid])
        a, b = pts[seg], pts[seg + 1]
        heading = math.atan2(b[1] - a[1], b[0] - a[0])
        L = math.dist(a, b)
        for f, side in ((0.9, 1), (0.9, -1), (0.75, 1), (0.75, -1), (1.0, 1), (1.0, -1)):
            along, lat = f * L, side * (1.1 + 0.5 * size[1])
            x = a[0] + math.cos(heading) * along - math.sin(heading) * lat
            y = a[1] + math.sin(heading) * along + math.cos(heading) * lat
            o = obj(i, cls, shape, color, size, [round(x, 2), round(y, 2), z, round(heading, 3)])
            o["route_clearance"] = 0.5 * size[1] + 0.15  # boxes lie along the segment
            o["view_from"] = (a[0] + math.cos(heading) * max(0.0, along - 2.8),
                              a[1] + math.sin(heading) * max(0.0, along - 2.8))
            if all(seg_dist((x, y), p, q) > object_clearance(o) + ROBOT_RADIUS + 0.35
                   for rb in robots for p, q in zip(route_points(rb), route_points(rb)[1:])):
                objects.append(o)
                break
        else:
            raise SystemExit("no free place for object %d" % i)
    return objects


def collapsed():
    """~35 m x 25 m collapsed floor: broken room walls, tilted slabs, rubble, narrow passages.
    Passages are where the robots' routes were cleared through the debris (1.0 m wide)."""
    W, H = 35.0, 25.0
    rng = random.Random(2024)
    g = Grid(W, H)
    for a, b in (((0.1, 0.1), (W - 0.1, 0.1)), ((0.1, H - 0.1), (W - 0.1, H - 0.1)),
                 ((0.1, 0.1), (0.1, H - 0.1)), ((W - 0.1, 0.1), (W - 0.1, H - 0.1))):
        g.line(a, b, 0.25)
    for x in (7.0, 14.0, 21.0, 28.0):
        broken_wall(g, rng, (x, 0.2), (x, H - 0.2))
    for y in (8.3, 16.6):
        broken_wall(g, rng, (0.2, y), (W - 0.2, y))
    rubble(g, rng, 110, W, H)
    robots = [
        {"id": 0, "start": [1.5, 2.5, 0.0], "max_speed_mps": 0.6,
         "waypoints": zigzag(4.5, 32.5, 6.6, 2.2, 3.5) + [[32.5, 10.5]] + zigzag(29.0, 18.5, 14.5, 10.5, 3.5)},
        {"id": 1, "start": [33.5, 12.5, math.pi], "max_speed_mps": 0.6,
         "waypoints": zigzag(30.5, 2.5, 10.3, 14.7, 3.5) + [[2.5, 19.0], [6.0, 20.5]]},
        {"id": 2, "start": [1.5, 22.5, 0.0], "max_speed_mps": 0.6,
         "waypoints": zigzag(4.5, 32.5, 18.5, 23.0, 3.5) + [[32.5, 14.0], [30.0, 6.0]]},
        {"id": 3, "start": [10.5, 1.5, math.pi / 2], "max_speed_mps": 0.6,
         "waypoints": [[12.0, 5.5], [9.5, 9.5], [12.0, 13.5], [9.5, 17.5], [11.5, 21.0], [17.5, 23.5],
                       [24.0, 20.5], [25.5, 15.0], [23.5, 10.0], [25.5, 5.0], [24.0, 1.5]]},
    ]
    for rb in robots:
        pts = route_points(rb)
        for a, b in zip(pts, pts[1:]):
            g.clear_segment(a, b, 0.5)
    specs = [
        (0, 1, "victim", "box", RED, [1.6, 0.5, 0.3], 0.15),
        (0, 5, "hazard", "cylinder", YELLOW, [0.6, 0.6, 0.9], 0.45),
        (1, 2, "victim", "cylinder", ORANGE, [0.5, 0.5, 1.0], 0.5),
        (1, 6, "exit", "box", GREEN, [1.0, 0.12, 2.0], 1.0),
        (2, 3, "hazard", "sphere", YELLOW, [0.6, 0.6, 0.6], 0.3),
        (2, 6, "victim", "box", RED, [1.6, 0.5, 0.3], 0.15),
        (3, 2, "exit", "box", GREEN, [1.0, 0.12, 2.0], 1.0),
        (3, 7, "victim", "sphere", ORANGE, [0.5, 0.5, 0.5], 0.25),
    ]
    objects = place_objects(robots, specs)
    for o in objects:
        g.disc(o["pose"][:2], 0.5 * math.hypot(o["size"][0], o["size"][1]) + 0.2, 0)
        g.clear_segment(o["view_from"], o["pose"][:2], 0.25)
    finish("collapsed", g, robots, objects, 600, 11, "Collapsed floor, 35 m x 25 m", (110, 185))


def rubble_site_world():
    """The large world (rubble_site.py): no routes at all, the robots explore by themselves."""
    from rubble_site import rubble_site
    g, robots, objects = rubble_site()
    g.write_pgm(os.path.join(HERE, "rubble_site.pgm"))
    write_yaml(os.path.join(HERE, "rubble_site.yaml"), "rubble_site", "rubble_site.pgm", (g.w * RES, g.h * RES),
               900, 11, robots, objects, "Collapsed building site, 64 m x 40 m, 6 robots")
    print("rubble_site: %dx%d px, %d robots, %d objects" % (g.w, g.h, len(robots), len(objects)))


if __name__ == "__main__":
    office()
    collapsed()
    rubble_site_world()
