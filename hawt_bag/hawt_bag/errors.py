"""The error of the bag library: bad or unreadable input, said in one line naming the file.

`UnfinishedBagError`, a `BagError`, marks the one case a command may want to tell apart:
a file that starts as MCAP but whose writer never finished it.
"""

import os
from pathlib import Path

__all__ = ["BagError", "UnfinishedBagError", "not_a_file"]


class BagError(ValueError):
    """A bag (or its use) is invalid: not MCAP, truncated, missing, lacking a topic, or an existing output.

    The message is one line and names the file, topic or field at fault, so a command
    can print it as it is and exit 2.
    """


class UnfinishedBagError(BagError):
    """An MCAP file cut off or never finished (no footer or summary to read): ``hawt bag recover`` rescues it."""


def not_a_file(path: os.PathLike) -> BagError:
    """The error for a bag path that is no file: a folder (a user's runs folder), or nothing there."""
    what = "a folder; expected an MCAP file (FILE.mcap)" if Path(path).is_dir() else "no such file"
    return BagError(f"{path}: {what}")
