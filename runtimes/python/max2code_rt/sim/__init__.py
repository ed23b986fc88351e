"""The discrete-event simulator: the Python runtime, and the reference for
the C, Rust and Modula-2 ones (docs/simulator.md).

It reads a compiled scene (the flat text format of docs/simulator.md, made
by `max2code simulate` from a JSON scene) and writes the flat trace.  Every
prediction goes through the generated entry functions of
equations/circle-circle.mxm and equations/point-edge.mxm (the module objects
`cc` and `pe` hold `circle_circle_coefficients`, `circle_circle_variant`,
`point_edge_coefficients`, `point_edge_variant`), and through the runtime's
root solver.  The four runtimes perform the same IEEE double operations in
the same order, so they write the same bytes.

One module per concept (the same names in every runtime): scene (the flat
scene), queue (event records, the queue), grid (broad phase), motion,
predict (pairs, features, first valid roots, cell crossings), contact
(contact frame and impulse), cluster (simultaneous contacts), support
(resting, sliding, carried bodies), sleep (sleeping islands), overlap (a
teleport's or an added body's check), world (the World's state), live (the
World and its API), handlers (one per event kind, their dispatch) and out
(the trace).  World (live.py) combines one mixin class per concept; this
package exports the names its users take from it.
"""
from max2code_rt.sim.cluster import (CLUSTER_APART, CLUSTER_REPEATS, CLUSTER_SWEEPS, CLUSTER_TOL, FREE, HELD, HOLD_TOL,
                                     SLIDER)
from max2code_rt.sim.live import World, simulate
from max2code_rt.sim.out import NoTrace, SimError
from max2code_rt.sim.predict import (CC, CHAIN, FEATURE_NAMES, HALF_PI, PE, TWO_M30, TWO_M40, TWO_M450, TWO_M900,
                                     TWO_P450)
from max2code_rt.sim.queue import (CELL, COLLISION, FRAME, HORIZON, INPUT, KIND_NAMES, LEAVE, STOP, CellEvent,
                                   CollisionEvent, FrameEvent, HorizonEvent, InputEvent, LeaveEvent, StopEvent)
from max2code_rt.sim.scene import (ADD_VELOCITY, IMPULSE, REMOVE, SET_VELOCITY, TELEPORT, Body, Input, Scene, Tokens,
                                   Vertex, drivable, read_body)
from max2code_rt.sim.world import STAT_NAMES, Contact, Stats

__all__ = ["ADD_VELOCITY", "CC", "CELL", "CHAIN", "CLUSTER_APART", "CLUSTER_REPEATS", "CLUSTER_SWEEPS",
           "CLUSTER_TOL", "COLLISION", "FEATURE_NAMES", "FRAME", "FREE", "HALF_PI", "HELD", "HOLD_TOL",
           "HORIZON", "IMPULSE", "INPUT", "KIND_NAMES", "LEAVE", "PE", "REMOVE", "SET_VELOCITY", "SLIDER",
           "STAT_NAMES", "STOP", "TELEPORT", "TWO_M30", "TWO_M40", "TWO_M450", "TWO_M900", "TWO_P450",
           "Body", "CellEvent", "CollisionEvent", "Contact", "FrameEvent", "HorizonEvent", "Input",
           "InputEvent", "LeaveEvent", "NoTrace", "Scene", "SimError", "Stats", "StopEvent", "Tokens",
           "Vertex", "World", "drivable", "read_body", "simulate"]
