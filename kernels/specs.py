"""Layouts and tolerances that device code and its host twins share, with no Warp import (reading a
model stays light): the closed forms' spec rows (``Chain.closed_form``) and the rows of loops
solved by damped Newton steps (``Chain.newton_rows``)."""

from __future__ import annotations

import numpy as np

# -- closed forms: one spec per passive joint, [kind, ...], kind 0 for none; its input angle is
# ``Chain.closed_input[k] @ q``
ANGLE, STROKE = 1, 2  # a balance cylinder's pivot angle, or its piston's stroke
FOUR_BAR = 3  # a passive joint of a planar four-bar
SPEC = 12  # the longest spec: the four-bar's [kind, V0..V3 (8), w (3)]
DEAD_TOLERANCE = 1e-5  # four-bar: relative to the coupler's length squared, rounding at a dead point still closes

# -- loops with no closed form: one row per joint of a loop,
# [loop, role, jtype (0 revolute, 1 prismatic), q column, unknown, axis (3), point (3), then for the
# closing joint: the residual rows of the square part as a bit mask, and its determinant at zero]
ROW = 13
PATH_A, PATH_B, CLOSING = 1, 2, 3
STEPS, ITERATIONS, POLISH = 8, 3, 4  # continuation steps, Newton iterations per step, and at the end
FINE_STEPS, FINE_ITERATIONS = 128, 2  # the second pass, for paths that come near a singular pose
MAX_STEP = 0.5  # rad (or m): a Newton step is damped to this length
CLOSURE_TOLERANCE = 1e-5  # residual (m, and unitless for the axis) under which a loop counts as closed
NEAR, SINGULAR = 0.3, 0.05  # the square part's determinant relative to zero's: near a singular pose (a path
# taken again in fine steps), and at one (the configuration is NaN)
MAX_UNKNOWNS = 6  # passive joints one loop may solve for


def square_rows(rows: np.ndarray) -> list[int]:
    """The residual rows of a loop's square part (its closing row's mask)."""
    mask = int(rows[rows[:, 1] == CLOSING][0, 11])
    return [r for r in range(6) if mask >> r & 1]
