"""Write the example scenes of this folder (run from the project root:
`python examples/make_examples.py`).  The JSON files are committed; this
script says how their numbers were chosen."""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def box(w, h, thick=0.1, restitution=1.0, x0=0.0, y0=0.0):
    """Four fixed walls around [x0, x0+w] x [y0, y0+h]."""
    def wall(name, cx, cy, hw, hh):
        return {"name": name, "shape": "polygon", "fixed": True, "restitution": restitution, "position": [cx, cy],
                "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    t = thick / 2
    return [wall("floor", x0 + w / 2, y0 - t, w / 2 + thick, t), wall("ceiling", x0 + w / 2, y0 + h + t, w / 2 + thick, t),
            wall("left", x0 - t, y0 + h / 2, t, h / 2), wall("right", x0 + w + t, y0 + h / 2, t, h / 2)]


def write(name, scene):
    os.makedirs(os.path.dirname(os.path.join(HERE, name)), exist_ok=True)
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


# a pool table (2.54 m x 1.27 m), 15 balls racked touching, the cue ball shot at 6 m/s
r, m = 0.028575, 0.17
balls = [{"name": "cue", "shape": "circle", "radius": r, "mass": m, "restitution": 0.96,
          "position": [0.635, 0.635], "velocity": [6.0, 0.01]}]
apex = 1.905
k = 1
for row in range(5):
    for i in range(row + 1):
        x = apex + row * r * math.sqrt(3.0) * 1.0000001
        y = 0.635 + (i - row / 2) * 2 * r * 1.0000001
        balls.append({"name": f"ball{k}", "shape": "circle", "radius": r, "mass": m, "restitution": 0.96,
                      "position": [round(x, 12), round(y, 12)]})
        k += 1
write("billiard-break.json", {"name": "billiard break", "end_time": 4.0, "frame_rate": 60,
                              "bodies": box(2.54, 1.27, restitution=0.9) + balls})

# 24 balls under gravity in a 2 m box, restitution 0.9: they settle on the floor
balls = []
for i in range(24):
    balls.append({"name": f"ball{i}", "shape": "circle", "radius": 0.08, "mass": 1.0, "restitution": 0.9,
                  "position": [0.25 + (i % 6) * 0.3, 0.6 + (i // 6) * 0.35],
                  "velocity": [math.cos(i * 1.7) * 1.5, math.sin(i * 2.3) * 1.5]})
write("gravity-box.json", {"name": "balls bouncing under gravity in a box", "end_time": 4.0, "frame_rate": 60,
                           "gravity": [0.0, -9.81], "bodies": box(2.0, 2.0) + balls})

# spinning polygons in a box, no gravity, restitution 1
shapes = {"triangle": 3, "square": 4, "pentagon": 5, "hexagon": 6}
bodies = []
for i in range(8):
    n = list(shapes.values())[i % 4]
    rad = 0.12 + 0.02 * (i % 3)
    verts = [[round(rad * math.cos(2 * math.pi * k / n), 12), round(rad * math.sin(2 * math.pi * k / n), 12)]
             for k in range(n)]
    bodies.append({"name": f"{list(shapes)[i % 4]}{i}", "shape": "polygon", "mass": 1.0 + 0.25 * i,
                   "position": [0.4 + (i % 4) * 0.55, 0.5 + (i // 4) * 0.8], "vertices": verts,
                   "velocity": [math.cos(i * 2.1), math.sin(i * 1.3)], "angle": 0.3 * i,
                   "angular_velocity": [3.0, -2.0, 5.0, -4.0][i % 4]})
write("spinning-polygons.json", {"name": "spinning polygons in a box", "end_time": 3.0, "frame_rate": 60,
                                 "bodies": box(2.4, 1.8) + bodies})

# Newton's cradle: five touching balls in a row, the first one swung in at 1 m/s
balls = [{"name": "striker", "shape": "circle", "radius": 0.05, "mass": 1.0, "position": [0.2, 0.5],
          "velocity": [1.0, 0.0]}]
for i in range(5):
    balls.append({"name": f"ball{i}", "shape": "circle", "radius": 0.05, "mass": 1.0,
                  "position": [0.5 + 0.1 * i, 0.5]})
write("newtons-cradle.json", {"name": "Newton's cradle", "end_time": 3.0, "frame_rate": 60,
                              "bodies": box(1.4, 1.0) + balls})

# a ball dropped on a floor under gravity, restitution 0.5: it comes to rest
write("resting-ball.json", {"name": "a ball coming to rest on a floor", "end_time": 5.0, "frame_rate": 30,
                            "gravity": [0.0, -9.81],
                            "bodies": box(1.0, 1.0)[:1] + [{"name": "ball", "shape": "circle", "radius": 0.1,
                                                             "mass": 1.0, "restitution": 0.5,
                                                             "position": [0.5, 0.6]}]})


# ---- game scenes: resting, sliding and friction --------------------
def plank(name, cx, cy, hw, hh, angle=0.0, **kw):
    """A fixed box: a floor, a ledge, a wall or (turned) a ramp."""
    b = {"name": name, "shape": "polygon", "fixed": True, "position": [cx, cy], "angle": angle,
         "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    b.update(kw)
    return b


# a platformer: a box character standing on the ground, walked and jumped by
# scripted inputs onto two ledges; it slides with friction, stops, falls off
# a ledge's end and lands on a ramp down which it slides to the ground
character = {"name": "hero", "shape": "polygon", "mass": 1.0, "restitution": 0.0, "friction": 0.5,
             "position": [0.5, 0.2], "vertices": [[-0.15, -0.2], [0.15, -0.2], [0.15, 0.2], [-0.15, 0.2]]}
write("platformer.json", {
    "name": "platformer: a box walking, jumping, sliding and resting on ledges", "end_time": 6.0,
    "frame_rate": 60, "gravity": [0.0, -9.81],
    "bodies": [plank("ground", 4.0, -0.1, 4.2, 0.1, friction=1.0),
               plank("left", -0.3, 2.0, 0.1, 2.0), plank("right", 8.3, 2.0, 0.1, 2.0),
               plank("ledge1", 2.6, 1.2, 0.7, 0.08, friction=1.0),
               plank("ledge2", 4.6, 2.2, 0.6, 0.08, friction=0.2),
               plank("ramp", 6.8, 0.9, 1.0, 0.06, angle=-0.35, friction=0.1),
               character],
    "inputs": [{"time": 0.5, "body": "hero", "set_velocity": [1.5, 0.0]},
               {"time": 1.2, "body": "hero", "set_velocity": [2.2, 5.6]},
               {"time": 2.4, "body": "hero", "set_velocity": [1.8, 5.2]}]})

# a pinball table (tilted: gravity 5 m/s^2 along it): walls, two ramps, two
# paddles spinning on their own (fixed), three bumpers, three balls
write("pinball.json", {
    "name": "pinball: spinning paddles, ramps, bumpers and three balls", "end_time": 6.0, "frame_rate": 60,
    "gravity": [0.0, -5.0],
    "bodies": [plank("bottom", 0.6, -0.05, 0.7, 0.05), plank("top", 0.6, 2.05, 0.7, 0.05),
               plank("left", -0.05, 1.0, 0.05, 1.0), plank("right", 1.25, 1.0, 0.05, 1.0),
               plank("ramp_l", 0.22, 0.45, 0.25, 0.03, angle=-0.5, friction=0.2),
               plank("ramp_r", 0.98, 0.45, 0.25, 0.03, angle=0.5, friction=0.2),
               plank("paddle_l", 0.35, 1.0, 0.14, 0.02, angular_velocity=3.0),
               plank("paddle_r", 0.85, 1.0, 0.14, 0.02, angular_velocity=-3.0),
               {"name": "bumper1", "shape": "circle", "fixed": True, "radius": 0.07, "position": [0.6, 1.5]},
               {"name": "bumper2", "shape": "circle", "fixed": True, "radius": 0.06, "position": [0.3, 1.7]},
               {"name": "bumper3", "shape": "circle", "fixed": True, "radius": 0.06, "position": [0.9, 1.7]},
               {"name": "ball1", "shape": "circle", "radius": 0.03, "mass": 0.08, "restitution": 0.8,
                "friction": 0.1, "position": [0.55, 1.9], "velocity": [0.8, 0.0]},
               {"name": "ball2", "shape": "circle", "radius": 0.03, "mass": 0.08, "restitution": 0.8,
                "friction": 0.1, "position": [0.2, 1.3], "velocity": [1.5, 1.0]},
               {"name": "ball3", "shape": "circle", "radius": 0.03, "mass": 0.08, "restitution": 0.8,
                "friction": 0.1, "position": [1.0, 1.25], "velocity": [-1.0, 2.0]}]})

# a ball pit: 42 balls (restitution 0.8, a little friction) rain
# into a bin and settle as sleeping islands; one more ball rests asleep on a
# shelf beside the bin until a scripted push at t = 5 s rolls it off: it
# drops into the settled pile and wakes the islands it hits
balls = []
for i in range(42):
    row, col = divmod(i, 7)
    balls.append({"name": f"ball{i}", "shape": "circle", "radius": 0.05, "mass": 0.1, "restitution": 0.8,
                  "friction": 0.3, "position": [round(0.12 + col * 0.12 + 0.008 * math.sin(i * 2.3), 6),
                                                round(0.35 + row * 0.16, 6)],
                  "velocity": [round(0.4 * math.cos(i * 1.7), 6), 0.0]})
write("ball-pit.json", {
    "name": "ball pit: 42 balls settle in a bin and fall asleep; a 43rd is pushed in at t = 5 s",
    "end_time": 8.0, "frame_rate": 60, "gravity": [0.0, -9.81],
    "bodies": [plank("floor", 0.5, -0.05, 0.6, 0.05, friction=0.5),
               plank("left", -0.05, 0.7, 0.05, 0.75), plank("right", 1.01, 0.7, 0.05, 0.75),
               plank("shelf", -0.35, 1.5, 0.25, 0.03, friction=0.5)] + balls
              + [{"name": "dropper", "shape": "circle", "radius": 0.05, "mass": 0.1, "restitution": 0.8,
                  "friction": 0.3, "position": [-0.45, 1.58]}],
    "inputs": [{"time": 5.0, "body": "dropper", "set_velocity": [1.2, 0.0]}]})

# a moving platform: a short level of two ledges with a gap; a
# platform (fixed, friction) goes back and forth across the gap at 0.5 m/s
# (scripted set_velocity inputs reverse it at each end), carrying a box that
# rests on it; a ball dropped into the gap lands on the platform, bounces,
# comes to rest on it and is carried along too (neither sleeps: a body on a
# moving support never does); at each reversal both slide on the platform
# until friction stops them; another ball sleeps on the right ledge
V = 0.5
write("moving-platform.json", {
    "name": "moving platform: a box and a ball carried back and forth across a gap", "end_time": 8.0,
    "frame_rate": 60, "gravity": [0.0, -9.81],
    "bodies": [plank("ledge_l", 0.5, -0.1, 0.5, 0.1, friction=1.0),
               plank("ledge_r", 3.9, -0.1, 0.5, 0.1, friction=1.0),
               plank("pit", 2.2, -1.1, 1.2, 0.1),
               plank("wall_l", -0.1, 0.0, 0.1, 1.2), plank("wall_r", 4.5, 0.0, 0.1, 1.2),
               plank("platform", 1.35, -0.05, 0.3, 0.05, friction=1.0, velocity=[V, 0.0]),
               {"name": "box", "shape": "polygon", "mass": 1.0, "restitution": 0.2, "friction": 0.5,
                "position": [1.2, 0.1], "velocity": [V, 0.0],
                "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]},
               {"name": "ball", "shape": "circle", "radius": 0.06, "mass": 0.2, "restitution": 0.5,
                "friction": 0.3, "position": [1.85, 0.9]},
               {"name": "rester", "shape": "circle", "radius": 0.08, "mass": 0.3, "restitution": 0.5,
                "friction": 0.3, "position": [3.9, 0.08]}],
    "inputs": [{"time": 3.4, "body": "platform", "set_velocity": [-V, 0.0]},
               {"time": 6.8, "body": "platform", "set_velocity": [V, 0.0]}]})


# ---- piles, stacks and dominoes: lasting contact among movable bodies ----
# In piles/: the benchmarks' scenes (max2code event-vs-frame, bench/idle.py)
# of bodies in lasting contact with each other, which the simulator may stop
# as stuck or model only in part (friction between movable bodies, tipping);
# the tests that run every examples/*.json do not run these.
def square(name, cx, cy, half, mass, **kw):
    """A movable square box of side 2 half."""
    b = {"name": name, "shape": "polygon", "mass": mass, "position": [round(cx, 12), round(cy, 12)],
         "vertices": [[-half, -half], [half, -half], [half, half], [-half, half]]}
    b.update(kw)
    return b


def bin_walls(w, h, friction=0.5):
    """A floor and two side walls around [0, w] x [0, h] (open at the top)."""
    return [plank("floor", w / 2, -0.05, w / 2 + 0.1, 0.05, friction=friction),
            plank("left", -0.05, h / 2, 0.05, h / 2), plank("right", w + 0.05, h / 2, 0.05, h / 2)]


# a ball pit of 200: balls (radius 5 cm, restitution 0.3, friction 0.3) in a
# 2 x 3 m bin, in a 16 x 13 grid with start velocities up to 1 m/s; they fall,
# pile up and settle
balls = []
for i in range(200):
    row, col = divmod(i, 16)
    balls.append({"name": f"ball{i}", "shape": "circle", "radius": 0.05, "mass": 0.1, "restitution": 0.3,
                  "friction": 0.3, "position": [round(0.1 + col * 0.12 + 0.01 * math.sin(i * 2.3), 6),
                                                round(0.3 + row * 0.16, 6)],
                  "velocity": [round(math.cos(i * 1.7), 6), round(0.5 * math.sin(i * 2.9), 6)]})
write("piles/pit-200.json", {"name": "a pit of 200 balls: they fall into a 2 x 3 m bin, pile up and settle",
                       "end_time": 5.0, "frame_rate": 60, "gravity": [0.0, -9.81],
                       "bodies": bin_walls(2.0, 3.0) + balls})

# a mixed pile: 50 boxes (10 cm) and 50 balls (radius 5 cm) in a 10 x 10
# grid, alternating, dropped into a 2 m wide bin (restitution 0.3, friction 0.3)
bodies = []
for i in range(100):
    row, col = divmod(i, 10)
    x, y = round(0.15 + col * 0.19 + 0.01 * math.sin(i * 1.3), 6), round(0.3 + row * 0.2, 6)
    if (row + col) % 2 == 0:
        bodies.append(square(f"box{i}", x, y, 0.05, 0.1, restitution=0.3, friction=0.3, angle=round(0.3 * math.sin(i), 6)))
    else:
        bodies.append({"name": f"ball{i}", "shape": "circle", "radius": 0.05, "mass": 0.1, "restitution": 0.3,
                       "friction": 0.3, "position": [x, y]})
write("piles/mixed-pile.json", {"name": "a mixed pile: 50 boxes and 50 balls dropped into a bin",
                          "end_time": 5.0, "frame_rate": 60, "gravity": [0.0, -9.81],
                          "bodies": bin_walls(2.0, 3.0) + bodies})

# 20 dominoes (2 x 20 cm, 50 g) 12 cm apart on a floor; the first is set
# tipping at 3 rad/s about its front bottom corner (its centre moves as a
# point of a body turning about that corner): each falls onto the next
W, H, PITCH = 0.01, 0.1, 0.12
dominoes = []
for i in range(20):
    d = square(f"domino{i}", 0.2 + i * PITCH, H, 0.0, 0.05, restitution=0.1, friction=0.5)
    d["vertices"] = [[-W, -H], [W, -H], [W, H], [-W, H]]
    dominoes.append(d)
OM = -3.0          # clockwise: the top moves in +x
dominoes[0]["angular_velocity"] = OM
dominoes[0]["velocity"] = [-OM * H, OM * -W]      # omega x (centre - corner), corner (W, -H) from the centre
write("piles/dominoes.json", {"name": "20 dominoes: the first tips over and knocks down the rest",
                        "end_time": 4.0, "frame_rate": 60, "gravity": [0.0, -9.81],
                        "bodies": [plank("floor", 1.5, -0.05, 1.8, 0.05, friction=0.5)] + dominoes})

# a 6-row pyramid of 21 boxes (20 cm, 1 kg, 1 mm apart in a row) hit at its
# second row by a ball (radius 10 cm, 2 kg) at 8 m/s
boxes = []
for row in range(6):
    for i in range(6 - row):
        boxes.append(square(f"box{row}_{i}", 1.5 + (i + row / 2) * 0.201, 0.1 + row * 0.2, 0.1, 1.0,
                            restitution=0.1, friction=0.5))
write("piles/pyramid-hit.json", {"name": "a 6-row pyramid of boxes hit by a ball", "end_time": 4.0, "frame_rate": 60,
                           "gravity": [0.0, -9.81],
                           "bodies": [plank("floor", 2.5, -0.05, 3.0, 0.05, friction=0.5),
                                      {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 2.0,
                                       "restitution": 0.1, "friction": 0.5, "position": [0.3, 0.3],
                                       "velocity": [8.0, 1.0]}] + boxes})

# a stack of 10 boxes (20 cm, 1 kg) hit at its fourth box by a ball
# (radius 10 cm, 2 kg) at 6 m/s
write("piles/stack-hit.json", {"name": "a stack of 10 boxes hit by a ball", "end_time": 4.0, "frame_rate": 60,
                         "gravity": [0.0, -9.81],
                         "bodies": [plank("floor", 2.0, -0.05, 2.5, 0.05, friction=0.5),
                                    {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 2.0,
                                     "restitution": 0.1, "friction": 0.5, "position": [0.3, 0.7],
                                     "velocity": [6.0, 0.5]}]
                         + [square(f"box{k}", 1.5, 0.1 + k * 0.2, 0.1, 1.0, restitution=0.1, friction=0.5)
                            for k in range(10)]})

# a box sliding on a box: the bottom box (1 m x 20 cm, 2 kg) rests on a floor
# (friction 1 x 0.5); the top box (20 cm, 0.5 kg) slides on it at 1 m/s with
# friction 0.5 x 0.5 = 0.25: Coulomb stops it after v^2 / (2 mu g) = 0.2039 m,
# while the floor holds the bottom box (0.25 x 0.5 g < 0.5 x 2.5 g)
write("piles/box-on-box.json", {"name": "a box sliding to a stop on a box", "end_time": 2.0, "frame_rate": 60,
                          "gravity": [0.0, -9.81],
                          "bodies": [plank("floor", 1.0, -0.05, 1.5, 0.05, friction=1.0),
                                     {"name": "bottom", "shape": "polygon", "mass": 2.0, "restitution": 0.0,
                                      "friction": 0.5, "position": [1.0, 0.1],
                                      "vertices": [[-0.5, -0.1], [0.5, -0.1], [0.5, 0.1], [-0.5, 0.1]]},
                                     square("top", 0.65, 0.3, 0.1, 0.5, restitution=0.0, friction=0.5,
                                            velocity=[1.0, 0.0])]})

# a box overhanging a ledge: two boxes (20 cm, 1 kg) at rest on a fixed ledge
# whose right end is at x = 1; "tipper" has its centre of mass 5 cm beyond
# the end (it should tip and fall to the floor), "holder", at the ledge's left
# end, has 5 cm of its width over the edge and its centre 5 cm inside (it stays)
write("piles/overhang.json", {"name": "a box overhanging a ledge by 5 cm tips off; a supported one stays",
                        "end_time": 2.0, "frame_rate": 60, "gravity": [0.0, -9.81],
                        "bodies": [plank("floor", 0.5, -0.05, 1.5, 0.05, friction=0.5),
                                   plank("ledge", 0.5, 0.45, 0.5, 0.05, friction=0.5),
                                   square("tipper", 1.05, 0.6, 0.1, 1.0, restitution=0.0, friction=0.5),
                                   square("holder", 0.05, 0.6, 0.1, 1.0, restitution=0.0, friction=0.5)]})
