"""What ``rswarp check`` and ``rswarp info`` show: a file's problems and verdict, and a plain dict of
a checked file (SI units, snake_case keys) for ``--json`` beside a readable text in the file's own
units."""

from __future__ import annotations

from pathlib import Path

from ..errors import RsxmlError, one_line
from ..geometry.meshes import part_mesh_path
from ..kinematics.loops import loops
from ..rsxml.cell import read_cell
from ..rsxml.documents import Report, check, checked
from ..rsxml.library import DocumentProperties, LibraryCompiler, LibraryResource
from ..rsxml.model import Group, Mechanism, Part, Pose, SmartComponent, iter_parts
from ..rsxml.units import format_number
from ..transforms import matrix_euler_zyx
from .output import Output, Warn, ignore

SHOWN_LOOPS = 20  # loops info describes (each costs a walk of its length); the rest are counted


def _pose(p: Pose | None) -> dict | None:
    return None if p is None else _matrix(p.matrix())


def _matrix(m) -> dict:
    return {"translation": [round(float(v), 12) for v in m[:3, 3]],
            "rotation": [[round(float(v), 12) for v in row] for row in m[:3, :3]]}


def mechanism_dict(mech: Mechanism) -> dict:
    links = []
    for link in mech.links:
        parts = []
        for part, placed in iter_parts(link):
            mesh = part_mesh_path(mech, part)
            parts.append({"name": part.name, "source": part.source, "mesh": str(mesh) if mesh else None,
                          "placement": _matrix(placed)})
        links.append({"name": link.name, "group": isinstance(link, Group), "parts": parts})
    joints = []
    for j in mech.joints:
        lim = mech.limit(j.name)
        joints.append({
            "name": j.name, "type": j.type, "active": j.active, "parent": j.parent, "child": j.child,
            "point1": list(j.point1), "point2": list(j.point2), "axis": [float(v) for v in j.axis],
            "limits": None if lim is None else [lim.min, lim.max],
        })
    return {
        "kind": "Mechanism", "name": mech.name, "type": mech.type, "model_name": mech.model_name,
        "kinematics_flags": list(mech.kinematics_flags), "length_unit": mech.length_unit or "m",
        "angle_unit": mech.angle_unit or "rad", "motion_control": mech.motion_control,
        "base_link": mech.base_link, "dof": mech.dof, "links": links, "joints": joints,
        "flanges": [{"name": f.name, "link": f.link, "pose": _pose(f.pose)} for f in mech.flanges],
        "base_frame": _pose(mech.base_frame),
        "home_position": None if mech.home is None else list(mech.home),
        "joint_mask": None if mech.joint_mask is None else list(mech.joint_mask),
        "loops": [loop.as_dict() for loop in loops(mech.graph, SHOWN_LOOPS)],
        "loop_count": len(mech.graph.closing),
        "attributes": [{"key": a.key, "value": a.value, "definition": a.definition} for a in mech.attributes],
        "cables": [{
            "name": c.name, "radius": c.radius, "max_segment_length": c.max_segment_length,
            "color": None if c.color is None else list(c.color), "desired_length": c.desired_length,
            "youngs_modulus": c.youngs_modulus,
            "control_points": [{"attached_to": p.attached_to, "position": list(p.position),
                                "direction": None if p.direction is None else p.unit_direction.tolist()}
                               for p in c.control_points],
        } for c in mech.cables],
    }


def smart_component_dict(sc: SmartComponent) -> dict:
    desc = dict(sc.descriptions)
    return {
        "kind": "SmartComponent", "name": sc.name, "description": desc.get(""), "options": dict(sc.options),
        "code_behind": sc.code_behind,
        "properties": [{"name": p.name, "value_type": p.value_type, "value": p.value, "options": dict(p.options),
                        "attributes": dict(p.attributes), "description": desc.get(p.name)} for p in sc.properties],
        "signals": [{"name": s.name, "signal_type": s.signal_type, "options": dict(s.options),
                     "description": desc.get(s.name)} for s in sc.signals],
        "bindings": [{"kind": b.kind, **dict(b.options)} for b in sc.bindings],
        "components": [model_dict(c) for c in sc.components],
        "assets": list(sc.assets),
    }


def _props(p: DocumentProperties) -> dict:
    img = p.image
    return {"title": p.title, "author": p.author, "revision": p.revision,
            "image": None if img is None else {k: getattr(img, k) for k in
                                               ("generate", "source", "zoom", "panx", "pany", "flip")},
            **{k: v for k, v in p.extra}}


def model_dict(model) -> dict:
    if isinstance(model, Mechanism):
        return mechanism_dict(model)
    if isinstance(model, SmartComponent):
        return smart_component_dict(model)
    if isinstance(model, (Part, Group)):
        return {"kind": type(model).__name__, "name": model.name,
                "parts": [{"name": p.name, "source": p.source} for p, _ in iter_parts(model)]}
    if isinstance(model, LibraryCompiler):
        return {"kind": "LibraryCompiler", "defaults": _props(model.defaults), "libraries": [{
            "file_name": e.file_name, "source": e.source, "source_path": e.source_path,
            "properties": _props(e.properties),
            "variants": [{"name": v.name, **dict(v.options), "properties": _props(v.properties)} for v in e.variants],
            "component": None if e.component is None else model_dict(e.component),
        } for e in model.libraries]}
    if isinstance(model, LibraryResource):
        def entry(e):
            return {"kind": e.kind, "name": e.name, "description": e.description,
                    "children": [entry(c) for c in e.children]}
        return {"kind": "LibraryResource", "language": model.language, "entries": [entry(e) for e in model.entries]}
    return {"kind": None}


def report_dict(report: Report) -> dict:
    """The whole report: path, model, problems, and the reports of the sources a library builds."""
    return {
        "path": report.path, "kind": report.kind, "ok": report.ok,
        "errors": [_diag(d) for d in report.errors], "warnings": [_diag(d) for d in report.warnings],
        "model": None if report.model is None else model_dict(report.model),
        "sources": [report_dict(c) for c in report.children],
    }


def _diag(d) -> dict:
    return {"file": d.file, "line": d.line, "message": d.message} | ({"repeats": d.repeats} if d.repeats > 1 else {})


# -- text --------------------------------------------------------------------------------------------


def _table(rows: list[list[str]], indent: str = "  ") -> list[str]:
    if not rows:
        return []
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return [indent + "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]


def _rounded(values, factor: float) -> str:
    """SI values in file units to 6 decimals: placements are computed, so their last digits are noise."""
    return "(" + ", ".join(format_number(round(float(v) / factor, 6) * factor, factor) for v in values) + ")"


def mechanism_text(mech: Mechanism) -> list[str]:
    lf = mech.length_factor
    lu, au = mech.length_unit or "m", mech.angle_unit or "rad"

    def vec(v, f=lf):
        return "(" + ", ".join(format_number(x, f) for x in v) + ")"

    out = [f"{mech.name}: {mech.type or 'Mechanism'} '{mech.model_name or '-'}', "
           f"{' '.join(mech.kinematics_flags) or 'no kinematics flags'}, units {lu} and {au}, {mech.dof} axes"]
    if mech.motion_control:
        out.append(f"  motion control: {mech.motion_control}")
    out.append(f"Links ({len(mech.links)}, base {mech.base_link}):")
    rows = [["link", "part", "source", "mesh", f"placed at [{lu}]", f"rotated zyx [{au}]"]]
    for link in mech.links:
        for part, placed in iter_parts(link):
            mesh = part_mesh_path(mech, part)
            rows.append([link.name, part.name, part.source or "-", mesh.name if mesh else "-",
                         _rounded(placed[:3, 3], lf), _rounded(matrix_euler_zyx(placed[:3, :3]), mech.angle_factor)])
    out += _table(rows)
    out.append("Joints:")
    rows = [["joint", "type", "active", "parent -> child", f"axis point1 -> point2 [{lu}]", "min", "max", "home"]]
    home = dict(zip((j.name for j in mech.active_joints), mech.home or ()))
    for j in mech.joints:
        lim, f = mech.limit(j.name), mech.joint_factor(j)
        unit = au if j.revolute else lu
        rows.append([j.name, j.type, "yes" if j.active else "passive", f"{j.parent} -> {j.child}",
                     f"{vec(j.point1)} -> {vec(j.point2)}",
                     f"{format_number(lim.min, f)} {unit}" if lim else "-",
                     f"{format_number(lim.max, f)} {unit}" if lim else "-",
                     format_number(home[j.name], f) if j.name in home else "-"])
    out += _table(rows)
    out += _loops_text(mech)
    if mech.flanges:
        out.append("Flanges:")
        for fl in mech.flanges:
            m = fl.pose.matrix()
            out.append(f"  {fl.name} on {fl.link}: t {vec(m[:3, 3])}, x {vec(m[:3, 0], 1)}, "
                       f"y {vec(m[:3, 1], 1)}, z {vec(m[:3, 2], 1)}")
    if mech.base_frame is not None and not mech.base_frame.is_identity:
        m = mech.base_frame.matrix()
        out.append(f"Base frame: t {vec(m[:3, 3])}, z {vec(m[:3, 2], 1)}")
    if mech.joint_mask is not None:
        out.append("Joint mask: " + ", ".join(map(str, mech.joint_mask)))
    for c in mech.cables:
        extra = []
        if c.desired_length is not None:
            extra.append(f"desired length {format_number(c.desired_length, lf)} {lu}")
        if c.youngs_modulus is not None:
            extra.append(f"Young's modulus {format_number(c.youngs_modulus)} Pa")
        out.append(f"Cable {c.name}: radius {format_number(c.radius, lf)} {lu}, segments <= "
                   f"{format_number(c.max_segment_length, lf)} {lu}"
                   + (f", colour {c.color}" if c.color else "") + "".join(", " + e for e in extra))
        for p in c.control_points:
            out.append(f"  point {vec(p.position)} on {p.attached_to or '(routing only)'}"
                       + (f", direction {vec(p.direction, 1)}" if p.direction else ", free direction"))
    if mech.attributes:
        out.append("Attributes:")
        out += _table([[a.key, a.value, "definition" if a.definition else "instance"] for a in mech.attributes])
    return out


def _loops_text(mech: Mechanism) -> list[str]:
    """Each kinematic loop: the joint that closes it, its kind, its corners and passive joints."""
    if mech.graph.is_tree:
        return []
    out = ["Loops:"]
    for loop in loops(mech.graph, SHOWN_LOOPS):
        corners = ", ".join("+".join(c) for c in loop.corners)
        out.append(f"  closed by {loop.closing.name}: {loop.kind}"
                   + (f", corners {corners}" if corners else f", joints {', '.join(j.name for j in loop.joints)}")
                   + f"; passive {', '.join(j.name for j in loop.passive) or 'none'}")
    more = len(mech.graph.closing) - SHOWN_LOOPS
    return out + ([f"  ... and {more} more loops"] if more > 0 else [])


def smart_component_text(sc: SmartComponent) -> list[str]:
    desc = dict(sc.descriptions)
    out = [f"{sc.name}: SmartComponent" + (f" - {desc['']}" if "" in desc else "")]
    if sc.code_behind:
        out.append(f"  code-behind {sc.code_behind} (named only: it cannot run here)")
    if sc.properties:
        out.append("Properties:")
        out += _table([[p.name, p.value_type or "-", repr(p.value) if p.value is not None else "-",
                        desc.get(p.name, "")] for p in sc.properties])
    if sc.signals:
        out.append("Signals:")
        out += _table([[s.name, s.signal_type or "-", desc.get(s.name, "")] for s in sc.signals])
    if sc.bindings:
        out.append("Bindings:")
        out += [f"  {b.kind} " + " ".join(f"{k}={v}" for k, v in b.options) for b in sc.bindings]
    for c in sc.components:
        out += ["Component:"] + ["  " + line for line in model_text(c)]
    if sc.assets:
        out.append("Assets: " + ", ".join(sc.assets))
    return out


def model_text(model) -> list[str]:
    if isinstance(model, Mechanism):
        return mechanism_text(model)
    if isinstance(model, SmartComponent):
        return smart_component_text(model)
    if isinstance(model, (Part, Group)):
        return [f"{model.name}: {type(model).__name__}"] + [f"  part {p.name}: {p.source or '-'}"
                                                            for p, _ in iter_parts(model)]
    if isinstance(model, LibraryCompiler):
        out = [f"LibraryCompiler: {len(model.libraries)} librar{'y' if len(model.libraries) == 1 else 'ies'}"]
        for e in model.libraries:
            p = e.properties
            out.append(f"  {e.file_name} <- {e.source or '(inline ' + type(e.component).__name__ + ')'}: "
                       f"'{p.title or '-'}', author {p.author or '-'}, revision {p.revision or '-'}")
            for v in e.variants:
                out.append(f"    variant {v.name or '-'}: '{v.properties.title or '-'}'")
            if e.component is not None:
                out += ["    " + line for line in model_text(e.component)]
        return out
    if isinstance(model, LibraryResource):
        out = [f"LibraryResource ({model.language or 'unknown language'}):"]
        for e in model.entries:
            out.append(f"  {e.kind} {e.name}: {e.description or ''}")
            out += [f"    {c.kind} {c.name}: {c.description or ''}" for c in e.children]
        return out
    return []


def report_text(report: Report) -> str:
    lines = [f"{report.path}"] + model_text(report.model)
    for sub in report.children:
        if sub.model is not None:
            lines += ["", f"{Path(sub.path).name}:"] + ["  " + line for line in model_text(sub.model)]
    return "\n".join(lines)


def check_dict(reports: list[Report]) -> dict:
    """``rswarp check --json``: every file's problems."""
    return {"ok": all(r.ok for r in reports), "files": [
        {"path": r.path, "kind": r.kind, "ok": r.ok, "errors": [_diag(d) for d in r.errors],
         "warnings": [_diag(d) for d in r.warnings]} for r in reports]}


def check_verdict(r: Report) -> str:
    """``rswarp check``'s line per file: OK or FAILED, with the counts of problems."""
    ne, nw = (sum(d.repeats for d in found) for found in (r.errors, r.warnings))
    return one_line(f"{r.path}: {'OK' if r.ok else 'FAILED'} ({r.kind}; {ne} error{'s' * (ne != 1)}, "
                    f"{nw} warning{'s' * (nw != 1)})")


def check_any(path: str) -> Report:
    """``check`` of an RSXML or library file, or of a cell file (``.toml``: its RSXML files read
    with it, every problem at its line)."""
    if not str(path).lower().endswith(".toml"):
        return check(path)
    try:
        cell = read_cell(path)
    except RsxmlError as exc:
        return Report(str(path), "Cell", None, tuple(exc.diagnostics))
    return Report(str(path), "Cell", cell, cell.diagnostics)


def run_check(paths: list[str], warn: Warn = ignore, say: Warn = ignore) -> Output:
    """``rswarp check``: each file's problems to ``warn`` and its verdict to ``say``, file by file
    as they are checked (the text is empty: all of it was said); exit 1 when any file has errors."""
    reports = []
    for path in paths:
        reports.append(report := check_any(path))
        for d in report.all_diagnostics:
            warn(str(d))
        say(check_verdict(report))
    return Output(check_dict(reports), "", 0 if all(r.ok for r in reports) else 1)


def run_info(path: str, warn: Warn = ignore) -> Output:
    """``rswarp info``: what a file describes (its warnings to ``warn``); errors raise."""
    if str(path).lower().endswith(".toml"):
        from .cell_info import cell_output

        return cell_output(read_cell(path), warn)
    report = checked(path)
    for d in report.warnings:
        warn(str(d))
    return Output(report_dict(report), report_text(report))
