"""Preview images, as device code: one thread per pixel casts four rays (a rotated grid, for
anti-aliased edges) of an orthographic camera at one ``wp.Mesh`` of the whole component, and
shades each hit with its face's colour (ambient plus one directional light)."""


import warp as wp

from .cache import cached

SAMPLES = 4  # rays per pixel
AMBIENT = 0.35  # share of a colour lit from nowhere; the light gives the rest


@wp.struct
class Camera:
    """An orthographic camera: rays start on the plane through ``origin`` spanned by ``right`` and
    ``up`` (``pixel`` metres apart) and run along ``forward``; the light shines along ``light``."""

    origin: wp.vec3
    right: wp.vec3
    up: wp.vec3
    forward: wp.vec3
    light: wp.vec3
    pixel: float
    width: int
    height: int


@cached
def render_kernel(samples: int = SAMPLES):
    """render(mesh, colours, camera, pixel_index, rgba_out): ``rgba_out[i]`` = RGBA (0..1, straight
    alpha: the share of the pixel's rays that hit) of pixel ``pixel_index[i]`` (row-major, top row
    first), from ``samples`` rays (1 to 4: the first of the rotated grid's offsets)."""

    @wp.kernel(enable_backward=False, module=f"rswarp_render_{samples}")
    def render(
        # Model:
        mesh: wp.uint64,
        colours: wp.array(dtype=wp.vec3),
        cam: Camera,
        # In:
        pixel_index: wp.array(dtype=wp.int32),
        # Out:
        rgba_out: wp.array(dtype=wp.vec4),
    ):
        i = wp.tid()
        k = pixel_index[i]
        x = float(k % cam.width)
        y = float(k // cam.width)
        colour = wp.vec3(0.0, 0.0, 0.0)
        hits = float(0.0)
        for s in range(wp.static(samples)):
            # rotated-grid offsets within the pixel: (1/8, 3/8), (5/8, 1/8), (7/8, 5/8), (3/8, 7/8)
            ox = wp.where(s == 0, 0.125, wp.where(s == 1, 0.625, wp.where(s == 2, 0.875, 0.375)))
            oy = wp.where(s == 0, 0.375, wp.where(s == 1, 0.125, wp.where(s == 2, 0.625, 0.875)))
            u = (x + ox - 0.5 * float(cam.width)) * cam.pixel
            v = (0.5 * float(cam.height) - y - oy) * cam.pixel
            q = wp.mesh_query_ray(mesh, cam.origin + u * cam.right + v * cam.up, cam.forward, 1.0e9)
            if q.result:
                n = wp.normalize(q.normal)
                if wp.dot(n, cam.forward) > 0.0:  # the side facing the camera, whatever the winding
                    n = -n
                lit = AMBIENT + (1.0 - AMBIENT) * wp.max(-wp.dot(n, cam.light), 0.0)
                colour += colours[q.face] * lit
                hits += 1.0
        if hits > 0.0:
            colour = colour / hits
        rgba_out[i] = wp.vec4(colour[0], colour[1], colour[2], hits / float(wp.static(samples)))

    return render
