"""A simple temporal network of named time points and named constraints, that relaxes
before it refuses (seed 004, section 5).

Time points are nodes of a :class:`networkx.MultiDiGraph`; every constraint
``t_v − t_u ≥ l`` is an edge ``u → v`` of weight ``−l`` (an upper bound ``t_v − t_u ≤ w``
is the edge ``v → u`` of weight ``w``). The shortest distance from :data:`ZERO` to a point
is minus its earliest consistent time; a negative cycle is a set of constraints no timing
satisfies. Weights are whole nanoseconds, so that tight cycles (a preparation that fits
exactly) sum to exactly zero. All-pairs distances come from Floyd–Warshall on a numpy
matrix (the networks of a chunk have tens of points); a conflict is named from a
Bellman–Ford negative cycle over the edges themselves, parallel ones included.

A constraint may be *soft*: it carries :class:`Give`\\ s, the relaxation steps
(:mod:`blackboard.relaxation`) by which its bound may move and how far, in the order they
apply to it (a give is taken back only when those after it on the same constraint are).
:meth:`TemporalNetwork.solve` resolves conflicts with the earliest steps of the relaxation
order first and the latest only as far as needed — a lexicographic minimum, found in two
passes:

1. every give is taken in full; if a negative cycle remains, no relaxation satisfies the
   spec: :class:`TimingConflict` names the constraints of that cycle;
2. going through the steps from the last to the first, each give is taken back as far as
   the network stays consistent: a soft edge ``u → v`` of weight ``w`` may tighten until
   ``w + d(v, u) = 0``, ``d`` the shortest distance from ``v`` back to ``u``. A ``whole``
   give (a discrete choice, such as dropping a repetition) is taken back all or not at all.

What remains taken is reported as :class:`~blackboard.relaxation.Relaxation`\\ s, each with
the constraints of the cycle it keeps from being negative (a constraint of no behaviour,
such as a pause, is relaxed on behalf of the first behaviour on that cycle).

The network knows nothing of gestures or speech: any behaviour's sync points can be
nodes, any rule between them a named constraint.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import networkx as nx
import numpy as np

from blackboard.errors import TimingConflict
from blackboard.relaxation import RELAXATION_ORDER, Relaxation, RelaxationStep

_NS = 1_000_000_000
#: The time point every other one is measured from (time 0 of the clock the network uses).
ZERO = "utterance start"
#: How far a give "without limit" may move a bound, seconds (far beyond any utterance).
UNLIMITED = 10_000.0


@dataclass(frozen=True)
class Give:
    """One way a soft constraint gives: ``step`` moves its bound by up to ``seconds``
    (``math.inf``: without limit). A ``whole`` give is taken all at once and reported as
    ``amount`` ``unit`` (e.g. 1 repetition); otherwise the amount is the seconds moved."""

    step: RelaxationStep
    seconds: float
    whole: bool = False
    amount: float | None = None
    unit: str = "s"


def _ns(seconds: float, name: str = "a time") -> int:
    if math.isnan(seconds) or seconds < -UNLIMITED:
        raise TimingConflict(f"{name}: {seconds} s is not a time the schedule can hold", (name,))
    return int(round(min(seconds, UNLIMITED) * _NS))


class TemporalNetwork:
    """A simple temporal network of named time points and named difference constraints."""

    def __init__(self) -> None:
        self.graph = nx.MultiDiGraph()
        self.graph.add_node(ZERO)
        self._serial = itertools.count()

    def at_least(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None,
                 gives: tuple[Give, ...] = ()) -> None:
        """``t[later] − t[earlier] ≥ gap`` seconds; ``gives`` lower the gap."""
        self._edge(earlier, later, -_ns(gap, name), name, behavior, gives)

    def at_most(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None,
                gives: tuple[Give, ...] = ()) -> None:
        """``t[later] − t[earlier] ≤ gap`` seconds; ``gives`` raise the gap."""
        self._edge(later, earlier, _ns(gap, name), name, behavior, gives)

    def exactly(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None) -> None:
        """``t[later] − t[earlier] = gap`` seconds (hard)."""
        self.at_least(later, earlier, gap, name, behavior)
        self.at_most(later, earlier, gap, name, behavior)

    def _edge(self, u: str, v: str, weight: int, name: str, behavior: str | None, gives: tuple[Give, ...]) -> None:
        for node in (u, v):
            if node not in self.graph:
                self.graph.add_node(node)
                self.graph.add_edge(ZERO, node, weight=0, name=f"{node} is not before the {ZERO}", behavior=None,
                                    gives=[], serial=next(self._serial))
        stages = [[give, _ns(give.seconds), 0] for give in gives if give.seconds > 0]  # give, most ns, ns taken
        self.graph.add_edge(u, v, weight=weight, name=name, behavior=behavior, gives=stages, serial=next(self._serial))

    def solve(self, label: str) -> tuple[dict[str, float], tuple[Relaxation, ...]]:
        """Earliest time of every point (s) and the relaxations taken, in the relaxation order.

        Raises :class:`TimingConflict` naming the constraints of a cycle that no relaxation
        satisfies. Solving changes the network (its soft constraints end relaxed as reported).
        """
        nodes = list(self.graph)
        index = {node: k for k, node in enumerate(nodes)}
        edges = [(index[u], index[v], data) for u, v, data in self.graph.edges(data=True)]
        soft = sorted((e for e in edges if e[2]["gives"]), key=lambda e: e[2]["serial"])
        for _, _, data in soft:
            for stage in data["gives"]:
                _take(data, stage, stage[1])
        distance, before = _all_pairs(len(nodes), edges)
        if np.any(np.diag(distance) < 0):
            cycle = _negative_cycle(nodes, self.graph)
            names = tuple(dict.fromkeys(data["name"] for _, _, data in cycle))
            raise TimingConflict(f"{label}: timing constraints conflict, and no relaxation satisfies them: "
                                 + "; ".join(names), names)
        for step in reversed(RELAXATION_ORDER):
            for u, v, data in soft:
                for k in reversed(range(len(data["gives"]))):
                    stage = data["gives"][k]
                    if stage[0].step is not step or stage[2] == 0:
                        continue
                    if any(later[2] > 0 for later in data["gives"][k + 1:]):
                        break
                    back = min(stage[2], data["weight"] + distance[v, u])
                    if back <= 0 or (stage[0].whole and back < stage[2]):
                        continue
                    _take(data, stage, -int(back))
                    distance, before = _all_pairs(len(nodes), edges)
        times = {node: 0.0 - float(distance[0, k]) / _NS for node, k in index.items()}
        taken = [(u, v, data, stage) for u, v, data in soft for stage in data["gives"] if stage[2] > 0]
        taken.sort(key=lambda t: (t[3][0].step.rank, t[2]["serial"]))
        return times, tuple(self._reported(nodes, u, v, data, stage, before) for u, v, data, stage in taken)

    def _reported(self, nodes: list[str], u: int, v: int, data: dict, stage: list, before: np.ndarray) -> Relaxation:
        """The relaxation ``stage`` of the edge ``u → v``, with the cycle through it that it keeps consistent."""
        path = []
        here = u
        while here != v and before[v, here] >= 0 and len(path) < len(nodes):
            previous = int(before[v, here])
            parallel = self.graph[nodes[previous]][nodes[here]].values()
            path.append(min(parallel, key=lambda e: (e["weight"], e["serial"])))
            here = previous
        cycle = [data] + path[::-1]
        names = tuple(dict.fromkeys(e["name"] for e in cycle))
        behaviors = [e["behavior"] for e in cycle if e["behavior"] is not None]
        give, _, used = stage
        seconds = used / _NS
        amount = give.amount if give.whole and give.amount is not None else seconds
        return Relaxation(behaviors[0] if behaviors else None, give.step, amount, give.unit, data["name"], names, seconds)


def _take(data: dict, stage: list, nanoseconds: int) -> None:
    """Take ``nanoseconds`` more of ``stage``'s give (negative: give them back)."""
    stage[2] += nanoseconds
    data["weight"] += nanoseconds


def _all_pairs(count: int, edges: list[tuple[int, int, dict]]) -> tuple[np.ndarray, np.ndarray]:
    """Floyd–Warshall: shortest distances ``(count, count)`` (ns, float) and, per pair, the
    point before the last on a shortest path (−1 when there is none)."""
    weights = np.full((count, count), np.inf)
    np.fill_diagonal(weights, 0.0)
    for u, v, data in edges:
        weights[u, v] = min(weights[u, v], data["weight"])
    before = np.where(np.isfinite(weights), np.arange(count)[:, None], -1)
    distance = weights
    for k in range(count):
        through = distance[:, k, None] + distance[None, k, :]
        shorter = through < distance
        distance = np.where(shorter, through, distance)
        before = np.where(shorter, before[k][None, :], before)
    return distance, before


def _negative_cycle(nodes: list[str], graph: nx.MultiDiGraph) -> list[tuple[str, str, dict]]:
    """A negative cycle's edges ``(u, v, data)`` by Bellman–Ford from :data:`ZERO`; a cycle in
    the predecessor graph after ``|V|`` rounds is negative (Cormen et al., lemma 24.16)."""
    edges = list(graph.edges(data=True))
    distance: dict[str, float] = dict.fromkeys(nodes, math.inf)
    distance[ZERO] = 0
    parent: dict[str, tuple[str, dict]] = {}
    changed = None
    for _ in range(len(nodes)):
        changed = None
        for u, v, data in edges:
            if distance[u] + data["weight"] < distance[v]:
                distance[v] = distance[u] + data["weight"]
                parent[v] = (u, data)
                changed = v
        if changed is None:
            return []
    node = changed
    for _ in range(len(nodes)):
        node = parent[node][0]
    cycle, here = [], node
    while True:
        previous, data = parent[here]
        cycle.append((previous, here, data))
        here = previous
        if here == node:
            return cycle[::-1]
