"""The side-by-side benchmark's peers (max2code/reports/peers.py): each
driver reads the scene as meant (a ball and a box dropped on a floor land
when free fall says, within the peer's step; a start velocity carries a body
on a frictionless floor; restitution 1 bounces back to the drop height),
the overlap judge measures depths right, and a run of ours that stops early
is reported with the instant, not raised."""
import json
import math
import os
from pathlib import Path

import pytest

from max2code.reports import peers
from max2code.sim.scene import parse_scene

ROOT = next(p for p in Path(__file__).resolve().parents if (p / "pyproject.toml").exists())
G = 9.81
DROP = 1.0          # m from the bodies' lowest points to the floor


def drop_scene():
    """A floor (top at y = 0); a ball (radius 0.1, restitution 0, sliding at
    0.5 m/s), a box (0.2 m, restitution 0) and a bouncing ball (restitution 1),
    each DROP above the floor."""
    return parse_scene(json.dumps({
        "name": "drops", "end_time": 1.0, "gravity": [0.0, -G],
        "bodies": [
            {"name": "floor", "shape": "polygon", "fixed": True, "position": [2.0, -0.05],
             "vertices": [[-3, -0.05], [3, -0.05], [3, 0.05], [-3, 0.05]]},
            {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1.0, "restitution": 0.0,
             "position": [0.0, DROP + 0.1], "velocity": [0.5, 0.0]},
            {"name": "box", "shape": "polygon", "mass": 2.0, "restitution": 0.0, "position": [1.5, DROP + 0.1],
             "vertices": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]},
            {"name": "bouncer", "shape": "circle", "radius": 0.1, "mass": 1.0, "position": [3.0, DROP + 0.1]}]}),
        "<drops>")


def check_drops(run: peers.Run, dt: float) -> None:
    assert run.status == "ok", run.status
    assert run.cpu > 0.0 and run.simulated == pytest.approx(1.0, abs=dt)
    samples = run.samples
    land = math.sqrt(2 * DROP / G)
    for i in (1, 2):            # ball, box: the first instant their fall stops
        t = next(t for t, st in samples if st[i][4] > -1.0 and t > 0.2)
        assert abs(t - land) <= 2 * dt, (i, t, land)
        x, y, a, vx, vy, om = samples[-1][1][i]
        assert y == pytest.approx(0.1, abs=0.01) and abs(vy) < 0.05
    assert samples[-1][1][1][0] == pytest.approx(0.5 * 1.0, abs=0.02)       # slid on at 0.5 m/s
    assert samples[-1][1][2][0] == pytest.approx(1.5, abs=1e-3) and abs(samples[-1][1][2][2]) < 1e-3
    after = [st[3][1] for t, st in samples if land + 0.1 < t < land + 0.6]
    assert max(after) > 0.1 + 0.9 * DROP                                    # bounced back up
    # the judge sees the landings' overlaps: at most one step's travel at the landing speed
    out = peers.judge(drop_scene(), samples)
    assert 0.0 <= out.overlap < math.sqrt(2 * G * DROP) * dt


def test_peer_text_carries_every_number_exactly():
    s = drop_scene()
    words = peers.peer_text(s).split()
    assert words[:10] == ["peer-scene", "end", "1.0", "dt", repr(peers.STEP), "substeps", "4", "gravity", "0.0",
                          repr(-G)]
    k = words.index("bodies")
    assert words[k + 1] == "4"
    box = words.index("p", k + 3)       # the box: the second polygon
    assert words[box:box + 3] == ["p", "0", "2.0"]
    assert float(words[box + 3]) == s.bodies[2].inertia
    assert words[-2:] == ["inputs", "0"]


def test_role_of_fixed_bodies():
    s = parse_scene(json.dumps({"end_time": 1.0, "bodies": [
        {"name": "still", "shape": "polygon", "fixed": True, "position": [0, 0],
         "vertices": [[-1, -0.1], [1, -0.1], [1, 0.1], [-1, 0.1]]},
        {"name": "paddle", "shape": "polygon", "fixed": True, "position": [0, 2], "angular_velocity": 1.0,
         "vertices": [[-1, -0.1], [1, -0.1], [1, 0.1], [-1, 0.1]]},
        {"name": "platform", "shape": "polygon", "fixed": True, "position": [0, 4],
         "vertices": [[-1, -0.1], [1, -0.1], [1, 0.1], [-1, 0.1]]},
        {"name": "ball", "shape": "circle", "radius": 0.1, "mass": 1, "position": [3, 3]}],
        "inputs": [{"time": 0.5, "body": "platform", "set_velocity": [1, 0]}]}), "<roles>")
    assert [peers._role(s, i) for i in range(4)] == [1, 2, 2, 0]


def test_overlap_depths():
    sq = lambda cx, cy, h: ("p", [(cx - h, cy - h), (cx + h, cy - h), (cx + h, cy + h), (cx - h, cy + h)])
    assert peers.overlap(("c", 0, 0, 1), ("c", 1.5, 0, 1)) == pytest.approx(0.5)
    assert peers.overlap(("c", 0, 0, 1), ("c", 3, 0, 1)) == 0.0
    assert peers.overlap(("c", 0, 1.2, 0.3), sq(0, 0, 1)) == pytest.approx(0.1)       # centre outside, over an edge
    assert peers.overlap(("c", 0, 0.9, 0.3), sq(0, 0, 1)) == pytest.approx(0.4)       # centre inside
    assert peers.overlap(("c", 1.1, 1.1, 0.2), sq(0, 0, 1)) == pytest.approx(0.2 - math.hypot(0.1, 0.1))
    assert peers.overlap(sq(0, 0, 1), sq(1.9, 0.5, 1)) == pytest.approx(0.1)
    assert peers.overlap(sq(0, 0, 1), sq(2.1, 0, 1)) == 0.0


def test_judge_rest_and_watched():
    s = parse_scene(json.dumps({"end_time": 1.0, "bodies": [
        {"name": "top", "shape": "circle", "radius": 0.1, "mass": 1, "position": [0, 0]}]}), "<one>")
    samples = [(0.1, [(0.0, 0.0, 0.0, 1.0, 0.0, 0.0)]), (0.2, [(0.1, 0.0, 0.0, 0.001, 0.0, 0.0)]),
               (0.3, [(0.1, 0.0, 7.0, 0.0, 0.0, 0.0)])]
    out = peers.judge(s, samples, "box-on-box")
    assert out.rest_from == pytest.approx(0.2) and out.overlap == 0.0
    assert out.watched["top"] == pytest.approx((0.1, 0.0, 7.0 - 2 * math.pi))


def test_tables_report_a_stopped_run():
    s = drop_scene()
    rows = [peers.Row("drops", s, {"ours": peers.Run("ours c", 0.5, 0.25, "stuck at t = 0.25 s"),
                                   "pymunk": peers.Run("pymunk", 0.01, 1.0),
                                   "rapier": peers.Run("rapier", status="not available: cargo not found")},
                      {"ours": peers.Outcome(), "pymunk": peers.Outcome(0.001, 0.5, {}),
                       "rapier": peers.Outcome()})]
    table = peers.cpu_table(rows)
    assert table[2].startswith("| drops (4, 1) | 2 | 0.01 | - | 200x | - |")
    assert "ours: stuck at t = 0.25 s; rapier: not available: cargo not found" in table[2]
    outcomes = "\n".join(peers.outcome_table(rows))
    assert "| drops | pymunk | 1 | 0.5 | - |" in outcomes and "(stuck at t = 0.25 s)" in outcomes


def test_pymunk_reads_the_scene():
    check_drops(peers.run_pymunk(drop_scene()), peers.STEP)


# The rapier2d driver's answer to drop_scene(), recorded: building rapier2d from crates.io takes minutes
# of CPU, so the suite runs the driver's recorded output through the same Python path instead (peer_text
# in, run_driver's subprocess, parse_driver_output, check_drops), and the recording names the driver
# sources (Cargo.toml, Cargo.lock, src/) and the exact input it was made from: a change to either fails
# test_rapier_recording_is_current until `python3 tests/commands/test_peers.py --record` builds the driver
# (peers.build_rapier, as the benchmark does) and records it again.
RAPIER_RECORDING = ROOT / "tests" / "data" / "peers" / "rapier-drops.json"


def rapier_driver_digest() -> str:
    """The digest of the rapier driver's sources, by their paths relative to the driver's folder."""
    import hashlib
    h = hashlib.sha256()
    d = peers.RAPIER_DIR
    for f in [d / "Cargo.toml", d / "Cargo.lock", *sorted((d / "src").rglob("*.rs"))]:
        data = f.read_bytes()
        h.update(f"{f.relative_to(d).as_posix()} {len(data)}\0".encode() + data)
    return h.hexdigest()


def record_rapier() -> None:
    """Build the rapier driver, run it on drop_scene() and write RAPIER_RECORDING."""
    import subprocess
    binary = peers.build_rapier(progress=True)
    text = peers.peer_text(drop_scene(), peers.STEP)
    proc = subprocess.run([binary], input=text, capture_output=True, text=True, timeout=600, check=True)
    RAPIER_RECORDING.parent.mkdir(parents=True, exist_ok=True)
    RAPIER_RECORDING.write_text(json.dumps({"driver": rapier_driver_digest(), "input": text, "output": proc.stdout},
                                           indent=1) + "\n", encoding="utf-8")


def rapier_recording() -> dict:
    return json.loads(RAPIER_RECORDING.read_text(encoding="utf-8"))


def test_rapier_recording_is_current():
    rec = rapier_recording()
    again = "the rapier driver's recording is stale: run `python3 tests/commands/test_peers.py --record`"
    assert rec["driver"] == rapier_driver_digest(), again + " (bench/peers/rapier changed)"
    assert rec["input"] == peers.peer_text(drop_scene(), peers.STEP), again + " (peer_text or the scene changed)"


def test_rapier_reads_the_scene(tmp_path):
    """The recorded driver output through run_driver: a stand-in program
    that answers the recorded input, and only it, with the recorded output."""
    import sys
    rec = rapier_recording()
    (tmp_path / "recording.json").write_text(json.dumps(rec), encoding="utf-8")
    stand_in = tmp_path / "rapier-peer"
    stand_in.write_text(f"#!{sys.executable}\n"
                        "import json, sys\n"
                        f"rec = json.load(open({str(tmp_path / 'recording.json')!r}))\n"
                        "if sys.stdin.read() != rec['input']:\n"
                        "    print('X not the recorded input'); sys.exit(1)\n"
                        "sys.stdout.write(rec['output'])\n")
    stand_in.chmod(0o755)
    check_drops(peers.run_driver("rapier", str(stand_in), drop_scene()), peers.STEP)
    # and another scene is not answered from the recording
    other = peers.run_driver("rapier", str(stand_in), drop_scene().replace(end_time=0.5))
    assert other.status == "not the recorded input"


@pytest.mark.slow
def test_box2d_reads_the_scene():
    src = os.environ.get("MAX2CODE_BOX2D_SRC")
    if not src:
        pytest.skip("no Box2D source: set MAX2CODE_BOX2D_SRC to a Box2D v3 source folder (github.com/erincatto/box2d)")
    check_drops(peers.run_driver("box2d", peers.build_box2d(src, progress=False), drop_scene()), peers.STEP)


@pytest.mark.slow
def test_ours_reads_the_scene_and_a_stop_is_a_status():
    s = drop_scene().replace(frame_rate=60.0)
    run = peers.run_ours(s, "c")
    assert run.status == "ok" and run.simulated == 1.0
    t = next(t for t, st in run.samples if st[1][4] > -1.0 and t > 0.2)
    assert abs(t - math.sqrt(2 * DROP / G)) <= 1.0 / 60.0
    assert peers.judge(s, run.samples).overlap < 1e-6
    # at most 1 event at one instant: the ball, the box and the bouncer land together, and the run stops there,
    # a status, not an error
    stuck = peers.run_ours(s.replace(max_same=1), "c")
    assert stuck.status.startswith("stuck at t = "), stuck.status
    assert stuck.simulated == pytest.approx(math.sqrt(2 * DROP / G), rel=1e-3) and stuck.cpu > 0.0
    assert stuck.samples == []
    # stopped after a CPU budget: the time reached is reported
    cut = peers.run_ours(s.replace(end_time=1e6, frame_rate=1000.0, max_events=10**12), "c", budget=0.5)
    assert cut.status.startswith("unfinished: stopped after 0.5 CPU s at t = "), cut.status
    assert 0.0 < cut.simulated < 1e6 and cut.cpu >= 0.5


@pytest.mark.slow
def test_event_vs_frame_sweep_reports_a_stuck_scene():
    from max2code.reports import event_vs_frame as ev
    s = drop_scene().replace(max_same=1)
    results, _ = ev.sweep(["c"], (peers.STEP,), 5, False, scenes=[("drops", "<drops>", s)])
    row = ev.cpu_table(results, ["c"])[2]
    assert row.startswith("| drops | 1 | 0 (0) | stopped: ") and "the scene is stuck" in row
    assert results[0].frames[0].cpu_per_s > 0.0        # pymunk's free run is still timed


if __name__ == "__main__":
    import sys
    if sys.argv[1:] != ["--record"]:
        sys.exit("usage: python3 tests/commands/test_peers.py --record   (builds the rapier driver, records its output)")
    record_rapier()
    print(f"wrote {RAPIER_RECORDING}")
