"""The finding record: kinds and severities are checked, and its JSON is plain SI data."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rswarp.findings import KINDS, Finding


def test_a_finding_of_an_unknown_kind_or_severity_is_refused():
    with pytest.raises(ValueError, match="unknown kind"):
        Finding("bump", "a bump")
    with pytest.raises(ValueError, match="unknown kind"):
        Finding("collision", "a hit", severity="bad")


def test_its_record_is_json_with_every_field_and_plain_numbers():
    f = Finding("floor", "Link4 12 mm below the floor", "fail", "a.mod", 7, "main", np.float64(1.5), ("Link4",),
                joints=(np.float32(0.5), 0.25), value=np.float64(-0.012), limit=0.0, unit="m", env=np.int64(3),
                at_m=float("nan"))
    record = json.loads(json.dumps(f.record()))
    assert record["t_s"] == 1.5 and record["links"] == ["Link4"] and record["joints"] == [0.5, 0.25]
    assert record["env"] == 3 and record["at_m"] is None and record["advice"] is None
    assert set(record) == {"kind", "text", "severity", "file", "line", "routine", "t_s", "links", "joint", "joints",
                           "value", "limit", "unit", "advice", "cable", "env", "at_m", "chain", "declared"}
    assert record["chain"] == [] and record["declared"] is None
    assert "floor" in KINDS
