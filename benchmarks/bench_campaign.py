"""A DLC 1.2-style campaign on this machine: wall time and aggregate real-time factor (``./hawt bench campaign``).

Runs ``campaigns/dlc12.yaml`` (4 controller configurations x 6 wind-speed bins x 3 seeds x (60 + 600) s, IEC
class B turbulence) with ``hawt campaign`` on a local Dask cluster of one worker per CPU, into a fresh folder,
and prints the lifetime table, the wall time, the simulated time and their ratio (the aggregate real-time
factor, turbulence generation included), and the per-case mean.

Usage: ./hawt bench campaign [--campaign FILE] [--workers N] [--output DIR]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--campaign", default=str(ROOT / "campaigns" / "dlc12.yaml"))
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--output", help="results folder (default: a new temporary folder, kept)")
    args = parser.parse_args()
    from hawt_tools.campaign import plan_cases
    from hawt_tools.campaign_file import load_campaign

    campaign = load_campaign(Path(args.campaign))
    cases = plan_cases(campaign)
    output = Path(args.output or tempfile.mkdtemp(prefix="hawt-bench-campaign-"))
    print(f"{args.campaign}: {len(cases)} cases on {args.workers} local worker(s) into {output}", flush=True)
    start = time.monotonic()
    code = subprocess.call([sys.executable, "-m", "hawt_tools.cli", "campaign", args.campaign, "-o", str(output),
                            "--workers", str(args.workers)])
    wall = time.monotonic() - start
    simulated = len(cases) * (campaign.transient + campaign.duration)
    print(f"exit {code}; wall {wall:.0f} s for {simulated:.0f} s simulated: aggregate {simulated / wall:.1f}x real "
          f"time on {args.workers} worker(s), {wall / len(cases):.1f} s wall per case")
    print("load average (1, 5, 15 min): {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(), os.cpu_count()))


if __name__ == "__main__":
    main()
