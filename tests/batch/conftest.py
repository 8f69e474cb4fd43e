"""Fixtures of the batch tests: a corpus written for them, and a local cluster of two
worker processes shared by the tests that need one (reached as a running scheduler)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import cloudpickle
import dask
import pytest
from batch_helpers import SIGNS, sigml
from distributed import LocalCluster

import batch_helpers
from agent.batch.run import CLUSTER_SETTINGS


@pytest.fixture(scope="session")
def corpus_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("corpus") / "signs.sigml"
    path.write_text(sigml(SIGNS), encoding="utf-8")
    return path


@pytest.fixture(scope="session")
def cluster() -> Iterator[str]:
    """The address of a LocalCluster of two single-threaded worker processes."""
    cloudpickle.register_pickle_by_value(batch_helpers)  # the poisoned renderer travels by value
    with dask.config.set(CLUSTER_SETTINGS), LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0", silence_logs=50) as local:
        yield local.scheduler_address
