#!/usr/bin/env python3
"""symdyn-sim's HTML viewer of the four-bar with --reaction-arrows.

Usage: check_four_bar_viewer.py <symdyn-sim> <chromium> <work dir>

1. The page's data: one arrow, the loop C, with a point and a force per output
   instant; the force is the CSV's reaction.C.Fx, reaction.C.Fy and the point
   the rocker's end, r3 = 0.3 from D = (0.4, 0) along psi.
2. In headless Chromium the arrow is drawn (data-arrows="1").
3. Without a loop model, or without --html, the option is refused.
"""
import csv
import json
import math
import re
import subprocess
import sys
from pathlib import Path

from check_viewer import chromium


def main():
    sim, browser, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    work.mkdir(parents=True, exist_ok=True)
    html, table = work / "four_bar.html", work / "four_bar.csv"
    done = subprocess.run([sim, "four_bar", "--out", str(table), "--html", str(html),
                           "--reaction-arrows"], capture_output=True, text=True, timeout=300)
    if done.returncode != 0:
        sys.exit(f"symdyn-sim four_bar failed: {done.stderr[-2000:]}")
    data = json.loads(re.search(r'<script id="symdyn-data" type="application/json">(.*?)</script>',
                                html.read_text(), re.S).group(1).replace("<\\/", "</"))
    arrows = data["arrows"]
    if arrows["names"] != ["C"]:
        sys.exit(f"arrows {arrows['names']}, expected ['C']")
    rows = list(csv.DictReader(table.open()))
    times = data["series"]["columns"][0]
    if len(times) != len(rows) or len(arrows["vectors"][0]) != 3 * len(rows):
        sys.exit(f"{len(arrows['vectors'][0])} arrow values for {len(rows)} rows")
    for i in (0, len(rows) // 2, len(rows) - 1):
        row = rows[i]
        force = arrows["vectors"][0][3 * i:3 * i + 3]
        point = arrows["points"][0][3 * i:3 * i + 3]
        psi = float(row["psi"])
        expected = [float(row["reaction.C.Fx"]), float(row["reaction.C.Fy"]), 0.0]
        if any(abs(a - b) > 1e-9 * (1 + abs(b)) for a, b in zip(force, expected)):
            sys.exit(f"t = {row['t']}: arrow force {force}, the CSV's {expected}")
        at = [0.4 + 0.3 * math.cos(psi), 0.3 * math.sin(psi), 0.0]
        if any(abs(a - b) > 1e-12 for a, b in zip(point, at)):
            sys.exit(f"t = {row['t']}: arrow at {point}, the rocker's end is {at}")
    print("the page holds the force at C and its point at every output instant")

    dom = chromium(browser, "--dump-dom", f"{html.resolve().as_uri()}#t=0.5&paused")
    if 'data-ready="true"' not in dom or 'data-arrows="1"' not in dom:
        sys.exit("the viewer did not load, or does not draw the arrow at C")
    print("the viewer draws the arrow at C")

    for args, refusal in ((["double_pendulum", "--html", str(work / "dp.html")], "has no closed loops"),
                          (["four_bar"], "draws in --html, which is not asked")):
        done = subprocess.run([sim, *args, "--out", str(work / "refused.csv"), "--reaction-arrows"],
                              capture_output=True, text=True, timeout=300)
        if done.returncode == 0 or refusal not in done.stderr:
            sys.exit(f"symdyn-sim {' '.join(args)} --reaction-arrows: {done.stderr[-500:]!r}, "
                     f"expected a refusal saying '{refusal}'")
    print("--reaction-arrows is refused without a loop model or without --html")


if __name__ == "__main__":
    main()
