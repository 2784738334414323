"""The large generated world: a 64 m x 40 m collapsed building site for 6 robots (rubble_site.{pgm,yaml}).

Corridors (one partly blocked), rooms on both sides, inner rooms reachable only through their outer
room's one door, narrow gaps a robot just fits through (0.7 m for a 0.4 m robot), dead-end stubs
ending in rubble, rubble piles in every room, 14 objects of interest. The six robots enter together
through the west door, as a team does. No waypoints: the robots explore by themselves.
Deterministic: the layout and rubble come from one seeded random stream.
"""
import math
import random
from collections import deque

from generate_worlds import (GREEN, ORANGE, RED, RES, ROBOT_RADIUS, YELLOW, Grid, footprint_free, obj)

W, H = 64.0, 40.0
T = 0.15  # inner wall thickness


def distance_to_walls(g):
    """Per cell, the distance (m) from its centre to the nearest wall cell, by a two-pass chamfer
    transform (3-4 weights; within ~8 % of Euclidean)."""
    inf = 10 ** 9
    d = [0 if v else inf for v in g.cells]
    w, h = g.w, g.h
    for r in range(h):
        row = r * w
        for c in range(w):
            i = row + c
            if d[i] == 0:
                continue
            best = d[i]
            if c > 0: best = min(best, d[i - 1] + 3)
            if r > 0:
                best = min(best, d[i - w] + 3)
                if c > 0: best = min(best, d[i - w - 1] + 4)
                if c < w - 1: best = min(best, d[i - w + 1] + 4)
            d[i] = best
    for r in range(h - 1, -1, -1):
        row = r * w
        for c in range(w - 1, -1, -1):
            i = row + c
            best = d[i]
            if c < w - 1: best = min(best, d[i + 1] + 3)
            if r < h - 1:
                best = min(best, d[i + w] + 3)
                if c < w - 1: best = min(best, d[i + w + 1] + 4)
                if c > 0: best = min(best, d[i + w - 1] + 4)
            d[i] = best
    return [v * RES / 3.0 for v in d]


def drivable_from(g, dist, starts, radius):
    """Cells whose centre a robot disc can reach from the starts (4-neighbour flood fill)."""
    ok = [v > radius + 0.5 * RES for v in dist]
    seen = bytearray(g.w * g.h)
    q = deque()
    for x, y in starts:
        i = int(y / RES) * g.w + int(x / RES)
        if ok[i]:
            seen[i] = 1
            q.append(i)
    while q:
        i = q.popleft()
        c, r = i % g.w, i // g.w
        for cc, rr in ((c + 1, r), (c - 1, r), (c, r + 1), (c, r - 1)):
            if 0 <= cc < g.w and 0 <= rr < g.h:
                j = rr * g.w + cc
                if ok[j] and not seen[j]:
                    seen[j] = 1
                    q.append(j)
    return seen


def wall_with_doors(g, a, b, doors):
    """An axis-aligned wall from a to b with door openings (centre along the wall, width)."""
    horizontal = a[1] == b[1]
    g.rect(a[0] - (0 if horizontal else T / 2), a[1] - (T / 2 if horizontal else 0),
           b[0] + (0 if horizontal else T / 2), b[1] + (T / 2 if horizontal else 0))
    for centre, width in doors:
        if horizontal:
            g.rect(centre - width / 2, a[1] - T, centre + width / 2, a[1] + T, 0)
        else:
            g.rect(a[0] - T, centre - width / 2, a[0] + T, centre + width / 2, 0)


def rubble_site():
    rng = random.Random(4242)
    g = Grid(W, H)
    for r in ((0, 0, W, 0.25), (0, H - 0.25, W, H), (0, 0, 0.25, H), (W - 0.25, 0, W, H)):
        g.rect(*r)
    g.rect(0, 18.6, 0.25, 20.9, 0)  # the west entrance
    # Main corridor y in [18, 21.5]; cross corridor x in [30, 33].
    south = [(0.25, 10.0), (10.0, 20.0), (20.0, 30.0), (33.0, 43.0), (43.0, 53.0), (53.0, W - 0.25)]
    north = [(0.25, 12.0), (12.0, 22.0), (22.0, 30.0), (33.0, 45.0), (45.0, 55.0), (55.0, W - 0.25)]
    narrow = 0.7
    south_doors = [(5.0, 1.0), (15.0, narrow), (25.0, 1.0), (38.0, 1.0), (48.0, 1.0), (58.5, narrow)]
    north_doors = [(6.0, 1.0), (17.0, 1.0), (26.0, narrow), (39.0, 1.0), (50.0, 1.0), (59.5, 1.0)]
    wall_with_doors(g, (0.25, 18.0), (30.0, 18.0), [d for d in south_doors if d[0] < 30])
    wall_with_doors(g, (33.0, 18.0), (W - 0.25, 18.0), [d for d in south_doors if d[0] > 33])
    wall_with_doors(g, (0.25, 21.5), (30.0, 21.5), [d for d in north_doors if d[0] < 30])
    wall_with_doors(g, (33.0, 21.5), (W - 0.25, 21.5), [d for d in north_doors if d[0] > 33])
    wall_with_doors(g, (30.0, 0.25), (30.0, 18.0), [(3.0, 1.0)])  # cross corridor walls
    wall_with_doors(g, (33.0, 0.25), (33.0, 18.0), [(14.0, 1.0)])
    wall_with_doors(g, (30.0, 21.5), (30.0, H - 0.25), [(36.0, 1.0)])
    wall_with_doors(g, (33.0, 21.5), (33.0, H - 0.25), [])
    for x0, x1 in south[1:3] + south[4:]:
        wall_with_doors(g, (x0, 0.25), (x0, 18.0), [])
    for x0, x1 in north[1:3] + north[4:]:
        wall_with_doors(g, (x0, 21.5), (x0, H - 0.25), [(30.0, 1.0)] if x0 in (12.0, 45.0) else [])
    # Inner rooms: the south rooms are split at y = 9; the inner half opens only onto the outer one.
    for (x0, x1), inner_door in zip(south, (3.0, 16.5, 27.0, 36.0, 50.0, 60.0)):
        wall_with_doors(g, (x0, 9.0), (x1, 9.0), [(inner_door, 1.0 if inner_door != 36.0 else narrow)])
    # Dead ends: stubs that end in rubble (north-east and south of the cross corridor's top).
    wall_with_doors(g, (57.0, 21.5), (57.0, 33.0), [])
    wall_with_doors(g, (58.6, 21.5), (58.6, 33.0), [(26.0, 1.0)])
    for k in range(6):
        g.disc((57.8 + rng.uniform(-0.3, 0.3), 32.6 + rng.uniform(-0.4, 0.4)), rng.uniform(0.3, 0.5))
    # A collapsed stretch of the main corridor: a pile leaving a gap of about 0.85 m along its north wall.
    for k in range(8):
        g.disc((44.0 + rng.uniform(-0.8, 0.8), 18.4 + 0.25 * k), rng.uniform(0.25, 0.4))
    g.rect(42.0, 20.55, 46.0, 21.5 - T / 2, 0)
    rooms = [((x0, 0.25), (x1, 9.0)) for x0, x1 in south] + [((x0, 9.0), (x1, 18.0)) for x0, x1 in south] + \
            [((x0, 21.5), (x1, H - 0.25)) for x0, x1 in north]
    # Rubble piles in every room, away from its doors and walls' openings.
    openings = [(x, 18.0) for x, _ in south_doors] + [(x, 21.5) for x, _ in north_doors] + \
               [(x, 9.0) for x in (3.0, 16.5, 27.0, 36.0, 50.0, 60.0)] + \
               [(30.0, 3.0), (33.0, 14.0), (30.0, 36.0), (12.0, 30.0), (45.0, 30.0), (58.6, 26.0)]
    for (x0, y0), (x1, y1) in rooms:
        for _ in range(int((x1 - x0) * (y1 - y0) / 14)):
            cx, cy = rng.uniform(x0 + 1.2, x1 - 1.2), rng.uniform(y0 + 1.2, y1 - 1.2)
            if min(math.dist((cx, cy), o) for o in openings) < 2.5:
                continue
            for _ in range(rng.randint(1, 3)):
                g.disc((cx + rng.uniform(-0.5, 0.5), cy + rng.uniform(-0.5, 0.5)), rng.uniform(0.12, 0.45))
    starts = [(1.2, 19.1), (1.2, 20.4), (2.5, 19.1), (2.5, 20.4), (3.8, 19.1), (3.8, 20.4)]
    robots = [{"id": i, "start": [x, y, 0.0], "max_speed_mps": 0.6} for i, (x, y) in enumerate(starts)]
    specs = [("victim", "box", RED, [1.6, 0.5, 0.3], 0.15), ("victim", "cylinder", ORANGE, [0.5, 0.5, 1.0], 0.5),
             ("hazard", "cylinder", YELLOW, [0.6, 0.6, 0.9], 0.45), ("victim", "sphere", ORANGE, [0.5, 0.5, 0.5], 0.25),
             ("exit", "box", GREEN, [1.0, 0.12, 2.0], 1.0), ("hazard", "sphere", YELLOW, [0.6, 0.6, 0.6], 0.3)]
    # Rooms to place objects in (index into rooms), one object each; exits stand against a wall.
    where = [0, 7, 13, 2, 9, 15, 4, 11, 16, 5, 8, 14, 3, 17]
    dist = distance_to_walls(g)
    drivable = drivable_from(g, dist, starts, ROBOT_RADIUS)
    objects = []
    for i, room in enumerate(where):
        cls, shape, color, size, z = specs[i % len(specs)]
        (x0, y0), (x1, y1) = rooms[room]
        for _ in range(400):
            x, y = rng.uniform(x0 + 1.0, x1 - 1.0), rng.uniform(y0 + 1.0, y1 - 1.0)
            o = obj(i, cls, shape, color, size, [round(x, 2), round(y, 2), z, round(rng.uniform(-1.5, 1.5), 3)])
            near = int(y / RES) * g.w + int(x / RES)
            reach = any(drivable[near + dr * g.w + dc] for dr in range(-30, 31, 5) for dc in range(-30, 31, 5))
            if footprint_free(g, o, margin=0.35) and reach:
                objects.append(o)
                break
        else:
            raise SystemExit("rubble_site: no free place for object %d in room %d" % (i, room))
    # Every room must be reachable by a robot: no rubble may seal one.
    for k, ((x0, y0), (x1, y1)) in enumerate(rooms):
        cells = [r * g.w + c for r in range(int(y0 / RES), int(y1 / RES)) for c in range(int(x0 / RES), int(x1 / RES))]
        if sum(drivable[i] for i in cells) * RES * RES < 0.5 * (x1 - x0) * (y1 - y0):
            raise SystemExit("rubble_site: room %d (%s-%s) is mostly out of the robots' reach" % (k, (x0, y0), (x1, y1)))
    return g, robots, objects
