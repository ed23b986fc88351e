"""Ball hero: a small platformer on max2code's event-driven engine.

The world (level.json) runs in the compiled C engine through
max2code.sim.live (or the pure-Python reference: --engine python).  Every
frame the game advances the world to the frame's time, reads each body's
exact state there to draw it, and turns the keys into live inputs at that
time: walking sets the hero's horizontal velocity, a jump sets its vertical
one; a gem the hero touches is teleported to the shelf above the room (a
point), a boulder that touches the hero sends it back to the start
(teleport; refused while something is in the way, so tried again each
frame).  Every live input goes into the world's input list, so the session
can be saved as a scene that replays it exactly.  Between frames the engine has nothing to do
unless an event (a contact, a support ending, ...) falls there.

Play:      python examples/game/game.py            (arrows or A/D to walk, space/up/W to jump, Esc to quit)
Headless:  SDL_VIDEODRIVER=dummy python examples/game/game.py --keys examples/game/keys.txt --frames 1200
           --record build/game-recording.json      (the session as a scene: max2code crosscheck takes it)
Options:   --engine c|python, --fps F, --save-keys FILE (write your play as a key script), --trace FILE
           (the flat trace), --shots DIR --every N (PNG frames), --quiet.

Key script: one line per key change, `FRAME KEY down|up` with KEY left, right or jump; `#` starts a comment.
In a key script the clock is the frame counter (frame k at k / fps s), so a run is the same on any machine;
played live, the clock is the wall clock.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

WIDTH, HEIGHT, SCALE = 960, 600, 60.0       # pixels; pixels per metre (the room is 16 m x 9 m, the shelf above)
WALK, JUMP = 3.2, 6.6                        # m/s
SPAWN = (1.0, 0.25)                          # where the hero starts and returns after a hit
SHELF_Y = 9.6                                # m: collected gems rest here, above the ceiling, one slot each
KEYS = ("left", "right", "jump")
LIFT_Y = (3.0, 6.5)                          # m: the lift's centre turns back at these heights


class GameError(Exception):
    pass


def read_keys(path: str) -> dict[int, list[tuple[str, bool]]]:
    """The key script: frame -> [(key, down)] in file order."""
    script: dict[int, list[tuple[str, bool]]] = {}
    with open(path, encoding="utf-8") as fh:
        for n, line in enumerate(fh, 1):
            words = line.split("#", 1)[0].split()
            if not words:
                continue
            if len(words) != 3 or not words[0].isdigit() or words[1] not in KEYS or words[2] not in ("down", "up"):
                raise GameError(f"{path}:{n}: error: expected 'FRAME KEY down|up' with KEY one of "
                                f"{', '.join(KEYS)}, got {line.strip()!r}")
            script.setdefault(int(words[0]), []).append((words[1], words[2] == "down"))
    return script


class Game:
    """The rules, independent of the display: which inputs the keys make,
    what a contact with a gem or a boulder does."""

    def __init__(self, world, scene):
        self.w, self.scene = world, scene
        self.names = [b.name for b in scene.bodies]
        idx = {n: k for k, n in enumerate(self.names)}
        self.hero = idx["hero"]
        self.lift = idx.get("lift")
        self.gems = {k for k, n in enumerate(self.names) if n.startswith("gem")}
        self.boulders = {k for k, n in enumerate(self.names) if n.startswith("boulder")}
        self.collected: list[int] = []      # gems on the shelf, in the order taken
        self.pending: list[int] = []        # gems touched, to move at the next input time
        self.held = {k: False for k in KEYS}
        self.jump_pressed = False
        self.vx_set = 0.0            # the walking speed last given to the hero
        self.ground_until = -1.0     # s: the hero may jump until then (it touched something below it)
        self.score = 0
        self.hits = 0
        self.respawn = False         # a boulder hit the hero: teleport it at the next chance
        self.inputs = 0

    def key(self, name: str, down: bool) -> None:
        if name == "jump" and down and not self.held["jump"]:
            self.jump_pressed = True
        self.held[name] = down

    def contacts(self, contacts) -> None:
        h = self.hero
        for c in contacts:
            if h not in (c.a, c.b):
                continue
            other = c.b if c.a == h else c.a
            # the normal points from a to b: from below the hero it points up at the hero
            up = c.ny if c.b == h else -c.ny
            if up > 0.5:
                self.ground_until = c.t + 0.12
            if other in self.gems and other not in self.collected and other not in self.pending:
                self.pending.append(other)
            elif other in self.boulders and not self.respawn:
                self.hits += 1
                self.respawn = True

    def _input(self, op: str, body: int, x: float, y: float):
        done = getattr(self.w, op)(body, x, y)
        if done is not False:           # a refused teleport changes nothing and is not recorded
            self.inputs += 1
        return done

    def step(self, t: float) -> None:
        """The live inputs of this frame, at the world's time t."""
        w, h = self.w, self.hero
        if self.lift is not None:
            # the lift turns back at the first frame past an end of its shaft (a live
            # set_velocity on a fixed polygon: what rests on it meets it again at once)
            _, ly, _, lvy, _, _ = w.state(self.lift, t)
            if (lvy > 0.0 and ly >= LIFT_Y[1]) or (lvy < 0.0 and ly <= LIFT_Y[0]):
                self._input("set_velocity", self.lift, 0.0, -lvy)
        for g in list(self.pending):
            slot = 12.2 + 0.45 * len(self.collected)
            if self._input("teleport", g, slot, SHELF_Y):
                self._input("set_velocity", g, 0.0, 0.0)
                self.pending.remove(g)
                self.collected.append(g)
                self.score += 1
        if self.respawn and self._input("teleport", h, *SPAWN):
            self._input("set_velocity", h, 0.0, 0.0)
            self.respawn = False
            self.vx_set = 0.0
        x, y, vx, vy, _, _ = w.state(h, t)
        want = WALK * ((1.0 if self.held["right"] else 0.0) - (1.0 if self.held["left"] else 0.0))
        grounded = vy == 0.0 or t <= self.ground_until
        jump = self.jump_pressed and grounded
        self.jump_pressed = False
        if jump:
            self._input("set_velocity", h, want, JUMP)
            self.vx_set = want
            self.ground_until = -1.0
        elif want != self.vx_set:
            self._input("set_velocity", h, want, vy)
            self.vx_set = want


def save_recording(scene_path: str, world, end_time: float, path: str) -> None:
    """The session as a scene (max2code.sim.recording: the scene with every
    live input scripted at its time), ending at end_time: with --frames the
    world's own end, so that the scene's trace is the session's byte for byte;
    played live, the time the game stopped."""
    from max2code.sim.recording import recording
    from max2code.sim.scene import parse_scene
    rec = recording(scene_path, world.input_log(), world.added)
    rec["end_time"] = end_time
    text = json.dumps(rec, indent=1) + "\n"
    parse_scene(text, path)                 # checked as any scene is
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


class View:
    """Draws the world's bodies from their exact states at the frame's time."""

    def __init__(self, scene, pygame):
        self.pg = pygame
        self.screen = pygame.display.set_mode((WIDTH, HEIGHT))
        pygame.display.set_caption("max2code: ball hero")
        self.font = pygame.font.Font(None, 24)
        self.scene = scene

    @staticmethod
    def px(x: float, y: float) -> tuple[int, int]:
        return round(x * SCALE), round(HEIGHT - y * SCALE)

    def colour(self, name: str, fixed: bool):
        if name == "hero":
            return (240, 150, 40)
        if name.startswith("gem"):
            return (60, 210, 230)
        if name.startswith("boulder"):
            return (200, 60, 60)
        return (120, 120, 140) if fixed else (200, 200, 200)

    def draw(self, game: Game, t: float, busy_ms: float) -> None:
        pg, w = self.pg, game.w
        self.screen.fill((24, 26, 34))
        pg.draw.line(self.screen, (70, 70, 90), self.px(0.0, 9.2), self.px(16.0, 9.2))
        for b, (x, y, _, _, ang, _) in zip(self.scene.bodies, w.states(t)):
            col = self.colour(b.name, b.fixed)
            if b.polygon:
                c, s = math.cos(ang), math.sin(ang)
                pts = [self.px(x + c * vx - s * vy, y + s * vx + c * vy) for vx, vy in b.vertices]
                pg.draw.polygon(self.screen, col, pts)
            else:
                if b.orbit_radius > 0.0:
                    x += b.orbit_radius * math.cos(ang + b.orbit_angle)
                    y += b.orbit_radius * math.sin(ang + b.orbit_angle)
                pg.draw.circle(self.screen, col, self.px(x, y), max(1, round(b.radius * SCALE)))
                if b.name == "hero":
                    for dx in (-0.08, 0.08):
                        pg.draw.circle(self.screen, (20, 20, 20), self.px(x + dx, y + 0.07), 3)
        text = (f"gems {game.score}/{len(game.gems)}   hits {game.hits}   t {t:6.2f} s   "
                f"engine {busy_ms:5.2f} ms/frame")
        self.screen.blit(self.font.render(text, True, (230, 230, 230)), (10, 8))
        pg.display.flip()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Ball hero: a platformer on max2code's event-driven engine")
    ap.add_argument("--engine", choices=("c", "python"), default="c")
    ap.add_argument("--scene", default=os.path.join(HERE, "level.json"))
    ap.add_argument("--keys", help="play this key script instead of the keyboard (FRAME KEY down|up lines)")
    ap.add_argument("--frames", type=int, help="stop after this many frames")
    ap.add_argument("--fps", type=float, default=60.0)
    ap.add_argument("--record", help="save the session as a scene (JSON) here")
    ap.add_argument("--save-keys", help="write the keys played as a key script here")
    ap.add_argument("--trace", help="write the engine's flat trace here (docs/simulator.md)")
    ap.add_argument("--shots", help="save every --every'th frame as a PNG into this folder")
    ap.add_argument("--every", type=int, default=30)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)

    import pygame
    from max2code.sim.live import open_world
    from max2code.sim.scene import SceneError, parse_scene
    from max2code_rt.sim import SimError

    try:
        script = read_keys(args.keys) if args.keys else None
        with open(args.scene, encoding="utf-8") as fh:
            raw = json.load(fh)
        if args.frames is not None:
            # the world ends at the last frame: the recording then replays the whole session, final lines included
            raw["end_time"] = args.frames / args.fps
        scene = parse_scene(json.dumps(raw), args.scene)
    except OSError as exc:
        print(f"{exc.filename}: error: cannot read: {exc.strerror}", file=sys.stderr)
        return 1
    except ValueError as exc:          # not JSON
        print(f"{args.scene}: error: not a JSON scene: {exc}", file=sys.stderr)
        return 1
    except (GameError, SceneError) as exc:
        print(str(exc), file=sys.stderr)
        return 1
    trace = open(args.trace, "w", encoding="ascii") if args.trace else None
    world = open_world(scene, args.engine, out=trace)
    pygame.display.init()        # no sound: the mixer is never started
    pygame.font.init()
    view = View(scene, pygame)
    game = Game(world, scene)
    clock = pygame.time.Clock()
    keymap = {pygame.K_LEFT: "left", pygame.K_a: "left", pygame.K_RIGHT: "right", pygame.K_d: "right",
              pygame.K_SPACE: "jump", pygame.K_UP: "jump", pygame.K_w: "jump"}
    played: list[str] = []
    start = time.monotonic()
    busy = 0.0          # s of CPU in the engine (advance, inputs, state reads), all frames
    t = 0.0
    frame = 0
    drawn = 0
    status = 0
    running = True
    while running:
        frame += 1
        if args.frames is not None and frame > args.frames:
            break
        for ev in pygame.event.get():
            if ev.type == pygame.QUIT or (ev.type == pygame.KEYDOWN and ev.key == pygame.K_ESCAPE):
                running = False
            elif script is None and ev.type in (pygame.KEYDOWN, pygame.KEYUP) and ev.key in keymap:
                game.key(keymap[ev.key], ev.type == pygame.KEYDOWN)
                played.append(f"{frame} {keymap[ev.key]} {'down' if ev.type == pygame.KEYDOWN else 'up'}")
        if script is not None:
            for name, down in script.get(frame, ()):
                game.key(name, down)
            t = frame / args.fps
        else:
            t = max(t, time.monotonic() - start)
        t = min(t, scene.end_time)
        c0 = time.process_time()
        try:
            game.contacts(world.advance(t))
            game.step(t)
        except SimError as exc:         # a stuck scene: the world cannot go on
            print(f"{args.scene}: error: the engine stopped before t = {t:.6f} s: {exc}", file=sys.stderr)
            status = 1
            break
        busy_frame = time.process_time() - c0
        busy += busy_frame
        view.draw(game, t, busy_frame * 1e3)
        drawn += 1
        if args.shots and frame % args.every == 0:
            os.makedirs(args.shots, exist_ok=True)
            pygame.image.save(view.screen, os.path.join(args.shots, f"frame{frame:05d}.png"))
        if t >= scene.end_time:
            game.contacts(world.finish())        # the events at the end, the trace's final lines
            break
        if script is None:
            clock.tick(args.fps)
    pygame.quit()
    if args.record and status == 0:
        save_recording(args.scene, world, scene.end_time if t >= scene.end_time else t, args.record)
    if hasattr(world, "close"):
        world.close()           # the C world passes the rest of its trace on
    if trace is not None:
        trace.close()
    if args.save_keys:
        with open(args.save_keys, "w", encoding="utf-8") as fh:
            fh.write("# frame key down|up (examples/game/game.py --keys)\n" + "".join(p + "\n" for p in played))
    if not args.quiet:
        n = max(drawn, 1)
        print(f"game: {drawn} frames to t = {t:.3f} s on the {args.engine} engine: gems {game.score}/{len(game.gems)}, "
              f"hits {game.hits}, live inputs {game.inputs}; engine {busy / n * 1e3:.3f} ms CPU per frame"
              + (f"; recording {args.record}" if args.record else ""))
    return status


if __name__ == "__main__":
    sys.exit(main())
