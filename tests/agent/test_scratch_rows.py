"""The face and GLB writers read their frames back from a scratch file a run of rows at a
time (:class:`agent.export.staging.ScratchRows`), each run mapped on its own: the rows as
written, for every run of rows and both widths of number."""

from __future__ import annotations

import numpy as np
import pytest

from agent.export.staging import ScratchRows

RNG = np.random.default_rng(7)


@pytest.fixture(params=["<f8", "<f4"])
def written(tmp_path, request):
    rows = RNG.normal(size=(1000, 13)).astype(request.param)
    path = tmp_path / "frames.part"
    path.write_bytes(rows.tobytes())
    return ScratchRows(path, *rows.shape, request.param), rows


@pytest.mark.parametrize(("start", "stop"), [(0, 1000), (0, 1), (999, 1000), (512, 700), (900, 5000), (-10, None), (700, 512)])
def test_runs_of_rows_are_the_rows_written(written, start, stop):
    frames, rows = written
    got = np.asarray(frames[start:stop])
    assert got.shape == rows[start:stop].shape
    assert got.dtype == rows.dtype
    assert np.array_equal(got, rows[start:stop])


def test_the_shape_is_the_rows_and_their_width(written):
    frames, rows = written
    assert frames.shape == rows.shape


def test_rows_with_a_step_are_refused(written):
    frames, _ = written
    with pytest.raises(IndexError, match="runs"):
        frames[0:10:2]
