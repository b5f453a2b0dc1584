"""Values a device function starts a variable from. Warp 1.19 makes ``wp.float64(NAME)`` of a
module constant the constant's own variable: a dynamic loop that then updates a variable started
so updates every later ``NAME`` of the same function too (a ``bound = F64(BIG)`` after such a loop
read the loop's least). ``fresh`` starts it as a value of its own; ``tests/test_kernel_constants.py``
finds any kernel that starts a loop's variable straight from a constant's constructor."""

from typing import Any

import warp as wp


@wp.func
def fresh(x: Any):
    """``x`` as a new variable, never a module constant's own."""
    return x
