"""Turbine definitions: ``hawt turbine import|show`` (an OpenFAST deck converted, a definition summarised), ``hawt
validate`` (a turbine's cases side by side in OpenFAST and in hawt)."""
import argparse
from pathlib import Path
from typing import Sequence

from hawt_tools.commands.options import POSITIVE
from hawt_tools.graph_file import GraphError, find_graph, resolve_turbine


def _cmd_validate(args: argparse.Namespace) -> int:
    """The turbine's cases in OpenFAST and in hawt with ROSCO on both, and the report of their differences."""
    from hawt_plant.turbine import TurbineDefinitionError, turbine_from
    from hawt_tools.openfast_case import OpenFastFailed, deck_of, openfast_executable
    from hawt_tools.validation import DEFAULT_CASES, parse_case, run_case, with_duration, write_report

    try:
        openfast = openfast_executable(args.openfast)
        cases = [parse_case(text, args.duration) for text in args.case] if args.case else \
            [with_duration(case, args.duration) if args.duration is not None else case for case in DEFAULT_CASES]
        turbine_from(resolve_turbine(args.turbine, "T"))
        deck = deck_of(args.turbine)
    except (ValueError, TurbineDefinitionError) as error:
        raise GraphError(str(error)) from None
    out = Path(args.output or f"validation-{Path(args.turbine).name}")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise GraphError(f"-o {out}: cannot create the report folder ({error.strerror})") from None
    graph = find_graph("validation")
    print(f"hawt validate {args.turbine}: {len(cases)} case(s) in OpenFAST ({openfast}) and in hawt, deck {deck}, "
          f"report in {out}", flush=True)
    results = []
    for number, case in enumerate(cases, start=1):
        print(f"case {number} of {len(cases)}: {case.name}, {case.duration:g} s simulated", flush=True)
        try:
            result = run_case(case, args.turbine, graph, deck, openfast, out, args.param,
                              lambda line: print(line, flush=True))
        except OpenFastFailed as error:
            raise RuntimeError(str(error)) from None
        results.append(result)
        outside = [row["label"] for row in result.rows if not row["within"]]
        print(f"  {case.name}: {len(result.rows) - len(outside)} of {len(result.rows)} figures within tolerance"
              + (f"; outside: {', '.join(outside)}" if outside else ""), flush=True)
    page = write_report(args.turbine, openfast, results, out)
    print(f"report: {out / 'validation.md'} and {page}")
    return 0


def _cmd_turbine_import(args: argparse.Namespace) -> int:
    """An OpenFAST deck converted into DIR/turbine.yaml and DIR/airfoils/, checked by loading it."""
    from hawt_plant.turbine import TurbineDefinitionError, load_turbine
    from hawt_tools.turbine_import import DeckError, import_deck, write_turbine

    from hawt_tools.openfast_case import DeckNotFound, keep_deck

    try:
        imported = import_deck(args.deck)
        path = write_turbine(imported, args.output or Path(args.deck).stem)
        load_turbine(path)
        deck = keep_deck(Path(args.deck), path.parent)
    except (DeckError, TurbineDefinitionError, DeckNotFound) as error:
        raise GraphError(str(error)) from None
    print(f"{args.deck} -> {path} and {len(imported.airfoils)} airfoil polars in {path.parent / 'airfoils'}; each "
          "value names its source file and key")
    for title, lines in (("approximated", imported.approximations), ("not modelled", imported.not_modelled)):
        print(f"{title}:" + "".join(f"\n  - {line}" for line in lines))
    print(f"the deck, for hawt validate: {deck}")
    print(f"next: hawt turbine show {path.parent}; hawt design cpc --turbine {path.parent} (writes its cpc.yaml); "
          f"then hawt launch baseline turbine:={path.parent}")
    return 0


def _cmd_turbine_show(args: argparse.Namespace) -> int:
    """Rated values, the plant's Cp-max and optimal tip-speed ratio, and first modes of a turbine definition."""
    from hawt_plant.turbine import TurbineDefinitionError, turbine_from
    from hawt_plant.turbine_summary import format_summary, turbine_summary

    try:
        turbine = turbine_from(resolve_turbine(args.turbine, "show"))
    except TurbineDefinitionError as error:
        raise GraphError(str(error)) from None
    print(format_summary(turbine_summary(turbine)))
    return 0


def _add_turbine(commands: argparse._SubParsersAction) -> None:
    turbine = commands.add_parser("turbine", help="import an OpenFAST deck as a turbine definition, or summarise one")
    turbine_commands = turbine.add_subparsers(dest="turbine_action", required=True, metavar="ACTION")
    importing = turbine_commands.add_parser(
        "import", help="convert an OpenFAST deck (.fst and the files it names) into DIR/turbine.yaml and airfoils/",
        description="Read the deck with openfast-io (ElastoDyn, AeroDyn, ServoDyn and the ROSCO DISCON.IN it "
                    "names), convert what the plant models into the hawt turbine definition, each value with its "
                    "source file and key, and list what is approximated and what the plant does not model. A "
                    "missing file or an option the plant cannot honour is refused, naming the file and key.")
    importing.add_argument("deck", metavar="DECK.fst")
    importing.add_argument("-o", "--output", metavar="DIR", help="folder for turbine.yaml and airfoils/ (default: "
                                                                 "the deck's name)")
    importing.set_defaults(run=_cmd_turbine_import)
    show = turbine_commands.add_parser(
        "show", help="rated values, Cp-max and optimal tip-speed ratio (the plant's BEM), first modes")
    show.add_argument("turbine", metavar="T", help="a turbine.yaml, its folder, or a packaged turbine's name "
                                                   "(nrel_5mw, nrel_5mw_two_bladed, nrel_5mw_two_bladed_downwind)")
    show.set_defaults(run=_cmd_turbine_show)


def _add_validate(commands: argparse._SubParsersAction) -> None:
    validate = commands.add_parser(
        "validate", help="the turbine's cases side by side in OpenFAST and in hawt, ROSCO on both, and a report",
        description="Run each case in OpenFAST (the turbine's own deck, with only TMax, the wind, the initial "
                    "state, the controller and the outputs changed) and in hawt's validation graph (plant, ROSCO, mbc) in process, with the "
                    "same ROSCO library and DISCON.IN and the same wind (turbulent: the plant's field as a TurbSim "
                    ".bts both read), analyse both with hawt's analysis over the same window, and write "
                    "validation.md, index.html with plots and validation.json. Cases: steady-V or turbulent-V "
                    "(default: steady-8 steady-11.4 steady-18 turbulent-18).")
    validate.add_argument("turbine", metavar="T", help="nrel_5mw, or the folder hawt turbine import wrote")
    validate.add_argument("--openfast", metavar="PATH", help="OpenFAST executable (default: $HAWT_OPENFAST)")
    validate.add_argument("--case", action="append", default=[], metavar="NAME",
                          help="run this case (repeatable): steady-V or turbulent-V, V in m/s")
    validate.add_argument("--duration", type=POSITIVE, metavar="S", help="simulated seconds per case (default: "
                                                                          "160 steady, 600 turbulent)")
    validate.add_argument("-o", "--output", metavar="DIR", help="report folder (default: validation-T)")
    validate.add_argument("-p", dest="param", action="append", default=[], metavar="NODE.PARAM:=VALUE",
                          help="a parameter of hawt's validation graph (e.g. -p plant.skewed_wake:=false)")
    validate.set_defaults(run=_cmd_validate)


_PARSERS = {"turbine": _add_turbine, "validate": _add_validate}


def add_parsers(commands: argparse._SubParsersAction, names: Sequence[str] = tuple(_PARSERS)) -> None:
    """The subparsers of this group's commands ``names`` (default: all of them), added to hawt's ``commands`` in
    that order."""
    for name in names:
        _PARSERS[name](commands)
