import os
import signal
import tempfile
from pathlib import Path

import pytest
from hypothesis import settings

DATA = Path(__file__).parent / "data"

# Property tests are seeded: the same examples on every run, so the suite never goes red at random
# (a new failure is found by changing the code, not by the draw), and no example database is kept.
# RSWARP_EXPLORE=1 draws fresh examples on each run (to look for new failures; add each as an @example).
settings.register_profile("seeded", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False, database=None)
settings.load_profile("explore" if os.environ.get("RSWARP_EXPLORE") else "seeded")

# Ctrl-C as a terminal delivers it: a pytest started ignoring SIGINT (a script's background job,
# nohup) would pass that on to every command the tests start, and rswarp keeps an ignored SIGINT
# ignored (``rswarp.files.note_interrupts``), so the tests of Ctrl-C would see it lost
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

# collision pieces are cached per session, never in the user's ~/.cache
os.environ["RSWARP_CACHE_DIR"] = tempfile.mkdtemp(prefix="rswarp-test-cache-")


@pytest.fixture
def data() -> Path:
    return DATA


@pytest.fixture(scope="session")
def demo_run(tmp_path_factory):
    """``rswarp demo`` run once for the whole session (it takes a minute or more): its folder, its
    exit code and what it printed. Tests that read the demo share this run."""
    import contextlib
    import io

    from rswarp.cli import main

    folder = tmp_path_factory.mktemp("demo")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["demo", "--out", str(folder)])
    return folder, code, printed.getvalue()


@pytest.fixture(scope="session")
def local_ray():
    """One local Ray instance of 2 CPUs for the whole session, shared by every test that asks for
    it (tests/test_ray.py, tests/test_api.py); its workers keep their kernels. Those tests run
    last (``pytest_collection_modifyitems``), so Ray starts once and lives only while they run."""
    ray = pytest.importorskip("ray")
    from rswarp.sim import engine

    engine.connect(engine.Cluster(cpus=2))
    yield
    ray.shutdown()


def pytest_collection_modifyitems(items):
    """The tests on the local Ray instance moved to the end, in their order: one start of Ray."""
    on_ray = [item for item in items if "local_ray" in getattr(item, "fixturenames", ())]
    if on_ray:
        items[:] = [item for item in items if "local_ray" not in getattr(item, "fixturenames", ())] + on_ray
