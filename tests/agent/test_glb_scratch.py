"""The GLB writer reads its frames back from the scratch file a block of rows at a time
(:class:`agent.export.gltf.ScratchFrames`), each block mapped on its own: the rows as
written, for every run of rows, and no more of the file resident than a block."""

from __future__ import annotations

import numpy as np
import pytest

from agent.export.gltf import ScratchFrames

RNG = np.random.default_rng(7)


@pytest.fixture
def written(tmp_path):
    rows = RNG.normal(size=(1000, 13))
    path = tmp_path / "frames.part"
    path.write_bytes(np.ascontiguousarray(rows, dtype="<f8").tobytes())
    return ScratchFrames(path, *rows.shape), rows


@pytest.mark.parametrize(("start", "stop"), [(0, 1000), (0, 1), (999, 1000), (512, 700), (900, 5000), (-10, None), (700, 512)])
def test_runs_of_rows_are_the_rows_written(written, start, stop):
    frames, rows = written
    got = np.asarray(frames[start:stop])
    assert got.shape == rows[start:stop].shape
    assert np.array_equal(got, rows[start:stop])


def test_the_shape_is_the_frames_and_their_width(written):
    frames, rows = written
    assert frames.shape == rows.shape


def test_rows_with_a_step_are_refused(written):
    frames, _ = written
    with pytest.raises(IndexError, match="runs of rows"):
        frames[0:10:2]
