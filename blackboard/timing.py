"""A simple temporal network of named time points and named constraints, that relaxes
before it refuses (seed 004, section 5).

Time points are nodes of a :class:`networkx.MultiDiGraph`; every constraint
``t_v − t_u ≥ l`` is an edge ``u → v`` of weight ``−l`` (an upper bound ``t_v − t_u ≤ w``
is the edge ``v → u`` of weight ``w``). Bellman–Ford from :data:`ZERO` then gives minus
the earliest consistent time of every point; a negative cycle is a set of constraints no
timing satisfies. (Bellman–Ford is written out here rather than taken from networkx, so
that a conflict comes back as the exact edges of a negative cycle, parallel ones included.) Weights are whole nanoseconds, so that tight cycles (a preparation that
fits exactly) sum to exactly zero.

A constraint may be *soft*: it carries :class:`Give`\\ s, the relaxation steps
(:mod:`blackboard.relaxation`) by which its bound may move and how far. :meth:`solve`
finds a negative cycle's deficit (how many seconds too much it asks for) and moves the
bound of the soft constraint on the cycle whose next give comes earliest in the
relaxation order — by the deficit, or by all its give, whichever is less (a constraint of
no behaviour, such as a pause, is relaxed on behalf of the first behaviour on the cycle);
a give marked
``whole`` (a discrete choice, such as dropping a repetition) is taken all at once. It
repeats until no cycle is negative, and reports every move as a
:class:`~blackboard.relaxation.Relaxation`. A cycle with nothing left to give is a
conflict: :class:`TimingConflict` names its constraints.

The network knows nothing of gestures or speech: any behaviour's sync points can be
nodes, any rule between them a named constraint.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import networkx as nx

from blackboard.errors import TimingConflict
from blackboard.relaxation import Relaxation, RelaxationStep

_NS = 1_000_000_000
#: The time point every other one is measured from (time 0 of the clock the network uses).
ZERO = "utterance start"
#: More rounds of relaxation than this per constraint means the network does not settle.
_ROUNDS_PER_CONSTRAINT = 20


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


def _ns(seconds: float) -> int:
    return int(round(seconds * _NS))


class TemporalNetwork:
    """A simple temporal network of named time points and named difference constraints."""

    def __init__(self) -> None:
        self.graph = nx.MultiDiGraph()
        self.graph.add_node(ZERO)
        self._serial = itertools.count()

    def at_least(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None,
                 gives: tuple[Give, ...] = ()) -> None:
        """``t[later] − t[earlier] ≥ gap`` seconds; ``gives`` lower the gap."""
        self._edge(earlier, later, -_ns(gap), name, behavior, gives)

    def at_most(self, later: str, earlier: str, gap: float, name: str, behavior: str | None = None,
                gives: tuple[Give, ...] = ()) -> None:
        """``t[later] − t[earlier] ≤ gap`` seconds; ``gives`` raise the gap."""
        self._edge(later, earlier, _ns(gap), name, behavior, gives)

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
        self.graph.add_edge(u, v, weight=weight, name=name, behavior=behavior,
                            gives=[[g, math.inf if math.isinf(g.seconds) else _ns(g.seconds)] for g in gives if g.seconds > 0],
                            serial=next(self._serial))

    def solve(self, label: str) -> tuple[dict[str, float], tuple[Relaxation, ...]]:
        """Earliest time of every point (s) after the relaxations it took, in the order taken.

        Raises :class:`TimingConflict` naming the constraints of a cycle that nothing can relax.
        """
        taken: list[Relaxation] = []
        for _ in range(_ROUNDS_PER_CONSTRAINT * max(1, self.graph.number_of_edges())):
            distances, cycle = self._bellman_ford()
            if cycle is None:
                return {node: -d / _NS for node, d in distances.items() if not math.isinf(d)}, tuple(taken)
            relaxation = self._relax(cycle)
            if relaxation is None:
                names = tuple(dict.fromkeys(data["name"] for _, _, data in cycle))
                tried = "; ".join(f"{r.behavior}: {r.step.value} {r.amount:g} {r.unit}" for r in taken)
                raise TimingConflict(f"{label}: timing constraints conflict: " + "; ".join(names)
                                     + (f" (after relaxing {tried})" if tried else ""), names)
            taken.append(relaxation)
        raise TimingConflict(f"{label}: timing constraints do not settle after {len(taken)} relaxations", ())

    def _bellman_ford(self) -> tuple[dict[str, float], list[tuple[str, str, dict]] | None]:
        """Shortest distances from :data:`ZERO` (ns), or a negative cycle as its edges ``(u, v, data)``.

        A cycle in the predecessor graph after ``|V|`` rounds of relaxation is negative
        (Cormen et al., lemma 24.16), and it names the very parallel edge that binds.
        """
        nodes = list(self.graph)
        edges = list(self.graph.edges(data=True))
        distance: dict[str, float] = dict.fromkeys(nodes, math.inf)
        distance[ZERO] = 0
        parent: dict[str, tuple[str, dict]] = {}
        for _ in range(len(nodes)):
            changed = None
            for u, v, data in edges:
                through = distance[u] + data["weight"]
                if through < distance[v]:
                    distance[v] = through
                    parent[v] = (u, data)
                    changed = v
            if changed is None:
                return distance, None
        node = changed
        for _ in range(len(nodes)):
            node = parent[node][0]
        cycle, here = [], node
        while True:
            previous, data = parent[here]
            cycle.append((previous, here, data))
            here = previous
            if here == node:
                return distance, cycle[::-1]

    def _relax(self, cycle: list[tuple[str, str, dict]]) -> Relaxation | None:
        """Relax the soft constraint of ``cycle`` whose next give comes first in the
        relaxation order; None when nothing on the cycle can give."""
        deficit = -sum(data["weight"] for _, _, data in cycle)
        names = tuple(dict.fromkeys(data["name"] for _, _, data in cycle))
        options = []
        for u, v, data in cycle:
            others = [e["weight"] for e in self.graph[u][v].values() if e is not data]
            room = min(others) - data["weight"] if others else math.inf
            if data["gives"] and room > 0:
                options.append((data["gives"][0][0].step.rank, data["serial"], data, room))
        if not options:
            return None
        _, _, edge, room = min(options, key=lambda option: option[:2])
        give, left = edge["gives"][0]
        delta = left if give.whole else min(deficit, left, room)
        edge["weight"] += delta
        if give.whole or delta >= left:
            edge["gives"].pop(0)
        else:
            edge["gives"][0][1] = left - delta
        seconds = delta / _NS
        amount = give.amount if give.whole and give.amount is not None else seconds
        behaviors = [data["behavior"] for _, _, data in cycle if data["behavior"] is not None]
        behavior = edge["behavior"] if edge["behavior"] is not None else (behaviors[0] if behaviors else None)
        return Relaxation(behavior, give.step, amount, give.unit, edge["name"], names, seconds)
