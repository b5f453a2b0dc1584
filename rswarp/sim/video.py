"""Pictures that move: a robot's links (and its hoses, as tubes) over frames, ray cast by the
previews' Warp kernel (``kernels.render``) with one BVH refitted per frame, written by imageio
(GIF, or MP4 through imageio-ffmpeg).

Each frame is a band of text at the top (each frame's captions: the time, a program's line; then
the legend) above the scene, framed in the rest, so no text ever covers the robot or its hose. The
scene stands on a floor grid (at the floor's height, else at the robot's lowest point), drawn
where no link or hose is.

Colours are per face and per frame: the links grey, or red where a frame marks them (a program's
collisions); a hose by its bend radius against the allowed one, or by its wear."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from ..errors import InputError
from ..files import cleanup_on_terminate, commit, output_error, usual_mode
from ..launch import Launcher, init_warp
from .cable.solver import contact_meshes
from .preview import MARGIN, View, camera

RING = 8  # vertices around a tube
GREY, RED = (0.78, 0.78, 0.80), (0.90, 0.15, 0.12)
BEND_COLOURS = ((0.20, 0.65, 0.30), (0.95, 0.60, 0.10), (0.90, 0.15, 0.12))  # ok, below allowed, below half
GRID = (0.80, 0.83, 0.88)  # the floor grid's lines
GRID_STEPS = (0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 2.5, 5.0, 10.0)  # m: a grid square's side
SAMPLES = 2  # rays per pixel: half the previews' four, for the frame rate
FORMATS = (".gif", ".mp4")


@dataclass(frozen=True)
class Tube:
    """A hose over frames: ``points`` (F, n + 1, 3) its centreline, ``colours`` (F, n, 3) per
    segment, its radius (m)."""

    points: np.ndarray
    colours: np.ndarray
    radius: float


def check_video_path(path: str | Path, made: Path | None = None) -> Path:
    """``path`` if a video can be written there: a .gif or .mp4 name in a folder that exists (or is
    ``made``, the run's own output folder)."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise InputError(f"--video {path}: name a .gif or .mp4 file")
    if path.is_dir():
        raise InputError(f"--video {path}: is a folder; name a .gif or .mp4 file")
    folder = path.parent if str(path.parent) else Path(".")
    if made is not None and folder.resolve() == Path(made).resolve():
        return path
    if not folder.is_dir():
        what = "is a file, not a folder" if folder.exists() else "does not exist"
        raise InputError(f"--video {path}: {folder} {what}")
    return path


def bend_colours(points: np.ndarray, allowed: float) -> np.ndarray:
    """(F, n, 3) per segment: green at or above the allowed bend radius, orange below it, red
    below half of it (the radius from the turn between neighbouring segments)."""
    e = np.diff(points, axis=1)
    length = np.linalg.norm(e, axis=2)
    u = e / np.maximum(length, 1e-12)[..., None]
    turn = np.arccos(np.clip(np.einsum("fni,fni->fn", u[:, :-1], u[:, 1:]), -1.0, 1.0))
    radius = np.full(points.shape[:2], np.inf)  # at each point
    radius[:, 1:-1] = 0.5 * (length[:, :-1] + length[:, 1:]) / np.maximum(turn, 1e-12)
    seg = np.minimum(radius[:, :-1], radius[:, 1:])
    out = np.empty(seg.shape + (3,))
    out[:] = BEND_COLOURS[0]
    out[seg < allowed] = BEND_COLOURS[1]
    out[seg < 0.5 * allowed] = BEND_COLOURS[2]
    return out


def wear_colours(wear: np.ndarray, frames: int) -> np.ndarray:
    """(F, n, 3): each segment's accumulated wear (Archard), light grey to dark red."""
    share = wear / max(float(wear.max()), 1e-30)
    c = np.asarray(GREY)[None] * (1 - share[:, None]) + np.array([0.55, 0.05, 0.05])[None] * share[:, None]
    return np.repeat(c[None], frames, axis=0)


def _tube_faces(n: int, base: int) -> np.ndarray:
    faces = []
    for s in range(n):
        for r in range(RING):
            a, b = base + s * RING + r, base + s * RING + (r + 1) % RING
            c, d = a + RING, b + RING
            faces += [(a, b, d), (a, d, c)]
    return np.array(faces, np.int64).reshape(-1, 3)


def _tube_vertices(points: np.ndarray, radius: float) -> np.ndarray:
    """(n + 1) rings of RING vertices around a centreline, framed by parallel transport."""
    t = np.gradient(points, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1), 1e-12)[:, None]
    helper = np.array([0.0, 0.0, 1.0]) if abs(t[0, 2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    n1 = np.cross(t[0], helper)
    n1 /= np.linalg.norm(n1)
    angles = np.linspace(0, 2 * np.pi, RING, endpoint=False)
    out = np.empty((len(points), RING, 3))
    for i in range(len(points)):
        n1 = n1 - (n1 @ t[i]) * t[i]
        n1 /= max(np.linalg.norm(n1), 1e-12)
        n2 = np.cross(t[i], n1)
        out[i] = points[i] + radius * (np.cos(angles)[:, None] * n1 + np.sin(angles)[:, None] * n2)
    return out.reshape(-1, 3)


class _Scene:
    """The triangles of every frame: the links' and the tool's (posed) and the tubes'."""

    def __init__(self, mech, poses: np.ndarray, tubes: list[Tube], tool=None, extra=()):
        meshes = contact_meshes(mech, tool=tool)
        graph = mech.graph
        self.links = [(graph.links[k], k, m[0], m[1]) for k, m in enumerate(meshes.links) if m is not None]
        self.links += [(name, k, v, f) for name, k, v, f in meshes.tool]
        if not self.links and not tubes:
            raise InputError(f"'{mech.name}' has no mesh to draw")
        self.poses, self.tubes = poses, tubes
        self.extra = [(name, -1 - k, v, f) for k, (name, v, f, _) in enumerate(extra)]
        self.extra_poses = [p for *_, p in extra]  # each (F, 4, 4): a cell's unit links, its meshes
        self.links += self.extra
        faces, base, self.link_faces = [], 0, []
        for name, _, v, f in self.links:
            faces.append(f + base)
            self.link_faces.append((name, len(f)))
            base += len(v)
        for tube in tubes:
            faces.append(_tube_faces(tube.points.shape[1] - 1, base))
            base += tube.points.shape[1] * RING
        self.faces = np.concatenate(faces)

    def vertices(self, frame: int) -> np.ndarray:
        out = [v @ self._pose(frame, k)[:3, :3].T + self._pose(frame, k)[:3, 3] for _, k, v, _ in self.links]
        out += [_tube_vertices(t.points[frame], t.radius) for t in self.tubes]
        return np.concatenate(out)

    def _pose(self, frame: int, k: int) -> np.ndarray:
        return self.poses[frame, k] if k >= 0 else self.extra_poses[-1 - k][frame]

    def colours(self, frame: int, marked: set[str]) -> np.ndarray:
        out = [np.tile(RED if name in marked else GREY, (n, 1)) for name, n in self.link_faces]
        out += [np.repeat(t.colours[frame], 2 * RING, axis=0) for t in self.tubes]
        return np.concatenate(out).astype(np.float32)


def render_frames(mech, poses: np.ndarray, tubes: list[Tube], size: int = 512, marked=None, legend=(),
                  device: str = "cpu", captions: Sequence[str] | None = None, floor: float | None = None,
                  grid: bool = True, length: tuple[float, str] = (1.0, "m"), tool=None,
                  progress: Callable[[int, int], None] | None = None, extra=()) -> np.ndarray:
    """(F, size, size, 3) uint8 frames: the links at ``poses`` (F, links, 4, 4), the ``tool`` on
    the flange (``sim.tool.Tool``), the tubes, ``extra`` bodies ((name, vertices, faces, (F, 4, 4)
    poses): a cell's units and meshes), the bodies named in ``marked[f]`` red, on a floor
    grid at height ``floor`` (m; None: the scene's lowest point; ``grid`` False: on white); above
    the scene a band with ``captions[f]`` (lines of text for frame f) and ``legend`` ((colour,
    text) entries) with the grid's entry after them, its lengths in ``length`` (factor to metres,
    unit name). ``progress(done, total)`` counts frames."""
    wp = init_warp()
    from ..kernels.render import Camera, render_kernel

    scene = _Scene(mech, poses, tubes, tool, extra)
    frames = len(poses)
    if captions is not None and len(captions) != frames:
        raise ValueError(f"{len(captions)} captions for {frames} frames")
    probe = np.concatenate([scene.vertices(f) for f in range(0, frames, max(1, frames // 12))])
    floor_z = float(probe[:, 2].min()) if floor is None else float(floor)
    step = _grid_step(probe)
    if grid:
        probe = np.concatenate([probe, np.column_stack([probe[:, :2], np.full(len(probe), floor_z)])])  # its shadow
        from ..rsxml.units import length_text

        where = "floor at" if floor is not None else "no floor: grid at the lowest point,"
        legend = [*legend, (GRID, f"{where} z = {length_text(floor_z, *length)}, "
                                  f"{length_text(step, *length)} squares")]
    band = Band.of(size, legend, captions)
    width, height = size, size - band.height
    c = scene_camera(probe, width, height)
    launcher = Launcher(device)
    points = wp.array(scene.vertices(0).astype(np.float32), dtype=wp.vec3, device=launcher.device)
    mesh = wp.Mesh(points=points, indices=wp.array(scene.faces.astype(np.int32).ravel(), dtype=wp.int32,
                                                   device=launcher.device))
    cam = Camera()
    for key in ("origin", "right", "up", "forward", "light"):
        setattr(cam, key, wp.vec3(*(float(x) for x in c[key])))
    cam.pixel, cam.width, cam.height = c["pixel"], width, height
    kernel = render_kernel(SAMPLES)
    launcher.load(kernel)
    pixels = np.arange(width * height, dtype=np.int32)
    rgba = np.empty((width * height, 4), np.float32)
    background = floor_grid(c, width, height, floor_z, step, probe) if grid else np.ones((height, width, 3))
    out = np.empty((frames, size, size, 3), np.uint8)
    for f in range(frames):
        if f:
            points.assign(scene.vertices(f).astype(np.float32))
            mesh.refit()
        colours = wp.array(scene.colours(f, set(marked[f]) if marked is not None else set()), dtype=wp.vec3,
                           device=launcher.device)
        launcher.launch(kernel, width * height, params=[mesh.id, colours, cam], inputs=[pixels], outputs=[rgba])
        alpha = rgba[:, 3:4].reshape(height, width, 1)
        image = rgba[:, :3].reshape(height, width, 3) * alpha + background * (1.0 - alpha)  # over the floor
        out[f, band.height:] = np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)
        out[f, :band.height] = band.image(None if captions is None else captions[f])
        if progress is not None:
            progress(f + 1, frames)
    launcher.close()
    return out


def scene_camera(vertices: np.ndarray, width: int, height: int) -> dict:
    """The previews' camera (``preview.camera``) framing ``vertices`` in a ``width`` x ``height``
    image, centred with its margin."""
    c = camera(vertices, View(), min(width, height))
    u, v = vertices @ c["right"], vertices @ c["up"]
    c["pixel"] = float(max(np.ptp(u) / width, np.ptp(v) / height, 1e-9) / (1 - 2 * MARGIN))
    return c


def project(c: dict, width: int, height: int, points: np.ndarray) -> np.ndarray:
    """(N, 2) pixel coordinates (x right, y down; pixel centres at +0.5) of world ``points`` seen
    by the camera ``c`` in a ``width`` x ``height`` image."""
    rel = np.asarray(points, float) - c["origin"]
    return np.column_stack([rel @ c["right"] / c["pixel"] + 0.5 * width, 0.5 * height - rel @ c["up"] / c["pixel"]])


def _grid_step(vertices: np.ndarray) -> float:
    """A grid square's side (m): a round length near a sixth of the scene's widest horizontal span."""
    span = float(max(np.ptp(vertices[:, 0]), np.ptp(vertices[:, 1]), 1e-3))
    return min(GRID_STEPS, key=lambda s: abs(np.log(span / 6 / s)))


def floor_grid(c: dict, width: int, height: int, z: float, step: float, vertices: np.ndarray) -> np.ndarray:
    """(height, width, 3) floats: white, with the lines of a floor grid at height ``z`` (``step``
    apart, one square past the scene's footprint on every side) as the camera ``c`` sees them."""
    from PIL import Image, ImageDraw

    lo = np.floor(vertices[:, :2].min(axis=0) / step) - 1
    hi = np.ceil(vertices[:, :2].max(axis=0) / step) + 1
    image = Image.new("RGB", (width, height), (255, 255, 255))
    draw = ImageDraw.Draw(image)
    ink = tuple(int(round(255 * v)) for v in GRID)
    xs, ys = np.arange(lo[0], hi[0] + 1) * step, np.arange(lo[1], hi[1] + 1) * step
    for a, b in [((x, ys[0]), (x, ys[-1])) for x in xs] + [((xs[0], y), (xs[-1], y)) for y in ys]:
        ends = project(c, width, height, np.array([[*a, z], [*b, z]])) - 0.5  # Pillow's pixel i is centred on i
        draw.line([tuple(ends[0]), tuple(ends[1])], fill=ink, width=1)
    return np.asarray(image, np.float32) / 255.0


def _font(size: int):
    """Pillow's own font at a height that suits a ``size`` frame (its bitmap font without FreeType)."""
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=max(10, size // 40))
    except (ImportError, OSError, TypeError, ValueError):
        return ImageFont.load_default()


@dataclass
class Band:
    """The strip at the top of a ``size`` frame: ``caption_lines`` lines of captions, then the
    legend's entries, flowed left to right, on as many lines as they need. Nothing of the scene is
    drawn in it."""

    size: int
    height: int
    line: int  # pixels a line of text
    caption_lines: int
    legend: object  # the PIL image of the band with the legend drawn and no caption
    font: object

    PAD = 4  # pixels around the text

    @classmethod
    def of(cls, size: int, legend, captions: Sequence[str] | None) -> "Band":
        from PIL import Image, ImageDraw

        font = _font(size)
        ascent, descent = font.getmetrics()
        line = ascent + descent + 2
        lines = max((len(c.split("\n")) for c in captions), default=0) if captions is not None else 0
        places, x, row = [], cls.PAD, 0  # each entry's swatch at (x, row)
        swatch = line - 4
        for colour, text in legend:
            w = swatch + 4 + int(np.ceil(font.getlength(text))) + 3 * cls.PAD
            if x > cls.PAD and x + w > size:
                x, row = cls.PAD, row + 1
            places.append((x, row, colour, text))
            x += w
        rows = row + 1 if legend else 0
        height = min(size // 2, 2 * cls.PAD + line * (lines + rows)) if lines + rows else 0
        card = Image.new("RGB", (size, max(height, 1)), (255, 255, 255))
        draw = ImageDraw.Draw(card)
        for x, row, colour, text in places:
            y = cls.PAD + line * (lines + row)
            draw.rectangle([x, y + 2, x + swatch, y + 2 + swatch - 1], fill=tuple(int(255 * v) for v in colour),
                           outline=(90, 90, 90))
            draw.text((x + swatch + 4, y + 1), _fit(text, font, size - x - swatch - 4), fill=(0, 0, 0), font=font)
        if height:
            draw.line([(0, height - 1), (size, height - 1)], fill=(200, 200, 200))
        return cls(size, height, line, lines, card, font)

    def image(self, caption: str | None) -> np.ndarray:
        """(height, size, 3) uint8: the band with ``caption``'s lines written in it."""
        if not self.height:
            return np.zeros((0, self.size, 3), np.uint8)
        if not caption:
            return np.asarray(self.legend)
        from PIL import ImageDraw

        card = self.legend.copy()
        draw = ImageDraw.Draw(card)
        for i, text in enumerate(caption.split("\n")[:self.caption_lines]):
            draw.text((self.PAD, self.PAD + self.line * i + 1), _fit(text, self.font, self.size - 2 * self.PAD),
                      fill=(0, 0, 0), font=self.font)
        return np.asarray(card)


def _fit(text: str, font, width: float) -> str:
    """``text`` cut (with "...") to ``width`` pixels."""
    if font.getlength(text) <= width:
        return text
    while text and font.getlength(text + "...") > width:
        text = text[:-1]
    return text + "..."


def write_video(path: str | Path, frames: np.ndarray, fps: float) -> None:
    """GIF (looping) or MP4 (H.264 through imageio-ffmpeg) of RGB frames, written beside ``path``
    and renamed into place: Ctrl-C or SIGTERM leaves the earlier file, never half a video."""
    import imageio.v3 as iio

    path = Path(path)
    suffix = path.suffix.lower()
    with cleanup_on_terminate():
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:64]}.", suffix=f".tmp{suffix}",
                                       dir=path.parent if str(path.parent) else ".")
        except OSError as exc:
            raise output_error(path, exc) from None
        os.close(fd)
        try:
            if suffix == ".gif":
                iio.imwrite(tmp, frames, extension=".gif", duration=1000.0 / fps, loop=0)
            else:
                iio.imwrite(tmp, frames, extension=".mp4", fps=fps, codec="libx264", macro_block_size=8)
            usual_mode(tmp)
            commit(tmp, path)
        except OSError as exc:
            raise output_error(path, exc) from None
        finally:
            Path(tmp).unlink(missing_ok=True)
