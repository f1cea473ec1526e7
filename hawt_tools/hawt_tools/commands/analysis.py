"""Recorded runs analysed: ``hawt analyze`` (one run), ``hawt compare`` (runs or campaign folders side by side),
``hawt transfer`` (Zalkind & Pao's load-transfer model over steady runs)."""
import argparse
import json
import math
from pathlib import Path
from typing import Sequence

from hawt_tools.commands.options import progress, report_folder, warn
from hawt_tools.graph_file import GraphError


def _cmd_analyze(args: argparse.Namespace) -> int:
    from hawt_analysis.analysis_report import analysis_text, write_analysis_report
    from hawt_analysis.run_analysis import analyze_bag

    report_folder(args.report)
    analysis = analyze_bag(args.bag, args.namespace, progress=progress)
    warn("analyze", analysis.summary["warnings"])
    print(json.dumps(analysis.summary) if args.json else analysis_text(analysis.summary))
    if args.report:
        progress(f"writing the report into {args.report}")
        progress(f"report: {write_analysis_report(analysis, args.report)}")
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from hawt_analysis.analysis_report import comparison_text, write_comparison_report
    from hawt_analysis.run_analysis import compare_bags

    folders = [Path(path).is_dir() for path in args.bags]
    if any(folders):
        return _compare_campaigns(args, all(folders))
    report_folder(args.report)
    from hawt_plant.safety_system import TRIP_EVENTS

    analyses, comparison = compare_bags(args.bags, args.namespace, progress=progress)
    for path, analysis in zip(args.bags, analyses):
        warn("compare", analysis.summary["warnings"])
        warn("compare", [f"{path}: {event['kind']} at t={event['time']:.2f} s: from then on its loads are a "
                         f"feathered turbine's" for event in analysis.summary["events"] if event["kind"] in TRIP_EVENTS])
    warn("compare", comparison["warnings"])
    print(json.dumps(comparison) if args.json else comparison_text(comparison))
    if args.report:
        progress(f"report: {write_comparison_report(comparison, args.report, analyses)}")
    return 0


def _compare_campaigns(args: argparse.Namespace, only_folders: bool) -> int:
    """Lifetime DELs and AEP, and design loads, of campaign folders' controllers side by side, changes against the
    first. A folder of several DLCs has design loads only (its DLCs' folders have their lifetime tables)."""
    from hawt_analysis.campaign_report import lifetime_text, ultimate_text
    from hawt_tools.campaign import read_lifetime, read_ultimate
    from hawt_tools.campaign_file import CampaignError

    if not only_folders:
        raise GraphError("give bags or campaign folders, not both")
    if args.report:
        raise GraphError("--report: each campaign folder has its report.html already")
    several = len(args.bags) > 1
    lifetime, ultimate = [], []
    for path in map(Path, args.bags):
        prefix = f"{path.name}/" if several else ""
        designs = read_ultimate(path, prefix)
        try:
            lifetime += read_lifetime(path, prefix)
        except CampaignError:
            if not designs:
                raise
        ultimate += designs
    if args.json:
        print(json.dumps({"lifetime": lifetime, "ultimate": ultimate}))
        return 0
    print("\n".join(text for text in (lifetime_text(lifetime) if lifetime else "", ultimate_text(ultimate)) if text))
    return 0


def _cmd_transfer(args: argparse.Namespace) -> int:
    """Zalkind & Pao's load-transfer model fitted over recorded steady runs, per link and region."""
    from hawt_analysis.two_bladed import transfer_model_from_bags

    if len(args.bags) < 2:
        raise GraphError("give two or more bags (steady runs at different wind speeds) to fit over")
    try:
        _, fits = transfer_model_from_bags([Path(path) for path in args.bags], fine_pitch=args.fine_pitch)
    except ValueError as error:
        raise GraphError(str(error)) from None
    rows = [{"input": source, "output": target, "region": region, "gain": [fit.gain.real, fit.gain.imag],
             "offset": [fit.offset.real, fit.offset.imag], "residual_rms": fit.residual_rms, "points": fit.points}
            for (source, target), by_region in fits.items() for region, fit in sorted(by_region.items())]
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'input':>14s} -> {'output':<14s} region  |gain|  arg(gain) [deg]  |offset| [MN*m]  "
          "residual [MN*m]  points")
    for row in rows:
        gain, offset = complex(*row["gain"]), complex(*row["offset"])
        print(f"{row['input']:>14s} -> {row['output']:<14s} {row['region']:>6d}  {abs(gain):6.3f}  "
              f"{math.degrees(math.atan2(gain.imag, gain.real)):15.1f}  {abs(offset) / 1e6:15.3f}  "
              f"{row['residual_rms'] / 1e6:15.3f}  {row['points']:6d}")
    return 0


def _add_analyze(commands: argparse._SubParsersAction) -> None:
    analyze = commands.add_parser("analyze", help="DELs, harmonics, spectra, pitch activity and events of a run",
                                  description="Analyse one turbine's run in a bag: plant/blade_loads and "
                                              "plant/state (required), control/pitch_command and control/events.")
    analyze.add_argument("bag", metavar="FILE.mcap")
    analyze.add_argument("--json", action="store_true",
                         help="print the summary as one JSON object (the text's quantities, in SI units)")
    analyze.add_argument("--report", metavar="DIR", help="write index.html, plots and summary.json into DIR")
    analyze.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when the bag holds several")
    analyze.set_defaults(run=_cmd_analyze)


def _add_compare(commands: argparse._SubParsersAction) -> None:
    compare = commands.add_parser("compare", help="several runs (or campaign folders) side by side, changes "
                                                  "against the first")
    compare.add_argument("bags", nargs="+", metavar="FILE.mcap|CAMPAIGN_DIR",
                         help="bags, or the output folders of hawt campaign (their lifetime DELs and AEP, and "
                              "their design loads where they have ultimate.csv)")
    compare.add_argument("--json", action="store_true", help="print the comparison as JSON (campaign folders: "
                                                             "{\"lifetime\": […], \"ultimate\": […]})")
    compare.add_argument("--report", metavar="DIR", help="write index.html, plots and comparison.json into DIR")
    compare.add_argument("--namespace", metavar="NS", help="the turbine (e.g. /wt1) when a bag holds several")
    compare.set_defaults(run=_cmd_compare)


def _add_transfer(commands: argparse._SubParsersAction) -> None:
    transfer = commands.add_parser(
        "transfer", help="Zalkind & Pao's load-transfer model (blade -> hub -> main bearing -> yaw bearing -> tower) "
                         "fitted over recorded steady runs",
        description="Fit the complex affine transfer m2 = gain*m1 + offset (Zalkind & Pao 2019 eqs. 8-11) of each "
                    "link of the load chain over the last revolutions of each bag (one steady run per wind speed), "
                    "separately for region II and III (by the collective pitch against --fine-pitch).")
    transfer.add_argument("bags", nargs="+", metavar="FILE.mcap")
    transfer.add_argument("--fine-pitch", type=float, default=0.0, help="region boundary: collective pitch [rad]")
    transfer.add_argument("--json", action="store_true", help="print the fits as JSON")
    transfer.set_defaults(run=_cmd_transfer)


_PARSERS = {"analyze": _add_analyze, "compare": _add_compare, "transfer": _add_transfer}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
