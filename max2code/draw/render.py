"""`max2code render SCENE.json TRACE.jsonl -o OUT`: pictures of a simulation.

* OUT.svg: an animated SVG (SMIL, no script) that plays in a browser, one
  key frame per frame event of the trace (or at --fps), looping; collisions
  flash at their contact points; a clock and a progress bar show the time.
* OUT-overview.png and OUT-overview.svg (matplotlib): every body at the start
  (faint) and at the end (solid), the paths of the centres, and the contact
  points of all collisions coloured by feature or by time.
* with --gif / --png-frames (matplotlib and Pillow): OUT.gif and
  OUT-frames/frame-NNNNN.png.

The bodies' motion comes from max2code/sim/replay.py (exact between events);
this module only samples and draws it.  y points up in every picture.
"""
from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
import os
import sys
from dataclasses import dataclass
from xml.sax.saxutils import escape, quoteattr

from max2code.errors import ArgumentParser, Max2CodeError
from max2code.progress import bar
from max2code.sim.replay import Replay, TraceError, advance, circle_centre_at, load_trace
from max2code.sim.scene import Body, SceneError, load_scene

PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
           "#7f7f7f")
FIXED_FILL, FIXED_EDGE = "#9a9a9a", "#555555"
FEATURE_COLOURS = {"circle-circle": "#d62728", "circle-vertex": "#ff7f0e", "circle-edge": "#1f77b4",
                   "vertex-edge": "#2ca02c"}
DEFAULT_FPS = 30.0
MAX_FLASHES = 2000          # collision flashes in the animated SVG (the strongest impulses when there are more)
FLASH_SECONDS = 0.25        # how long a flash lasts, in scene time
TOP, BOTTOM = 30, 14        # pixels above (title, clock) and below (progress bar) the world in the SVG


class RenderError(Max2CodeError):
    """Bad input to `max2code render` (a missing file, a trace of another scene)."""


def _colour(k: int, b: Body) -> str:
    return FIXED_FILL if b.fixed else PALETTE[k % len(PALETTE)]


# ---------------------------------------------------------------- sampling
def sample_times(rp: Replay, fps: float | None = None) -> list[float]:
    """The key-frame times: 0, every frame event of the trace (or every
    1/fps seconds when fps is given or the trace has none: the scene's own
    frame_rate, else 30), and the end time."""
    end = rp.end_time
    frames = [] if fps else rp.frame_times
    if not frames:
        rate = fps or rp.scene.frame_rate or DEFAULT_FPS
        n = int(math.floor(end * rate + 1e-9))
        frames = [k / rate for k in range(1, n + 1)]
    out = [0.0]
    for t in frames:
        if out[-1] < t <= end:
            out.append(t)
    if out[-1] < end:
        out.append(end)
    return out


def body_extent(rp: Replay, k: int, t: float) -> tuple[float, float, float, float]:
    shape = rp.shape_at(k, t)
    if shape[0] == "polygon":
        xs = [p[0] for p in shape[1]]
        ys = [p[1] for p in shape[1]]
        return min(xs), min(ys), max(xs), max(ys)
    (x, y), r = shape[1], shape[2]
    return x - r, y - r, x + r, y + r


def view_box(rp: Replay, times: list[float]) -> tuple[float, float, float, float]:
    """The smallest box holding every body at every sample time, plus 4 %."""
    x0 = y0 = math.inf
    x1 = y1 = -math.inf
    for k in range(len(rp.scene.bodies)):
        for t in _own_times(rp, k, times):
            a, b, c, d = body_extent(rp, k, t)
            x0, y0, x1, y1 = min(x0, a), min(y0, b), max(x1, c), max(y1, d)
    w, h = x1 - x0, y1 - y0
    pad = 0.04 * max(w, h, 1e-9)
    return x0 - pad, y0 - pad, x1 + pad, y1 + pad


def _own_times(rp: Replay, k: int, times: list[float]) -> list[float]:
    """Sample times that matter for one body: only the start when it never moves."""
    return times if _moves(rp, k) else times[:1]


def _moves(rp: Replay, k: int) -> bool:
    b = rp.scene.bodies[k]
    if len(rp.states[k]) > 1:
        return True
    s = rp.states[k][0]
    turns = s.omega != 0.0 and (b.polygon or b.orbit_radius > 0.0)
    return s.vx != 0.0 or s.vy != 0.0 or b.acceleration != (0.0, 0.0) or turns


def path_points(rp: Replay, k: int, steps: int = 400) -> list[tuple[float, float]]:
    """The path of a body's centre (an orbiting circle: of its circle) from 0
    to the end, exact at every state change; curved pieces (acceleration,
    orbits) are sampled at least every end/steps seconds."""
    b = rp.scene.bodies[k]
    end = rp.end_time
    curved = b.acceleration != (0.0, 0.0) or b.orbit_radius > 0.0
    pts: list[tuple[float, float]] = []
    times = rp.times[k] + [end]
    for i, s in enumerate(rp.states[k]):
        t0, t1 = max(times[i], 0.0), min(times[i + 1], end)
        if t1 < t0 or (t1 == t0 and i + 1 < len(rp.states[k])):
            continue
        n = max(1, math.ceil((t1 - t0) / end * steps)) if curved else 1
        for j in range(n + 1):
            t = t0 + (t1 - t0) * j / n
            st = advance(s, b, t)
            p = circle_centre_at(b, st.px, st.py, st.angle) if not b.polygon else (st.px, st.py)
            if not pts or pts[-1] != p:
                pts.append(p)
    return pts


# ---------------------------------------------------------------- animated SVG
@dataclass
class SvgOptions:
    width: int = 800
    speed: float = 1.0
    flashes: int = MAX_FLASHES


class _Fmt:
    """Numbers rounded to 1/10000 of the view (0.1 mm for a 2 m box)."""

    def __init__(self, size: float):
        self.d = max(0, 4 - math.floor(math.log10(size))) if size > 0 else 6

    def __call__(self, x: float) -> str:
        s = f"{x:.{self.d}f}"
        if "." in s:
            s = s.rstrip("0").rstrip(".")
        return "0" if s in ("-0", "") else s


def _keep(values: list[str]) -> list[int]:
    """Indices to keep so that linear interpolation gives the same picture:
    inside a run of equal values only its two ends matter."""
    n = len(values)
    return [i for i in range(n) if i == 0 or i == n - 1 or values[i] != values[i - 1] or values[i] != values[i + 1]]


def _key_times(times: list[float], end: float) -> list[str]:
    out = []
    for t in times:
        kt = f"{t / end:.6f}".rstrip("0").rstrip(".") if end > 0 else "0"
        out.append(kt or "0")
    out[0], out[-1] = "0", "1"
    return out


def animated_svg(rp: Replay, times: list[float], opts: SvgOptions | None = None, title: str | None = None,
                 progress: bool = False) -> str:
    """The animated SVG of a replay sampled at `times` (0 first, end last)."""
    opts = opts or SvgOptions()
    sc = rp.scene
    end = rp.end_time
    x0, y0, x1, y1 = view_box(rp, times)
    ww, wh = x1 - x0, y1 - y0
    kpx = opts.width / ww                   # pixels per metre
    hpx = max(1, round(wh * kpx))
    height = hpx + TOP + BOTTOM
    f = _Fmt(max(ww, wh))
    dur = f"{_num(end / opts.speed)}s"
    rep = f'dur="{dur}" repeatCount="indefinite"'
    stroke = 1.2 / kpx
    kt_all = _key_times(times, end)
    title = title if title is not None else sc.name

    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{opts.width}" height="{height}" '
           f'viewBox="0 0 {opts.width} {height}" font-family="sans-serif">',
           f"<title>{escape(title)}</title>",
           f'<desc>{escape(f"max2code render: {sc.path}, {len(times)} key frames over {end:g} s")}</desc>',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<g id="world" transform="matrix({_num(kpx)} 0 0 {_num(-kpx)} {_num(-x0 * kpx)} {_num(TOP + y1 * kpx)})" '
           f'stroke-width="{_num(stroke)}" stroke-linejoin="round">']
    n = len(sc.bodies)
    # fixed bodies that do not move first (drawn under everything), then the rest
    order = sorted(range(n), key=lambda k: (_moves(rp, k), k))
    for done, k in enumerate(order, 1):
        b = sc.bodies[k]
        out.extend(_svg_body(rp, k, b, times, kt_all, f, rep))
        if progress and (done == n or done % 8 == 0):
            bar(done, n, "animated SVG: bodies", "max2code render")
    out.extend(_svg_flashes(rp, end, f, rep, kpx, opts.flashes))
    out.append("</g>")
    out.extend(_svg_clock(times, end, opts.width, height, rep, title))
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _num(x: float) -> str:
    return f"{x:.6g}"


def _svg_shape(b: Body, k: int, f: _Fmt) -> str:
    fill = _colour(k, b)
    edge = FIXED_EDGE if b.fixed else "#222222"
    opacity = "" if b.fixed else ' fill-opacity="0.85"'
    name = f' id={quoteattr("b-" + b.name)}'
    if b.polygon:
        pts = " ".join(f"{f(x)},{f(y)}" for x, y in b.vertices)
        return f'<polygon{name} class="body" points="{pts}" fill="{fill}"{opacity} stroke="{edge}"/>'
    cx, cy = (b.orbit_radius * math.cos(b.orbit_angle), b.orbit_radius * math.sin(b.orbit_angle))
    return (f'<circle{name} class="body" cx="{f(cx)}" cy="{f(cy)}" r="{f(b.radius)}" fill="{fill}"{opacity} '
            f'stroke="{edge}"/>')


def _svg_body(rp: Replay, k: int, b: Body, times: list[float], kt_all: list[str], f: _Fmt, rep: str) -> list[str]:
    """One body: its shape in its own frame inside a translated group and,
    when it turns, a rotated one; the groups' transforms are animated."""
    shape = _svg_shape(b, k, f)
    s0 = rp.states[k][0]
    if not _moves(rp, k):
        return [f'<g transform="translate({f(s0.px)} {f(s0.py)}) rotate({_deg(s0.angle)})">{shape}</g>']
    states = [rp.state_at(k, t) for t in times]
    tr = [f"{f(s.px)} {f(s.py)}" for s in states]
    lines = [f'<g transform="translate({tr[0]})">']
    keep = _keep(tr)
    lines.append(f'<animateTransform attributeName="transform" type="translate" '
                 f'values="{";".join(tr[i] for i in keep)}" keyTimes="{";".join(kt_all[i] for i in keep)}" {rep}/>')
    turns = b.polygon or b.orbit_radius > 0.0
    rot = [_deg(s.angle) for s in states] if turns else []
    if turns and len(set(rot)) > 1:
        keep = _keep(rot)
        lines.append(f'<g transform="rotate({rot[0]})">')
        lines.append(f'<animateTransform attributeName="transform" type="rotate" '
                     f'values="{";".join(rot[i] for i in keep)}" keyTimes="{";".join(kt_all[i] for i in keep)}" '
                     f'{rep}/>')
        lines.append(shape)
        lines.append("</g>")
    else:
        lines.append(f'<g transform="rotate({_deg(s0.angle)})">{shape}</g>')
    lines.append("</g>")
    return lines


def _deg(a: float) -> str:
    s = f"{math.degrees(a):.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _svg_flashes(rp: Replay, end: float, f: _Fmt, rep: str, kpx: float, limit: int) -> list[str]:
    """A dot at each contact point that appears at the collision and fades
    over FLASH_SECONDS; past `limit` collisions only the strongest impulses."""
    cols = [e for e in rp.collisions if e.point is not None]
    if len(cols) > limit:
        cols = sorted(sorted(cols, key=lambda e: -abs(e.impulse))[:limit], key=lambda e: e.t)
    if not cols or end <= 0:
        return []
    r = 4.0 / kpx
    out = ['<g id="collisions" stroke="none">']
    for e in cols:
        a = e.t / end
        b = min(1.0, (e.t + FLASH_SECONDS) / end)
        colour = FEATURE_COLOURS.get(e.feature or "", "#000000")
        if a >= 1.0:
            continue
        kt = f"0;{a:.6f};{a:.6f};{b:.6f};1" if b < 1.0 else f"0;{a:.6f};{a:.6f};1"
        vals = "0;0;1;0;0" if b < 1.0 else "0;0;1;0"
        out.append(f'<circle cx="{f(e.point[0])}" cy="{f(e.point[1])}" r="{f(r)}" fill="{colour}" opacity="0">'
                   f'<animate attributeName="opacity" values="{vals}" keyTimes="{kt}" {rep}/></circle>')
    out.append("</g>")
    return out


def _svg_clock(times: list[float], end: float, width: int, height: int, rep: str, title: str) -> list[str]:
    """Title, a clock (one label per key frame, at most ~400, each shown in
    its own slice of the loop) and a progress bar along the bottom."""
    out = [f'<text x="8" y="20" font-size="15" fill="#222">{escape(title)}</text>',
           '<g font-size="14" fill="#222" text-anchor="end" font-variant-numeric="tabular-nums">']
    step = max(1, math.ceil(len(times) / 400))
    shown = times[::step]
    digits = 2 if end >= 1 else 3
    for i, t in enumerate(shown):
        a = t / end if end > 0 else 0.0
        label = f"t = {t:.{digits}f} s"
        if len(shown) == 1:
            out.append(f'<text x="{width - 8}" y="20">{label}</text>')
            continue
        nxt = shown[i + 1] / end if i + 1 < len(shown) else None
        if i == 0:
            anim = f'values="visible;hidden" keyTimes="0;{nxt:.6f}"'
        elif nxt is None:
            anim = f'values="hidden;visible" keyTimes="0;{a:.6f}"'
        else:
            anim = f'values="hidden;visible;hidden" keyTimes="0;{a:.6f};{nxt:.6f}"'
        vis = "visible" if i == 0 else "hidden"
        out.append(f'<text x="{width - 8}" y="20" visibility="{vis}">{label}'
                   f'<animate attributeName="visibility" calcMode="discrete" {anim} {rep}/></text>')
    out.append("</g>")
    y = height - BOTTOM + 5
    out.append(f'<rect x="0" y="{y}" width="{width}" height="5" fill="#e4e4e4"/>')
    out.append(f'<rect x="0" y="{y}" width="0" height="5" fill="#4a7ebb">'
               f'<animate attributeName="width" values="0;{width}" keyTimes="0;1" {rep}/></rect>')
    return out


# ---------------------------------------------------------------- matplotlib pictures
def _pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise RenderError("max2code render: error: the overview and the GIF need matplotlib "
                          "(pip install matplotlib; bash scripts/setup installs it)") from None
    return plt


def _patch(b: Body, k: int, shape, *, alpha: float, faint: bool):
    from matplotlib.patches import Circle, Polygon
    fill = _colour(k, b)
    edge = FIXED_EDGE if b.fixed else ("#999999" if faint else "#222222")
    kw = dict(facecolor=fill, edgecolor=edge, alpha=alpha, linewidth=0.6 if faint else 0.8,
              linestyle="--" if faint else "-", zorder=1 if faint else 2)
    if shape[0] == "polygon":
        return Polygon(shape[1], closed=True, **kw)
    return Circle(shape[1], shape[2], **kw)


def overview(rp: Replay, png: str | None, svg: str | None, *, colour_by: str = "feature",
             times: list[float] | None = None, title: str | None = None) -> None:
    """The still overview: bodies at the start (faint) and at the end
    (solid), the centres' paths, the contact points coloured by feature or
    time."""
    plt = _pyplot()
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D

    sc = rp.scene
    end = rp.end_time
    x0, y0, x1, y1 = view_box(rp, times or sample_times(rp))
    w, h = x1 - x0, y1 - y0
    fw = 8.0
    fh = min(12.0, max(3.0, fw * h / w + 1.0))
    fig, ax = plt.subplots(figsize=(fw, fh))
    try:
        for k, b in enumerate(sc.bodies):
            moving = _moves(rp, k)
            if moving:
                ax.add_patch(_patch(b, k, rp.shape_at(k, 0.0), alpha=0.25, faint=True))
            ax.add_patch(_patch(b, k, rp.shape_at(k, end), alpha=0.8 if not b.fixed else 1.0, faint=False))
        segs, cols = [], []
        for k, b in enumerate(sc.bodies):
            if _moves(rp, k):
                pts = path_points(rp, k)
                if len(pts) > 1:
                    segs.append(pts)
                    cols.append(_colour(k, b))
        if segs:
            ax.add_collection(LineCollection(segs, colors=cols, linewidths=0.9, alpha=0.8, zorder=3))
        collisions = [e for e in rp.collisions if e.point is not None]
        size = 14 if len(collisions) < 300 else (6 if len(collisions) < 3000 else 2)
        marker = "x" if size > 6 else "o"
        many = len(collisions) > 3000        # a raster layer inside the SVG keeps it small
        handles = []
        if collisions:
            xs = [e.point[0] for e in collisions]
            ys = [e.point[1] for e in collisions]
            if colour_by == "time":
                sp = ax.scatter(xs, ys, c=[e.t for e in collisions], cmap="viridis", vmin=0.0, vmax=end, s=size,
                                marker=marker, linewidths=1.0 if marker == "x" else 0.0, zorder=4, rasterized=many)
                fig.colorbar(sp, ax=ax, label="collision time (s)", fraction=0.046, pad=0.03)
            else:
                for feat, colour in FEATURE_COLOURS.items():
                    sel = [e for e in collisions if e.feature == feat]
                    if not sel:
                        continue
                    ax.scatter([e.point[0] for e in sel], [e.point[1] for e in sel], c=colour, s=size,
                               marker=marker, linewidths=1.0 if marker == "x" else 0.0, zorder=4, rasterized=many)
                    handles.append(Line2D([], [], color=colour, marker=marker, linestyle="",
                                          label=f"{feat} ({len(sel)})"))
        if colour_by != "time":
            handles.append(Line2D([], [], color="#444444", linewidth=0.9, label="path of a centre"))
            ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False,
                      title="contacts", title_fontsize=8)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"{title if title is not None else sc.name}: 0 to {end:g} s, {len(collisions)} collisions "
                     "(faint: start, solid: end)", fontsize=10, parse_math=False)     # a name is text, never TeX
        fig.tight_layout()
        if png:
            fig.savefig(png, dpi=150, bbox_inches="tight")
        if svg:
            fig.savefig(svg, dpi=150, bbox_inches="tight")
    finally:
        plt.close(fig)


def frames(rp: Replay, *, gif: str | None, png_dir: str | None, fps: float, width: int = 640,
           progress: bool = False, title: str | None = None) -> int:
    """Draw the scene at 0, 1/fps, 2/fps, ... and the end with matplotlib;
    write each as PNG into png_dir and/or all as a looping GIF.  Returns the
    number of frames."""
    plt = _pyplot()
    from PIL import Image
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Circle, Polygon

    sc = rp.scene
    end = rp.end_time
    times = sample_times(rp, fps)
    x0, y0, x1, y1 = view_box(rp, times)
    w, h = x1 - x0, y1 - y0
    dpi = 100
    fw = width / dpi
    fh = max(1.0, round(fw * h / w * dpi + 30) / dpi)
    fig = plt.figure(figsize=(fw, fh), dpi=dpi)
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0 - 30.0 / (fh * dpi)))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_axis_off()
    fig.text(0.01, 1.0 - 15.0 / (fh * dpi), title if title is not None else sc.name,
             va="center", fontsize=10, parse_math=False)         # a name is text, never TeX
    clock = fig.text(0.99, 1.0 - 15.0 / (fh * dpi), "", va="center", ha="right", fontsize=10, family="monospace")
    patches = []
    for k, b in enumerate(sc.bodies):
        shape = rp.shape_at(k, 0.0)
        kw = dict(facecolor=_colour(k, b), edgecolor=FIXED_EDGE if b.fixed else "#222222", linewidth=0.8,
                  alpha=1.0 if b.fixed else 0.9)
        p = Polygon(shape[1], closed=True, **kw) if shape[0] == "polygon" else Circle(shape[1], shape[2], **kw)
        ax.add_patch(p)
        patches.append((k, p, _moves(rp, k)))
    flash = ax.scatter([], [], s=30, zorder=5)
    cols = sorted((e for e in rp.collisions if e.point is not None), key=lambda e: e.t)
    col_t = [e.t for e in cols]
    images = []
    if png_dir:
        os.makedirs(png_dir, exist_ok=True)
    digits = 2 if end >= 1 else 3
    try:
        for i, t in enumerate(times):
            for k, p, moving in patches:
                if not moving:
                    continue
                shape = rp.shape_at(k, t)
                if shape[0] == "polygon":
                    p.set_xy(shape[1])
                else:
                    p.set_center(shape[1])
            recent = cols[bisect_left(col_t, t - FLASH_SECONDS):bisect_right(col_t, t)]
            if recent:
                flash.set_offsets([e.point for e in recent])
                rgba = [to_rgba(FEATURE_COLOURS.get(e.feature or "", "#000000"),
                                max(0.15, 1.0 - (t - e.t) / FLASH_SECONDS)) for e in recent]
                flash.set_facecolor(rgba)
                flash.set_edgecolor(rgba)
            else:
                flash.set_offsets(_empty_offsets())
            clock.set_text(f"t = {t:.{digits}f} s")
            fig.canvas.draw()
            img = Image.frombuffer("RGBA", fig.canvas.get_width_height(), fig.canvas.buffer_rgba(), "raw",
                                   "RGBA", 0, 1).convert("RGB")
            if png_dir:
                img.save(os.path.join(png_dir, f"frame-{i:05d}.png"))
            if gif:
                images.append(img.quantize(colors=128))
            if progress:
                bar(i + 1, len(times), "frames", "max2code render")
    finally:
        plt.close(fig)
    if gif and images:
        ms = max(20, round(1000.0 / fps / 10.0) * 10)
        images[0].save(gif, save_all=True, append_images=images[1:], duration=ms, loop=0, optimize=False)
    return len(times)


def _empty_offsets():
    import numpy as np
    return np.empty((0, 2))


def have_pillow() -> bool:
    try:
        import PIL
    except ImportError:
        return False
    return bool(PIL.__version__)


# ---------------------------------------------------------------- command
MAX_FRAMES = 100000      # key frames of the SVG, frames of the GIF
MAX_WIDTH = 20000        # pixels


def _out_base(out: str | None, trace: str) -> str:
    if out is None:
        base = trace
        for ext in (".jsonl", ".json"):
            if base.endswith(ext):
                base = base[: -len(ext)]
                break
        return base
    if out.endswith(os.sep) or os.path.isdir(out):
        stem = os.path.basename(trace)
        for ext in (".jsonl", ".json"):
            if stem.endswith(ext):
                stem = stem[: -len(ext)]
                break
        return os.path.join(out, stem)
    for ext in (".svg", ".png", ".gif"):
        if out.endswith(ext):
            return out[: -len(ext)]
    return out


def _size(path: str) -> str:
    n = os.path.getsize(path)
    return f"{n / 1e6:.1f} MB" if n >= 1e6 else f"{n / 1e3:.0f} kB"


def render_main(argv: list[str]) -> int:
    p = ArgumentParser(
        prog="max2code render",
        description="Pictures of a simulation from its scene and the trace 'max2code simulate -o' wrote: "
                    "OUT.svg, an animated SVG that plays in a browser (no script), one key frame per frame "
                    "event of the trace; OUT-overview.png and OUT-overview.svg, a still picture with every body "
                    "at the start (faint) and the end (solid), the paths of the centres and the contact points; "
                    "with --gif and --png-frames also OUT.gif and OUT-frames/frame-NNNNN.png (these need "
                    "matplotlib and Pillow; without Pillow they are skipped with a message).",
        epilog="example: max2code simulate --lang c examples/billiard-break.json -o b.jsonl && "
               "max2code render examples/billiard-break.json b.jsonl -o build/billiard")
    p.add_argument("scene", help="the scene file (JSON) the trace was made from")
    p.add_argument("trace", help="the trace (JSON lines of 'max2code simulate -o')")
    p.add_argument("-o", "--output", metavar="OUT",
                   help="base name of the pictures (a directory: named after the trace; default: the trace's "
                        "name without .jsonl)")
    p.add_argument("--fps", type=float, metavar="F",
                   help="key frames per second of the animation (default: the trace's frame events; without "
                        "them the scene's frame_rate, else 30)")
    p.add_argument("--speed", type=float, default=1.0, metavar="S",
                   help="playback speed of the animated SVG, 1 = real time (default 1)")
    p.add_argument("--width", type=int, default=800, metavar="PX", help="width of the animated SVG (default 800)")
    p.add_argument("--colour-by", "--color-by", choices=("feature", "time"), default="feature",
                   help="colour of the contact points in the overview (default feature)")
    p.add_argument("--no-overview", action="store_true", help="no overview PNG and SVG")
    p.add_argument("--gif", action="store_true", help="also OUT.gif (needs Pillow)")
    p.add_argument("--png-frames", action="store_true", help="also OUT-frames/frame-NNNNN.png (needs Pillow)")
    p.add_argument("--gif-fps", type=float, default=25.0, metavar="F",
                   help="frames per second of the GIF and the PNG frames (default 25)")
    p.add_argument("--gif-width", type=int, default=640, metavar="PX", help="width of the GIF and PNG frames")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    args = p.parse_args(argv)
    for name in ("fps", "speed", "gif_fps"):
        v = getattr(args, name)
        if v is not None and not (math.isfinite(v) and v > 0):
            raise RenderError(f"max2code render: error: --{name.replace('_', '-')} must be a positive number, got {v:g}")
    for name in ("width", "gif_width"):
        if not 16 <= getattr(args, name) <= MAX_WIDTH:
            raise RenderError(f"max2code render: error: --{name.replace('_', '-')} must be from 16 to {MAX_WIDTH} pixels")
    try:
        scene = load_scene(args.scene)
    except SceneError as exc:
        raise RenderError(str(exc)) from None
    rp = load_trace(args.trace, scene)
    for name, rate in (("fps", args.fps), ("gif-fps", args.gif_fps if args.gif or args.png_frames else None)):
        if rate is not None and rate * scene.end_time > MAX_FRAMES:
            raise RenderError(f"max2code render: error: --{name} {rate:g} gives {rate * scene.end_time:.3g} frames for "
                              f"end_time {scene.end_time:g} s of {scene.path}: at most {MAX_FRAMES}")
    base = _out_base(args.output, args.trace)
    folder = os.path.dirname(base)
    if folder:
        try:
            os.makedirs(folder, exist_ok=True)
        except OSError as exc:
            raise RenderError(f"-o {args.output}: error: cannot make the folder {folder}: {exc.strerror}") from None
    progress = not args.quiet
    times = sample_times(rp, args.fps)
    written = []
    svg = animated_svg(rp, times, SvgOptions(width=args.width, speed=args.speed), progress=progress)
    _write(base + ".svg", svg)
    written.append(f"{base}.svg ({len(times)} key frames, {_size(base + '.svg')})")
    if not args.no_overview:
        try:
            overview(rp, base + "-overview.png", base + "-overview.svg", colour_by=args.colour_by, times=times)
        except OSError as exc:
            raise RenderError(f"{base}-overview.png: error: cannot write: {exc.strerror}") from None
        written.append(f"{base}-overview.png ({_size(base + '-overview.png')}) and .svg")
    if args.gif or args.png_frames:
        if not have_pillow():
            print("max2code render: --gif and --png-frames need Pillow, which is not installed: skipped "
                  "(pip install pillow)", file=sys.stderr)
        else:
            try:
                n = frames(rp, gif=base + ".gif" if args.gif else None,
                           png_dir=base + "-frames" if args.png_frames else None,
                           fps=args.gif_fps, width=args.gif_width, progress=progress)
            except OSError as exc:
                raise RenderError(f"{base}: error: cannot write the frames: {exc.strerror}") from None
            if args.gif:
                written.append(f"{base}.gif ({n} frames, {_size(base + '.gif')})")
            if args.png_frames:
                written.append(f"{base}-frames/ ({n} PNG frames)")
    if progress:
        print(f"max2code render: {scene.path} + {args.trace}: {len(rp.collisions)} collisions; wrote "
              + ", ".join(written), file=sys.stderr)
    return 0


def _write(path: str, text: str) -> None:
    try:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    except OSError as exc:
        raise RenderError(f"{path}: error: cannot write: {exc.strerror}") from None


__all__ = ["RenderError", "TraceError", "animated_svg", "overview", "frames", "sample_times", "view_box",
           "path_points", "render_main"]
