"""A cable's contact in three figures, per environment and over the run, named alike in the text,
``report.json`` and the plots:

- the **peak contact force**: the greatest normal force of any one contact on the hose (anything
  it touched: a link, the floor, the cell, a cable), when and where along it;
- the **worst rub**: of the rubs (per link, mesh of the cell or floor the hose touched: of its
  segments that slid on it, the one pressed hardest), the hardest: that force, what it rubbed on,
  where along the hose and that segment's time in contact, the wear on it in all, and when the
  hose first touched it;
- the **worst wear**: the segment with the most Archard wear (normal force x sliding distance),
  what it wore on most, where along the hose, its time in contact, and when the hose first touched
  that.

A rub's force is its segment's (the greatest total normal force on it, whatever pressed it), so a
segment pressed by two things at once rubs harder than its peak contact force."""

from __future__ import annotations

import numpy as np

from ..sim.cable.results import CableResult, worst_wear


def _f(x) -> float | None:
    return float(x) if np.isfinite(x) else None


def shown_slots(c: CableResult, floor: bool = True) -> list[int]:
    """The slots of ``c`` a report names: all but the floor's in a run with none (``floor`` False)."""
    return [j for j, name in enumerate(c.links) if floor or name != "floor"]


def rubs(c: CableResult, e: int) -> list[dict]:
    """Environment ``e``'s rubs, one per slot the cable touched (other cables aside), in slot order:
    of its segments that slid on it, the one pressed hardest, that force, where along the hose and
    its time in contact; the Archard wear on it in all; when the hose first touched it."""
    out = []
    force = rub_forces(c, e)
    for j, name in enumerate(c.links):
        if not np.isfinite(force[j]):
            continue
        slid = c.wear[e, :, j] > 0
        s = int(np.argmax(np.where(slid, c.wear_peak_normal[e], -1.0))) if slid.any() else None
        out.append({"on": name, "segment": s, "force_N": float(force[j]), "first_touch_s": float(c.contact_time[e, j]),
                    "at_m": float(c.segments[s]) if s is not None else _f(c.contact_at[e, j]),
                    "wear_J": float(c.wear[e, :, j].sum()),
                    "contact_time_s": float(c.wear_contact_time[e, s]) if s is not None else 0.0})
    return out


def rub_forces(c: CableResult, e=slice(None)) -> np.ndarray:
    """(envs, slots), or (slots,) of environment ``e``: each rub's force as ``rubs`` gives it, the
    greatest normal force on a segment that slid on the slot (0: touched, never slid); NaN where
    the cable never touched it, and for other cables."""
    slid = c.wear[e] > 0  # (..., segments, slots)
    peak = np.asarray(c.wear_peak_normal[e])[..., :, None]
    force = np.where(slid, peak, 0.0).max(axis=-2)
    rubbed = np.isfinite(c.contact_time[e]) & (np.asarray(c.links) != "cables")
    return np.where(rubbed, force, np.nan)


def hardest(found: list[dict]) -> dict | None:
    """The rub pressed hardest (the first of equals, as the verdict's worst is)."""
    best = None
    for r in found:
        if best is None or r["force_N"] > best["force_N"]:
            best = r
    return best


def peak_force(c: CableResult, e: int) -> dict | None:
    if not c.peak_normal[e] > 0:
        return None
    return {"force_N": float(c.peak_normal[e]), "time_s": _f(c.peak_normal_time[e]), "at_m": _f(c.peak_normal_at[e]),
            "sliding_speed_m_s": float(c.max_sliding_speed[e])}


def wear_at(c: CableResult, e: int, s: int) -> dict:
    j = int(np.argmax(c.wear[e, s]))
    return {"on": c.links[j], "segment": s, "wear_J": float(c.segment_wear[e, s]),
            "at_m": float(c.segments[s]), "contact_time_s": float(c.wear_contact_time[e, s]),
            "first_touch_s": _f(c.contact_time[e, j])}


def contact(c: CableResult, e: int) -> dict:
    """Environment ``e``'s three figures (None where it has none)."""
    worn = c.segment_wear[e]
    return {"peak_force": peak_force(c, e), "worst_rub": hardest(rubs(c, e)),
            "worst_wear": wear_at(c, e, int(np.argmax(worn))) if np.any(worn > 0) else None}


def run_worst(c: CableResult, done: np.ndarray) -> dict:
    """The run's worst of each figure over the environments ``done`` (those that ran to the end),
    each with its ``environment``; None where none has it."""
    out = {"peak_force": None, "worst_rub": None, "worst_wear": None}
    if len(done):
        e = int(done[np.argmax(c.peak_normal[done])])
        if c.peak_normal[e] > 0:
            out["peak_force"] = {"environment": e, **peak_force(c, e)}
        force = rub_forces(c)[done]
        if np.isfinite(force).any():  # the first of equals in environment, then slot, order: the verdict's
            k, j = np.unravel_index(int(np.argmax(np.where(np.isfinite(force), force, -np.inf))), force.shape)
            e = int(done[k])
            out["worst_rub"] = {"environment": e, **next(r for r in rubs(c, e) if r["on"] == c.links[j])}
        worst = worst_wear(c, done)
        if worst is not None:
            out["worst_wear"] = {"environment": worst[0], **wear_at(c, worst[0], worst[1])}
    return out
