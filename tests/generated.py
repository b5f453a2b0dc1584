"""Input files made at test time (large or hostile ones never live in the repository)."""

from __future__ import annotations

NS = "urn:abb-robotics-robotstudio-graphiccomponent"


def mechanism(joints: int = 1, *, closing: int = 0, point: str = "0,0,{z}", t: str = "0,0,10",
              limits: tuple[str, str] = ("-90", "90"), active: bool = True, extra: str = "",
              part_source: str | None = None, units: str = 'lengthUnit="mm" angleUnit="deg"') -> str:
    """A serial chain L0-L1-...-Ln (Rotational joints about x, one per link), optional closing
    passive joints from L0 to each link, and a flange on the last link."""
    src = f' source="{part_source}"' if part_source else ""
    lines = [f'<Mechanism xmlns="{NS}" type="Other" name="Chain" {units}>', '<Links baseLink="L0">']
    lines += [f'<Part name="L{i}"{src if i == 1 else ""}/>' for i in range(joints + 1)]
    lines.append("</Links><Joints>")
    lines += [f'<Joint name="J{i}" parent="L{i}" child="L{i + 1}" type="Rotational" active="{str(active).lower()}" '
              f'point1="{point.format(z=i)}" point2="1,0,{i}"/>' for i in range(joints)]
    lines += [f'<Joint name="C{i}" parent="L0" child="L{i + 1}" type="Rotational" active="false" '
              f'point1="0,0,{i}" point2="1,0,{i}"/>' for i in range(closing)]
    lines.append("</Joints><Limits>")
    lines += [f'<Limit joint="J{i}" min="{limits[0]}" max="{limits[1]}"/>' for i in range(joints) if active]
    lines.append(f'</Limits><Flanges><Flange name="tool0" link="L{joints}" t="{t}"/></Flanges>{extra}</Mechanism>')
    return "\n".join(lines) + "\n"


def library(sources: list[str], title: str = "T") -> str:
    """A LibraryCompiler file building ``sources``."""
    entries = "".join(f'<Library source="{s}" fileName="f{i}.rslib"><DocumentProperties><Title>{title}</Title>'
                      f"</DocumentProperties></Library>" for i, s in enumerate(sources))
    return f'<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">{entries}</LibraryCompiler>\n'


def torus_ply(path, n: int, m: int, radii: tuple[float, float] = (300.0, 100.0)) -> int:
    """A closed torus of ``2 n m`` triangles written as binary PLY (millimetres); returns that count."""
    import numpy as np

    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n, endpoint=False), np.linspace(0, 2 * np.pi, m, endpoint=False),
                       indexing="ij")
    big, small = radii
    pts = np.stack([(big + small * np.cos(v)) * np.cos(u), (big + small * np.cos(v)) * np.sin(u), small * np.sin(v)],
                   axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b = i * m + j, ((i + 1) % n) * m + j
    c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(pts)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    rows = np.empty(len(faces), dtype=[("k", "u1"), ("f", "<i4", 3)])
    rows["k"], rows["f"] = 3, faces
    with open(path, "wb") as fh:
        fh.write(header.encode())
        fh.write(pts.astype("<f4").tobytes())
        fh.write(rows.tobytes())
    return len(faces)
