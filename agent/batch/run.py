"""Rendering a corpus on Dask: a local cluster of processes, or a running scheduler.

:func:`run_batch` splits the items into chunks of :data:`~agent.batch.items.CHUNK_ITEMS` consecutive items
(fixed by corpus position, so a chunk is the same whatever the number of workers), sends
every chunk with an item still to do to the cluster, and records each finished item in the
manifest's journal as it comes back, under a progress bar. By default the cluster is a
``LocalCluster`` of worker *processes*, one thread each, as many as the machine has cores
(``workers``); with ``scheduler`` the chunks go to a running Dask scheduler at that address
(``tcp://host:8786``), whose workers must see the output folder (a shared file system)
and run the same mura.

One item never stops the batch: :func:`agent.batch.render.render_chunk` turns every
failure of an item into a failed result. Should a worker die with a chunk (killed for
running out of memory, or crashing outright), that chunk is sent again item by item, and
the item whose worker dies alone is recorded as failed with that reason. An interrupted
run (Ctrl-C) stops its workers and keeps every item finished so far: the next run with
the same output folder goes on from there.

When every chunk is back, the driver writes ``manifest.json``, ``report.json`` (totals,
failures and warnings grouped by kind) and ``index.html`` (the corpus viewer), all in
corpus order and without clock times, so a corpus gives the same files on one worker or
many.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import dask
from distributed import Client, LocalCluster, as_completed
from tqdm import tqdm

from agent.batch.items import Corpus, CorpusItem, chunks_of, corpus_title
from agent.batch.manifest import Entry, Journal, entry_of, is_done, read_manifest, write_manifest
from agent.batch.outputs import write_corpus_pages, write_report
from agent.batch.render import FAILED, ItemResult, RenderOptions, render_chunk

#: Seconds a local cluster may take to start its workers.
STARTUP_TIMEOUT = 120.0
#: Dask settings of the local cluster (give a scheduler of your own the same): a task
#: whose worker died is not retried (its items are, one by one), and a worker runs one
#: task per thread, so a death takes no bystander with it.
CLUSTER_SETTINGS = {
    "distributed.scheduler.allowed-failures": 0,
    "distributed.scheduler.worker-saturation": 1.0,
    "distributed.worker.daemon": False,
}

Renderer = Callable[[Sequence[CorpusItem], RenderOptions, str, frozenset[int]], list[ItemResult]]


@dataclass(frozen=True)
class BatchSummary:
    """What a run did: items in the corpus, skipped as already done, rendered and failed
    now, the seconds the run took (``seconds``) and those from the first item sent to the
    last one back (``render_seconds``, without starting the cluster and writing the
    pages), the processor seconds the workers spent meanwhile (``worker_cpu_seconds``)
    and the workers it had."""

    items: int
    skipped: int
    rendered: int
    failed: int
    seconds: float
    workers: int
    render_seconds: float = 0.0
    worker_cpu_seconds: float = 0.0

    @property
    def items_per_second(self) -> float:
        """Items rendered or failed now per second of rendering."""
        done = self.rendered + self.failed
        return done / self.render_seconds if self.render_seconds > 0 else 0.0


def run_batch(
    corpus: Corpus,
    output: str | Path,
    options: RenderOptions,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    renderer: Renderer = render_chunk,
) -> BatchSummary:
    """Render ``corpus`` into ``output`` (module docstring); returns what was done."""
    folder = Path(output)
    folder.mkdir(parents=True, exist_ok=True)
    _remove_stale_parts(folder)
    started = time.perf_counter()
    options_key = options.key()
    recorded = read_manifest(folder)
    done = {item.index for item in corpus.items if is_done(recorded.get(item.name), item, options_key, folder)}
    entries = {item.name: recorded[item.name] for item in corpus.items if item.index in done}
    todo = [chunk for chunk in chunks_of(corpus.items) if any(item.index not in done for item in chunk)]
    remaining = sum(1 for item in corpus.items if item.index not in done)
    journal = Journal(folder)
    count, rendering, cpu = 0, 0.0, 0.0
    try:
        if todo:
            with _client(workers, scheduler) as client:
                count = len(client.scheduler_info().get("workers", {}))
                sent, cpu_before = time.perf_counter(), _workers_cpu(client)
                _render_all(client, todo, done, options, options_key, folder, renderer, journal, entries, progress, remaining)
                rendering, cpu = time.perf_counter() - sent, _workers_cpu(client) - cpu_before
    finally:
        journal.close()
    kept = {name: entry for name, entry in recorded.items() if name not in entries}
    write_manifest(folder, [*entries.values(), *kept.values()], _options_json(options))
    current = [entries[item.name] for item in corpus.items]
    write_report(folder / "report.json", current, corpus.unreadable)
    write_corpus_pages(folder, current, options, corpus_title(corpus))
    rendered_now = sum(entries[item.name].rendered for item in corpus.items if item.index not in done)
    return BatchSummary(len(corpus.items), len(done), rendered_now, remaining - rendered_now, time.perf_counter() - started, count, rendering, cpu)


def _render_all(
    client: Client,
    chunks: list[list[CorpusItem]],
    done: set[int],
    options: RenderOptions,
    options_key: str,
    folder: Path,
    renderer: Renderer,
    journal: Journal,
    entries: dict[str, Entry],
    progress: bool,
    remaining: int,
) -> None:
    by_index = {item.index: item for chunk in chunks for item in chunk}
    bar = tqdm(total=remaining, desc="rendering", unit="item", file=sys.stderr, disable=not progress, smoothing=0.1)
    futures = {}
    for chunk in chunks:
        skip = frozenset(item.index for item in chunk if item.index in done)
        future = client.submit(renderer, chunk, options, str(folder), skip, pure=False)
        futures[future] = chunk
    pending = as_completed(list(futures))
    try:
        for future in pending:
            chunk = futures.pop(future)
            results = _results_of(client, future, chunk, done, options, folder, renderer, futures, pending)
            for result in results:
                entry = entry_of(by_index[result.index], result, options_key)
                entries[entry.name] = entry
                journal.append(entry)
            bar.update(len(results))
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        bar.close()


def _results_of(client, future, chunk, done, options, folder, renderer, futures, pending) -> list[ItemResult]:
    """A chunk's results; a chunk whose worker died is sent again item by item, and a
    single item whose worker died is a failed item."""
    try:
        return future.result()
    except Exception as error:  # noqa: BLE001 - a worker's death (or the task's) is the chunk's, not the batch's
        todo = [item for item in chunk if item.index not in done]
        if len(todo) == 1:
            item = todo[0]
            reason = f"{item.source}: {item.label}: the worker rendering it died ({type(error).__name__}: {error}); out of memory?"
            return [ItemResult(item.index, item.name, FAILED, reason)]
        for item in todo:
            single = client.submit(renderer, [item], options, str(folder), frozenset(), pure=False)
            futures[single] = [item]
            pending.add(single)
        return []


class _client:
    """A Dask client on the scheduler given, or on a local cluster made (and closed) here."""

    def __init__(self, workers: int | None, scheduler: str | None) -> None:
        self.workers = workers or os.cpu_count() or 1
        self.scheduler = scheduler
        self.cluster: LocalCluster | None = None
        self.client: Client | None = None

    def __enter__(self) -> Client:
        with dask.config.set(CLUSTER_SETTINGS):
            if self.scheduler is not None:
                self.client = Client(self.scheduler, timeout=STARTUP_TIMEOUT)
                self.client.wait_for_workers(1, timeout=STARTUP_TIMEOUT)
                return self.client
            # Workers start with Ctrl-C ignored (they inherit it): the driver alone answers it,
            # by stopping them; a worker interrupted on its own would leave the driver waiting.
            previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
            try:
                self.cluster = LocalCluster(
                    n_workers=self.workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                    silence_logs=50, memory_limit="auto",
                )  # fmt: skip
                self.client = Client(self.cluster, timeout=STARTUP_TIMEOUT)
                self.client.wait_for_workers(self.workers, timeout=STARTUP_TIMEOUT)
            finally:
                signal.signal(signal.SIGINT, previous)
        return self.client

    def __exit__(self, *exc: object) -> None:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _workers_cpu(client: Client) -> float:
    """Processor seconds (user and system) the workers' processes have spent so far."""
    return float(sum(client.run(_process_cpu_seconds).values()))


def _process_cpu_seconds() -> float:
    times = os.times()
    return times.user + times.system


def _remove_stale_parts(folder: Path) -> None:
    """Remove the temporary files (``.NAME.….part``) a killed run left in the output folder."""
    for path in folder.glob(".*.part"):
        path.unlink(missing_ok=True)


def _options_json(options: RenderOptions) -> dict:
    fields = asdict(options)
    fields["lexicons"] = list(fields["lexicons"])
    return fields
