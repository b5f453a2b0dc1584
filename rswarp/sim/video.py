"""Pictures that move: a robot's links (and its hoses, as tubes) over frames, ray cast by the
previews' Warp kernel (``kernels.render``) with one BVH refitted per frame, a legend drawn on each
frame, written by imageio (GIF, or MP4 through imageio-ffmpeg).

Colours are per face and per frame: the links grey, or red where a frame marks them (a program's
collisions); a hose by its bend radius against the allowed one, or by its wear."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import cleanup_on_terminate, commit, output_error, usual_mode
from ..launch import Launcher, init_warp
from .cable_solver import contact_meshes
from .preview import View, camera

RING = 8  # vertices around a tube
GREY, RED = (0.78, 0.78, 0.80), (0.90, 0.15, 0.12)
BEND_COLOURS = ((0.20, 0.65, 0.30), (0.95, 0.60, 0.10), (0.90, 0.15, 0.12))  # ok, below allowed, below half
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
    """The triangles of every frame: the links' (posed) and the tubes'."""

    def __init__(self, mech, poses: np.ndarray, tubes: list[Tube]):
        meshes = contact_meshes(mech).links
        self.links = [(k, m[0], m[1]) for k, m in enumerate(meshes) if m is not None]
        if not self.links and not tubes:
            raise InputError(f"'{mech.name}' has no mesh to draw")
        self.poses, self.tubes = poses, tubes
        faces, base, self.link_faces = [], 0, []
        for k, v, f in self.links:
            faces.append(f + base)
            self.link_faces.append((k, len(f)))
            base += len(v)
        for tube in tubes:
            faces.append(_tube_faces(tube.points.shape[1] - 1, base))
            base += tube.points.shape[1] * RING
        self.faces = np.concatenate(faces)

    def vertices(self, frame: int) -> np.ndarray:
        out = [v @ self.poses[frame, k, :3, :3].T + self.poses[frame, k, :3, 3] for k, v, _ in self.links]
        out += [_tube_vertices(t.points[frame], t.radius) for t in self.tubes]
        return np.concatenate(out)

    def colours(self, frame: int, marked: set[int]) -> np.ndarray:
        out = [np.tile(RED if k in marked else GREY, (n, 1)) for k, n in self.link_faces]
        out += [np.repeat(t.colours[frame], 2 * RING, axis=0) for t in self.tubes]
        return np.concatenate(out).astype(np.float32)


def render_frames(mech, poses: np.ndarray, tubes: list[Tube], size: int = 512, marked=None, legend=(),
                  device: str = "cpu") -> np.ndarray:
    """(F, size, size, 3) uint8 frames on white: the links at ``poses`` (F, links, 4, 4), the
    tubes, the links in ``marked[f]`` red, and ``legend`` ((colour, text) rows) at the top left."""
    wp = init_warp()
    from ..kernels.render import Camera, render_kernel

    scene = _Scene(mech, poses, tubes)
    frames = len(poses)
    probe = np.concatenate([scene.vertices(f) for f in range(0, frames, max(1, frames // 12))])
    c = camera(probe, View(), size)
    launcher = Launcher(device)
    points = wp.array(scene.vertices(0).astype(np.float32), dtype=wp.vec3, device=launcher.device)
    mesh = wp.Mesh(points=points, indices=wp.array(scene.faces.astype(np.int32).ravel(), dtype=wp.int32,
                                                   device=launcher.device))
    cam = Camera()
    for key in ("origin", "right", "up", "forward", "light"):
        setattr(cam, key, wp.vec3(*(float(x) for x in c[key])))
    cam.pixel, cam.width, cam.height = c["pixel"], size, size
    kernel = render_kernel(SAMPLES)
    launcher.load(kernel)
    pixels = np.arange(size * size, dtype=np.int32)
    rgba = np.empty((size * size, 4), np.float32)
    out = np.empty((frames, size, size, 3), np.uint8)
    for f in range(frames):
        if f:
            points.assign(scene.vertices(f).astype(np.float32))
            mesh.refit()
        colours = wp.array(scene.colours(f, set(marked[f]) if marked is not None else set()), dtype=wp.vec3,
                           device=launcher.device)
        launcher.launch(kernel, size * size, params=[mesh.id, colours, cam], inputs=[pixels], outputs=[rgba])
        alpha = rgba[:, 3:4]
        image = rgba[:, :3] * alpha + (1.0 - alpha)  # on white
        out[f] = np.round(np.clip(image, 0, 1) * 255).astype(np.uint8).reshape(size, size, 3)
    launcher.close()
    if legend:
        _legend(out, legend)
    return out


def _legend(frames: np.ndarray, rows) -> None:
    """Colour swatches and their meaning at the top left of every frame (drawn once, copied)."""
    from PIL import Image, ImageDraw

    height = 14 * len(rows) + 8
    width = min(frames.shape[2], 8 + 14 + max(6 * len(text) for _, text in rows) + 8)
    card = Image.new("RGB", (width, height), (255, 255, 255))
    draw = ImageDraw.Draw(card)
    for i, (colour, text) in enumerate(rows):
        y = 4 + 14 * i
        draw.rectangle([6, y + 2, 16, y + 12], fill=tuple(int(255 * v) for v in colour))
        draw.text((22, y + 1), text, fill=(0, 0, 0))
    patch = np.asarray(card)
    h, w = min(height, frames.shape[1]), min(width, frames.shape[2])
    frames[:, :h, :w] = patch[:h, :w]


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
