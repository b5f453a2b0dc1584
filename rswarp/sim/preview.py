"""Preview images of a component at its home position (LibraryCompiler's ``Image generate="true"``):
the posed meshes with their colours, the framing, and the Warp ray cast (``rswarp.kernels.render``).

The view is RobotStudio's usual one of a robot: from the front right and a little above, looking
down its base, orthographic. The ``Image`` attributes tune it:

- ``zoom``: percent larger than the framing that fits the component with a 5 % margin (0: fit;
  100: twice as large; -50: half as large);
- ``panx``, ``pany``: percent of the image's width (height) by which the component moves right (up);
- ``flip``: ``true`` views the component from the other side (the camera mirrored across the
  robot's XZ plane, so a robot symmetric about that plane shows as its mirror image).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import numpy as np

from ..errors import MeshError, MeshNotFoundError
from ..geometry.meshes import mesh_color, part_mesh
from ..launch import Launcher, init_warp
from ..rsxml.model import Mechanism

AZIMUTH = math.radians(-55.0)  # where the camera stands, seen from above: front (+X), to the right (-Y)
ELEVATION = math.radians(25.0)
MARGIN = 0.05  # of the image, each side, around the fitted component
FLIP_TRUE = frozenset({"true", "1", "yes", "x", "horizontal"})
FLIP_FALSE = frozenset({"", "false", "0", "no", "none"})


@dataclass(frozen=True)
class View:
    """The framing options of ``Image`` (see the module's docstring)."""

    zoom: float = 0.0
    panx: float = 0.0
    pany: float = 0.0
    flip: bool = False

    @classmethod
    def of(cls, image) -> "View":
        """The view an ``Image`` asks for; ValueError for a flip that means nothing."""
        flip = (image.flip or "").strip().lower()
        if flip not in FLIP_TRUE | FLIP_FALSE:
            raise ValueError(f"Image flip='{image.flip}' is not one of true or false")
        return cls(zoom=image.zoom or 0.0, panx=image.panx or 0.0, pany=image.pany or 0.0, flip=flip in FLIP_TRUE)


@dataclass(frozen=True)
class Scene:
    """Triangles of the component at home (world, metres) with one colour (0..1) per face, and
    the parts left out: (``'name' (source)``, why)."""

    vertices: np.ndarray
    faces: np.ndarray
    colours: np.ndarray
    missing: tuple[tuple[str, str], ...]


def home_scene(mech: Mechanism, poses: np.ndarray | None) -> Scene:
    """Every part with a mesh, moved by its link's pose (``poses``: (links, 4, 4) in the order of
    ``mech.link_names``; None: the zero position). Cables are left out, as RobotStudio's are."""
    vertices, faces, colours, missing, base = [], [], [], [], 0
    for k, link in enumerate(mech.link_names):
        pose = np.eye(4) if poses is None else poses[k]
        for part, transform in mech.parts(link):
            if not part.source:
                continue
            try:
                mesh = part_mesh(mech, part, transform)
            except (MeshNotFoundError, MeshError) as exc:
                missing.append((f"'{part.name}' ({part.source})", str(exc)))
                continue
            vertices.append(np.asarray(mesh.vertices) @ pose[:3, :3].T + pose[:3, 3])
            faces.append(np.asarray(mesh.faces) + base)
            colours.append(np.tile(mesh_color(mesh), (len(mesh.faces), 1)))
            base += len(mesh.vertices)
    if not faces:
        return Scene(np.zeros((0, 3)), np.zeros((0, 3), np.int64), np.zeros((0, 3)), tuple(missing))
    return Scene(np.concatenate(vertices), np.concatenate(faces), np.concatenate(colours), tuple(missing))


def camera(vertices: np.ndarray, view: View, size: int) -> dict:
    """The orthographic camera that frames ``vertices`` in a ``size`` square image as ``view``
    asks: origin, right, up, forward and light (unit vectors, world), and ``pixel`` (metres)."""
    az = -AZIMUTH if view.flip else AZIMUTH
    eye = np.array([math.cos(ELEVATION) * math.cos(az), math.cos(ELEVATION) * math.sin(az), math.sin(ELEVATION)])
    forward = -eye
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    u, v = vertices @ right, vertices @ up
    extent = max(u.max() - u.min(), v.max() - v.min(), 1e-9)
    pixel = extent / (size * (1 - 2 * MARGIN)) / max(1.0 + view.zoom / 100.0, 0.01)
    centre_u = (u.max() + u.min()) / 2 - view.panx / 100.0 * size * pixel
    centre_v = (v.max() + v.min()) / 2 - view.pany / 100.0 * size * pixel
    depth = vertices @ forward
    origin = centre_u * right + centre_v * up + (depth.min() - extent) * forward
    light = forward + 0.6 * right - 0.8 * up  # from behind the viewer's left shoulder, above
    return {"origin": origin, "right": right, "up": up, "forward": forward, "light": light / np.linalg.norm(light),
            "pixel": float(pixel)}


def render(scene: Scene, view: View, size: int = 512, device: str = "cpu", threads: int | None = None) -> np.ndarray:
    """The (size, size, 4) RGBA uint8 image of ``scene``; transparent where nothing is."""
    wp = init_warp()
    from ..kernels.render import Camera, render_kernel

    if len(scene.faces) == 0:
        raise ValueError("there is no mesh to render")
    launcher = Launcher(device, threads=threads)
    mesh = wp.Mesh(points=wp.array(scene.vertices.astype(np.float32), dtype=wp.vec3, device=launcher.device),
                   indices=wp.array(scene.faces.astype(np.int32).ravel(), dtype=wp.int32, device=launcher.device))
    colours = wp.array(np.asarray(scene.colours, np.float32), dtype=wp.vec3, device=launcher.device)
    cam, c = Camera(), camera(scene.vertices, view, size)
    for key in ("origin", "right", "up", "forward", "light"):
        setattr(cam, key, wp.vec3(*(float(x) for x in c[key])))
    cam.pixel, cam.width, cam.height = c["pixel"], size, size
    kernel = render_kernel()
    launcher.load(kernel)
    out = np.empty((size * size, 4), np.float32)
    launcher.launch(kernel, size * size, params=[mesh.id, colours, cam],
                    inputs=[np.arange(size * size, dtype=np.int32)], outputs=[out])
    launcher.close()
    return np.round(np.clip(out, 0.0, 1.0) * 255.0).astype(np.uint8).reshape(size, size, 4)


def png(image: np.ndarray) -> bytes:
    """PNG bytes of an RGBA image (no timestamps: the same image gives the same bytes)."""
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(image, "RGBA").save(buf, format="PNG", optimize=False)
    return buf.getvalue()
