"""Load campaigns (``hawt campaign``): every case of a campaign file on the in-process engine, on Dask workers.

A case is one controller configuration at one wind-speed bin and seed. Cases run as Dask tasks,
on a local cluster of worker processes (``distributed.LocalCluster``, one thread each) or on an
existing scheduler, each with ``hawt run``'s engine (:mod:`hawt_tools.in_process`), so a case is
the lockstep ROS graph's run bit for bit. The turbulent field of each (speed, seed) is generated
once, by a task every controller's case of that bin and seed waits for (pyconturb, cached on disk by
:func:`hawt_plant.turbulence.cached_turbulence`; workers on other machines without the shared cache
generate the same field again).

Everything a case needs is checked before any wind is generated or worker started (:func:`plan_cases`): each
graph with its arguments (the campaign's turbine among them), its parameters for every speed, and its controllers built
once per controller configuration against the plant's turbine, as every engine configures them (a tuning for another
turbine, say); then the output folders. Each is one line, a :class:`CampaignError`.

Results are stored per case, ``OUTPUT/cases/KEY.json``, written by this (client) process when the
case's task completes, so a case rerun by Dask after a worker died is written once. ``KEY`` hashes
everything that defines the case: the campaign's wind and times, the turbine (a packaged one's name, or the files
of its definition: :func:`turbine_digest`), the graph and the files its parameters read or name, the arguments, and
the code (:func:`code_version`). A rerun of the same
campaign skips the cases already stored (after a Ctrl-C, a failure or a change to one controller).
A case that fails is reported with its error, stored under ``OUTPUT/failed/`` and the others go on.

The per-case numbers are those of ``hawt analyze`` (:func:`hawt_analysis.summary.summarize`) on the
analysed part of the run (after ``transient``): DEL per load channel at 1 Hz equivalent frequency,
extremes, rotor speed, power and pitch activity. Lifetime loads: :mod:`hawt_analysis.lifetime`.
"""
import hashlib
import json
import math
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from hawt_analysis.record import PER_BLADE_CHANNELS, SCALAR_CHANNELS, make_record
from hawt_analysis.summary import load_channels, summarize
from hawt_core.yaml_text import safe_load
from hawt_tools.campaign_file import DLCS, Campaign, CampaignError, ControllerConfig, case_overrides, graph_arguments
from hawt_tools.graph_file import Graph, GraphError, ParameterFile, load_graph

__all__ = ["SCHEDULER_TIMEOUT", "Case", "CampaignRun", "case_graph", "check_scheduler", "code_version", "plan_cases",
           "prepare_wind", "run_case", "run_campaign", "lifetime_table", "ultimate_table", "write_tables",
           "read_lifetime", "read_ultimate", "turbine_digest", "governing_series"]

SCHEDULER_TIMEOUT = 10.0
"""Seconds ``--scheduler`` has to answer (TCP connection, Dask handshake and identity); the client's timeout too."""

_PACKAGES = ("hawt_core", "hawt_plant", "hawt_controllers", "hawt_analysis", "hawt_tools", "hawt_bag", "hawt_node")


@dataclass(frozen=True)
class Case:
    """One run of a campaign: a controller configuration at a wind speed [m/s] and seed, with its key."""

    controller: ControllerConfig
    speed: float
    seed: int
    key: str

    @property
    def label(self) -> str:
        return f"{self.controller.name} at {self.speed:g} m/s, seed {self.seed}"

    @property
    def file_stem(self) -> str:
        return f"{self.controller.name}_{self.speed:g}ms_seed{self.seed}"


def code_version() -> str:
    """Hash of the hawt sources that decide a run's numbers (Python, graph, parameter and model files)."""
    import importlib

    digest = hashlib.sha256()
    for name in _PACKAGES:
        root = Path(importlib.import_module(name).__file__).resolve().parent.parent
        for path in sorted(p for p in root.rglob("*") if p.suffix in (".py", ".yaml", ".npz", ".msg")
                           and "test" not in p.parts):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def case_graph(config: ControllerConfig, campaign: Campaign) -> Graph:
    """The graph every case of ``config`` runs: its file with its arguments and the campaign's turbine."""
    from hawt_tools.graph_file import find_graph
    from hawt_tools.graph_file import package_prefix

    return load_graph(find_graph(config.graph), graph_arguments(campaign, config), package_prefix)


def _overrides(graph: Graph, config: ControllerConfig, campaign: Campaign, speed: float, seed: int):
    from hawt_tools.node_parameters import parse_overrides

    return parse_overrides(graph, case_overrides(campaign, speed, seed) + list(config.parameters))


def _files_digest(graph: Graph) -> str:
    """Hash of the graph file, of every parameter file its nodes read and of every file a parameter's value names
    (a tuning given inline: ``controller_file``, ``linear_models``, ``infile``)."""
    digest = hashlib.sha256(Path(graph.path).read_bytes())
    for spec in graph.nodes:
        for parameters in spec.parameters:
            if isinstance(parameters, ParameterFile):
                digest.update(parameters.path.read_bytes())
                continue
            for _, value in parameters.values:
                if isinstance(value, str) and value and Path(value).is_file():
                    digest.update(value.encode() + Path(value).read_bytes())
    return digest.hexdigest()


def turbine_digest(turbine: str) -> str:
    """What the plant's ``turbine_file`` is made of, for a case's key: a packaged turbine's name (:func:`code_version`
    covers its files), else the hash of its definition file (a folder's ``turbine.yaml``), of the definitions it is ``derived_from`` and
    of its airfoils."""
    from hawt_plant.turbine import PACKAGED_TURBINES

    path = Path(turbine)
    if turbine in PACKAGED_TURBINES or not path.exists():
        return turbine
    definition = path / "turbine.yaml" if path.is_dir() else path
    digest, seen = hashlib.sha256(), []
    while definition.is_file() and definition not in seen:
        seen.append(definition)
        digest.update(definition.read_bytes())
        data = safe_load(definition.read_text())
        base = data.get("derived_from") if isinstance(data, dict) else None
        if not isinstance(base, str):
            break
        definition = definition.parent / base
    for airfoil in sorted((path.parent if path.is_file() else path).glob("airfoils/*.yaml")):
        digest.update(airfoil.name.encode() + airfoil.read_bytes())
    return digest.hexdigest()


def plan_cases(campaign: Campaign) -> List[Case]:
    """Every case of the campaign, controllers outermost, all checked as the module notes say: each graph with its
    parameters for every speed (:func:`hawt_tools.parameter_check.check_graph_parameters`, as ``hawt run`` checks
    them), then its controllers built once against the plant's turbine
    (:func:`hawt_tools.parameter_check.check_against_plant`: the same description as every case's plant, without
    building the plant model or its wind).

    Raises
    ------
    CampaignError
        A graph that cannot be loaded, a parameter it refuses or a core that cannot be built (a tuning for another
        turbine), named with the campaign file, line and controller.
    """
    from hawt_tools.in_process import plant_parameters
    from hawt_tools.parameter_check import check_against_plant, check_graph_parameters

    code = code_version()
    cases = []
    for config in campaign.controllers:
        where = f"{campaign.path}:{config.line}: controllers.{config.name}"
        try:
            graph = case_graph(config, campaign)
            graph.refuse_programs("in one process (hawt run, campaigns)")
            checked = [check_graph_parameters(graph, _overrides(graph, config, campaign, speed, campaign.seeds[0]), {})
                       for speed in campaign.speeds]
            check_against_plant(graph, checked[0])  # the speed changes no controller's values nor the turbine
            files = _files_digest(graph)
            turbine = turbine_digest(plant_parameters(graph, _overrides(graph, config, campaign, campaign.speeds[0],
                                                                        campaign.seeds[0]))["turbine_file"])
        except GraphError as error:
            raise CampaignError(f"{where}: {error}") from None
        for speed in campaign.speeds:
            for seed in campaign.seeds:
                identity = {"speed": speed, "seed": seed, "dlc": campaign.dlc, "duration": campaign.duration,
                            "transient": campaign.transient, "turbulence_class": campaign.turbulence_class,
                            "shear_exponent": campaign.shear_exponent, "turbine": turbine, "graph": files,
                            "arguments": config.arguments, "parameters": config.parameters, "code": code}
                key = hashlib.sha256(json.dumps(identity, sort_keys=True).encode()).hexdigest()[:20]
                cases.append(Case(config, speed, seed, key))
    return cases


def prepare_wind(config: ControllerConfig, campaign: Campaign, speed: float, seed: int) -> str:
    """Generate (or find in the cache) the turbulent field of (speed, seed) on a worker; its plant's description."""
    from hawt_plant.plant_setup import make_plant
    from hawt_tools.in_process import plant_parameters

    graph = case_graph(config, campaign)
    turbine, _, _ = make_plant(plant_parameters(graph, _overrides(graph, config, campaign, speed, seed)))
    return f"{speed:g} m/s seed {seed}: field ready for {turbine.name}"


def run_case(case: Case, campaign: Campaign, bag: Optional[str] = None, wind: Any = None) -> Dict[str, Any]:
    """Run one case in process (on a worker); its row of numbers (module notes). ``wind`` is the `prepare_wind`
    task it waits for. With ``bag``, the whole run (transient included) is written there as `hawt run` would."""
    from hawt_plant.safety_system import TRIP_EVENTS

    start = time.monotonic()
    run, channels, command = _simulate(case, campaign, bag)
    dt = run.description.dt
    trips = [f"{event['kind']} at t={event['step'] * dt:.2f} s" for event in run.events
             if event["level"] >= 40 and event["kind"] in TRIP_EVENTS]
    faults = [f"{fault.describe(run.actuator)} at t={fault.step * dt:.2f} s" for fault in run.faults.faults
              if fault.step < run.step_index]  # the faults that acted: each starts at its step
    return case_row(case, channels, command, dt, time.monotonic() - start, trips, faults)


def _simulate(case: Case, campaign: Campaign, bag: Optional[str] = None) -> Tuple[Any, Dict[str, np.ndarray],
                                                                                np.ndarray]:
    """Step a case in process: the run, the channels of its analysed time and the loop assembler's command there."""
    from hawt_tools.in_process import RunRecord, build_run, write_run

    graph = case_graph(case.controller, campaign)
    run = build_run(graph, _overrides(graph, case.controller, campaign, case.speed, case.seed))
    dt = run.description.dt
    skipped, kept = round(campaign.transient / dt), round(campaign.duration / dt)
    book = RunRecord() if bag else None
    for _ in range(skipped):
        run.step(book)
    first = run.output
    channels = {"time": np.empty(kept)}
    channels.update({name: np.empty(kept) for name in SCALAR_CHANNELS if hasattr(first, name)})
    channels.update({name: np.empty((kept, len(first.pitch))) for name in PER_BLADE_CHANNELS})
    command = np.empty((kept, len(first.pitch)))
    for k in range(kept):
        run.step(book)
        out = run.output
        for name, values in channels.items():
            values[k] = getattr(out, name)
        command[k] = run.previous  # the loop assembler's, as control/pitch_command carries it (not a trip's feather)
    if bag:
        write_run(run, book, Path(bag))
    return run, channels, command


def governing_series(campaign: Campaign, ultimate: Sequence[Mapping[str, Any]]) -> List[Dict[str, Any]]:
    """The time series of each load channel of an ultimate table (:func:`ultimate_table`) in the case that governs
    it, per controller: ``controller``, ``channel``, ``case``, ``time`` [s] and ``values``. The governing cases are run
    again in process (a case is deterministic: its extreme is the table's to the bit); DLC 1.1's extrapolated
    loads have no one case and no series."""
    planned = {(case.controller.name, case.speed, case.seed): case for case in plan_cases(campaign)}
    runs: Dict[Tuple[str, float, int], Dict[str, np.ndarray]] = {}
    series = []
    for entry in ultimate:
        key = (entry["controller"], float(entry.get("wind_speed", math.nan)), int(entry.get("seed", 0)))
        if key not in planned:
            continue
        if key not in runs:
            _, channels, _ = _simulate(planned[key], campaign)
            runs[key] = {"time": channels["time"],
                         **{name: values for name, (values, _) in load_channels(make_record(channels)).items()}}
        series.append({"controller": key[0], "channel": entry["channel"], "case": entry["case"],
                       "time": runs[key]["time"], "values": runs[key][entry["channel"]]})
    return series


def case_row(case: Case, channels: Dict[str, np.ndarray], command: np.ndarray, dt: float,
             wall: float, trips: Sequence[str] = (), faults: Sequence[str] = ()) -> Dict[str, Any]:
    """The numbers of one case: identity, DEL (N·m, 1 Hz) and extremes of every load channel, operation, pitch,
    ``trips`` (the safety system's, each ``kind at t=… s``; empty if none), whose loads are a feathered turbine's,
    and ``faults`` (the injected faults that acted, each ``what at t=… s``)."""
    summary = summarize(channels)
    row: Dict[str, Any] = {"controller": case.controller.name, "wind_speed": case.speed, "seed": case.seed,
                           "key": case.key, "wall_s": wall, "trips": "; ".join(trips), "faults": "; ".join(faults)}
    for name, entry in summary["del"].items():
        row[f"del.{name}"] = entry["value"]
    for name, (values, _) in load_channels(make_record(channels)).items():  # derived channels too
        row[f"max.{name}"], row[f"min.{name}"] = float(values.max()), float(values.min())
    speed = channels["rotor_speed"]
    row.update({"rotor_speed.mean": float(speed.mean()), "rotor_speed.std": float(speed.std()),
                "rotor_speed.max": float(speed.max()),
                "power.mean": float(channels["electrical_power"].mean()),
                "power.std": float(channels["electrical_power"].std()),
                "pitch.travel": summary["pitch"]["travel_rad"]["total"],
                "pitch.duty_cycle": summary["pitch"]["duty_cycle"]["mean"],
                "pitch.max_command_rate": float(np.abs(np.diff(command, axis=0)).max() / dt)})
    row["wohler"] = {name: entry["m"] for name, entry in summary["del"].items()}
    return row


@dataclass
class CampaignRun:
    """What ``run_campaign`` did: the rows of every case done (this run or before) and what failed."""

    rows: List[Dict[str, Any]]
    failed: Dict[str, str]
    skipped: int
    interrupted: bool = False


def _write_json(path: Path, data: Any) -> None:
    """Write atomically: a reader (or a rerun after a crash) never sees half a file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    partial.write_text(json.dumps(data, indent=1))
    os.replace(partial, path)


def _counted(count: int, what: str) -> str:
    """``1 case``, ``2 cases``."""
    return f"{count} {what}" + ("s" if count != 1 else "")


def _duration_text(seconds: float) -> str:
    minutes, seconds = divmod(int(round(seconds)), 60)
    return f"{minutes // 60}:{minutes % 60:02d}:{seconds:02d}"


def measured_speed(case: Case, campaign: Campaign, seconds: float = 2.0) -> float:
    """Real-time factor of ``case``'s graph on this machine, for the campaign's time estimate: ``seconds`` simulated
    in process in steady wind at its speed (its turbulent field may not exist yet), timed after the build."""
    from hawt_tools.in_process import build_run, plant_node

    graph = case_graph(case.controller, campaign)
    overrides = _overrides(graph, case.controller, campaign, case.speed, case.seed)
    overrides.setdefault(plant_node(graph).label, []).append(("wind_type", "steady"))
    run = build_run(graph, overrides)
    steps = max(1, round(seconds / run.description.dt))
    start = time.perf_counter()
    for _ in range(steps):
        run.step()
    return steps * run.description.dt / (time.perf_counter() - start)


def check_scheduler(address: str, timeout: float = SCHEDULER_TIMEOUT) -> None:
    """Refuse ``address`` (CampaignError, one line) unless a Dask scheduler answers there within ``timeout`` [s].

    First a plain TCP connection (refused, unknown host, no answer), then Dask's handshake and an ``identity``
    request under one deadline: distributed bounds only the TCP connection by its timeout, so a listener that
    accepts and never answers (or an HTTP server waiting for a request line) held ``Client`` forever, and one
    that answers something else had its bytes read as frame lengths (a 3.07 EiB allocation).
    """
    import asyncio
    import socket

    from distributed.comm import connect
    from distributed.comm.addressing import get_address_host_port
    from distributed.security import Security

    deadline = time.monotonic() + timeout
    try:
        socket.create_connection(get_address_host_port(address), timeout).close()
    except TimeoutError:
        raise CampaignError(f"--scheduler {address}: no connection within {timeout:g} s") from None
    except OSError as error:
        raise CampaignError(f"--scheduler {address}: cannot connect ({error.strerror or error})") from None

    async def identity():
        comm = await connect(address, timeout=timeout, **Security().get_connection_args("client"))
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    try:
        answer = asyncio.run(asyncio.wait_for(identity(), max(0.0, deadline - time.monotonic())))
    except TimeoutError:
        problem = f"within {timeout:g} s (the port accepts connections but says nothing)"
    except Exception as error:  # whatever distributed's decoder makes of another protocol's bytes
        problem = f"(the port answers in another protocol: Dask's decoder raised {type(error).__name__})"
    else:
        kind = answer.get("type") if isinstance(answer, dict) else None
        if kind == "Scheduler":
            return
        problem = f"(a Dask {kind} answered)" if kind else "(the port answered something else)"
    raise CampaignError(f"--scheduler {address}: no Dask scheduler answered {problem}")


def _client(workers: Optional[int], scheduler: Optional[str]):
    """A Dask client: of ``scheduler`` if given, else of a local cluster of ``workers`` processes."""
    import logging

    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout=SCHEDULER_TIMEOUT), None
        except (OSError, TimeoutError) as error:
            raise CampaignError(f"--scheduler {scheduler}: cannot connect ({error})") from None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def run_campaign(campaign: Campaign, output: Path, workers: Optional[int] = None, scheduler: Optional[str] = None,
                 bags: bool = False, report: Callable[[str], None] = print) -> CampaignRun:
    """Run every case not yet stored under ``output`` (module notes) and return all the rows of the campaign.

    A ``scheduler`` that is no Dask scheduler is refused first (`check_scheduler`), before any work or output.
    ``report`` gets one line per finished or failed case (progress, elapsed time, estimate of what is left).
    A KeyboardInterrupt stops the campaign; what finished is kept (``interrupted`` is set).
    """
    from distributed import as_completed

    if scheduler:
        check_scheduler(scheduler)
    cases = plan_cases(campaign)
    output = Path(output)
    stored = {case.key: output / "cases" / f"{case.key}.json" for case in cases}
    todo = [case for case in cases if not stored[case.key].exists()]
    failed: Dict[str, str] = {}
    interrupted = False
    dlc = DLCS[campaign.dlc]
    fault = "" if not campaign.fault else (f"; fault '{campaign.fault}' at {dlc.fault_time(campaign.transient, 1):g} s"
                                           + (" and later, by case" if dlc.fault_delays else ""))
    report(f"{_counted(len(cases), 'case')} of DLC {campaign.dlc} ({_counted(len(campaign.controllers), 'controller')}"
           f" x {_counted(len(campaign.speeds), 'speed')} x "
           f"{_counted(len(campaign.seeds), 'case' if dlc.transients else 'seed')}, "
           f"{campaign.transient + campaign.duration:g} s each{fault}); {len(cases) - len(todo)} already done in "
           f"{output}")
    if todo:
        for folder in (output / "cases", *([output / "bags"] if bags else ())):  # before any wind or worker
            try:
                folder.mkdir(parents=True, exist_ok=True)
            except OSError as error:
                raise CampaignError(f"-o {output}: cannot create {folder} ({error.strerror or error})") from None
        client, cluster = _client(workers, scheduler)
        try:
            count = len(client.scheduler_info()["workers"])
            speed = measured_speed(todo[0], campaign)
            expected = len(todo) * (campaign.transient + campaign.duration) / (speed * max(count, 1))
            report(f"running {len(todo)} on {count} Dask worker(s) ({scheduler or 'local cluster'}): expected about "
                   f"{_duration_text(expected)} ({len(todo)} x {campaign.transient + campaign.duration:g} s at "
                   f"{speed:.0f}x real time, measured here), plus any wind field not cached yet; each case is stored "
                   f"as it finishes")
            winds = {}
            for case in todo:
                if (case.speed, case.seed) not in winds:
                    winds[(case.speed, case.seed)] = client.submit(
                        prepare_wind, case.controller, campaign, case.speed, case.seed, pure=False,
                        key=f"wind-{case.speed:g}-{case.seed}-{case.key}")
            futures = {client.submit(run_case, case, campaign,
                                     str(output / "bags" / f"{case.file_stem}.mcap") if bags else None,
                                     winds[(case.speed, case.seed)], key=f"case-{case.key}", pure=False): case
                       for case in todo}
            start, done = time.monotonic(), 0
            for future in as_completed(futures):
                case = futures[future]
                done += 1
                elapsed = time.monotonic() - start
                left = elapsed / done * (len(todo) - done)
                if future.status == "finished":
                    row = future.result()
                    _write_json(stored[case.key], row)
                    what = f"done in {row['wall_s']:.0f} s " \
                           f"({(campaign.transient + campaign.duration) / row['wall_s']:.1f}x real time)" + \
                           (f"; TRIPPED: {row['trips']}" if row.get("trips") else "")
                else:
                    error = future.exception()
                    failed[case.key] = f"{case.label}: {type(error).__name__}: {error}"
                    _write_json(output / "failed" / f"{case.key}.json", {"case": case.label, "error": str(error)})
                    what = f"FAILED ({type(error).__name__}: {error})"
                report(f"[{done}/{len(todo)}] {case.label}: {what}; elapsed {_duration_text(elapsed)}, about "
                       f"{_duration_text(left)} left")
        except KeyboardInterrupt:
            interrupted = True
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    rows = [json.loads(stored[case.key].read_text()) for case in cases if stored[case.key].exists()]
    return CampaignRun(rows, failed, len(cases) - len(todo), interrupted)


def _missing_cases(campaign: Campaign, rows: Sequence[Dict[str, Any]]) -> str:
    """The campaign's cases without a row, per controller: ``"ipc at 12 m/s (seed 3), 20 m/s"``, a bin named by its
    speed alone when all its seeds are missing; empty when none is."""
    done = {(row["controller"], row["wind_speed"], row["seed"]) for row in rows}
    parts = []
    for config in campaign.controllers:
        bins = []
        for speed in campaign.speeds:
            seeds = [str(seed) for seed in campaign.seeds if (config.name, speed, seed) not in done]
            if len(seeds) == len(campaign.seeds):
                bins.append(f"{speed:g} m/s")
            elif seeds:
                bins.append(f"{speed:g} m/s (seed{'s' if len(seeds) > 1 else ''} {', '.join(seeds)})")
        if bins:
            parts.append(f"{config.name} at {', '.join(bins)}")
    return "; ".join(parts)


def lifetime_table(campaign: Campaign, rows: Sequence[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """Per controller and load channel: the lifetime DEL over the campaign's bins and site (hawt_analysis.lifetime),
    and per controller the AEP [J]. A controller missing a whole bin gets none (NaN).

    Every entry also says what it is computed from: ``cases`` is ``"all M cases"``, or ``"incomplete: N of M
    cases"`` after a Ctrl-C or a failure, and ``missing`` names the campaign's cases without a row
    (`_missing_cases`). An incomplete campaign's numbers come from the cases it has and change once it is resumed.
    """
    from hawt_analysis.lifetime import annual_energy, bin_probabilities, lifetime_del

    probabilities = bin_probabilities(campaign.speeds, campaign.site)
    total = len(campaign.controllers) * len(campaign.speeds) * len(campaign.seeds)
    missing = _missing_cases(campaign, rows)
    cases = f"incomplete: {len(rows)} of {total} cases" if missing else f"all {total} cases"
    table = []
    for config in campaign.controllers:
        mine = [row for row in rows if row["controller"] == config.name]
        if not mine:
            continue
        complete = all(any(row["wind_speed"] == speed for row in mine) for speed in campaign.speeds)

        def per_bin(column: str) -> np.ndarray:
            grid = np.full((len(campaign.speeds), len(campaign.seeds)), np.nan)
            for row in mine:
                grid[campaign.speeds.index(row["wind_speed"]), campaign.seeds.index(row["seed"])] = row[column]
            return grid

        for channel, m in mine[0]["wohler"].items():
            value = lifetime_del(per_bin(f"del.{channel}"), probabilities, m) if complete else math.nan
            table.append({"controller": config.name, "quantity": f"lifetime DEL {channel}", "m": m, "value": value,
                          "cases": cases, "missing": missing})
        energy = annual_energy(np.nanmean(per_bin("power.mean"), axis=1), probabilities) if complete else math.nan
        table.append({"controller": config.name, "quantity": "AEP [J]", "m": math.nan, "value": energy,
                      "cases": cases, "missing": missing})
    return table


def ultimate_table(campaign: Campaign, rows: Sequence[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """Per controller and load channel of an ultimate-load campaign (every DLC but 1.2), the design load γ_f·F_k and
    what it comes from (:mod:`hawt_analysis.ultimate`); empty for DLC 1.2 (fatigue).

    DLC 1.3–1.5: F_k is the largest extreme over the cases, the case named (with its trip, if the safety system
    tripped: the loads of a shutdown). DLC 1.1: F_k is the 50-year value of the run
    maxima (of the negated minima where they are larger), extrapolated over the campaign's bins and site; a
    controller missing a case gets none (NaN), since the fit needs every bin's maxima.
    """
    from hawt_analysis.lifetime import bin_probabilities
    from hawt_analysis.ultimate import fifty_year_load, partial_safety_factor, ultimate_loads

    if campaign.dlc == "1.2" or not rows:
        return []
    channels = sorted(column[len("max."):] for column in rows[0] if column.startswith("max.")
                      and f"min.{column[len('max.'):]}" in rows[0])
    if campaign.dlc != "1.1":
        label = DLCS[campaign.dlc].label
        return [{**load.__dict__, "basis": "largest extreme of the cases"} for load in ultimate_loads(
            [{**row, "dlc": campaign.dlc, "case": f"{row['wind_speed']:g} m/s {label(row['seed'])}"
              + (f", tripped: {row['trips']}" if row.get("trips") else "")} for row in rows], channels)]
    probabilities = bin_probabilities(campaign.speeds, campaign.site)
    duration = campaign.duration
    factor = partial_safety_factor("1.1")
    table = []
    for config in campaign.controllers:
        mine = [row for row in rows if row["controller"] == config.name]
        if not mine:
            continue
        complete = len(mine) == len(campaign.speeds) * len(campaign.seeds)
        for channel in channels:
            characteristic, basis = math.nan, "incomplete: a case missing"
            if complete:
                fits = [fifty_year_load([[sign * row[f"{column}.{channel}"] for row in mine if row["wind_speed"] == v]
                                         for v in campaign.speeds], probabilities, duration, resamples=200)
                        for sign, column in ((1.0, "max"), (-1.0, "min"))]
                high, low = fits[0].value, -fits[1].value
                characteristic = high if abs(high) >= abs(low) else low
                chosen = fits[0] if characteristic == high else fits[1]
                basis = f"50-year value, {chosen.confidence:.0%} interval {chosen.low:.4g} to {chosen.high:.4g}" + (
                    "" if characteristic == high else " (of the negated minima)")
            table.append({"controller": config.name, "channel": channel, "characteristic": characteristic,
                          "factor": factor, "design": factor * characteristic, "dlc": "1.1", "case": "all cases",
                          "basis": basis})
    return table


def write_tables(campaign: Campaign, rows: Iterable[Dict[str, Any]], output: Path) -> Dict[str, Path]:
    """``cases.parquet`` and ``cases.csv`` (one row per case), ``lifetime.csv`` and, for an ultimate-load DLC,
    ``ultimate.csv`` (:func:`ultimate_table`); their paths by name."""
    import pandas

    rows = list(rows)
    frame = pandas.DataFrame([{k: v for k, v in row.items() if k != "wohler"} for row in rows])
    frame = frame.sort_values(["controller", "wind_speed", "seed"], kind="stable") if len(frame) else frame
    paths = {"cases.parquet": output / "cases.parquet", "cases.csv": output / "cases.csv",
             "lifetime.csv": output / "lifetime.csv"}
    output.mkdir(parents=True, exist_ok=True)
    frame.to_parquet(paths["cases.parquet"], index=False)
    frame.to_csv(paths["cases.csv"], index=False)
    pandas.DataFrame(lifetime_table(campaign, rows)).to_csv(paths["lifetime.csv"], index=False)
    ultimate = ultimate_table(campaign, rows)
    if ultimate:
        paths["ultimate.csv"] = output / "ultimate.csv"
        pandas.DataFrame(ultimate).to_csv(paths["ultimate.csv"], index=False)
    return paths


def read_lifetime(directory: Path, prefix: str = "") -> List[Dict[str, Any]]:
    """The lifetime table a campaign wrote into ``directory``, each controller named ``prefix + name``."""
    path = Path(directory) / "lifetime.csv"
    if not path.is_file():
        raise CampaignError(f"{directory}: no lifetime.csv (not a campaign folder, or its campaign ran no case yet)")
    return _table_rows(path, prefix)


def read_ultimate(directory: Path, prefix: str = "") -> List[Dict[str, Any]]:
    """The design loads a campaign wrote into ``directory`` (``ultimate.csv``: an ultimate-load DLC's, or those over
    the DLCs of a file of several), each controller named ``prefix + name``; none if it wrote none."""
    path = Path(directory) / "ultimate.csv"
    return _table_rows(path, prefix, {"dlc": str, "case": str, "basis": str}) if path.is_file() else []


def _table_rows(path: Path, prefix: str, types: Optional[Dict[str, type]] = None) -> List[Dict[str, Any]]:
    """The rows of a campaign's CSV table, each controller named ``prefix + name``."""
    import pandas

    rows = pandas.read_csv(path, dtype=types).to_dict("records")
    return [{**row, "controller": prefix + str(row["controller"])} for row in rows]
