"""``hawt campaign``: a design-load-case campaign (wind speeds x seeds x controllers) on Dask workers, its tables,
lifetime loads, design loads and report."""
import argparse
import signal
import sys
from pathlib import Path
from typing import Sequence

from hawt_tools.commands.options import output_path, scheduler_address
from hawt_tools.graph_file import GraphError


def _cmd_campaign(args: argparse.Namespace) -> int:
    """Every case of a campaign file on Dask workers; tables, lifetime loads and a report in the output folder. A
    file of several DLCs runs each into its folder ``dlc-N.N`` and prints the design loads over them all, which
    ``ultimate.csv`` in the output folder keeps."""
    from hawt_tools.campaign_file import load_campaigns

    if args.workers is not None and args.workers < 1:
        raise GraphError(f"--workers {args.workers}: expected 1 or more")
    scheduler = scheduler_address(args.scheduler)
    campaigns = load_campaigns(Path(args.campaign))
    output = output_path(args.output or Path(args.campaign).stem, "-o", folder=True)
    several = len(campaigns) > 1
    tables, failed = [], 0
    for campaign in campaigns:  # a DLC with failed cases leaves the others to run; an interruption stops them all
        if several:
            print(f"DLC {campaign.dlc}:", flush=True)
        status, ultimate = _run_campaign(campaign, output / f"dlc-{campaign.dlc}" if several else output, args,
                                         scheduler)
        if status == 130:
            return status
        failed = failed or status
        tables.append(ultimate)
    if several and any(tables):
        import pandas

        from hawt_analysis.campaign_report import ultimate_text, write_design_load_report
        from hawt_analysis.ultimate import governing_loads

        governing = governing_loads(tables)
        over = [campaign.dlc for campaign in campaigns]
        pandas.DataFrame(governing).to_csv(output / "ultimate.csv", index=False)
        print(ultimate_text(governing, over))
        page = write_design_load_report(f"hawt campaign: {campaigns[0].path.name}, design loads", governing, over,
                                        output, [f"dlc-{dlc}/report.html" for dlc in over
                                                 if (output / f"dlc-{dlc}" / "report.html").is_file()])
        print(f"design loads over the DLCs: {output / 'ultimate.csv'}\nreport: {page}")
    return failed


def _run_campaign(campaign, output: Path, args: argparse.Namespace, scheduler: str) -> tuple[int, list]:
    """One DLC's campaign into ``output``: its exit status (0, 130 interrupted, 1 failed cases) and its ultimate
    table."""
    from hawt_analysis.campaign_report import lifetime_text, ultimate_text, write_campaign_report
    from hawt_core.stop_signals import stop_signals
    from hawt_tools.campaign import governing_series, lifetime_table, run_campaign, ultimate_table, write_tables

    # Ctrl-C or SIGTERM stops the campaign, keeping what finished, also in a process started with SIGINT ignored
    # (a script's background job, a test runner's worker)
    with stop_signals(signal.default_int_handler):
        done = run_campaign(campaign, output, args.workers, scheduler, args.bags,
                            report=lambda line: print(line, flush=True))
    ultimate = []
    if done.rows:
        tables = write_tables(campaign, done.rows, output)
        lifetime = lifetime_table(campaign, done.rows)
        print(f"lifetime DEL (Miner, m per channel, site mean {campaign.site.mean:g} m/s, Weibull k "
              f"{campaign.site.shape:g}) and AEP, over the bins run" + (
                  f" (in DLC {campaign.dlc}'s extreme conditions: to compare controllers, not a fatigue estimate):"
                  if campaign.dlc not in ("1.1", "1.2") else ":"))
        print(lifetime_text(lifetime))
        ultimate = ultimate_table(campaign, done.rows)
        governing = []
        if ultimate:
            print(ultimate_text(ultimate))
            cases = {(e["controller"], e.get("wind_speed"), e.get("seed")) for e in ultimate if e["dlc"] != "1.1"}
            if cases and not (done.failed or done.interrupted):
                print(f"running the {len(cases)} governing case(s) again for their time series (report)", flush=True)
                governing = governing_series(campaign, ultimate)
        page = write_campaign_report(f"hawt campaign: {campaign.path.name}", done.rows, lifetime, output, tables,
                                     ultimate, governing)
        print(f"tables: {', '.join(str(path) for path in tables.values())}\nreport: {page}")
    if done.interrupted:
        print(f"hawt campaign: interrupted; {len(done.rows)} finished case(s) kept in {output}: run the same command "
              "again to resume", file=sys.stderr)
        return 130, ultimate
    if done.failed:
        for line in done.failed.values():
            print(f"hawt campaign: failed: {line}", file=sys.stderr)
        return 1, ultimate
    return 0, ultimate


def _add_campaign(commands: argparse._SubParsersAction) -> None:
    campaign = commands.add_parser(
        "campaign", help="a design-load-case campaign (speeds x seeds x controllers) on Dask workers, lifetime loads",
        description="Run every case of CAMPAIGN.yaml (wind-speed bins x seeds x controller configurations) on the "
                    "in-process engine, on a local Dask cluster or an existing one; store each case's numbers, skip "
                    "those already stored (rerun to resume), and write cases.parquet/.csv, lifetime.csv (Miner-"
                    "consistent lifetime DELs over the site's wind distribution, AEP) and report.html.")
    campaign.add_argument("campaign", metavar="CAMPAIGN.yaml", help="the campaign file")
    campaign.add_argument("-o", "--output", metavar="DIR", help="results folder (default: the file's name)")
    campaign.add_argument("--workers", type=int, help="local worker processes (default: the CPU count)")
    campaign.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run on this Dask scheduler's workers")
    campaign.add_argument("--bags", action="store_true", help="also record every case to DIR/bags/*.mcap")
    campaign.set_defaults(run=_cmd_campaign)


_PARSERS = {"campaign": _add_campaign}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
