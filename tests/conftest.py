import os
import tempfile
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"

# collision pieces are cached per session, never in the user's ~/.cache
os.environ["RSWARP_CACHE_DIR"] = tempfile.mkdtemp(prefix="rswarp-test-cache-")


@pytest.fixture
def data() -> Path:
    return DATA
