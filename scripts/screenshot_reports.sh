#!/usr/bin/env bash
# Screenshots of the report pages of `hawt analyze --report` and `hawt compare --report`, and a check of their links.
# Makes two 30 s turbulent runs in process (baseline -> A.mcap, ipc -> B.mcap), writes both reports, opens each
# index.html in headless Chromium (Debian's chromium, installed with apt-get if /usr/bin/chromium is missing) and
# checks that every relative <img src> and <a href> of the pages exists on disk.
# Prints the screenshot paths and "no broken link"; exit 1 naming a broken link.
# Usage: scripts/screenshot_reports.sh [FOLDER]   (default: a new temporary folder; the runs and pages stay there)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -x /usr/bin/chromium ]; then
  echo "screenshot_reports: /usr/bin/chromium is missing: installing Debian's chromium with apt-get" >&2
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
folder="$(realpath "${1:-$(mktemp -d -t hawt-reports.XXXXXX)}")"
mkdir -p "$folder"
cd "$folder"
"$root/hawt" run baseline wind_type:=turbulent duration:=30 --record A.mcap >/dev/null
"$root/hawt" run ipc wind_type:=turbulent duration:=30 --record B.mcap >/dev/null
"$root/hawt" analyze B.mcap --report analyze >/dev/null
"$root/hawt" compare A.mcap B.mcap --report compare >/dev/null
for page in analyze compare; do
  # --no-sandbox: Chromium refuses to run as root with its sandbox
  /usr/bin/chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --screenshot="$folder/$page.png" \
    --window-size=1400,4000 "file://$folder/$page/index.html" >/dev/null 2>&1
  [ -s "$folder/$page.png" ] || { echo "screenshot_reports: chromium wrote no $folder/$page.png" >&2; exit 1; }
  echo "$folder/$page.png"
done
python3 - "$folder/analyze/index.html" "$folder/compare/index.html" <<'EOF'
"""Every relative <img src> and <a href> of the pages names an existing file; exit 1 naming the first that does not."""
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.targets = []

    def handle_starttag(self, tag, attrs):
        wanted = {"img": "src", "a": "href"}.get(tag)
        self.targets += [value for name, value in attrs if name == wanted and value]


for page in map(Path, sys.argv[1:]):
    parser = Links()
    parser.feed(page.read_text(encoding="utf-8"))
    for target in parser.targets:
        parts = urlsplit(target)
        if parts.scheme or parts.netloc or parts.path.startswith("/") or not parts.path:
            continue  # not a relative path: another site, an absolute path or a fragment of this page
        if not (page.parent / unquote(parts.path)).exists():
            print(f"broken link in {page}: {target}")
            sys.exit(1)
print("no broken link")
EOF
