"""The one error of the bag library: bad or unreadable input, said in one line naming the file."""

__all__ = ["BagError"]


class BagError(ValueError):
    """A bag (or its use) is invalid: not MCAP, truncated, missing, lacking a topic, or an existing output.

    The message is one line and names the file, topic or field at fault, so a command
    can print it as it is and exit 2.
    """
