"""The Foxglove layout hawt ships (``hawt_tools/foxglove/hawt_layout.json``), built with the SDK's layout types.

One page for a load engineer: blade-root moments (out-of-plane, in-plane), hub tilt and yaw moments and
tower-base moments; pitch per blade, rotor speed and electrical power; the events of ``control/events``
as a timeline and the latest one in full; the nodes' parameters, settable on a live graph. Every series
is timed by its ``header.stamp`` (the plant's simulated time), which is the log time of ``hawt view``
and the publish time of a bag (whose log time is the wall-clock receive time), so the same layout
opens a live graph and its recordings.

Regenerate the file after a change here (a test checks they agree):
``python -m hawt_tools.foxglove_layout > hawt_tools/foxglove/hawt_layout.json``.
"""
import json

import foxglove.layouts as fl

__all__ = ["hawt_layout", "layout_text"]


def _plot(title: str, label_paths: list[tuple[str, str]], unit: str) -> fl.SplitItem:
    series = [fl.PlotSeries(value=path, label=label, timestamp_method="headerStamp") for label, path in label_paths]
    return fl.SplitItem(content=fl.PlotPanel(title=title, config=fl.PlotConfig(
        paths=series, show_legend=True, legend_display="top", y_axis_label=unit)))


def _column(*items: fl.SplitItem) -> fl.SplitItem:
    return fl.SplitItem(content=fl.SplitContainer(direction="column", items=list(items)))


def hawt_layout(namespace: str = "wt1", blades: int = 3) -> fl.Layout:
    """The layout for the turbine under ``/namespace`` with ``blades`` blades."""
    loads, state = f"/{namespace}/plant/blade_loads", f"/{namespace}/plant/state"
    events = f"/{namespace}/control/events"
    per_blade = range(blades)

    def blade_series(field: str) -> list[tuple[str, str]]:
        return [(f"blade {i + 1}", f"{loads}.{field}[{i}]") for i in per_blade]

    return fl.Layout(content=fl.SplitContainer(direction="row", items=[
        _column(_plot("Blade-root out-of-plane moments", blade_series("root_moment_oop"), "N·m"),
                _plot("Blade-root in-plane moments", blade_series("root_moment_ip"), "N·m"),
                _plot("Hub tilt and yaw moments", [("tilt", f"{state}.hub_tilt_moment"),
                                                   ("yaw", f"{state}.hub_yaw_moment")], "N·m"),
                _plot("Tower-base moments", [("fore-aft", f"{state}.tower_base_fa_moment"),
                                             ("side-side", f"{state}.tower_base_ss_moment")], "N·m")),
        _column(_plot("Pitch per blade (measured)", blade_series("pitch"), "rad"),
                _plot("Rotor speed", [("rotor", f"{loads}.rotor_speed")], "rad/s"),
                _plot("Electrical power", [("power", f"{state}.electrical_power")], "W")),
        _column(fl.SplitItem(content=fl.StateTransitionsPanel(title="Events", config=fl.StateTransitionsConfig(
                    paths=[fl.StateTransitionsSeries(value=f"{events}.kind", label="kind",
                                                     timestamp_method="headerStamp")]))),
                fl.SplitItem(content=fl.RawMessagesPanel(title="Latest event", config=fl.RawMessagesConfig(
                    topic_path=events, expansion="all"))),
                fl.SplitItem(content=fl.ParametersPanel(title="Parameters"))),
    ]))


def layout_text(namespace: str = "wt1", blades: int = 3) -> str:
    """The layout as the shipped JSON file holds it (indented, newline at the end)."""
    return json.dumps(json.loads(hawt_layout(namespace, blades).to_json()), indent=2, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    print(layout_text(), end="")
