"""Faults on real graphs: an installed graph launched and recorded, then a node killed or bad commands injected."""
import os
import subprocess
from typing import Iterable, List

import pytest

from hawt_faults.fault_runs import GraphRun, Probe


@pytest.fixture
def launch(hawt_cli, tmp_path):
    """Start a recorded graph: ``launch(graph, namespace, *arguments)`` -> GraphRun; stopped after the test."""
    runs: List[GraphRun] = []

    def start(graph: str, namespace: str, *arguments: str) -> GraphRun:
        bag, output = tmp_path / f"{namespace}.mcap", tmp_path / f"{namespace}.log"
        with output.open("w") as sink:
            launcher = subprocess.Popen([*hawt_cli, "launch", graph, f"namespace:={namespace}", *arguments,
                                         "--record", str(bag)], stdout=sink, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, env=dict(os.environ, PYTHONUNBUFFERED="1"))
        runs.append(GraphRun(launcher, bag, output, namespace))
        return runs[-1]

    yield start
    for run in runs:
        if run.launcher.poll() is None:
            run.interrupt()
            try:
                run.launcher.wait(timeout=30)
            except subprocess.TimeoutExpired:
                run.launcher.kill()
                run.launcher.wait()


@pytest.fixture
def probe():
    """``probe(namespace, harmonics=())`` -> Probe, closed after the test."""
    probes: List[Probe] = []

    def make(namespace: str, harmonics: Iterable[int] = ()) -> Probe:
        probes.append(Probe(namespace, harmonics))
        return probes[-1]

    yield make
    for made in probes:
        made.close()
