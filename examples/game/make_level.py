"""Write level.json, the game's scene (run from the project root:
`python examples/game/make_level.py`).  The JSON file is committed; this
script says how its numbers were chosen.

A 16 m x 9 m room (60 pixels a metre fills a 960 x 540 window): ground,
walls and ceiling; five ledges; three moving platforms (a bar spinning slowly
about its centre, two discs carried round a wheel: orbiting fixed
circles, the paper's orbits, and a lift: a fixed plank that rises and
falls at constant speed, reversed by the game loop at the ends of its
shaft, which carries what rests on it); the hero, a ball (a circle never turns by
contact, so it cannot tumble) without friction or bounce, walked and jumped
by the keys; four gems that float (their own acceleration cancels gravity)
and drift, to collect; two heavy balls that bounce for ever (restitution 1),
to dodge.  end_time is long: a game plays until the player stops, and its
recording (max2code.sim.live) is cut to the time played."""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.81


def box(name, cx, cy, hw, hh, **kw):
    b = {"name": name, "shape": "polygon", "fixed": True, "position": [cx, cy],
         "vertices": [[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]]}
    b.update(kw)
    return b


def level():
    bodies = [box("ground", 8.0, -0.1, 8.2, 0.1), box("ceiling", 8.0, 9.1, 8.2, 0.1),
              box("left", -0.1, 4.5, 0.1, 4.5), box("right", 16.1, 4.5, 0.1, 4.5),
              box("ledge1", 3.0, 1.5, 1.0, 0.1), box("ledge2", 6.2, 2.8, 0.9, 0.1),
              box("ledge3", 12.2, 2.2, 1.1, 0.1), box("ledge4", 14.6, 4.2, 0.9, 0.1),
              box("ledge5", 1.6, 4.4, 1.1, 0.1),
              # moving platforms: a bar turning once in about 8 s, two discs round a wheel
              box("spinner", 9.4, 4.0, 1.1, 0.08, angular_velocity=0.8),
              # the lift: game.py reverses it at the ends of its shaft (LIFT_Y)
              box("lift", 11.3, 3.0, 0.6, 0.08, velocity=[0.0, 0.6]),
              {"name": "disc1", "shape": "circle", "fixed": True, "radius": 0.35, "position": [5.0, 6.2],
               "orbit": {"radius": 1.3, "angle": 0.0}, "angular_velocity": 0.6},
              {"name": "disc2", "shape": "circle", "fixed": True, "radius": 0.35, "position": [5.0, 6.2],
               "orbit": {"radius": 1.3, "angle": math.pi}, "angular_velocity": 0.6},
              {"name": "hero", "shape": "circle", "radius": 0.25, "mass": 1.0, "restitution": 0.0,
               "friction": 0.0, "position": [1.0, 0.25]}]
    for k, (x, y, vx, vy) in enumerate([(3.0, 2.3, 0.4, 0.1), (6.2, 3.6, -0.3, 0.2), (12.2, 3.0, 0.2, -0.3),
                                        (9.4, 6.8, -0.5, 0.25)]):
        bodies.append({"name": f"gem{k + 1}", "shape": "circle", "radius": 0.15, "mass": 0.1, "restitution": 1.0,
                       "position": [x, y], "velocity": [vx, vy], "acceleration": [0.0, G]})
    for k, (x, y, vx) in enumerate([(8.0, 1.6, 1.2), (13.5, 6.5, -0.9)]):
        bodies.append({"name": f"boulder{k + 1}", "shape": "circle", "radius": 0.3, "mass": 3.0,
                       "restitution": 1.0, "position": [x, y], "velocity": [vx, 0.0]})
    return {"name": "game: a ball hero, ledges, a spinning bar, a wheel, gems and boulders",
            "end_time": 3600.0, "gravity": [0.0, -G], "bodies": bodies}


if __name__ == "__main__":
    with open(os.path.join(HERE, "level.json"), "w") as f:
        json.dump(level(), f, indent=1)
        f.write("\n")
