"""The controller tests' helpers (launched_graph) are importable from their folder."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
