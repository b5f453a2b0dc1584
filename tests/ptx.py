"""A Warp module compiled to PTX by NVRTC where no GPU is (the CUDA path of a native snippet)."""

from pathlib import Path

import pytest
import warp as wp


def ptx_of(module, out: Path) -> str:
    """The PTX of ``module`` for sm_90; the test skipped where Warp has no CUDA compiler."""
    try:
        built = wp.compile_aot_module(module, device=None, arch=90, module_dir=out, use_ptx=True)
    except RuntimeError as e:
        if "NVRTC" in str(e) or "CUDA" in str(e):
            pytest.skip(f"no CUDA compiler here: {e}")
        raise
    ptx = [p for p in built if p.suffix == ".ptx"]
    assert ptx, f"no PTX among {built}"
    return ptx[0].read_text()
