"""An assembly expert in the spirit of the seed's agent Max: a short dialogue in which the
agent explains how to build a frame, pointing at parts on the table (deictic gestures by
function) and showing sizes with its hands (iconic gestures by form).

Each turn is one utterance; the agent answers the user's (scripted) questions. Offline it
writes every turn's WAV, BVH, timeline and page; with ``--live`` it speaks and moves live.

    python -m agent.examples.assembly_expert -o out/assembly [--tts espeak] [--live]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from agent.agent import Agent

#: (what the user asks, what the agent answers as an utterance body)
DIALOGUE: tuple[tuple[str, str], ...] = (
    (
        "What do I need first?",
        """<specification>You need <time id="a1"/> this bar <time id="a2" chunkborder="true"/>
        and <time id="a3"/> that one. <time id="a4"/></specification>
        <behaviorspec id="point_bar_1"><gesture><affiliate onset="a1" end="a2"/>
          <function name="refer_to_loc"><param name="refloc" value="$Loc-Bar_1"/></function></gesture></behaviorspec>
        <behaviorspec id="point_bar_2"><gesture scope="left_arm"><affiliate onset="a3" end="a4"/>
          <function name="refer_to_loc"><param name="refloc" value="$Loc-Bar_2"/></function></gesture></behaviorspec>""",
    ),
    (
        "How long should the frame be?",
        """<specification>Make it <time id="b1"/> about this long. <time id="b2"/></specification>
        <behaviorspec id="show_length"><gesture><affiliate onset="b1" end="b2"/>
          <function name="show_size"><param name="size" value="0.35m"/></function></gesture></behaviorspec>""",
    ),
    (
        "And then?",
        """<specification>Then put <time id="c1"/> the bolt <time id="c2" chunkborder="true"/>
        right <time id="c3"/> through the middle. <time id="c4"/></specification>
        <behaviorspec id="point_bolt"><gesture><affiliate onset="c1" end="c2"/>
          <function name="refer_to_loc"><param name="refloc" value="$Loc-Bolt_1"/></function></gesture></behaviorspec>
        <behaviorspec id="push_through"><gesture><affiliate onset="c3" end="c4"/>
          <constraints><parallel>
            <static slot="HandShape" value="BSifinger"/>
            <static slot="ExtFingerOrientation" value="DirA"/>
            <static slot="PalmOrientation" value="PalmD"/>
            <dynamic slot="HandLocation"><segment type="linear">
              <value type="start" name="LocChest LocCCenterRight LocNear"/>
              <value type="direction" name="DirA"/>
              <value type="distance" name="0.15m"/>
            </segment></dynamic>
          </parallel></constraints></gesture></behaviorspec>""",
    ),
)


def utterance(body: str) -> str:
    """A complete MURML document for one turn."""
    return f"<definition><utterance>{body}</utterance></definition>"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-o", "--output", default="out/assembly", help="output folder for the offline files")
    parser.add_argument("--tts", default="fake", help="speech backend: fake, espeak, pyttsx3, default")
    parser.add_argument("--live", action="store_true", help="speak and move live instead of writing files")
    args = parser.parse_args(argv)
    agent = Agent(avatar="max", tts=args.tts)
    for turn, (question, body) in enumerate(DIALOGUE, start=1):
        print(f"user:  {question}")
        xml = utterance(body)
        if args.live:
            agent.say(xml, name=f"turn{turn}").wait()
            continue
        performance = agent.render(xml, name=f"turn{turn}")
        files = performance.save(Path(args.output))
        words = " ".join(chunk["text"] for chunk in performance.timeline["chunks"])
        print(f"agent: {words}   [{performance.duration:.1f} s -> {files.html}]")
    agent.close()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
