"""The subcommands of the ``mura`` command line: their names, in the order ``mura --help``
lists them, and one line each on what they do. The command line imports a command's
module (:mod:`agent.commands`) only when that command runs, so that ``mura --help`` and
the light commands do not wait for the motor's compiled kernels and the plotting and
clustering libraries that the others load."""

from __future__ import annotations

#: Name → the line ``mura --help`` shows for it; each command's module registers its
#: parser with this line (``register(subparsers)``).
SUMMARIES: dict[str, str] = {
    "check": "parse and validate spec files",
    "say": "speak a sentence and show its timings",
    "render": "perform utterances offline and save WAV, BVH, timeline JSON and the avatar page",
    "play": "perform an utterance live with audio and the avatar in a browser page",
    "plot": "draw the wrist paths and speed profiles (Fig. 5) and the chunk timeline (Fig. 6) as PNG",
    "demo": "render the demo utterance (seed 004, Fig. 2) and print the page's address",
    "bench": "measure speed, synchrony and naturalness",
    "sign": "render SiGML/HamNoSys signs to BVH and the corpus viewer",
    "batch": "render a corpus (SiGML collections, folders of utterances) on Dask, resumably",
    "avatar": "build the default skinned avatar, or check a VRM/glTF avatar",
    "serve": "realizer server: perform BML blocks sent over a WebSocket and send BML feedback back",
    "verbs": "indicating verbs: fit models from recordings, render an inflected verb, evaluate the models",
}
