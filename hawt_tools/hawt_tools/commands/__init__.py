"""The ``hawt`` command's groups of commands (hawt_tools.cli builds the parser from them), one module each:

- ``graphs``: ``launch``, ``run``, ``bridge``, ``graph list|show``: running and inspecting node graphs;
- ``live``: ``list``, ``switch``, ``lifecycle``, ``view``, ``record``: a running graph;
- ``bags``: ``replay``, ``bag info|verify|recover``;
- ``analysis``: ``analyze``, ``compare``, ``transfer``: recorded runs analysed;
- ``design``: ``coupling``, ``linearize``, ``design lqg|cpc|ipc``: the plant's models and controller design;
- ``turbines``: ``turbine import|show``, ``validate``: turbine definitions;
- ``campaigns``: ``campaign``;
- ``demo``: ``demo``;

and ``options``, what they share: argument types with their ranges, the parser's one-line refusal, output paths,
progress and warning lines.

Each command module has ``add_parsers(commands, names)``, which adds the subparsers of its commands (those named,
default all of them), and the commands' handlers (each ``args.run``), which leave the computation to library
functions and print what those return.
"""
