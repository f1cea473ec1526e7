#!/usr/bin/env python3
"""Write the README's demo figures from a run of the demo, never by hand.

Runs ``./hawt demo`` for its default duration (into a temporary folder), times it, and replaces the README's
block between the ``<!-- readme_demo: begin -->`` and ``<!-- readme_demo: end -->`` markers with the command, its
wall time and the headline the demo printed. Prints the new block. Exit 1 if the demo fails, prints no headline or
cautions that a run did not go as meant (a contribution lost, a recorder given up: its numbers are not the demo's).

Usage: source scripts/env.sh; python scripts/readme_demo.py [--duration S] [--readme PATH]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from hawt_tools.commands.demo import CAUTION, DEFAULT_DURATION

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- readme_demo: begin -->", "<!-- readme_demo: end -->"
HEADLINE_START = "ipc.mcap against baseline.mcap:"


def headline_of(output: str) -> str:
    """The headline block of the demo's output: from ``ipc.mcap against baseline.mcap:`` through its indented rows.

    Raises
    ------
    ValueError
        If the output has no headline, or cautions that a run did not go as meant (its lines).
    """
    lines = output.splitlines()
    cautioned = [line for line in lines if line.startswith(CAUTION)]
    if cautioned:
        raise ValueError("the demo's runs did not go as meant; the README keeps its block:\n" + "\n".join(cautioned))
    try:
        start = lines.index(HEADLINE_START)
    except ValueError:
        raise ValueError(f"the demo printed no line {HEADLINE_START!r}") from None
    end = start + 1
    while end < len(lines) and lines[end].startswith("  "):
        end += 1
    return "\n".join(lines[start:end])


def demo_block(headline: str, duration: float, wall: float, cores: int) -> str:
    """The README's block: the command, its measured wall time on this machine, and the headline."""
    return (f"{BEGIN}\nMeasured with `./hawt demo --duration {duration:g}` ({wall:.0f} s wall on {cores} cores; written "
            f"by `scripts/readme_demo.py`):\n\n```\n{headline}\n```\n{END}")


def replace_block(readme: str, block: str) -> str:
    """``readme`` with its one demo block replaced by ``block``.

    Raises
    ------
    ValueError
        If the README has not exactly one pair of markers, in order.
    """
    if readme.count(BEGIN) != 1 or readme.count(END) != 1 or readme.index(BEGIN) > readme.index(END):
        raise ValueError(f"the README needs one {BEGIN} ... {END} block")
    return readme[:readme.index(BEGIN)] + block + readme[readme.index(END) + len(END):]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=DEFAULT_DURATION,
                        help=f"simulated seconds of each run (default {DEFAULT_DURATION:g}, the demo's own)")
    parser.add_argument("--readme", type=Path, default=ROOT / "README.md", help="the README to rewrite")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        started = time.monotonic()
        done = subprocess.run([str(ROOT / "hawt"), "demo", "--duration", f"{args.duration:g}", "--output", folder],
                              capture_output=True, text=True)
        wall = time.monotonic() - started
    if done.returncode != 0:
        print(f"readme_demo: ./hawt demo failed (exit {done.returncode}):\n{done.stdout}{done.stderr}", file=sys.stderr)
        return 1
    try:
        block = demo_block(headline_of(done.stdout), args.duration, wall, os.cpu_count() or 1)
        args.readme.write_text(replace_block(args.readme.read_text(), block))
    except ValueError as error:
        print(f"readme_demo: {error}", file=sys.stderr)
        return 1
    print(block)
    return 0


if __name__ == "__main__":
    sys.exit(main())
