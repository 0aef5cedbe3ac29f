"""``make demo``: the main job - the coach-facing report, then where to go next.

``python -m tennislab.demo [--out DIR]`` writes ``DIR/index.html`` (default ``out/demo``; missing
folders are created) with ``tennislab report`` and prints the next steps of
docs/getting-started.md.
"""

from __future__ import annotations

import argparse
import os
import sys

from tennislab.cli import main as cli_main

NEXT_STEPS = """
Next steps (docs/getting-started.md):
  open {index} in a browser
  source .venv/bin/activate      # puts the `tennislab` command on your PATH in this shell
  tennislab fly --speed-kmh 120 --elevation-deg 6 --spin-rpm 2500 --spin-axis topspin
  tennislab app                  # the web app at http://127.0.0.1:8000/
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="tennislab.demo", description="Write the report (the main job of make demo).")
    ap.add_argument("--out", default=os.path.join("out", "demo"), help="output directory (default out/demo)")
    args = ap.parse_args(argv)
    rc = cli_main(["report", "--out", args.out])
    if rc == 0:
        print(NEXT_STEPS.format(index=os.path.join(args.out, "index.html")), file=sys.stderr)
    return rc


if __name__ == "__main__":
    sys.exit(main())
